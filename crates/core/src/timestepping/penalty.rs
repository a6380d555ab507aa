//! Penalty / compliance (gap elements, as OpenSees users build them): a compression-only spring
//! k and dashpot c per contact (c from a target restitution), Coulomb friction as an elastic
//! stick–slip spring; integrated by Newmark average acceleration (implicit, [`super::newmark`])
//! or by the explicit central-difference scheme (stable for h < 2/ω).

use super::gap_elements::{GapElements, PenaltyForces};
use super::newmark::{StepState, newmark_step};
use super::{Stepper, number_of_steps};
use crate::methods::Method;
use crate::output::ContactState;
use crate::run::{Batcher, Observer, Run, SolverError};
use crate::scene::Scene;
use nalgebra::DVector;
use std::time::Instant;

/// Penalty method: explicit central difference (`explicit`) or Newmark average acceleration.
/// Runs stop with [`SolverError::Unstable`] when the energy grows without a source; what was
/// computed before a cancel or a failure is kept.
pub(crate) fn integrate_penalty(scene: &Scene, explicit: bool, observer: &mut dyn Observer) -> Run {
    let wall = Instant::now();
    let mut s = Stepper::new(scene);
    let mut contact_elastic = 0.0;
    let result = penalty_steps(&mut s, explicit, observer, &mut contact_elastic);
    let complete = result.is_ok();
    Run::new(s.finish(wall, contact_elastic, complete), result)
}

/// The penalty steps from t = 0 to t_end; `contact_elastic` ends as the gap elements' energy.
fn penalty_steps(
    s: &mut Stepper,
    explicit: bool,
    observer: &mut dyn Observer,
    contact_elastic: &mut f64,
) -> Result<(), SolverError> {
    let scene = s.scene;
    let steps = number_of_steps(scene)?;
    if !s.e0.is_finite() {
        return Err(SolverError::NonFinite { t: 0.0 });
    }
    let h = scene.settings.t_end / steps as f64;
    let gaps = GapElements::new(scene, scene.settings.contact_stiffness);
    let zero = vec![0.0; scene.contacts.len()];
    let (q0, v0, slip0) = (s.q.clone(), s.v.clone(), s.slip_spring.clone());
    let (mut a_k, p0, pf0) = gaps.accel(s, 0.0, &q0, &v0, &slip0, &zero, None);
    s.prev_power = p0;
    *contact_elastic = pf0.elastic;
    s.maybe_sample(*contact_elastic);
    let mut batcher = Batcher::new();
    // explicit: velocity at the half step
    let mut v_half = &s.v - &a_k * (0.5 * h);
    let mut guard = EnergyGuard::new(s, explicit, h);
    let (mut prev_absorbed, mut prev_driven) = (pf0.absorbed, pf0.driven);
    for k in 0..steps {
        let t1 = (k + 1) as f64 * h;
        let before = s.state.clone();
        let (q1, v1, a1, pf) = if explicit {
            let (vh, step) = central_difference_step(s, &gaps, &v_half, &a_k, h, t1);
            v_half = vh;
            step
        } else {
            newmark_with_substeps(s, &gaps, &a_k, h)?
        };
        if !q1.iter().chain(v1.iter()).all(|x| x.is_finite()) {
            return Err(SolverError::NonFinite { t: t1 });
        }
        s.q = q1;
        s.v = v1;
        a_k = a1;
        s.t = t1;
        s.commit_laws(h);
        let mut f = DVector::zeros(scene.ndof());
        let (qq, vv) = (s.q.clone(), s.v.clone());
        let p = s.forces_trial(t1, &qq, &vv, &mut f);
        s.add_power(p, h);
        s.ledger[1] += 0.5 * h * (prev_driven + pf.driven);
        s.ledger[4] += 0.5 * h * (prev_absorbed + pf.absorbed);
        (prev_absorbed, prev_driven) = (pf.absorbed, pf.driven);
        *contact_elastic = pf.elastic;
        set_contact_states(s, &pf);
        s.out.stats.steps_accepted += 1;
        s.out.stats.rhs_evals += 1;
        guard.check(s, *contact_elastic, k)?;
        s.log_transitions(&before, None);
        s.maybe_sample(*contact_elastic);
        batcher.maybe(&s.out, s.t, observer)?;
    }
    batcher.flush(&s.out, s.t, observer);
    Ok(())
}

/// Central difference: v_{k+½} = v_{k−½} + h a_k, q_{k+1} = q_k + h v_{k+½},
/// v_{k+1} = v_{k+½} + h/2 a_{k+1}; the tangential increment from v_{k+½} at t_k + h/2.
/// Returns v_{k+½} and the end of the step at `t1`.
fn central_difference_step(
    s: &Stepper,
    gaps: &GapElements,
    v_half: &DVector<f64>,
    a_k: &DVector<f64>,
    h: f64,
    t1: f64,
) -> (DVector<f64>, StepState) {
    let scene = s.scene;
    let vh = v_half + a_k * h;
    let q1 = &s.q + &vh * h;
    let fr_mid = scene.frame(s.t + 0.5 * h, &(&s.q + &vh * (0.5 * h)), &vh);
    let dslip: Vec<f64> = (scene.contacts.iter())
        .map(|c| scene.contact_kinematics(&fr_mid, c).slip_rate * h)
        .collect();
    let (a1, _, pf) = gaps.accel(s, t1, &q1, &vh, &s.slip_spring, &dslip, None);
    let v1 = &vh + &a1 * (0.5 * h);
    (vh, (q1, v1, a1, pf))
}

/// A Newmark step; on failure the step is split into 2, 4, … 256 substeps.
fn newmark_with_substeps(
    s: &mut Stepper,
    gaps: &GapElements,
    a_k: &DVector<f64>,
    h: f64,
) -> Result<StepState, SolverError> {
    let (q, v) = (&s.q, &s.v);
    if let Some(done) = newmark_step(s, gaps, s.t, h, q, v, a_k, &s.slip_spring) {
        return Ok(done);
    }
    let mut m = 2usize;
    while m <= 256 {
        let hs = h / m as f64;
        let (mut qs, mut vs, mut as_) = (q.clone(), v.clone(), a_k.clone());
        let mut slip = s.slip_spring.clone();
        let mut last = None;
        for j in 0..m {
            let t0 = s.t + j as f64 * hs;
            let Some((q1, v1, a1, pf)) = newmark_step(s, gaps, t0, hs, &qs, &vs, &as_, &slip)
            else {
                last = None;
                break;
            };
            slip = committed_slip(&pf);
            (qs, vs, as_) = (q1.clone(), v1.clone(), a1.clone());
            last = Some((q1, v1, a1, pf));
        }
        if let Some(done) = last {
            s.out.stats.steps_rejected += 1;
            return Ok(done);
        }
        m *= 2;
    }
    Err(SolverError::NoConvergence {
        t: s.t,
        method: "penalty (Newmark)",
        detail: "no convergence even with 256 substeps".into(),
    })
}

/// Tangential springs carried into the next step: released where the gap element is open.
fn committed_slip(pf: &PenaltyForces) -> Vec<f64> {
    let mut slip = pf.slip.clone();
    for (sl, &ln) in slip.iter_mut().zip(&pf.lam_n) {
        if ln <= 0.0 {
            *sl = 0.0;
        }
    }
    slip
}

/// Committed contact forces, springs and states: closed where λ_N > 0, stick where
/// |λ_T| < μλ_N.
fn set_contact_states(s: &mut Stepper, pf: &PenaltyForces) {
    s.slip_spring = committed_slip(pf);
    for (i, c) in s.scene.contacts.iter().enumerate() {
        let (ln, lt) = (pf.lam_n[i], pf.lam_t[i]);
        s.lam_n[i] = ln;
        s.lam_t[i] = lt;
        s.state[i] = if ln > 0.0 {
            if !c.law.frictionless() && lt.abs() < c.law.mu * ln * (1.0 - 1e-9) {
                ContactState::Stick
            } else {
                ContactState::Slide(if !c.law.frictionless() {
                    -lt.signum()
                } else {
                    0.0
                })
            }
        } else {
            ContactState::Open
        };
    }
}

/// Energy growth without a source: T + V (contact springs included) above 10 × the largest
/// energy the initial state, the loads and the supports have supplied so far.
struct EnergyGuard {
    explicit: bool,
    h: f64,
    supplied: f64,
}

impl EnergyGuard {
    fn new(s: &Stepper, explicit: bool, h: f64) -> Self {
        Self {
            explicit,
            h,
            supplied: Self::input_scale(s),
        }
    }

    fn input_scale(s: &Stepper) -> f64 {
        s.e0.abs() + s.ledger[0].abs() + s.ledger[1].abs()
    }

    /// [`SolverError::Unstable`] after step `k` (from the 11th step on) or on a non-finite state.
    fn check(&mut self, s: &Stepper, contact_elastic: f64, k: usize) -> Result<(), SolverError> {
        let scene = s.scene;
        let finite = s.q.iter().chain(s.v.iter()).all(|x| x.is_finite());
        let e_now =
            scene.kinetic_energy(&s.v) + scene.spring_energy(s.t, &s.q, &s.v) + contact_elastic;
        self.supplied = self.supplied.max(Self::input_scale(s));
        let e_supplied = self.supplied;
        let bound = 10.0 * e_supplied + 1e-12;
        if finite && !(e_now > bound && k > 10) {
            return Ok(());
        }
        let (method, why) = if self.explicit {
            (
                Method::PenaltyExplicit.name(),
                "explicit central difference is stable for h < 2/ω of the stiffest contact",
            )
        } else {
            (
                Method::Penalty.name(),
                "the switching gap elements pump energy into the Newmark scheme at this step",
            )
        };
        Err(SolverError::Unstable {
            t: s.t,
            method,
            step: self.h,
            detail: format!(
                "energy {e_now:.3e} exceeds 10 × the largest input {e_supplied:.3e} ({why})"
            ),
        })
    }
}
