//! Recorded accelerograms → support motions for multi-support excitation.
//!
//! Readers: PEER NGA `.AT2` ([`read_at2`]) and two-column `t a` text ([`read_two_column`]).
//! Processing ([`GroundMotion::from_samples`]), in this order:
//!
//! 1. time scaling `t' = t·time_scale` (similitude: 1/4 scale → 0.5; accelerations unchanged);
//! 2. baseline correction ([`Baseline`]): fit to the displacement, subtract its second
//!    derivative at the nodes (Boore 2001; Boore & Bommer 2005);
//! 3. cosine (half-Hann) taper of `taper` s at both ends (processed time);
//! 4. `pad` s of zero acceleration appended;
//! 5. exact end correction (with a polynomial baseline only): two smooth shapes vanishing at
//!    both record ends are added to the acceleration, their weights solved so that the
//!    exactly integrated final velocity and displacement are zero (see [`END_TOLERANCE`]);
//! 6. amplitude scaling (`target_pga` or `scale`), last, so the processed PGA equals the
//!    target and the drift stays zero (both steps are linear).
//!
//! Acceleration is piecewise linear between samples; velocity and displacement are its exact
//! integrals (piecewise quadratic / cubic), so `d' = v`, `v' = a` hold at every `t`.
//!
//! References: D. M. Boore (2001), BSSA 91(5) 1199–1211; D. M. Boore & J. J. Bommer (2005),
//! Soil Dyn. Earthq. Eng. 25, 93–115; A. Arias (1970); M. D. Trifunac & A. G. Brady (1975),
//! BSSA 65(3) 581–626 (5–95 % significant duration); PEER NGA AT2 format.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

/// Standard gravity, m/s².
pub const G: f64 = 9.80665;

/// Drift promised by a polynomial baseline: `|final disp| ≤ END_TOLERANCE·PGD` and
/// `|final vel| ≤ END_TOLERANCE·PGV` (measured ~1e-15 on the Northridge records).
pub const END_TOLERANCE: f64 = 1e-9;

/// Highest accepted [`Baseline::Polynomial`] order.
pub const MAX_POLY_ORDER: usize = 10;

/// Largest number of samples a processed motion may have (guards `pad` / `time_scale`).
pub const MAX_SAMPLES: usize = 50_000_000;

/// Errors from reading or processing a record.
#[derive(Debug, thiserror::Error)]
pub enum ExcitationError {
    /// The file could not be read (missing, permissions, not UTF-8 …).
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// Missing or garbled header (`NPTS`/`DT` line of an AT2, unit directive of a text file).
    #[error("{}:{line}: bad header: {reason}", path.display())]
    Header {
        path: PathBuf,
        line: usize,
        reason: String,
    },
    /// A value that is not a finite number.
    #[error("{}:{line}: not a finite number: {token:?}", path.display())]
    Value {
        path: PathBuf,
        line: usize,
        token: String,
    },
    /// `NPTS` disagrees with the number of values.
    #[error("{}: header says NPTS = {expected}, found {found} values", path.display())]
    Count {
        path: PathBuf,
        expected: usize,
        found: usize,
    },
    /// A two-column file row with the wrong number of columns.
    #[error("{}:{line}: expected {expected} columns, found {found}", path.display())]
    Columns {
        path: PathBuf,
        line: usize,
        expected: usize,
        found: usize,
    },
    /// A two-column file whose time column is not uniformly increasing.
    #[error("{}:{line}: {reason}", path.display())]
    Sampling {
        path: PathBuf,
        line: usize,
        reason: String,
    },
    /// Bad processing parameter or sample data.
    #[error("invalid {field}: {reason}")]
    Invalid { field: &'static str, reason: String },
}

type Result<T> = std::result::Result<T, ExcitationError>;

fn invalid(field: &'static str, reason: impl Into<String>) -> ExcitationError {
    ExcitationError::Invalid {
        field,
        reason: reason.into(),
    }
}

/// A uniformly sampled record, accelerations in g.
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    pub path: PathBuf,
    /// AT2: the 4 header lines; two-column: the comment lines.
    pub header: Vec<String>,
    /// Sampling interval, s.
    pub dt: f64,
    pub accel_g: Vec<f64>,
}

fn read_text(path: &Path) -> Result<String> {
    std::fs::read_to_string(path).map_err(|source| ExcitationError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Finite number; Fortran `D` exponents accepted.
fn parse_num(tok: &str) -> Option<f64> {
    let v = match tok.parse::<f64>() {
        Ok(v) => v,
        Err(_) if tok.contains(['D', 'd']) => tok.replace(['D', 'd'], "E").parse().ok()?,
        Err(_) => return None,
    };
    v.is_finite().then_some(v)
}

/// Reads a PEER NGA `.AT2` file (4 header lines, 4th `NPTS= n, DT= dt SEC`; values in g).
pub fn read_at2(path: &Path) -> Result<Record> {
    parse_at2(path, &read_text(path)?)
}

/// Text after `key` followed by optional blanks and `=` or `:`; `key` must not follow a letter.
fn after_key<'a>(upper: &'a str, key: &str) -> Option<&'a str> {
    let mut from = 0;
    while let Some(k) = upper[from..].find(key) {
        let start = from + k;
        let end = start + key.len();
        let prev_ok = !upper[..start]
            .chars()
            .next_back()
            .is_some_and(|c| c.is_ascii_alphabetic());
        let rest = upper[end..].trim_start();
        if prev_ok && let Some(r) = rest.strip_prefix(['=', ':']) {
            return Some(r.trim_start());
        }
        from = end;
    }
    None
}

fn number_token(s: &str) -> &str {
    let end = s
        .find(|c: char| !(c.is_ascii_digit() || matches!(c, '.' | '+' | '-' | 'E')))
        .unwrap_or(s.len());
    &s[..end]
}

fn parse_npts(tok: &str) -> std::result::Result<usize, String> {
    tok.parse::<usize>()
        .ok()
        .or_else(|| {
            parse_num(tok)
                .filter(|v| *v >= 0.0 && v.fract() == 0.0 && *v <= MAX_SAMPLES as f64)
                .map(|v| v as usize)
        })
        .filter(|n| (1..=MAX_SAMPLES).contains(n))
        .ok_or_else(|| format!("NPTS must be an integer in 1..={MAX_SAMPLES}, found {tok:?}"))
}

fn parse_dt(tok: &str) -> std::result::Result<f64, String> {
    parse_num(tok)
        .filter(|v| *v > 0.0)
        .ok_or_else(|| format!("DT must be a positive number, found {tok:?}"))
}

/// `NPTS= 1999, DT= 0.0100 SEC` and variants (any case, no comma, `:`), or the old
/// positional `1999 0.0100 NPTS, DT` layout.
fn parse_npts_dt(line: &str) -> std::result::Result<(usize, f64), String> {
    let upper = line.to_ascii_uppercase();
    match (after_key(&upper, "NPTS"), after_key(&upper, "DT")) {
        (Some(n), Some(d)) => Ok((parse_npts(number_token(n))?, parse_dt(number_token(d))?)),
        (Some(_), None) => Err(format!("missing `DT=` in {line:?}")),
        (None, Some(_)) => Err(format!("missing `NPTS=` in {line:?}")),
        (None, None) => {
            let mut toks = line
                .split(|c: char| c.is_whitespace() || c == ',')
                .filter(|t| !t.is_empty());
            match (toks.next(), toks.next()) {
                (Some(n), Some(d)) if parse_num(n).is_some() && parse_num(d).is_some() => {
                    Ok((parse_npts(n)?, parse_dt(d)?))
                }
                _ => Err(format!("expected `NPTS= n, DT= dt SEC`, found {line:?}")),
            }
        }
    }
}

/// Parses AT2 text; `path` is only used in errors and the returned [`Record`].
pub fn parse_at2(path: &Path, text: &str) -> Result<Record> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = text.lines();
    let header: Vec<String> = lines.by_ref().take(4).map(str::to_owned).collect();
    if header.len() < 4 {
        return Err(ExcitationError::Header {
            path: path.to_path_buf(),
            line: header.len() + 1,
            reason: format!("expected 4 header lines, file has {}", header.len()),
        });
    }
    let (npts, dt) = parse_npts_dt(&header[3]).map_err(|reason| ExcitationError::Header {
        path: path.to_path_buf(),
        line: 4,
        reason,
    })?;
    let mut accel_g = Vec::with_capacity(npts);
    for (k, line) in lines.enumerate() {
        for tok in line.split_whitespace() {
            let v = parse_num(tok).ok_or_else(|| ExcitationError::Value {
                path: path.to_path_buf(),
                line: k + 5,
                token: tok.to_owned(),
            })?;
            accel_g.push(v);
        }
    }
    if accel_g.len() != npts {
        return Err(ExcitationError::Count {
            path: path.to_path_buf(),
            expected: npts,
            found: accel_g.len(),
        });
    }
    Ok(Record {
        path: path.to_path_buf(),
        header,
        dt,
        accel_g,
    })
}

/// Reads a two-column `t a` file (blank, comma or semicolon separated; `#` starts a comment).
///
/// `a` is in g unless a comment `# units: U` states U ∈ {g, m/s2, m/s^2, cm/s2, cm/s^2, gal,
/// mm/s2, mm/s^2}; values are converted to g. Times must increase uniformly: every step
/// within 0.2 % of the first and every `t_i` within `1e-3·dt` of `t_0 + i·dt`, where
/// `dt = (t_last − t_0)/(n − 1)`, else
/// [`ExcitationError::Sampling`] (no resampling). The first time is taken as the record
/// start (a nonzero `t_0` is dropped: use [`Processing::lag`] for delays).
pub fn read_two_column(path: &Path) -> Result<Record> {
    parse_two_column(path, &read_text(path)?)
}

fn unit_to_g(unit: &str) -> Option<f64> {
    Some(match unit {
        "g" => 1.0,
        "m/s2" | "m/s^2" | "m/s**2" => 1.0 / G,
        "cm/s2" | "cm/s^2" | "cm/s**2" | "gal" => 0.01 / G,
        "mm/s2" | "mm/s^2" | "mm/s**2" => 0.001 / G,
        _ => return None,
    })
}

/// Parses two-column text; see [`read_two_column`].
pub fn parse_two_column(path: &Path, text: &str) -> Result<Record> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut header = Vec::new();
    let mut factor: Option<f64> = None;
    let mut rows: Vec<(usize, f64, f64)> = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let (data, comment) = match raw.split_once('#') {
            Some((d, c)) => (d, Some(c)),
            None => (raw, None),
        };
        if let Some(c) = comment {
            header.push(raw.to_owned());
            let c = c.trim().to_ascii_lowercase();
            if let Some(rest) = c.strip_prefix("units").or_else(|| c.strip_prefix("unit"))
                && let Some(u) = rest.trim_start().strip_prefix([':', '='])
            {
                let u = u.trim();
                let f = unit_to_g(u).ok_or_else(|| ExcitationError::Header {
                    path: path.to_path_buf(),
                    line,
                    reason: format!("unknown acceleration unit {u:?}"),
                })?;
                if factor.is_some_and(|old| old != f) {
                    return Err(ExcitationError::Header {
                        path: path.to_path_buf(),
                        line,
                        reason: "conflicting units directives".into(),
                    });
                }
                factor = Some(f);
            }
        }
        let toks: Vec<&str> = data
            .split(|c: char| c.is_whitespace() || c == ',' || c == ';')
            .filter(|t| !t.is_empty())
            .collect();
        if toks.is_empty() {
            continue;
        }
        if toks.len() != 2 {
            return Err(ExcitationError::Columns {
                path: path.to_path_buf(),
                line,
                expected: 2,
                found: toks.len(),
            });
        }
        let num = |tok: &str| {
            parse_num(tok).ok_or_else(|| ExcitationError::Value {
                path: path.to_path_buf(),
                line,
                token: tok.to_owned(),
            })
        };
        rows.push((line, num(toks[0])?, num(toks[1])?));
    }
    let sampling = |line: usize, reason: String| ExcitationError::Sampling {
        path: path.to_path_buf(),
        line,
        reason,
    };
    let (first, last) = match (rows.first(), rows.last()) {
        (Some(f), Some(l)) if rows.len() >= 2 => (*f, *l),
        _ => {
            let line = rows.first().map_or(text.lines().count().max(1), |r| r.0);
            return Err(sampling(
                line,
                format!("need at least 2 samples, found {}", rows.len()),
            ));
        }
    };
    let step0 = rows[1].1 - first.1;
    for w in rows.windows(2) {
        let h = w[1].1 - w[0].1;
        if !(h > 0.0 && (h - step0).abs() <= 2e-3 * step0) {
            return Err(sampling(
                w[1].0,
                format!("time step {h} differs from the first step {step0}"),
            ));
        }
    }
    let dt = (last.1 - first.1) / (rows.len() - 1) as f64;
    for (i, &(line, t, _)) in rows.iter().enumerate() {
        let expect = first.1 + i as f64 * dt;
        if (t - expect).abs() > 1e-3 * dt {
            return Err(sampling(
                line,
                format!("non-uniform time step: t = {t}, expected {expect} (dt = {dt})"),
            ));
        }
    }
    let f = factor.unwrap_or(1.0);
    Ok(Record {
        path: path.to_path_buf(),
        header,
        dt,
        accel_g: rows.iter().map(|r| r.2 * f).collect(),
    })
}

/// By extension: `.at2` (any case) → [`read_at2`], anything else → [`read_two_column`].
pub fn read_any(path: &Path) -> Result<Record> {
    let is_at2 = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("at2"));
    if is_at2 {
        read_at2(path)
    } else {
        read_two_column(path)
    }
}

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
    Polynomial { order: usize },
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
        Ok(())
    }
}

/// Summary of a processed motion (SI units unless `_g`).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize, Serialize)]
pub struct MotionStats {
    pub pga_g: f64,
    /// m/s².
    pub pga: f64,
    /// Exact max |v| of the piecewise-quadratic velocity, m/s.
    pub pgv: f64,
    /// Exact max |d| of the piecewise-cubic displacement, m.
    pub pgd: f64,
    /// Sampled length (without lag), s.
    pub duration: f64,
    /// 5–95 % Arias significant duration (Trifunac & Brady 1975), s.
    pub significant_duration: f64,
    /// Arias intensity `π/(2g)∫a²dt`, m/s.
    pub arias_intensity: f64,
    pub final_displacement: f64,
    pub final_velocity: f64,
    /// Relative PGA change from baseline correction + taper (before amplitude scaling).
    pub correction_pga_change: f64,
}

/// A processed, uniformly sampled support motion (SI units).
#[derive(Clone, Debug, PartialEq)]
pub struct GroundMotion {
    /// Sampling interval, s.
    pub dt: f64,
    /// Start time (the lag), s.
    pub t0: f64,
    /// Node accelerations, m/s².
    pub acc: Vec<f64>,
    /// Node velocities, m/s (exact integral, `vel[0] = 0`).
    pub vel: Vec<f64>,
    /// Node displacements, m (exact integral, `disp[0] = 0`).
    pub disp: Vec<f64>,
    /// Relative PGA change from baseline correction + taper.
    pub correction_pga_change: f64,
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

fn max_abs(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m: f64, x| m.max(x.abs()))
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
        Self::from_samples(rec.dt, rec.accel_g.iter().map(|x| x * G).collect(), p)
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
        let dt = dt * p.time_scale;
        if !(dt.is_finite() && dt > 0.0) {
            return Err(invalid(
                "time_scale",
                format!("scaled dt = {dt} is unusable"),
            ));
        }
        let mut a = acc_m_s2;
        let pga_raw = max_abs(&a);

        if let Baseline::Polynomial { order } = p.baseline {
            polynomial_correction(&mut a, dt, order)?;
        }

        let m = sample_count(p.taper, dt, "taper")?;
        if 2 * m > n - 1 {
            let len = (n - 1) as f64 * dt;
            return Err(invalid(
                "taper",
                format!("{} s exceeds half the record ({len} s)", p.taper),
            ));
        }
        for i in 0..m {
            let w = 0.5 * (1.0 - (std::f64::consts::PI * i as f64 / m as f64).cos());
            a[i] *= w;
            a[n - 1 - i] *= w;
        }

        let pad = sample_count(p.pad, dt, "pad")?;
        if n + pad > MAX_SAMPLES {
            return Err(invalid("pad", format!("{} s is too long", p.pad)));
        }
        a.resize(n + pad, 0.0);

        if let Baseline::Polynomial { .. } = p.baseline {
            end_correction(&mut a, dt, n)?;
        }

        let pga_corr = max_abs(&a);
        let correction_pga_change = if pga_raw > 0.0 {
            pga_corr / pga_raw - 1.0
        } else {
            0.0
        };
        let factor = match (p.target_pga, p.scale) {
            (Some(t), _) => {
                if pga_corr == 0.0 {
                    return Err(invalid("target_pga", "motion has zero PGA"));
                }
                t * G / pga_corr
            }
            (None, Some(s)) => s,
            (None, None) => 1.0,
        };
        if factor != 1.0 {
            a.iter_mut().for_each(|x| *x *= factor);
        }
        let (vel, disp) = integrate(dt, &a);
        Ok(GroundMotion {
            dt,
            t0: p.lag,
            acc: a,
            vel,
            disp,
            correction_pga_change,
        })
    }

    fn valid(&self) -> bool {
        let n = self.acc.len();
        n >= 2 && self.vel.len() == n && self.disp.len() == n
    }

    /// (d, v, a) at local time `s ∈ [0, dt]` of interval `i`.
    #[inline]
    fn local(&self, i: usize, s: f64) -> (f64, f64, f64) {
        let (a0, a1) = (self.acc[i], self.acc[i + 1]);
        let j = (a1 - a0) / self.dt;
        let a = a0 + j * s;
        let v = self.vel[i] + s * (a0 + 0.5 * j * s);
        let d = self.disp[i] + s * (self.vel[i] + s * (0.5 * a0 + j * s / 6.0));
        (d, v, a)
    }

    /// (displacement, velocity, acceleration) at `t`: zero before `t0`; at and after the end,
    /// (final displacement, 0, 0). O(1), no allocation; NaN `t` gives NaNs.
    pub fn at(&self, t: f64) -> (f64, f64, f64) {
        let tau = t - self.t0;
        if tau.is_nan() {
            return (f64::NAN, f64::NAN, f64::NAN);
        }
        if tau < 0.0 || !self.valid() {
            return (0.0, 0.0, 0.0);
        }
        let last = self.acc.len() - 1;
        if tau >= last as f64 * self.dt {
            return (self.disp[last], 0.0, 0.0);
        }
        let i = ((tau / self.dt) as usize).min(last - 1);
        self.local(i, tau - i as f64 * self.dt)
    }

    /// Sampled length `(n − 1)·dt`, s (the lag not included).
    pub fn duration(&self) -> f64 {
        self.acc.len().saturating_sub(1) as f64 * self.dt
    }

    /// `t0 + duration()`: from here on the support is at rest.
    pub fn end_time(&self) -> f64 {
        self.t0 + self.duration()
    }

    /// The breakpoints `t0 + i·dt` (kinks of the acceleration).
    pub fn sample_times(&self) -> impl Iterator<Item = f64> + use<> {
        let (t0, dt) = (self.t0, self.dt);
        (0..self.acc.len()).map(move |i| t0 + i as f64 * dt)
    }

    /// Peak values (exact for the piecewise polynomials), durations and end drift.
    pub fn stats(&self) -> MotionStats {
        let duration = self.duration();
        let pga = max_abs(&self.acc);
        let mut st = MotionStats {
            pga_g: pga / G,
            pga,
            pgv: 0.0,
            pgd: 0.0,
            duration,
            significant_duration: 0.0,
            arias_intensity: 0.0,
            final_displacement: self.disp.last().copied().unwrap_or(0.0),
            final_velocity: self.vel.last().copied().unwrap_or(0.0),
            correction_pga_change: self.correction_pga_change,
        };
        if !self.valid() {
            return st;
        }
        let dt = self.dt;
        let mut pgv = max_abs(&self.vel);
        let mut pgd = max_abs(&self.disp);
        for i in 0..self.acc.len() - 1 {
            let (a0, a1, v0) = (self.acc[i], self.acc[i + 1], self.vel[i]);
            // velocity extremum where a = 0
            if a0 * a1 < 0.0 {
                let s = a0 * dt / (a0 - a1);
                pgv = pgv.max(self.local(i, s).1.abs());
            }
            // displacement extrema where v = v0 + a0 s + k s² = 0
            let k = 0.5 * (a1 - a0) / dt;
            let mut roots = [f64::NAN; 2];
            if k == 0.0 {
                if a0 != 0.0 {
                    roots[0] = -v0 / a0;
                }
            } else {
                let disc = a0 * a0 - 4.0 * k * v0;
                if disc >= 0.0 {
                    let sgn = if a0 >= 0.0 { 1.0 } else { -1.0 };
                    let q = -0.5 * (a0 + sgn * disc.sqrt());
                    roots[0] = q / k;
                    if q != 0.0 {
                        roots[1] = v0 / q;
                    }
                }
            }
            for s in roots {
                if s > 0.0 && s < dt {
                    pgd = pgd.max(self.local(i, s).0.abs());
                }
            }
        }
        st.pgv = pgv;
        st.pgd = pgd;

        // Arias: ∫a² per interval, exact for linear a.
        let seg = |i: usize, s: f64| {
            let a0 = self.acc[i];
            let j = (self.acc[i + 1] - a0) / dt;
            s * (a0 * a0 + s * (a0 * j + s * j * j / 3.0))
        };
        let mut cum = Vec::with_capacity(self.acc.len());
        let mut e = 0.0;
        cum.push(0.0);
        for i in 0..self.acc.len() - 1 {
            e += seg(i, dt);
            cum.push(e);
        }
        st.arias_intensity = std::f64::consts::PI / (2.0 * G) * e;
        if e > 0.0 {
            let crossing = |frac: f64| {
                let target = frac * e;
                let i = cum.partition_point(|c| *c < target).clamp(1, cum.len() - 1) - 1;
                let (mut lo, mut hi) = (0.0, dt);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if cum[i] + seg(i, mid) < target {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                i as f64 * dt + 0.5 * (lo + hi)
            };
            st.significant_duration = crossing(0.95) - crossing(0.05);
        }
        st
    }
}
