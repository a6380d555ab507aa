//! Axis ranges and ticks at round numbers: linear steps of 1, 2 or 5 × 10ᵏ, log axes at
//! decades (with 2 and 5 inside a single decade).

use super::chart::{Axis, Chart, Scale};

/// Linear axes aim at about this many intervals between ticks (5 to 7).
const TARGET_INTERVALS: f64 = 5.0;
/// Most decade ticks on a log axis (more decades: every k-th).
const MAX_DECADES: usize = 10;

/// The resolved range of an axis: where a value falls on it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span {
    pub lo: f64,
    pub hi: f64,
    pub scale: Scale,
    /// Tick step of a linear axis ([`linear_step`]).
    pub step: f64,
}

impl Span {
    /// (v − lo)/(hi − lo) on a linear axis, (log v − log lo)/(log hi − log lo) on a log axis:
    /// 0 at `lo`, 1 at `hi`; `None` for a value that cannot be drawn (not finite, ≤ 0 on log).
    pub fn frac(&self, v: f64) -> Option<f64> {
        if !v.is_finite() {
            return None;
        }
        match self.scale {
            Scale::Linear => Some((v - self.lo) / (self.hi - self.lo)),
            Scale::Log if v > 0.0 => {
                Some((v.log10() - self.lo.log10()) / (self.hi.log10() - self.lo.log10()))
            }
            Scale::Log => None,
        }
    }

    /// The ticks inside the span, in increasing order.
    pub fn ticks(&self) -> Vec<f64> {
        match self.scale {
            Scale::Linear => {
                let step = self.step;
                let first = (self.lo / step - 1e-9).ceil() as i64;
                let last = (self.hi / step + 1e-9).floor() as i64;
                (first..=last)
                    .map(|k| clean(k as f64 * step, step))
                    .collect()
            }
            Scale::Log => {
                let (a, b) = (self.lo.log10(), self.hi.log10());
                let (d0, d1) = ((a - 1e-9).ceil() as i64, (b + 1e-9).floor() as i64);
                let decades = (d1 - d0 + 1).max(0) as usize;
                let every = decades.div_ceil(MAX_DECADES).max(1) as i64;
                let mut t: Vec<f64> = (d0..=d1)
                    .filter(|k| (k - d0) % every == 0)
                    .map(|k| 10f64.powi(k as i32))
                    .collect();
                if b - a <= 2.0 + 1e-9 {
                    let inside =
                        |v: f64| v >= self.lo * (1.0 - 1e-9) && v <= self.hi * (1.0 + 1e-9);
                    for k in (d0 - 1)..=d1 {
                        for m in [2.0, 5.0] {
                            let v = m * 10f64.powi(k as i32);
                            if inside(v) {
                                t.push(v);
                            }
                        }
                    }
                    t.sort_by(f64::total_cmp);
                }
                t
            }
        }
    }

    /// The text of tick `v` among `ticks`.
    pub fn label(&self, v: f64, ticks: &[f64]) -> String {
        match self.scale {
            Scale::Linear => {
                let step = if ticks.len() > 1 {
                    ticks[1] - ticks[0]
                } else {
                    self.step
                };
                linear_label(v, step)
            }
            Scale::Log => log_label(v),
        }
    }
}

/// The smallest of 1, 2, 5 × 10ᵏ at least `raw` (1 for a step that is not positive).
pub(crate) fn nice_step(raw: f64) -> f64 {
    if raw.is_nan() || raw <= 0.0 || !raw.is_finite() {
        return 1.0;
    }
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|s| *s >= raw * (1.0 - 1e-12))
        .unwrap_or(10.0 * p)
}

/// The tick step of a linear range: the smallest of 1, 2, 5 × 10ᵏ at least 0.7·range/5
/// (5 to 7 intervals).
pub(crate) fn linear_step(range: f64) -> f64 {
    nice_step(0.7 * range / TARGET_INTERVALS)
}

/// k·step without the rounding noise of the product (and without −0).
fn clean(v: f64, step: f64) -> f64 {
    let digits = (-step.log10().floor()).max(0.0) as i32 + 1;
    let f = 10f64.powi(digits.min(15));
    let r = (v * f).round() / f;
    if r.abs() < step * 1e-9 { 0.0 } else { r }
}

/// `v` with as many decimals as `step` needs; exponent form outside [1e-4, 1e6).
fn linear_label(v: f64, step: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let big = v.abs().max(step.abs());
    if big >= 1e6 || step.abs() < 1e-4 {
        return exp_label(v);
    }
    let decimals = (-step.abs().log10().floor()).max(0.0) as usize;
    // a step of 2.5 or 0.25 does not occur (1, 2, 5 only), so `decimals` digits suffice
    format!("{v:.decimals$}")
}

/// 10ᵏ (and 2, 5 × 10ᵏ) as plain decimals from 0.001 to 10000, else as `1e-5`.
fn log_label(v: f64) -> String {
    let k = v.log10().floor();
    if (-3.0..=4.0).contains(&k) {
        let decimals = (-k).max(0.0) as usize;
        format!("{v:.decimals$}")
    } else {
        exp_label(v)
    }
}

/// `2.5e-5`: the shortest mantissa (at most 3 significant digits).
fn exp_label(v: f64) -> String {
    let s = format!("{v:.2e}");
    let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
    let m = m.trim_end_matches('0').trim_end_matches('.');
    format!("{m}e{e}")
}

/// The span of an axis: its fixed range, else `values` (the finite ones, and > 0 on a log axis)
/// widened outward to round ticks; an empty or one-valued extent is widened around it.
pub fn span(axis: &Axis, values: &[f64]) -> Span {
    let scale = axis.scale;
    if let Some((lo, hi)) = axis.range {
        let ok =
            lo.is_finite() && hi.is_finite() && hi > lo && (scale == Scale::Linear || lo > 0.0);
        if ok {
            let step = linear_step(hi - lo);
            return Span {
                lo,
                hi,
                scale,
                step,
            };
        }
    }
    let usable = |v: &&f64| v.is_finite() && (scale == Scale::Linear || **v > 0.0);
    let (mut lo, mut hi) = (values.iter().filter(usable))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    match scale {
        Scale::Linear => {
            if lo > hi {
                (lo, hi) = (0.0, 1.0);
            } else if lo == hi {
                let d = if lo == 0.0 { 1.0 } else { lo.abs() * 0.1 };
                (lo, hi) = (lo - d, hi + d);
            }
            let step = linear_step(hi - lo);
            let lo = (lo / step + 1e-9).floor() * step;
            let hi = (hi / step - 1e-9).ceil() * step;
            Span {
                lo: clean(lo, step),
                hi: clean(hi, step),
                scale,
                step,
            }
        }
        Scale::Log => {
            if lo > hi {
                (lo, hi) = (1.0, 10.0);
            }
            let a = (lo.log10() + 1e-9).floor();
            let mut b = (hi.log10() - 1e-9).ceil();
            if b <= a {
                b = a + 1.0;
            }
            Span {
                lo: 10f64.powf(a),
                hi: 10f64.powf(b),
                scale,
                step: 0.0,
            }
        }
    }
}

/// The span of a chart's y axis: with labelled rows ([`Chart::rows`]) 0.5 … n + 0.5, a tick
/// at each row; else [`span`] of its y values.
pub(crate) fn y_span(chart: &Chart) -> Span {
    if chart.rows.is_empty() {
        return span(&chart.y, &chart.ys());
    }
    Span {
        lo: 0.5,
        hi: chart.rows.len() as f64 + 0.5,
        scale: Scale::Linear,
        step: 1.0,
    }
}

/// The y ticks of a chart on its span `sy` ([`y_span`]) with their text: a row's label at each
/// row, else round numbers.
pub(crate) fn y_ticks(chart: &Chart, sy: &Span) -> Vec<(f64, String)> {
    if !chart.rows.is_empty() {
        let rows = chart.rows.iter().enumerate();
        return rows.map(|(i, l)| (chart.row_y(i), l.clone())).collect();
    }
    let t = sy.ticks();
    t.iter().map(|&v| (v, sy.label(v, &t))).collect()
}
