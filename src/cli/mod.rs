//! Commands of the `deckspin` binary kept apart from `main.rs`.

pub mod stress;
