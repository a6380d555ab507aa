//! Kinematics of the scene: body poses and support motions ([`Frame`]), exact corner-on-face
//! contact kinematics (g_N, ġ_N, ġ_T, W_N, W_T and the velocity-product terms of eq. 8), and
//! the deformation of force elements. Bodies driven by the ground ([`Body::drive`]) take their
//! pose from the support motions: ġ = Wᵀq̇ + ∂g/∂t, and their accelerations enter ŵ.

use super::{Attachment, Body, BodyRef, Contact, Motion, Scene};
use nalgebra::{DVector, Vector2};
use std::sync::Arc;

/// Kinematics of one contact at (q, q̇): gap, Jacobian rows and the velocity-product terms.
#[derive(Clone, Debug)]
pub struct ContactKinematics {
    /// g_N.
    pub gap: f64,
    /// W_N = ∂g_N/∂q (so ġ_N = W_Nᵀ q̇).
    pub w_n: DVector<f64>,
    /// W_T: ġ_T = W_Tᵀ q̇, along the face tangent t = (n_y, −n_x) ((t, n) right-handed).
    pub w_t: DVector<f64>,
    /// ġ_N.
    pub gap_rate: f64,
    /// ġ_T.
    pub slip_rate: f64,
    /// ŵ_N, ŵ_T: g̈ = Wᵀ q̈ + ŵ.
    pub bias_n: f64,
    /// ŵ_T.
    pub bias_t: f64,
    /// ∂g_N/∂t, ∂g_T/∂t: the parts of ġ_N, ġ_T that bodies driven by the ground make,
    /// n·(v_A − v_B) and t·(v_A − v_B) of the driven ones (ġ = Wᵀq̇ + these).
    pub driven_n: f64,
    /// ∂g_T/∂t.
    pub driven_t: f64,
    /// World position of the contact point (for drawing).
    pub point: Vector2<f64>,
    /// The face's unit normal n, world frame.
    pub normal: Vector2<f64>,
}

impl ContactKinematics {
    /// An open contact whose kinematics were not needed (no allocation).
    pub(crate) fn placeholder() -> Self {
        Self {
            gap: f64::INFINITY,
            w_n: DVector::zeros(0),
            w_t: DVector::zeros(0),
            gap_rate: 0.0,
            slip_rate: 0.0,
            bias_n: 0.0,
            bias_t: 0.0,
            driven_n: 0.0,
            driven_t: 0.0,
            point: Vector2::zeros(),
            normal: Vector2::zeros(),
        }
    }
}

/// k × a for a planar vector a.
#[inline]
pub(crate) fn perp(a: Vector2<f64>) -> Vector2<f64> {
    Vector2::new(-a.y, a.x)
}

/// Pose and velocity of a body (or ground) from q, q̇.
#[derive(Clone, Copy, Debug)]
pub struct BodyState {
    /// The centre's world position.
    pub position: Vector2<f64>,
    /// θ.
    pub angle: f64,
    /// The centre's velocity.
    pub velocity: Vector2<f64>,
    /// θ̇.
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
    /// Per body.
    pub poses: Vec<BodyState>,
    /// The fixed ground's.
    pub ground: BodyState,
    /// (u_g, u̇_g, ü_g) per support.
    pub supports: Vec<(f64, f64, f64)>,
    /// The supports driven by a record and factor no earlier support has (evaluated), each
    /// with the end of its run in `copies`: the later supports driven alike (copied).
    roots: Vec<(usize, usize)>,
    copies: Vec<usize>,
    /// The time of `supports` (they are not evaluated again at the same t).
    supports_at: Option<f64>,
    /// The bodies driven by the ground (listed on first use, `driven_known`).
    driven: Vec<usize>,
    driven_known: bool,
    /// Per body, (velocity, acceleration) of a driven body's centre, zero for the others;
    /// empty when no body is driven.
    drive: Vec<(Vector2<f64>, Vector2<f64>)>,
}

impl Frame {
    /// The pose of `b` (the ground's for [`BodyRef::Ground`]).
    #[inline]
    pub fn pose(&self, b: BodyRef) -> &BodyState {
        match b {
            BodyRef::Ground => &self.ground,
            BodyRef::Body(i) => &self.poses[i],
        }
    }

    /// (velocity, acceleration) of body `b` prescribed by the ground: a driven body's, else 0.
    #[inline]
    pub fn drive(&self, b: BodyRef) -> (Vector2<f64>, Vector2<f64>) {
        match b {
            BodyRef::Body(i) => self.drive.get(i).copied(),
            BodyRef::Ground => None,
        }
        .unwrap_or((Vector2::zeros(), Vector2::zeros()))
    }
}

impl Scene {
    /// Poses of the driven bodies from their supports' (u_g, u̇_g, ü_g), read by `motion`.
    #[inline(always)]
    fn drive_poses(&self, fr: &mut Frame, motion: impl Fn(&Frame, usize) -> (f64, f64, f64)) {
        if !(fr.driven_known && fr.driven.is_empty()) {
            self.drive_poses_listed(fr, motion);
        }
    }

    /// [`Scene::drive_poses`] once the scene is known to have driven bodies (or not yet known).
    #[inline(never)]
    fn drive_poses_listed(
        &self,
        fr: &mut Frame,
        motion: impl Fn(&Frame, usize) -> (f64, f64, f64),
    ) {
        if !fr.driven_known {
            fr.driven = (self.bodies.iter().enumerate())
                .filter(|(_, b)| b.is_driven())
                .map(|(i, _)| i)
                .collect();
            fr.driven_known = true;
        }
        if fr.driven.is_empty() {
            return;
        }
        let zero = (Vector2::zeros(), Vector2::zeros());
        fr.drive.clear();
        fr.drive.resize(self.bodies.len(), zero);
        for k in 0..fr.driven.len() {
            let i = fr.driven[k];
            let b = &self.bodies[i];
            let m = b.drive.map(|s| s.map(|s| motion(fr, s)));
            fr.drive[i] = drive_axes(b, &mut fr.poses[i], m);
        }
    }

    /// Velocity of body `b` prescribed by the ground at t: a driven body's centre velocity,
    /// else 0.
    pub(crate) fn driven_velocity(&self, b: BodyRef, t: f64) -> Vector2<f64> {
        match b {
            BodyRef::Body(i) if self.bodies[i].is_driven() => {
                let rate = |s: Option<usize>| s.map_or(0.0, |s| self.supports[s].at(t).1);
                let [x, y] = self.bodies[i].drive.map(rate);
                Vector2::new(x, y)
            }
            _ => Vector2::zeros(),
        }
    }

    /// Adds `coef·(∂ (point velocity)/∂q̇)ᵀ d` to a Jacobian row for d = n and d = t (rows W_N
    /// and W_T): the generalized directions of forces along n and t applied at world arm ρ from
    /// the centre of body b.
    #[inline(always)]
    fn add_point_jacobians(
        &self,
        (w_n, w_t): (&mut [f64], &mut [f64]),
        b: BodyRef,
        arm: Vector2<f64>,
        (n, t): (Vector2<f64>, Vector2<f64>),
        coef: f64,
    ) {
        if let BodyRef::Body(i) = b {
            let dofs = &self.bodies[i].dofs;
            if let Some(k) = dofs[0] {
                w_n[k] += coef * n.x;
                w_t[k] += coef * t.x;
            }
            if let Some(k) = dofs[1] {
                w_n[k] += coef * n.y;
                w_t[k] += coef * t.y;
            }
            if let Some(k) = dofs[2] {
                w_n[k] += coef * n.dot(&perp(arm));
                w_t[k] += coef * t.dot(&perp(arm));
            }
        }
    }

    /// Poses of all bodies and support motions at (t, q, q̇).
    pub fn frame(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>) -> Frame {
        let mut fr = Frame::default();
        self.frame_into(&mut fr, t, q, v);
        fr
    }

    /// [`Scene::frame`] written into `fr`, reusing its storage: the support motions first, then
    /// the poses (driven bodies from the supports).
    pub(crate) fn frame_into(&self, fr: &mut Frame, t: f64, q: &DVector<f64>, v: &DVector<f64>) {
        self.frame_of(fr, t, q.as_slice(), v.as_slice());
    }

    /// [`Scene::frame_into`] from q and q̇ as slices.
    pub(crate) fn frame_of(&self, fr: &mut Frame, t: f64, q: &[f64], v: &[f64]) {
        let n = self.supports.len();
        if fr.roots.len() + fr.copies.len() != n {
            let alias: Vec<Option<usize>> = (self.supports.iter().enumerate())
                .map(|(i, s)| match &s.motion {
                    Motion::Record(g) => self.supports[..i].iter().position(|o| {
                        matches!(&o.motion, Motion::Record(h) if Arc::ptr_eq(g, h))
                            && o.factor == s.factor
                    }),
                    Motion::Harmonic { .. } => None,
                })
                .collect();
            fr.roots.clear();
            fr.copies.clear();
            for r in (0..n).filter(|&r| alias[r].is_none()) {
                fr.copies.extend((0..n).filter(|&i| alias[i] == Some(r)));
                fr.roots.push((r, fr.copies.len()));
            }
            fr.supports_at = None;
        }
        if fr.supports_at != Some(t) || fr.supports.len() != n {
            fr.supports.resize(n, (0.0, 0.0, 0.0));
            let mut start = 0;
            for &(r, end) in &fr.roots {
                let val = self.supports[r].at(t);
                fr.supports[r] = val;
                for &i in &fr.copies[start..end] {
                    fr.supports[i] = val;
                }
                start = end;
            }
            fr.supports_at = Some(t);
        }
        self.dof_poses(fr, q, v);
        self.drive_poses(fr, |fr, s| fr.supports[s]);
    }

    /// The poses of [`Scene::frame_into`] at t alone (the support motions are left as they
    /// were; a driven body's supports are evaluated for it): enough for contact kinematics.
    pub(crate) fn poses_into(&self, fr: &mut Frame, t: f64, q: &DVector<f64>, v: &DVector<f64>) {
        self.dof_poses(fr, q.as_slice(), v.as_slice());
        self.drive_poses(fr, |_, s| self.supports[s].at(t));
    }

    /// The poses from the DOFs (a body without DOFs at its reference).
    fn dof_poses(&self, fr: &mut Frame, qs: &[f64], vs: &[f64]) {
        if fr.poses.len() != self.bodies.len() {
            fr.poses.resize(self.bodies.len(), BodyState::default());
        }
        for (p, b) in fr.poses.iter_mut().zip(&self.bodies) {
            *p = match b.dofs {
                // a deck (x, y, θ) and an abutment (x, θ) without the Option per coordinate
                [Some(x), Some(y), Some(r)] => {
                    planar_pose(b, [qs[x], qs[y], qs[r]], [vs[x], vs[y], vs[r]])
                }
                [Some(x), None, Some(r)] => {
                    planar_pose(b, [qs[x], 0.0, qs[r]], [vs[x], 0.0, vs[r]])
                }
                _ => pose(b, |k| qs[k], |k| vs[k]),
            };
        }
    }

    /// Exact planar kinematics of contact `c` (no small-rotation linearisation):
    /// g_N = n·(P − O), n = R(θ_B) n₀, P = X_A + R(θ_A) r_A, O = X_B + R(θ_B) p_B; W_N, W_T and
    /// the velocity-product terms of g̈ = Wᵀq̈ + ŵ, at the poses of `fr`.
    pub fn contact_kinematics(&self, fr: &Frame, c: &Contact) -> ContactKinematics {
        let mut out = ContactKinematics::placeholder();
        self.contact_kinematics_into(fr, c, &mut out);
        out
    }

    /// (g_N, ġ_N, ġ_T) of a contact without its Jacobians (event functions).
    pub(crate) fn contact_rates(&self, fr: &Frame, c: &Contact) -> (f64, f64, f64) {
        self.contact_rates_between(fr.pose(c.point_body), fr.pose(c.face_body), c)
    }

    /// [`Scene::contact_kinematics`] written into `out`, reusing its Jacobian storage. A body
    /// driven by the ground adds its velocity to ∂g/∂t and its acceleration a to ŵ:
    /// ŵ_N ∋ n·(a_A − a_B), ŵ_T ∋ t·(a_A − a_B).
    pub(crate) fn contact_kinematics_into(
        &self,
        fr: &Frame,
        c: &Contact,
        out: &mut ContactKinematics,
    ) {
        self.contact_kinematics_fill(c, fr.pose(c.point_body), fr.pose(c.face_body), out);
        if !fr.drive.is_empty() {
            let ((va, aa), (vb, ab)) = (fr.drive(c.point_body), fr.drive(c.face_body));
            let n = out.normal;
            let t = Vector2::new(n.y, -n.x);
            out.driven_n = n.dot(&(va - vb));
            out.driven_t = t.dot(&(va - vb));
            out.bias_n += n.dot(&(aa - ab));
            out.bias_t += t.dot(&(aa - ab));
        }
    }

    fn contact_kinematics_fill(
        &self,
        c: &Contact,
        a: &BodyState,
        b: &BodyState,
        out: &mut ContactKinematics,
    ) {
        let n_dof = self.ndof();
        // the rows zeroed first: no value is live across the fills
        if out.w_n.len() != n_dof {
            out.w_n = DVector::zeros(n_dof);
        } else {
            out.w_n.as_mut_slice().fill(0.0);
        }
        if out.w_t.len() != n_dof {
            out.w_t = DVector::zeros(n_dof);
        } else {
            out.w_t.as_mut_slice().fill(0.0);
        }
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
        let rows = (out.w_n.as_mut_slice(), out.w_t.as_mut_slice());
        self.add_point_jacobians(rows, c.point_body, rho_a, (n, t), 1.0);
        let rows = (out.w_n.as_mut_slice(), out.w_t.as_mut_slice());
        self.add_point_jacobians(rows, c.face_body, arm_b, (n, t), -1.0);
        // g̈ = d/dt[n·v_rel]: ṅ = −ω_B t, ṫ = ω_B n; a_P ∋ −ω_A² ρ_A; d/dt v_Bmat ∋ ω_B k×(v_P − v_B).
        let common = -a.omega * a.omega * rho_a - b.omega * perp(v_p - b.velocity);
        out.gap = gap;
        out.gap_rate = n.dot(&v_rel);
        out.slip_rate = t.dot(&v_rel);
        out.bias_n = -b.omega * t.dot(&v_rel) + n.dot(&common);
        out.bias_t = b.omega * n.dot(&v_rel) + t.dot(&common);
        out.driven_n = 0.0;
        out.driven_t = 0.0;
        out.point = p;
        out.normal = n;
    }

    /// Deformation e, rate ė, the rate u̇ with ė = J q̇ − u̇ (the support velocity u̇_g, less
    /// what bodies driven by the ground add) and the Jacobian J = ∂e/∂q as (dof, coefficient)
    /// pairs (the first `nj` of at most 6) of an attachment, at the poses and support motions
    /// of `fr` ([`spread`] makes J a dense row).
    pub fn deformation(&self, fr: &Frame, att: &Attachment, support: Option<usize>) -> Deformation {
        let (a, b) = att.bodies();
        let sup = support.map_or((0.0, 0.0, 0.0), |s| fr.supports[s]);
        self.deformation_at(att, &fr.poses[a], &fr.poses[b.unwrap_or(a)], sup)
    }

    /// (e, ė) of [`Scene::deformation`] alone (event functions: no Jacobian).
    pub fn deformation_rates(
        &self,
        fr: &Frame,
        att: &Attachment,
        support: Option<usize>,
    ) -> (f64, f64) {
        let (a, b) = att.bodies();
        let sup = support.map_or((0.0, 0.0, 0.0), |s| fr.supports[s]);
        self.deformation_value(att, &fr.poses[a], &fr.poses[b.unwrap_or(a)], sup)
    }

    /// ë of an attachment at the poses and support motions of `fr`, with q̈ = `qdd`: d·P̈ − ü_g,
    /// P̈ = a_c + α ρ⊥ − ω² ρ (ρ = R(θ) p; an axis without a DOF has the ground's a_c if
    /// driven, else 0); θ̈ − ü_g for a rotation.
    pub fn deformation_acceleration(
        &self,
        fr: &Frame,
        att: &Attachment,
        support: Option<usize>,
        qdd: &[f64],
    ) -> f64 {
        let ag = support.map_or(0.0, |s| fr.supports[s].2);
        match *att {
            Attachment::Point {
                body,
                point,
                direction: d,
            } => d.dot(&self.point_acceleration(fr, body, point, qdd)) - ag,
            Attachment::Rotation { body } => self.bodies[body].dofs[2].map_or(0.0, |k| qdd[k]) - ag,
            Attachment::Relative {
                body,
                point,
                other,
                other_point,
                direction: d,
            } => {
                let pa = self.point_acceleration(fr, body, point, qdd);
                let pb = self.point_acceleration(fr, other, other_point, qdd);
                d.dot(&(pa - pb)) - ag
            }
        }
    }

    /// P̈ of a body point (see [`Scene::deformation_acceleration`]).
    fn point_acceleration(
        &self,
        fr: &Frame,
        body: usize,
        point: Vector2<f64>,
        qdd: &[f64],
    ) -> Vector2<f64> {
        let (b, s) = (&self.bodies[body], &fr.poses[body]);
        let ground = fr.drive.get(body).map_or(Vector2::zeros(), |d| d.1);
        let axis = |k: usize, g: f64| b.dofs[k].map_or(g, |k| qdd[k]);
        let alpha = axis(2, 0.0);
        let rho = s.rot(point);
        Vector2::new(axis(0, ground.x), axis(1, ground.y)) + alpha * perp(rho)
            - s.omega * s.omega * rho
    }

    /// [`Scene::deformation`] from the pose `s` of the element's body, the pose `o` of the
    /// other body of a two-body element (ignored otherwise) and the motion (u_g, u̇_g, ü_g) of
    /// its support.
    pub(crate) fn deformation_at(
        &self,
        att: &Attachment,
        s: &BodyState,
        o: &BodyState,
        (ug, vg, _): (f64, f64, f64),
    ) -> Deformation {
        let mut jac = [(0usize, 0.0f64); 6];
        let mut nj = 0;
        match *att {
            Attachment::Point {
                body,
                point,
                direction: d,
            } => {
                let (disp, vel) = self.point_motion(body, point, s);
                let row = [d.x, d.y, d.dot(&perp(s.rot(point)))];
                push_jacobian(&self.bodies[body], row, &mut jac, &mut nj);
                let driven = self.driven_rate(body, d, vel);
                (d.dot(&disp) - ug, d.dot(&vel) - vg, vg - driven, jac, nj)
            }
            Attachment::Rotation { body } => {
                if let Some(k) = self.bodies[body].dofs[2] {
                    jac[0] = (k, 1.0);
                    nj = 1;
                }
                (s.angle - ug, s.omega - vg, vg, jac, nj)
            }
            Attachment::Relative {
                body,
                point,
                other,
                other_point,
                direction: d,
            } => {
                let (disp_a, vel_a) = self.point_motion(body, point, s);
                let (disp_b, vel_b) = self.point_motion(other, other_point, o);
                let row_a = [d.x, d.y, d.dot(&perp(s.rot(point)))];
                let row_b = [-d.x, -d.y, -d.dot(&perp(o.rot(other_point)))];
                push_jacobian(&self.bodies[body], row_a, &mut jac, &mut nj);
                push_jacobian(&self.bodies[other], row_b, &mut jac, &mut nj);
                let driven = self.driven_rate(body, d, vel_a) - self.driven_rate(other, d, vel_b);
                let ed = d.dot(&(vel_a - vel_b)) - vg;
                (d.dot(&(disp_a - disp_b)) - ug, ed, vg - driven, jac, nj)
            }
        }
    }

    /// (e, ė) of [`Scene::deformation_at`] alone (event functions: no Jacobian).
    pub fn deformation_value(
        &self,
        att: &Attachment,
        s: &BodyState,
        o: &BodyState,
        (ug, vg, _): (f64, f64, f64),
    ) -> (f64, f64) {
        match *att {
            Attachment::Point {
                body,
                point,
                direction: d,
            } => {
                let (disp, vel) = self.point_motion(body, point, s);
                (d.dot(&disp) - ug, d.dot(&vel) - vg)
            }
            Attachment::Rotation { .. } => (s.angle - ug, s.omega - vg),
            Attachment::Relative {
                body,
                point,
                other,
                other_point,
                direction: d,
            } => {
                let (disp_a, vel_a) = self.point_motion(body, point, s);
                let (disp_b, vel_b) = self.point_motion(other, other_point, o);
                (d.dot(&(disp_a - disp_b)) - ug, d.dot(&(vel_a - vel_b)) - vg)
            }
        }
    }

    /// Displacement P(q) − P(0) and velocity of the point `point` of body `body` at pose `s`.
    fn point_motion(
        &self,
        body: usize,
        point: Vector2<f64>,
        s: &BodyState,
    ) -> (Vector2<f64>, Vector2<f64>) {
        let rho = s.rot(point);
        let disp = s.position - self.bodies[body].reference + rho - point;
        (disp, s.velocity + s.omega * perp(rho))
    }

    /// d·v of a point of a body without DOFs (its velocity is the ground's), else 0.
    fn driven_rate(&self, body: usize, d: Vector2<f64>, vel: Vector2<f64>) -> f64 {
        if self.bodies[body].has_no_dofs() {
            d.dot(&vel)
        } else {
            0.0
        }
    }

    /// Pose of body `i` at t from a state vector y = [q; q̇] with n DOFs (a driven body's from
    /// its supports).
    pub fn body_state_at(&self, i: usize, t: f64, y: &DVector<f64>, n: usize) -> BodyState {
        self.body_state_with(i, t, |k| y[k], |k| y[n + k])
    }

    /// [`Scene::body_state_at`] with DOF values read by `q(k)` and rates by `v(k)`.
    #[inline]
    pub(crate) fn body_state_with(
        &self,
        i: usize,
        t: f64,
        q: impl Fn(usize) -> f64,
        v: impl Fn(usize) -> f64,
    ) -> BodyState {
        let b = &self.bodies[i];
        let mut s = pose(b, q, v);
        drive_axes(
            b,
            &mut s,
            b.drive.map(|d| d.map(|d| self.supports[d].at(t))),
        );
        s
    }

    /// [`Scene::contact_rates`] from the poses `a` of the point body and `b` of the face body.
    #[inline]
    pub(crate) fn contact_rates_between(
        &self,
        a: &BodyState,
        b: &BodyState,
        c: &Contact,
    ) -> (f64, f64, f64) {
        let rho_a = a.rot(c.point);
        let p = a.position + rho_a;
        let n = b.rot(c.face_normal);
        let t = Vector2::new(n.y, -n.x);
        let o = b.position + b.rot(c.face_point);
        let v_rel =
            a.velocity + a.omega * perp(rho_a) - b.velocity - b.omega * perp(p - b.position);
        (n.dot(&(p - o)), n.dot(&v_rel), t.dot(&v_rel))
    }
}

/// The driven axes of body `b` in its pose `p`: a driven axis has no DOF, so its position and
/// velocity are the ground's (u, u̇, ü per axis in `m`); the others (a body with DOFs driven
/// in y only) keep the DOFs' pose. Returns the driven part of the velocity and acceleration.
fn drive_axes(
    b: &Body,
    p: &mut BodyState,
    m: [Option<(f64, f64, f64)>; 2],
) -> (Vector2<f64>, Vector2<f64>) {
    let (mut v, mut a) = (Vector2::zeros(), Vector2::zeros());
    for (axis, motion) in m.into_iter().enumerate() {
        if let Some((u, ud, udd)) = motion {
            p.position[axis] = b.reference[axis] + u;
            p.velocity[axis] = ud;
            (v[axis], a[axis]) = (ud, udd);
        }
    }
    (v, a)
}

/// (e, ė, u̇, sparse J, its length) of [`Scene::deformation`].
pub type Deformation = (f64, f64, f64, [(usize, f64); 6], usize);

/// Appends the entries of `row` (∂e/∂x, ∂e/∂y, ∂e/∂θ of a body point) on the body's DOFs.
fn push_jacobian(body: &Body, row: [f64; 3], jac: &mut [(usize, f64); 6], nj: &mut usize) {
    for (a, c) in row.into_iter().enumerate() {
        if let Some(k) = body.dofs[a] {
            jac[*nj] = (k, c);
            *nj += 1;
        }
    }
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

/// [`pose`] of a body with DOF values `q` and rates `v` (0 on a fixed axis).
#[inline(always)]
fn planar_pose(body: &Body, [x, y, angle]: [f64; 3], [vx, vy, omega]: [f64; 3]) -> BodyState {
    BodyState {
        position: body.reference + Vector2::new(x, y),
        angle,
        velocity: Vector2::new(vx, vy),
        omega,
        cs: cos_sin(angle),
    }
}

/// (cos a, sin a). For |a| ≤ 0.1 (decks and abutments turn by milliradians) by their Taylor
/// series to a¹² and a¹¹, whose remainders are below 2⁻⁵³ relative there; otherwise libm.
#[inline]
pub(crate) fn cos_sin(a: f64) -> (f64, f64) {
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

/// A sparse Jacobian row of [`Scene::deformation`] written into the dense row `jac`.
pub fn spread(sparse: &[(usize, f64)], jac: &mut DVector<f64>) {
    jac.fill(0.0);
    for &(k, c) in sparse {
        jac[k] = c;
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
