//! Newmark average acceleration (β = ¼, γ = ½) for the penalty model:
//! a₁ = 4/h² (q₁ − q₀ − h v₀) − a₀, v₁ = v₀ + h/2 (a₀ + a₁), solved for q₁ by Newton.

use super::Stepper;
use super::gap_elements::{GapElements, PenaltyForces};
use nalgebra::{DMatrix, DVector, Dyn, LU};

/// (q₁, v₁, a₁, contact forces) at the end of a step.
pub(super) type StepState = (DVector<f64>, DVector<f64>, DVector<f64>, PenaltyForces);

/// Residual a₁ − M⁻¹ f(q₁, v₁), with a₁ and v₁ from the Newmark relations and the contact forces.
type Residual = (DVector<f64>, DVector<f64>, DVector<f64>, PenaltyForces);

/// One step from (t₀, q₀, v₀, a₀) with the tangential springs `slip0`.
struct Step<'a> {
    s: &'a Stepper<'a>,
    gaps: &'a GapElements,
    t1: f64,
    h: f64,
    q: &'a DVector<f64>,
    v: &'a DVector<f64>,
    a_k: &'a DVector<f64>,
    slip0: &'a [f64],
    /// ġ_T of each contact at the start of the step.
    slip_rate0: Vec<f64>,
}

impl Step<'_> {
    /// The residual at q₁ within the active set `mask`; Δs = h/2 (ġ_T₀ + ġ_T₁).
    fn residual(&self, q1: &DVector<f64>, mask: &[bool]) -> Residual {
        let (scene, h) = (self.s.scene, self.h);
        let a1 = (q1 - self.q - self.v * h) * (4.0 / (h * h)) - self.a_k;
        let v1 = self.v + (self.a_k + &a1) * (0.5 * h);
        let fr1 = scene.frame(self.t1, q1, &v1);
        let dslip: Vec<f64> = (scene.contacts.iter().enumerate())
            .map(|(i, c)| {
                0.5 * h * (self.slip_rate0[i] + scene.contact_kinematics(&fr1, c).slip_rate)
            })
            .collect();
        let (acc, _, pf) =
            (self.gaps).accel(self.s, self.t1, q1, &v1, self.slip0, &dslip, Some(mask));
        (a1.clone() - acc, a1, v1, pf)
    }

    /// LU of the finite-difference Jacobian ∂r/∂q₁.
    fn jacobian(&self, q1: &DVector<f64>, r: &DVector<f64>, mask: &[bool]) -> LU<f64, Dyn, Dyn> {
        let n = q1.len();
        let mut jm = DMatrix::zeros(n, n);
        for j in 0..n {
            let d = 1e-7 * (1.0 + q1[j].abs());
            let mut qp = q1.clone();
            qp[j] += d;
            let (rp, ..) = self.residual(&qp, mask);
            for i in 0..n {
                jm[(i, j)] = (rp[i] - r[i]) / d;
            }
        }
        jm.lu()
    }

    /// Newton on q₁ within a fixed active set, the Jacobian renewed every 4 iterations;
    /// (a₁, v₁, forces) when converged.
    fn newton(
        &self,
        q1: &mut DVector<f64>,
        mask: &[bool],
    ) -> Option<(DVector<f64>, DVector<f64>, PenaltyForces)> {
        let (mut r, mut a1, mut v1, mut pf) = self.residual(q1, mask);
        let mut lu = self.jacobian(q1, &r, mask);
        for it in 0..30 {
            if r.amax() <= 1e-10 * (1.0 + a1.amax()) {
                return Some((a1, v1, pf));
            }
            if it > 0 && it % 4 == 0 {
                lu = self.jacobian(q1, &r, mask);
            }
            let dq = lu.solve(&r)?;
            *q1 -= &dq;
            (r, a1, v1, pf) = self.residual(q1, mask);
            if !r.iter().all(|x| x.is_finite()) {
                return None;
            }
            // the update is at round-off and the residual at round-off of the 4/h² scaling
            if dq.amax() <= 1e-13 * (1.0 + q1.amax()) && r.amax() <= 1e-6 * (1.0 + a1.amax()) {
                return Some((a1, v1, pf));
            }
        }
        None
    }

    /// The consistent active set at (q₁, v₁): penetrating and compressed, −k g_N − c ġ_N > 0.
    fn natural_set(&self, q1: &DVector<f64>, v1: &DVector<f64>) -> Vec<bool> {
        let scene = self.s.scene;
        let fr = scene.frame(self.t1, q1, v1);
        let (k, cd) = (self.gaps.k, &self.gaps.dashpots);
        (scene.contacts.iter().enumerate())
            .map(|(i, c)| {
                let kin = scene.contact_kinematics(&fr, c);
                kin.gap < 0.0 && -k * kin.gap - cd[i].0 * kin.gap_rate > 0.0
            })
            .collect()
    }
}

/// One Newmark average-acceleration step of the penalty model: Newton on q₁ with a
/// finite-difference tangent within a fixed active set of gap elements, the set then corrected
/// until consistent (compressed in, tensile out). None when it does not converge.
#[allow(clippy::too_many_arguments)]
pub(super) fn newmark_step(
    s: &Stepper,
    gaps: &GapElements,
    t0: f64,
    h: f64,
    q: &DVector<f64>,
    v: &DVector<f64>,
    a_k: &DVector<f64>,
    slip0: &[f64],
) -> Option<StepState> {
    let scene = s.scene;
    let fr0 = scene.frame(t0, q, v);
    let step = Step {
        s,
        gaps,
        t1: t0 + h,
        h,
        q,
        v,
        a_k,
        slip0,
        slip_rate0: (scene.contacts.iter())
            .map(|c| scene.contact_kinematics(&fr0, c).slip_rate)
            .collect(),
    };
    let mut q1 = q + v * h + a_k * (0.5 * h * h);
    let fr = scene.frame(step.t1, &q1, v);
    let mut mask: Vec<bool> = (scene.contacts.iter())
        .map(|c| scene.contact_kinematics(&fr, c).gap < 0.0)
        .collect();
    for _set in 0..8 {
        let (a1, v1, pf) = step.newton(&mut q1, &mask)?;
        let natural = step.natural_set(&q1, &v1);
        if natural == mask {
            return Some((q1, v1, a1, pf));
        }
        mask = natural;
    }
    // the set cycles on the element's jump (c|ġ_N| at g_N = 0): take the last converged state
    let (_, a1, v1, pf) = step.residual(&q1, &mask);
    Some((q1, v1, a1, pf))
}
