//! deckspin — nonsmooth seismic analysis of bridges whose decks pound their abutments and
//! rotate in plan (reference: "Nonsmooth seismic response analysis of a straight bridge with
//! deck rotation induced by abutment impact").
//!
//! The engine is plain modules; the CLI and the terminal workbench are thin layers over it.
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

pub mod clock;
pub mod contact;
pub mod design;
pub mod dopri;
pub mod event_driven;
pub mod excitation;
pub mod figures;
pub mod hysteresis;
pub mod input;
pub mod lemke;
pub mod linalg;
pub mod methods;
pub mod modal;
pub mod model;
pub mod output;
pub mod plot;
pub mod precision;
pub mod precision_study;
pub mod progress;
pub mod run;
pub mod scene;
pub mod sequence;
pub mod shard;
pub mod simulate;
pub mod stress;
pub mod studies;
pub mod study_csv;
pub mod study_table;
pub mod suite;
pub mod timestepping;
#[cfg(feature = "workbench")]
pub mod tui;
pub mod units;

pub use event_driven::{FrictionFork, run};
pub use model::{ModelError, load};
pub use output::RunOutput;
pub use run::{Observer, Run, Silent, SolverError, Stop};
pub use simulate::simulate;
