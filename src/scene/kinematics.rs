//! Kinematics of the scene: body poses and support motions ([`Frame`]), exact corner-on-face
//! contact kinematics (g_N, ġ_N, ġ_T, W_N, W_T and the velocity-product terms of eq. 8), and
//! the deformation of force elements.

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
    fn body_state(&self, b: BodyRef, q: &DVector<f64>, v: &DVector<f64>) -> BodyState {
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

    /// Exact planar kinematics of contact `c` (no small-rotation linearisation):
    /// g_N = n·(P − O), n = R(θ_B) n₀, P = X_A + R(θ_A) r_A, O = X_B + R(θ_B) p_B; W_N, W_T and
    /// the velocity-product terms of g̈ = Wᵀq̈ + ŵ, at the poses of `fr`.
    pub fn contact_kinematics(&self, fr: &Frame, c: &Contact) -> ContactKinematics {
        let mut out = ContactKinematics::placeholder();
        self.contact_kinematics_into(fr, c, &mut out);
        out
    }

    /// (g_N, ġ_N, ġ_T) of a contact without its Jacobians (event functions).
    pub fn contact_rates(&self, fr: &Frame, c: &Contact) -> (f64, f64, f64) {
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

    /// [`Scene::contact_kinematics`] written into `out`, reusing its Jacobian storage.
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

    /// Deformation e, rate ė, support velocity u̇_g and the Jacobian J = ∂e/∂q as (dof,
    /// coefficient) pairs (the first `nj` of at most 3) of an attachment, at the poses and
    /// support motions of `fr` ([`spread`] makes J a dense row).
    pub fn deformation(
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
