//! Event-driven nonsmooth integration (paper §3): DP5 between events, events located by root
//! finding on the dense output, impacts by the velocity LCP (eq. 5–7), contact state changes
//! by the acceleration LCP (eq. 8–10), closed constraints held at position and velocity level.
//!
//! Where each part of the paper lives:
//! - [`driver`]: start, the step loop (DP5 step, event search, grid samples), finish;
//! - [`engine`]: the physical state of a run (a fork is a clone); [`workspace`]: reused storage;
//! - [`dynamics`]: the constrained right-hand side between events (eq. 1–4);
//! - [`event_fn`], [`events`], [`locate`]: event functions, their arming, their location on the
//!   dense output (Illinois); [`restep`]: the state at a located contact event (a DP5 step to
//!   it, then Newton onto g_N = 0);
//! - [`resolve`]: at an event — impacts (eq. 5–7) with the accumulation rule, the contact phase
//!   (eq. 8–10), transitions; [`project`]: the projection onto the closed constraints;
//! - [`record`]: output samples, the energy ledger, peaks;
//! - [`fork`]: friction sweeps sharing their motion up to the first contact.

mod driver;
mod dynamics;
mod engine;
mod event_fn;
mod events;
mod fork;
mod locate;
mod project;
mod record;
mod resolve;
mod restep;
mod workspace;

pub use driver::{integrate, run};
pub use fork::FrictionFork;
