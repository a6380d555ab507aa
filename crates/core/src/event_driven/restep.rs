//! The state at a located contact event. The root is found on the dense output, which is of
//! order 4 where the step is of order 5; a run that restarts from it at thousands of impacts
//! (ε = 1, a light abutment rattling against the deck) drifts off its energy balance. So the
//! state is taken from a DP5 step of its own from the step's start to the event, and for a
//! gap the remaining offset (of the order of the dense output's error) is removed by Newton's
//! method along the flow: Δt = −g_N/ġ_N, q ← q + Δt q̇ + ½ Δt² q̈, q̇ ← q̇ + Δt q̈.

use super::engine::Engine;
use super::event_fn::EventFn;
use crate::dopri;
use crate::output::ContactState;
use crate::run::SolverError;
use nalgebra::DVector;

/// Newton moves along the flow at most; each needs the gap only.
const NEWTON_MOVES: usize = 4;
/// Times the event may pass to a corner that crossed first.
const SWITCHES: usize = 3;
/// The largest move along the flow, as a fraction of the step to the event: beyond it the
/// gap is grazing (ġ_N ≈ 0) and the dense output's state is kept.
const MAX_MOVE: f64 = 1e-3;

/// The state `dt` along the flow from the end of `rs` (n DOFs), into `y`: q + Δt q̇ + ½ Δt² q̈,
/// q̇ + Δt q̈, and the ledger terms by their rates.
pub(super) fn move_along_flow(rs: &dopri::Step, n: usize, dt: f64, y: &mut DVector<f64>) {
    let (y1, f1) = (rs.y1.as_slice(), rs.f1.as_slice());
    let ys = y.as_mut_slice();
    for k in 0..n {
        ys[k] = y1[k] + dt * f1[k] + 0.5 * dt * dt * f1[n + k];
        ys[n + k] = y1[n + k] + dt * f1[n + k];
    }
    for k in 2 * n..ys.len() {
        ys[k] = y1[k] + dt * f1[k];
    }
}

impl Engine<'_> {
    /// The state at the event `f` located at `te` in `step` (started from `step.y0` with
    /// f(t0, y0) = `f0`), into `y`: returns the event's time and function, or None where the re-step is
    /// rejected by its error estimate or the gap cannot be moved onto its root (grazing) —
    /// then the caller keeps the dense output. `t_min`: no earlier time may be returned (an
    /// output sample was made there).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn state_at_event(
        &mut self,
        ws: &mut dopri::Workspace,
        step: &dopri::Step,
        f0: &DVector<f64>,
        f: EventFn,
        te: f64,
        t_min: f64,
        y: &mut DVector<f64>,
    ) -> Result<Option<(f64, EventFn)>, SolverError> {
        let st = &self.scene.settings;
        let (t0, tau) = (step.t0, te - step.t0);
        if tau <= 0.0 {
            return Ok(None);
        }
        let n = self.n;
        let mut rhs = |t: f64, y: &DVector<f64>, out: &mut DVector<f64>| self.rhs(t, y, out);
        dopri::step_into(ws, &mut rhs, t0, &step.y0, f0, tau, st.rtol, st.atol, 2 * n)?;
        let rs = &ws.step;
        if rs.error.is_nan() || rs.error > 1.0 || rs.y1.iter().any(|x| !x.is_finite()) {
            return Ok(None);
        }
        y.as_mut_slice().copy_from_slice(rs.y1.as_slice());
        let mut i = match f {
            EventFn::Gap(i) => i,
            EventFn::Unseat(k) => {
                // width − g_N: Newton on the gap with the seat's edge as its zero
                let seat = &self.scene.seats[k];
                let (i, w) = (seat.contact, seat.edge);
                let dt = self.newton_on_gap(rs, i, w, te, 0.0, tau, y)?;
                return Ok(dt
                    .map(|dt| (te + dt, f))
                    .filter(|(t, _)| *t > t_min && *t <= step.t1()));
            }
            EventFn::Release(i) => {
                return self.release_state(ws, step, f0, (i, te, t_min), y);
            }
            _ => return Ok(Some((te, f))),
        };
        // Newton on g_N(te + Δt) along the Taylor polynomial of the flow at (te, y1); a corner
        // that this trajectory has taken through its face first (two crossings closer than the
        // dense output's error) takes the event over
        let mut dt = 0.0;
        for _ in 0..=SWITCHES {
            dt = match self.newton_on_gap(rs, i, 0.0, te, dt, tau, y)? {
                Some(dt) => dt,
                None => return Ok(None),
            };
            match self.earlier_crossing(i, te + dt, te - t0, y)? {
                Some(k) => i = k,
                None => {
                    let t = te + dt;
                    let ok = t > t_min && t <= step.t1();
                    return Ok(ok.then_some((t, EventFn::Gap(i))));
                }
            }
        }
        Ok(None)
    }

    /// Newton on the gap of contact `i` less `edge` (0: the face; a seat's width: the seat's
    /// edge, reached from below) from the move `dt` along the flow at the end of `rs` (the
    /// state in `y`): the move that closes it to the gap threshold, or None (not
    /// approaching, or a move beyond [`MAX_MOVE`]).
    #[allow(clippy::too_many_arguments)]
    fn newton_on_gap(
        &mut self,
        rs: &dopri::Step,
        i: usize,
        edge: f64,
        te: f64,
        mut dt: f64,
        tau: f64,
        y: &mut DVector<f64>,
    ) -> Result<Option<f64>, SolverError> {
        let n = self.n;
        let one = [EventFn::Gap(i)];
        let thr = self.threshold(one[0]);
        for _ in 0..=NEWTON_MOVES {
            // the distance to the crossing, and its rate: g − 0 closing from above, or
            // edge − g closing from below
            let g = self.event_values(te + dt, y, &one)?[0];
            let (g, rate) = match edge {
                0.0 => (g, self.ws.gap_rates[0]),
                w => (w - g, -self.ws.gap_rates[0]),
            };
            if g.abs() <= thr {
                return Ok(Some(dt));
            }
            if rate.is_nan() || rate >= 0.0 {
                return Ok(None);
            }
            dt -= g / rate;
            if dt.is_nan() || dt.abs() > MAX_MOVE * tau {
                return Ok(None);
            }
            move_along_flow(rs, n, dt, y);
        }
        Ok(None)
    }

    /// The state at the release of contact `i` located at `te`, after the re-step in `ws`
    /// (its end in `y`). Where that state, projected onto the closed constraints as the event
    /// will be, pulls (λ_N < −threshold/100: its root on the dense output lies after the
    /// root of the re-stepped trajectory, by the dense output's error and the drift), the
    /// secant method on that λ_N over the re-step's length, each iterate a DP5 step of its own
    /// from the step's start, moves it back onto λ_N ∈ [−threshold/100, threshold]; so the state
    /// before the release exerts no pull. Returns the event's time (`te` where no move was
    /// needed or none was found after `t_min`, `y` then the first re-step's end).
    fn release_state(
        &mut self,
        ws: &mut dopri::Workspace,
        step: &dopri::Step,
        f0: &DVector<f64>,
        (i, te, t_min): (usize, f64, f64),
        y: &mut DVector<f64>,
    ) -> Result<Option<(f64, EventFn)>, SolverError> {
        let f = EventFn::Release(i);
        let thr = self.threshold(f);
        let ok = |v: f64| v <= thr && v >= -1e-2 * thr;
        let fe = self.projected_force(i, te, y)?;
        if fe >= -1e-2 * thr || !fe.is_finite() {
            return Ok(Some((te, f)));
        }
        let (t0, tau) = (step.t0, te - step.t0);
        let st = &self.scene.settings;
        let (rtol, atol, n) = (st.rtol, st.atol, self.n);
        // a probe along the flow at the re-step's end for the rate, then secant steps
        let mut moved = y.clone();
        let probe = -1e-6 * tau;
        move_along_flow(&ws.step, n, probe, &mut moved);
        let (mut a, mut fa) = (te, fe);
        let (mut b, mut fb) = (te + probe, self.projected_force(i, te + probe, &moved)?);
        for _ in 0..=NEWTON_MOVES {
            if ok(fb) {
                y.copy_from(&moved);
                return Ok((b > t_min).then_some((b, f)));
            }
            if !fb.is_finite() || fb == fa {
                break;
            }
            let next = b - fb * (b - a) / (fb - fa);
            if next.is_nan() || next <= t0.max(t_min) || next > te {
                break;
            }
            let mut rhs = |t: f64, y: &DVector<f64>, out: &mut DVector<f64>| self.rhs(t, y, out);
            dopri::step_into(ws, &mut rhs, t0, &step.y0, f0, next - t0, rtol, atol, 2 * n)?;
            let rs = &ws.step;
            if rs.error.is_nan() || rs.error > 1.0 || rs.y1.iter().any(|x| !x.is_finite()) {
                break;
            }
            moved.copy_from(&rs.y1);
            (a, fa) = (b, fb);
            (b, fb) = (next, self.projected_force(i, next, &moved)?);
        }
        // none found: the first re-step's end, and its step back in `ws` for the samples
        // before the event
        if b != te + probe {
            let mut rhs = |t: f64, y: &DVector<f64>, out: &mut DVector<f64>| self.rhs(t, y, out);
            dopri::step_into(ws, &mut rhs, t0, &step.y0, f0, tau, rtol, atol, 2 * n)?;
        }
        Ok(Some((te, f)))
    }

    /// λ_N of contact `i` at (t, y) projected onto the closed constraints ([`Engine::project`]);
    /// the engine's state is left as it was.
    fn projected_force(&mut self, i: usize, t: f64, y: &DVector<f64>) -> Result<f64, SolverError> {
        let (t_was, y_was) = (
            self.state.t,
            std::mem::replace(&mut self.state.y, y.clone()),
        );
        self.state.t = t;
        self.project();
        let yp = std::mem::replace(&mut self.state.y, y_was);
        self.state.t = t_was;
        Ok(self.event_values(t, &yp, &[EventFn::Release(i)])?[0])
    }

    /// An open contact other than `i` that is through its face at (t, y) and approaching, and
    /// went through within the last `span` (g_N/ġ_N ago): the one that went through first.
    fn earlier_crossing(
        &mut self,
        i: usize,
        t: f64,
        span: f64,
        y: &DVector<f64>,
    ) -> Result<Option<usize>, SolverError> {
        let open: Vec<EventFn> = (0..self.state.contacts.len())
            .filter(|&k| k != i && self.state.contacts[k] == ContactState::Open)
            .map(EventFn::Gap)
            .collect();
        if open.is_empty() {
            return Ok(None);
        }
        let vals = self.event_values(t, y, &open)?;
        let mut first: Option<(usize, f64)> = None;
        for (m, f) in open.iter().enumerate() {
            let (g, rate) = (vals[m], self.ws.gap_rates[m]);
            let ago = g / rate;
            if g < -self.threshold(*f)
                && rate < 0.0
                && ago < span
                && first.is_none_or(|b| ago > b.1)
                && let EventFn::Gap(k) = *f
            {
                first = Some((k, ago));
            }
        }
        Ok(first.map(|b| b.0))
    }
}
