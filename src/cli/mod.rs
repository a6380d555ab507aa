//! Commands of the `deckspin` binary kept apart from `main.rs`.

pub mod bench;
pub mod fragility;
pub mod sequence;
pub mod show;
pub mod stress;
pub mod tables;
