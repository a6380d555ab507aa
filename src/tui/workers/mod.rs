//! The workbench's threads off the UI: runs (`run`), studies (`study`), the results pages'
//! modes and records (`results`), and the model file's watcher for hot reload (`watch`).

pub mod results;
pub mod run;
pub mod study;
pub mod watch;
