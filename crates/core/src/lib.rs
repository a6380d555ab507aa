//! deckspin's engine — nonsmooth seismic analysis of bridges whose decks pound their abutments
//! and rotate in plan (reference: "Nonsmooth seismic response analysis of a straight bridge with
//! deck rotation induced by abutment impact"). No front end: the studies, the CLI, the terminal
//! workbench and the Python package are layers over it.
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
//! - [`output`]: history, events, energy ledger, summary, and their files.
//! - [`run`]: the run API (observer, stop, errors); [`clock`]: CPU clocks; [`input`]: bounded
//!   reading of user files; [`linalg`]: small dense solves; [`units`]: the model's unit system.
#![warn(missing_docs)]

pub mod clock;
pub mod contact;
pub mod dopri;
pub mod event_driven;
pub mod excitation;
pub mod hysteresis;
pub mod input;
pub mod lemke;
pub mod linalg;
pub mod methods;
pub mod modal;
pub mod model;
pub mod output;
pub mod run;
pub mod scene;
pub mod simulate;
pub mod timestepping;
pub mod units;

pub use event_driven::{FrictionFork, run};
pub use model::{ModelError, load};
pub use output::RunOutput;
pub use run::{Observer, Run, Silent, SolverError, Stop};
pub use simulate::simulate;
