//! Event functions (an event is a crossing from > 0 to ≤ 0) of contacts and hysteretic
//! branches, their thresholds and their arming at the start of a phase.

use super::engine::Engine;
use super::event_fn::EventFn;
use crate::output::ContactState;
use crate::run::SolverError;
use nalgebra::DVector;

impl<'a> Engine<'a> {
    pub(super) fn event_fns(&mut self) -> Vec<EventFn> {
        let mut f = Vec::new();
        self.event_fns_into(&mut f);
        f
    }

    /// [`Engine::event_fns`] into `f` (cleared first).
    pub(super) fn event_fns_into(&mut self, f: &mut Vec<EventFn>) {
        self.state.fns_generation += 1;
        f.clear();
        for (i, st) in self.state.contacts.iter().enumerate() {
            match st {
                ContactState::Open => f.push(EventFn::Gap(i)),
                ContactState::Stick => {
                    f.push(EventFn::Release(i));
                    f.push(EventFn::StickSlip(i));
                }
                ContactState::Slide(s) => {
                    f.push(EventFn::Release(i));
                    if *s != 0.0 && !self.scene.contacts[i].law.frictionless() {
                        f.push(EventFn::SlideStop(i));
                    }
                }
            }
        }
        f.extend((0..self.scene.seats.len()).map(EventFn::Unseat));
        for (j, law) in self.state.laws.iter().enumerate() {
            let b = law.branch();
            if b.lower.is_finite() {
                f.push(EventFn::Lower(j));
            }
            if b.upper.is_finite() {
                f.push(EventFn::Upper(j));
            }
            if b.ends_on_reversal {
                f.push(EventFn::Reversal(j));
            }
        }
    }

    /// Values of the event functions (an event is a crossing from > 0 to ≤ 0) and their
    /// "zero" thresholds.
    pub(super) fn event_values(
        &mut self,
        t: f64,
        y: &DVector<f64>,
        fns: &[EventFn],
    ) -> Result<Vec<f64>, SolverError> {
        let mut vals = Vec::with_capacity(fns.len());
        self.event_values_into(t, y, fns, &mut vals)?;
        Ok(vals)
    }

    /// [`Engine::event_values`] into `vals` (cleared first).
    pub(super) fn event_values_into(
        &mut self,
        t: f64,
        y: &DVector<f64>,
        fns: &[EventFn],
        vals: &mut Vec<f64>,
    ) -> Result<(), SolverError> {
        let needs_forces = fns
            .iter()
            .any(|f| matches!(f, EventFn::Release(_) | EventFn::StickSlip(_)));
        let n = self.n;
        let scene = self.scene;
        let held = needs_forces || self.ws.dynamics.holds(t, y, false);
        let mut defo = std::mem::take(&mut self.ws.defo);
        if held {
            // the dynamics leave the frame and the element deformations of (t, y) in the scratch
            self.dynamics_into(t, y, false)?;
            defo.clear();
            defo.extend_from_slice(&self.ws.dynamics.elements);
        } else {
            if self.ws.event_qv.0.len() != n {
                self.ws.event_qv = (DVector::zeros(n), DVector::zeros(n));
            }
            let (q, v) = &mut self.ws.event_qv;
            q.as_mut_slice().copy_from_slice(&y.as_slice()[..n]);
            v.as_mut_slice().copy_from_slice(&y.as_slice()[n..2 * n]);
            let branch = fns.iter().any(|f| f.is_branch());
            let fr = &mut self.ws.event_frame;
            if branch {
                scene.frame_into(fr, t, q, v);
            } else {
                // contact functions need the poses only
                scene.poses_into(fr, t, q, v);
            }
            defo.clear();
            defo.resize(scene.hysteretic.len(), (f64::NAN, f64::NAN));
        }
        let fr = if held {
            &self.ws.dynamics.fr
        } else {
            &self.ws.event_frame
        };
        let mut rates = std::mem::take(&mut self.ws.gap_rates);
        vals.clear();
        vals.resize(fns.len(), 0.0);
        rates.clear();
        rates.resize(fns.len(), f64::NAN);
        let (d, laws) = (&self.ws.dynamics, &self.state.laws);
        for ((f, val), rate) in fns.iter().zip(vals.iter_mut()).zip(rates.iter_mut()) {
            *val = match *f {
                EventFn::Gap(i) => {
                    let (gap, gap_rate, _) = scene.contact_rates(fr, &scene.contacts[i]);
                    *rate = gap_rate;
                    gap
                }
                EventFn::Release(i) => d.lam_n[i],
                EventFn::StickSlip(i) => scene.contacts[i].law.stick_margin(d.lam_n[i], d.lam_t[i]),
                EventFn::Unseat(k) => {
                    let seat = &scene.seats[k];
                    let (gap, gap_rate, _) = scene.contact_rates(fr, &scene.contacts[seat.contact]);
                    *rate = -gap_rate;
                    seat.edge - gap
                }
                EventFn::SlideStop(i) => {
                    let s = match self.state.contacts[i] {
                        ContactState::Slide(s) => s,
                        _ => 1.0,
                    };
                    s * scene.contact_rates(fr, &scene.contacts[i]).2
                }
                EventFn::Lower(j) | EventFn::Upper(j) | EventFn::Reversal(j) => {
                    let de = &mut defo[j];
                    if de.0.is_nan() {
                        let el = &scene.hysteretic[j];
                        *de = scene.deformation_rates(fr, &el.attachment, el.support);
                    }
                    let (e, ed) = *de;
                    let b = laws[j].branch();
                    match *f {
                        EventFn::Lower(_) => {
                            *rate = ed;
                            e - b.lower
                        }
                        EventFn::Upper(_) => {
                            *rate = -ed;
                            b.upper - e
                        }
                        _ => b.direction * ed,
                    }
                }
            };
        }
        self.ws.gap_rates = rates;
        self.ws.defo = defo;
        Ok(())
    }

    /// The rates d·ë of the load-reversal functions among `fns` into `rates`, from the q̈ and
    /// frame of the dynamics evaluated at (t, y); nothing written if they were not.
    pub(super) fn reversal_rates_into(
        &self,
        t: f64,
        y: &DVector<f64>,
        fns: &[EventFn],
        rates: &mut [f64],
    ) {
        let d = &self.ws.dynamics;
        if !d.holds(t, y, false) {
            return;
        }
        for (f, r) in fns.iter().zip(rates.iter_mut()) {
            if let EventFn::Reversal(j) = *f {
                let el = &self.scene.hysteretic[j];
                let acc = (self.scene).deformation_acceleration(
                    &d.fr,
                    &el.attachment,
                    el.support,
                    d.qdd.as_slice(),
                );
                *r = self.state.laws[j].branch().direction * acc;
            }
        }
    }

    /// The band ε of f: f is armed once past it, and watched for v ≤ −ε until then, so that
    /// a value resting at zero (an element on the kink of its law) is no crossing.
    pub(super) fn threshold(&self, f: EventFn) -> f64 {
        let s = &self.scene.settings;
        match f {
            EventFn::Gap(_) | EventFn::Unseat(_) => 1e-3 * s.gap_tol,
            EventFn::Release(_) | EventFn::StickSlip(_) => 1e-10 * self.state.force_scale,
            EventFn::SlideStop(_) | EventFn::Reversal(_) => 1e-3 * s.velocity_tol,
            // a deformation is held to atol: a bound is not crossed back and forth within it
            EventFn::Lower(_) | EventFn::Upper(_) => (1e-3 * s.atol).max(1e-13),
        }
    }
}

/// A function already past its threshold at the current instant (it crossed together with
/// the event just processed). Gaps count only while closing.
/// Uses the values [`arm`] has just computed at this instant.
pub(super) fn due_now(
    eng: &mut Engine,
    fns: &[EventFn],
    done: &[EventFn],
) -> Result<Option<EventFn>, SolverError> {
    if eng.state.arm_values.len() != fns.len() {
        let y = std::mem::take(&mut eng.state.y);
        let mut vals = std::mem::take(&mut eng.state.arm_values);
        let r = eng.event_values_into(eng.state.t, &y, fns, &mut vals);
        eng.state.y = y;
        eng.state.arm_values = vals;
        r?;
    }
    for (k, f) in fns.iter().enumerate() {
        if eng.state.arm_values[k] < -eng.threshold(*f) && !done.contains(f) {
            if let EventFn::Gap(i) = *f {
                let gap_rate = eng.contact_kinematics_now(i).gap_rate;
                if gap_rate >= -eng.scene.settings.velocity_tol {
                    continue;
                }
            }
            eng.state.arm_values.clear();
            return Ok(Some(*f));
        }
    }
    eng.state.arm_values.clear();
    Ok(None)
}

/// Armed flags: a function is armed when it is known to be positive just after the start of a
/// phase — clearly positive, or zero and moving up (a separating gap, a slide just begun).
/// Unarmed ones trigger only below −threshold (an inconsistent state the LCP repairs).
///
/// A branch bound's e − lower or upper − e is armed only above its threshold ε: an element at
/// the bound (|v| ≤ ε: a branch just begun there, a wall at rest at the kink of its backfill)
/// is watched for v ≤ −ε, from either side. Moving into the branch it is armed once v > ε;
/// moving back it passes −ε and the branch beyond is taken again, with one event; a rounding
/// sign at the bound is no crossing. Below −ε it is due at once ([`due_now`]).
pub(super) fn arm(eng: &mut Engine, fns: &[EventFn]) -> Result<Vec<bool>, SolverError> {
    let mut armed = Vec::new();
    arm_into(eng, fns, &mut armed)?;
    Ok(armed)
}

/// [`arm`] into `armed`.
pub(super) fn arm_into(
    eng: &mut Engine,
    fns: &[EventFn],
    armed: &mut Vec<bool>,
) -> Result<(), SolverError> {
    eng.state.last_event_values = None;
    let y = std::mem::take(&mut eng.state.y);
    let mut vals = std::mem::take(&mut eng.state.arm_values);
    let r = eng.event_values_into(eng.state.t, &y, fns, &mut vals);
    // they are also the start values of the next step's event search, with the load
    // reversals' rates (the dynamics were evaluated here)
    let mut rates = eng.ws.gap_rates.clone();
    if r.is_ok() {
        eng.reversal_rates_into(eng.state.t, &y, fns, &mut rates);
    }
    eng.state.y = y;
    r?;
    let scene = eng.scene;
    let st = &scene.settings;
    armed.clear();
    armed.extend(fns.iter().zip(&vals).map(|(f, &val)| {
        let thr = eng.threshold(*f);
        match *f {
            // a gap at zero counts as positive if it opens
            EventFn::Gap(i) => {
                val > thr
                    || (val > -st.gap_tol
                        && eng.contact_kinematics_now(i).gap_rate > st.velocity_tol)
            }
            EventFn::SlideStop(_) | EventFn::Reversal(_) | EventFn::Unseat(_) => val > -thr,
            EventFn::Release(_) | EventFn::StickSlip(_) | EventFn::Lower(_) | EventFn::Upper(_) => {
                val > thr
            }
        }
    }));
    eng.state.last_event_values = Some((eng.state.t, vals.clone(), rates));
    eng.state.arm_values = vals;
    Ok(())
}
