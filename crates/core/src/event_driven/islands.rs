//! Islands on their own steps (`solver.islands`): while their contacts are open, the bodies
//! joined by elements (an island, [`Scene::islands`]) move independently of the others, so
//! each is integrated on the scene restricted to it ([`Scene::restrict`]), with its own step
//! size and its own events, over windows of [`WINDOW`]. The open contacts between islands are
//! watched on the islands' dense outputs; where one of them may close, its two islands are
//! joined into a group ([`super::groups`]) from the last sample that held, and the group goes
//! on on its own steps while the other islands go on untouched. A group's contact events (and
//! a key's failure) are applied by the whole scene at the group's instant, on the state
//! gathered there from every group, and handed back; at a window's end a group whose contacts
//! between its islands are all open is parted again. Only a group that cannot go on hands the
//! rest to the whole scene, which locates and applies what stopped it.
//!
//! An event of one island thus ends only that island's step, and a contact phase integrates
//! only the islands in contact. Each island is held to the tolerance on its own, where the
//! whole scene's step, set by its stiffest island and every island's events, holds the others
//! closer: at equal accuracy the islands pay only with many frames
//! (`scripts/islands-precision.sh`, `docs/results.md`). Outputs are those of the whole scene:
//! the grid samples from the groups' dense outputs and the laws along their steps, the events'
//! samples, impulses and log from the whole scene; the peaks, statistics and energy ledger add
//! the groups' own.

use super::driver::{Integration, Kept};
use super::engine::{Engine, State};
use super::events::arm;
use super::groups::{Group, forward};
use super::locate::{hermite_min, hermite_stays_above};
use super::record::track_peaks;
use super::workspace::Workspace;
use crate::dopri;
use crate::output::{ContactState, SampleKind};
use crate::run::{Observer, Silent, SolverError};
use crate::scene::{BodyRef, Frame, LEDGER_TERMS, Restricted, Scene};
use nalgebra::DVector;
use std::collections::HashMap;
use std::time::Instant;
use typed_arena::Arena;

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
    /// The bodies of each island.
    bodies: Vec<Vec<usize>>,
    cross: Vec<Cross>,
}

impl Split {
    pub(super) fn new(scene: &Scene) -> Self {
        let bodies = scene.islands();
        let subs: Vec<Restricted> = (bodies.iter())
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
        Self {
            subs,
            bodies,
            cross,
        }
    }
}

/// Integrate `it` (the whole scene) to its end, by groups of islands while it can
/// ([`separate`]).
pub(super) fn run_phases(
    it: &mut Integration,
    split: &Split,
    observer: &mut dyn Observer,
) -> Result<(), SolverError> {
    let mut coupled_until = 0.0;
    let mut pool = Pool::default();
    let arena = Arena::new();
    let mut groups = Joined {
        arena: &arena,
        made: HashMap::new(),
    };
    loop {
        it.clock.split_after = Some(coupled_until);
        if !it.advance(observer, false)? {
            return Ok(());
        }
        let wall = Instant::now();
        let r = separate(it, split, &mut pool, &mut groups, observer);
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

/// The restricted scenes of the groups of more than one island made so far, by their islands.
struct Joined<'s> {
    arena: &'s Arena<Restricted>,
    made: HashMap<Vec<usize>, &'s Restricted>,
}

impl<'s> Joined<'s> {
    fn scene_of(&mut self, scene: &Scene, split: &Split, islands: &[usize]) -> &'s Restricted {
        if let Some(r) = self.made.get(islands) {
            return r;
        }
        let mut bodies: Vec<usize> = (islands.iter())
            .flat_map(|&i| split.bodies[i].iter().copied())
            .collect();
        bodies.sort_unstable();
        let mut r = scene.restrict(&bodies);
        r.scene.settings.keep_history = false;
        let r: &'s Restricted = self.arena.alloc(r);
        self.made.insert(islands.to_vec(), r);
        r
    }
}

/// The groups from the whole scene's state, window after window, each group to the window's
/// end or its first contact event; the earliest of those events (applied by the whole scene,
/// [`forward`]) or of a contact between groups that may close (the two groups joined from the
/// last sample before it) comes first. At a window's end a group whose contacts between its
/// islands are all open is parted again. None at the run's end, else the instant from which
/// the whole scene goes on (a group that could not go on: it then locates and applies what
/// stopped it).
fn separate<'s>(
    it: &mut Integration,
    split: &'s Split,
    pool: &mut Pool<'s>,
    joined: &mut Joined<'s>,
    observer: &mut dyn Observer,
) -> Result<Option<f64>, SolverError> {
    let Some(islands) = pool.resume(split, &it.eng.state, it.clock.h) else {
        return Ok(Some(it.eng.state.t));
    };
    let n = it.eng.n;
    let mut groups: Vec<Group<'s>> = (islands.into_iter().enumerate())
        .map(|(i, isl)| Group::new(vec![i], &split.subs[i], isl, n))
        .collect();
    let mut ledger: Vec<f64> = it.eng.state.y.as_slice()[2 * n..].to_vec();
    let mut watch = Watch::new(it.eng.scene);
    let r = windows(
        it,
        split,
        joined,
        &mut groups,
        &mut ledger,
        &mut watch,
        observer,
    );
    for g in &groups {
        add_counts(it, g);
    }
    pool.take_back(groups, split.subs.len());
    r
}

/// [`separate`]'s windows.
fn windows<'s>(
    it: &mut Integration,
    split: &'s Split,
    joined: &mut Joined<'s>,
    groups: &mut Vec<Group<'s>>,
    ledger: &mut [f64],
    watch: &mut Watch,
    observer: &mut dyn Observer,
) -> Result<Option<f64>, SolverError> {
    let scene = it.eng.scene;
    let (end, dt) = (scene.settings.t_end, scene.settings.output_dt);
    let per_window = (WINDOW / dt).round().max(1.0) as usize;
    loop {
        let t = it.eng.state.t;
        if t >= end {
            return Ok(None);
        }
        let tw = (((it.clock.next_out + per_window - 1) as f64) * dt).min(end);
        if tw <= t {
            return Ok(Some(t));
        }
        for g in groups.iter_mut() {
            g.it.clock.kept.clear();
            g.it.eng.state.out.step_peaks.fill((0.0, 0.0));
        }
        loop {
            for g in groups.iter_mut() {
                if g.it.clock.pending || g.it.eng.state.t >= tw {
                    continue;
                }
                g.it.clock.stop = tw;
                if g.it.advance(&mut Silent, true).is_err() {
                    return Ok(Some(it.eng.state.t));
                }
            }
            let t_c = it.eng.state.t;
            let paused = (0..groups.len())
                .filter(|&g| groups[g].it.clock.pending)
                .min_by(|&a, &b| {
                    groups[a]
                        .it
                        .eng
                        .state
                        .t
                        .total_cmp(&groups[b].it.eng.state.t)
                });
            let t_lim = paused.map_or(tw, |g| groups[g].it.eng.state.t);
            let group_of = group_of(groups, split.subs.len());
            if let Some((safe, c)) = watch.may_close(scene, split, groups, &group_of, (t_c, t_lim))
            {
                if safe > t_c {
                    commit(it, groups, ledger, safe)?;
                }
                let pair = split.cross[c].dofs.iter().map(|&(_, isl, _)| group_of[isl]);
                let (lo, hi) = (pair.clone().min().unwrap_or(0), pair.max().unwrap_or(0));
                join(it, split, joined, groups, ledger, (lo, hi))?;
                continue;
            }
            if let Some(g) = paused {
                commit(it, groups, ledger, t_lim)?;
                // an impact on a face the ground moves works in the whole scene's ledger
                let before: Vec<f64> = it.eng.state.y.as_slice()[2 * it.eng.n..].to_vec();
                forward(it, &mut groups[g])?;
                let after = &it.eng.state.y.as_slice()[2 * it.eng.n..];
                for ((b, x), y) in ledger.iter_mut().zip(after).zip(before) {
                    *b += x - y;
                }
                it.batcher.maybe(&it.eng.state.out, t_lim, observer)?;
                continue;
            }
            commit(it, groups, ledger, tw)?;
            peaks(it, groups);
            part(it, split, groups, ledger)?;
            it.batcher.maybe(&it.eng.state.out, tw, observer)?;
            break;
        }
    }
}

/// The group of each island.
fn group_of(groups: &[Group], n_islands: usize) -> Vec<usize> {
    let mut of = vec![usize::MAX; n_islands];
    for (g, grp) in groups.iter().enumerate() {
        for &i in &grp.islands {
            of[i] = g;
        }
    }
    of
}

/// Groups `lo` < `hi` joined into one at the whole scene's present state (the last sample
/// before their contact may close); their ledgers so far go to the base `ledger`.
fn join<'s>(
    it: &mut Integration,
    split: &'s Split,
    joined: &mut Joined<'s>,
    groups: &mut Vec<Group<'s>>,
    ledger: &mut [f64],
    (lo, hi): (usize, usize),
) -> Result<(), SolverError> {
    let t = it.eng.state.t;
    let mut b = groups.remove(hi);
    let mut a = groups.remove(lo);
    let mut islands = a.islands.clone();
    islands.extend(&b.islands);
    islands.sort_unstable();
    let h = a.it.clock.h.min(b.it.clock.h);
    for g in [&mut a, &mut b] {
        retire(it, g, ledger, t);
    }
    let r = joined.scene_of(it.eng.scene, split, &islands);
    let eng = Engine::new(&r.scene)?;
    let g = Integration::resume(eng, r, &it.eng.state, h, None)?;
    groups.push(Group::new(islands, r, g, it.eng.n));
    Ok(())
}

/// Groups of several islands whose contacts between islands are all open, parted into their
/// islands at the whole scene's present state (a window's end).
fn part<'s>(
    it: &mut Integration,
    split: &'s Split,
    groups: &mut Vec<Group<'s>>,
    ledger: &mut [f64],
) -> Result<(), SolverError> {
    let t = it.eng.state.t;
    let mut k = 0;
    while k < groups.len() {
        let g = &groups[k];
        let open = g.islands.len() > 1
            && (split.cross.iter())
                .filter(|c| c.dofs.iter().all(|&(_, isl, _)| g.islands.contains(&isl)))
                .all(|c| it.eng.state.contacts[c.contact] == ContactState::Open);
        if !open {
            k += 1;
            continue;
        }
        let mut g = groups.remove(k);
        retire(it, &mut g, ledger, t);
        for &i in &g.islands {
            let r = &split.subs[i];
            let eng = Engine::new(&r.scene)?;
            let isl = Integration::resume(eng, r, &it.eng.state, g.it.clock.h, None)?;
            groups.push(Group::new(vec![i], r, isl, it.eng.n));
        }
    }
    Ok(())
}

/// A group that stops at `t`: its counts to the whole scene's, its peaks up to t and its
/// ledger to the base.
fn retire(it: &mut Integration, g: &mut Group, ledger: &mut [f64], t: f64) {
    add_counts(it, g);
    g.it.peaks_until(t);
    peaks(it, std::slice::from_ref(g));
    for (b, x) in ledger.iter_mut().zip(g.ledger_at(t)) {
        *b += x;
    }
}

/// The window's peaks of every group into the whole scene's.
fn peaks(it: &mut Integration, groups: &[Group]) {
    let n = it.eng.n;
    let state = &mut it.eng.state;
    if state.out.step_peaks.len() != n {
        state.out.step_peaks = vec![(0.0, 0.0); n];
    }
    for g in groups {
        for (k, p) in g.it.eng.state.out.step_peaks.iter().enumerate() {
            let global = &mut state.out.step_peaks[g.r.dofs[k]];
            if p.0 > global.0 {
                *global = *p;
            }
        }
    }
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

    /// The groups' integrations kept for the next phase, where each group is one island.
    fn take_back(&mut self, mut groups: Vec<Group<'s>>, n: usize) {
        groups.sort_by_key(|g| g.islands[0]);
        if groups.len() == n && groups.iter().all(|g| g.islands.len() == 1) {
            self.islands = groups.into_iter().map(|g| *g.it).collect();
        }
    }

    fn emptied(&mut self) -> Option<Vec<Integration<'s>>> {
        self.initial.clear();
        None
    }
}

/// What an island's integration reuses from the last phase: its window's steps and its DP5
/// storage (each written before it is read).
type Storage = (Kept, dopri::Workspace, dopri::Workspace);

/// The groups up to `tw` into the whole scene: the grid samples in (t, tw] from their dense
/// outputs and the laws along their steps, then the state at `tw` (each group's present state
/// where it is at `tw`).
fn commit(
    it: &mut Integration,
    groups: &[Group],
    ledger: &[f64],
    tw: f64,
) -> Result<(), SolverError> {
    let dt = it.eng.scene.settings.output_dt;
    loop {
        let tg = (it.clock.next_out as f64) * dt;
        let at_end = (tg - tw).abs() <= 1e-12 * tw.max(1.0);
        if tg > tw && !at_end {
            break;
        }
        gather(it, groups, ledger, if at_end { tw } else { tg });
        if it
            .eng
            .state
            .contacts
            .iter()
            .any(|s| *s != ContactState::Open)
        {
            // a sample inside a group's step, back on its closed constraints
            it.eng.project();
        }
        it.eng.record_sample(SampleKind::Grid)?;
        it.clock.next_out += 1;
        if at_end {
            break;
        }
    }
    gather(it, groups, ledger, tw);
    Ok(())
}

/// The whole scene's state at `t` from the groups ([`Group::y_at`]), the laws along the step
/// holding t (or the present ones), the contact modes; the ledger is the base `ledger` plus
/// the groups' own.
fn gather(it: &mut Integration, groups: &[Group], ledger: &[f64], t: f64) {
    let n = it.eng.n;
    let state = &mut it.eng.state;
    let mut sums = [0.0; LEDGER_TERMS];
    for g in groups {
        let ni = g.it.eng.n;
        for (k, &d) in g.r.dofs.iter().enumerate() {
            state.y[d] = g.y_at(t, k);
            state.y[n + d] = g.y_at(t, ni + k);
        }
        for (s, x) in sums.iter_mut().zip(g.ledger_at(t)) {
            *s += x;
        }
        let ck = &g.it.clock;
        let along = (g.it.eng.state.t != t).then(|| ck.kept.at(t)).flatten();
        let laws = along.map_or(&g.it.eng.state.laws[..], |&(_, l)| ck.kept.laws(l));
        for (k, &j) in g.r.hysteretic.iter().enumerate() {
            state.laws[j].clone_from(&laws[k]);
        }
        for (k, &c) in g.r.contacts.iter().enumerate() {
            state.contacts[c] = g.it.eng.state.contacts[k];
        }
        state.force_scale = state.force_scale.max(g.it.eng.state.force_scale);
    }
    for (k, s) in sums.iter().enumerate() {
        state.y[2 * n + k] = ledger[k] + s;
    }
    state.t = t;
    state.last_event_values = None;
    it.eng.ws.dynamics.at = None;
}

/// A group's steps, right-hand sides, events and step control in the whole scene's counts.
fn add_counts(it: &mut Integration, g: &Group) {
    let n = it.eng.n;
    let (s, ni) = (&g.it.eng.state.out.stats, g.it.eng.n);
    let whole = &mut it.eng.state.out.stats;
    whole.steps_accepted += s.steps_accepted;
    whole.steps_rejected += s.steps_rejected;
    whole.events_located += s.events_located;
    whole.branch_events += s.branch_events;
    for (k, &c) in s.step_control.iter().enumerate() {
        let global = if k < ni {
            g.r.dofs[k]
        } else {
            n + g.r.dofs[k - ni]
        };
        if let Some(x) = whole.step_control.get_mut(global) {
            *x += c;
        }
    }
    it.clock.rhs_evals += g.it.clock.rhs_evals;
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

    /// The first contact between two groups that may close (or its corner leave its seat) in
    /// [t, tw], with the last sample before it that held: g_N (and edge − g_N) sampled at the
    /// window's ends and at the middle and end of every step of its two groups, and between
    /// samples by the cubic Hermite bound of [`super::locate`]; a sample at or below 0, or a
    /// bound that fails with a Hermite minimum at or below 0, is where it may close.
    fn may_close(
        &mut self,
        scene: &Scene,
        split: &Split,
        groups: &[Group],
        group_of: &[usize],
        (t, tw): (f64, f64),
    ) -> Option<(f64, usize)> {
        let mut first: Option<(f64, usize)> = None;
        let mut safe = tw;
        for (ci, c) in split.cross.iter().enumerate() {
            let g0 = c
                .dofs
                .first()
                .map_or(usize::MAX, |&(_, isl, _)| group_of[isl]);
            if c.dofs.iter().all(|&(_, isl, _)| group_of[isl] == g0)
                || self.clearly_open(scene, c, groups, group_of, (t, tw))
            {
                continue;
            }
            self.times.clear();
            self.times.extend([t, tw]);
            for &(_, isl, _) in &c.dofs {
                for (s, _) in groups[group_of[isl]].it.clock.kept.steps() {
                    let inside = [s.t0 + 0.5 * s.h, s.t1()].into_iter();
                    self.times.extend(inside.filter(|&x| x > t && x < tw));
                }
            }
            self.times.sort_by(f64::total_cmp);
            self.times.dedup();
            let mut prev: Option<(f64, f64, f64)> = None;
            for k in 0..self.times.len() {
                let s = self.times[k];
                let (g, rate) = self.gap(scene, c, groups, group_of, s);
                if self.fails(c, prev, (s, g, rate)) {
                    // every contact held up to `safe`, the last sample before any failed
                    safe = safe.min(prev.map_or(t, |p| p.0));
                    if first.is_none_or(|(f, _)| s < f) {
                        first = Some((s, ci));
                    }
                    break;
                }
                if first.is_some_and(|(f, _)| f <= s) {
                    break;
                }
                prev = Some((s, g, rate));
            }
        }
        first.map(|(_, c)| (safe, c))
    }

    /// A sample (s, g, ġ) of contact `c` at or below 0 (or its seat's edge reached), or a
    /// Hermite bound from the previous sample that fails with a minimum at or below 0.
    fn fails(
        &self,
        c: &Cross,
        prev: Option<(f64, f64, f64)>,
        (s, g, rate): (f64, f64, f64),
    ) -> bool {
        let fns = [(g, rate)]
            .into_iter()
            .chain(c.edge.map(|e| (e - g, -rate)));
        for (m, (v, r)) in fns.enumerate() {
            if v <= 0.0 || !v.is_finite() {
                return true;
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
                    return true;
                }
            }
        }
        false
    }

    /// The window's ends alone show contact `c` open throughout: the cubic Hermite bound
    /// holds with three times the rates' terms (a motion far from closing the gap, as a
    /// joint's 25 mm against the frames' relative motion in 0.05 s).
    fn clearly_open(
        &mut self,
        scene: &Scene,
        c: &Cross,
        groups: &[Group],
        group_of: &[usize],
        (t, tw): (f64, f64),
    ) -> bool {
        let ((g0, r0), (g1, r1)) = (
            self.gap(scene, c, groups, group_of, t),
            self.gap(scene, c, groups, group_of, tw),
        );
        let dt = 3.0 * (tw - t);
        let open =
            |g0: f64, r0: f64, g1: f64, r1: f64| hermite_stays_above(g0, r0 * dt, g1, r1 * dt);
        open(g0, r0, g1, r1) && c.edge.is_none_or(|e| open(e - g0, -r0, e - g1, -r1))
    }

    /// (g_N, ġ_N) of contact `c` at `s` from its groups' states ([`Group::y_at`]).
    fn gap(
        &mut self,
        scene: &Scene,
        c: &Cross,
        groups: &[Group],
        group_of: &[usize],
        s: f64,
    ) -> (f64, f64) {
        let n = scene.ndof();
        for &(d, isl, _) in &c.dofs {
            let g = &groups[group_of[isl]];
            let k = g.local[d];
            self.y[d] = g.y_at(s, k);
            self.y[n + d] = g.y_at(s, g.it.eng.n + k);
        }
        for &b in &c.bodies {
            self.fr.poses[b] = scene.body_state_at(b, s, &self.y, n);
        }
        let (g, rate, _) = scene.contact_rates(&self.fr, &scene.contacts[c.contact]);
        (g, rate)
    }
}

impl<'a> Integration<'a> {
    /// The peaks of the window's steps up to `t` only.
    fn peaks_until(&mut self, t: f64) {
        let (n, out) = (self.eng.n, &mut self.eng.state.out);
        out.step_peaks.fill((0.0, 0.0));
        let mut y1 = DVector::zeros(self.eng.state.y.len());
        let steps = self.clock.kept.steps();
        for (k, (s, _)) in steps.iter().enumerate() {
            // a step in which an event was located holds only up to it: the next step's start
            let end = steps
                .get(k + 1)
                .map_or(s.t1(), |(next, _)| next.t0.min(s.t1()));
            if s.t0 < t {
                track_peaks(out, s, t.min(end), n, &mut y1);
            }
        }
    }

    /// A group's integration from the whole scene's `state` (its DOFs, laws and contact modes
    /// through `r`'s indices, its ledger from 0), `h` its first step; `eng` holds the group's
    /// initial state.
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
        for (k, &c) in r.contacts.iter().enumerate() {
            eng.state.contacts[k] = state.contacts[c];
        }
        eng.ws.new_contact_mode();
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
