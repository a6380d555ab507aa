//! One linear piece of a hysteretic law and the sign of a motion.

/// One linear piece: `f(u) = f_ref + stiffness·(u − u_ref)`, valid for `lower ≤ u ≤ upper`.
///
/// If `ends_on_reversal`, the branch also ends when the velocity changes sign; its sign while on
/// it is `direction` (±1). Otherwise `direction` is the last known direction of motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Branch {
    /// A point (u_ref, f_ref) of the branch: f = f_ref + stiffness·(u − u_ref).
    pub u_ref: f64,
    /// The force at `u_ref`.
    pub f_ref: f64,
    /// The branch's slope df/du.
    pub stiffness: f64,
    /// The branch ends below this deformation (−∞: never).
    pub lower: f64,
    /// The branch ends above this deformation (+∞: never).
    pub upper: f64,
    /// The sign of the deformation rate on it (±1).
    pub direction: f64,
    /// The branch ends when the deformation rate changes sign (a load reversal).
    pub ends_on_reversal: bool,
}

impl Branch {
    /// Force at `u` on this line.
    pub fn force(&self, u: f64) -> f64 {
        self.f_ref + self.stiffness * (u - self.u_ref)
    }

    /// The bound reached when moving in `direction`: `upper` if positive, else `lower`.
    pub fn end(&self, direction: f64) -> f64 {
        if direction > 0.0 {
            self.upper
        } else {
            self.lower
        }
    }
}

/// Sign of `x` (0 at 0).
pub(super) fn sgn(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}
