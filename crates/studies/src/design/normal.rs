//! The standard normal distribution where the fits need it, accurate in the far tails:
//! Φ(z) = ½ erfc(−z/√2); below z = −30 the asymptotic series of Mills' ratio
//! Φ(z)/φ(z) ≈ (1/x)(1 − 1/x² + 3/x⁴ − 15/x⁶), x = −z (Abramowitz & Stegun 26.2.12).

use std::f64::consts::{PI, SQRT_2};

/// Where the tail series takes over from erfc (its truncation error there: 105/x⁸ ≈ 2e-10).
const TAIL: f64 = -30.0;

/// φ(z) = exp(−z²/2)/√(2π).
pub(crate) fn pdf(z: f64) -> f64 {
    (-0.5 * z * z).exp() / (2.0 * PI).sqrt()
}

/// Φ(z).
pub(crate) fn cdf(z: f64) -> f64 {
    0.5 * libm::erfc(-z / SQRT_2)
}

/// 1 − 1/x² + 3/x⁴ − 15/x⁶: x·Φ(−x)/φ(x) for large x.
fn mills_series(x: f64) -> f64 {
    let u = 1.0 / (x * x);
    1.0 - u + 3.0 * u * u - 15.0 * u * u * u
}

/// ln Φ(z), finite for every finite z.
pub(crate) fn ln_cdf(z: f64) -> f64 {
    if z < TAIL {
        let x = -z;
        -0.5 * x * x - 0.5 * (2.0 * PI).ln() - x.ln() + mills_series(x).ln()
    } else if z > 0.0 {
        (-cdf(-z)).ln_1p()
    } else {
        cdf(z).ln()
    }
}

/// λ(z) = φ(z)/Φ(z), the inverse Mills ratio: d ln Φ(z)/dz.
pub(crate) fn mills(z: f64) -> f64 {
    if z < TAIL {
        -z / mills_series(-z)
    } else {
        pdf(z) / cdf(z)
    }
}

/// λ′(z) = −λ(z)(z + λ(z)) = d² ln Φ(z)/dz² (negative: Φ is log-concave).
pub(crate) fn mills_slope(z: f64) -> f64 {
    let l = mills(z);
    -l * (z + l)
}
