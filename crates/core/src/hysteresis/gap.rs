//! Compression-only gap laws: passive backfill and sacrificial shear keys (module docs of
//! [`super`], rules G1–G5).

use super::branch::Branch;
use super::law::Law;

/// State of a gap law seen from outside: closing point, permanent set, peak force, failure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GapState {
    /// Closing point c = gap + e_p: the force is 0 for e ≤ c (as of the last reversal: on the
    /// plastic branch e_p grows with e until the next one).
    pub closing: f64,
    /// Permanent set e_p = c − gap (soil pushed back, key deformed plastically).
    pub permanent_set: f64,
    /// Largest force carried so far.
    pub peak_force: f64,
    /// A key whose deformation beyond the gap reached its failure displacement (force 0 since).
    pub failed: bool,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum GKind {
    /// G1: e below the closing point, f = 0.
    Open,
    /// G2: f = k (e − c) between c and c + f_c/k.
    Elastic,
    /// G3: f = f_c, moving in +.
    Plastic,
    /// G5: the key is gone.
    Failed,
}

#[derive(Clone, Debug)]
pub(super) struct Gap {
    k: f64,
    capacity: f64,
    gap: f64,
    /// e at which a key fails, gap + failure_displacement (∞ for backfill).
    fail_at: f64,
    /// Closing point c.
    closing: f64,
    peak: f64,
    kind: GKind,
}

impl Gap {
    /// Virgin state (open, c = gap) and its branch.
    pub(super) fn new(law: &Law) -> (Self, Branch) {
        let (gap, k, capacity, fail_at) = match *law {
            Law::Backfill {
                gap,
                stiffness,
                capacity,
            } => (gap, stiffness, capacity, f64::INFINITY),
            Law::Key {
                gap,
                stiffness,
                capacity,
                failure_displacement,
            } => (gap, stiffness, capacity, gap + failure_displacement),
            _ => (0.0, 0.0, 0.0, f64::INFINITY),
        };
        let g = Self {
            k,
            capacity,
            gap,
            fail_at,
            closing: gap,
            peak: 0.0,
            kind: GKind::Open,
        };
        let b = g.open(1.0);
        (g, b)
    }

    pub(super) fn state(&self) -> GapState {
        GapState {
            closing: self.closing,
            permanent_set: self.closing - self.gap,
            peak_force: self.peak,
            failed: self.kind == GKind::Failed,
        }
    }

    /// G1: f = 0 up to the closing point.
    fn open(&self, d: f64) -> Branch {
        Branch {
            u_ref: self.closing,
            f_ref: 0.0,
            stiffness: 0.0,
            lower: f64::NEG_INFINITY,
            upper: self.closing,
            direction: d,
            ends_on_reversal: false,
        }
    }

    /// G2: f = k (e − c) from the closing point up to `upper` (c + f_c/k, or the reversal
    /// point of G4), written from `(c, 0)` so that it is never negative above `c`.
    fn elastic(&self, upper: f64, d: f64) -> Branch {
        Branch {
            u_ref: self.closing,
            f_ref: 0.0,
            stiffness: self.k,
            lower: self.closing,
            upper,
            direction: d,
            ends_on_reversal: false,
        }
    }

    /// G3: f = f_c while e grows (a key: up to its failure point).
    fn plastic(&self, u: f64) -> Branch {
        Branch {
            u_ref: u,
            f_ref: self.capacity,
            stiffness: 0.0,
            lower: f64::NEG_INFINITY,
            upper: self.fail_at,
            direction: 1.0,
            ends_on_reversal: true,
        }
    }

    /// G5: f = 0 for ever.
    fn failed(u: f64, d: f64) -> Branch {
        Branch {
            u_ref: u,
            f_ref: 0.0,
            stiffness: 0.0,
            lower: f64::NEG_INFINITY,
            upper: f64::INFINITY,
            direction: d,
            ends_on_reversal: false,
        }
    }

    /// Next branch after `b` ended at `u`, moving in `d`.
    pub(super) fn next(&mut self, b: &Branch, u: f64, d: f64) -> Branch {
        // (the elastic line reaches f_c to rounding)
        self.peak = self.peak.max(b.force(u).min(self.capacity));
        let (kind, next) = match self.kind {
            GKind::Open if d > 0.0 && u >= self.closing => {
                let upper = self.closing + self.capacity / self.k;
                (GKind::Elastic, self.elastic(upper, d))
            }
            GKind::Open => (GKind::Open, self.open(d)),
            GKind::Elastic if d > 0.0 => (GKind::Plastic, self.plastic(u)),
            GKind::Elastic => (GKind::Open, self.open(d)),
            GKind::Plastic if d < 0.0 => {
                // G4: the soil or key pushed back
                self.closing = u - self.capacity / self.k;
                (GKind::Elastic, self.elastic(u, d))
            }
            GKind::Plastic if u < self.fail_at => (GKind::Plastic, self.plastic(u)),
            GKind::Plastic | GKind::Failed => (GKind::Failed, Self::failed(u, d)),
        };
        self.kind = kind;
        next
    }
}
