//! Fixed-step methods beside the event-driven one, on the same scenes:
//! - [`moreau`]: Moreau–Jean time-stepping (Moreau 1988; Jean 1999; Acary & Brogliato 2008,
//!   §10.1).
//! - [`penalty`]: gap elements (penalty / compliance), Newmark average acceleration
//!   ([`newmark`]) or explicit central difference.
//!
//! This module holds what they share: the committed state, the hysteretic laws, the energy
//! ledger and the output recording ([`Stepper`]).

mod gap_elements;
mod moreau;
mod newmark;
mod penalty;

pub(crate) use moreau::integrate_moreau;
pub(crate) use penalty::integrate_penalty;

use crate::hysteresis::Hysteretic;
use crate::output::{
    ContactSample, ContactState, EnergySample, EventKind, EventRecord, FinalState, RunOutput,
    SampleKind, SampleView,
};
use crate::run::SolverError;
use crate::scene::{ForceModel, Frame, PowerTerms, Scene, spread};
use nalgebra::{DMatrix, DVector};
use std::cell::RefCell;
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
    /// Jacobian row of one element (tangents).
    jac: DVector<f64>,
    /// ė of each hysteretic element at the committed state.
    rates: Vec<f64>,
    /// A shear key failing inside a step acted on the committed branch until the step's end
    /// (Moreau–Jean linearises h about the committed branches; the penalty methods use the
    /// failed law at the step's end, as the ledger's trapezoid does).
    key_acts_to_step_end: bool,
    /// h(t, q, q̇) of eq. 1, as the event-driven engine evaluates it.
    forces: ForceModel,
    scratch: RefCell<Scratch>,
}

/// Buffers of the smooth-force evaluations: frame, trial laws, (e, ė) per hysteretic element.
#[derive(Default)]
struct Scratch {
    fr: Frame,
    laws: Vec<Hysteretic>,
    elements: Vec<(f64, f64)>,
}

impl<'a> Stepper<'a> {
    fn new(scene: &'a Scene) -> Self {
        let n = scene.ndof();
        let mut laws: Vec<Hysteretic> = scene.hysteretic.iter().map(|h| h.law.clone()).collect();
        let forces = ForceModel::new(scene);
        let mut scratch = Scratch {
            elements: vec![(0.0, 0.0); laws.len()],
            ..Scratch::default()
        };
        scene.frame_into(&mut scratch.fr, 0.0, &scene.q0, &scene.v0);
        forces.deformations(scene, &scratch.fr, &mut scratch.elements);
        for (law, &(e, ed)) in laws.iter_mut().zip(&scratch.elements) {
            law.set_direction(e, if ed < 0.0 { -1.0 } else { 1.0 });
        }
        let nc = scene.contacts.len();
        let rates = scratch.elements.iter().map(|&(_, ed)| ed).collect();
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
            jac: DVector::zeros(n),
            rates,
            key_acts_to_step_end: false,
            forces,
            scratch: RefCell::new(scratch),
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
        let mut scratch = self.scratch.borrow_mut();
        let Scratch { fr, laws, elements } = &mut *scratch;
        self.scene.frame_into(fr, t, q, v);
        self.forces.deformations(self.scene, fr, elements);
        laws.clone_from(&self.laws);
        for (law, &(e, _)) in laws.iter_mut().zip(elements.iter()) {
            law.drive(&[e]);
        }
        self.forces.eval(self.scene, laws, fr, v, h, elements)
    }

    /// Move the laws along to the committed state q, `h` after the previous one.
    fn commit_laws(&mut self, h: f64) {
        let mut scratch = self.scratch.borrow_mut();
        let Scratch { fr, elements, .. } = &mut *scratch;
        self.scene.frame_into(fr, self.t, &self.q, &self.v);
        self.forces.deformations(self.scene, fr, elements);
        for (j, (law, &(e, ed))) in self.laws.iter_mut().zip(elements.iter()).enumerate() {
            let (before, intact) = (law.branch().stiffness, !law.failed());
            let (e0, b0) = (law.displacement(), *law.branch());
            law.drive(&[e]);
            if law.branch().stiffness != before || intact && law.failed() {
                self.out.stats.branch_events += 1;
            }
            if intact && law.failed() {
                // rule G5 within this step, logged at its end
                if self.key_acts_to_step_end {
                    // the ledger's ½ h (f₀ ė₀ + 0) → the committed branch's work over the step
                    let (f0, f1) = (b0.force(e0), b0.force(e));
                    self.ledger[3] += 0.5 * (f0 + f1) * (e - e0) - 0.5 * h * f0 * self.rates[j];
                }
                let peak = law.gap_state().map_or(f64::NAN, |g| g.peak_force);
                let rec = EventRecord::key_failure(self.t, j);
                self.out.stats.count(rec.kind);
                self.out.events.push(rec);
                self.out.note_key_failure(self.t, j, peak);
            }
            self.rates[j] = ed;
        }
    }

    /// Tangents of the smooth forces at (q, current branches): K = Σ k_e J_eᵀJ_e,
    /// C = Σ c_e J_eᵀJ_e + a₀M.
    fn tangents(&mut self, t: f64) -> (DMatrix<f64>, DMatrix<f64>) {
        let scene = self.scene;
        let n = scene.ndof();
        let fr = scene.frame(t, &self.q, &self.v);
        let mut k = DMatrix::zeros(n, n);
        let mut c = DMatrix::zeros(n, n);
        for s in &scene.springs {
            let (.., sparse, nj) = scene.deformation(&fr, &s.attachment, s.support);
            spread(&sparse[..nj], &mut self.jac);
            let jj = &self.jac * self.jac.transpose();
            k += &jj * s.stiffness;
            c += &jj * s.damping;
        }
        for (j, el) in scene.hysteretic.iter().enumerate() {
            let (.., sparse, nj) = scene.deformation(&fr, &el.attachment, el.support);
            spread(&sparse[..nj], &mut self.jac);
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
                let k = scene.contact_kinematics(&fr, c);
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
        let mut elements = vec![(0.0, 0.0); self.laws.len()];
        self.forces.deformations(scene, &fr, &mut elements);
        for ((e, f), law) in elements.iter_mut().zip(&self.laws) {
            *f = law.force(*e);
        }
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
        // usize::MAX: the output step is too small to count its instants (every step samples)
        let every = self.next_out == usize::MAX;
        if every || self.t + 1e-12 >= self.next_out as f64 * dt {
            self.sample(SampleKind::Grid, contact_elastic);
            // the next grid instant after t, in one jump (an output step far below the fixed
            // step would otherwise be counted through one by one)
            let k = ((self.t + 1e-12) / dt).floor();
            if k.is_nan() || k >= 2f64.powi(52) {
                self.next_out = usize::MAX;
                return;
            }
            self.next_out = (k as usize).max(self.next_out);
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

    /// The output, with a final sample if `complete` (the run reached its end).
    fn finish(mut self, wall: Instant, contact_elastic: f64, complete: bool) -> RunOutput {
        if complete && self.out.last_sample_time().is_none_or(|t| t < self.t) {
            self.sample(SampleKind::Grid, contact_elastic);
        }
        self.out.stats.wall_time = wall.elapsed().as_secs_f64();
        self.out.final_laws = self.laws.clone();
        self.out.final_state = FinalState {
            t: self.t,
            q: self.q.as_slice().to_vec(),
            v: self.v.as_slice().to_vec(),
        };
        let scale = self.energy_scale;
        self.out.finish(scale);
        self.out
    }
}

/// N = ⌈t_end / h⌉ steps, at most `solver.max_steps`.
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
