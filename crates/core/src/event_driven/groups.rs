//! Groups of islands (`solver.islands`, [`super::islands`]): islands whose bodies may meet
//! are integrated together, the others on their own. A group is an island, or islands joined
//! while a contact between them may close or is closed ([`Scene::restrict`] of their
//! bodies). Its contact events are applied by the whole scene at the group's instant, on the
//! state gathered from every group there (the events' samples, impulses, log and ledger are
//! the whole scene's), and handed back to the group; every other group goes on over the same
//! window untouched.

use super::driver::{Integration, process_event};
use super::event_fn::EventFn;
use super::events::due_now;
use crate::dopri;
use crate::run::SolverError;
use crate::scene::{Restricted, Scene};

/// A group of islands and its integration.
pub(super) struct Group<'s> {
    /// The islands (indices into [`super::islands::Split`]'s), sorted.
    pub(super) islands: Vec<usize>,
    pub(super) r: &'s Restricted,
    /// Boxed: a group leaves the list of groups (joined, parted) without moving its storage.
    pub(super) it: Box<Integration<'s>>,
    /// Per whole-scene DOF, its index in the group (`usize::MAX`: not in the group).
    pub(super) local: Vec<usize>,
}

impl<'s> Group<'s> {
    pub(super) fn new(
        islands: Vec<usize>,
        r: &'s Restricted,
        it: Integration<'s>,
        n: usize,
    ) -> Self {
        let mut local = vec![usize::MAX; n];
        for (k, &d) in r.dofs.iter().enumerate() {
            local[d] = k;
        }
        Self {
            islands,
            r,
            it: Box::new(it),
            local,
        }
    }

    /// Component `i` of the group's state at `t`: its present state if it is there (or has
    /// no step holding `t`), else its window's dense output.
    pub(super) fn y_at(&self, t: f64, i: usize) -> f64 {
        let ck = &self.it.clock;
        if self.it.eng.state.t == t {
            return self.it.eng.state.y[i];
        }
        match ck.kept.at(t) {
            Some((s, _)) => dense(s, ((t - s.t0) / s.h).clamp(0.0, 1.0), i),
            None => self.it.eng.state.y[i],
        }
    }

    /// The group's ledger terms at `t`.
    pub(super) fn ledger_at(&self, t: f64) -> [f64; crate::scene::LEDGER_TERMS] {
        let ni = self.it.eng.n;
        std::array::from_fn(|k| self.y_at(t, 2 * ni + k))
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

/// Event `f` of the restricted scene `r` in the whole scene's numbering.
pub(super) fn to_whole(scene: &Scene, r: &Restricted, f: EventFn) -> EventFn {
    match f {
        EventFn::Gap(i) => EventFn::Gap(r.contacts[i]),
        EventFn::Release(i) => EventFn::Release(r.contacts[i]),
        EventFn::StickSlip(i) => EventFn::StickSlip(r.contacts[i]),
        EventFn::SlideStop(i) => EventFn::SlideStop(r.contacts[i]),
        EventFn::Lower(j) => EventFn::Lower(r.hysteretic[j]),
        EventFn::Upper(j) => EventFn::Upper(r.hysteretic[j]),
        EventFn::Reversal(j) => EventFn::Reversal(r.hysteretic[j]),
        EventFn::Unseat(k) => {
            let c = r.contacts[r.scene.seats[k].contact];
            EventFn::Unseat(scene.seats.iter().position(|s| s.contact == c).unwrap_or(k))
        }
    }
}

/// The events at which group `g` paused, applied by the whole scene `it` (whose state is the
/// gathered state at that instant), the result handed back to the group, then the group's
/// events due at once (simultaneous crossings) the same way, as a restart of the whole scene
/// would.
pub(super) fn forward(it: &mut Integration, grp: &mut Group) -> Result<(), SolverError> {
    let scene = it.eng.scene;
    let mut todo: Vec<EventFn> = (grp.it.eng.state.cluster.iter())
        .map(|&f| to_whole(scene, grp.r, f))
        .collect();
    grp.it.clock.pending = false;
    let mut done: Vec<EventFn> = Vec::new();
    loop {
        it.check_stall()?;
        for &f in &todo {
            it.eng.state.out.stats.events_located += 1;
            process_event(&mut it.eng, f)?;
        }
        scatter(it, grp);
        grp.it.rearm()?;
        match due_now(&mut grp.it.eng, &grp.it.clock.fns, &done)? {
            Some(f) => {
                done.push(f);
                todo = vec![to_whole(scene, grp.r, f)];
            }
            None => return Ok(()),
        }
    }
}

/// The whole scene's state after its events, into the group: positions, velocities, laws,
/// contact modes, time (the group's ledger is its own).
fn scatter(it: &Integration, grp: &mut Group) {
    let (n, ni) = (it.eng.n, grp.it.eng.n);
    let (from, to) = (&it.eng.state, &mut grp.it.eng.state);
    for (k, &d) in grp.r.dofs.iter().enumerate() {
        to.y[k] = from.y[d];
        to.y[ni + k] = from.y[n + d];
    }
    for (k, &j) in grp.r.hysteretic.iter().enumerate() {
        to.laws[k].clone_from(&from.laws[j]);
    }
    for (k, &c) in grp.r.contacts.iter().enumerate() {
        to.contacts[k] = from.contacts[c];
    }
    to.t = from.t;
    to.force_scale = from.force_scale;
    to.last_event_values = None;
    grp.it.eng.ws.dynamics.at = None;
    grp.it.eng.ws.new_contact_mode();
}
