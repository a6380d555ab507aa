//! Bilinear kinematic hardening: the elastic band and the yield lines.

use super::branch::Branch;

/// Bilinear kinematic hardening: next branch after `b` ended at `u`, moving in `d`.
pub(super) fn bilinear_next(k: f64, kp: f64, c: f64, b: &Branch, u: f64, d: f64) -> Branch {
    let f = b.force(u);
    if b.ends_on_reversal && d != b.direction {
        // Reversal on a yield line: the elastic line starts exactly there.
        let mut e = bilinear_elastic(k, kp, c, u, f, d);
        if d < 0.0 {
            e.upper = u;
        } else {
            e.lower = u;
        }
        e
    } else {
        Branch {
            u_ref: u,
            f_ref: f,
            stiffness: kp,
            lower: f64::NEG_INFINITY,
            upper: f64::INFINITY,
            direction: d,
            ends_on_reversal: true,
        }
    }
}

/// Elastic branch through `(u, f)` up to the yield lines `f = ±c + kp·u`.
pub(super) fn bilinear_elastic(k: f64, kp: f64, c: f64, u: f64, f: f64, d: f64) -> Branch {
    let up = (c - f + k * u) / (k - kp);
    let lo = (-c - f + k * u) / (k - kp);
    Branch {
        u_ref: u,
        f_ref: f,
        stiffness: k,
        lower: lo.min(u),
        upper: up.max(u),
        direction: d,
        ends_on_reversal: false,
    }
}
