//! The general planar scene the engine integrates: rigid bodies with only the DOFs they need,
//! point-on-face unilateral contacts, force elements to fixed or moving supports, constant loads.
//!
//! Generalized coordinates q are displacements from a reference configuration
//! (paper §3.2: u = [x₁, θ₁, x₂, y₂, θ₂, x₃, θ₃]); M is diagonal (eq. 1).

use crate::excitation::GroundMotion;
use crate::hysteresis::{Branch, Hysteretic};
use crate::lemke::LemkeOptions;
use nalgebra::{DVector, Vector2};
use std::sync::Arc;

/// Planar coordinate a body may have as a degree of freedom.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    X = 0,
    Y = 1,
    Theta = 2,
}

/// A planar rigid body. `dofs[a]` is the index in q of axis a, or `None` when that axis is fixed.
#[derive(Clone, Debug)]
pub struct Body {
    pub name: String,
    pub mass: f64,
    pub inertia: f64,
    /// Centre position at the reference configuration (q = 0).
    pub reference: Vector2<f64>,
    pub dofs: [Option<usize>; 3],
}

/// Which body: a scene body or the fixed ground.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyRef {
    Ground,
    Body(usize),
}

/// Unilateral frictional contact of a point of one body against a straight face of another
/// (corner-on-face; the face at any angle, so skew abutments work).
#[derive(Clone, Debug)]
pub struct Contact {
    pub name: String,
    pub point_body: BodyRef,
    /// Contact point, body frame, relative to the body centre.
    pub point: Vector2<f64>,
    pub face_body: BodyRef,
    /// A point of the face, face-body frame, relative to the face body's centre.
    pub face_point: Vector2<f64>,
    /// Unit outward normal of the face in the face-body frame (g_N > 0 is open).
    pub face_normal: Vector2<f64>,
    /// Coulomb coefficient μ.
    pub mu: f64,
    /// Newton restitution ε (eq. 3).
    pub restitution: f64,
}

/// How an element's deformation is measured.
#[derive(Clone, Debug)]
pub enum Attachment {
    /// e = d·(P(q) − P(0)) − u_g(t): a body point along a fixed world direction d.
    Point {
        body: usize,
        point: Vector2<f64>,
        direction: Vector2<f64>,
    },
    /// e = θ − u_g(t).
    Rotation { body: usize },
}

/// Linear spring–dashpot to a fixed or moving support.
#[derive(Clone, Debug)]
pub struct Spring {
    pub name: String,
    pub attachment: Attachment,
    pub stiffness: f64,
    pub damping: f64,
    pub support: Option<usize>,
}

/// Hysteretic element (a column in one direction) with an optional parallel dashpot.
#[derive(Clone, Debug)]
pub struct HystereticElement {
    pub name: String,
    pub attachment: Attachment,
    pub law: Hysteretic,
    pub damping: f64,
    pub support: Option<usize>,
}

/// A prescribed support motion u_g(t).
#[derive(Clone, Debug)]
pub enum Motion {
    /// u_g = A sin(ω t + φ).
    Harmonic {
        amplitude: f64,
        omega: f64,
        phase: f64,
    },
    /// A processed record (piecewise-linear acceleration, exact integrals).
    Record(Arc<GroundMotion>),
}

#[derive(Clone, Debug)]
pub struct Support {
    pub name: String,
    pub motion: Motion,
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
    pub alpha: f64,
    /// (dof, support, factor) terms of q̇_ref.
    pub reference: Vec<(usize, usize, f64)>,
}

pub use crate::methods::Method;

/// Solver settings of one run (one documented struct, rapier style).
#[derive(Clone, Debug)]
pub struct Settings {
    pub method: Method,
    /// Fixed step of the time-stepping and penalty methods, s.
    pub step: f64,
    /// θ of the Moreau–Jean θ-method for smooth forces.
    pub theta: f64,
    /// Penalty contact stiffness (normal and tangential stick spring), force/length.
    pub contact_stiffness: f64,
    pub t_end: f64,
    /// Output step of the time history (event instants are always added).
    pub output_dt: f64,
    pub rtol: f64,
    pub atol: f64,
    /// Largest step, s (0 = none).
    pub h_max: f64,
    /// Event location tolerance on time, s.
    pub event_time_tol: f64,
    /// |g_N| below this is a closed contact, m.
    pub gap_tol: f64,
    /// |ġ| below this is zero (no impact, stick), m/s.
    pub velocity_tol: f64,
    /// Accumulation rule: an impact slower than `zeno_velocity` closes the contact (ε → 0).
    pub accumulation_rule: bool,
    pub zeno_velocity: f64,
    /// Zeno guard: 16 impacts in a row of one contact each closer than this to the previous
    /// one stop the run (without the accumulation rule); with the rule, such an impact closes
    /// the contact.
    pub min_event_spacing: f64,
    pub max_events: usize,
    pub max_steps: usize,
    /// Never step over the sample instants of recorded support motions.
    pub stop_at_samples: bool,
    /// Hysteretic branch events that follow the first event located in a step by at most this
    /// (s) are applied together at the last of them; 0 applies each at its own instant.
    pub branch_window: f64,
    /// Keep every output sample (else only the summary: sweeps).
    pub keep_history: bool,
    pub lemke: LemkeOptions,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            method: Method::Event,
            step: 1e-3,
            theta: 0.5,
            contact_stiffness: 1e6,
            t_end: 1.0,
            output_dt: 0.01,
            rtol: 1e-8,
            atol: 1e-10,
            h_max: 0.0,
            event_time_tol: 1e-13,
            gap_tol: 1e-9,
            velocity_tol: 1e-9,
            accumulation_rule: true,
            zeno_velocity: 1e-6,
            min_event_spacing: 1e-6,
            max_events: 200_000,
            max_steps: 5_000_000,
            stop_at_samples: false,
            branch_window: 0.0,
            keep_history: true,
            // the Moreau–Jean Delassus Wᵀ Ŵ⁻¹ W of light abutments on stiff actuators is badly
            // scaled: accept solutions whose relative residual is below 1e-7
            lemke: LemkeOptions {
                check_tolerance: 1e-7,
                ..LemkeOptions::default()
            },
        }
    }
}

/// A compiled scene: what the integrators run.
#[derive(Clone, Debug)]
pub struct Scene {
    pub title: String,
    pub bodies: Vec<Body>,
    pub contacts: Vec<Contact>,
    pub springs: Vec<Spring>,
    pub hysteretic: Vec<HystereticElement>,
    pub supports: Vec<Support>,
    pub mass_damping: MassDamping,
    /// Constant generalized forces (gravity, loads).
    pub loads: DVector<f64>,
    /// Diagonal of M.
    pub mass: DVector<f64>,
    pub dof_names: Vec<String>,
    pub q0: DVector<f64>,
    pub v0: DVector<f64>,
    pub settings: Settings,
}

/// Kinematics of one contact at (q, q̇): gap, Jacobian rows and the velocity-product terms.
#[derive(Clone, Debug)]
pub struct ContactKinematics {
    /// g_N.
    pub gap: f64,
    /// W_N = ∂g_N/∂q (so ġ_N = W_Nᵀ q̇).
    pub w_n: DVector<f64>,
    /// W_T: ġ_T = W_Tᵀ q̇, along the face tangent t = (n_y, −n_x) ((t, n) right-handed).
    pub w_t: DVector<f64>,
    pub gap_rate: f64,
    pub slip_rate: f64,
    /// ŵ_N, ŵ_T: g̈ = Wᵀ q̈ + ŵ.
    pub bias_n: f64,
    pub bias_t: f64,
    /// World position of the contact point (for drawing).
    pub point: Vector2<f64>,
    pub normal: Vector2<f64>,
}

impl ContactKinematics {
    /// An open contact whose kinematics were not needed (no allocation).
    pub fn placeholder() -> Self {
        Self {
            gap: f64::INFINITY,
            w_n: DVector::zeros(0),
            w_t: DVector::zeros(0),
            gap_rate: 0.0,
            slip_rate: 0.0,
            bias_n: 0.0,
            bias_t: 0.0,
            point: Vector2::zeros(),
            normal: Vector2::zeros(),
        }
    }
}

/// k × a for a planar vector a.
#[inline]
pub fn perp(a: Vector2<f64>) -> Vector2<f64> {
    Vector2::new(-a.y, a.x)
}

/// Pose and velocity of a body (or ground) from q, q̇.
#[derive(Clone, Copy, Debug)]
pub struct BodyState {
    pub position: Vector2<f64>,
    pub angle: f64,
    pub velocity: Vector2<f64>,
    pub omega: f64,
    /// (cos θ, sin θ).
    pub cs: (f64, f64),
}

impl BodyState {
    /// R(θ) a.
    #[inline]
    pub fn rot(&self, a: Vector2<f64>) -> Vector2<f64> {
        let (c, s) = self.cs;
        Vector2::new(c * a.x - s * a.y, s * a.x + c * a.y)
    }
}

impl Default for BodyState {
    fn default() -> Self {
        Self {
            position: Vector2::zeros(),
            angle: 0.0,
            velocity: Vector2::zeros(),
            omega: 0.0,
            cs: (1.0, 0.0),
        }
    }
}

/// Everything position- and time-dependent that several elements share, computed once per
/// evaluation: body poses and support motions.
#[derive(Clone, Debug, Default)]
pub struct Frame {
    pub poses: Vec<BodyState>,
    pub ground: BodyState,
    /// (u_g, u̇_g, ü_g) per support.
    pub supports: Vec<(f64, f64, f64)>,
    /// Per support, an earlier support driven by the same record and factor (evaluated once).
    alias: Vec<Option<usize>>,
}

impl Frame {
    #[inline]
    pub fn pose(&self, b: BodyRef) -> &BodyState {
        match b {
            BodyRef::Ground => &self.ground,
            BodyRef::Body(i) => &self.poses[i],
        }
    }
}

impl Scene {
    pub fn ndof(&self) -> usize {
        self.mass.len()
    }

    pub fn body_state(&self, b: BodyRef, q: &DVector<f64>, v: &DVector<f64>) -> BodyState {
        match b {
            BodyRef::Ground => BodyState {
                position: Vector2::zeros(),
                angle: 0.0,
                velocity: Vector2::zeros(),
                omega: 0.0,
                cs: (1.0, 0.0),
            },
            BodyRef::Body(i) => self.pose_of(i, |k| q[k], |k| v[k]),
        }
    }

    /// Adds `coef·(∂ (point velocity)/∂q̇)ᵀ d` to a Jacobian row: the generalized direction of a
    /// force d applied at world arm ρ from the centre of body b.
    fn add_point_jacobian(
        &self,
        row: &mut DVector<f64>,
        b: BodyRef,
        arm: Vector2<f64>,
        d: Vector2<f64>,
        coef: f64,
    ) {
        if let BodyRef::Body(i) = b {
            let dofs = &self.bodies[i].dofs;
            let row = row.as_mut_slice();
            if let Some(k) = dofs[0] {
                row[k] += coef * d.x;
            }
            if let Some(k) = dofs[1] {
                row[k] += coef * d.y;
            }
            if let Some(k) = dofs[2] {
                row[k] += coef * d.dot(&perp(arm));
            }
        }
    }

    /// Exact planar kinematics of contact `c` (no small-rotation linearisation):
    /// g_N = n·(P − O), n = R(θ_B) n₀, P = X_A + R(θ_A) r_A, O = X_B + R(θ_B) p_B.
    pub fn contact_kinematics(
        &self,
        c: &Contact,
        q: &DVector<f64>,
        v: &DVector<f64>,
    ) -> ContactKinematics {
        let a = self.body_state(c.point_body, q, v);
        let b = self.body_state(c.face_body, q, v);
        self.contact_kinematics_of(c, &a, &b)
    }

    /// Poses of all bodies and support motions at (t, q, q̇).
    pub fn frame(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>) -> Frame {
        Frame {
            poses: (0..self.bodies.len())
                .map(|i| self.body_state(BodyRef::Body(i), q, v))
                .collect(),
            ground: self.body_state(BodyRef::Ground, q, v),
            supports: self.supports.iter().map(|s| s.at(t)).collect(),
            alias: Vec::new(),
        }
    }

    /// [`Scene::frame`] written into `fr`, reusing its storage.
    pub fn frame_into(&self, fr: &mut Frame, t: f64, q: &DVector<f64>, v: &DVector<f64>) {
        self.poses_into(fr, q, v);
        if fr.alias.len() != self.supports.len() {
            fr.alias = self
                .supports
                .iter()
                .enumerate()
                .map(|(i, s)| match &s.motion {
                    Motion::Record(g) => self.supports[..i].iter().position(|o| {
                        matches!(&o.motion, Motion::Record(h) if Arc::ptr_eq(g, h))
                            && o.factor == s.factor
                    }),
                    Motion::Harmonic { .. } => None,
                })
                .collect();
        }
        fr.supports.clear();
        for (s, alias) in self.supports.iter().zip(&fr.alias) {
            let val = match *alias {
                Some(j) => fr.supports[j],
                None => s.at(t),
            };
            fr.supports.push(val);
        }
    }

    /// The poses of [`Scene::frame_into`] alone (the support motions are left as they were):
    /// enough for contact kinematics.
    pub fn poses_into(&self, fr: &mut Frame, q: &DVector<f64>, v: &DVector<f64>) {
        let (qs, vs) = (q.as_slice(), v.as_slice());
        fr.poses.clear();
        fr.poses
            .extend(self.bodies.iter().map(|b| pose(b, |k| qs[k], |k| vs[k])));
    }

    /// [`Scene::contact_kinematics`] from precomputed poses.
    pub fn contact_kinematics_in(&self, fr: &Frame, c: &Contact) -> ContactKinematics {
        self.contact_kinematics_of(c, fr.pose(c.point_body), fr.pose(c.face_body))
    }

    fn contact_kinematics_of(
        &self,
        c: &Contact,
        a: &BodyState,
        b: &BodyState,
    ) -> ContactKinematics {
        let mut out = ContactKinematics::placeholder();
        self.contact_kinematics_fill(c, a, b, &mut out);
        out
    }

    /// (g_N, ġ_N, ġ_T) of a contact without its Jacobians (event functions).
    pub fn contact_rates_in(&self, fr: &Frame, c: &Contact) -> (f64, f64, f64) {
        let (a, b) = (fr.pose(c.point_body), fr.pose(c.face_body));
        let rho_a = a.rot(c.point);
        let p = a.position + rho_a;
        let n = b.rot(c.face_normal);
        let t = Vector2::new(n.y, -n.x);
        let o = b.position + b.rot(c.face_point);
        let v_rel =
            a.velocity + a.omega * perp(rho_a) - b.velocity - b.omega * perp(p - b.position);
        (n.dot(&(p - o)), n.dot(&v_rel), t.dot(&v_rel))
    }

    /// [`Scene::contact_kinematics_in`] written into `out`, reusing its Jacobian storage.
    pub fn contact_kinematics_into(&self, fr: &Frame, c: &Contact, out: &mut ContactKinematics) {
        self.contact_kinematics_fill(c, fr.pose(c.point_body), fr.pose(c.face_body), out);
    }

    fn contact_kinematics_fill(
        &self,
        c: &Contact,
        a: &BodyState,
        b: &BodyState,
        out: &mut ContactKinematics,
    ) {
        let n_dof = self.ndof();
        let rho_a = a.rot(c.point);
        let p = a.position + rho_a;
        let n = b.rot(c.face_normal);
        // (t, n) right-handed: t = n rotated by −90° (floor n = +y → t = +x)
        let t = Vector2::new(n.y, -n.x);
        let o = b.position + b.rot(c.face_point);
        let gap = n.dot(&(p - o));
        let arm_b = p - b.position;
        let v_p = a.velocity + a.omega * perp(rho_a);
        let v_bmat = b.velocity + b.omega * perp(arm_b);
        let v_rel = v_p - v_bmat;
        let mut w_n = std::mem::replace(&mut out.w_n, DVector::zeros(0));
        let mut w_t = std::mem::replace(&mut out.w_t, DVector::zeros(0));
        if w_n.len() != n_dof {
            w_n = DVector::zeros(n_dof);
            w_t = DVector::zeros(n_dof);
        } else {
            w_n.as_mut_slice().fill(0.0);
            w_t.as_mut_slice().fill(0.0);
        }
        self.add_point_jacobian(&mut w_n, c.point_body, rho_a, n, 1.0);
        self.add_point_jacobian(&mut w_n, c.face_body, arm_b, n, -1.0);
        self.add_point_jacobian(&mut w_t, c.point_body, rho_a, t, 1.0);
        self.add_point_jacobian(&mut w_t, c.face_body, arm_b, t, -1.0);
        // g̈ = d/dt[n·v_rel]: ṅ = −ω_B t, ṫ = ω_B n; a_P ∋ −ω_A² ρ_A; d/dt v_Bmat ∋ ω_B k×(v_P − v_B).
        let common = -a.omega * a.omega * rho_a - b.omega * perp(v_p - b.velocity);
        let bias_n = -b.omega * t.dot(&v_rel) + n.dot(&common);
        let bias_t = b.omega * n.dot(&v_rel) + t.dot(&common);
        *out = ContactKinematics {
            gap,
            gap_rate: n.dot(&v_rel),
            slip_rate: t.dot(&v_rel),
            w_n,
            w_t,
            bias_n,
            bias_t,
            point: p,
            normal: n,
        };
    }

    /// Deformation e, rate ė and generalized direction J = ∂e/∂q of an attachment.
    pub fn deformation(
        &self,
        att: &Attachment,
        support: Option<usize>,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        jac: &mut DVector<f64>,
    ) -> (f64, f64, f64) {
        let fr = self.frame(t, q, v);
        self.deformation_in(&fr, att, support, jac)
    }

    /// [`Scene::deformation`] from precomputed poses and support motions.
    pub fn deformation_in(
        &self,
        fr: &Frame,
        att: &Attachment,
        support: Option<usize>,
        jac: &mut DVector<f64>,
    ) -> (f64, f64, f64) {
        // the kinematics of [`Scene::deformation_at`], its sparse Jacobian spread over the DOFs
        let (e, ed, vg, sparse, nj) = self.deformation_sparse(fr, att, support);
        jac.fill(0.0);
        for &(k, c) in &sparse[..nj] {
            jac[k] = c;
        }
        (e, ed, vg)
    }

    /// [`Scene::deformation_in`] with the Jacobian as (dof, coefficient) pairs (at most 3),
    /// for the force loop of the right-hand side.
    pub fn deformation_sparse(
        &self,
        fr: &Frame,
        att: &Attachment,
        support: Option<usize>,
    ) -> (f64, f64, f64, [(usize, f64); 3], usize) {
        let body = match att {
            Attachment::Point { body, .. } | Attachment::Rotation { body } => *body,
        };
        let sup = support.map_or((0.0, 0.0, 0.0), |s| fr.supports[s]);
        self.deformation_at(att, &fr.poses[body], sup)
    }

    /// Deformation, rate, support velocity and sparse Jacobian of an attachment from the pose of
    /// its body and the motion (u_g, u̇_g, ü_g) of its support.
    pub fn deformation_at(
        &self,
        att: &Attachment,
        s: &BodyState,
        (ug, vg, _): (f64, f64, f64),
    ) -> (f64, f64, f64, [(usize, f64); 3], usize) {
        let mut jac = [(0usize, 0.0f64); 3];
        let mut nj = 0;
        match att {
            Attachment::Point {
                body,
                point,
                direction,
            } => {
                let rho = s.rot(*point);
                let disp = s.position - self.bodies[*body].reference + rho - point;
                let vel = s.velocity + s.omega * perp(rho);
                let dofs = &self.bodies[*body].dofs;
                for (a, c) in [direction.x, direction.y, direction.dot(&perp(rho))]
                    .into_iter()
                    .enumerate()
                {
                    if let Some(k) = dofs[a] {
                        jac[nj] = (k, c);
                        nj += 1;
                    }
                }
                (
                    direction.dot(&disp) - ug,
                    direction.dot(&vel) - vg,
                    vg,
                    jac,
                    nj,
                )
            }
            Attachment::Rotation { body } => {
                if let Some(k) = self.bodies[*body].dofs[2] {
                    jac[0] = (k, 1.0);
                    nj = 1;
                }
                (s.angle - ug, s.omega - vg, vg, jac, nj)
            }
        }
    }

    /// Pose of body `i` from a state vector y = [q; q̇] with n DOFs.
    pub fn body_state_from(&self, i: usize, y: &DVector<f64>, n: usize) -> BodyState {
        self.pose_of(i, |k| y[k], |k| y[n + k])
    }

    /// Pose of body `i` with DOF values read by `q(k)` and rates by `v(k)`.
    fn pose_of(&self, i: usize, q: impl Fn(usize) -> f64, v: impl Fn(usize) -> f64) -> BodyState {
        pose(&self.bodies[i], q, v)
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

    /// Elastic energy stored in the linear springs.
    pub fn spring_energy(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>) -> f64 {
        let mut jac = DVector::zeros(self.ndof());
        let fr = self.frame(t, q, v);
        self.springs
            .iter()
            .map(|s| {
                let (e, _, _) = self.deformation_in(&fr, &s.attachment, s.support, &mut jac);
                0.5 * s.stiffness * e * e
            })
            .sum()
    }

    pub fn kinetic_energy(&self, v: &DVector<f64>) -> f64 {
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

/// Rates of the energy ledger's integrated terms.
#[derive(Clone, Copy, Debug, Default)]
pub struct PowerTerms {
    /// Work rate of constant loads.
    pub loads: f64,
    /// Power delivered by moving supports.
    pub supports: f64,
    /// Dissipation rate in dashpots and mass-proportional damping.
    pub damping: f64,
    /// Rate of work absorbed by hysteretic elements (stored + dissipated).
    pub hysteretic: f64,
}

/// Number of integrated ledger terms appended to the ODE state (loads, supports, damping,
/// hysteretic, sliding friction).
pub const LEDGER_TERMS: usize = 5;

/// Smooth (non-contact) generalized forces h(t, q, q̇) of eq. 1 (F_D + F_S + loads), and their powers.
pub fn smooth_forces(
    scene: &Scene,
    laws: Option<&[Hysteretic]>,
    t: f64,
    q: &DVector<f64>,
    v: &DVector<f64>,
    h: &mut DVector<f64>,
    jac: &mut DVector<f64>,
) -> PowerTerms {
    let _ = (q, jac);
    let fr = scene.frame(t, q, v);
    smooth_forces_in(scene, laws, &fr, v, h, None)
}

/// [`smooth_forces`] from a precomputed [`Frame`]; `elements` receives (e, ė) of each
/// hysteretic element.
pub fn smooth_forces_in(
    scene: &Scene,
    laws: Option<&[Hysteretic]>,
    fr: &Frame,
    v: &DVector<f64>,
    h: &mut DVector<f64>,
    mut elements: Option<&mut [(f64, f64)]>,
) -> PowerTerms {
    h.copy_from(&scene.loads);
    let mut p = PowerTerms {
        loads: scene.loads.dot(v),
        ..Default::default()
    };
    for s in &scene.springs {
        let (e, ed, vg, jj, nj) = scene.deformation_sparse(fr, &s.attachment, s.support);
        let f = s.stiffness * e + s.damping * ed;
        for &(k, c) in &jj[..nj] {
            h[k] -= f * c;
        }
        p.supports -= f * vg;
        p.damping += s.damping * ed * ed;
    }
    for (j, el) in scene.hysteretic.iter().enumerate() {
        let (e, ed, vg, jj, nj) = scene.deformation_sparse(fr, &el.attachment, el.support);
        if let Some(out) = elements.as_deref_mut() {
            out[j] = (e, ed);
        }
        let fh = laws.map_or(&el.law, |l| &l[j]).force(e);
        let f = fh + el.damping * ed;
        for &(k, c) in &jj[..nj] {
            h[k] -= f * c;
        }
        p.supports -= f * vg;
        p.damping += el.damping * ed * ed;
        p.hysteretic += fh * ed;
    }
    let (damping, supports) = mass_damping(scene, &scene.mass_damping.reference, fr, v, h);
    p.damping += damping;
    p.supports += supports;
    p
}

/// Mass-proportional damping −a₀ M (q̇ − q̇_ref) added to h, with q̇_ref from the (dof,
/// support, factor) terms `reference`; returns its dissipation rate and the support power.
fn mass_damping(
    scene: &Scene,
    reference: &[(usize, usize, f64)],
    fr: &Frame,
    v: &DVector<f64>,
    h: &mut DVector<f64>,
) -> (f64, f64) {
    let alpha = scene.mass_damping.alpha;
    if alpha == 0.0 {
        return (0.0, 0.0);
    }
    let n = h.len();
    let mut stack = [0.0f64; 16];
    let mut heap = Vec::new();
    let vref: &mut [f64] = if n <= 16 {
        &mut stack[..n]
    } else {
        heap.resize(n, 0.0);
        &mut heap
    };
    for &(k, s, f) in reference {
        vref[k] += f * fr.supports[s].1;
    }
    let (mut damping, mut supports) = (0.0, 0.0);
    let (v, h, mass) = (v.as_slice(), h.as_mut_slice(), scene.mass.as_slice());
    for k in 0..n {
        let rel = v[k] - vref[k];
        let f = alpha * mass[k] * rel;
        h[k] -= f;
        damping += f * rel;
        supports -= f * vref[k];
    }
    (damping, supports)
}

/// Pose of `body` with DOF values read by `q(k)` and rates by `v(k)`.
#[inline(always)]
fn pose(body: &Body, q: impl Fn(usize) -> f64, v: impl Fn(usize) -> f64) -> BodyState {
    let [dx, dy, dt] = body.dofs;
    let angle = dt.map_or(0.0, &q);
    BodyState {
        position: body.reference + Vector2::new(dx.map_or(0.0, &q), dy.map_or(0.0, &q)),
        angle,
        velocity: Vector2::new(dx.map_or(0.0, &v), dy.map_or(0.0, &v)),
        omega: dt.map_or(0.0, &v),
        cs: cos_sin(angle),
    }
}

/// (cos a, sin a). For |a| ≤ 0.1 (decks and abutments turn by milliradians) by their Taylor
/// series to a¹² and a¹¹, whose remainders are below 2⁻⁵³ relative there; otherwise libm.
#[inline]
pub fn cos_sin(a: f64) -> (f64, f64) {
    if a == 0.0 {
        return (1.0, 0.0);
    }
    if a.abs() > 0.1 {
        let (s, c) = a.sin_cos();
        return (c, s);
    }
    const S: [f64; 5] = [
        -1.0 / 6.0,
        1.0 / 120.0,
        -1.0 / 5040.0,
        1.0 / 362880.0,
        -1.0 / 39916800.0,
    ];
    const C: [f64; 6] = [
        -1.0 / 2.0,
        1.0 / 24.0,
        -1.0 / 720.0,
        1.0 / 40320.0,
        -1.0 / 3628800.0,
        1.0 / 479001600.0,
    ];
    let x2 = a * a;
    let s = a + a * x2 * (S[0] + x2 * (S[1] + x2 * (S[2] + x2 * (S[3] + x2 * S[4]))));
    let c = 1.0 + x2 * (C[0] + x2 * (C[1] + x2 * (C[2] + x2 * (C[3] + x2 * (C[4] + x2 * C[5])))));
    (c, s)
}

/// Sentinel of a missing DOF or support in [`ForceModel`].
const NONE: usize = usize::MAX;

/// One element of a [`ForceModel`]: e = d·(X − X₀ + R(θ)p − p) − u_g (point) or θ − u_g
/// (rotation), with generalized direction J = ∂e/∂q.
#[derive(Clone, Debug)]
struct FlatElement {
    body: usize,
    rotation: bool,
    point: Vector2<f64>,
    direction: Vector2<f64>,
    /// DOF of x, y, θ of the body (NONE if fixed).
    dofs: [usize; 3],
    support: usize,
    stiffness: f64,
    damping: f64,
    /// Direction along x (1) or y (2) exactly, else 0: half the kinematics suffices.
    axis: u8,
}

impl FlatElement {
    fn new(scene: &Scene, att: &Attachment, support: Option<usize>, k: f64, c: f64) -> Self {
        let (body, rotation, point, direction) = match *att {
            Attachment::Point {
                body,
                point,
                direction,
            } => (body, false, point, direction),
            Attachment::Rotation { body } => (body, true, Vector2::zeros(), Vector2::zeros()),
        };
        Self {
            body,
            rotation,
            point,
            direction,
            dofs: scene.bodies[body].dofs.map(|d| d.unwrap_or(NONE)),
            support: support.unwrap_or(NONE),
            stiffness: k,
            damping: c,
            axis: if direction == Vector2::new(1.0, 0.0) {
                1
            } else if direction == Vector2::new(0.0, 1.0) {
                2
            } else {
                0
            },
        }
    }

    /// Same deformation measure: springs on it add up.
    fn same_as(&self, o: &Self) -> bool {
        self.body == o.body
            && self.rotation == o.rotation
            && self.point == o.point
            && self.direction == o.direction
            && self.support == o.support
    }

    /// (e, ė, u̇_g, J over x, y, θ).
    #[inline(always)]
    fn deformation(&self, fr: &Frame, reference: Vector2<f64>) -> (f64, f64, f64, [f64; 3]) {
        let s = &fr.poses[self.body];
        self.deformation_of(s, s.position - reference, fr)
    }

    /// [`FlatElement::deformation`] from the pose `s` of the element's body and its
    /// displacement `rel` = X − X₀.
    #[inline(always)]
    fn deformation_of(
        &self,
        s: &BodyState,
        rel: Vector2<f64>,
        fr: &Frame,
    ) -> (f64, f64, f64, [f64; 3]) {
        let (ug, vg) = if self.support == NONE {
            (0.0, 0.0)
        } else {
            let (u, v, _) = fr.supports[self.support];
            (u, v)
        };
        if self.rotation {
            return (s.angle - ug, s.omega - vg, vg, [0.0, 0.0, 1.0]);
        }
        let (dx, dy) = (self.direction.x, self.direction.y);
        let (px, py) = (self.point.x, self.point.y);
        let (c, sn) = s.cs;
        // d = x or y: the general expressions below with the zero terms left out
        match self.axis {
            1 => {
                let ry = sn * px + c * py;
                let ux = rel.x + (c * px - sn * py) - px;
                let arm = -ry;
                return (
                    ux - ug,
                    s.velocity.x + s.omega * arm - vg,
                    vg,
                    [1.0, 0.0, arm],
                );
            }
            2 => {
                let rx = c * px - sn * py;
                let uy = rel.y + (sn * px + c * py) - py;
                return (
                    uy - ug,
                    s.velocity.y + s.omega * rx - vg,
                    vg,
                    [0.0, 1.0, rx],
                );
            }
            _ => {}
        }
        let (rx, ry) = (c * px - sn * py, sn * px + c * py);
        let ux = rel.x + rx - px;
        let uy = rel.y + ry - py;
        let arm = dx * -ry + dy * rx; // d·perp(ρ)
        let e = dx * ux + dy * uy - ug;
        let ed = dx * s.velocity.x + dy * s.velocity.y + s.omega * arm - vg;
        (e, ed, vg, [dx, dy, arm])
    }
}

/// Elements `start..end` of springs ++ hysteretic elements, all on `body`.
#[derive(Clone, Debug)]
struct ForceRun {
    body: usize,
    dofs: [usize; 3],
    start: usize,
    end: usize,
}

/// The smooth forces of a scene flattened for repeated evaluation: the same h(t, q, q̇) and
/// power terms as [`smooth_forces_in`], with linear springs of identical attachment and support
/// merged (their stiffnesses and dampings add).
#[derive(Clone, Debug)]
pub struct ForceModel {
    springs: Vec<FlatElement>,
    elements: Vec<FlatElement>,
    references: Vec<Vector2<f64>>,
    /// Consecutive elements (springs, then hysteretic elements) on one body: their forces are
    /// summed before they touch h.
    runs: Vec<ForceRun>,
    /// (dof, support, factor) of q̇_ref with supports that move alike merged.
    mass_reference: Vec<(usize, usize, f64)>,
}

impl ForceModel {
    pub fn new(scene: &Scene) -> Self {
        let mut springs: Vec<FlatElement> = Vec::new();
        for s in &scene.springs {
            let f = FlatElement::new(scene, &s.attachment, s.support, s.stiffness, s.damping);
            match springs.iter_mut().find(|o| o.same_as(&f)) {
                Some(o) => {
                    o.stiffness += f.stiffness;
                    o.damping += f.damping;
                }
                None => springs.push(f),
            }
        }
        let elements = scene
            .hysteretic
            .iter()
            .map(|h| FlatElement::new(scene, &h.attachment, h.support, 0.0, h.damping))
            .collect();
        // supports driven by the same record with the same factor move alike
        let alias: Vec<usize> = scene
            .supports
            .iter()
            .enumerate()
            .map(|(i, s)| match &s.motion {
                Motion::Record(g) => scene.supports[..i]
                    .iter()
                    .position(|o| {
                        matches!(&o.motion, Motion::Record(h) if Arc::ptr_eq(g, h))
                            && o.factor == s.factor
                    })
                    .unwrap_or(i),
                Motion::Harmonic { .. } => i,
            })
            .collect();
        let mut mass_reference: Vec<(usize, usize, f64)> = Vec::new();
        for &(k, s, f) in &scene.mass_damping.reference {
            let root = alias.get(s).copied().unwrap_or(s);
            match mass_reference
                .iter_mut()
                .find(|(k2, s2, _)| *k2 == k && *s2 == root)
            {
                Some(e) => e.2 += f,
                None => mass_reference.push((k, root, f)),
            }
        }
        let mut runs: Vec<ForceRun> = Vec::new();
        for (i, el) in springs.iter().chain(&elements).enumerate() {
            match runs.last_mut() {
                Some(r) if r.body == el.body => r.end = i + 1,
                _ => runs.push(ForceRun {
                    body: el.body,
                    dofs: el.dofs,
                    start: i,
                    end: i + 1,
                }),
            }
        }
        Self {
            springs,
            elements,
            references: scene.bodies.iter().map(|b| b.reference).collect(),
            runs,
            mass_reference,
        }
    }

    /// h(t, q, q̇) into `h` (eq. 1: F_D + F_S + loads) and the ledger's power terms; (e, ė) of
    /// each hysteretic element into `elements`.
    pub fn eval(
        &self,
        scene: &Scene,
        laws: &[Hysteretic],
        fr: &Frame,
        v: &DVector<f64>,
        h: &mut DVector<f64>,
        elements: &mut [(f64, f64)],
    ) -> PowerTerms {
        h.as_mut_slice().copy_from_slice(scene.loads.as_slice());
        let mut p = PowerTerms {
            loads: scene.loads.dot(v),
            ..Default::default()
        };
        let hs = h.as_mut_slice();
        // generalized forces summed per run of elements on one body, in registers, then
        // subtracted from h once per run
        let (mut supports, mut damping, mut hysteretic) = (0.0, 0.0, 0.0);
        let ns = self.springs.len();
        for run in &self.runs {
            let s = &fr.poses[run.body];
            let rel = s.position - self.references[run.body];
            let mut acc = [0.0f64; 3];
            let mut add = |f: f64, jac: [f64; 3]| {
                acc[0] += f * jac[0];
                acc[1] += f * jac[1];
                acc[2] += f * jac[2];
            };
            for sp in &self.springs[run.start.min(ns)..run.end.min(ns)] {
                let (e, ed, vg, jac) = sp.deformation_of(s, rel, fr);
                let f = sp.stiffness * e + sp.damping * ed;
                add(f, jac);
                supports -= f * vg;
                damping += sp.damping * ed * ed;
            }
            let (e0, e1) = (run.start.max(ns) - ns, run.end.max(ns) - ns);
            for ((el, law), out) in self.elements[e0..e1]
                .iter()
                .zip(&laws[e0..e1])
                .zip(&mut elements[e0..e1])
            {
                let (e, ed, vg, jac) = el.deformation_of(s, rel, fr);
                *out = (e, ed);
                let fh = law.force(e);
                let f = fh + el.damping * ed;
                add(f, jac);
                supports -= f * vg;
                damping += el.damping * ed * ed;
                hysteretic += fh * ed;
            }
            for (&k, a) in run.dofs.iter().zip(acc) {
                if let Some(x) = hs.get_mut(k) {
                    *x -= a;
                }
            }
        }
        p.supports += supports;
        p.damping += damping;
        p.hysteretic += hysteretic;
        let (damping, supports) = mass_damping(scene, &self.mass_reference, fr, v, h);
        p.damping += damping;
        p.supports += supports;
        p
    }

    /// (e, ė) of each hysteretic element, as [`ForceModel::eval`] writes them.
    pub fn deformations(&self, fr: &Frame, elements: &mut [(f64, f64)]) {
        for (el, out) in self.elements.iter().zip(elements.iter_mut()) {
            let (e, ed, ..) = el.deformation(fr, self.references[el.body]);
            *out = (e, ed);
        }
    }

    /// Elastic energy of the linear springs, Σ ½ k e².
    pub fn spring_energy(&self, fr: &Frame) -> f64 {
        self.springs
            .iter()
            .map(|s| {
                let e = s.deformation(fr, self.references[s.body]).0;
                0.5 * s.stiffness * e * e
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::cos_sin;

    #[test]
    fn small_angle_cos_sin_matches_libm_to_rounding() {
        let mut worst = 0.0f64;
        for i in -2000..=2000 {
            let a = i as f64 * 0.1 / 2000.0 * (1.0 + 1e-3 * (i % 7) as f64);
            let (c, s) = cos_sin(a);
            let (s0, c0) = a.sin_cos();
            worst = worst.max(((c - c0) / c0).abs()).max(if s0 == 0.0 {
                s.abs()
            } else {
                ((s - s0) / s0).abs()
            });
        }
        assert!(worst < 4.0 * f64::EPSILON, "{worst:e}");
        // outside the series' range: libm
        assert_eq!(cos_sin(0.5), (0.5f64.cos(), 0.5f64.sin()));
    }
}
