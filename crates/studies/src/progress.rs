//! How far a long job has come: the studies report runs planned and runs done to a
//! [`Progress`] they are handed; the front end draws it (the library never prints).

/// Receives a job's counts of runs; called from the worker threads.
pub trait Progress: Sync {
    /// `runs` more runs are planned (a job of several sweeps adds each sweep's).
    fn plan(&self, runs: usize);
    /// `runs` more runs are done.
    fn done(&self, runs: usize);
    /// False: the runs not started yet are skipped (a sweep's rows fail with
    /// `studies::RunFailure::Cancelled`). Always true by default.
    fn go_on(&self) -> bool {
        true
    }
}

/// A progress nobody watches.
pub struct Unwatched;

impl Progress for Unwatched {
    fn plan(&self, _: usize) {}
    fn done(&self, _: usize) {}
}
