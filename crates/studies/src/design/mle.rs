//! Maximum-likelihood fits of a lognormal fragility P(exceed | IM = x) = Φ(ln(x/θ)/β)
//! (Baker 2015, "Efficient analytical fragility function fitting using dynamic structural
//! analysis", Earthquake Spectra 31(1)):
//!
//! - multiple stripes: zⱼ of nⱼ runs at level xⱼ exceed; ℓ = Σ zⱼ ln pⱼ + (nⱼ − zⱼ) ln(1 − pⱼ)
//!   (binomial coefficients left out), maximised as a probit regression pⱼ = Φ(a + b(uⱼ − ū)),
//!   uⱼ = ln xⱼ, whose log-likelihood is concave in (a, b); θ = exp(ū − a/b), β = 1/b;
//! - IDA: each record's capacity c (the lowest level at which it exceeds) is lognormal;
//!   records that never exceed are right-censored at their highest level;
//!   ℓ = Σ_exceed [ln φ((ln c − μ)/σ) − ln σ − ln c] + Σ_censored ln(1 − Φ((ln c − μ)/σ)),
//!   maximised in Olsen's (1978) parameters δ = μ/σ, γ = 1/σ, in which it is concave;
//!   θ = e^μ, β = σ. Without censoring μ̂ and σ̂ are the mean and population standard
//!   deviation of ln c.
//!
//! Both by Newton's method with a backtracking (Armijo) line search; data for which the
//! maximum does not exist (no exceedance, all exceed, one level, separated levels) are refused
//! before the search with a [`FitError`].

use super::normal::{ln_cdf, mills, mills_slope};
use serde::Serialize;

/// Largest β of a fit: above it the fraction hardly rises with the level (a factor e^β of
/// intensity between P = 16 % and 50 %) and the data say no fragility.
pub(crate) const MAX_BETA: f64 = 10.0;

/// Newton iterations before a fit is given up.
pub(crate) const MAX_ITERATIONS: usize = 100;
/// Halvings of a step before the line search gives up.
const MAX_HALVINGS: usize = 60;

/// n runs at a level, z of them exceeding.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Count {
    pub level: f64,
    pub runs: usize,
    pub exceed: usize,
}

/// A record's capacity: the level at which it first exceeds, or (censored) the highest level
/// it was run at without exceeding.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Capacity {
    pub level: f64,
    pub censored: bool,
}

/// A fitted lognormal fragility.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Fit {
    /// Median θ (units of the level).
    pub theta: f64,
    /// Logarithmic standard deviation β.
    pub beta: f64,
    /// ℓ at (θ, β).
    pub log_likelihood: f64,
    pub iterations: usize,
}

impl Fit {
    /// P(exceed | x) = Φ(ln(x/θ)/β); 0 at x ≤ 0.
    pub(crate) fn probability(&self, x: f64) -> f64 {
        probability(x, self.theta, self.beta)
    }
}

/// Φ(ln(x/θ)/β), 0 at x ≤ 0.
pub(crate) fn probability(x: f64, theta: f64, beta: f64) -> f64 {
    if x <= 0.0 {
        0.0
    } else {
        super::normal::cdf((x / theta).ln() / beta)
    }
}

/// The message of [`FitError::Separated`]: the levels where every run is safe and where every
/// run exceeds, or the one level where they mix.
fn separated_text(highest_safe: f64, lowest_exceeding: f64) -> String {
    if highest_safe < lowest_exceeding {
        format!(
            "every run at {highest_safe} or below is safe and every run at {lowest_exceeding} \
             or above exceeds: the likelihood grows as β → 0 (run levels in between)"
        )
    } else {
        format!(
            "every run below {highest_safe} is safe and every run above it exceeds, the runs \
             mix only at {highest_safe}: the likelihood grows as β → 0 with θ → \
             {highest_safe} (run levels around it)"
        )
    }
}

/// Why no fit.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FitError {
    #[error("a level is not a finite positive number: {level}")]
    BadLevel { level: f64 },
    #[error(
        "no finished run to which the limit state applies (failed, refused and not-applicable \
         runs are left out of the likelihood)"
    )]
    NoRuns,
    #[error("runs at {levels} level(s): a fit needs runs at two levels or more")]
    TooFewLevels { levels: usize },
    #[error(
        "none of the {runs} runs exceeds the limit state: the median lies above every level run"
    )]
    NoExceedance { runs: usize },
    #[error("all {runs} runs exceed the limit state: the median lies below every level run")]
    AllExceed { runs: usize },
    #[error("{}", separated_text(*highest_safe, *lowest_exceeding))]
    Separated {
        highest_safe: f64,
        lowest_exceeding: f64,
    },
    #[error(
        "every exceedance (up to {highest_exceeding}) is at or below every safe run (from \
         {lowest_safe}): the fraction falls with the level"
    )]
    Falling {
        highest_exceeding: f64,
        lowest_safe: f64,
    },
    #[error("every capacity is {capacity} and no record is censored above it: β → 0 (no spread)")]
    NoSpread { capacity: f64 },
    #[error("the fraction hardly rises with the level: β = {beta:.3e} > {max} (θ = {theta:.3e})")]
    Flat { theta: f64, beta: f64, max: f64 },
    #[error("no convergence in {iterations} Newton iterations")]
    NotConverged { iterations: usize },
}

/// ℓ, its gradient and Hessian at a point.
struct Eval {
    value: f64,
    grad: [f64; 2],
    hess: [[f64; 2]; 2],
}

/// The maximum of a concave ℓ(p) by Newton's method with a backtracking line search
/// (Armijo, factor 1e-4); `f` is `None` outside the domain. Returns the point, its value and
/// the iterations.
fn maximize(
    f: impl Fn([f64; 2]) -> Option<Eval>,
    p0: [f64; 2],
) -> Result<([f64; 2], f64, usize), FitError> {
    let not_converged = FitError::NotConverged {
        iterations: MAX_ITERATIONS,
    };
    let mut p = p0;
    let mut e = f(p).ok_or_else(|| not_converged.clone())?;
    for it in 0..MAX_ITERATIONS {
        let (g, h) = (e.grad, e.hess);
        let det = h[0][0] * h[1][1] - h[0][1] * h[1][0];
        // Newton's direction −H⁻¹g where H is negative definite, else the gradient
        let d = if h[0][0] < 0.0 && det > 0.0 {
            [
                -(h[1][1] * g[0] - h[0][1] * g[1]) / det,
                -(-h[1][0] * g[0] + h[0][0] * g[1]) / det,
            ]
        } else {
            g
        };
        let slope = g[0] * d[0] + g[1] * d[1];
        if !slope.is_finite() {
            return Err(not_converged);
        }
        // the Newton decrement gᵀ(−H⁻¹)g: ℓ's distance to its maximum, to about rounding
        if slope <= 1e-20 * (1.0 + e.value.abs()) {
            return Ok((p, e.value, it));
        }
        let mut t = 1.0;
        let mut next = None;
        for _ in 0..MAX_HALVINGS {
            let q = [p[0] + t * d[0], p[1] + t * d[1]];
            if let Some(eq) = f(q).filter(|eq| eq.value >= e.value + 1e-4 * t * slope) {
                next = Some((q, eq));
                break;
            }
            t *= 0.5;
        }
        match next {
            Some((q, eq)) => {
                let moved = (q[0] - p[0]).abs().max((q[1] - p[1]).abs());
                let size = 1.0 + p[0].abs().max(p[1].abs());
                p = q;
                e = eq;
                if moved <= 1e-14 * size {
                    return Ok((p, e.value, it + 1));
                }
            }
            // no step gains: the maximum to rounding
            None if slope <= 1e-8 * (1.0 + e.value.abs()) => return Ok((p, e.value, it)),
            None => return Err(not_converged),
        }
    }
    Err(not_converged)
}

fn check_levels<'a>(levels: impl Iterator<Item = &'a f64>) -> Result<(), FitError> {
    for &level in levels {
        if !(level.is_finite() && level > 0.0) {
            return Err(FitError::BadLevel { level });
        }
    }
    Ok(())
}

/// ℓ of multiple stripes at (θ, β): Σ zⱼ ln pⱼ + (nⱼ − zⱼ) ln(1 − pⱼ).
pub fn stripes_log_likelihood(counts: &[Count], theta: f64, beta: f64) -> f64 {
    (counts.iter())
        .map(|c| {
            let eta = (c.level / theta).ln() / beta;
            let (z, s) = (c.exceed as f64, (c.runs - c.exceed.min(c.runs)) as f64);
            z * ln_cdf(eta) + s * ln_cdf(-eta)
        })
        .sum()
}

/// The multiple-stripe maximum-likelihood fit (counts at the same level add up).
pub fn fit_stripes(counts: &[Count]) -> Result<Fit, FitError> {
    check_levels(counts.iter().map(|c| &c.level))?;
    let used: Vec<&Count> = counts.iter().filter(|c| c.runs > 0).collect();
    let mut levels: Vec<f64> = used.iter().map(|c| c.level).collect();
    levels.sort_by(f64::total_cmp);
    levels.dedup();
    let runs: usize = used.iter().map(|c| c.runs).sum();
    let exceed: usize = used.iter().map(|c| c.exceed.min(c.runs)).sum();
    if runs == 0 {
        return Err(FitError::NoRuns);
    }
    if exceed == 0 {
        return Err(FitError::NoExceedance { runs });
    }
    if exceed == runs {
        return Err(FitError::AllExceed { runs });
    }
    if levels.len() < 2 {
        return Err(FitError::TooFewLevels {
            levels: levels.len(),
        });
    }
    let safe_levels = used.iter().filter(|c| c.exceed < c.runs).map(|c| c.level);
    let hit_levels = used.iter().filter(|c| c.exceed > 0).map(|c| c.level);
    let (lo_safe, hi_safe) = extent(safe_levels);
    let (lo_hit, hi_hit) = extent(hit_levels);
    if hi_safe <= lo_hit {
        return Err(FitError::Separated {
            highest_safe: hi_safe,
            lowest_exceeding: lo_hit,
        });
    }
    if hi_hit <= lo_safe {
        return Err(FitError::Falling {
            highest_exceeding: hi_hit,
            lowest_safe: lo_safe,
        });
    }
    // probit in u − ū: η = a + b(u − ū)
    let ubar = used
        .iter()
        .map(|c| c.runs as f64 * c.level.ln())
        .sum::<f64>()
        / runs as f64;
    let data: Vec<(f64, f64, f64)> = (used.iter())
        .map(|c| {
            let z = c.exceed.min(c.runs) as f64;
            (c.level.ln() - ubar, z, c.runs as f64 - z)
        })
        .collect();
    let f = |p: [f64; 2]| {
        let mut e = Eval {
            value: 0.0,
            grad: [0.0; 2],
            hess: [[0.0; 2]; 2],
        };
        for &(u, z, s) in &data {
            let eta = p[0] + p[1] * u;
            e.value += z * ln_cdf(eta) + s * ln_cdf(-eta);
            let d1 = z * mills(eta) - s * mills(-eta);
            let d2 = z * mills_slope(eta) + s * mills_slope(-eta);
            accumulate(&mut e, [1.0, u], d1, d2);
        }
        e.value.is_finite().then_some(e)
    };
    let (p, value, iterations) = maximize(f, [0.0, 2.0])?;
    if p[1].is_nan() || p[1] <= 0.0 {
        return Err(FitError::Falling {
            highest_exceeding: hi_hit,
            lowest_safe: lo_safe,
        });
    }
    checked(Fit {
        theta: (ubar - p[0] / p[1]).exp(),
        beta: 1.0 / p[1],
        log_likelihood: value,
        iterations,
    })
}

/// `fit` unless its β is above [`MAX_BETA`] or θ is not a finite positive number.
fn checked(fit: Fit) -> Result<Fit, FitError> {
    let ok =
        fit.beta.is_finite() && fit.beta <= MAX_BETA && fit.theta.is_finite() && fit.theta > 0.0;
    if ok {
        Ok(fit)
    } else {
        Err(FitError::Flat {
            theta: fit.theta,
            beta: fit.beta,
            max: MAX_BETA,
        })
    }
}

/// (min, max) of levels (∞, −∞ when empty).
fn extent(v: impl Iterator<Item = f64>) -> (f64, f64) {
    v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    })
}

/// Adds a term of ℓ whose derivatives along the linear predictor x·p are d1, d2.
fn accumulate(e: &mut Eval, x: [f64; 2], d1: f64, d2: f64) {
    for i in 0..2 {
        e.grad[i] += d1 * x[i];
        for j in 0..2 {
            e.hess[i][j] += d2 * x[i] * x[j];
        }
    }
}

/// ℓ of IDA capacities at (θ, β): Σ_exceed [ln φ(z) − ln β − ln c] + Σ_censored ln(1 − Φ(z)),
/// z = ln(c/θ)/β.
pub fn ida_log_likelihood(caps: &[Capacity], theta: f64, beta: f64) -> f64 {
    let half_ln_2pi = 0.5 * (2.0 * std::f64::consts::PI).ln();
    (caps.iter())
        .map(|c| {
            let z = (c.level / theta).ln() / beta;
            if c.censored {
                ln_cdf(-z)
            } else {
                -0.5 * z * z - half_ln_2pi - beta.ln() - c.level.ln()
            }
        })
        .sum()
}

/// The IDA maximum-likelihood fit: lognormal capacities, right-censored ones included.
pub fn fit_ida(caps: &[Capacity]) -> Result<Fit, FitError> {
    check_levels(caps.iter().map(|c| &c.level))?;
    if caps.is_empty() {
        return Err(FitError::NoRuns);
    }
    let exceeded: Vec<f64> = (caps.iter().filter(|c| !c.censored))
        .map(|c| c.level.ln())
        .collect();
    if exceeded.is_empty() {
        return Err(FitError::NoExceedance { runs: caps.len() });
    }
    let (lo, hi) = extent(exceeded.iter().copied());
    let above = (caps.iter()).any(|c| c.censored && c.level.ln() > lo);
    if hi == lo && !above {
        return Err(FitError::NoSpread { capacity: lo.exp() });
    }
    let n = caps.len() as f64;
    let m = caps.iter().map(|c| c.level.ln()).sum::<f64>() / n;
    let sd = (caps.iter().map(|c| (c.level.ln() - m).powi(2)).sum::<f64>() / n).sqrt();
    let data: Vec<(f64, bool)> = caps
        .iter()
        .map(|c| (c.level.ln() - m, c.censored))
        .collect();
    // Olsen: δ = μ/σ, γ = 1/σ (of the centred logs)
    let f = |p: [f64; 2]| {
        let (delta, gamma) = (p[0], p[1]);
        if gamma.is_nan() || gamma <= 0.0 {
            return None;
        }
        let mut e = Eval {
            value: 0.0,
            grad: [0.0; 2],
            hess: [[0.0; 2]; 2],
        };
        for &(y, censored) in &data {
            if censored {
                // ln Φ(δ − γy)
                let t = delta - gamma * y;
                e.value += ln_cdf(t);
                accumulate(&mut e, [1.0, -y], mills(t), mills_slope(t));
            } else {
                // ln γ − (γy − δ)²/2
                let r = gamma * y - delta;
                e.value += gamma.ln() - 0.5 * r * r;
                e.grad[0] += r;
                e.grad[1] += 1.0 / gamma - r * y;
                e.hess[0][0] -= 1.0;
                e.hess[0][1] += y;
                e.hess[1][0] += y;
                e.hess[1][1] -= 1.0 / (gamma * gamma) + y * y;
            }
        }
        e.value.is_finite().then_some(e)
    };
    let start = [0.0, 1.0 / sd.max(1e-3)];
    let (p, _, iterations) = maximize(f, start)?;
    let (theta, beta) = ((m + p[0] / p[1]).exp(), 1.0 / p[1]);
    checked(Fit {
        theta,
        beta,
        log_likelihood: ida_log_likelihood(caps, theta, beta),
        iterations,
    })
}
