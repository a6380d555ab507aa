//! The general planar scene the engine integrates: rigid bodies with only the DOFs they need,
//! point-on-face unilateral contacts, force elements to fixed or moving supports, constant loads.
//!
//! Generalized coordinates q are displacements from a reference configuration
//! (paper §3.2: u = [x₁, θ₁, x₂, y₂, θ₂, x₃, θ₃]); M is diagonal (eq. 1).
//!
//! - [`settings`]: the solver settings of a run (units, defaults, which method reads each);
//! - [`kinematics`]: poses, exact contact kinematics (gap, Jacobians), element deformations;
//! - [`forces`]: the smooth forces h(t, q, q̇) of eq. 1 and the energy ledger's power terms.

mod force_runs;
mod forces;
mod key;
mod kinematics;
mod restrict;
mod settings;

pub use crate::methods::Method;
pub(crate) use forces::LEDGER_TERMS;
pub use forces::{ForceModel, PowerTerms, smooth_forces, smooth_forces_in};
pub use key::SceneKey;
pub use kinematics::{BodyState, ContactKinematics, Deformation, Frame, spread};
pub use restrict::Restricted;
pub use settings::Settings;

use crate::excitation::GroundMotion;
use crate::hysteresis::{Branch, Hysteretic};
use nalgebra::{DVector, Vector2};
use std::sync::Arc;

/// Planar coordinate a body may have as a degree of freedom.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// Longitudinal translation.
    X = 0,
    /// Transverse translation.
    Y = 1,
    /// Rotation in plan.
    Theta = 2,
}

/// A planar rigid body. `dofs[a]` is the index in q of axis a, or `None` when that axis is fixed.
#[derive(Clone, Debug)]
pub struct Body {
    /// Its name in outputs (`NAME.x`, `NAME.theta`, …).
    pub name: String,
    /// Mass.
    pub mass: f64,
    /// Mass moment of inertia about the vertical axis through the centre.
    pub inertia: f64,
    /// Centre position at the reference configuration (q = 0).
    pub reference: Vector2<f64>,
    /// Per [`Axis`], its index in q (None: fixed or driven).
    pub dofs: [Option<usize>; 3],
    /// Supports whose motion drives the centre's x and y, on axes without a DOF:
    /// X(t) = X₀ + (u_g,x(t), u_g,y(t)) — a rigid abutment moving with the ground (no DOFs), or
    /// a backwall free in x and θ carried in y by the ground (bridge files).
    pub drive: [Option<usize>; 2],
}

impl Body {
    /// A body moved by the ground ([`Body::drive`]).
    pub fn is_driven(&self) -> bool {
        self.drive.iter().any(Option::is_some)
    }

    /// No DOF: fixed, or driven by the ground.
    pub(crate) fn has_no_dofs(&self) -> bool {
        self.dofs.iter().all(Option::is_none)
    }
}

/// Which body: a scene body or the fixed ground.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyRef {
    /// The fixed ground.
    Ground,
    /// A body of [`Scene::bodies`].
    Body(usize),
}

/// The seat under a deck corner. `width` is the support length at the reference configuration
/// (AASHTO's N: from the deck end to the seat's edge); the deck end is unseated when it has moved
/// that far away from the backwall, i.e. when the corner's gap g_N (rotation included) reaches
/// `edge` = width + g_N(0); margin(t) = edge − g_N(t).
#[derive(Clone, Debug, PartialEq)]
pub struct Seat {
    /// The corner's contact.
    pub contact: usize,
    /// Support length at the reference configuration, m.
    pub width: f64,
    /// The gap at which the corner leaves the seat: width + the initial gap, m.
    pub edge: f64,
    /// The minimum support length of AASHTO LRFD 4.7.4.4 for this deck, m, and the percentage
    /// of N applied (100 % in seismic zone 2, 150 % in zones 3–4); None in scene files.
    pub required: Option<(f64, f64)>,
}

/// Unilateral frictional contact of a point of one body against a straight face of another
/// (corner-on-face; the face at any angle, so skew abutments work).
#[derive(Clone, Debug)]
pub struct Contact {
    /// Its name in outputs (`NAME.gap`, …).
    pub name: String,
    /// The body of the contact point (the corner).
    pub point_body: BodyRef,
    /// Contact point, body frame, relative to the body centre.
    pub point: Vector2<f64>,
    /// The body of the face.
    pub face_body: BodyRef,
    /// A point of the face, face-body frame, relative to the face body's centre.
    pub face_point: Vector2<f64>,
    /// Unit outward normal of the face in the face-body frame (g_N > 0 is open).
    pub face_normal: Vector2<f64>,
    /// Friction and restitution (eq. 2–4).
    pub law: crate::contact::law::ContactLaw,
}

/// How an element's deformation is measured.
#[derive(Clone, Debug)]
pub enum Attachment {
    /// e = d·(P(q) − P(0)) − u_g(t): a body point along a fixed world direction d.
    Point {
        /// The body.
        body: usize,
        /// The point, body frame, relative to the centre.
        point: Vector2<f64>,
        /// The fixed world direction d (unit).
        direction: Vector2<f64>,
    },
    /// e = θ − u_g(t).
    Rotation {
        /// The body.
        body: usize,
    },
    /// e = d·[(P_a(q) − P_a(0)) − (P_b(q) − P_b(0))] − u_g(t): two body points (a of `body`, b
    /// of `other`) along a fixed world direction d (a shear key between two frames).
    Relative {
        /// Body a.
        body: usize,
        /// Point a, body a's frame.
        point: Vector2<f64>,
        /// Body b.
        other: usize,
        /// Point b, body b's frame.
        other_point: Vector2<f64>,
        /// The fixed world direction d (unit).
        direction: Vector2<f64>,
    },
}

impl Attachment {
    /// The body the element is attached to, and the other one of a two-body element.
    pub fn bodies(&self) -> (usize, Option<usize>) {
        match *self {
            Attachment::Point { body, .. } | Attachment::Rotation { body } => (body, None),
            Attachment::Relative { body, other, .. } => (body, Some(other)),
        }
    }
}

/// Linear spring–dashpot to a fixed or moving support.
#[derive(Clone, Debug)]
pub struct Spring {
    /// Its name.
    pub name: String,
    /// What its deformation e measures.
    pub attachment: Attachment,
    /// f = stiffness·e + damping·ė.
    pub stiffness: f64,
    /// The dashpot's coefficient.
    pub damping: f64,
    /// The support whose motion u_g enters e (None: fixed).
    pub support: Option<usize>,
}

/// Hysteretic element (a column in one direction) with an optional parallel dashpot.
#[derive(Clone, Debug)]
pub struct HystereticElement {
    /// Its name in outputs (`NAME.deformation`, `NAME.force`).
    pub name: String,
    /// What its deformation e measures.
    pub attachment: Attachment,
    /// Its law and present branch.
    pub law: Hysteretic,
    /// The parallel dashpot's coefficient.
    pub damping: f64,
    /// The support whose motion u_g enters e (None: fixed).
    pub support: Option<usize>,
}

/// A prescribed support motion u_g(t).
#[derive(Clone, Debug)]
pub enum Motion {
    /// u_g = A sin(ω t + φ).
    Harmonic {
        /// A.
        amplitude: f64,
        /// ω, rad/s.
        omega: f64,
        /// φ, rad.
        phase: f64,
    },
    /// A processed record (piecewise-linear acceleration, exact integrals).
    Record(Arc<GroundMotion>),
}

/// A support (a table, a bent's foundation, an actuator's base) and its motion.
#[derive(Clone, Debug)]
pub struct Support {
    /// Its name.
    pub name: String,
    /// u_g(t) before the factor.
    pub motion: Motion,
    /// The motion's scale (a component's share, a unit change).
    pub factor: f64,
}

impl Support {
    /// (u_g, u̇_g, ü_g) at t.
    pub fn at(&self, t: f64) -> (f64, f64, f64) {
        let (d, v, a) = match &self.motion {
            Motion::Harmonic {
                amplitude,
                omega,
                phase,
            } => {
                let s = (omega * t + phase).sin();
                let c = (omega * t + phase).cos();
                (
                    amplitude * s,
                    amplitude * omega * c,
                    -amplitude * omega * omega * s,
                )
            }
            Motion::Record(g) => g.at(t),
        };
        (self.factor * d, self.factor * v, self.factor * a)
    }
}

/// Mass-proportional damping −a₀ M (q̇ − q̇_ref(t)), with q̇_ref the quasi-static velocity
/// Σ_s r_{i,s} u̇_{g,s}; it vanishes for rigid-body support motion.
#[derive(Clone, Debug, Default)]
pub struct MassDamping {
    /// a₀, 1/s.
    pub alpha: f64,
    /// (dof, support, factor) terms of q̇_ref.
    pub reference: Vec<(usize, usize, f64)>,
}

/// A compiled scene: what the integrators run.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The model's title.
    pub title: String,
    /// The model's unit system (names units; the engine itself is unit-free).
    pub units: crate::units::UnitSystem,
    /// Compiled from a bridge file (its numbers in `units`); false for a scene file, whose
    /// units are its author's.
    pub bridge: bool,
    /// Seats under the deck ends (bridge files with `abutment.seat_width`): one per corner.
    pub seats: Vec<Seat>,
    /// The rigid bodies.
    pub bodies: Vec<Body>,
    /// The unilateral frictional contacts.
    pub contacts: Vec<Contact>,
    /// The linear spring–dashpots.
    pub springs: Vec<Spring>,
    /// The hysteretic elements (columns, backfill, keys).
    pub hysteretic: Vec<HystereticElement>,
    /// The supports and their motions.
    pub supports: Vec<Support>,
    /// Mass-proportional damping.
    pub mass_damping: MassDamping,
    /// Constant generalized forces (gravity, loads).
    pub loads: DVector<f64>,
    /// Diagonal of M.
    pub mass: DVector<f64>,
    /// Per DOF, its name in outputs (`deck.theta`).
    pub dof_names: Vec<String>,
    /// Initial positions q(0).
    pub q0: DVector<f64>,
    /// Initial velocities q̇(0).
    pub v0: DVector<f64>,
    /// The solver's settings.
    pub settings: Settings,
}

impl Scene {
    /// The number of DOFs, the length of q.
    pub fn ndof(&self) -> usize {
        self.mass.len()
    }

    /// Time instants where the right-hand side is not smooth in t (record samples).
    pub fn breakpoints(&self) -> Vec<f64> {
        let mut out = Vec::new();
        if self.settings.stop_at_samples {
            for s in &self.supports {
                if let Motion::Record(g) = &s.motion {
                    out.extend(g.sample_times());
                }
            }
        }
        out.retain(|t| *t > 0.0 && *t < self.settings.t_end);
        out.sort_by(f64::total_cmp);
        out.dedup();
        out
    }

    /// The strong-motion window spanning every record of the supports: the earliest time their
    /// Arias intensity reaches 5 %, the latest it reaches 95 %
    /// ([`GroundMotion::strong_motion_window`], lags included: the time axis of a bridge
    /// file's `excitation.window`). None without a record.
    pub fn strong_motion_window(&self) -> Option<(f64, f64)> {
        (self.supports.iter())
            .filter_map(|s| match &s.motion {
                Motion::Record(g) => g.strong_motion_window(),
                Motion::Harmonic { .. } => None,
            })
            .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
    }

    /// The longest step while a contact is closed: its λ_N and stick margin are driven in t by
    /// the supports even where the state rests (a body held against a fixed stop, whose error
    /// estimate is then 0), and the event search samples them at ½ and 1 of a step. 1/16 of a
    /// harmonic period, 8 samples of a record; ∞ without supports.
    pub(crate) fn closed_step_cap(&self) -> f64 {
        self.supports
            .iter()
            .map(|s| match &s.motion {
                Motion::Harmonic { omega, .. } if *omega != 0.0 => {
                    std::f64::consts::TAU / omega.abs() / 16.0
                }
                Motion::Harmonic { .. } => f64::INFINITY,
                Motion::Record(g) => 8.0 * g.dt,
            })
            .filter(|h| *h > 0.0)
            .fold(f64::INFINITY, f64::min)
    }

    /// ½ q̇ᵀ M q̇.
    pub(crate) fn kinetic_energy(&self, v: &DVector<f64>) -> f64 {
        0.5 * v
            .iter()
            .zip(self.mass.iter())
            .map(|(a, m)| m * a * a)
            .sum::<f64>()
    }

    /// Current branches of all hysteretic elements.
    pub fn branches(&self) -> Vec<Branch> {
        self.hysteretic.iter().map(|h| *h.law.branch()).collect()
    }
}
