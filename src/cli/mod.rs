//! Commands of the `deckspin` binary kept apart from `main.rs`.

pub mod adequacy;
pub mod bench;
pub mod fragility;
pub mod jobs;
pub mod merge;
pub mod progress;
pub mod screen;
pub mod sequence;
pub mod show;
pub mod signals;
pub mod stdout;
pub mod stress;
pub mod suite;
pub mod sweep;
pub mod tables;
