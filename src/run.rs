//! The run API every method shares: why a run stopped ([`SolverError`]), observers of a run
//! in progress, and the batching of what a run adds for them.

use crate::lemke::LcpError;
use crate::output::{EventRecord, RunOutput, Sample};
use std::time::Instant;

/// Why a run stopped early. Every variant names the time.
#[derive(Debug, thiserror::Error)]
pub enum SolverError {
    #[error("t = {t:.9} s: {what} LCP failed: {source}")]
    Lcp {
        t: f64,
        what: &'static str,
        #[source]
        source: LcpError,
    },
    #[error(
        "t = {t:.9} s: Painlevé configuration at contact(s) {contacts}: {detail} (the contact LCP has no or several solutions)"
    )]
    Painleve {
        t: f64,
        contacts: String,
        detail: String,
    },
    #[error(
        "t = {t:.9} s: step collapse: {events} events of contact '{contact}' within {window:.3e} s ({})",
        if *rule { "impact accumulation that the accumulation rule did not close" } else { "impact accumulation; enable solver.accumulation_rule" }
    )]
    StepCollapse {
        t: f64,
        contact: String,
        events: usize,
        window: f64,
        /// The accumulation rule was on.
        rule: bool,
    },
    #[error("t = {t:.9} s: step size {h:.3e} s fell below the minimum")]
    StepTooSmall { t: f64, h: f64 },
    #[error("t = {t:.9} s: more than {limit} events")]
    TooManyEvents { t: f64, limit: usize },
    #[error("t = {t:.9} s: more than {limit} steps")]
    TooManySteps { t: f64, limit: usize },
    #[error("initial penetration at contact '{contact}': g_N = {gap:.6e} m")]
    InitialPenetration { contact: String, gap: f64 },
    #[error("t = {t:.9} s: state became non-finite")]
    NonFinite { t: f64 },
    #[error(
        "too stiff for the step budget: the stiffest mode (ω = {omega:.4e} rad/s) needs at least {steps:.3e} DP5 steps over t_end, more than solver.max_steps = {limit}"
    )]
    TooStiff {
        omega: f64,
        steps: f64,
        limit: usize,
    },
    #[error(
        "t = {t:.9} s: time stopped advancing: {events} events since t = {since:.9} s (contacts: {contacts})"
    )]
    Stalled {
        t: f64,
        since: f64,
        events: usize,
        /// Each contact's state, gap and gap rate at `t`.
        contacts: String,
    },
    #[error("t = {t:.9} s: {method} with step {step:.3e} s is unstable: {detail}")]
    Unstable {
        t: f64,
        method: &'static str,
        step: f64,
        detail: String,
    },
    #[error("t = {t:.9} s: {method} iterations did not converge: {detail}")]
    NoConvergence {
        t: f64,
        method: &'static str,
        detail: String,
    },
    #[error("t = {t:.9} s: cancelled")]
    Cancelled { t: f64 },
}

/// Receives results while a run goes on (for live charts); return false to cancel.
pub trait Observer {
    fn batch(&mut self, samples: &[Sample], events: &[EventRecord], t: f64) -> bool;
}

/// An observer that only lets the run go on.
pub struct Silent;

impl Observer for Silent {
    fn batch(&mut self, _: &[Sample], _: &[EventRecord], _: f64) -> bool {
        true
    }
}

/// Streams what a run adds to an [`Observer`]: every 256 samples or 40 ms, and at the end.
pub(crate) struct Batcher {
    samples: usize,
    events: usize,
    at: Instant,
}

impl Batcher {
    pub(crate) fn new() -> Self {
        Self {
            samples: 0,
            events: 0,
            at: Instant::now(),
        }
    }

    /// Hand over the new results when due; `Cancelled` when the observer says stop.
    pub(crate) fn maybe(
        &mut self,
        out: &RunOutput,
        t: f64,
        observer: &mut dyn Observer,
    ) -> Result<(), SolverError> {
        if out.samples.len() - self.samples >= 256 || self.at.elapsed().as_millis() >= 40 {
            let go = self.flush(out, t, observer);
            if !go {
                return Err(SolverError::Cancelled { t });
            }
        }
        Ok(())
    }

    pub(crate) fn flush(&mut self, out: &RunOutput, t: f64, observer: &mut dyn Observer) -> bool {
        let go = observer.batch(&out.samples[self.samples..], &out.events[self.events..], t);
        *self = Self {
            samples: out.samples.len(),
            events: out.events.len(),
            at: Instant::now(),
        };
        go
    }
}

/// How a run ended.
#[derive(Debug)]
pub enum Stop {
    /// It reached `t_end`.
    Finished,
    /// The observer asked it to stop at `t`.
    Cancelled { t: f64 },
    /// The method could not go on.
    Failed(SolverError),
}

/// What a run computed, however it ended: a cancelled or failed run keeps its output up to
/// the instant it stopped.
#[derive(Debug)]
pub struct Run {
    pub output: RunOutput,
    pub stop: Stop,
}

impl Run {
    /// The run that ended with `result` (a [`SolverError::Cancelled`] is a cancel).
    pub fn new(output: RunOutput, result: Result<(), SolverError>) -> Self {
        let stop = match result {
            Ok(()) => Stop::Finished,
            Err(SolverError::Cancelled { t }) => Stop::Cancelled { t },
            Err(e) => Stop::Failed(e),
        };
        Self { output, stop }
    }

    pub fn finished(&self) -> bool {
        matches!(self.stop, Stop::Finished)
    }

    /// The output of a finished run, else why it stopped (the partial output is dropped).
    pub fn into_result(self) -> Result<RunOutput, SolverError> {
        match self.stop {
            Stop::Finished => Ok(self.output),
            Stop::Cancelled { t } => Err(SolverError::Cancelled { t }),
            Stop::Failed(e) => Err(e),
        }
    }
}
