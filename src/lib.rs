//! deckspin — nonsmooth seismic analysis of bridges whose decks pound their abutments and
//! rotate in plan (reference: "Nonsmooth seismic response analysis of a straight bridge with
//! deck rotation induced by abutment impact").
//!
//! The engine is its own crate (`deckspin-core`, re-exported here by its module names); the
//! studies, the CLI and the terminal workbench are layers over it.
//! - [`lemke`]: Lemke's algorithm for the LCP.
//! - [`scene`]: planar rigid bodies, contacts, force elements (eq. 1–2).
//! - [`contact`]: the impact LCP (eq. 5–7) and the contact LCP (eq. 8–10).
//! - [`dopri`], [`event_driven`]: the event-driven integrator.
//! - [`timestepping`]: Moreau–Jean and penalty methods; [`methods`]: the registry of methods;
//!   [`simulate`]: a scene to the method its settings name.
//! - [`hysteresis`]: linear, bilinear and Takeda laws for columns; compression-only backfill and
//!   shear-key laws.
//! - [`excitation`]: records, processing, multi-support motions.
//! - [`model`]: model files (general scenes and bridges).
//! - [`modal`]: K₀, modes and Rayleigh damping of any model.
//! - [`output`]: history, events, energy ledger, summary.
//! - [`studies`], [`stress`], [`suite`]: sweeps, the paper's studies, record suites
//!   (incremental dynamic analysis); [`shard`]: jobs cut into parts and merged; [`progress`]:
//!   how far a job has come.
//! - [`plot`]: charts as data, drawn as SVG or ASCII text; [`figures`]: the studies' charts.
//! - [`units`]: the model's unit system (the `units` key: SI-kN, SI, kip-in).
//! - [`design`]: fragility curves of a record suite (limit states: `model::limit_state`).
//! - [`studies`]: sweeps and the paper's studies; [`study_table`], [`study_csv`]: a study's
//!   results as a table that fills while it runs, and its CSV.

#[cfg(feature = "workbench")]
pub mod tui;

pub use deckspin_studies::{
    FrictionFork, ModelError, Observer, Run, RunOutput, Silent, SolverError, Stop, clock, contact,
    csv_error, design, dopri, event_driven, excitation, figures, hysteresis, input, lemke, linalg,
    load, methods, modal, model, output, plot, precision, precision_study, progress, run, scene,
    sequence, shard, simulate, stress, studies, study_csv, study_table, suite, timestepping, units,
};
