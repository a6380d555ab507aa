//! Record suites (incremental dynamic analysis).

pub mod intensity;
