//! Commands of the `deckspin` binary kept apart from `main.rs`.

pub mod bench;
pub mod screen;
pub mod sequence;
pub mod stress;
pub mod tables;
