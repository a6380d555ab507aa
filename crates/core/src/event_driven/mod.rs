//! Event-driven nonsmooth integration (paper §3): DP5 between events, events located by root
//! finding on the dense output, impacts by the velocity LCP (eq. 5–7), contact state changes
//! by the acceleration LCP (eq. 8–10), closed constraints held at position and velocity level.
//!
//! Where each part of the paper lives:
//! - [`driver`]: start, the step loop (DP5 step, event search, grid samples), finish;
//! - [`engine`]: the physical state of a run (a fork is a clone); [`workspace`]: reused storage;
//! - [`dynamics`]: the constrained right-hand side between events (eq. 1–4);
//! - [`event_fn`], [`events`], [`locate`]: event functions, their arming, their location on the
//!   dense output (Illinois; [`probe`]: one function's value there); [`restep`]: the state at a located contact event (a DP5 step to
//!   it, then Newton onto g_N = 0);
//! - [`resolve`]: at an event — impacts (eq. 5–7) with the accumulation rule, the contact phase
//!   (eq. 8–10), transitions; [`project`]: the projection onto the closed constraints;
//! - [`record`]: output samples, the energy ledger, peaks;
//! - [`fork`]: friction sweeps sharing their motion up to the first contact;
//! - [`islands`]: islands of bodies on their own steps while their contacts are open;
//!   [`groups`]: islands joined while a contact between them may close or is closed.

mod driver;
mod dynamics;
mod engine;
mod event_fn;
mod events;
mod fork;
mod groups;
mod islands;
mod locate;
mod probe;
mod project;
mod record;
mod resolve;
mod restep;
mod workspace;

pub use fork::FrictionFork;

use crate::output::RunOutput;
use crate::run::{Observer, Run, SolverError};
use crate::scene::Scene;
use driver::Integration;

/// Run the event-driven integration of a scene: the output of a finished run, else the
/// reason it stopped.
pub fn run(scene: &Scene, observer: &mut dyn Observer) -> Result<RunOutput, SolverError> {
    integrate(scene, observer).into_result()
}

/// Run the event-driven integration of a scene, keeping what was computed before a cancel or
/// a failure; by islands while their contacts are open if the scene asks for it
/// ([`islands`]).
pub fn integrate(scene: &Scene, observer: &mut dyn Observer) -> Run {
    let mut it = match Integration::start(scene) {
        Ok(it) => it,
        Err(e) => return Run::new(RunOutput::new(scene), Err(e)),
    };
    let result = if islands::eligible(scene) {
        let split = islands::Split::new(scene);
        islands::run_phases(&mut it, &split, observer)
    } else {
        it.advance(observer, false).map(|_| ())
    };
    let complete = result.is_ok();
    Run::new(it.finish(observer, complete), result)
}
