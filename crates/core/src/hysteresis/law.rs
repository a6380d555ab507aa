//! Law parameters (TOML/JSON schema), their validation and the backbone.

use serde::{Deserialize, Serialize};

/// Errors of law parameters; `field` is the offending parameter.
#[derive(Debug, thiserror::Error)]
pub enum HysteresisError {
    /// A parameter out of its range.
    #[error("{field}: {reason}")]
    Invalid {
        /// The parameter.
        field: &'static str,
        /// What is wrong.
        reason: String,
    },
}

fn default_unloading_exponent() -> f64 {
    0.4
}

/// A hysteretic law (TOML/JSON: `law = "linear" | "bilinear" | "takeda" | "backfill" | "key"`
/// plus its fields).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(tag = "law", rename_all = "lowercase", deny_unknown_fields)]
pub enum Law {
    /// `f = stiffness·u`.
    Linear {
        /// Stiffness, force / deformation.
        stiffness: f64,
    },
    /// Bilinear with kinematic hardening; post-yield slope `post_yield_ratio·stiffness`.
    Bilinear {
        /// Initial stiffness, force / deformation.
        stiffness: f64,
        /// Yield force.
        yield_force: f64,
        /// Post-yield slope / initial stiffness.
        post_yield_ratio: f64,
    },
    /// Takeda (see the module rules T1–T7).
    ///
    /// Backbone: bilinear `(0,0)–(f_y/k, f_y)` then slope `r·k`; or, with `crack_force`,
    /// trilinear `(0,0)–(f_c/k, f_c)–(yield_displacement, f_y)` then slope `r·k`
    /// (`k = stiffness`, the cracked-section stiffness, `r = post_yield_ratio`).
    Takeda {
        /// Initial stiffness, force / deformation.
        stiffness: f64,
        /// Yield force.
        yield_force: f64,
        /// Post-yield slope / initial stiffness.
        post_yield_ratio: f64,
        /// Cracking force of a trilinear backbone.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        crack_force: Option<f64>,
        /// Yield displacement of the trilinear backbone; required with `crack_force` only.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        yield_displacement: Option<f64>,
        /// Exponent α of the unloading stiffness (T3).
        #[serde(default = "default_unloading_exponent")]
        unloading_exponent: f64,
    },
    /// Passive backfill behind an abutment backwall (Caltrans SDC v1.7, §7.8.1), compression
    /// only (rules G1–G4): `f = 0` for `e < gap + e_p`, `f = stiffness·(e − gap − e_p)` up to
    /// `capacity`, then `f = capacity` while `e_p` grows; unloading along `stiffness`.
    Backfill {
        /// Deformation at which contact begins.
        gap: f64,
        /// Initial stiffness, force / deformation.
        stiffness: f64,
        /// Largest force.
        capacity: f64,
    },
    /// Sacrificial shear key (Megally, Silva & Seible 2001): the backfill law (G1–G4), and once
    /// `e − gap` reaches `failure_displacement` the key is gone, `f = 0` for ever (G5).
    Key {
        /// Deformation at which contact begins.
        gap: f64,
        /// Initial stiffness, force / deformation.
        stiffness: f64,
        /// Largest force.
        capacity: f64,
        /// Deformation past the gap at which the key fails (G5).
        failure_displacement: f64,
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

fn nonneg(field: &'static str, x: f64) -> Result<(), HysteresisError> {
    if x.is_finite() && x >= 0.0 {
        Ok(())
    } else {
        Err(invalid(
            field,
            format!("must be non-negative and finite, got {x}"),
        ))
    }
}

/// Gap, stiffness and capacity of a compression-only law.
fn gap_law(gap: f64, stiffness: f64, capacity: f64) -> Result<(), HysteresisError> {
    nonneg("gap", gap)?;
    positive("stiffness", stiffness)?;
    positive("capacity", capacity)
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
            Law::Backfill {
                gap,
                stiffness,
                capacity,
            } => gap_law(gap, stiffness, capacity),
            Law::Key {
                gap,
                stiffness,
                capacity,
                failure_displacement,
            } => {
                gap_law(gap, stiffness, capacity)?;
                let yield_displacement = capacity / stiffness;
                if failure_displacement.is_finite() && failure_displacement > yield_displacement {
                    Ok(())
                } else {
                    Err(invalid(
                        "failure_displacement",
                        format!(
                            "must be finite and exceed capacity/stiffness = {yield_displacement}, got {failure_displacement}"
                        ),
                    ))
                }
            }
        }
    }

    /// Initial (tangent) stiffness at `u = 0`; 0 for the gap laws (open at rest, like a
    /// contact: K₀ and stiffness-proportional damping leave them out).
    pub fn initial_stiffness(&self) -> f64 {
        match *self {
            Law::Linear { stiffness }
            | Law::Bilinear { stiffness, .. }
            | Law::Takeda { stiffness, .. } => stiffness,
            Law::Backfill { .. } | Law::Key { .. } => 0.0,
        }
    }

    /// Compression-only with a gap (backfill, key).
    pub fn is_gap_law(&self) -> bool {
        matches!(self, Law::Backfill { .. } | Law::Key { .. })
    }

    /// Monotonic backbone (skeleton) force at `u`: odd in `u`; for the gap laws the monotonic
    /// push `clamp(k (u − gap), 0, capacity)` (a key: 0 from `gap + failure_displacement` on).
    pub fn backbone(&self, u: f64) -> f64 {
        match *self {
            Law::Linear { stiffness } => stiffness * u,
            Law::Backfill {
                gap,
                stiffness,
                capacity,
            } => (stiffness * (u - gap)).clamp(0.0, capacity),
            Law::Key {
                gap,
                stiffness,
                capacity,
                failure_displacement,
            } => {
                if u - gap >= failure_displacement {
                    0.0
                } else {
                    (stiffness * (u - gap)).clamp(0.0, capacity)
                }
            }
            _ => u.signum() * Backbone::of(self).force(u.abs()),
        }
    }
}

/// Backbone corners: elastic to `(ue, fe)`, slope `k2` to `(uy, fy)`, then slope `kp`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Backbone {
    pub(super) k: f64,
    pub(super) ue: f64,
    pub(super) fe: f64,
    pub(super) k2: f64,
    pub(super) uy: f64,
    pub(super) fy: f64,
    pub(super) kp: f64,
}

impl Backbone {
    /// The backbone of `law` (the gap laws, whose backbone is not odd, get the linear one:
    /// [`Law::backbone`] does not use it for them).
    pub(super) fn of(law: &Law) -> Self {
        match *law {
            Law::Linear { stiffness }
            | Law::Backfill { stiffness, .. }
            | Law::Key { stiffness, .. } => Self {
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
    pub(super) fn force(&self, a: f64) -> f64 {
        if a <= self.ue {
            self.k * a
        } else if a <= self.uy {
            self.fe + self.k2 * (a - self.ue)
        } else {
            self.fy + self.kp * (a - self.uy)
        }
    }

    pub(super) fn trilinear(&self) -> bool {
        self.ue < self.uy
    }
}
