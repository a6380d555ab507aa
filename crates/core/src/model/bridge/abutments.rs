//! What an abutment is made of, as a scene needs it: (a) a block on two longitudinal
//! spring–dampers (the specimen's actuators), (b) a rigid wall moving with the ground (no DOFs),
//! (c) a backwall block on its stem springs with the passive backfill behind it (Caltrans SDC
//! v1.7 §7.8.1, the skew reduction of Rollins & Jessee 2013); bearings under the deck ends and
//! exterior shear keys beside them; interior keys across the joints.

use super::layout::{Frame, Plan, frame_body};
use super::schema::{AbutmentSpec, BridgeFile, KeySpec, Kind};
use crate::hysteresis::{HysteresisError, Hysteretic, Law};
use crate::model::check::{Check, ModelError};
use crate::scene::{Attachment, HystereticElement, Spring};
use crate::units::UnitSystem;
use nalgebra::Vector2;

/// Caltrans SDC v1.7 §7.8.1 initial backfill stiffness per unit width and height ratio:
/// K = K_i w (h / 1.7 m), K_i = 28.7 kN/mm/m.
const K_I: f64 = 28.7e3;
/// Passive pressure of the SDC: P = A_e · 239 kPa · (h / 1.7 m).
const P_PASSIVE: f64 = 239.0;
/// The SDC's reference backwall height, m (5.5 ft).
const H_REF: f64 = 1.7;

/// Rollins & Jessee (2013): the passive force of a backwall skewed θ (degrees) over that of a
/// straight one, R = 8.0·10⁻⁵ θ² − 0.018 θ + 1.
pub fn skew_reduction(theta_deg: f64) -> f64 {
    let t = theta_deg.abs();
    8.0e-5 * t * t - 0.018 * t + 1.0
}

/// Stiffness (kN/m) and capacity (kN) of the whole backfill behind a backwall of height h and
/// width w (m, along the wall) skewed θ: the SDC's K and P, both times Rollins & Jessee's R.
pub fn caltrans_backfill(h: f64, w: f64, theta_deg: f64) -> (f64, f64) {
    let r = skew_reduction(theta_deg);
    let k = K_I * w * (h / H_REF);
    let p = h * w * P_PASSIVE * (h / H_REF);
    (r * k, r * p)
}

/// The two springs of an abutment block (kinds `actuators` and `backfill`), body `ab`.
fn springs_of(a: &AbutmentSpec, ab: usize, side: &str, support: Option<usize>) -> Vec<Spring> {
    let (k, off) = (
        a.actuator_stiffness.unwrap_or(0.0),
        a.actuator_offset.unwrap_or(0.0),
    );
    [(1.0, "top"), (-1.0, "bottom")]
        .map(|(sgn, tag)| Spring {
            name: format!("{side}_actuator_{tag}"),
            attachment: Attachment::Point {
                body: ab,
                point: Vector2::new(0.0, sgn * off),
                direction: Vector2::new(1.0, 0.0),
            },
            stiffness: k,
            damping: a.actuator_damping,
            support,
        })
        .to_vec()
}

/// Where the bridge's abutments are and how they are driven: bodies 0 and `last`; supports
/// of their ground motion in x (`sx`) and y (`sy`, when present).
pub(super) struct Ends {
    pub last: usize,
    pub sx: Option<[usize; 2]>,
    pub sy: Option<[usize; 2]>,
    /// The actuators follow the ground (`excitation.drive_abutments`).
    pub drive_actuators: bool,
}

/// Springs of the abutment blocks (kinds `actuators` and `backfill`).
pub(super) fn abutment_springs(a: &AbutmentSpec, kind: Kind, ends: &Ends) -> Vec<Spring> {
    if kind == Kind::Rigid {
        return Vec::new();
    }
    let mut out = Vec::new();
    for (i, (ab, side)) in [(0usize, "left"), (ends.last, "right")]
        .into_iter()
        .enumerate()
    {
        let support = ends.sx.filter(|_| ends.drive_actuators).map(|s| s[i]);
        out.extend(springs_of(a, ab, side, support));
    }
    out
}

fn element(
    name: String,
    attachment: Attachment,
    law: Law,
    support: Option<usize>,
    field: &str,
    ck: &Check,
) -> Result<HystereticElement, ModelError> {
    Ok(HystereticElement {
        name,
        attachment,
        law: Hysteretic::new(law).map_err(|e| ck.err(field, e.to_string()))?,
        damping: 0.0,
        support,
    })
}

fn key_law(k: &KeySpec) -> Law {
    Law::Key {
        gap: k.gap,
        stiffness: k.stiffness,
        capacity: k.capacity,
        failure_displacement: k.failure_displacement,
    }
}

/// The abutments' gap elements: the backfill behind each backwall (two halves at the springs'
/// offsets, pushed along −x at the left, +x at the right), the bearings under the end frames'
/// corners (x and y, to the ground) and the exterior keys beside them (along ±y, to the
/// ground).
pub(super) fn abutment_elements(
    f: &BridgeFile,
    kind: Kind,
    frames: &[Frame],
    plan: &Plan,
    ends: &Ends,
    ck: &Check,
) -> Result<Vec<HystereticElement>, ModelError> {
    let a = &f.abutment;
    let n = frames.len();
    let mut out = Vec::new();
    for (i, (side, k, right)) in [("left", 0, false), ("right", n - 1, true)]
        .into_iter()
        .enumerate()
    {
        let sx = ends.sx.map(|s| s[i]);
        let sy = ends.sy.map(|s| s[i]);
        if kind == Kind::Backfill {
            let line = &plan.lines[if right { n } else { 0 }];
            let (stiffness, capacity) = backfill_of(a, frames[k].width, line.skew, ck.units);
            let ab = if right { ends.last } else { 0 };
            let off = a.actuator_offset.unwrap_or(0.0);
            let d = Vector2::new(if right { 1.0 } else { -1.0 }, 0.0);
            for (sgn, tag) in [(1.0, "top"), (-1.0, "bottom")] {
                let law = Law::Backfill {
                    gap: 0.0,
                    stiffness: 0.5 * stiffness,
                    capacity: 0.5 * capacity,
                };
                let point = Vector2::new(0.0, sgn * off);
                let att = Attachment::Point {
                    body: ab,
                    point,
                    direction: d,
                };
                out.push(element(
                    format!("{side}_backfill_{tag}"),
                    att,
                    law,
                    sx,
                    "abutment.backfill_stiffness",
                    ck,
                )?);
            }
        }
        let corners = plan.corners(frames, k, right);
        if let Some(law) = &a.bearing {
            for (c, tag) in corners.iter().zip(["top", "bottom"]) {
                for (d, axis, s) in [(Vector2::x(), "x", sx), (Vector2::y(), "y", sy)] {
                    let att = Attachment::Point {
                        body: frame_body(k),
                        point: *c,
                        direction: d,
                    };
                    let name = format!("{side}_bearing_{tag}.{axis}");
                    out.push(element(name, att, law.clone(), s, "abutment.bearing", ck)?);
                }
            }
        }
        if let Some(key) = &a.key {
            for (c, (sgn, tag)) in corners.iter().zip([(1.0, "top"), (-1.0, "bottom")]) {
                let att = Attachment::Point {
                    body: frame_body(k),
                    point: *c,
                    direction: Vector2::new(0.0, sgn),
                };
                let name = format!("{side}_key_{tag}");
                out.push(element(name, att, key_law(key), sy, "abutment.key", ck)?);
            }
        }
    }
    Ok(out)
}

/// The backfill of one backwall: given, or Caltrans' from its height, the deck's width along
/// the skewed wall (w / cos θ) and the skew; in the model's units `u`.
fn backfill_of(a: &AbutmentSpec, width: f64, skew: f64, u: UnitSystem) -> (f64, f64) {
    let m = u.per_metre();
    let h = a.backwall_height.unwrap_or(0.0) / m;
    let w = width / skew.to_radians().cos() / m;
    let (k, p) = caltrans_backfill(h, w, skew);
    (
        a.backfill_stiffness.unwrap_or(k * u.per_kilonewton() / m),
        a.backfill_capacity.unwrap_or(p * u.per_kilonewton()),
    )
}

/// Interior keys across each joint with a `key`: one beside each side of the left frame's end,
/// between the two frames, along the joint line (±t, t = m turned +90°).
pub(super) fn joint_keys(
    f: &BridgeFile,
    frames: &[Frame],
    plan: &Plan,
    ck: &Check,
) -> Result<Vec<HystereticElement>, ModelError> {
    let mut out = Vec::new();
    for (j, joint) in f.joints.iter().enumerate().take(frames.len() - 1) {
        let Some(key) = &joint.key else { continue };
        let m = plan.lines[j + 1].m;
        let t = Vector2::new(-m.y, m.x);
        let corners = plan.corners(frames, j, true);
        let offset = plan.centres[j] - plan.centres[j + 1];
        for (c, (sgn, tag)) in corners.iter().zip([(1.0, "top"), (-1.0, "bottom")]) {
            let att = Attachment::Relative {
                body: frame_body(j),
                point: *c,
                other: frame_body(j + 1),
                other_point: c + offset,
                direction: sgn * t,
            };
            let name = format!("joint{}_key_{tag}", j + 1);
            out.push(element(
                name,
                att,
                key_law(key),
                None,
                &format!("joint.{j}.key"),
                ck,
            )?);
        }
    }
    Ok(out)
}

/// Checks of the abutment's kind and the fields it reads; a key's values.
pub(super) fn validate(f: &BridgeFile, ck: &Check) -> Result<Kind, ModelError> {
    let a = &f.abutment;
    let kind = Kind::of(a, ck)?;
    let required = |field: &str, v: Option<f64>| -> Result<f64, ModelError> {
        let full = format!("abutment.{field}");
        let v = v.ok_or_else(|| {
            ck.err(
                &full,
                format!("required for abutment kind = \"{}\"", kind.name()),
            )
        })?;
        ck.positive(&full, v)
    };
    if kind != Kind::Rigid {
        required("mass", a.mass)?;
        required("inertia", a.inertia)?;
        required("actuator_stiffness", a.actuator_stiffness)?;
        required("actuator_offset", a.actuator_offset)?;
    }
    ck.nonneg("abutment.actuator_damping", a.actuator_damping)?;
    if kind == Kind::Backfill {
        required("backwall_height", a.backwall_height)?;
        for (field, v) in [
            ("backfill_stiffness", a.backfill_stiffness),
            ("backfill_capacity", a.backfill_capacity),
        ] {
            if v.is_some() {
                required(field, v)?;
            }
        }
    }
    if let Some(b) = &a.bearing {
        b.validate()
            .map_err(|e| ck.err("abutment.bearing", e.to_string()))?;
        if b.is_gap_law() {
            return Err(ck.err(
                "abutment.bearing",
                "a bearing law is linear, bilinear or takeda",
            ));
        }
    }
    let keys = std::iter::once(("abutment.key".to_string(), &a.key)).chain(
        (f.joints.iter().enumerate()).map(|(j, joint)| (format!("joint.{j}.key"), &joint.key)),
    );
    for (table, key) in keys {
        if let Some(k) = key
            && let Err(HysteresisError::Invalid { field, reason }) = key_law(k).validate()
        {
            return Err(ck.err(&format!("{table}.{field}"), reason));
        }
    }
    Ok(kind)
}

/// The fields a kind does not read, when given: (field, kind).
pub(super) fn unread(a: &AbutmentSpec, kind: Kind) -> Vec<&'static str> {
    let given: &[(&'static str, bool)] = match kind {
        Kind::Rigid => &[
            ("mass", a.mass.is_some()),
            ("inertia", a.inertia.is_some()),
            ("actuator_stiffness", a.actuator_stiffness.is_some()),
            ("actuator_damping", a.actuator_damping != 0.0),
            ("actuator_offset", a.actuator_offset.is_some()),
            ("backwall_height", a.backwall_height.is_some()),
            ("backfill_stiffness", a.backfill_stiffness.is_some()),
            ("backfill_capacity", a.backfill_capacity.is_some()),
        ],
        Kind::Actuators => &[
            ("backwall_height", a.backwall_height.is_some()),
            ("backfill_stiffness", a.backfill_stiffness.is_some()),
            ("backfill_capacity", a.backfill_capacity.is_some()),
        ],
        Kind::Backfill => &[],
    };
    given.iter().filter(|(_, g)| *g).map(|(f, _)| *f).collect()
}
