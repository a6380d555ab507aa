//! Uniaxial hysteretic force–displacement laws for bridge columns, as piecewise-linear
//! [`Branch`]es that an event-driven integrator follows exactly.
//!
//! On a branch the force is linear in the displacement `u`. A branch ends when `u` reaches
//! [`Branch::lower`] or [`Branch::upper`], or, if [`Branch::ends_on_reversal`], when the
//! velocity changes sign; the integrator then calls [`Hysteretic::on_branch_end`] and the law
//! chooses the next branch, which starts at the force the old branch had there (except a
//! failing shear key, rule G5).
//!
//! Laws ([`Law`]):
//! - `linear`: one branch `f = k·u`, unbounded, never ends.
//! - `bilinear`: kinematic hardening; elastic (`k`) inside the yield band
//!   `|f − r·k·u| ≤ f_y·(1 − r)`, post-yield slope `r·k` on its edges (ends on reversal).
//! - `takeda`: Takeda, Sozen & Nielsen (1970) degrading-stiffness model as summarised by
//!   Otani (1981), bilinear or trilinear backbone; rules T1–T7:
//!   - T1 virgin: elastic line (`k`) in both directions up to the crack point (trilinear) or the
//!     yield point (bilinear).
//!   - T2 cracked, no yield anywhere (trilinear): unloading from the backbone aims at the peak
//!     point in the opposite direction (its crack point if uncracked); that line is followed both
//!     ways and, at either end, loading continues on the backbone.
//!   - T3 after yield (either side): unloading from a point `P` (force of sign `s`) has stiffness
//!     `k_u = k_y·(d_y/d_max)^α`, `k_y = f_y/d_y` (secant to yield), `d_max` = largest `|u|` reached
//!     in either direction; `k_u` is raised, if needed, to the slope of the chord from `P` to the
//!     reloading target in direction `−s` (the reloading line is never stiffer than the unloading
//!     line). The unloading line ends at zero force and is followed both ways; back at `P` the
//!     branch left at `P` resumes (T6).
//!   - T4 from zero force, reloading in direction `s` aims at the target of that direction: the
//!     most recent unreached local peak (T5), else the outer peak `(d_max,s, B(d_max,s))`, or the
//!     yield point if direction `s` has not yielded; at the outer peak it joins the backbone.
//!   - T5 inner loops: a reversal on a reloading line at `P` (force of sign `s`) stores `P` as a
//!     local peak of direction `s` and unloads by T3. Local peaks form a stack per direction
//!     (most recent first, [`MEMORY`] deep): reloading aims at the top; when it is reached it is
//!     dropped and reloading goes on toward the next one (finally the outer peak). Reaching the
//!     backbone clears the stack of that direction.
//!   - T6 a reversal on an unloading line (before zero force) retraces it; back at `P` the
//!     reloading (or backbone) branch resumes — the same rule as T5 reaching its local peak `P`.
//!   - T7 a reversal on a reloading line at zero force reloads toward the opposite target.
//! - `backfill`: passive backfill behind an abutment backwall, Caltrans SDC v1.7 §7.8.1
//!   (elastic–perfectly-plastic, compression only, with a gap); `key`: a sacrificial shear key,
//!   Megally, Silva & Seible (2001) "Seismic response of sacrificial shear keys in bridge
//!   abutments" (the same law, and a failure displacement). The force is never negative: it
//!   resists positive `e` (the element's direction chooses which way is compression). Rules
//!   G1–G5, with the closing point `c = gap + e_p` (`e_p` the permanent set, 0 at first):
//!   - G1 open: `f = 0` for `e ≤ c`; at `c` moving in +, G2.
//!   - G2 elastic: `f = k (e − c)` for `c ≤ e ≤ c + f_c/k`; at `c` moving in −, G1; at
//!     `c + f_c/k` moving in +, G3.
//!   - G3 plastic: `f = f_c` while `e` grows (ends on reversal).
//!   - G4 a reversal at `u` on G3 sets `c = u − f_c/k` (the soil or key is pushed back:
//!     `e_p = u − gap − f_c/k`) and unloads along G2 (back up to `u`, then G3 again).
//!   - G5 (`key` only) when `e − gap` reaches `failure_displacement` on G3 the key is gone:
//!     `f = 0` for ever. The force drops there (the one branch change that is not continuous
//!     in force); the work `∫f de` is continuous.

mod bilinear;
mod branch;
mod gap;
mod law;
mod takeda;

pub use branch::Branch;
pub use gap::GapState;
pub use law::{HysteresisError, Law};
pub(crate) use takeda::MEMORY;

use bilinear::{bilinear_elastic, bilinear_next};
use branch::sgn;
use gap::Gap;
use takeda::Takeda;

#[derive(Debug)]
enum Model {
    Linear,
    /// Elastic slope, post-yield slope, half band `f_y·(1 − r)`.
    Bilinear {
        k: f64,
        kp: f64,
        c: f64,
    },
    Takeda(Box<Takeda>),
    Gap(Gap),
}

impl Clone for Model {
    fn clone(&self) -> Self {
        match self {
            Model::Linear => Model::Linear,
            &Model::Bilinear { k, kp, c } => Model::Bilinear { k, kp, c },
            Model::Takeda(t) => Model::Takeda(t.clone()),
            Model::Gap(g) => Model::Gap(g.clone()),
        }
    }

    /// A Takeda state copied into the box it replaces (laws are copied at every sample of a
    /// run by islands and at every event of a kept step: no allocation there).
    fn clone_from(&mut self, source: &Self) {
        match (self, source) {
            (Model::Takeda(to), Model::Takeda(from)) => (**to).clone_from(from),
            (to, from) => *to = from.clone(),
        }
    }
}

/// A hysteretic element: a [`Law`] and its state (current branch and memory).
#[derive(Debug)]
pub struct Hysteretic {
    law: Law,
    branch: Branch,
    u: f64,
    model: Model,
}

impl Clone for Hysteretic {
    fn clone(&self) -> Self {
        Self {
            law: self.law.clone(),
            branch: self.branch,
            u: self.u,
            model: self.model.clone(),
        }
    }

    fn clone_from(&mut self, source: &Self) {
        self.law.clone_from(&source.law);
        self.branch = source.branch;
        self.u = source.u;
        self.model.clone_from(&source.model);
    }
}

/// Most branch changes allowed at one instant (zero-length branches are skipped).
const SETTLE: usize = 2 * MEMORY + 8;

impl Hysteretic {
    /// Virgin state at `u = 0`, `f = 0`.
    pub fn new(law: Law) -> Result<Self, HysteresisError> {
        law.validate()?;
        let (model, branch) = match law {
            Law::Linear { stiffness } => (
                Model::Linear,
                Branch {
                    u_ref: 0.0,
                    f_ref: 0.0,
                    stiffness,
                    lower: f64::NEG_INFINITY,
                    upper: f64::INFINITY,
                    direction: 1.0,
                    ends_on_reversal: false,
                },
            ),
            Law::Bilinear {
                stiffness: k,
                yield_force: fy,
                post_yield_ratio: r,
            } => {
                let (kp, c) = (r * k, fy * (1.0 - r));
                (
                    Model::Bilinear { k, kp, c },
                    bilinear_elastic(k, kp, c, 0.0, 0.0, 1.0),
                )
            }
            Law::Takeda { .. } => {
                let (t, b) = Takeda::new(&law);
                (Model::Takeda(Box::new(t)), b)
            }
            Law::Backfill { .. } | Law::Key { .. } => {
                let (g, b) = Gap::new(&law);
                (Model::Gap(g), b)
            }
        };
        Ok(Self {
            law,
            branch,
            u: 0.0,
            model,
        })
    }

    /// The law.
    pub fn law(&self) -> &Law {
        &self.law
    }

    /// Current branch.
    pub fn branch(&self) -> &Branch {
        &self.branch
    }

    /// Force at `u` on the current branch.
    pub fn force(&self, u: f64) -> f64 {
        self.branch.force(u)
    }

    /// Closing point, permanent set, peak force and failure of a gap law (`backfill`, `key`);
    /// `None` for the others.
    pub fn gap_state(&self) -> Option<GapState> {
        match &self.model {
            Model::Gap(g) => Some(g.state()),
            _ => None,
        }
    }

    /// A shear key that has failed (rule G5): its force is 0 for ever.
    pub fn failed(&self) -> bool {
        self.gap_state().is_some_and(|g| g.failed)
    }

    /// Would ending the current branch at `u`, moving in `direction`, fail this shear key
    /// (rule G5)?
    pub fn fails_at(&self, u: f64, direction: f64) -> bool {
        if !matches!(self.model, Model::Gap(_)) || self.failed() {
            return false;
        }
        let mut after = self.clone();
        after.on_branch_end(u, direction);
        after.failed()
    }

    /// Tangent stiffness of the current branch.
    pub fn tangent(&self) -> f64 {
        self.branch.stiffness
    }

    /// Displacement at the last call of `on_branch_end`, `set_direction` or `drive`.
    pub fn displacement(&self) -> f64 {
        self.u
    }

    /// The current branch ended at `u` (a bound was reached, or a reversal happened on a branch
    /// that ends on reversal) and the motion now has sign `direction`; chooses the next branch,
    /// continuous in force at `u`. A reversal at or beyond a branch's outer bound first ends the
    /// branch there. Zero-length branches are skipped.
    pub fn on_branch_end(&mut self, u: f64, direction: f64) {
        self.u = u;
        let d = sgn(direction);
        if d == 0.0 {
            return;
        }
        let b = self.branch;
        if b.ends_on_reversal && d != b.direction && b.direction * (u - b.end(b.direction)) >= 0.0 {
            self.step(u, b.direction);
            let b = self.branch;
            if b.ends_on_reversal && d != b.direction {
                self.step(u, d);
            } else {
                self.branch.direction = d;
            }
        } else {
            self.step(u, d);
        }
        for _ in 0..SETTLE {
            let b = self.branch;
            if d * (b.end(d) - u) > 0.0 {
                break;
            }
            self.step(u, d);
        }
    }

    /// Sets the direction of motion at `u`; ends the branch only if it ends on reversal and
    /// the direction changed, or if `u` is at its bound in `direction`. `direction = 0` is ignored.
    pub fn set_direction(&mut self, u: f64, direction: f64) {
        self.u = u;
        let d = sgn(direction);
        if d == 0.0 {
            return;
        }
        let b = self.branch;
        if (b.ends_on_reversal && d != b.direction) || d * (b.end(d) - u) <= 0.0 {
            self.on_branch_end(u, d);
        } else {
            self.branch.direction = d;
        }
    }

    fn step(&mut self, u: f64, d: f64) {
        let b = self.branch;
        self.branch = match &mut self.model {
            Model::Linear => Branch { direction: d, ..b },
            Model::Bilinear { k, kp, c } => bilinear_next(*k, *kp, *c, &b, u, d),
            Model::Takeda(t) => t.next(&b, u, d),
            Model::Gap(g) => g.next(&b, u, d),
        };
    }

    /// Drives the law from the current displacement through each point of `path` in turn
    /// (straight moves), ending branches at their bounds and at reversals as an integrator would.
    /// Returns `(u, f)` at every path point and every branch change (consecutive duplicates
    /// merged). Non-finite path points are skipped.
    ///
    /// # Panics
    /// If a move crosses more than a million branches (an internal error).
    pub fn drive(&mut self, path: &[f64]) -> Vec<(f64, f64)> {
        let mut out: Vec<(f64, f64)> = Vec::with_capacity(2 * path.len());
        let push = |out: &mut Vec<(f64, f64)>, p: (f64, f64)| {
            if out.last() != Some(&p) {
                out.push(p);
            }
        };
        for &target in path.iter().filter(|x| x.is_finite()) {
            let mut changes = 0usize;
            loop {
                let u = self.u;
                let d = sgn(target - u);
                if d == 0.0 {
                    push(&mut out, (u, self.force(u)));
                    break;
                }
                self.set_direction(u, d);
                let end = self.branch.end(d);
                if d * (end - target) >= 0.0 {
                    self.u = target;
                    push(&mut out, (target, self.force(target)));
                    break;
                }
                let end = if d * (end - u) > 0.0 { end } else { u };
                self.u = end;
                push(&mut out, (end, self.force(end)));
                self.on_branch_end(end, d);
                changes += 1;
                assert!(changes < 1_000_000, "hysteresis: no progress at u = {end}");
            }
        }
        out
    }
}
