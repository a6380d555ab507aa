//! A bridge in bridge words, compiled into the engine's general [`Scene`] (paper §2, §4.1):
//! frames (rigid decks, x, y, θ each; x, y only with `rotation = false`) in series between two
//! abutments (x, θ) on two actuator spring–dampers each; deck-corner contacts at the abutments
//! and at the expansion joints between frames (corner on face between two moving bodies);
//! two-column bents with hysteretic columns; Rayleigh damping; multi-support excitation. The
//! shake-table specimen is the one-frame case (`[deck]`).
//!
//! - [`schema`]: the file's tables; [`layout`]: frames, support lines, skew, headings, corner
//!   contacts; `structure`: actuators and columns; `supports`: the excitation; `seat`: seats and
//!   AASHTO's support length; `validate`: the checks.
//!
//! Units: t, kN, m, s (1 t·m/s² = 1 kN).

mod abutments;
pub mod layout;
pub mod schema;
mod seat;
mod structure;
mod supports;
mod validate;

pub use abutments::{caltrans_backfill, skew_reduction};
pub use schema::*;

use super::check::{Check, ModelError};
use super::records::Motions;
use super::solver::settings;
use super::warnings::ModelWarning;
use crate::modal::{apply_rayleigh_coefficients, rayleigh_coefficients};
use crate::scene::{MassDamping, Scene, Settings, Support};
use layout::{Frame, Plan};
use nalgebra::DVector;
use seat::SeatSpec;

/// Validate and compile a bridge file into the engine's general scene.
pub fn compile(f: &BridgeFile, ck: &Check, motions: &Motions) -> Result<Scene, ModelError> {
    let path = ck.path;
    let settings = settings(&f.solver, ck)?;
    let frames = layout::frames(f);
    validate::validate(f, &frames, ck)?;
    let kind = abutments::validate(f, ck)?;
    // supports: per bent x and y, per abutment x, and y where keys, bearings or the ground
    // move something beside the deck ends
    let nb = frames.iter().map(|fr| fr.bents.len()).sum();
    let a = &f.abutment;
    let transverse = kind != Kind::Actuators || a.key.is_some() || a.bearing.is_some();
    let supports = match &f.excitation {
        Some(e) => supports::excitation_supports(e, &f.runs, nb, transverse, ck, path, motions)?,
        None => Vec::new(),
    };
    let mut scene = assemble(f, ck, &frames, (kind, transverse), supports, settings)?;
    if f.damping.ratio > 0.0 {
        let (ratio, modes) = (f.damping.ratio, f.damping.modes);
        let err = |r| ck.err("damping.modes", r);
        // a translating frame keeps the damping of the bridge whose frames all rotate: its
        // modes 1 and 3 are that bridge's, and only θ is held
        let (a0, a1) = if frames.iter().all(|fr| fr.rotation) {
            rayleigh_coefficients(&scene, ratio, modes).map_err(err)?
        } else {
            let turning: Vec<Frame> = (frames.iter().cloned())
                .map(|fr| Frame {
                    rotation: true,
                    ..fr
                })
                .collect();
            let (s, t) = (scene.supports.clone(), scene.settings.clone());
            let full = assemble(f, ck, &turning, (kind, transverse), s, t)?;
            rayleigh_coefficients(&full, ratio, modes).map_err(err)?
        };
        apply_rayleigh_coefficients(&mut scene, a0, a1);
    }
    Ok(scene)
}

/// The scene of the bridge's `frames` on its abutments with `supports`, undamped.
fn assemble(
    f: &BridgeFile,
    ck: &Check,
    frames: &[Frame],
    (kind, transverse): (Kind, bool),
    supports: Vec<Support>,
    settings: Settings,
) -> Result<Scene, ModelError> {
    let plan = Plan::of(f, frames);
    let nb = frames.iter().map(|fr| fr.bents.len()).sum::<usize>();
    let ex = f.excitation.as_ref();
    let driven = !supports.is_empty();
    let sx = driven.then_some([2 * nb, 2 * nb + 1]);
    let sy = (driven && transverse).then_some([2 * nb + 2, 2 * nb + 3]);
    let follow = ex.is_some_and(|e| e.drive_abutments);
    let drive = |i: usize| match kind {
        Kind::Rigid if follow => [sx.map(|s| s[i]), sy.map(|s| s[i])],
        Kind::Backfill => [None, sy.map(|s| s[i])],
        _ => [None; 2],
    };
    let (bodies, mass, dof_names) = layout::bodies(f, kind, frames, &plan, [drive(0), drive(1)]);
    let contacts = layout::corner_contacts(f, frames, &plan, &bodies);
    let ends = abutments::Ends {
        last: bodies.len() - 1,
        sx,
        sy,
        drive_actuators: driven && follow,
    };
    let a = &f.abutment;
    let mut springs = abutments::abutment_springs(a, kind, &ends);
    let mut hysteretic =
        structure::bent_columns(&f.column, frames, &plan, ck, driven, &mut springs)?;
    hysteretic.extend(abutments::abutment_elements(
        f, kind, frames, &plan, &ends, ck,
    )?);
    hysteretic.extend(abutments::joint_keys(f, frames, &plan, ck)?);
    let seats = seat::seats(&seat_lines(f, frames, &plan), ck)?;
    let n = mass.len();
    Ok(Scene {
        title: title(f),
        units: ck.units,
        bridge: true,
        seats,
        bodies,
        contacts,
        springs,
        hysteretic,
        supports,
        mass_damping: MassDamping::default(),
        loads: DVector::zeros(n),
        mass,
        dof_names,
        q0: DVector::zeros(n),
        v0: DVector::zeros(n),
        settings,
    })
}

/// The title: the file's (or "bridge") and, for a record input at a test run, that run and
/// its target PGAs (`four-span straight bridge, test run 4 (0.60 g / 0.50 g)`).
fn title(f: &BridgeFile) -> String {
    let base = f.title.clone().unwrap_or_else(|| "bridge".into());
    let run = (f.excitation.as_ref())
        .filter(|e| e.kind == "record")
        .and_then(|e| e.run)
        .and_then(|r| Some((r, f.runs.get(r.checked_sub(1)?)?)));
    match run {
        Some((r, spec)) => format!(
            "{base}, test run {r} ({:.2} g / {:.2} g)",
            spec.pga_x, spec.pga_y
        ),
        None => base,
    }
}

/// Mean column height of some frames' bents, m.
fn mean_height(frames: &[Frame]) -> f64 {
    let h: Vec<f64> = frames
        .iter()
        .flat_map(|fr| fr.bents.iter().map(|b| b.height))
        .collect();
    h.iter().sum::<f64>() / (h.len().max(1) as f64)
}

/// The seats of the two abutments (their four corners, when `contacts.enabled`) and of each
/// joint (its two corners), with AASHTO's L, H and S of each.
fn seat_lines(f: &BridgeFile, frames: &[Frame], plan: &Plan) -> Vec<SeatSpec> {
    let n = frames.len();
    let a = &f.abutment;
    let mut lines = Vec::new();
    let mut next = 0;
    if f.contacts.enabled {
        for (side, k) in [(0usize, 0usize), (1, n - 1)] {
            lines.push(SeatSpec {
                table: "abutment".into(),
                width: a.seat_width,
                percent: a.seat_percent,
                corners: (2 * side..2 * side + 2)
                    .map(|i| (i, f.contacts.gaps[i]))
                    .collect(),
                length: frames[k].length,
                height: mean_height(&frames[k..=k]),
                skew: plan.lines[if side == 0 { 0 } else { n }].skew,
            });
        }
        next = 4;
    }
    for (j, joint) in f.joints.iter().enumerate().take(n - 1) {
        lines.push(SeatSpec {
            table: format!("joint.{j}"),
            width: joint.seat_width,
            percent: joint.seat_percent,
            corners: vec![(next, joint.gaps[0]), (next + 1, joint.gaps[1])],
            length: frames[j].length + frames[j + 1].length,
            height: mean_height(&frames[j..=j + 1]),
            skew: plan.lines[j + 1].skew,
        });
        next += 2;
    }
    lines
}

/// What a bridge file leaves to defaults or does not use: no `[excitation]`, `[[run]]` tables
/// that no `excitation.run` picks, excitation fields its kind does not read (kept so that
/// `--set excitation.kind=…` can switch kinds).
pub fn warnings(f: &BridgeFile, ck: &Check) -> Vec<ModelWarning> {
    let path = ck.path.to_path_buf();
    let mut unread_abutment = Vec::new();
    if let Ok(kind) = Kind::of(&f.abutment, ck) {
        for k in abutments::unread(&f.abutment, kind) {
            let field = format!("abutment.{k}");
            unread_abutment.push(ModelWarning::AbutmentUnread {
                path: path.clone(),
                line: ck.line(&field),
                field,
                kind: kind.name().into(),
            });
        }
    }
    let mut out = unread_abutment;
    out.extend(excitation_warnings(f, ck));
    out
}

/// What the `[excitation]` leaves to defaults or does not use.
fn excitation_warnings(f: &BridgeFile, ck: &Check) -> Vec<ModelWarning> {
    let path = ck.path.to_path_buf();
    let Some(e) = &f.excitation else {
        return vec![ModelWarning::NoExcitation { path }];
    };
    let mut out = Vec::new();
    if e.kind == "record" && e.run.is_none() && !f.runs.is_empty() {
        let runs = f.runs.len();
        out.push(ModelWarning::RunsUnused {
            path: path.clone(),
            runs,
        });
    }
    let unread: &[(&str, bool)] = match e.kind.as_str() {
        "harmonic" => &[
            ("longitudinal", e.longitudinal.is_some()),
            ("transverse", e.transverse.is_some()),
            ("run", e.run.is_some()),
            ("taper", e.taper.is_some()),
        ],
        "record" => &[
            ("amplitude_x", e.amplitude_x.is_some()),
            ("amplitude_y", e.amplitude_y.is_some()),
            ("frequency", e.frequency.is_some()),
        ],
        _ => &[],
    };
    for (k, _) in unread.iter().filter(|(_, given)| *given) {
        let field = format!("excitation.{k}");
        out.push(ModelWarning::Unread {
            path: path.clone(),
            line: ck.line(&field),
            field,
            kind: e.kind.clone(),
        });
    }
    out
}

/// The tables only a bridge file has.
const BRIDGE_TABLES: [&str; 8] = [
    "abutment",
    "joint",
    "contacts",
    "bent",
    "column",
    "damping",
    "excitation",
    "run",
];

/// A file without `[deck]` or `[[frame]]` but with a bridge's tables is a bridge missing its
/// deck (not a general scene with unknown fields).
pub(crate) fn refuse_without_deck(table: &toml::Table, ck: &Check) -> Result<(), ModelError> {
    let Some(key) = BRIDGE_TABLES.iter().find(|k| table.contains_key(**k)) else {
        return Ok(());
    };
    let line = ck.line(key);
    Err(ModelError::Invalid {
        path: ck.path.to_path_buf(),
        line,
        field: "deck".into(),
        reason: format!(
            "missing: [{key}] (line {line}) makes this a bridge file, which needs a [deck] \
             table (mass, inertia, length, width) or [[frame]] tables"
        ),
    })
}
