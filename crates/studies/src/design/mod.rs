//! Design answers: screening by the impact law before any run (`screen`), which gap element
//! reproduces the event-driven answer (`equivalence`), and fragility curves of a record suite
//! (lognormal, maximum likelihood over multiple stripes or IDA capacities, bootstrap band;
//! Baker 2015).
//!
//! - `suite`: the suite's per-run CSV.
//! - `mle`: the likelihoods and their maximisation; `normal`: Φ and its logarithm.
//! - `bootstrap`: resampling records with a seeded generator.
//! - `fragility`: limit states over a suite's runs → fitted curves with their band.
//! - `chart`: the curves as a `plot::Chart`.
//! - `cases`: the runs a model study measures; `sensitivity`: which uncertain inputs the
//!   answer is most sensitive to, `swings` its rows and swings, `tornado` its chart.

pub mod adequacy;
pub mod adequacy_report;
pub mod bootstrap;
pub mod cases;
pub mod chart;
pub mod equivalence;
pub mod fragility;
pub mod ladder;
pub mod mle;
pub mod normal;
pub mod screen;
pub mod screen_chart;
pub mod sensitivity;
pub mod suite;
pub mod swings;
pub mod tornado;

pub use fragility::{Fragility, FragilityError, Method, Options, fragility};
pub use mle::{Capacity, Count, Fit, FitError};
pub use suite::{Suite, SuiteError};
