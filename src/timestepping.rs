//! Fixed-step methods beside the event-driven one, on the same scenes:
//! - Moreau–Jean time-stepping (Moreau 1988; Jean 1999; Acary & Brogliato 2008, §10.1): per
//!   step one velocity-level LCP with Newton restitution and Coulomb friction over the contacts
//!   predicted active, θ-method for the smooth forces. First order, robust to accumulations.
//! - Penalty / compliance (gap elements, as OpenSees users build them): a compression-only spring
//!   k and dashpot c per contact (c from a target restitution), Coulomb friction as an
//!   elastic stick–slip spring; integrated by Newmark average acceleration (implicit) or by the
//!   explicit central-difference scheme (stable for h < 2/ω).

use crate::contact::frictional_velocity_lcp;
use crate::hysteresis::Hysteretic;
use crate::output::{
    ContactSample, ContactState, EnergySample, EventKind, EventRecord, RunOutput, SampleKind,
    SampleView,
};
use crate::run::{Batcher, Observer, SolverError};
use crate::scene::{Attachment, ContactKinematics, Frame, Method, PowerTerms, Scene};
use nalgebra::{DMatrix, DVector};
use std::time::Instant;

/// Shared state of a fixed-step run: laws, ledger, output.
struct Stepper<'a> {
    scene: &'a Scene,
    laws: Vec<Hysteretic>,
    t: f64,
    q: DVector<f64>,
    v: DVector<f64>,
    minv: DVector<f64>,
    out: RunOutput,
    next_out: usize,
    /// loads, supports, damping, hysteretic, contact dissipation
    ledger: [f64; 5],
    e0: f64,
    energy_scale: f64,
    prev_power: PowerTerms,
    /// Per-contact: last normal force/impulse and state, for events.
    state: Vec<ContactState>,
    lam_n: Vec<f64>,
    lam_t: Vec<f64>,
    /// Penalty: elastic tangential (stick) displacement per contact.
    slip_spring: Vec<f64>,
    jac: DVector<f64>,
}

fn deformation_of(
    scene: &Scene,
    fr: &Frame,
    att: &Attachment,
    sup: Option<usize>,
    jac: &mut DVector<f64>,
) -> (f64, f64, f64) {
    scene.deformation_in(fr, att, sup, jac)
}

impl<'a> Stepper<'a> {
    fn new(scene: &'a Scene) -> Self {
        let n = scene.ndof();
        let mut laws: Vec<Hysteretic> = scene.hysteretic.iter().map(|h| h.law.clone()).collect();
        let fr = scene.frame(0.0, &scene.q0, &scene.v0);
        let mut jac = DVector::zeros(n);
        for (j, el) in scene.hysteretic.iter().enumerate() {
            let (e, ed, _) = deformation_of(scene, &fr, &el.attachment, el.support, &mut jac);
            laws[j].set_direction(e, if ed < 0.0 { -1.0 } else { 1.0 });
        }
        let nc = scene.contacts.len();
        Self {
            scene,
            laws,
            t: 0.0,
            q: scene.q0.clone(),
            v: scene.v0.clone(),
            minv: scene.mass.map(|m| 1.0 / m),
            out: RunOutput {
                keep_history: scene.settings.keep_history,
                ..RunOutput::new(scene)
            },
            next_out: 0,
            ledger: [0.0; 5],
            e0: scene.kinetic_energy(&scene.v0) + scene.spring_energy(0.0, &scene.q0, &scene.v0),
            energy_scale: 0.0,
            prev_power: PowerTerms::default(),
            state: vec![ContactState::Open; nc],
            lam_n: vec![0.0; nc],
            lam_t: vec![0.0; nc],
            slip_spring: vec![0.0; nc],
            jac,
        }
    }

    /// Smooth forces with the laws advanced (on clones) from their committed state to q.
    fn forces_trial(
        &self,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        h: &mut DVector<f64>,
    ) -> PowerTerms {
        let scene = self.scene;
        let fr = scene.frame(t, q, v);
        let mut jac = DVector::zeros(scene.ndof());
        let mut laws = self.laws.clone();
        for (j, el) in scene.hysteretic.iter().enumerate() {
            let (e, _, _) = deformation_of(scene, &fr, &el.attachment, el.support, &mut jac);
            laws[j].drive(&[e]);
        }
        crate::scene::smooth_forces_in(scene, Some(&laws), &fr, v, h, None)
    }

    /// Move the laws along to the committed state q.
    fn commit_laws(&mut self) {
        let scene = self.scene;
        let fr = scene.frame(self.t, &self.q, &self.v);
        for (j, el) in scene.hysteretic.iter().enumerate() {
            let (e, _, _) = deformation_of(scene, &fr, &el.attachment, el.support, &mut self.jac);
            let before = self.laws[j].branch().stiffness;
            self.laws[j].drive(&[e]);
            if self.laws[j].branch().stiffness != before {
                self.out.stats.branch_events += 1;
            }
        }
    }

    /// Tangent stiffness and damping of the smooth forces at (q, current branches).
    fn tangents(&mut self, t: f64) -> (DMatrix<f64>, DMatrix<f64>) {
        let scene = self.scene;
        let n = scene.ndof();
        let fr = scene.frame(t, &self.q, &self.v);
        let mut k = DMatrix::zeros(n, n);
        let mut c = DMatrix::zeros(n, n);
        for s in &scene.springs {
            deformation_of(scene, &fr, &s.attachment, s.support, &mut self.jac);
            let jj = &self.jac * self.jac.transpose();
            k += &jj * s.stiffness;
            c += &jj * s.damping;
        }
        for (j, el) in scene.hysteretic.iter().enumerate() {
            deformation_of(scene, &fr, &el.attachment, el.support, &mut self.jac);
            let jj = &self.jac * self.jac.transpose();
            k += &jj * self.laws[j].branch().stiffness;
            c += &jj * el.damping;
        }
        for i in 0..n {
            c[(i, i)] += scene.mass_damping.alpha * scene.mass[i];
        }
        (k, c)
    }

    fn add_power(&mut self, p: PowerTerms, h: f64) {
        let a = &self.prev_power;
        self.ledger[0] += 0.5 * h * (a.loads + p.loads);
        self.ledger[1] += 0.5 * h * (a.supports + p.supports);
        self.ledger[2] += 0.5 * h * (a.damping + p.damping);
        self.ledger[3] += 0.5 * h * (a.hysteretic + p.hysteretic);
        self.prev_power = p;
    }

    fn energy(&self, contact_elastic: f64) -> EnergySample {
        let s = self.scene;
        let mut e = EnergySample {
            kinetic: s.kinetic_energy(&self.v),
            elastic: s.spring_energy(self.t, &self.q, &self.v) + contact_elastic,
            loads: self.ledger[0],
            supports: self.ledger[1],
            damping: self.ledger[2],
            hysteretic: self.ledger[3],
            // work absorbed by contacts less what their springs still store
            friction: self.ledger[4] - contact_elastic,
            impact_normal: 0.0,
            impact_tangential: 0.0,
            initial: self.e0,
            closure: 0.0,
        };
        e.closure = e.balance();
        e
    }

    fn sample(&mut self, kind: SampleKind, contact_elastic: f64) {
        let scene = self.scene;
        let fr = scene.frame(self.t, &self.q, &self.v);
        let contacts: Vec<ContactSample> = scene
            .contacts
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let k = scene.contact_kinematics_in(&fr, c);
                ContactSample {
                    gap: k.gap,
                    gap_rate: k.gap_rate,
                    slip_rate: k.slip_rate,
                    normal_force: self.lam_n[i],
                    tangential_force: self.lam_t[i],
                    state: self.state[i],
                }
            })
            .collect();
        let elements: Vec<(f64, f64)> = scene
            .hysteretic
            .iter()
            .enumerate()
            .map(|(j, el)| {
                let (e, _, _) =
                    deformation_of(scene, &fr, &el.attachment, el.support, &mut self.jac);
                (e, self.laws[j].force(e))
            })
            .collect();
        let energy = self.energy(contact_elastic);
        self.energy_scale = self.energy_scale.max(energy.scale());
        self.out.record(SampleView {
            t: self.t,
            kind,
            q: self.q.as_slice(),
            v: self.v.as_slice(),
            contacts: &contacts,
            elements: &elements,
            energy,
        });
    }

    /// Record grid samples due by now.
    fn maybe_sample(&mut self, contact_elastic: f64) {
        let dt = self.scene.settings.output_dt;
        if self.t + 1e-12 >= self.next_out as f64 * dt {
            self.sample(SampleKind::Grid, contact_elastic);
            while self.t + 1e-12 >= self.next_out as f64 * dt {
                self.next_out += 1;
            }
        }
    }

    /// Events from contact state changes over a step.
    fn log_transitions(&mut self, before: &[ContactState], impulses: Option<(&[f64], &[f64])>) {
        for i in 0..self.state.len() {
            let (b, a) = (before[i], self.state[i]);
            let kind = match (b, a) {
                (ContactState::Open, ContactState::Open) => None,
                (ContactState::Open, _) => Some(EventKind::Impact),
                (_, ContactState::Open) => Some(EventKind::Release),
                (ContactState::Stick, ContactState::Slide(_)) => Some(EventKind::Slip),
                (ContactState::Slide(x), ContactState::Slide(y)) if x != y => Some(EventKind::Slip),
                (ContactState::Slide(_), ContactState::Stick) => Some(EventKind::Stick),
                _ => None,
            };
            if let Some(kind) = kind {
                let (pn, pt) =
                    impulses.map_or((self.lam_n[i], self.lam_t[i]), |(n, t)| (n[i], t[i]));
                self.out.stats.count(kind);
                self.out.events.push(EventRecord {
                    t: self.t,
                    contact: i,
                    kind,
                    normal: pn,
                    tangential: pt,
                    gap_rate_before: f64::NAN,
                    gap_rate_after: f64::NAN,
                    slip_rate_after: f64::NAN,
                    sticks: Some(a == ContactState::Stick),
                    info: f64::NAN,
                });
            }
        }
    }

    fn finish(mut self, wall: Instant, contact_elastic: f64) -> RunOutput {
        if self.out.last_sample_time().is_none_or(|t| t < self.t) {
            self.sample(SampleKind::Grid, contact_elastic);
        }
        self.out.stats.wall_time = wall.elapsed().as_secs_f64();
        self.out.final_laws = self.laws.clone();
        let scale = self.energy_scale;
        self.out.finish(scale);
        self.out
    }
}

fn number_of_steps(scene: &Scene) -> Result<usize, SolverError> {
    let st = &scene.settings;
    let n = (st.t_end / st.step).ceil();
    if !(n.is_finite() && n >= 1.0) || n > st.max_steps as f64 {
        return Err(SolverError::TooManySteps {
            t: 0.0,
            limit: st.max_steps,
        });
    }
    Ok(n as usize)
}

/// Moreau–Jean θ-method: Ŵ = M + hθC + h²θ²K,
/// v_free = v_k + Ŵ⁻¹ h[θ f(t_{k+1}, q_k, v_k) + (1−θ) f_k − hθ K v_k],
/// LCP over contacts with g_N(q_k) + h/2 ġ_N ≤ 0 (Siconos' γ = ½),
/// v_{k+1} = v_free + Ŵ⁻¹(W_N P_N + W_T P_T), q_{k+1} = q_k + h(θ v_{k+1} + (1−θ) v_k).
pub fn run_moreau(scene: &Scene, observer: &mut dyn Observer) -> Result<RunOutput, SolverError> {
    let wall = Instant::now();
    let st = &scene.settings;
    let n = scene.ndof();
    let nc = scene.contacts.len();
    let steps = number_of_steps(scene)?;
    let h = st.t_end / steps as f64;
    let th = st.theta;
    let mut s = Stepper::new(scene);
    let mut f_k = DVector::zeros(n);
    s.prev_power = s.forces_trial(0.0, &s.q.clone(), &s.v.clone(), &mut f_k);
    s.maybe_sample(0.0);
    let mut batcher = Batcher::new();
    for k in 0..steps {
        let t1 = (k + 1) as f64 * h;
        let mut f_1 = DVector::zeros(n);
        let (q, v) = (s.q.clone(), s.v.clone());
        s.forces_trial(t1, &q, &v, &mut f_1);
        let (kt, ct) = s.tangents(s.t);
        let mut w = DMatrix::from_diagonal(&scene.mass);
        w += &ct * (h * th) + &kt * (h * h * th * th);
        let winv = w
            .clone()
            .try_inverse()
            .ok_or(SolverError::NonFinite { t: s.t })?;
        let r = (&f_1 * th + &f_k * (1.0 - th) - &kt * &v * (h * th)) * h;
        let v_free = &v + &winv * r;
        // contacts predicted active
        let fr = scene.frame(s.t, &q, &v);
        let kin: Vec<ContactKinematics> = scene
            .contacts
            .iter()
            .map(|c| scene.contact_kinematics_in(&fr, c))
            .collect();
        let active: Vec<usize> = (0..nc)
            .filter(|&i| kin[i].gap + 0.5 * h * kin[i].gap_rate <= 0.0)
            .collect();
        let before = s.state.clone();
        let mut v_new = v_free.clone();
        s.lam_n.iter_mut().for_each(|x| *x = 0.0);
        s.lam_t.iter_mut().for_each(|x| *x = 0.0);
        let mut pn_all = vec![0.0; nc];
        let mut pt_all = vec![0.0; nc];
        let mut contact_loss = 0.0;
        if !active.is_empty() {
            let w_n: Vec<&DVector<f64>> = active.iter().map(|&i| &kin[i].w_n).collect();
            let w_t: Vec<&DVector<f64>> = active.iter().map(|&i| &kin[i].w_t).collect();
            let q_n: Vec<f64> = active
                .iter()
                .map(|&i| {
                    kin[i].w_n.dot(&v_free)
                        + scene.contacts[i].restitution * kin[i].gap_rate.min(0.0)
                })
                .collect();
            let q_t: Vec<f64> = active.iter().map(|&i| kin[i].w_t.dot(&v_free)).collect();
            let mu: Vec<f64> = active.iter().map(|&i| scene.contacts[i].mu).collect();
            let g = |a: &DVector<f64>, b: &DVector<f64>| a.dot(&(&winv * b));
            let (pn, pt, piv) = frictional_velocity_lcp(&w_n, &w_t, &g, &q_n, &q_t, &mu, &st.lemke)
                .map_err(|e| SolverError::Lcp {
                    t: s.t,
                    what: "Moreau–Jean",
                    source: e,
                })?;
            s.out.stats.lcp_solves += 1;
            s.out.stats.lemke_pivots += piv;
            let mut imp = DVector::zeros(n);
            for (a, &i) in active.iter().enumerate() {
                imp.axpy(pn[a], &kin[i].w_n, 1.0);
                imp.axpy(pt[a], &kin[i].w_t, 1.0);
                pn_all[i] = pn[a];
                pt_all[i] = pt[a];
            }
            v_new = &v_free + &winv * imp;
            for (a, &i) in active.iter().enumerate() {
                let gn = 0.5 * (kin[i].w_n.dot(&v_new) + kin[i].w_n.dot(&v_free));
                let gt = 0.5 * (kin[i].w_t.dot(&v_new) + kin[i].w_t.dot(&v_free));
                contact_loss -= pn[a] * gn + pt[a] * gt;
            }
        }
        for i in 0..nc {
            s.state[i] = if active.contains(&i) && pn_all[i] > 0.0 {
                let gt = kin[i].w_t.dot(&v_new);
                if scene.contacts[i].mu > 0.0 && gt.abs() <= 1e-9 {
                    ContactState::Stick
                } else {
                    ContactState::Slide(if scene.contacts[i].mu > 0.0 {
                        gt.signum()
                    } else {
                        0.0
                    })
                }
            } else {
                ContactState::Open
            };
            // report forces as impulse / h
            s.lam_n[i] = pn_all[i] / h;
            s.lam_t[i] = pt_all[i] / h;
        }
        s.q = &q + (&v_new * th + &v * (1.0 - th)) * h;
        s.v = v_new;
        s.t = t1;
        s.ledger[4] += contact_loss;
        s.commit_laws();
        let (qq, vv) = (s.q.clone(), s.v.clone());
        let p = s.forces_trial(t1, &qq, &vv, &mut f_k);
        s.add_power(p, h);
        if !s.q.iter().chain(s.v.iter()).all(|x| x.is_finite()) {
            return Err(SolverError::NonFinite { t: s.t });
        }
        s.out.stats.steps_accepted += 1;
        s.log_transitions(&before, Some((&pn_all, &pt_all)));
        s.maybe_sample(0.0);
        batcher.maybe(&s.out, s.t, observer)?;
    }
    batcher.flush(&s.out, s.t, observer);
    Ok(s.finish(wall, 0.0))
}

/// Penalty contact forces at (q, v) with trial tangential springs `slip0 + Δs`.
struct PenaltyForces {
    f: DVector<f64>,
    lam_n: Vec<f64>,
    lam_t: Vec<f64>,
    slip: Vec<f64>,
    elastic: f64,
    /// Power absorbed by the contact elements, −Σ(λ_N ġ_N + λ_T ġ_T).
    absorbed: f64,
}

/// Gap element per contact: λ_N = max(0, −k g_N − c ġ_N) for g_N < 0; c = 2ζ√(k m_eff) with
/// ζ from the target restitution ε = exp(−ζπ/√(1−ζ²)) (ζ = 1 for ε = 0); Coulomb friction as
/// an elastic stick spring k_T = k with return mapping to μλ_N.
fn penalty_forces(
    scene: &Scene,
    fr: &Frame,
    k: f64,
    dashpots: &[(f64, f64)],
    slip0: &[f64],
    dslip: &[f64],
    mask: Option<&[bool]>,
) -> PenaltyForces {
    let n = scene.ndof();
    let nc = scene.contacts.len();
    let mut out = PenaltyForces {
        f: DVector::zeros(n),
        lam_n: vec![0.0; nc],
        lam_t: vec![0.0; nc],
        slip: vec![0.0; nc],
        elastic: 0.0,
        absorbed: 0.0,
    };
    for (i, c) in scene.contacts.iter().enumerate() {
        if mask.is_some_and(|m| !m[i]) {
            continue;
        }
        let kin = scene.contact_kinematics_in(fr, c);
        if mask.is_none() && kin.gap >= 0.0 {
            continue;
        }
        let (c_n, c_t) = dashpots[i];
        // with a fixed active set (Newmark iterations) the element is linear
        let ln = if mask.is_some() {
            -k * kin.gap - c_n * kin.gap_rate
        } else {
            (-k * kin.gap - c_n * kin.gap_rate).max(0.0)
        };
        out.elastic += 0.5 * k * kin.gap * kin.gap;
        let mut s = slip0[i] + dslip[i];
        // stick spring with a dashpot of the normal damping ratio (an undamped stick spring
        // would give the tangential motion a restitution of one)
        let mut lt = -k * s - c_t * kin.slip_rate;
        if c.mu > 0.0 {
            if lt.abs() > c.mu * ln {
                lt = c.mu * ln * lt.signum();
                s = -lt / k;
            }
            out.elastic += 0.5 * k * s * s;
        } else {
            lt = 0.0;
            s = 0.0;
        }
        out.absorbed -= ln * kin.gap_rate + lt * kin.slip_rate;
        out.lam_n[i] = ln;
        out.lam_t[i] = lt;
        out.slip[i] = s;
        out.f.axpy(ln, &kin.w_n, 1.0);
        out.f.axpy(lt, &kin.w_t, 1.0);
    }
    out
}

/// (normal, tangential) dashpot per contact: c = 2ζ√(k m_eff) with m_eff = 1/(WᵀM⁻¹W).
fn dashpots(scene: &Scene, k: f64) -> Vec<(f64, f64)> {
    let minv = scene.mass.map(|m| 1.0 / m);
    let fr = scene.frame(0.0, &scene.q0, &scene.v0);
    scene
        .contacts
        .iter()
        .map(|c| {
            let kin = scene.contact_kinematics_in(&fr, c);
            let m_eff = |w: &DVector<f64>| {
                let g: f64 = w.iter().zip(minv.iter()).map(|(w, m)| w * w * m).sum();
                1.0 / g.max(1e-300)
            };
            let e = c.restitution;
            let zeta = if e <= 0.0 {
                1.0
            } else {
                let l = e.ln();
                -l / (std::f64::consts::PI.powi(2) + l * l).sqrt()
            };
            (
                2.0 * zeta * (k * m_eff(&kin.w_n)).sqrt(),
                2.0 * zeta * (k * m_eff(&kin.w_t)).sqrt(),
            )
        })
        .collect()
}

/// Penalty method: explicit central difference (`explicit`) or Newmark average acceleration.
/// Explicit runs stop with [`SolverError::Unstable`] when the energy grows without a source.
pub fn run_penalty(
    scene: &Scene,
    explicit: bool,
    observer: &mut dyn Observer,
) -> Result<RunOutput, SolverError> {
    let wall = Instant::now();
    let st = &scene.settings;
    let n = scene.ndof();
    let nc = scene.contacts.len();
    let steps = number_of_steps(scene)?;
    let h = st.t_end / steps as f64;
    let kc = st.contact_stiffness;
    let cd = dashpots(scene, kc);
    let mut s = Stepper::new(scene);
    let zero = vec![0.0; nc];
    let accel = |s: &Stepper,
                 t: f64,
                 q: &DVector<f64>,
                 v: &DVector<f64>,
                 slip0: &[f64],
                 dslip: &[f64],
                 mask: Option<&[bool]>| {
        let mut f = DVector::zeros(n);
        let p = s.forces_trial(t, q, v, &mut f);
        let fr = scene.frame(t, q, v);
        let pf = penalty_forces(scene, &fr, kc, &cd, slip0, dslip, mask);
        let a = (f + &pf.f).component_mul(&s.minv);
        (a, p, pf)
    };
    let (mut a_k, p0, pf0) = accel(
        &s,
        0.0,
        &s.q.clone(),
        &s.v.clone(),
        &s.slip_spring.clone(),
        &zero,
        None,
    );
    s.prev_power = p0;
    let mut contact_elastic = pf0.elastic;
    s.maybe_sample(contact_elastic);
    let mut batcher = Batcher::new();
    // explicit: velocity at the half step
    let mut v_half = &s.v - &a_k * (0.5 * h);
    let e_input_scale = |s: &Stepper| s.e0.abs() + s.ledger[0].abs() + s.ledger[1].abs();
    // the largest energy the initial state, loads and supports have supplied so far
    let mut e_supplied = e_input_scale(&s);
    let mut prev_absorbed = pf0.absorbed;
    for k in 0..steps {
        let t1 = (k + 1) as f64 * h;
        let (q, v) = (s.q.clone(), s.v.clone());
        let before = s.state.clone();
        let (q1, v1, a1, pf) = if explicit {
            let vh = &v_half + &a_k * h;
            let q1 = &q + &vh * h;
            // tangential increment over the step from the half-step velocity
            let fr_mid = scene.frame(s.t + 0.5 * h, &(&q + &vh * (0.5 * h)), &vh);
            let dslip: Vec<f64> = scene
                .contacts
                .iter()
                .map(|c| scene.contact_kinematics_in(&fr_mid, c).slip_rate * h)
                .collect();
            let (a1, _, pf) = accel(&s, t1, &q1, &vh, &s.slip_spring.clone(), &dslip, None);
            let v1 = &vh + &a1 * (0.5 * h);
            v_half = vh;
            (q1, v1, a1, pf)
        } else {
            // Newmark; on failure the step is split into 2, 4, … 256 substeps
            let mut done = newmark_step(&s, kc, &cd, s.t, h, &q, &v, &a_k, &s.slip_spring);
            let mut m = 2usize;
            while done.is_none() && m <= 256 {
                let hs = h / m as f64;
                let (mut qs, mut vs, mut as_) = (q.clone(), v.clone(), a_k.clone());
                let mut slip = s.slip_spring.clone();
                let mut last = None;
                for j in 0..m {
                    match newmark_step(&s, kc, &cd, s.t + j as f64 * hs, hs, &qs, &vs, &as_, &slip)
                    {
                        Some((q1, v1, a1, pf)) => {
                            slip = pf.slip.clone();
                            for (i, sl) in slip.iter_mut().enumerate() {
                                if pf.lam_n[i] <= 0.0 {
                                    *sl = 0.0;
                                }
                            }
                            (qs, vs, as_) = (q1.clone(), v1.clone(), a1.clone());
                            last = Some((q1, v1, a1, pf));
                        }
                        None => {
                            last = None;
                            break;
                        }
                    }
                }
                done = last;
                if done.is_some() {
                    s.out.stats.steps_rejected += 1;
                }
                m *= 2;
            }
            match done {
                Some(x) => x,
                None => {
                    return Err(SolverError::NoConvergence {
                        t: s.t,
                        method: "penalty (Newmark)",
                        detail: "no convergence even with 256 substeps".into(),
                    });
                }
            }
        };
        s.q = q1;
        s.v = v1;
        a_k = a1;
        s.t = t1;
        s.slip_spring = pf.slip.clone();
        for i in 0..nc {
            if pf.lam_n[i] <= 0.0 {
                s.slip_spring[i] = 0.0;
            }
        }
        s.commit_laws();
        let mut f = DVector::zeros(n);
        let (qq, vv) = (s.q.clone(), s.v.clone());
        let p = s.forces_trial(t1, &qq, &vv, &mut f);
        s.add_power(p, h);
        s.ledger[4] += 0.5 * h * (prev_absorbed + pf.absorbed);
        prev_absorbed = pf.absorbed;
        contact_elastic = pf.elastic;
        for i in 0..nc {
            s.lam_n[i] = pf.lam_n[i];
            s.lam_t[i] = pf.lam_t[i];
            s.state[i] = if pf.lam_n[i] > 0.0 {
                let c = &scene.contacts[i];
                if c.mu > 0.0 && pf.lam_t[i].abs() < c.mu * pf.lam_n[i] * (1.0 - 1e-9) {
                    ContactState::Stick
                } else {
                    ContactState::Slide(if c.mu > 0.0 {
                        -pf.lam_t[i].signum()
                    } else {
                        0.0
                    })
                }
            } else {
                ContactState::Open
            };
        }
        s.out.stats.steps_accepted += 1;
        s.out.stats.rhs_evals += 1;
        let finite = s.q.iter().chain(s.v.iter()).all(|x| x.is_finite());
        // energy growth without a source: T + V (incl. contact springs) far above what the
        // initial state and the loads and supports could have supplied
        let e_now =
            scene.kinetic_energy(&s.v) + scene.spring_energy(s.t, &s.q, &s.v) + contact_elastic;
        e_supplied = e_supplied.max(e_input_scale(&s));
        let bound = 10.0 * e_supplied + 1e-12;
        if !finite || (e_now > bound && k > 10) {
            return Err(SolverError::Unstable {
                t: s.t,
                method: if explicit {
                    "penalty-explicit"
                } else {
                    "penalty"
                },
                step: h,
                detail: format!(
                    "energy {e_now:.3e} exceeds 10 × the largest input {e_supplied:.3e} ({})",
                    if explicit {
                        "explicit central difference is stable for h < 2/ω of the stiffest contact"
                    } else {
                        "the switching gap elements pump energy into the Newmark scheme at this step"
                    }
                ),
            });
        }
        s.log_transitions(&before, None);
        s.maybe_sample(contact_elastic);
        batcher.maybe(&s.out, s.t, observer)?;
    }
    batcher.flush(&s.out, s.t, observer);
    Ok(s.finish(wall, contact_elastic))
}

/// Accelerations from smooth and penalty forces (trial laws, trial tangential springs).
#[allow(clippy::too_many_arguments)]
fn penalty_accel(
    s: &Stepper,
    kc: f64,
    cd: &[(f64, f64)],
    t: f64,
    q: &DVector<f64>,
    v: &DVector<f64>,
    slip0: &[f64],
    dslip: &[f64],
    mask: Option<&[bool]>,
) -> (DVector<f64>, PenaltyForces) {
    let n = s.scene.ndof();
    let mut f = DVector::zeros(n);
    s.forces_trial(t, q, v, &mut f);
    let fr = s.scene.frame(t, q, v);
    let pf = penalty_forces(s.scene, &fr, kc, cd, slip0, dslip, mask);
    ((f + &pf.f).component_mul(&s.minv), pf)
}

/// (q₁, v₁, a₁, contact forces) at the end of a step.
type StepState = (DVector<f64>, DVector<f64>, DVector<f64>, PenaltyForces);

/// One Newmark average-acceleration step (β = ¼, γ = ½) of the penalty model: Newton on q₁
/// with a finite-difference tangent within a fixed active set of gap elements, the set then
/// corrected until consistent (compressed in, tensile out). None when it does not converge.
#[allow(clippy::too_many_arguments)]
fn newmark_step(
    s: &Stepper,
    kc: f64,
    cd: &[(f64, f64)],
    t0: f64,
    h: f64,
    q: &DVector<f64>,
    v: &DVector<f64>,
    a_k: &DVector<f64>,
    slip0: &[f64],
) -> Option<StepState> {
    let scene = s.scene;
    let n = scene.ndof();
    let t1 = t0 + h;
    let fr0 = scene.frame(t0, q, v);
    let slip_rate0: Vec<f64> = scene
        .contacts
        .iter()
        .map(|c| scene.contact_kinematics_in(&fr0, c).slip_rate)
        .collect();
    let resid = |q1: &DVector<f64>, mask: &[bool]| {
        let a1 = (q1 - q - v * h) * (4.0 / (h * h)) - a_k;
        let v1 = v + (a_k + &a1) * (0.5 * h);
        let fr1 = scene.frame(t1, q1, &v1);
        let dslip: Vec<f64> = scene
            .contacts
            .iter()
            .enumerate()
            .map(|(i, c)| {
                0.5 * h * (slip_rate0[i] + scene.contact_kinematics_in(&fr1, c).slip_rate)
            })
            .collect();
        let (acc, pf) = penalty_accel(s, kc, cd, t1, q1, &v1, slip0, &dslip, Some(mask));
        (a1.clone() - acc, a1, v1, pf)
    };
    let jacobian = |q1: &DVector<f64>, r: &DVector<f64>, mask: &[bool]| {
        let mut jm = DMatrix::zeros(n, n);
        for j in 0..n {
            let d = 1e-7 * (1.0 + q1[j].abs());
            let mut qp = q1.clone();
            qp[j] += d;
            let (rp, ..) = resid(&qp, mask);
            for i in 0..n {
                jm[(i, j)] = (rp[i] - r[i]) / d;
            }
        }
        jm.lu()
    };
    let mut q1 = q + v * h + a_k * (0.5 * h * h);
    let mut mask: Vec<bool> = {
        let fr = scene.frame(t1, &q1, v);
        scene
            .contacts
            .iter()
            .map(|c| scene.contact_kinematics_in(&fr, c).gap < 0.0)
            .collect()
    };
    let mut converged_last = false;
    for _set in 0..8 {
        let (mut r, mut a1, mut v1, mut pf) = resid(&q1, &mask);
        let mut lu = jacobian(&q1, &r, &mask);
        let mut converged = false;
        for it in 0..30 {
            if r.amax() <= 1e-10 * (1.0 + a1.amax()) {
                converged = true;
                break;
            }
            if it > 0 && it % 4 == 0 {
                lu = jacobian(&q1, &r, &mask);
            }
            let dq = lu.solve(&r)?;
            q1 -= &dq;
            (r, a1, v1, pf) = resid(&q1, &mask);
            if !r.iter().all(|x| x.is_finite()) {
                return None;
            }
            // the update is at round-off and the residual at round-off of the 4/h² scaling
            if dq.amax() <= 1e-13 * (1.0 + q1.amax()) && r.amax() <= 1e-6 * (1.0 + a1.amax()) {
                converged = true;
                break;
            }
        }
        converged_last = converged;
        if !converged {
            return None;
        }
        let fr = scene.frame(t1, &q1, &v1);
        let natural: Vec<bool> = scene
            .contacts
            .iter()
            .enumerate()
            .map(|(i, c)| {
                let k = scene.contact_kinematics_in(&fr, c);
                k.gap < 0.0 && -kc * k.gap - cd[i].0 * k.gap_rate > 0.0
            })
            .collect();
        if natural == mask {
            return Some((q1, v1, a1, pf));
        }
        mask = natural;
    }
    // the set cycles on the element's jump (c|ġ_N| at g_N = 0): take the last converged state
    if converged_last {
        let (_, a1, v1, pf) = resid(&q1, &mask);
        return Some((q1, v1, a1, pf));
    }
    None
}

/// Run a scene with the method its settings name.
pub fn simulate(scene: &Scene, observer: &mut dyn Observer) -> Result<RunOutput, SolverError> {
    match scene.settings.method {
        Method::Event => crate::event_driven::run(scene, observer),
        Method::Moreau => run_moreau(scene, observer),
        Method::Penalty => run_penalty(scene, false, observer),
        Method::PenaltyExplicit => run_penalty(scene, true, observer),
    }
}
