//! One event function's value and rate on a step's dense output, from the bodies it reads
//! alone: no frame of every body, no dynamics.

use super::engine::Engine;
use super::event_fn::EventFn;
use super::workspace::ProbeScratch;
use crate::dopri::{self, dense_value};
use crate::output::ContactState;
use crate::scene::{BodyRef, BodyState, Scene};

impl ProbeScratch {
    /// A new step: nothing loaded.
    pub(super) fn reset(&mut self) {
        self.loaded.fill(false);
        self.posed.fill(false);
    }

    /// The pose of body `b` at `t` (θ in the step; 1 at its end, where y = y1).
    fn pose(
        &mut self,
        scene: &Scene,
        step: &dopri::Step,
        b: usize,
        (t, theta): (f64, f64),
    ) -> BodyState {
        let nb = scene.bodies.len();
        if self.loaded.len() != nb {
            let n = scene.ndof();
            self.coef.resize(2 * n, [0.0; 5]);
            (self.loaded, self.posed) = (vec![false; nb], vec![false; nb]);
            self.poses.resize(nb, BodyState::default());
        }
        if self.at != (t, theta) {
            self.at = (t, theta);
            self.posed.fill(false);
        }
        if self.posed[b] {
            return self.poses[b];
        }
        let n = self.coef.len() / 2;
        let dofs = scene.bodies[b].dofs.into_iter().flatten();
        if !self.loaded[b] {
            for k in dofs.clone() {
                self.coef[k] = step.dense_coefficients(k);
                self.coef[n + k] = step.dense_coefficients(n + k);
            }
            self.loaded[b] = true;
        }
        let s = if theta == 1.0 {
            let y = step.y1.as_slice();
            scene.body_state_with(b, t, |k| y[k], |k| y[n + k])
        } else {
            let c = &self.coef;
            scene.body_state_with(
                b,
                t,
                |k| dense_value(&c[k], theta),
                |k| dense_value(&c[n + k], theta),
            )
        };
        (self.poses[b], self.posed[b]) = (s, true);
        s
    }
}

impl Engine<'_> {
    /// (f, ḟ) at `t` on the dense output of `step`, as [`Engine::event_values_into`] gives
    /// them (ḟ NaN for a slide stop and a load reversal); None for λ_N and μ λ_N − |λ_T|,
    /// which need the dynamics.
    pub(super) fn probe(&mut self, step: &dopri::Step, f: EventFn, t: f64) -> Option<(f64, f64)> {
        let scene = self.scene;
        let at = (t, dense_theta(step, t));
        let ps = &mut self.ws.probe;
        let mut pose = |r: BodyRef| match r {
            BodyRef::Ground => BodyState::default(),
            BodyRef::Body(i) => ps.pose(scene, step, i, at),
        };
        let mut contact = |i: usize| {
            let c = &scene.contacts[i];
            let (a, b) = (pose(c.point_body), pose(c.face_body));
            scene.contact_rates_between(&a, &b, c)
        };
        Some(match f {
            EventFn::Gap(i) => {
                let (g, g_rate, _) = contact(i);
                (g, g_rate)
            }
            EventFn::Unseat(k) => {
                let seat = &scene.seats[k];
                let (g, g_rate, _) = contact(seat.contact);
                (seat.edge - g, -g_rate)
            }
            EventFn::SlideStop(i) => {
                let s = match self.state.contacts[i] {
                    ContactState::Slide(s) => s,
                    _ => 1.0,
                };
                (s * contact(i).2, f64::NAN)
            }
            EventFn::Lower(j) | EventFn::Upper(j) | EventFn::Reversal(j) => {
                let el = &scene.hysteretic[j];
                let (a, b) = el.attachment.bodies();
                let pa = ps.pose(scene, step, a, at);
                let pb = b.map_or(pa, |b| ps.pose(scene, step, b, at));
                let sup = (el.support).map_or((0.0, 0.0, 0.0), |s| scene.supports[s].at(t));
                let (e, ed) = scene.deformation_value(&el.attachment, &pa, &pb, sup);
                let b = self.state.laws[j].branch();
                match f {
                    EventFn::Lower(_) => (e - b.lower, ed),
                    EventFn::Upper(_) => (b.upper - e, -ed),
                    _ => (b.direction * ed, f64::NAN),
                }
            }
            EventFn::Release(_) | EventFn::StickSlip(_) => return None,
        })
    }
}

/// θ of `t` in `step`, as [`dopri::Step::dense_at_into`] takes it.
#[inline]
fn dense_theta(step: &dopri::Step, t: f64) -> f64 {
    if step.h == 0.0 {
        0.0
    } else {
        ((t - step.t0) / step.h).clamp(0.0, 1.0)
    }
}
