//! The terminal workbench (ratatui + crossterm) over the engine's public API.
//!
//! Event-driven: an input thread (crossterm key and resize events), the simulation worker
//! ([`worker`]) and the file watcher ([`watch`]) all send [`Msg`]s into one channel; the loop
//! ([`runtime`]) drains it, feeds each message to [`update()`], executes the returned
//! [`Effect`]s ([`effects`]), and draws ([`ui`]) once per drain. See `docs/workbench.md`.

pub mod app;
pub mod chart;
pub mod chart_prefs;
pub mod design_rows;
pub mod effects;
pub mod eng;
pub mod export;
pub mod form;
pub mod form_edit;
pub mod form_spec;
pub mod help;
pub mod keymap;
pub mod list_edit;
pub mod merge;
pub mod messages;
pub mod model_files;
pub mod msg;
pub mod nav;
pub mod out_folder;
pub mod results;
pub mod results_worker;
pub mod run_data;
pub mod run_info;
pub mod run_list;
pub mod run_results;
pub mod run_store;
pub mod runtime;
pub mod series;
pub mod signals;
pub mod study;
pub mod study_files;
pub mod study_points;
pub mod study_worker;
pub mod swap;
pub mod term;
pub mod ui;
pub mod units;
pub mod update;
pub mod watch;
pub mod worker;

pub use app::{App, Options};
pub use effects::{Blocking, Host, execute_blocking, perform, save_atomic};
pub use export::write_exports;
pub use msg::{Effect, Msg};
pub use runtime::run;
pub use update::update;
