//! Multi-support excitation of a bridge (paper §4.1): per bent x and y, per abutment x, each
//! support with its own record, PGA and time lag.

use super::schema::{ExcitationSpec, RunSpec};
use crate::excitation::{Baseline, Processing};
use crate::model::check::{Check, ModelError};
use crate::model::records::{Motions, record_error};
use crate::scene::{Motion, Support};
use std::path::Path;

/// Time lag of support `i` (0 beyond the list).
fn lag(lags: &[f64], i: usize) -> f64 {
    lags.get(i).copied().unwrap_or(0.0)
}

/// Supports of the `[excitation]`: per bent x and y, then left and right abutment x, then (if
/// `transverse`: keys, bearings or abutments moving with the ground) left and right abutment y.
pub(super) fn excitation_supports(
    e: &ExcitationSpec,
    runs: &[RunSpec],
    nb: usize,
    transverse: bool,
    ck: &Check,
    path: &Path,
    motions: &Motions,
) -> Result<Vec<Support>, ModelError> {
    validate_excitation(e, nb, ck)?;
    match e.kind.as_str() {
        "harmonic" => harmonic_supports(e, nb, transverse, ck),
        "record" => record_supports(e, runs, (nb, transverse), ck, path, motions),
        k => Err(ck.err(
            "excitation.kind",
            format!("unknown excitation kind '{k}' (record, harmonic)"),
        )),
    }
}

/// Sinusoidal displacement of every support, delayed by its lag.
fn harmonic_supports(
    e: &ExcitationSpec,
    nb: usize,
    transverse: bool,
    ck: &Check,
) -> Result<Vec<Support>, ModelError> {
    let f = ck.positive(
        "excitation.frequency",
        e.frequency
            .ok_or_else(|| ck.err("excitation.frequency", "required for harmonic input"))?,
    )?;
    let ax = ck.finite("excitation.amplitude_x", e.amplitude_x.unwrap_or(0.0))?;
    let ay = ck.finite("excitation.amplitude_y", e.amplitude_y.unwrap_or(0.0))?;
    let ay = if longitudinal_only(e, ck)? { 0.0 } else { ay };
    let w = 2.0 * std::f64::consts::PI * f;
    let h = |amp: f64, lag: f64, name: String| Support {
        name,
        motion: Motion::Harmonic {
            amplitude: amp,
            omega: w,
            phase: -w * lag,
        },
        factor: 1.0,
    };
    let mut out = Vec::new();
    for b in 0..nb {
        out.push(h(ax, lag(&e.lag_bents, b), format!("bent{}.x", b + 1)));
        out.push(h(ay, lag(&e.lag_bents, b), format!("bent{}.y", b + 1)));
    }
    out.push(h(ax, lag(&e.lag_abutments, 0), "left_abutment.x".into()));
    out.push(h(ax, lag(&e.lag_abutments, 1), "right_abutment.x".into()));
    if transverse {
        out.push(h(ay, lag(&e.lag_abutments, 0), "left_abutment.y".into()));
        out.push(h(ay, lag(&e.lag_abutments, 1), "right_abutment.y".into()));
    }
    Ok(out)
}

/// Recorded motions (longitudinal, transverse), scaled to the PGAs of the chosen run and
/// delayed by each support's lag.
fn record_supports(
    e: &ExcitationSpec,
    runs: &[RunSpec],
    (nb, transverse): (usize, bool),
    ck: &Check,
    path: &Path,
    motions: &Motions,
) -> Result<Vec<Support>, ModelError> {
    let run =
        match e.run {
            Some(r) => Some(runs.get(r.wrapping_sub(1)).ok_or_else(|| {
                ck.err("excitation.run", format!("no run {r} (1..={})", runs.len()))
            })?),
            None => None,
        };
    let (pga_x, pga_y) = run.map_or((None, None), |r| (Some(r.pga_x), Some(r.pga_y)));
    let base = Processing {
        time_scale: ck.positive("excitation.time_scale", e.time_scale)?,
        baseline: Baseline::Polynomial {
            order: e.baseline_order,
        },
        taper: e.taper.unwrap_or(Processing::default().taper),
        per_metre: ck.units.per_metre(),
        window: e.window.as_ref().map(|w| [w[0], w[1]]),
        ..Processing::default()
    };
    // supports with the same record, PGA and lag share one motion
    let get = |file: &Option<String>, field: &str, pga: Option<f64>, lag: f64| {
        let file = file
            .as_ref()
            .ok_or_else(|| ck.err(field, "required for record input"))?;
        let p = Processing {
            target_pga: pga,
            lag,
            ..base.clone()
        };
        let axis = if field.ends_with("longitudinal") {
            "x"
        } else {
            "y"
        };
        let model_field = |f: &str| match f {
            "target_pga" => e
                .run
                .map(|r| format!("run.{}.pga_{axis}", r.wrapping_sub(1))),
            "time_scale" | "taper" | "window" => Some(format!("excitation.{f}")),
            _ => None,
        };
        (motions.get(path, file, p)).map_err(|e| record_error(e, ck, field, file, &model_field))
    };
    let moving = |name: String, motion| Support {
        name,
        motion,
        factor: 1.0,
    };
    let record = |name: String, m| moving(name, Motion::Record(m));
    let longitudinal_only = longitudinal_only(e, ck)?;
    // at rest in y: u_g = 0
    let rest = || Motion::Harmonic {
        amplitude: 0.0,
        omega: 0.0,
        phase: 0.0,
    };
    let get_y = |l: f64| -> Result<Motion, ModelError> {
        if longitudinal_only {
            return Ok(rest());
        }
        get(&e.transverse, "excitation.transverse", pga_y, l).map(Motion::Record)
    };
    let mut out = Vec::new();
    for b in 0..nb {
        let l = lag(&e.lag_bents, b);
        let mx = get(&e.longitudinal, "excitation.longitudinal", pga_x, l)?;
        let my = get_y(l)?;
        out.push(record(format!("bent{}.x", b + 1), mx));
        out.push(moving(format!("bent{}.y", b + 1), my));
    }
    for (i, side) in ["left", "right"].iter().enumerate() {
        let l = lag(&e.lag_abutments, i);
        let m = get(&e.longitudinal, "excitation.longitudinal", pga_x, l)?;
        out.push(record(format!("{side}_abutment.x"), m));
    }
    if transverse {
        for (i, side) in ["left", "right"].iter().enumerate() {
            let l = lag(&e.lag_abutments, i);
            let m = get_y(l)?;
            out.push(moving(format!("{side}_abutment.y"), m));
        }
    }
    Ok(out)
}

/// `excitation.components`: whether only the longitudinal record moves the supports.
fn longitudinal_only(e: &ExcitationSpec, ck: &Check) -> Result<bool, ModelError> {
    match e.components.as_deref() {
        None | Some("both") => Ok(false),
        Some("longitudinal") => Ok(true),
        Some(c) => Err(ck.err(
            "excitation.components",
            format!("'{c}': \"both\" or \"longitudinal\""),
        )),
    }
}

/// Per-support lags: none (all 0) or one per support; fields the kind does not read refused.
fn validate_excitation(e: &ExcitationSpec, nb: usize, ck: &Check) -> Result<(), ModelError> {
    for (field, lags, n, what) in [
        ("excitation.lag_bents", &e.lag_bents, nb, "bent"),
        ("excitation.lag_abutments", &e.lag_abutments, 2, "abutment"),
    ] {
        if !lags.is_empty() && lags.len() != n {
            let k = lags.len();
            return Err(ck.err(
                field,
                format!("{k} lags for {n} {what}s: give one per {what} or none (all 0)"),
            ));
        }
        for (i, l) in lags.iter().enumerate() {
            ck.nonneg(&format!("{field}.{i}"), *l)?;
        }
    }
    if let Some(w) = &e.window {
        validate_window(w, &e.kind, ck)?;
    }
    Ok(())
}

/// `excitation.window`: `[start, end]`, finite, 0 ≤ start < end, on a record input.
fn validate_window(w: &[f64], kind: &str, ck: &Check) -> Result<(), ModelError> {
    let field = "excitation.window";
    if kind == "harmonic" {
        return Err(ck.err(
            field,
            "a window cuts recorded input: a harmonic excitation has no record to cut",
        ));
    }
    let &[start, end] = w else {
        let n = w.len();
        return Err(ck.err(field, format!("expected [start, end] (s), got {n} numbers")));
    };
    ck.finite(field, start)?;
    ck.finite(field, end)?;
    if start < 0.0 {
        return Err(ck.err(field, format!("start must be ≥ 0, got {start}")));
    }
    if end <= start {
        return Err(ck.err(
            field,
            format!("end must be after start, got [{start}, {end}]"),
        ));
    }
    Ok(())
}
