//! Plan layout of a bridge: frames in series between two abutments, each end on its own
//! (skewed) support line, each frame at its own heading (a plan-curved alignment as a chain of
//! straight frames), and the corner contacts at the abutments and joints.
//!
//! Support lines, from left to right: the left abutment, joints 1 … N−1, the right abutment.
//! Line j has a unit normal m_j along the bridge (left to right): m = R(−φ) b, with b the
//! frame axis at an abutment and the bisector of the two frames' axes at a joint, φ the line's
//! skew. A frame end lies on its line; its corners sit ±w/2 across the frame's axis a:
//! P = E ± (w/2)(p + tan(ψ − ψ_m) a), p = a rotated by +90°, ψ the frame's heading and ψ_m
//! that of m (straight bridge, φ = skew: P = (∓L/2 ± (w/2) tan φ, ±w/2)).

use super::schema::{BentSpec, BridgeFile, CORNERS, Kind};
use crate::contact::law::ContactLaw;
use crate::scene::{Body, BodyRef, Contact};
use nalgebra::{DVector, Vector2};

/// One frame of the bridge, whatever table it came from.
#[derive(Clone)]
pub(super) struct Frame<'a> {
    /// Body name (`deck` for a `[deck]` file).
    pub name: String,
    /// Field prefix of its values (`deck` or `frame.{i}`) and of its bents (`bent` or
    /// `frame.{i}.bent`).
    pub field: String,
    pub bent_field: String,
    pub mass: f64,
    pub inertia: f64,
    pub length: f64,
    pub width: f64,
    /// Degrees.
    pub skew: f64,
    pub heading: f64,
    /// Has a θ DOF (false: translates only, `rotation = false`).
    pub rotation: bool,
    pub bents: &'a [BentSpec],
}

/// The frames of a file: its `[deck]` with the top-level `[[bent]]`, or its `[[frame]]`s.
pub(super) fn frames(f: &BridgeFile) -> Vec<Frame<'_>> {
    if let Some(d) = &f.deck {
        return vec![Frame {
            name: "deck".into(),
            field: "deck".into(),
            bent_field: "bent".into(),
            mass: d.mass,
            inertia: d.inertia,
            length: d.length,
            width: d.width,
            skew: d.skew,
            heading: 0.0,
            rotation: d.rotation,
            bents: &f.bents,
        }];
    }
    (f.frames.iter().enumerate())
        .map(|(i, fr)| Frame {
            name: fr.name.clone().unwrap_or_else(|| format!("frame{}", i + 1)),
            field: format!("frame.{i}"),
            bent_field: format!("frame.{i}.bent"),
            mass: fr.mass,
            inertia: fr.inertia,
            length: fr.length,
            width: fr.width,
            skew: fr.skew,
            heading: fr.heading,
            rotation: fr.rotation,
            bents: &fr.bents,
        })
        .collect()
}

/// A support line: its skew (degrees) and its normal m along the bridge.
#[derive(Clone, Copy, Debug)]
pub(super) struct Line {
    pub skew: f64,
    /// Heading of m, degrees.
    pub heading: f64,
    pub m: Vector2<f64>,
}

impl Line {
    fn new(reference_heading: f64, skew: f64) -> Self {
        let heading = reference_heading - skew;
        // m = (cos d, −sin d), d = skew − reference: (1, −0) for a straight line, as before
        let d = (skew - reference_heading).to_radians();
        Self {
            skew,
            heading,
            m: Vector2::new(d.cos(), -d.sin()),
        }
    }
}

/// The bridge in plan at its reference configuration.
pub(super) struct Plan {
    /// Frame centres (the first at the origin).
    pub centres: Vec<Vector2<f64>>,
    /// Per frame: axis a and its +90° rotation p.
    pub axes: Vec<(Vector2<f64>, Vector2<f64>)>,
    /// Left abutment, joints, right abutment.
    pub lines: Vec<Line>,
    /// Mean of the four abutment gaps: the abutments' reference offset.
    pub gap0: f64,
}

fn unit(deg: f64) -> Vector2<f64> {
    let r = deg.to_radians();
    Vector2::new(r.cos(), r.sin())
}

impl Plan {
    pub fn of(f: &BridgeFile, frames: &[Frame]) -> Self {
        let n = frames.len();
        let axes: Vec<_> = frames
            .iter()
            .map(|fr| {
                let a = unit(fr.heading);
                (a, Vector2::new(-a.y, a.x))
            })
            .collect();
        let mut lines = vec![Line::new(
            frames[0].heading,
            f.abutment.left_skew.unwrap_or(frames[0].skew),
        )];
        for (j, joint) in f.joints.iter().enumerate().take(n.saturating_sub(1)) {
            let bisector = 0.5 * (frames[j].heading + frames[j + 1].heading);
            lines.push(Line::new(bisector, joint.skew.unwrap_or(frames[j].skew)));
        }
        lines.push(Line::new(
            frames[n - 1].heading,
            f.abutment.right_skew.unwrap_or(frames[n - 1].skew),
        ));
        let mut centres = vec![Vector2::zeros()];
        for j in 0..n - 1 {
            let joint = &f.joints[j];
            let line = &lines[j + 1];
            let b = unit(line.heading + line.skew);
            // the mean gap measured along m, the next frame's end moved along the bisector
            let gap = 0.5 * (joint.gaps[0] + joint.gaps[1]);
            let shift = gap / line.skew.to_radians().cos();
            let end = centres[j] + 0.5 * frames[j].length * axes[j].0;
            let start = end + shift * b;
            centres.push(start + 0.5 * frames[j + 1].length * axes[j + 1].0);
        }
        Self {
            centres,
            axes,
            lines,
            gap0: f.contacts.gaps.iter().sum::<f64>() / 4.0,
        }
    }

    /// The two corners (+y side first) of frame k at its left (`right` false) or right end,
    /// relative to the frame's centre.
    pub fn corners(&self, frames: &[Frame], k: usize, right: bool) -> [Vector2<f64>; 2] {
        let (a, p) = self.axes[k];
        let (ls, lw) = (0.5 * frames[k].length, 0.5 * frames[k].width);
        let (line, end) = match right {
            false => (&self.lines[k], -ls),
            true => (&self.lines[k + 1], ls),
        };
        let tan = (frames[k].heading - line.heading).to_radians().tan();
        [a * (end + lw * tan) + p * lw, a * (end - lw * tan) - p * lw]
    }

    /// A point of frame k's bent at x along its axis, y across it (bents parallel to the
    /// frame's skew), relative to the frame's centre.
    pub(crate) fn bent_point(&self, frame: &Frame, k: usize, x: f64, y: f64) -> Vector2<f64> {
        let (a, p) = self.axes[k];
        let tan = frame.skew.to_radians().tan();
        a * (x + y * tan) + p * y
    }
}

/// Body index of frame k (after the left abutment).
pub(super) fn frame_body(k: usize) -> usize {
    k + 1
}

/// An abutment body: `actuators` (x, θ), `rigid` (no DOFs, driven in x and y by `drive`),
/// `backfill` (x, θ, driven in y); its DOFs from `first`.
fn abutment(
    f: &BridgeFile,
    kind: Kind,
    side: &str,
    reference: Vector2<f64>,
    (first, drive): (usize, [Option<usize>; 2]),
    mass: &mut Vec<f64>,
    names: &mut Vec<String>,
) -> Body {
    let a = &f.abutment;
    let (m, i) = (a.mass.unwrap_or(0.0), a.inertia.unwrap_or(0.0));
    let (dofs, drive) = match kind {
        Kind::Rigid => ([None; 3], drive),
        Kind::Actuators => ([Some(first), None, Some(first + 1)], [None; 2]),
        Kind::Backfill => ([Some(first), None, Some(first + 1)], [None, drive[1]]),
    };
    if kind != Kind::Rigid {
        mass.extend([m, i]);
        names.extend([
            format!("{side}_abutment.x"),
            format!("{side}_abutment.theta"),
        ]);
    }
    Body {
        name: format!("{side}_abutment"),
        mass: m,
        inertia: i,
        reference,
        dofs,
        drive,
    }
}

/// Left abutment, the frames (x, y, and θ unless `rotation` is false), right abutment; `drive`: the supports of the two
/// abutments' ground motion in x and y.
pub(super) fn bodies(
    f: &BridgeFile,
    kind: Kind,
    frames: &[Frame],
    plan: &Plan,
    drive: [[Option<usize>; 2]; 2],
) -> (Vec<Body>, DVector<f64>, Vec<String>) {
    let n = frames.len();
    let first_end = plan.centres[0] - 0.5 * frames[0].length * plan.axes[0].0;
    let last_end = plan.centres[n - 1] + 0.5 * frames[n - 1].length * plan.axes[n - 1].0;
    let (mut mass, mut names) = (Vec::new(), Vec::new());
    let left = first_end - plan.gap0 * plan.axes[0].0;
    let mut bodies = vec![abutment(
        f,
        kind,
        "left",
        left,
        (0, drive[0]),
        &mut mass,
        &mut names,
    )];
    for (k, fr) in frames.iter().enumerate() {
        let d = mass.len();
        bodies.push(Body {
            name: fr.name.clone(),
            mass: fr.mass,
            inertia: fr.inertia,
            reference: plan.centres[k],
            dofs: [Some(d), Some(d + 1), fr.rotation.then_some(d + 2)],
            drive: [None; 2],
        });
        mass.extend([fr.mass, fr.mass]);
        names.extend(["x", "y"].map(|c| format!("{}.{c}", fr.name)));
        if fr.rotation {
            mass.push(fr.inertia);
            names.push(format!("{}.theta", fr.name));
        }
    }
    let right = last_end + plan.gap0 * plan.axes[n - 1].0;
    let d = mass.len();
    let body = abutment(
        f,
        kind,
        "right",
        right,
        (d, drive[1]),
        &mut mass,
        &mut names,
    );
    bodies.push(body);
    (bodies, DVector::from_vec(mass), names)
}

/// One corner contact: `corner` of body `point_body` (relative to its centre) against the face
/// of `face_body` with outward normal n, `gap` away.
struct Corner {
    name: String,
    point_body: usize,
    corner: Vector2<f64>,
    face_body: usize,
    n: Vector2<f64>,
    gap: f64,
    mu: f64,
    restitution: f64,
}

fn contact(bodies: &[Body], c: Corner) -> Contact {
    let p = bodies[c.point_body].reference + c.corner;
    let xb = bodies[c.face_body].reference;
    Contact {
        name: c.name,
        point_body: BodyRef::Body(c.point_body),
        point: c.corner,
        face_body: BodyRef::Body(c.face_body),
        face_point: p - xb - c.gap * c.n,
        face_normal: c.n,
        law: ContactLaw {
            mu: c.mu,
            restitution: c.restitution,
        },
    }
}

/// The four end corners against the abutment faces (if `contacts.enabled`), then per joint the
/// left frame's two end corners against the right frame's end face, each at its initial gap.
pub(super) fn corner_contacts(
    f: &BridgeFile,
    frames: &[Frame],
    plan: &Plan,
    bodies: &[Body],
) -> Vec<Contact> {
    let c = &f.contacts;
    let n = frames.len();
    let mut out = Vec::new();
    if c.enabled {
        let right_abutment = bodies.len() - 1;
        let ends = [
            (0, false, 0, plan.lines[0].m),
            (n - 1, true, right_abutment, -plan.lines[n].m),
        ];
        for (side, (k, right, face_body, normal)) in ends.into_iter().enumerate() {
            for (i, corner) in plan.corners(frames, k, right).into_iter().enumerate() {
                let idx = 2 * side + i;
                out.push(contact(
                    bodies,
                    Corner {
                        name: CORNERS[idx].into(),
                        point_body: frame_body(k),
                        corner,
                        face_body,
                        n: normal,
                        gap: c.gaps[idx],
                        mu: c.mu,
                        restitution: c.restitution,
                    },
                ));
            }
        }
    }
    for (j, joint) in f.joints.iter().enumerate().take(n - 1) {
        let m = plan.lines[j + 1].m;
        for (i, corner) in plan.corners(frames, j, true).into_iter().enumerate() {
            out.push(contact(
                bodies,
                Corner {
                    name: format!("joint{}_{}", j + 1, ["top", "bottom"][i]),
                    point_body: frame_body(j),
                    corner,
                    face_body: frame_body(j + 1),
                    n: -m,
                    gap: joint.gaps[i],
                    mu: joint.mu.unwrap_or(c.mu),
                    restitution: joint.restitution.unwrap_or(c.restitution),
                },
            ));
        }
    }
    out
}
