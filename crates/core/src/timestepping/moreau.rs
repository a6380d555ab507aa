//! Moreau–Jean time-stepping (Moreau 1988; Jean 1999; Acary & Brogliato 2008, §10.1): per
//! step one velocity-level LCP with Newton restitution and Coulomb friction over the contacts
//! predicted active, θ-method for the smooth forces. First order, robust to accumulations.

use super::{Stepper, number_of_steps};
use crate::contact::frictional_velocity_lcp;
use crate::output::ContactState;
use crate::run::{Batcher, Observer, Run, SolverError};
use crate::scene::{ContactKinematics, Scene};
use nalgebra::{DMatrix, DVector};
use std::time::Instant;

/// Moreau–Jean θ-method, keeping what was computed before a cancel or a failure: Ŵ = M + hθC + h²θ²K,
/// v_free = v_k + Ŵ⁻¹ h[θ f(t_{k+1}, q_k, v_k) + (1−θ) f_k − hθ K v_k],
/// LCP over contacts with g_N(q_k) + h/2 ġ_N ≤ 0 (Siconos' γ = ½) on ġ_N⁺ = W_Nᵀv_{k+1} +
/// ∂g_N/∂t(t_{k+1}) (faces moved by the ground), v_{k+1} = v_free + Ŵ⁻¹(W_N P_N + W_T P_T),
/// q_{k+1} = q_k + h(θ v_{k+1} + (1−θ) v_k).
pub(crate) fn integrate_moreau(scene: &Scene, observer: &mut dyn Observer) -> Run {
    let wall = Instant::now();
    let mut s = Stepper::new(scene);
    s.key_acts_to_step_end = true;
    let result = moreau_steps(&mut s, observer);
    let complete = result.is_ok();
    Run::new(s.finish(wall, 0.0, complete), result)
}

/// The Moreau–Jean steps from t = 0 to t_end.
fn moreau_steps(s: &mut Stepper, observer: &mut dyn Observer) -> Result<(), SolverError> {
    let scene = s.scene;
    let steps = number_of_steps(scene)?;
    if !s.e0.is_finite() {
        return Err(SolverError::NonFinite { t: 0.0 });
    }
    let h = scene.settings.t_end / steps as f64;
    let th = scene.settings.theta;
    let mut f_k = DVector::zeros(scene.ndof());
    s.prev_power = s.forces_trial(0.0, &s.q.clone(), &s.v.clone(), &mut f_k);
    s.maybe_sample(0.0);
    let mut batcher = Batcher::new();
    for k in 0..steps {
        let t1 = (k + 1) as f64 * h;
        let (q, v) = (s.q.clone(), s.v.clone());
        let (v_free, winv) = free_velocity(s, h, t1, &f_k)?;
        // contacts predicted active
        let fr = scene.frame(s.t, &q, &v);
        let kin: Vec<ContactKinematics> = (scene.contacts.iter())
            .map(|c| scene.contact_kinematics(&fr, c))
            .collect();
        let active: Vec<usize> = (0..kin.len())
            .filter(|&i| kin[i].gap + 0.5 * h * kin[i].gap_rate <= 0.0)
            .collect();
        let before = s.state.clone();
        let driven = driven_rates(scene, &kin, t1);
        let p = percussions(s, &kin, &driven, &active, v_free, &winv)?;
        set_contact_states(s, &kin, &driven, &active, &p, h);
        s.q = &q + (&p.v_new * th + &v * (1.0 - th)) * h;
        s.v = p.v_new;
        s.t = t1;
        s.ledger[1] += p.driven_work;
        s.ledger[4] += p.loss;
        s.commit_laws(h);
        let (qq, vv) = (s.q.clone(), s.v.clone());
        let power = s.forces_trial(t1, &qq, &vv, &mut f_k);
        s.add_power(power, h);
        if !s.q.iter().chain(s.v.iter()).all(|x| x.is_finite()) {
            return Err(SolverError::NonFinite { t: s.t });
        }
        s.out.stats.steps_accepted += 1;
        s.log_transitions(&before, Some((&p.p_n, &p.p_t)));
        s.maybe_sample(0.0);
        batcher.maybe(&s.out, s.t, observer)?;
    }
    batcher.flush(&s.out, s.t, observer);
    Ok(())
}

/// v_free = v_k + Ŵ⁻¹ h[θ f(t_{k+1}, q_k, v_k) + (1−θ) f_k − hθ K v_k] and Ŵ⁻¹.
fn free_velocity(
    s: &mut Stepper,
    h: f64,
    t1: f64,
    f_k: &DVector<f64>,
) -> Result<(DVector<f64>, DMatrix<f64>), SolverError> {
    let th = s.scene.settings.theta;
    let (q, v) = (s.q.clone(), s.v.clone());
    let mut f_1 = DVector::zeros(s.scene.ndof());
    s.forces_trial(t1, &q, &v, &mut f_1);
    let (kt, ct) = s.tangents(s.t);
    let mut w = DMatrix::from_diagonal(&s.scene.mass);
    w += &ct * (h * th) + &kt * (h * h * th * th);
    let winv = w.try_inverse().ok_or(SolverError::NonFinite { t: s.t })?;
    let r = (&f_1 * th + f_k * (1.0 - th) - &kt * &v * (h * th)) * h;
    Ok((&v + &winv * r, winv))
}

/// Percussions of one step: P_N, P_T per contact (zero off the active set), v_{k+1}, the
/// work they absorb, −Σ (P_N ½(ġ_N⁺ + ġ_N^free) + P_T ½(ġ_T⁺ + ġ_T^free)) in relative rates,
/// and the work of faces moved by the ground, −Σ (P_N ∂g_N/∂t + P_T ∂g_T/∂t).
struct Percussions {
    p_n: Vec<f64>,
    p_t: Vec<f64>,
    v_new: DVector<f64>,
    loss: f64,
    driven_work: f64,
}

/// (∂g_N/∂t, ∂g_T/∂t) of each contact at t₁ (the velocities of bodies driven by the ground
/// at the step's end, along n and t of `kin`).
fn driven_rates(scene: &Scene, kin: &[ContactKinematics], t1: f64) -> Vec<(f64, f64)> {
    (scene.contacts.iter().zip(kin))
        .map(|(c, k)| {
            let dv =
                scene.driven_velocity(c.point_body, t1) - scene.driven_velocity(c.face_body, t1);
            let n = k.normal;
            (n.dot(&dv), n.y * dv.x - n.x * dv.y)
        })
        .collect()
}

/// The velocity LCP over the active set: ġ_N⁺ + ε ġ_N⁻ ⊥ P_N ≥ 0 with Coulomb's cone on P_T,
/// Delassus operator W Ŵ⁻¹ W.
fn percussions(
    s: &mut Stepper,
    kin: &[ContactKinematics],
    driven: &[(f64, f64)],
    active: &[usize],
    v_free: DVector<f64>,
    winv: &DMatrix<f64>,
) -> Result<Percussions, SolverError> {
    let scene = s.scene;
    let nc = kin.len();
    let mut p = Percussions {
        p_n: vec![0.0; nc],
        p_t: vec![0.0; nc],
        v_new: v_free.clone(),
        loss: 0.0,
        driven_work: 0.0,
    };
    if active.is_empty() {
        return Ok(p);
    }
    let w_n: Vec<&DVector<f64>> = active.iter().map(|&i| &kin[i].w_n).collect();
    let w_t: Vec<&DVector<f64>> = active.iter().map(|&i| &kin[i].w_t).collect();
    let q_n: Vec<f64> = (active.iter())
        .map(|&i| {
            let e = scene.contacts[i].law.restitution;
            kin[i].w_n.dot(&v_free) + driven[i].0 + e * kin[i].gap_rate.min(0.0)
        })
        .collect();
    let q_t: Vec<f64> = (active.iter())
        .map(|&i| kin[i].w_t.dot(&v_free) + driven[i].1)
        .collect();
    let mu: Vec<f64> = active.iter().map(|&i| scene.contacts[i].law.mu).collect();
    let g = |a: &DVector<f64>, b: &DVector<f64>| a.dot(&(winv * b));
    let lemke = &scene.settings.lemke;
    let (pn, pt, piv, delta) = frictional_velocity_lcp(&w_n, &w_t, &g, &q_n, &q_t, &mu, lemke)
        .map_err(|e| SolverError::Lcp {
            t: s.t,
            what: "Moreau–Jean",
            source: e,
        })?;
    s.out.stats.lcp_solves += 1;
    s.out.stats.lemke_pivots += piv;
    s.out.stats.lcp_regularized += usize::from(delta > 0.0);
    let mut imp = DVector::zeros(scene.ndof());
    for (a, &i) in active.iter().enumerate() {
        imp.axpy(pn[a], &kin[i].w_n, 1.0);
        imp.axpy(pt[a], &kin[i].w_t, 1.0);
        p.p_n[i] = pn[a];
        p.p_t[i] = pt[a];
    }
    p.v_new = &v_free + winv * imp;
    for (a, &i) in active.iter().enumerate() {
        let (dn, dt) = driven[i];
        let gn = 0.5 * (kin[i].w_n.dot(&p.v_new) + kin[i].w_n.dot(&v_free)) + dn;
        let gt = 0.5 * (kin[i].w_t.dot(&p.v_new) + kin[i].w_t.dot(&v_free)) + dt;
        p.loss -= pn[a] * gn + pt[a] * gt;
        p.driven_work -= pn[a] * dn + pt[a] * dt;
    }
    Ok(p)
}

/// Contact states after the step (closed where P_N > 0: stick where ġ_T⁺ = 0) and the forces
/// reported as λ = P / h.
fn set_contact_states(
    s: &mut Stepper,
    kin: &[ContactKinematics],
    driven: &[(f64, f64)],
    active: &[usize],
    p: &Percussions,
    h: f64,
) {
    for (i, c) in s.scene.contacts.iter().enumerate() {
        s.state[i] = if active.contains(&i) && p.p_n[i] > 0.0 {
            let gt = kin[i].w_t.dot(&p.v_new) + driven[i].1;
            if !c.law.frictionless() && gt.abs() <= 1e-9 {
                ContactState::Stick
            } else {
                ContactState::Slide(if !c.law.frictionless() {
                    gt.signum()
                } else {
                    0.0
                })
            }
        } else {
            ContactState::Open
        };
        s.lam_n[i] = p.p_n[i] / h;
        s.lam_t[i] = p.p_t[i] / h;
    }
}
