//! Design answers: screening by the impact law before any run (`screen`), and which gap
//! element reproduces the event-driven answer (`equivalence`).

pub mod equivalence;
pub mod screen;
