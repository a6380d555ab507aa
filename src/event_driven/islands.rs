//! Islands on their own steps (`solver.islands`): while every contact is open, the bodies
//! joined by elements (an island, [`Scene::islands`]) move independently of the others, so
//! each is integrated on the scene restricted to it ([`Scene::restrict`]), with its own step
//! size and its own events, over windows of [`WINDOW`]. The open contacts between islands are
//! watched on the islands' dense outputs; a window in which one of them may close, or in
//! which an island meets a contact event or a key's failure of its own, is given up: its part
//! before the last sample that held (if any) is kept, and the whole scene integrates the rest
//! again, locating and resolving the event as always. The whole scene goes on until its
//! contacts are all open again, past that instant.
//!
//! An event of one island thus ends only that island's step. Each island is held to the
//! tolerance on its own, where the whole scene's step, set by its stiffest island and every
//! island's events, holds the others closer: at equal accuracy the islands pay only with many
//! frames (`scripts/islands-precision.sh`, `docs/results.md`). Outputs are those of
//! the whole scene: the grid samples of a kept window from the islands' dense outputs and the
//! laws along their steps; the peaks, statistics and energy ledger add the islands' own.

use super::driver::{Integration, Kept};
use super::engine::{Engine, State};
use super::events::arm;
use super::locate::{hermite_min, hermite_stays_above};
use super::record::track_peaks;
use super::workspace::Workspace;
use crate::dopri;
use crate::output::SampleKind;
use crate::run::{Observer, Silent, SolverError};
use crate::scene::{BodyRef, Frame, LEDGER_TERMS, Restricted, Scene};
use nalgebra::DVector;
use std::time::Instant;

/// Whether `scene` runs by islands: asked for (one island too: its windows and steps are then
/// those it has beside others, so that a simplification of the others changes nothing of it).
pub(super) fn eligible(scene: &Scene) -> bool {
    scene.settings.islands && !scene.islands().is_empty()
}

/// An open contact between two islands (with its seat's edge, if it has one), and where each
/// body's DOFs lie: (whole-scene DOF, island, island DOF).
struct Cross {
    contact: usize,
    edge: Option<f64>,
    bodies: [usize; 2],
    dofs: Vec<(usize, usize, usize)>,
}

/// The islands' scenes (no history of their own) and the contacts between them.
pub(super) struct Split {
    subs: Vec<Restricted>,
    cross: Vec<Cross>,
}

impl Split {
    pub(super) fn new(scene: &Scene) -> Self {
        let subs: Vec<Restricted> = (scene.islands().iter())
            .map(|p| {
                let mut r = scene.restrict(p);
                r.scene.settings.keep_history = false;
                r
            })
            .collect();
        let island_of = |d: usize| {
            (subs.iter().enumerate())
                .find_map(|(i, r)| r.dofs.iter().position(|&g| g == d).map(|k| (i, k)))
        };
        let mut cross = Vec::new();
        for (i, c) in scene.contacts.iter().enumerate() {
            if subs.iter().any(|r| r.contacts.contains(&i)) {
                continue;
            }
            let (BodyRef::Body(a), BodyRef::Body(b)) = (c.point_body, c.face_body) else {
                continue;
            };
            let dofs = [a, b]
                .iter()
                .flat_map(|&body| scene.bodies[body].dofs.into_iter().flatten())
                .filter_map(|d| island_of(d).map(|(isl, k)| (d, isl, k)))
                .collect();
            let edge = scene.seats.iter().find(|s| s.contact == i).map(|s| s.edge);
            cross.push(Cross {
                contact: i,
                edge,
                bodies: [a, b],
                dofs,
            });
        }
        Self { subs, cross }
    }
}

/// Integrate `it` (the whole scene) to its end, by islands while every contact is open.
pub(super) fn run_phases(
    it: &mut Integration,
    split: &Split,
    observer: &mut dyn Observer,
) -> Result<(), SolverError> {
    let mut coupled_until = 0.0;
    let mut pool = Pool::default();
    loop {
        it.clock.split_after = Some(coupled_until);
        if !it.advance(observer, false)? {
            return Ok(());
        }
        let wall = Instant::now();
        let r = separate(it, split, &mut pool, observer);
        it.clock.wall += wall.elapsed().as_secs_f64();
        match r? {
            None => return Ok(()),
            Some(t) => {
                coupled_until = t;
                it.rearm()?;
            }
        }
    }
}

/// Length of a window, s (whole output steps, at least one): long enough that cutting the
/// islands' steps at its end costs little, short enough that a window given up costs little.
const WINDOW: f64 = 0.05;

/// The islands from the whole scene's state, window after window: None at the run's end, else
/// the instant from which a window was given up (an island's contact event, or the first
/// sample of a contact between islands that may close); the whole scene, at that window's
/// start or at the last sample before that instant, goes on past it.
fn separate<'s>(
    it: &mut Integration,
    split: &'s Split,
    pool: &mut Pool<'s>,
    observer: &mut dyn Observer,
) -> Result<Option<f64>, SolverError> {
    let Some(mut islands) = pool.resume(split, &it.eng.state, it.clock.h) else {
        return Ok(Some(it.eng.state.t));
    };
    let n = it.eng.n;
    let ledger: Vec<f64> = it.eng.state.y.as_slice()[2 * n..].to_vec();
    let mut watch = Watch::new(it.eng.scene);
    let (end, dt) = (it.eng.scene.settings.t_end, it.eng.scene.settings.output_dt);
    let per_window = (WINDOW / dt).round().max(1.0) as usize;
    let given_up = loop {
        let t = it.eng.state.t;
        if t >= end {
            break None;
        }
        let tw = (((it.clock.next_out + per_window - 1) as f64) * dt).min(end);
        let mut lost = (tw <= t).then_some(t);
        for isl in islands.iter_mut() {
            if lost.is_some() {
                break;
            }
            isl.clock.stop = tw;
            isl.clock.kept.clear();
            if !matches!(isl.advance(&mut Silent, true), Ok(false)) {
                lost = Some(isl.eng.state.t);
            }
        }
        if lost.is_some() {
            break lost;
        }
        if let Some((safe, first)) = watch.may_close(it.eng.scene, split, &islands, (t, tw)) {
            // the islands hold up to the last sample before the first that may close: that
            // part of the window is kept, the whole scene goes on from there
            if safe > t {
                for isl in islands.iter_mut() {
                    isl.peaks_until(safe);
                }
                commit(it, split, &islands, &ledger, (safe, false))?;
                it.batcher.maybe(&it.eng.state.out, safe, observer)?;
            }
            break Some(first);
        }
        commit(it, split, &islands, &ledger, (tw, true))?;
        for isl in islands.iter_mut() {
            isl.eng.state.out.step_peaks.fill((0.0, 0.0));
        }
        it.batcher.maybe(&it.eng.state.out, tw, observer)?;
    };
    add_counts(it, split, &islands);
    pool.islands = islands;
    Ok(given_up)
}

/// The islands' integrations from one phase to the next, their storage reused, with the state
/// each engine starts from (`Engine::new`'s, which depends on the scene alone).
#[derive(Default)]
struct Pool<'s> {
    islands: Vec<Integration<'s>>,
    initial: Vec<State>,
}

impl<'s> Pool<'s> {
    /// Every island's integration from the whole scene's `state`, or None if one cannot start
    /// (the pool is then emptied).
    fn resume(&mut self, split: &'s Split, state: &State, h: f64) -> Option<Vec<Integration<'s>>> {
        let mut kept = std::mem::take(&mut self.islands).into_iter();
        let mut islands = Vec::with_capacity(split.subs.len());
        for (i, r) in split.subs.iter().enumerate() {
            let (eng, storage) = match kept.next() {
                Some(old) if i < self.initial.len() => old.into_fresh(&self.initial[i]),
                _ => match Engine::new(&r.scene) {
                    Ok(eng) => {
                        self.initial.truncate(i);
                        self.initial.push(eng.state.clone());
                        (eng, None)
                    }
                    Err(_) => return self.emptied(),
                },
            };
            match Integration::resume(eng, r, state, h, storage) {
                Ok(isl) => islands.push(isl),
                Err(_) => return self.emptied(),
            }
        }
        Some(islands)
    }

    fn emptied(&mut self) -> Option<Vec<Integration<'s>>> {
        self.initial.clear();
        None
    }
}

/// What an island's integration reuses from the last phase: its window's steps and its DP5
/// storage (each written before it is read).
type Storage = (Kept, dopri::Workspace, dopri::Workspace);

/// The window (t, tw] into the whole scene: the grid samples inside it from the islands' dense
/// outputs and the laws along their steps, then the state at `tw` (a grid sample if `tw` is
/// an output instant; the islands' own state if they are `at_tw`, else their dense outputs),
/// the peaks.
fn commit(
    it: &mut Integration,
    split: &Split,
    islands: &[Integration],
    ledger: &[f64],
    (tw, at_tw): (f64, bool),
) -> Result<(), SolverError> {
    let dt = it.eng.scene.settings.output_dt;
    let mut written = vec![usize::MAX; islands.len()];
    loop {
        let tg = (it.clock.next_out as f64) * dt;
        let at_end = (tg - tw).abs() <= 1e-12 * tw.max(1.0);
        if tg > tw && !at_end {
            break;
        }
        let tg = if at_end { tw } else { tg };
        gather(
            it,
            split,
            islands,
            ledger,
            (tg, at_end && at_tw),
            &mut written,
        );
        it.eng.record_sample(SampleKind::Grid)?;
        it.clock.next_out += 1;
        if at_end {
            break;
        }
    }
    gather(it, split, islands, ledger, (tw, at_tw), &mut written);
    let n = it.eng.n;
    let state = &mut it.eng.state;
    if state.out.step_peaks.len() != n {
        state.out.step_peaks = vec![(0.0, 0.0); n];
    }
    for (r, isl) in split.subs.iter().zip(islands) {
        for (k, p) in isl.eng.state.out.step_peaks.iter().enumerate() {
            let global = &mut state.out.step_peaks[r.dofs[k]];
            if p.0 > global.0 {
                *global = *p;
            }
        }
    }
    Ok(())
}

/// The whole scene's state at `t` from the islands: their present state (`now`) or their
/// dense outputs and the laws along the step holding t; the ledger is the phase's start
/// `ledger` plus the islands' own.
fn gather(
    it: &mut Integration,
    split: &Split,
    islands: &[Integration],
    ledger: &[f64],
    (t, now): (f64, bool),
    written: &mut [usize],
) {
    let n = it.eng.n;
    let state = &mut it.eng.state;
    let mut sums = [0.0; LEDGER_TERMS];
    for (i, (r, isl)) in split.subs.iter().zip(islands).enumerate() {
        let ni = isl.eng.n;
        let along = if now { None } else { isl.clock.kept.at(t) };
        let y_of = |i: usize| match along {
            Some((s, _)) => dense(s, ((t - s.t0) / s.h).clamp(0.0, 1.0), i),
            None => isl.eng.state.y[i],
        };
        for (k, &d) in r.dofs.iter().enumerate() {
            state.y[d] = y_of(k);
            state.y[n + d] = y_of(ni + k);
        }
        for (k, s) in sums.iter_mut().enumerate() {
            *s += y_of(2 * ni + k);
        }
        // the laws along the step (copied again only when they changed), or the present ones
        let index = along.map_or(usize::MAX, |&(_, l)| l);
        if index == usize::MAX || written[i] != index {
            let laws = along.map_or(&isl.eng.state.laws[..], |&(_, l)| isl.clock.kept.laws(l));
            for (k, &j) in r.hysteretic.iter().enumerate() {
                state.laws[j].clone_from(&laws[k]);
            }
            written[i] = index;
        }
    }
    for (k, s) in sums.iter().enumerate() {
        state.y[2 * n + k] = ledger[k] + s;
    }
    state.t = t;
    state.last_event_values = None;
    it.eng.ws.dynamics.at = None;
}

/// The islands' steps, right-hand sides, events and step control in the whole scene's counts.
fn add_counts(it: &mut Integration, split: &Split, islands: &[Integration]) {
    let n = it.eng.n;
    for (r, isl) in split.subs.iter().zip(islands) {
        let (s, ni) = (&isl.eng.state.out.stats, isl.eng.n);
        let g = &mut it.eng.state.out.stats;
        g.steps_accepted += s.steps_accepted;
        g.steps_rejected += s.steps_rejected;
        g.events_located += s.events_located;
        g.branch_events += s.branch_events;
        for (k, &c) in s.step_control.iter().enumerate() {
            let global = if k < ni {
                r.dofs[k]
            } else {
                n + r.dofs[k - ni]
            };
            if let Some(x) = g.step_control.get_mut(global) {
                *x += c;
            }
        }
        it.clock.rhs_evals += isl.clock.rhs_evals;
    }
}

/// Scratch of the watch over the contacts between islands.
struct Watch {
    y: DVector<f64>,
    fr: Frame,
    times: Vec<f64>,
}

impl Watch {
    fn new(scene: &Scene) -> Self {
        let n = scene.ndof();
        let z = DVector::zeros(n);
        Self {
            y: DVector::zeros(2 * n),
            fr: scene.frame(0.0, &z, &z),
            times: Vec::new(),
        }
    }

    /// Whether a contact between islands may close (or its corner leave its seat) in
    /// [t, tw]: g_N (and edge − g_N) sampled at the window's ends and at the middle and end of
    /// every step of its two islands, and between samples by the cubic Hermite bound of
    /// [`super::locate`]; a sample at or below 0, or a bound that fails with a Hermite minimum
    /// at or below 0, gives the window up (the whole scene then locates the event).
    fn may_close(
        &mut self,
        scene: &Scene,
        split: &Split,
        islands: &[Integration],
        (t, tw): (f64, f64),
    ) -> Option<(f64, f64)> {
        let mut first: Option<f64> = None;
        let mut safe = tw;
        for c in &split.cross {
            if self.clearly_open(scene, c, islands, (t, tw)) {
                continue;
            }
            self.times.clear();
            self.times.extend([t, tw]);
            for &(_, isl, _) in &c.dofs {
                let ck = &islands[isl].clock;
                for (s, _) in ck.kept.steps() {
                    self.times.extend([s.t0 + 0.5 * s.h, s.t1().min(tw)]);
                }
            }
            self.times.sort_by(f64::total_cmp);
            self.times.dedup();
            let mut prev: Option<(f64, f64, f64)> = None;
            for k in 0..self.times.len() {
                let s = self.times[k];
                let (g, rate) = self.gap(scene, c, islands, s);
                let fns = [(g, rate)]
                    .into_iter()
                    .chain(c.edge.map(|e| (e - g, -rate)));
                let mut fails = false;
                for (m, (v, r)) in fns.enumerate() {
                    if v <= 0.0 || !v.is_finite() {
                        fails = true;
                        break;
                    }
                    if let Some((s0, g0, r0)) = prev {
                        let (v0, r0) = if m == 0 {
                            (g0, r0)
                        } else {
                            (c.edge.unwrap_or(0.0) - g0, -r0)
                        };
                        let dt = s - s0;
                        if !hermite_stays_above(v0, r0 * dt, v, r * dt)
                            && hermite_min(v0, r0 * dt, v, r * dt).is_some_and(|(_, p)| p <= 0.0)
                        {
                            fails = true;
                            break;
                        }
                    }
                }
                if fails {
                    first = Some(first.map_or(s, |f: f64| f.min(s)));
                    safe = safe.min(prev.map_or(t, |p| p.0));
                }
                if first.is_some_and(|f| f <= s) {
                    break;
                }
                prev = Some((s, g, rate));
            }
        }
        first.map(|f| (safe, f))
    }

    /// The window's ends alone show contact `c` open throughout: the cubic Hermite bound
    /// holds with three times the rates' terms (a motion far from closing the gap, as a
    /// joint's 25 mm against the frames' relative motion in 0.05 s).
    fn clearly_open(
        &mut self,
        scene: &Scene,
        c: &Cross,
        islands: &[Integration],
        (t, tw): (f64, f64),
    ) -> bool {
        let ((g0, r0), (g1, r1)) = (
            self.gap(scene, c, islands, t),
            self.gap(scene, c, islands, tw),
        );
        let dt = 3.0 * (tw - t);
        let open =
            |g0: f64, r0: f64, g1: f64, r1: f64| hermite_stays_above(g0, r0 * dt, g1, r1 * dt);
        open(g0, r0, g1, r1) && c.edge.is_none_or(|e| open(e - g0, -r0, e - g1, -r1))
    }

    /// (g_N, ġ_N) of contact `c` at `s` from its islands' dense outputs.
    fn gap(&mut self, scene: &Scene, c: &Cross, islands: &[Integration], s: f64) -> (f64, f64) {
        let n = scene.ndof();
        for &(d, isl, k) in &c.dofs {
            let it = &islands[isl];
            let ni = it.eng.n;
            let ck = &it.clock;
            let (q, v) = match ck.kept.at(s) {
                Some((st, _)) => {
                    let th = ((s - st.t0) / st.h).clamp(0.0, 1.0);
                    (dense(st, th, k), dense(st, th, ni + k))
                }
                None => (it.eng.state.y[k], it.eng.state.y[ni + k]),
            };
            self.y[d] = q;
            self.y[n + d] = v;
        }
        for &b in &c.bodies {
            self.fr.poses[b] = scene.body_state_at(b, s, &self.y, n);
        }
        let (g, rate, _) = scene.contact_rates(&self.fr, &scene.contacts[c.contact]);
        (g, rate)
    }
}

/// Component i of a step's dense output at θ (y1 itself at θ = 1).
fn dense(step: &dopri::Step, theta: f64, i: usize) -> f64 {
    if theta >= 1.0 {
        step.y1[i]
    } else {
        step.dense_component(theta, i)
    }
}

impl<'a> Integration<'a> {
    /// The peaks of the window's steps up to `t` only.
    fn peaks_until(&mut self, t: f64) {
        let (n, out) = (self.eng.n, &mut self.eng.state.out);
        out.step_peaks.fill((0.0, 0.0));
        let mut y1 = DVector::zeros(self.eng.state.y.len());
        for (s, _) in self.clock.kept.steps() {
            if s.t0 < t {
                track_peaks(out, s, t.min(s.t1()), n, &mut y1);
            }
        }
    }

    /// An island's integration from the whole scene's `state` (its DOFs and laws through
    /// `r`'s indices, its ledger from 0), every contact open, `h` its first step; `eng` holds
    /// the island's initial state.
    fn resume(
        mut eng: Engine<'a>,
        r: &Restricted,
        state: &State,
        h: f64,
        storage: Option<Storage>,
    ) -> Result<Self, SolverError> {
        let ni = eng.n;
        let n = (state.y.len() - LEDGER_TERMS) / 2;
        for (k, &d) in r.dofs.iter().enumerate() {
            eng.state.y[k] = state.y[d];
            eng.state.y[ni + k] = state.y[n + d];
        }
        eng.state.t = state.t;
        eng.state.laws = r
            .hysteretic
            .iter()
            .map(|&j| state.laws[j].clone())
            .collect();
        eng.state.force_scale = state.force_scale;
        let mut f0 = DVector::zeros(eng.state.y.len());
        let y = eng.state.y.clone();
        eng.rhs(state.t, &y, &mut f0)?;
        let fns = eng.event_fns();
        let armed = arm(&mut eng, &fns)?;
        let mut it = Self::with_clock(eng, f0, h, fns, armed);
        // no grid instant of its own: the whole scene samples
        it.clock.next_out = usize::MAX / 4;
        it.clock.island = true;
        if let Some((kept, ws, ws_event)) = storage {
            (it.clock.kept, it.ws, it.ws_event) = (kept, ws, ws_event);
        }
        Ok(it)
    }

    /// The engine again at the island's `initial` state, with fresh scratch, and the storage
    /// the next phase reuses.
    fn into_fresh(self, initial: &State) -> (Engine<'a>, Option<Storage>) {
        let Integration {
            mut eng,
            clock,
            ws,
            ws_event,
            ..
        } = self;
        eng.state.clone_from(initial);
        eng.ws = Workspace::new(eng.n);
        (eng, Some((clock.kept, ws, ws_event)))
    }
}
