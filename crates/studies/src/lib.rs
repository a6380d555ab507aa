//! deckspin's studies: many runs of the engine (`deckspin-core`, re-exported here by its
//! module names) and the answers drawn from them. No front end: the CLI, the terminal
//! workbench and the Python package are layers over it.
//! - [`studies`]: sweeps and the paper's studies; [`study_table`], [`study_csv`]: a study's
//!   results as a table that fills while it runs, and its CSV; [`precision`],
//!   [`precision_study`]: work–precision; [`stress`]: the stress test of real records;
//!   [`sequence`]: runs from the final state of the one before.
//! - [`suite`]: record suites (incremental dynamic analysis); [`shard`]: jobs cut into parts
//!   and merged, and their journal; [`progress`]: how far a job has come; [`csv_error`]: a
//!   suite's or a sensitivity study's runs CSV that cannot be read back.
//! - [`design`]: fragility curves of a record suite, screening by the impact law, model
//!   adequacy and sensitivity.
//! - [`plot`]: charts as data, drawn as SVG or ASCII text; [`figures`]: the studies' charts.

pub mod csv_error;
pub mod design;
pub mod figures;
pub mod plot;
pub mod precision;
pub mod precision_study;
pub mod progress;
pub mod sequence;
pub mod shard;
pub mod stress;
pub mod studies;
pub mod study_csv;
pub mod study_table;
pub mod suite;

pub use deckspin_core::{
    FrictionFork, ModelError, Observer, Run, RunOutput, Silent, SolverError, Stop, clock, contact,
    dopri, event_driven, excitation, hysteresis, input, lemke, linalg, load, methods, modal, model,
    output, run, scene, simulate, timestepping, units,
};
