//! Takeda degrading-stiffness rules T1–T7 (module docs of [`super`]).

use super::branch::Branch;
use super::law::{Backbone, Law};

/// Index of direction `s` (+ → 0, − → 1).
fn ix(s: f64) -> usize {
    usize::from(s < 0.0)
}

/// Depth of the local-peak memory per direction (Takeda rule T5); older peaks are forgotten.
pub(crate) const MEMORY: usize = 16;

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
pub(super) struct Takeda {
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
    pub(super) fn new(law: &Law) -> (Self, Branch) {
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
    pub(super) fn next(&mut self, b: &Branch, u: f64, d: f64) -> Branch {
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
