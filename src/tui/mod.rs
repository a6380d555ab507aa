//! The terminal workbench (ratatui + crossterm) over the engine's public API.
//!
//! Event-driven: an input thread (crossterm key and resize events), the simulation worker
//! ([`worker`]) and the file watcher ([`watch`]) all send [`Msg`]s into one channel; the loop
//! ([`runtime`]) drains it, feeds each message to [`update()`], executes the returned
//! [`Effect`]s ([`effects`]), and draws ([`ui`]) once per drain. See `docs/workbench.md`.

pub mod app;
pub mod chart;
pub mod chart_prefs;
pub mod effects;
pub mod eng;
pub mod form;
pub mod help;
pub mod keymap;
pub mod messages;
pub mod msg;
pub mod results;
pub mod runs;
pub mod runtime;
pub mod signals;
pub mod studies;
pub mod term;
pub mod ui;
pub mod update;
pub mod workers;

pub use app::{App, Options};
pub use effects::{Blocking, Host, execute_blocking, perform, save_atomic};
pub use msg::{Effect, Msg};
pub use runs::export::write_exports;
pub use runtime::run;
pub use update::update;
