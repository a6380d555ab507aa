//! Uniaxial hysteretic force–displacement laws for bridge columns, as piecewise-linear
//! [`Branch`]es that an event-driven integrator follows exactly.
//!
//! On a branch the force is linear in the displacement `u`. A branch ends when `u` reaches
//! [`Branch::lower`] or [`Branch::upper`], or, if [`Branch::ends_on_reversal`], when the
//! velocity changes sign; the integrator then calls [`Hysteretic::on_branch_end`] and the law
//! chooses the next branch, which always starts at the force the old branch had there.
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

use serde::{Deserialize, Serialize};

/// One linear piece: `f(u) = f_ref + stiffness·(u − u_ref)`, valid for `lower ≤ u ≤ upper`.
///
/// If `ends_on_reversal`, the branch also ends when the velocity changes sign; its sign while on
/// it is `direction` (±1). Otherwise `direction` is the last known direction of motion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Branch {
    pub u_ref: f64,
    pub f_ref: f64,
    pub stiffness: f64,
    pub lower: f64,
    pub upper: f64,
    pub direction: f64,
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

/// Errors of law parameters; `field` is the offending parameter.
#[derive(Debug, thiserror::Error)]
pub enum HysteresisError {
    #[error("{field}: {reason}")]
    Invalid { field: &'static str, reason: String },
}

fn default_unloading_exponent() -> f64 {
    0.4
}

/// A hysteretic law (TOML/JSON: `law = "linear" | "bilinear" | "takeda"` plus its fields).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(tag = "law", rename_all = "lowercase", deny_unknown_fields)]
pub enum Law {
    /// `f = stiffness·u`.
    Linear { stiffness: f64 },
    /// Bilinear with kinematic hardening; post-yield slope `post_yield_ratio·stiffness`.
    Bilinear {
        stiffness: f64,
        yield_force: f64,
        post_yield_ratio: f64,
    },
    /// Takeda (see the module rules T1–T7).
    ///
    /// Backbone: bilinear `(0,0)–(f_y/k, f_y)` then slope `r·k`; or, with `crack_force`,
    /// trilinear `(0,0)–(f_c/k, f_c)–(yield_displacement, f_y)` then slope `r·k`
    /// (`k = stiffness`, the cracked-section stiffness, `r = post_yield_ratio`).
    Takeda {
        stiffness: f64,
        yield_force: f64,
        post_yield_ratio: f64,
        #[serde(default, skip_serializing_if = "Option::is_none")]
        crack_force: Option<f64>,
        /// Yield displacement of the trilinear backbone; required with `crack_force` only.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        yield_displacement: Option<f64>,
        /// Exponent α of the unloading stiffness (T3).
        #[serde(default = "default_unloading_exponent")]
        unloading_exponent: f64,
    },
}

fn invalid(field: &'static str, reason: impl Into<String>) -> HysteresisError {
    HysteresisError::Invalid {
        field,
        reason: reason.into(),
    }
}

fn positive(field: &'static str, x: f64) -> Result<(), HysteresisError> {
    if x.is_finite() && x > 0.0 {
        Ok(())
    } else {
        Err(invalid(
            field,
            format!("must be positive and finite, got {x}"),
        ))
    }
}

fn hardening_ratio(r: f64) -> Result<(), HysteresisError> {
    if r.is_finite() && (0.0..1.0).contains(&r) {
        Ok(())
    } else {
        Err(invalid(
            "post_yield_ratio",
            format!("must be in [0, 1), got {r}"),
        ))
    }
}

impl Law {
    /// Checks the parameters; the error names the first offending field.
    pub fn validate(&self) -> Result<(), HysteresisError> {
        match *self {
            Law::Linear { stiffness } => positive("stiffness", stiffness),
            Law::Bilinear {
                stiffness,
                yield_force,
                post_yield_ratio,
            } => {
                positive("stiffness", stiffness)?;
                positive("yield_force", yield_force)?;
                hardening_ratio(post_yield_ratio)
            }
            Law::Takeda {
                stiffness,
                yield_force,
                post_yield_ratio,
                crack_force,
                yield_displacement,
                unloading_exponent,
            } => {
                positive("stiffness", stiffness)?;
                positive("yield_force", yield_force)?;
                hardening_ratio(post_yield_ratio)?;
                match (crack_force, yield_displacement) {
                    (None, None) => {}
                    (None, Some(_)) => {
                        return Err(invalid(
                            "yield_displacement",
                            "only used with crack_force (trilinear backbone)",
                        ));
                    }
                    (Some(_), None) => {
                        return Err(invalid(
                            "yield_displacement",
                            "required with crack_force (trilinear backbone)",
                        ));
                    }
                    (Some(fc), Some(uy)) => {
                        positive("crack_force", fc)?;
                        if fc >= yield_force {
                            return Err(invalid(
                                "crack_force",
                                format!("must be below yield_force {yield_force}, got {fc}"),
                            ));
                        }
                        positive("yield_displacement", uy)?;
                        if uy <= yield_force / stiffness {
                            return Err(invalid(
                                "yield_displacement",
                                format!(
                                    "must exceed yield_force/stiffness = {}, got {uy}",
                                    yield_force / stiffness
                                ),
                            ));
                        }
                        let k2 = (yield_force - fc) / (uy - fc / stiffness);
                        if post_yield_ratio * stiffness > k2 {
                            return Err(invalid(
                                "post_yield_ratio",
                                format!(
                                    "post-yield slope {} exceeds the cracked slope {k2}",
                                    post_yield_ratio * stiffness
                                ),
                            ));
                        }
                    }
                }
                if !(unloading_exponent.is_finite() && (0.0..=1.0).contains(&unloading_exponent)) {
                    return Err(invalid(
                        "unloading_exponent",
                        format!("must be in [0, 1], got {unloading_exponent}"),
                    ));
                }
                Ok(())
            }
        }
    }

    /// Initial (tangent) stiffness.
    pub fn initial_stiffness(&self) -> f64 {
        match *self {
            Law::Linear { stiffness }
            | Law::Bilinear { stiffness, .. }
            | Law::Takeda { stiffness, .. } => stiffness,
        }
    }

    /// Monotonic backbone (skeleton) force at `u`, odd in `u`.
    pub fn backbone(&self, u: f64) -> f64 {
        match *self {
            Law::Linear { stiffness } => stiffness * u,
            _ => u.signum() * Backbone::of(self).force(u.abs()),
        }
    }
}

/// Backbone corners: elastic to `(ue, fe)`, slope `k2` to `(uy, fy)`, then slope `kp`.
#[derive(Clone, Copy, Debug)]
struct Backbone {
    k: f64,
    ue: f64,
    fe: f64,
    k2: f64,
    uy: f64,
    fy: f64,
    kp: f64,
}

impl Backbone {
    fn of(law: &Law) -> Self {
        match *law {
            Law::Linear { stiffness } => Self {
                k: stiffness,
                ue: f64::INFINITY,
                fe: f64::INFINITY,
                k2: stiffness,
                uy: f64::INFINITY,
                fy: f64::INFINITY,
                kp: stiffness,
            },
            Law::Bilinear {
                stiffness: k,
                yield_force: fy,
                post_yield_ratio: r,
            }
            | Law::Takeda {
                stiffness: k,
                yield_force: fy,
                post_yield_ratio: r,
                crack_force: None,
                ..
            } => Self {
                k,
                ue: fy / k,
                fe: fy,
                k2: r * k,
                uy: fy / k,
                fy,
                kp: r * k,
            },
            Law::Takeda {
                stiffness: k,
                yield_force: fy,
                post_yield_ratio: r,
                crack_force: Some(fc),
                yield_displacement,
                ..
            } => {
                let uy = yield_displacement.unwrap_or(fy / k);
                let ue = fc / k;
                Self {
                    k,
                    ue,
                    fe: fc,
                    k2: (fy - fc) / (uy - ue),
                    uy,
                    fy,
                    kp: r * k,
                }
            }
        }
    }

    /// Force at `a ≥ 0`.
    fn force(&self, a: f64) -> f64 {
        if a <= self.ue {
            self.k * a
        } else if a <= self.uy {
            self.fe + self.k2 * (a - self.ue)
        } else {
            self.fy + self.kp * (a - self.uy)
        }
    }

    fn trilinear(&self) -> bool {
        self.ue < self.uy
    }
}

fn sgn(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// Index of direction `s` (+ → 0, − → 1).
fn ix(s: f64) -> usize {
    usize::from(s < 0.0)
}

/// Depth of the local-peak memory per direction (Takeda rule T5); older peaks are forgotten.
pub const MEMORY: usize = 16;

#[derive(Clone, Copy, Debug, PartialEq)]
struct Pt {
    u: f64,
    f: f64,
}

/// Stack of local peaks (most recent on top), oldest dropped beyond [`MEMORY`].
#[derive(Clone, Copy, Debug)]
struct Peaks {
    pts: [Pt; MEMORY],
    len: usize,
}

impl Peaks {
    const EMPTY: Self = Self {
        pts: [Pt { u: 0.0, f: 0.0 }; MEMORY],
        len: 0,
    };

    fn push(&mut self, p: Pt) {
        if self.len == MEMORY {
            self.pts.copy_within(1.., 0);
            self.len -= 1;
        }
        self.pts[self.len] = p;
        self.len += 1;
    }

    fn pop(&mut self) {
        self.len = self.len.saturating_sub(1);
    }

    fn top(&self) -> Option<Pt> {
        self.len.checked_sub(1).map(|i| self.pts[i])
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum TKind {
    /// T1, between the elastic limits.
    Elastic,
    /// On the backbone, moving outward in `branch.direction`.
    Backbone,
    /// T2, between two pre-yield peaks.
    PeakToPeak,
    /// T3, from the point at the `side` end toward zero force.
    Unload { side: f64, from_backbone: bool },
    /// T4/T5, toward the target at the outer end; `to_memory` if it is the local-peak top.
    Reload { side: f64, to_memory: bool },
}

#[derive(Clone, Debug)]
struct Takeda {
    bb: Backbone,
    /// k_y = f_y/d_y.
    ky: f64,
    alpha: f64,
    /// Outer peak per direction (last backbone reversal or entry point).
    peak: [Pt; 2],
    cracked: [bool; 2],
    yielded: [bool; 2],
    memory: [Peaks; 2],
    kind: TKind,
}

impl Takeda {
    fn new(law: &Law) -> (Self, Branch) {
        let bb = Backbone::of(law);
        let alpha = match *law {
            Law::Takeda {
                unloading_exponent, ..
            } => unloading_exponent,
            _ => 0.0,
        };
        let t = Self {
            bb,
            ky: bb.fy / bb.uy,
            alpha,
            peak: [Pt { u: 0.0, f: 0.0 }; 2],
            cracked: [false; 2],
            yielded: [false; 2],
            memory: [Peaks::EMPTY; 2],
            kind: TKind::Elastic,
        };
        let b = Branch {
            u_ref: 0.0,
            f_ref: 0.0,
            stiffness: bb.k,
            lower: -bb.ue,
            upper: bb.ue,
            direction: 1.0,
            ends_on_reversal: false,
        };
        (t, b)
    }

    fn update_peak(&mut self, s: f64, u: f64, f: f64) {
        let p = &mut self.peak[ix(s)];
        if s * u >= s * p.u {
            *p = Pt { u, f };
        }
    }

    /// Outer target of direction `s` (T4).
    fn outer(&self, s: f64) -> Pt {
        if self.yielded[ix(s)] {
            self.peak[ix(s)]
        } else {
            Pt {
                u: s * self.bb.uy,
                f: s * self.bb.fy,
            }
        }
    }

    /// Reloading target of direction `s` and whether it is a local peak (T4, T5).
    fn target(&self, s: f64) -> (Pt, bool) {
        match self.memory[ix(s)].top() {
            Some(p) => (p, true),
            None => (self.outer(s), false),
        }
    }

    fn backbone(&mut self, u: f64, f: f64, s: f64) -> Branch {
        self.kind = TKind::Backbone;
        let (stiffness, end) = if self.bb.trilinear() && !self.yielded[ix(s)] {
            (self.bb.k2, s * self.bb.uy)
        } else {
            (self.bb.kp, s * f64::INFINITY)
        };
        let (lower, upper) = if s > 0.0 {
            (f64::NEG_INFINITY, end)
        } else {
            (end, f64::INFINITY)
        };
        Branch {
            u_ref: u,
            f_ref: f,
            stiffness,
            lower,
            upper,
            direction: s,
            ends_on_reversal: true,
        }
    }

    /// T2: line from the backbone point `(u, f)` of direction `s` to the opposite pre-yield peak.
    fn peak_to_peak(&mut self, u: f64, f: f64, s: f64) -> Branch {
        self.kind = TKind::PeakToPeak;
        let o = if self.cracked[ix(-s)] {
            self.peak[ix(-s)]
        } else {
            Pt {
                u: -s * self.bb.ue,
                f: -s * self.bb.fe,
            }
        };
        Branch {
            u_ref: u,
            f_ref: f,
            stiffness: (f - o.f) / (u - o.u),
            lower: u.min(o.u),
            upper: u.max(o.u),
            direction: -s,
            ends_on_reversal: false,
        }
    }

    /// T3: unloading from `(u, f)`, force of sign `s`, toward zero force.
    fn unload(&mut self, u: f64, f: f64, s: f64, from_backbone: bool) -> Branch {
        self.kind = TKind::Unload {
            side: s,
            from_backbone,
        };
        let d_max = self.peak[0]
            .u
            .abs()
            .max(self.peak[1].u.abs())
            .max(self.bb.uy);
        let mut ku = self.ky * (self.bb.uy / d_max).powf(self.alpha);
        let (t, _) = self.target(-s);
        if s * (u - t.u) > 0.0 {
            ku = ku.max((f - t.f) / (u - t.u));
        }
        let z = u - f / ku;
        let (lower, upper) = if s > 0.0 {
            (z.min(u), u)
        } else {
            (u, z.max(u))
        };
        Branch {
            u_ref: u,
            f_ref: f,
            stiffness: ku,
            lower,
            upper,
            direction: -s,
            ends_on_reversal: false,
        }
    }

    /// T4/T5: reloading from `(u, f)` in direction `s` toward its target.
    fn reload(&mut self, u: f64, f: f64, s: f64) -> Branch {
        loop {
            let (t, to_memory) = self.target(s);
            if s * (t.u - u) > 0.0 {
                self.kind = TKind::Reload { side: s, to_memory };
                let (lower, upper) = if s > 0.0 {
                    (f64::NEG_INFINITY, t.u)
                } else {
                    (t.u, f64::INFINITY)
                };
                return Branch {
                    u_ref: u,
                    f_ref: f,
                    stiffness: (t.f - f) / (t.u - u),
                    lower,
                    upper,
                    direction: s,
                    ends_on_reversal: true,
                };
            }
            if to_memory {
                // Already at or past this local peak.
                self.memory[ix(s)].pop();
            } else {
                // Already at or past the outer peak (defensive): continue on the backbone.
                return self.join_backbone(u, f, s);
            }
        }
    }

    fn join_backbone(&mut self, u: f64, f: f64, s: f64) -> Branch {
        let i = ix(s);
        self.cracked[i] = true;
        self.yielded[i] = true;
        self.memory[i] = Peaks::EMPTY;
        self.update_peak(s, u, f);
        self.backbone(u, f, s)
    }

    fn any_yield(&self) -> bool {
        self.yielded[0] || self.yielded[1]
    }

    /// Next branch after `b` ended at `u`, moving in `d`.
    fn next(&mut self, b: &Branch, u: f64, d: f64) -> Branch {
        let f = b.force(u);
        match self.kind {
            TKind::Elastic => {
                let i = ix(d);
                self.cracked[i] = true;
                if !self.bb.trilinear() {
                    self.yielded[i] = true;
                }
                self.update_peak(d, u, f);
                self.backbone(u, f, d)
            }
            TKind::Backbone => {
                let s = b.direction;
                let i = ix(s);
                self.update_peak(s, u, f);
                if d == s {
                    // Crack–yield segment ended at the yield point.
                    self.yielded[i] = true;
                    self.backbone(u, f, s)
                } else {
                    self.memory[i] = Peaks::EMPTY;
                    if self.any_yield() {
                        self.unload(u, f, s, true)
                    } else {
                        self.peak_to_peak(u, f, s)
                    }
                }
            }
            TKind::PeakToPeak => {
                self.cracked[ix(d)] = true;
                self.update_peak(d, u, f);
                self.backbone(u, f, d)
            }
            TKind::Unload {
                side,
                from_backbone,
            } => {
                if d == side {
                    // T6: back at the unloading point.
                    if from_backbone {
                        self.backbone(u, f, side)
                    } else {
                        self.memory[ix(side)].pop();
                        self.reload(u, f, side)
                    }
                } else {
                    self.reload(u, f, -side)
                }
            }
            TKind::Reload { side, to_memory } => {
                if d == side {
                    if to_memory {
                        self.memory[ix(side)].pop();
                        self.reload(u, f, side)
                    } else {
                        self.join_backbone(u, f, side)
                    }
                } else if side * f > 0.0 {
                    // T5: inner loop.
                    self.memory[ix(side)].push(Pt { u, f });
                    self.unload(u, f, side, false)
                } else {
                    // T7.
                    self.reload(u, f, -side)
                }
            }
        }
    }
}

/// Bilinear kinematic hardening: next branch after `b` ended at `u`, moving in `d`.
fn bilinear_next(k: f64, kp: f64, c: f64, b: &Branch, u: f64, d: f64) -> Branch {
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
fn bilinear_elastic(k: f64, kp: f64, c: f64, u: f64, f: f64, d: f64) -> Branch {
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

#[derive(Clone, Debug)]
enum Model {
    Linear,
    /// Elastic slope, post-yield slope, half band `f_y·(1 − r)`.
    Bilinear {
        k: f64,
        kp: f64,
        c: f64,
    },
    Takeda(Box<Takeda>),
}

/// A hysteretic element: a [`Law`] and its state (current branch and memory).
#[derive(Clone, Debug)]
pub struct Hysteretic {
    law: Law,
    branch: Branch,
    u: f64,
    model: Model,
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
