//! The driver: start (initial state and contact resolution), the step loop (DP5 step, event
//! search, grid samples, events, restart), finish.

use super::engine::Engine;
use super::event_fn::EventFn;
use super::events::{arm, arm_into, due_now};
use super::locate::locate_event;
use super::record::track_peaks;
use super::restep::move_along_flow;
use crate::dopri::{self, Controller};
use crate::hysteresis::Hysteretic;
use crate::output::{ContactState, EventRecord, FinalState, RunOutput, SampleKind};
use crate::run::{Batcher, Observer, SolverError};
use crate::scene::{LEDGER_TERMS, Scene};
use nalgebra::DVector;
use std::time::Instant;

/// A run in progress: the engine, the integrator's state between steps, reused storage.
pub(super) struct Integration<'a> {
    pub(super) eng: Engine<'a>,
    pub(super) clock: Clock,
    pub(super) batcher: Batcher,
    pub(super) ws: dopri::Workspace,
    /// The step to a located contact event ([`Engine::state_at_event`]).
    pub(super) ws_event: dopri::Workspace,
}

/// The integrator's state between steps (cloned with the engine's state by a fork).
#[derive(Clone)]
pub(super) struct Clock {
    pub(super) breakpoints: Vec<f64>,
    /// The longest step while a contact is closed ([`crate::scene::Scene::closed_step_cap`]).
    pub(super) closed_cap: f64,
    pub(super) bp: usize,
    /// Index of the next output grid instant.
    pub(super) next_out: usize,
    pub(super) ctrl: Controller,
    /// f(t, y) at the current state (FSAL).
    pub(super) f0: DVector<f64>,
    /// The next step size.
    pub(super) h: f64,
    pub(super) h_min: f64,
    /// The state at the start of the current step.
    pub(super) y0: DVector<f64>,
    pub(super) fns: Vec<EventFn>,
    pub(super) armed: Vec<bool>,
    pub(super) rhs_evals: usize,
    /// Seconds spent so far.
    pub(super) wall: f64,
    /// Events located at `eng.state.t` (in `eng.state.cluster`) and not applied yet: the run
    /// paused there.
    pub(super) pending: bool,
    /// (start, events located since) of the current stall window.
    pub(super) stall: (f64, usize),
    /// Where this advance ends (`t_end`, or the end of an island's window).
    pub(super) stop: f64,
    /// Pause at the first step end at or after this instant with every contact open (the
    /// whole scene of an islands run, `islands.rs`).
    pub(super) split_after: Option<f64>,
    /// An island's integration (`islands.rs`): it keeps each accepted step of the current
    /// window (`kept`) and pauses at a key's failure as at a contact event.
    pub(super) island: bool,
    pub(super) kept: Kept,
}

/// An island's accepted steps of the current window, with the laws along each.
#[derive(Clone, Default)]
pub(super) struct Kept {
    /// (step, index in `laws`).
    steps: Vec<(dopri::Step, usize)>,
    n: usize,
    /// The laws along the steps: a new entry after each event.
    laws: Vec<Vec<Hysteretic>>,
    n_laws: usize,
    /// `fns_generation` of the last entry of `laws` (every event makes a new list).
    generation: u64,
}

impl Kept {
    /// A new window.
    pub(super) fn clear(&mut self) {
        (self.n, self.n_laws) = (0, 0);
    }

    /// The window's steps, each with the index of its laws.
    pub(super) fn steps(&self) -> &[(dopri::Step, usize)] {
        &self.steps[..self.n]
    }

    pub(super) fn laws(&self, k: usize) -> &[Hysteretic] {
        &self.laws[k]
    }

    /// The step holding `t` (the last that starts at or before it).
    pub(super) fn at(&self, t: f64) -> Option<&(dopri::Step, usize)> {
        self.steps().iter().rev().find(|(s, _)| s.t0 <= t)
    }

    #[cold]
    #[inline(never)]
    fn push(&mut self, step: &dopri::Step, laws: &[Hysteretic], generation: u64) {
        if self.n_laws == 0 || generation != self.generation {
            if self.n_laws == self.laws.len() {
                self.laws.push(laws.to_vec());
            } else {
                self.laws[self.n_laws].clone_from_slice(laws);
            }
            self.n_laws += 1;
            self.generation = generation;
        }
        let k = self.n_laws - 1;
        if self.n == self.steps.len() {
            self.steps.push((step.clone(), k));
        } else {
            self.steps[self.n].0.clone_from(step);
            self.steps[self.n].1 = k;
        }
        self.n += 1;
    }
}

/// Located events within [`STALL_WINDOW`] × max(t_end, 1 s) that mean time has stopped
/// advancing (a legitimate run has thousands of times fewer).
const STALL_EVENTS: usize = 10_000;
const STALL_WINDOW: f64 = 1e-6;

/// The outcome of one step attempt.
enum Attempt {
    /// Error estimate above tolerance: retry with the smaller step.
    Rejected,
    /// The state moved to the step's end, or to the first event located in it (`Some(t)`).
    Accepted(Option<f64>),
}

impl<'a> Integration<'a> {
    /// The initial state, its contact resolution and the first step's data.
    pub(super) fn start(scene: &'a Scene) -> Result<Self, SolverError> {
        let wall = Instant::now();
        let n = scene.ndof();
        let st = &scene.settings;
        check_stiffness(scene)?;
        let mut eng = Engine::new(scene)?;
        settle_initial(&mut eng)?;
        let mut f0 = DVector::zeros(y_len(n));
        {
            let y0 = eng.state.y.clone();
            eng.rhs(0.0, &y0, &mut f0)?;
        }
        let mut h =
            dopri::initial_h(&eng.state.y, &f0, st.rtol, st.atol, 2 * n).min(st.t_end / 10.0);
        if st.h_max > 0.0 {
            h = h.min(st.h_max);
        }
        let fns = eng.event_fns();
        let armed = arm(&mut eng, &fns)?;
        let mut it = Self::with_clock(eng, f0, h, fns, armed);
        it.clock.next_out = 1;
        it.clock.wall = wall.elapsed().as_secs_f64();
        Ok(it)
    }

    /// The integration of `eng` at its present state: f(t, y) = `f0`, the first step `h`, the
    /// event functions `fns` and their arming; output from the first grid instant on
    /// (`next_out` 0), the stall window from now.
    pub(super) fn with_clock(
        eng: Engine<'a>,
        f0: DVector<f64>,
        h: f64,
        fns: Vec<EventFn>,
        armed: Vec<bool>,
    ) -> Self {
        let scene = eng.scene;
        let st = &scene.settings;
        let clock = Clock {
            breakpoints: scene.breakpoints(),
            closed_cap: scene.closed_step_cap(),
            bp: 0,
            next_out: 0,
            ctrl: Controller::default(),
            y0: DVector::zeros(f0.len()),
            f0,
            h,
            h_min: 1e-14 * st.t_end.max(1.0),
            fns,
            armed,
            rhs_evals: 1,
            wall: 0.0,
            pending: false,
            stall: (eng.state.t, 0),
            stop: st.t_end,
            split_after: None,
            island: false,
            kept: Kept::default(),
        };
        Self {
            eng,
            clock,
            batcher: Batcher::new(),
            ws: dopri::Workspace::default(),
            ws_event: dopri::Workspace::default(),
        }
    }

    /// Integrate to the end, or, with `pause_at_contact`, until a contact event is located
    /// (returns true, the event not yet applied).
    pub(super) fn advance(
        &mut self,
        observer: &mut dyn Observer,
        pause_at_contact: bool,
    ) -> Result<bool, SolverError> {
        let wall = Instant::now();
        let r = self.advance_in(observer, pause_at_contact);
        self.clock.wall += wall.elapsed().as_secs_f64();
        r
    }

    fn advance_in(
        &mut self,
        observer: &mut dyn Observer,
        pause_at_contact: bool,
    ) -> Result<bool, SolverError> {
        let st = &self.eng.scene.settings;
        loop {
            let found;
            if self.clock.pending {
                self.clock.pending = false;
                found = Some(self.eng.state.t);
            } else {
                if self.eng.state.t >= self.clock.stop {
                    return Ok(false);
                }
                let stats = &self.eng.state.out.stats;
                if stats.steps_accepted + stats.steps_rejected >= st.max_steps {
                    return Err(SolverError::TooManySteps {
                        t: self.eng.state.t,
                        limit: st.max_steps,
                    });
                }
                match self.attempt(observer)? {
                    Attempt::Rejected => continue,
                    Attempt::Accepted(f) => found = f,
                }
                let cluster = &self.eng.state.cluster;
                let contact = cluster.iter().any(|f| !f.is_branch())
                    || (self.clock.island && cluster.iter().any(|&f| self.key_fails(f)));
                if found.is_some() && pause_at_contact && contact {
                    self.clock.pending = true;
                    return Ok(true);
                }
            }
            let restart = if found.is_some() {
                self.check_stall()?;
                let cluster = std::mem::take(&mut self.eng.state.cluster);
                for &f in &cluster {
                    self.eng.state.out.stats.events_located += 1;
                    process_event(&mut self.eng, f)?;
                }
                self.eng.state.cluster = cluster;
                true
            } else if self
                .eng
                .state
                .contacts
                .iter()
                .any(|s| *s != ContactState::Open)
            {
                self.eng.project() > 0.0
            } else {
                false
            };
            if restart {
                self.restart()?;
            } else {
                let f1 = self.ws.step.f1.as_slice();
                self.clock.f0.as_mut_slice().copy_from_slice(f1);
            }
            self.batcher
                .maybe(&self.eng.state.out, self.eng.state.t, observer)?;
            if self.splits_here() {
                return Ok(true);
            }
        }
    }

    /// Event `f` is the failure of a shear key (rule G5).
    #[cold]
    fn key_fails(&self, f: EventFn) -> bool {
        match f {
            EventFn::Upper(j) => {
                let law = &self.eng.state.laws[j];
                law.fails_at(law.branch().upper, 1.0)
            }
            _ => false,
        }
    }

    /// At or after `split_after`, not at the end, no event pending, every contact open.
    fn splits_here(&self) -> bool {
        let t = self.eng.state.t;
        self.clock.split_after.is_some_and(|ts| t >= ts)
            && !self.clock.pending
            && t < self.clock.stop
            && (self.eng.state.contacts.iter()).all(|s| *s == ContactState::Open)
    }

    /// One DP5 step from the current state (to the next breakpoint at most), the event search
    /// on its dense output, the grid samples inside it and the move to its end or first event.
    /// The grid samples go to `observer` as they are made (a long step over a quiet stretch
    /// holds many).
    #[inline(never)]
    fn attempt(&mut self, observer: &mut dyn Observer) -> Result<Attempt, SolverError> {
        let Integration {
            eng,
            clock,
            ws,
            ws_event,
            batcher,
        } = self;
        let Clock {
            breakpoints,
            closed_cap,
            bp,
            next_out,
            ctrl,
            f0,
            h,
            h_min,
            y0,
            fns,
            armed,
            rhs_evals,
            stop,
            island,
            kept,
            ..
        } = clock;
        let scene = eng.scene;
        let st = &scene.settings;
        let n = eng.n;
        let t_stop = next_stop(breakpoints, bp, eng.state.t, *stop);
        let mut hh = h.min(t_stop - eng.state.t);
        if st.h_max > 0.0 {
            hh = hh.min(st.h_max);
        }
        if eng.state.contacts.iter().any(|s| *s != ContactState::Open) {
            hh = hh.min(*closed_cap);
        }
        if t_stop - eng.state.t - hh < 1e-12 * hh {
            hh = t_stop - eng.state.t;
        }
        y0.as_mut_slice().copy_from_slice(eng.state.y.as_slice());
        let t0 = eng.state.t;
        let mut rhs = |t: f64, y: &DVector<f64>, out: &mut DVector<f64>| {
            *rhs_evals += 1;
            eng.rhs(t, y, out)
        };
        dopri::step_into(ws, &mut rhs, t0, y0, f0, hh, st.rtol, st.atol, 2 * n)?;
        let step = &ws.step;
        let finite = step.y1.as_slice().iter().all(|x| x.is_finite());
        if !finite || step.error > 1.0 {
            eng.state.out.stats.steps_rejected += 1;
            *h = if finite {
                ctrl.next_h(hh, step.error, false)
            } else {
                hh * 0.25
            };
            if *h < *h_min {
                return Err(if finite {
                    SolverError::StepTooSmall { t: t0, h: *h }
                } else {
                    SolverError::NonFinite { t: t0 }
                });
            }
            return Ok(Attempt::Rejected);
        }
        eng.state.out.stats.steps_accepted += 1;
        if let Some(c) = eng.state.out.stats.step_control.get_mut(step.worst) {
            *c += 1;
        }
        *h = ctrl.next_h(hh, step.error, true);
        if *island {
            kept.push(step, &eng.state.laws, eng.state.fns_generation);
        }
        // event search on the dense output
        // the output instants inside the step
        let mut grid = [0.0; 16];
        let mut ng = 0;
        while ng < grid.len() {
            let tg = (*next_out + ng) as f64 * st.output_dt;
            if tg >= step.t1() {
                break;
            }
            grid[ng] = tg;
            ng += 1;
        }
        let found = locate_event(eng, step, fns, armed, &grid[..ng])?;
        let t1 = found.unwrap_or(step.t1());
        track_peaks(&mut eng.state.out, step, t1, n, y0);
        // grid output inside (t0, t1]
        let mut t_min = t0;
        let closed = eng.state.contacts.iter().any(|s| *s != ContactState::Open);
        while (*next_out as f64) * st.output_dt <= t1 * (1.0 + 1e-14) && eng.state.t < st.t_end {
            let tg = (*next_out as f64) * st.output_dt;
            if tg > t1 {
                break;
            }
            eng.state.t = tg.min(st.t_end);
            step.dense_at_into(eng.state.t, &mut eng.state.y);
            grid_sample(eng, closed, next_out, batcher, observer)?;
            t_min = eng.state.t;
        }
        eng.state.t = t1;
        match found {
            Some(_) => {
                if move_to_event(eng, ws_event, step, f0, t_min)? {
                    sample_before_moved_event(eng, ws_event, next_out, batcher, observer)?;
                }
            }
            None => (eng.state.y.as_mut_slice()).copy_from_slice(step.y1.as_slice()),
        }
        Ok(Attempt::Accepted(found))
    }

    /// Time that stops advancing (events located again and again at nearly one instant) is
    /// an error with the contacts' state, within [`STALL_EVENTS`] events.
    pub(super) fn check_stall(&mut self) -> Result<(), SolverError> {
        let t = self.eng.state.t;
        let window = STALL_WINDOW * self.eng.scene.settings.t_end.max(1.0);
        let (start, count) = &mut self.clock.stall;
        if t - *start > window {
            (*start, *count) = (t, 0);
        }
        *count += 1;
        if *count >= STALL_EVENTS {
            return Err(SolverError::Stalled {
                t,
                since: *start,
                events: *count,
                contacts: self.eng.describe_contacts(),
            });
        }
        Ok(())
    }

    /// A new phase after events or a projection: f(t, y), the event functions and their arming;
    /// then the events already due at this instant (simultaneous crossings, e.g. symmetric
    /// columns reversing together), each processed before any step.
    fn restart(&mut self) -> Result<(), SolverError> {
        self.rearm()?;
        let mut done: Vec<EventFn> = Vec::new();
        while let Some(f) = due_now(&mut self.eng, &self.clock.fns, &done)? {
            done.push(f);
            process_event(&mut self.eng, f)?;
            self.rearm()?;
        }
        Ok(())
    }

    /// f(t, y) at the current state, the event functions of the contact mode and their arming.
    pub(super) fn rearm(&mut self) -> Result<(), SolverError> {
        let (eng, clock) = (&mut self.eng, &mut self.clock);
        // the state is lent to the right-hand side (which does not read `state.y`), not cloned
        let y1 = std::mem::take(&mut eng.state.y);
        let t = eng.state.t;
        clock.rhs_evals += 1;
        let r = eng.rhs(t, &y1, &mut clock.f0);
        eng.state.y = y1;
        r?;
        eng.event_fns_into(&mut clock.fns);
        arm_into(eng, &clock.fns, &mut clock.armed)
    }

    /// The output, with the final sample (if `complete`: the run reached its end), statistics
    /// and summary.
    pub(super) fn finish(mut self, observer: &mut dyn Observer, complete: bool) -> RunOutput {
        let wall = Instant::now();
        let eng = &mut self.eng;
        let st = &eng.scene.settings;
        if complete
            && eng
                .state
                .out
                .last_sample_time()
                .is_none_or(|t| t < st.t_end)
        {
            // a failure here leaves the last sample where it was
            let _ = eng.record_sample(SampleKind::Grid);
        }
        self.batcher.flush(&eng.state.out, eng.state.t, observer);
        eng.state.out.stats.rhs_evals = self.clock.rhs_evals;
        eng.state.out.final_laws = eng.state.laws.clone();
        let n = eng.n;
        eng.state.out.final_state = FinalState {
            t: eng.state.t,
            q: eng.state.y.as_slice()[..n].to_vec(),
            v: eng.state.y.as_slice()[n..2 * n].to_vec(),
        };
        eng.state.out.stats.wall_time = self.clock.wall + wall.elapsed().as_secs_f64();
        eng.state.out.finish(eng.state.energy_scale);
        std::mem::replace(&mut eng.state.out, RunOutput::new(eng.scene))
    }
}

/// The state at the event located at `eng.state.t` in `step`: a contact event from a step
/// of its own ([`Engine::state_at_event`]; it may move the event's instant by Newton, or pass
/// it to a corner that went through first), branch changes (and a contact event that cannot
/// be re-stepped) from the dense output.
fn move_to_event(
    eng: &mut Engine,
    ws_event: &mut dopri::Workspace,
    step: &dopri::Step,
    f0: &DVector<f64>,
    t_min: f64,
) -> Result<bool, SolverError> {
    let t1 = eng.state.t;
    let contact = match eng.state.cluster[..] {
        [f] if !f.is_branch() => Some(f),
        _ => None,
    };
    let mut y = std::mem::take(&mut eng.state.y);
    let at = match contact {
        Some(f) => eng.state_at_event(ws_event, step, f0, f, t1, t_min, &mut y),
        None => Ok(None),
    };
    eng.state.y = y;
    match at? {
        Some((t, f)) => {
            eng.state.t = t;
            eng.state.cluster[0] = f;
            Ok(true)
        }
        None => {
            step.dense_at_into(t1, &mut eng.state.y);
            Ok(false)
        }
    }
}

/// The output instants a Newton move along the flow carried the event past (`restep.rs`):
/// sampled on that move (from the re-step's end, `ws_event`), before the event. Without them
/// an instant just before the event was sampled after it, on the next step's dense output
/// taken backwards through the impact (a corner 1.1e-6 m inside a rigid abutment's face).
fn sample_before_moved_event(
    eng: &mut Engine,
    ws_event: &dopri::Workspace,
    next_out: &mut usize,
    batcher: &mut Batcher,
    observer: &mut dyn Observer,
) -> Result<(), SolverError> {
    let st = &eng.scene.settings;
    let (t_ev, dt_out, t_end) = (eng.state.t, st.output_dt, st.t_end);
    if (*next_out as f64) * dt_out > t_ev || t_ev >= t_end {
        return Ok(());
    }
    let at_event = eng.state.y.clone();
    let closed = eng.state.contacts.iter().any(|s| *s != ContactState::Open);
    let rs = &ws_event.step;
    while (*next_out as f64) * dt_out <= t_ev {
        let tg = (*next_out as f64) * dt_out;
        move_along_flow(rs, eng.n, tg - rs.t1(), &mut eng.state.y);
        eng.state.t = tg;
        grid_sample(eng, closed, next_out, batcher, observer)?;
    }
    eng.state.t = t_ev;
    eng.state.y = at_event;
    Ok(())
}

/// The grid sample of the state at `eng.state.t` (from a step's dense output or a move along
/// the flow), projected like the step ends when a contact is closed: both leave the closed
/// constraints by their own error.
fn grid_sample(
    eng: &mut Engine,
    closed: bool,
    next_out: &mut usize,
    batcher: &mut Batcher,
    observer: &mut dyn Observer,
) -> Result<(), SolverError> {
    if closed {
        eng.project();
    }
    eng.record_sample(SampleKind::Grid)?;
    batcher.maybe(&eng.state.out, eng.state.t, observer)?;
    *next_out += 1;
    Ok(())
}

/// The next breakpoint after `t` (`bp` moved to it), or `stop` if that is earlier.
fn next_stop(breakpoints: &[f64], bp: &mut usize, t: f64, stop: f64) -> f64 {
    while *bp < breakpoints.len() && breakpoints[*bp] <= t * (1.0 + 1e-15) {
        *bp += 1;
    }
    breakpoints.get(*bp).map_or(stop, |b| b.min(stop))
}

/// Explicit DP5 needs h ≤ 3.3/|λ| for the fastest eigenvalue of the linearised system: ω of the
/// stiffest mode (its stability region on the imaginary axis) or the decay rate c Jᵀ M⁻¹ J of
/// the stiffest dashpot (on the real axis). A run that cannot finish within `max_steps` is
/// refused before it starts.
fn check_stiffness(scene: &Scene) -> Result<(), SolverError> {
    let st = &scene.settings;
    let modes = crate::modal::modes(scene).last().map_or(0.0, |m| m.omega);
    let omega = modes.max(damping_rate(scene));
    let steps = st.t_end * omega / DP5_IMAGINARY_STABILITY;
    if steps > st.max_steps as f64 {
        return Err(SolverError::TooStiff {
            omega,
            steps,
            limit: st.max_steps,
        });
    }
    Ok(())
}

/// The largest decay rate of a single dashpot, c Σ J_k²/m_k, and of the mass-proportional
/// damping a₀, 1/s.
fn damping_rate(scene: &Scene) -> f64 {
    let z = DVector::zeros(scene.ndof());
    let fr = scene.frame(0.0, &z, &z);
    let rate = |att, support, c: f64| {
        let (.., jac, nj) = scene.deformation(&fr, att, support);
        let g: f64 = jac[..nj].iter().map(|&(k, j)| j * j / scene.mass[k]).sum();
        c * g
    };
    let springs = scene
        .springs
        .iter()
        .map(|s| rate(&s.attachment, s.support, s.damping));
    let columns = (scene.hysteretic.iter()).map(|h| rate(&h.attachment, h.support, h.damping));
    springs
        .chain(columns)
        .fold(scene.mass_damping.alpha, f64::max)
}

/// Extent of DP5's stability region along the imaginary axis (Hairer & Wanner, *Solving ODEs
/// II*, §IV.2), rounded up so that the estimate of the steps needed is a lower bound.
const DP5_IMAGINARY_STABILITY: f64 = 3.5;

/// The initial instant: a pre-event sample if resolving it makes events (then the post-event
/// one), else a grid sample.
fn settle_initial(eng: &mut Engine) -> Result<(), SolverError> {
    let n_events = eng.state.out.events.len();
    let initial = {
        let mut silent = RunOutput::new(eng.scene);
        std::mem::swap(&mut eng.state.out, &mut silent);
        let r = eng.record_sample(SampleKind::PreEvent);
        std::mem::swap(&mut eng.state.out, &mut silent);
        r?;
        silent.samples.pop()
    };
    eng.resolve(None)?;
    eng.ws.new_contact_mode();
    if eng.state.out.events.len() > n_events {
        if let Some(pre) = initial {
            eng.state.out.record(pre.view());
        }
        eng.record_sample(SampleKind::PostEvent)
    } else {
        eng.record_sample(SampleKind::Grid)
    }
}

/// Apply one located event at the current instant: a branch change of a hysteretic element,
/// or a contact event (the LCPs decide the new state).
pub(super) fn process_event(eng: &mut Engine, f: EventFn) -> Result<(), SolverError> {
    eng.ws.dynamics.at = None;
    match f {
        EventFn::Lower(j) | EventFn::Upper(j) | EventFn::Reversal(j) => {
            let b = *eng.state.laws[j].branch();
            let e = eng.element_deformation(j).0;
            let (e_at, dir) = match f {
                EventFn::Lower(_) => (b.lower, -1.0),
                EventFn::Upper(_) => (b.upper, 1.0),
                _ => (e, -b.direction),
            };
            if eng.state.laws[j].fails_at(e_at, dir) {
                return key_failure(eng, j, e_at, dir);
            }
            eng.state.laws[j].on_branch_end(e_at, dir);
            eng.state.out.stats.branch_events += 1;
        }
        EventFn::Unseat(k) => {
            eng.record_sample(SampleKind::PreEvent)?;
            let seat = &eng.scene.seats[k];
            let i = seat.contact;
            return Err(SolverError::Unseated {
                t: eng.state.t,
                contact: eng.scene.contacts[i].name.clone(),
                gap: eng.contact_kinematics_now(i).gap,
                width: seat.width,
            });
        }
        _ => {
            if eng.state.contacts.iter().any(|s| *s != ContactState::Open) {
                // the state reached from the step's start, back on the closed constraints
                eng.project();
            }
            eng.record_sample(SampleKind::PreEvent)?;
            eng.resolve(Some(f))?;
            eng.ws.new_contact_mode();
            eng.record_sample(SampleKind::PostEvent)?;
        }
    }
    Ok(())
}

/// The plastic branch of key `j` ended at its failure point `e_at` (hysteresis rule G5): the
/// force drops to 0 there, with a pre- and a post-event sample and a `key failure` event. As at
/// a contact event, the state is first put back on the closed constraints, and the force's jump
/// is followed by the contact LCP (eq. 8–10), which decides stick, slide or detachment anew.
fn key_failure(eng: &mut Engine, j: usize, e_at: f64, dir: f64) -> Result<(), SolverError> {
    let closed = eng.state.contacts.iter().any(|s| *s != ContactState::Open);
    if closed {
        eng.project();
    }
    eng.record_sample(SampleKind::PreEvent)?;
    let law = &mut eng.state.laws[j];
    law.on_branch_end(e_at, dir);
    let peak = law.gap_state().map_or(f64::NAN, |g| g.peak_force);
    let t = eng.state.t;
    eng.state.out.stats.branch_events += 1;
    eng.log(EventRecord::key_failure(t, j))?;
    eng.state.out.note_key_failure(t, j, peak);
    eng.ws.dynamics.at = None;
    if closed {
        eng.resolve(None)?;
        eng.ws.new_contact_mode();
    }
    eng.record_sample(SampleKind::PostEvent)
}

/// Length of y: q, q̇ and the ledger terms.
fn y_len(n: usize) -> usize {
    2 * n + LEDGER_TERMS
}
