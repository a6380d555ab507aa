//! Processing a record into a motion: time scaling, baseline, taper, pad, end
//! correction, amplitude scaling (steps 1–6 of the module docs of [`super`]).

use serde::{Deserialize, Serialize};

use super::error::{Result, invalid};
use super::motion::{GroundMotion, max_abs};
use super::readers::{G, MAX_SAMPLES, Record};

/// Drift promised by a polynomial baseline: `|final disp| ≤ END_TOLERANCE·PGD` and
/// `|final vel| ≤ END_TOLERANCE·PGV` (measured ~1e-15 on the Northridge records).
pub const END_TOLERANCE: f64 = 1e-9;

/// Highest accepted [`Baseline::Polynomial`] order.
pub(crate) const MAX_POLY_ORDER: usize = 10;

/// A processed record must keep at least this fraction of its raw PGA: baseline correction
/// and taper change the PGA of a real accelerogram by a few per cent; a record they reduce
/// below 1 % (a constant, a pure drift) has no signal left, and scaling its round-off to a
/// target PGA would be noise.
pub(crate) const MIN_SIGNAL_FRACTION: f64 = 1e-2;

/// A `target_pga` factor must lie in [1/MAX_SCALE_FACTOR, MAX_SCALE_FACTOR]: recorded PGAs and
/// test targets both lie within 0.05–2 g (at most a factor 40 apart), while a record read in
/// the wrong unit is off by 981 (cm/s² as g) or a noise record by far more.
pub(crate) const MAX_SCALE_FACTOR: f64 = 100.0;

/// Largest ground acceleration a record may hold or be scaled to, g: the strongest recorded is
/// 4.4 g (Iwate–Miyagi 2008); a larger value is a unit mistake (cm/s² read as g) or a corrupt
/// file, and would drive the scene kilometres.
pub(crate) const MAX_PGA_G: f64 = 10.0;

/// Baseline correction (Boore & Bommer 2005).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Baseline {
    /// No correction (the motion may drift; after the end `at` holds the final displacement).
    None,
    /// Least-squares fit `Σ_{k=2}^{order} c_k (t/T)^k` to the displacement (no constant or
    /// linear term: starts at rest), its second derivative subtracted from the acceleration
    /// at the nodes, then the exact end correction (module docs, step 5).
    /// `order` in `2..=MAX_POLY_ORDER`.
    Polynomial {
        /// The polynomial's order.
        order: usize,
    },
}

impl Default for Baseline {
    fn default() -> Self {
        Baseline::Polynomial { order: 3 }
    }
}

/// Processing parameters (TOML/JSON: every field optional, unknown fields rejected).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(default, deny_unknown_fields)]
pub struct Processing {
    /// Target PGA in g: applied last, so `max|a|` of the processed motion equals it.
    pub target_pga: Option<f64>,
    /// Plain amplitude factor (exclusive with `target_pga`), applied last.
    pub scale: Option<f64>,
    /// `t' = t·time_scale`, > 0. Default 1.
    pub time_scale: f64,
    /// Start delay of this support, s, ≥ 0. Default 0.
    pub lag: f64,
    /// Default `Polynomial { order: 3 }`.
    pub baseline: Baseline,
    /// Cosine taper length at each end, processed seconds, ≥ 0, at most half the record.
    /// Default 0.5 s (acceleration starts and ends at zero).
    pub taper: f64,
    /// Zero acceleration appended, processed seconds, ≥ 0. Default 0.
    pub pad: f64,
    /// Length units of the model per metre: the processed motion (m/s², m/s, m) is multiplied
    /// by it last (`UnitSystem::per_metre`). Default 1; set from the model's `units`, never
    /// read from a file.
    #[serde(skip)]
    pub per_metre: f64,
    /// `[start, end]` of the run's time axis (processed seconds, `lag` included): only the
    /// samples inside it are kept, shifted so that `start` is t = 0, and steps 2–5 and the
    /// integration are applied to them (the cut starts at rest); the amplitude factor of step 6
    /// is the whole record's. Default none; set from the bridge file's `excitation.window`,
    /// never read from a processing table.
    #[serde(skip)]
    pub window: Option<[f64; 2]>,
}

impl Default for Processing {
    fn default() -> Self {
        Processing {
            target_pga: None,
            scale: None,
            time_scale: 1.0,
            lag: 0.0,
            baseline: Baseline::default(),
            taper: 0.5,
            pad: 0.0,
            per_metre: 1.0,
            window: None,
        }
    }
}

impl Processing {
    /// Checks the parameters alone (record-dependent checks happen in processing).
    pub fn validate(&self) -> Result<()> {
        if let Some(t) = self.target_pga {
            if !(t.is_finite() && t > 0.0) {
                return Err(invalid(
                    "target_pga",
                    format!("must be > 0 and finite, got {t}"),
                ));
            }
            if self.scale.is_some() {
                return Err(invalid("target_pga", "exclusive with scale"));
            }
        }
        if let Some(s) = self.scale
            && !s.is_finite()
        {
            return Err(invalid("scale", format!("must be finite, got {s}")));
        }
        if !(self.time_scale.is_finite() && self.time_scale > 0.0) {
            let v = self.time_scale;
            return Err(invalid(
                "time_scale",
                format!("must be > 0 and finite, got {v}"),
            ));
        }
        for (field, v) in [("lag", self.lag), ("taper", self.taper), ("pad", self.pad)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(invalid(field, format!("must be ≥ 0 and finite, got {v}")));
            }
        }
        if let Baseline::Polynomial { order } = self.baseline
            && !(2..=MAX_POLY_ORDER).contains(&order)
        {
            return Err(invalid(
                "baseline",
                format!("polynomial order must be in 2..={MAX_POLY_ORDER}, got {order}"),
            ));
        }
        if let Some([s, e]) = self.window
            && !(s.is_finite() && e.is_finite() && s >= 0.0 && e > s)
        {
            return Err(invalid(
                "window",
                format!("must be [start, end] with 0 ≤ start < end, finite, got [{s}, {e}]"),
            ));
        }
        Ok(())
    }
}

/// Exact node integrals of a piecewise-linear acceleration starting at rest.
fn integrate(dt: f64, a: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let mut vel = Vec::with_capacity(a.len());
    let mut disp = Vec::with_capacity(a.len());
    let (mut v, mut d) = (0.0, 0.0);
    if !a.is_empty() {
        vel.push(v);
        disp.push(d);
    }
    for w in a.windows(2) {
        (d, v) = step(dt, v, d, w[0], w[1]);
        vel.push(v);
        disp.push(d);
    }
    (vel, disp)
}

/// One exact interval step: returns (d, v) at the interval end.
#[inline]
fn step(dt: f64, v: f64, d: f64, a0: f64, a1: f64) -> (f64, f64) {
    (
        d + dt * v + dt * dt * (a0 / 3.0 + a1 / 6.0),
        v + 0.5 * dt * (a0 + a1),
    )
}

/// Final (v, d) of the exact integral, without allocation.
fn end_state(dt: f64, a: &[f64]) -> (f64, f64) {
    let (mut v, mut d) = (0.0, 0.0);
    for w in a.windows(2) {
        (d, v) = step(dt, v, d, w[0], w[1]);
    }
    (v, d)
}

/// Householder least squares; `cols` are the columns of the design matrix.
fn least_squares(mut cols: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let m = cols.len();
    let n = b.len();
    if n < m {
        return None;
    }
    for k in 0..m {
        let norm = cols[k][k..].iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm == 0.0 {
            return None;
        }
        let alpha = if cols[k][k] > 0.0 { -norm } else { norm };
        let mut v = cols[k][k..].to_vec();
        v[0] -= alpha;
        let vv: f64 = v.iter().map(|x| x * x).sum();
        let reflect = |x: &mut [f64]| {
            let f = 2.0 * v.iter().zip(x.iter()).map(|(p, q)| p * q).sum::<f64>() / vv;
            x.iter_mut().zip(&v).for_each(|(q, p)| *q -= f * p);
        };
        for col in cols.iter_mut().skip(k) {
            reflect(&mut col[k..]);
        }
        reflect(&mut b[k..]);
    }
    let rmax = (0..m).map(|i| cols[i][i].abs()).fold(0.0, f64::max);
    let mut c = vec![0.0; m];
    for i in (0..m).rev() {
        let rii = cols[i][i];
        if rii.is_nan() || rii.abs() <= 1e-13 * rmax {
            return None;
        }
        let s: f64 = b[i] - (i + 1..m).map(|j| cols[j][i] * c[j]).sum::<f64>();
        c[i] = s / rii;
    }
    Some(c)
}

/// Subtracts the second derivative of the least-squares displacement polynomial.
fn polynomial_correction(a: &mut [f64], dt: f64, order: usize) -> Result<()> {
    let n = a.len();
    if n < order + 2 {
        return Err(invalid(
            "baseline",
            format!(
                "polynomial order {order} needs at least {} samples, got {n}",
                order + 2
            ),
        ));
    }
    let (_, disp) = integrate(dt, a);
    let last = (n - 1) as f64;
    let tn = last * dt;
    let cols: Vec<Vec<f64>> = (2..=order)
        .map(|k| (0..n).map(|i| (i as f64 / last).powi(k as i32)).collect())
        .collect();
    let c = least_squares(cols, disp)
        .ok_or_else(|| invalid("baseline", "ill-conditioned polynomial fit"))?;
    for (i, x) in a.iter_mut().enumerate() {
        let s = i as f64 / last;
        let dd: f64 = (2..=order)
            .zip(&c)
            .map(|(k, ck)| ck * (k * (k - 1)) as f64 * s.powi(k as i32 - 2))
            .sum();
        *x -= dd / (tn * tn);
    }
    Ok(())
}

/// Adds `c1·s(1−s) + c2·s(1−s)(2s−1)` on the first `n_rec` nodes (zero at both record ends
/// and in the pad), `c1`, `c2` solved so the exact final velocity and displacement vanish.
fn end_correction(a: &mut [f64], dt: f64, n_rec: usize) -> Result<()> {
    if n_rec < 4 {
        return Err(invalid(
            "baseline",
            format!("end correction needs at least 4 samples, got {n_rec}"),
        ));
    }
    let last = (n_rec - 1) as f64;
    let shape = |i: usize, odd: bool| {
        if i >= n_rec {
            return 0.0;
        }
        let s = i as f64 / last;
        let b = s * (1.0 - s);
        if odd { b * (2.0 * s - 1.0) } else { b }
    };
    let p1: Vec<f64> = (0..a.len()).map(|i| shape(i, false)).collect();
    let p2: Vec<f64> = (0..a.len()).map(|i| shape(i, true)).collect();
    let (v1, d1) = end_state(dt, &p1);
    let (v2, d2) = end_state(dt, &p2);
    let det = v1 * d2 - v2 * d1;
    if det.is_nan() || det.abs() <= 1e-12 * (v1.abs() * d2.abs() + v2.abs() * d1.abs()) {
        return Err(invalid("baseline", "singular end correction"));
    }
    // Second pass removes the round-off left by the first.
    for _ in 0..2 {
        let (v, d) = end_state(dt, a);
        let c1 = (d * v2 - v * d2) / det;
        let c2 = (v * d1 - d * v1) / det;
        for ((x, q1), q2) in a.iter_mut().zip(&p1).zip(&p2) {
            *x += c1 * q1 + c2 * q2;
        }
    }
    Ok(())
}

fn sample_count(seconds: f64, dt: f64, field: &'static str) -> Result<usize> {
    let k = (seconds / dt).round();
    if k.is_nan() || k > MAX_SAMPLES as f64 {
        return Err(invalid(
            field,
            format!("{seconds} s is too many samples of {dt} s"),
        ));
    }
    Ok(k as usize)
}

/// Step 3: cosine (half-Hann) taper of `seconds` at both ends, at most half the record.
fn taper(a: &mut [f64], dt: f64, seconds: f64) -> Result<()> {
    let n = a.len();
    let m = sample_count(seconds, dt, "taper")?;
    if 2 * m > n - 1 {
        let len = (n - 1) as f64 * dt;
        return Err(invalid(
            "taper",
            format!("{seconds} s exceeds half the record ({len} s)"),
        ));
    }
    for i in 0..m {
        let w = 0.5 * (1.0 - (std::f64::consts::PI * i as f64 / m as f64).cos());
        a[i] *= w;
        a[n - 1 - i] *= w;
    }
    Ok(())
}

/// A record with signal left after processing ([`MIN_SIGNAL_FRACTION`]); PGAs in m/s².
fn check_signal(pga_raw: f64, pga_corr: f64) -> Result<()> {
    if pga_raw == 0.0 {
        return Err(invalid("acc", "no signal: every sample is zero"));
    }
    // (a NaN PGA has no signal either)
    if pga_corr.is_nan() || pga_corr < MIN_SIGNAL_FRACTION * pga_raw {
        return Err(invalid(
            "baseline",
            format!(
                "no signal after processing: raw PGA {:.4e} g, processed PGA {:.4e} g ({:.2e} \
                 of raw, below {MIN_SIGNAL_FRACTION}): baseline correction and taper removed \
                 the record (a constant or a pure drift)",
                pga_raw / G,
                pga_corr / G,
                pga_corr / pga_raw
            ),
        ));
    }
    Ok(())
}

/// Step 6: the amplitude factor, to `target_pga` (of the corrected PGA, within
/// [`MAX_SCALE_FACTOR`]) or `scale`, else 1.
fn amplitude_factor(p: &Processing, pga_raw: f64, pga_corr: f64) -> Result<f64> {
    Ok(match (p.target_pga, p.scale) {
        (Some(t), _) => {
            let factor = t * G / pga_corr;
            if !(1.0 / MAX_SCALE_FACTOR..=MAX_SCALE_FACTOR).contains(&factor) {
                return Err(invalid(
                    "target_pga",
                    format!(
                        "target {t} g needs a factor {factor:.4e} on the processed PGA \
                         {:.4e} g (raw PGA {:.4e} g), outside [{}, {MAX_SCALE_FACTOR}]: record \
                         and target are orders of magnitude apart (a unit mistake?)",
                        pga_corr / G,
                        pga_raw / G,
                        1.0 / MAX_SCALE_FACTOR
                    ),
                ));
            }
            factor
        }
        (None, Some(s)) => s,
        (None, None) => 1.0,
    })
}

/// The taper must fit twice in the time-scaled record; a short record from a small
/// `time_scale` is blamed on the time scale.
fn check_length(n: usize, dt_raw: f64, p: &Processing) -> Result<()> {
    let raw = (n - 1) as f64 * dt_raw;
    let len = raw * p.time_scale;
    if 2.0 * p.taper <= len {
        return Ok(());
    }
    let field = if p.time_scale != 1.0 && 2.0 * p.taper <= raw {
        "time_scale"
    } else {
        "taper"
    };
    let (ts, tp) = (p.time_scale, p.taper);
    Err(invalid(
        field,
        format!(
            "the record lasts {raw} s × time_scale {ts} = {len:.4e} s, shorter than the taper \
             of {tp} s at each end"
        ),
    ))
}

/// Steps 2–5 on the time-scaled samples `a` and the signal check: (corrected acceleration,
/// raw PGA, corrected PGA).
fn corrected(mut a: Vec<f64>, dt: f64, p: &Processing) -> Result<(Vec<f64>, f64, f64)> {
    let n = a.len();
    let pga_raw = max_abs(&a);

    if let Baseline::Polynomial { order } = p.baseline {
        polynomial_correction(&mut a, dt, order)?;
    }

    taper(&mut a, dt, p.taper)?;

    let pad = sample_count(p.pad, dt, "pad")?;
    if n + pad > MAX_SAMPLES {
        return Err(invalid("pad", format!("{} s is too long", p.pad)));
    }
    a.resize(n + pad, 0.0);

    if let Baseline::Polynomial { .. } = p.baseline {
        end_correction(&mut a, dt, n)?;
    }

    let pga_corr = max_abs(&a);
    check_signal(pga_raw, pga_corr)?;
    Ok((a, pga_raw, pga_corr))
}

/// The window `[s, e]` of the run's time axis on `n` samples `dt` apart (processed s) that
/// start at `lag`: the samples it keeps, `i0..=i1` (the first at or after s, the last at or
/// before e or the record's end; a node within 1e-9 of a sample counts as inside), and the
/// lag of the cut, `max(0, lag − s) + (i0·dt − max(0, s − lag))`: the cut starts at rest at its
/// first sample, t = 0 being s.
fn window_cut(
    [s, e]: [f64; 2],
    lag: f64,
    dt: f64,
    n: usize,
    taper: f64,
) -> Result<(usize, usize, f64)> {
    let duration = (n - 1) as f64 * dt;
    let (from, to) = ((s - lag).max(0.0), e - lag);
    if from >= duration {
        let end = lag + duration;
        return Err(invalid(
            "window",
            format!("starts at {s} s, after the record ends at {end} s (lag {lag} s)"),
        ));
    }
    if to <= 0.0 {
        return Err(invalid(
            "window",
            format!("ends at {e} s, before the record starts at its lag {lag} s"),
        ));
    }
    let i0 = (from / dt - 1e-9).ceil().max(0.0) as usize;
    let i1 = ((to / dt + 1e-9).floor() as usize).min(n - 1);
    let kept = i1.saturating_sub(i0) as f64 * dt;
    if i1 <= i0 || 2.0 * taper > kept {
        return Err(invalid(
            "window",
            format!(
                "[{s}, {e}] s keeps {kept} s of the record (samples of {dt} s), shorter than \
                 the taper of {taper} s at each end or than one sample"
            ),
        ));
    }
    let t0 = (lag - s).max(0.0) + (i0 as f64 * dt - from).max(0.0);
    Ok((i0, i1, t0))
}

impl GroundMotion {
    /// Processes a [`Record`] (g → m/s²); see [`GroundMotion::from_samples`].
    pub fn from_record(rec: &Record, p: &Processing) -> Result<Self> {
        if let Some(i) = rec.accel_g.iter().position(|x| !x.is_finite()) {
            let path = rec.path.display();
            return Err(invalid(
                "accel_g",
                format!("{path}: sample {i} is not finite"),
            ));
        }
        let peak = (rec.accel_g.iter().enumerate()).max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()));
        if let Some((i, x)) = peak
            && x.abs() > MAX_PGA_G
        {
            let path = rec.path.display();
            return Err(invalid(
                "accel_g",
                format!(
                    "{path}: sample {i} is {x:e} g, above the {MAX_PGA_G} g no ground motion                      reaches (the strongest recorded is 4.4 g): a unit mistake (cm/s² read as                      g?) or a corrupt file"
                ),
            ));
        }
        let mut m = Self::from_samples(rec.dt, rec.accel_g.iter().map(|x| x * G).collect(), p)?;
        if p.per_metre != 1.0 {
            for v in [&mut m.acc, &mut m.vel, &mut m.disp] {
                v.iter_mut().for_each(|x| *x *= p.per_metre);
            }
        }
        Ok(m)
    }

    /// Processes uniformly sampled accelerations (m/s², `dt` in record seconds); steps in the
    /// module docs. With a polynomial baseline the final velocity and displacement are zero
    /// within [`END_TOLERANCE`]; with `taper > 0` the first and last record samples are zero.
    pub fn from_samples(dt: f64, acc_m_s2: Vec<f64>, p: &Processing) -> Result<Self> {
        p.validate()?;
        if !(dt.is_finite() && dt > 0.0) {
            return Err(invalid("dt", format!("must be > 0 and finite, got {dt}")));
        }
        let n = acc_m_s2.len();
        if !(2..=MAX_SAMPLES).contains(&n) {
            return Err(invalid(
                "acc",
                format!("need 2..={MAX_SAMPLES} samples, got {n}"),
            ));
        }
        if let Some(i) = acc_m_s2.iter().position(|x| !x.is_finite()) {
            return Err(invalid("acc", format!("sample {i} is not finite")));
        }
        check_length(n, dt, p)?;
        let dt = dt * p.time_scale;
        if !(dt.is_finite() && dt > 0.0) {
            return Err(invalid(
                "time_scale",
                format!("scaled dt = {dt} is unusable"),
            ));
        }
        // the window's samples; the whole record's processing sets the amplitude factor
        let cut = (p.window)
            .map(|w| window_cut(w, p.lag, dt, n, p.taper))
            .transpose()?;
        let raw = cut.map(|(i0, i1, _)| acc_m_s2[i0..=i1].to_vec());
        let (mut a, mut pga_raw, mut pga_corr) = corrected(acc_m_s2, dt, p)?;
        let factor = amplitude_factor(p, pga_raw, pga_corr)?;
        let mut t0 = p.lag;
        if let (Some((.., lag)), Some(raw)) = (cut, raw) {
            (a, pga_raw, pga_corr) = corrected(raw, dt, p)?;
            t0 = lag;
        }
        let correction_pga_change = if pga_raw > 0.0 {
            pga_corr / pga_raw - 1.0
        } else {
            0.0
        };
        let scaled = factor.abs() * pga_corr / G;
        if scaled > MAX_PGA_G {
            let field = if p.target_pga.is_some() {
                "target_pga"
            } else {
                "scale"
            };
            return Err(invalid(
                field,
                format!(
                    "the scaled record peaks at {scaled:.4e} g (factor {factor:.4e} on {:.4e} g),                      above the {MAX_PGA_G} g no ground motion reaches",
                    pga_corr / G
                ),
            ));
        }
        if factor != 1.0 {
            a.iter_mut().for_each(|x| *x *= factor);
        }
        let (vel, disp) = integrate(dt, &a);
        Ok(GroundMotion {
            dt,
            t0,
            acc: a,
            vel,
            disp,
            correction_pga_change,
        })
    }
}
