//! Output of the event-driven engine: samples (grid, pre- and post-event), the energy ledger,
//! the event log and the peaks between samples.

use super::engine::Engine;
use super::locate::bracket_root;
use crate::dopri;
use crate::output::{
    ContactSample, ContactState, EnergySample, EventRecord, RunOutput, SampleKind, SampleView,
};
use crate::run::SolverError;
use crate::scene::ContactKinematics;
use nalgebra::DVector;

impl<'a> Engine<'a> {
    pub(super) fn record_sample(&mut self, kind: SampleKind) -> Result<(), SolverError> {
        let n = self.n;
        let scene = self.scene;
        if self.state.contacts.iter().all(|s| *s == ContactState::Open) {
            // no contact force to solve for: kinematics and element deformations only
            let sc = &mut self.ws.dynamics;
            sc.at = None;
            sc.size(n);
            sc.q.as_mut_slice()
                .copy_from_slice(&self.state.y.as_slice()[..n]);
            sc.v.as_mut_slice()
                .copy_from_slice(&self.state.y.as_slice()[n..2 * n]);
            scene.frame_into(&mut sc.fr, self.state.t, &sc.q, &sc.v);
            sc.kin
                .resize_with(scene.contacts.len(), ContactKinematics::placeholder);
            for (c, k) in scene.contacts.iter().zip(sc.kin.iter_mut()) {
                // gap and rates only: no Jacobians needed without forces
                (k.gap, k.gap_rate, k.slip_rate) = scene.contact_rates(&sc.fr, c);
            }
            sc.lam_n.clear();
            sc.lam_n.resize(scene.contacts.len(), 0.0);
            sc.lam_t.clear();
            sc.lam_t.resize(scene.contacts.len(), 0.0);
            sc.elements.resize(scene.hysteretic.len(), (0.0, 0.0));
            if self.state.out.keep_history {
                // (the running summary does not use them)
                self.forces.deformations(scene, &sc.fr, &mut sc.elements);
            }
        } else {
            let y = std::mem::take(&mut self.state.y);
            let r = self.dynamics_into(self.state.t, &y, true);
            self.state.y = y;
            r?;
        }
        let d = &self.ws.dynamics;
        let (contacts, elements) = &mut self.ws.sample_rows;
        contacts.clear();
        contacts.extend((0..scene.contacts.len()).map(|i| ContactSample {
            gap: d.kin[i].gap,
            gap_rate: d.kin[i].gap_rate,
            slip_rate: d.kin[i].slip_rate,
            normal_force: d.lam_n[i],
            tangential_force: d.lam_t[i],
            state: self.state.contacts[i],
        }));
        elements.clear();
        if self.state.out.keep_history {
            elements.extend(
                d.elements
                    .iter()
                    .zip(&self.state.laws)
                    .map(|(&(e, _), law)| (e, law.force(e))),
            );
        }
        let q = &self.state.y.as_slice()[..n];
        let v = &self.state.y.as_slice()[n..2 * n];
        let kinetic = 0.5
            * v.iter()
                .zip(scene.mass.as_slice())
                .map(|(a, m)| m * a * a)
                .sum::<f64>();
        let mut energy = self.energy_terms(kinetic, self.forces.spring_energy(scene, &d.fr));
        self.state.energy_scale = self.state.energy_scale.max(energy.scale());
        energy.closure = energy.balance();
        let (contacts, elements) = &self.ws.sample_rows;
        self.state.out.record(SampleView {
            t: self.state.t,
            kind,
            q,
            v,
            contacts,
            elements,
            energy,
        });
        Ok(())
    }

    pub(super) fn energy_terms(&self, kinetic: f64, elastic: f64) -> EnergySample {
        let n = self.n;
        EnergySample {
            kinetic,
            elastic,
            loads: self.state.y[2 * n],
            supports: self.state.y[2 * n + 1],
            damping: self.state.y[2 * n + 2],
            hysteretic: self.state.y[2 * n + 3],
            friction: self.state.y[2 * n + 4],
            impact_normal: -self.state.impact_normal,
            impact_tangential: -self.state.impact_tangential,
            initial: self.state.e0,
            closure: 0.0,
        }
    }

    pub(super) fn log(&mut self, rec: EventRecord) -> Result<(), SolverError> {
        if self.state.out.events.len() >= self.scene.settings.max_events {
            return Err(SolverError::TooManyEvents {
                t: self.state.t,
                limit: self.scene.settings.max_events,
            });
        }
        self.state.out.stats.count(rec.kind);
        self.state.out.events.push(rec);
        Ok(())
    }
}

/// Peaks of |q| over the step [t0, t1] from the dense output: the ends, and any interior
/// extremum (a sign change of q̇, located by Illinois), so peaks do not depend on the output
/// step.
pub(super) fn track_peaks(
    out: &mut RunOutput,
    step: &dopri::Step,
    t1: f64,
    n: usize,
    y1: &mut DVector<f64>,
) {
    if out.step_peaks.len() != n {
        out.step_peaks = vec![(0.0, 0.0); n];
    }
    if t1 >= step.t1() {
        y1.as_mut_slice().copy_from_slice(step.y1.as_slice());
    } else {
        step.dense_at_into(t1, y1);
    }
    for k in 0..n {
        let mut consider = |t: f64, q: f64| {
            if q.abs() > out.step_peaks[k].0 {
                out.step_peaks[k] = (q.abs(), t);
            }
        };
        consider(step.t0, step.y0[k]);
        consider(t1, y1[k]);
        let (v0, v1) = (step.y0[n + k], y1[n + k]);
        if v0 * v1 < 0.0 {
            // the extremum: q̇ = 0 by Illinois on the dense output, to 1e-9 of the step (q is
            // flat there: its error is of order q̈ (1e-9 h)²)
            let sign = v0.signum();
            let Ok::<_, std::convert::Infallible>((a, b)) = bracket_root(
                0.0,
                (t1 - step.t0) / step.h,
                v0 * sign,
                v1 * sign,
                1e-9,
                |m| Ok(step.dense_component(m, n + k) * sign),
            );
            let th = 0.5 * (a + b);
            consider(step.t0 + th * step.h, step.dense_component(th, k));
        }
    }
}
