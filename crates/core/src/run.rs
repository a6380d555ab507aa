//! The run API every method shares: why a run stopped ([`SolverError`]), observers of a run
//! in progress, and the batching of what a run adds for them.

use crate::lemke::LcpError;
use crate::methods::Method;
use crate::output::number::MAX_NUMBER_BYTES;
use crate::output::{EventRecord, HistoryWriter, RunOutput, Sample, Summary};
use crate::scene::Scene;
use serde::Serialize;
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;
use std::time::Instant;

/// Why a run stopped early. Every variant names the time.
#[derive(Debug, thiserror::Error)]
pub enum SolverError {
    /// An LCP (eq. 5–7 or 8–10) Lemke could not solve.
    #[error("t = {t:.9} s: {what} LCP failed: {source}")]
    Lcp {
        /// Simulated time, s.
        t: f64,
        /// Which LCP.
        what: &'static str,
        /// The underlying error.
        #[source]
        source: LcpError,
    },
    /// A sliding contact whose contact LCP has no solution or several (Painlevé).
    #[error(
        "t = {t:.9} s: Painlevé configuration at contact(s) {contacts}: {detail} (the contact LCP has no or several solutions)"
    )]
    Painleve {
        /// Simulated time, s.
        t: f64,
        /// The contacts involved.
        contacts: String,
        /// What was found.
        detail: String,
    },
    /// Impacts accumulating at one contact without end.
    #[error(
        "t = {t:.9} s: step collapse: {events} events of contact '{contact}' within {window:.3e} s ({})",
        if *rule { "impact accumulation that the accumulation rule did not close" } else { "impact accumulation; enable solver.accumulation_rule" }
    )]
    StepCollapse {
        /// Simulated time, s.
        t: f64,
        /// The contact's name.
        contact: String,
        /// Events located.
        events: usize,
        /// The window they fell in, s.
        window: f64,
        /// The accumulation rule was on.
        rule: bool,
    },
    /// The DP5 step fell below its minimum.
    #[error("t = {t:.9} s: step size {h:.3e} s fell below the minimum")]
    StepTooSmall {
        /// Simulated time, s.
        t: f64,
        /// The step size, s.
        h: f64,
    },
    /// More events than solver.max_events.
    #[error("t = {t:.9} s: more than {limit} events")]
    TooManyEvents {
        /// Simulated time, s.
        t: f64,
        /// The setting's value.
        limit: usize,
    },
    /// More steps than solver.max_steps.
    #[error("t = {t:.9} s: more than {limit} steps")]
    TooManySteps {
        /// Simulated time, s.
        t: f64,
        /// The setting's value.
        limit: usize,
    },
    /// A corner inside its face at t = 0.
    #[error("initial penetration at contact '{contact}': g_N = {gap:.6e} m")]
    InitialPenetration {
        /// The contact's name.
        contact: String,
        /// g_N, m.
        gap: f64,
    },
    /// A NaN or an infinity in the state.
    #[error("t = {t:.9} s: state became non-finite")]
    NonFinite {
        /// Simulated time, s.
        t: f64,
    },
    /// The stiffest mode needs more DP5 steps than solver.max_steps.
    #[error(
        "too stiff for the step budget: the stiffest mode (ω = {omega:.4e} rad/s) needs at least {steps:.3e} DP5 steps over t_end, more than solver.max_steps = {limit}"
    )]
    TooStiff {
        /// ω of the stiffest mode, rad/s.
        omega: f64,
        /// Steps it needs.
        steps: f64,
        /// The setting's value.
        limit: usize,
    },
    /// Events without time advancing.
    #[error(
        "t = {t:.9} s: time stopped advancing: {events} events since t = {since:.9} s (contacts: {contacts})"
    )]
    Stalled {
        /// Simulated time, s.
        t: f64,
        /// The window's start, s.
        since: f64,
        /// Events located.
        events: usize,
        /// Each contact's state, gap and gap rate at `t`.
        contacts: String,
    },
    /// A fixed-step method's state blew up.
    #[error("t = {t:.9} s: {method} with step {step:.3e} s is unstable: {detail}")]
    Unstable {
        /// Simulated time, s.
        t: f64,
        /// The method.
        method: &'static str,
        /// The step size, s.
        step: f64,
        /// What was found.
        detail: String,
    },
    /// A fixed-step method's iterations did not converge.
    #[error("t = {t:.9} s: {method} iterations did not converge: {detail}")]
    NoConvergence {
        /// Simulated time, s.
        t: f64,
        /// The method.
        method: &'static str,
        /// What was found.
        detail: String,
    },
    /// The observer asked the run to stop.
    #[error("t = {t:.9} s: cancelled")]
    Cancelled {
        /// Simulated time, s.
        t: f64,
    },
    /// A deck end left its seat.
    #[error(
        "t = {t:.9} s: the deck lost its seat at '{contact}': its gap reached {gap:.6e} m, the seat's edge (support length {width} m beyond the initial gap)"
    )]
    Unseated {
        /// Simulated time, s.
        t: f64,
        /// The contact's name.
        contact: String,
        /// g_N, m.
        gap: f64,
        /// The seat's support length, m.
        width: f64,
    },
    /// A finished run outside its accuracy bounds.
    #[error(
        "t = {t:.9} s: finished outside the accuracy asked for: {}",
        Bound::list(bounds)
    )]
    Inaccurate {
        /// Simulated time, s.
        t: f64,
        /// Every bound the run broke.
        bounds: Vec<Bound>,
    },
}

/// A bound of the accuracy judge a finished run broke (`simulate::judge`).
#[derive(Clone, Debug, PartialEq)]
pub struct Bound {
    /// "energy closure" (relative) or "penetration" (m).
    pub what: &'static str,
    /// The run's value.
    pub value: f64,
    /// The setting that bounds it: "max_closure" or "max_penetration".
    pub setting: &'static str,
    /// The setting's value.
    pub limit: f64,
    /// A setting that would meet it and its estimated cost, or what else to do.
    pub remedy: String,
}

impl Bound {
    /// "what value above solver.setting = limit (remedy); …".
    pub fn list(bounds: &[Bound]) -> String {
        (bounds.iter())
            .map(|b| {
                format!(
                    "{} {:.3e} above solver.{} = {:.3e} ({})",
                    b.what, b.value, b.setting, b.limit, b.remedy
                )
            })
            .collect::<Vec<_>>()
            .join("; ")
    }
}

/// Receives results while a run goes on (for live charts); return false to cancel.
pub trait Observer {
    /// New samples and events up to `t`; false cancels the run.
    fn batch(&mut self, samples: &[Sample], events: &[EventRecord], t: f64) -> bool;

    /// True when the observer keeps (or writes) every sample it is handed: the run's output
    /// then drops them, so that its memory does not grow with the run's length; the samples
    /// after the last batch stay in the [`Run`]'s `output.samples`.
    fn keeps_samples(&self) -> bool {
        false
    }
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
    /// The observer keeps the samples: the output drops those handed over, and the first new
    /// one is at `RunOutput::handed`.
    streamed: bool,
}

impl Batcher {
    pub(crate) fn new() -> Self {
        Self {
            samples: 0,
            events: 0,
            at: Instant::now(),
            streamed: false,
        }
    }

    /// Index of the first sample of `out` not handed over yet.
    fn first_new(&self, out: &RunOutput) -> usize {
        if self.streamed {
            out.handed.get().min(out.samples.len())
        } else {
            self.samples
        }
    }

    /// Hand over the new results when due; `Cancelled` when the observer says stop.
    pub(crate) fn maybe(
        &mut self,
        out: &RunOutput,
        t: f64,
        observer: &mut dyn Observer,
    ) -> Result<(), SolverError> {
        if out.samples.len() - self.first_new(out) >= 256 || self.at.elapsed().as_millis() >= 40 {
            let go = self.flush(out, t, observer);
            if !go {
                return Err(SolverError::Cancelled { t });
            }
        }
        Ok(())
    }

    pub(crate) fn flush(&mut self, out: &RunOutput, t: f64, observer: &mut dyn Observer) -> bool {
        let from = self.first_new(out);
        let go = observer.batch(&out.samples[from..], &out.events[self.events..], t);
        let streamed = observer.keeps_samples();
        if streamed {
            out.handed.set(out.samples.len());
        }
        *self = Self {
            samples: out.samples.len(),
            events: out.events.len(),
            at: Instant::now(),
            streamed,
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
    Cancelled {
        /// Simulated time, s.
        t: f64,
    },
    /// The method could not go on.
    Failed(SolverError),
}

/// What a run computed, however it ended: a cancelled or failed run keeps its output up to
/// the instant it stopped.
#[derive(Debug)]
pub struct Run {
    /// What it computed.
    pub output: RunOutput,
    /// How it ended.
    pub stop: Stop,
}

impl Run {
    /// The run that ended with `result` (a [`SolverError::Cancelled`] is a cancel). The samples
    /// handed to an observer that keeps them are dropped from the output; an output its method
    /// never summarised (a failure at the start) gets the summary of what it recorded.
    pub fn new(mut output: RunOutput, result: Result<(), SolverError>) -> Self {
        output.drop_handed();
        if output.summary.peaks.len() != output.dof_names.len() {
            output.finish(0.0);
        }
        let stop = match result {
            Ok(()) => Stop::Finished,
            Err(SolverError::Cancelled { t }) => Stop::Cancelled { t },
            Err(e) => Stop::Failed(e),
        };
        Self { output, stop }
    }

    /// It reached `t_end`.
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

impl SolverError {
    /// The instant the run stopped at (the start for an initial penetration).
    pub fn time(&self) -> f64 {
        match self {
            SolverError::InitialPenetration { .. } | SolverError::TooStiff { .. } => 0.0,
            SolverError::Stalled { t, .. }
            | SolverError::Lcp { t, .. }
            | SolverError::Painleve { t, .. }
            | SolverError::StepCollapse { t, .. }
            | SolverError::StepTooSmall { t, .. }
            | SolverError::TooManyEvents { t, .. }
            | SolverError::TooManySteps { t, .. }
            | SolverError::NonFinite { t }
            | SolverError::Unstable { t, .. }
            | SolverError::NoConvergence { t, .. }
            | SolverError::Inaccurate { t, .. }
            | SolverError::Unseated { t, .. }
            | SolverError::Cancelled { t } => *t,
        }
    }

    /// The variant's name (`"Lcp"`, `"TooManySteps"`, …), for files and scripts.
    pub fn kind(&self) -> &'static str {
        match self {
            SolverError::Lcp { .. } => "Lcp",
            SolverError::Painleve { .. } => "Painleve",
            SolverError::StepCollapse { .. } => "StepCollapse",
            SolverError::StepTooSmall { .. } => "StepTooSmall",
            SolverError::TooManyEvents { .. } => "TooManyEvents",
            SolverError::TooManySteps { .. } => "TooManySteps",
            SolverError::InitialPenetration { .. } => "InitialPenetration",
            SolverError::NonFinite { .. } => "NonFinite",
            SolverError::TooStiff { .. } => "TooStiff",
            SolverError::Stalled { .. } => "Stalled",
            SolverError::Unstable { .. } => "Unstable",
            SolverError::NoConvergence { .. } => "NoConvergence",
            SolverError::Cancelled { .. } => "Cancelled",
            SolverError::Inaccurate { .. } => "Inaccurate",
            SolverError::Unseated { .. } => "Unseated",
        }
    }
}

impl Stop {
    /// `"finished"`, `"cancelled"` or `"failed"` (the `status` of summary.json).
    pub fn label(&self) -> &'static str {
        match self {
            Stop::Finished => "finished",
            Stop::Cancelled { .. } => "cancelled",
            Stop::Failed(_) => "failed",
        }
    }
}

/// Why a run failed, as summary.json reports it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FailureReport {
    /// [`SolverError::time`].
    pub t: f64,
    /// The error's text.
    pub reason: String,
    /// [`SolverError::kind`].
    pub kind: &'static str,
}

impl From<&SolverError> for FailureReport {
    fn from(e: &SolverError) -> Self {
        Self {
            t: e.time(),
            reason: e.to_string(),
            kind: e.kind(),
        }
    }
}

/// summary.json: how the run stopped, then the summary's fields.
#[derive(Serialize)]
struct SummaryReport<'a> {
    status: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    failure: Option<FailureReport>,
    #[serde(skip_serializing_if = "Option::is_none")]
    cancelled_at: Option<f64>,
    #[serde(flatten)]
    summary: &'a Summary,
}

impl Run {
    /// Why the run failed, if it did.
    pub fn failure(&self) -> Option<FailureReport> {
        match &self.stop {
            Stop::Failed(e) => Some(e.into()),
            _ => None,
        }
    }

    /// summary.json: `"status"` (`"finished"`, `"cancelled"`, `"failed"`), for a failure
    /// `"failure": {"t", "reason", "kind"}`, for a cancel `"cancelled_at"`, then the fields of
    /// the output's [`Summary`].
    pub fn summary_json(&self) -> Result<String, serde_json::Error> {
        serde_json::to_string_pretty(&SummaryReport {
            status: self.stop.label(),
            failure: self.failure(),
            cancelled_at: match self.stop {
                Stop::Cancelled { t } => Some(t),
                _ => None,
            },
            summary: &self.output.summary,
        })
    }

    /// history.csv (the samples the output kept), events.csv and summary.json (with the status)
    /// in `dir` (created), as one transaction ([`crate::output::files::Staging`]).
    pub fn write_all(&self, dir: &Path) -> std::io::Result<()> {
        let staging = crate::output::files::Staging::begin(dir)?;
        self.output.write_history(&staging.path("history.csv"))?;
        self.output.write_events(&staging.path("events.csv"))?;
        let json = self.summary_json().map_err(std::io::Error::other)?;
        std::fs::write(staging.path("summary.json"), json)?;
        staging.commit(&format!(
            "{{\n  \"status\": \"writing\",\n  \"pid\": {}\n}}\n",
            std::process::id()
        ))
    }
}

/// Writes a run into a directory while it goes: the rows of history.csv from each batch (the
/// output keeps none of them: memory does not grow with the run's length), then, however the
/// run ended, the last rows, events.csv and summary.json ([`RunFiles::finish`]).
pub struct RunFiles {
    /// The output folder, locked, and the staging folder the files are made in.
    staging: crate::output::files::Staging,
    history: HistoryWriter<BufWriter<File>>,
    /// The first write error (the run is cancelled at it).
    error: Option<std::io::Error>,
    /// Keep the sample nearest to this instant.
    at: Option<f64>,
    nearest: Option<Sample>,
    /// Asked at each batch whether to stop (a signal to the front end): the run is then
    /// cancelled there.
    stop: Option<fn() -> bool>,
}

/// What [`RunFiles::finish`] wrote.
#[derive(Debug)]
pub struct Written {
    /// Rows of history.csv.
    pub rows: usize,
    /// The sample nearest to the instant asked for.
    pub nearest: Option<Sample>,
}

impl RunFiles {
    /// `dir` (created and locked: a second run on it is refused, naming the process that
    /// holds it) with the header of history.csv for `scene`'s columns in a staging folder;
    /// keeps the sample nearest to `at`. The previous result in `dir` stays whole until
    /// [`RunFiles::finish`] moves the new one in ([`crate::output::files::Staging`]).
    pub fn create(dir: &Path, scene: &Scene, at: Option<f64>) -> std::io::Result<Self> {
        let staging = crate::output::files::Staging::begin(dir)?;
        let file = BufWriter::new(
            File::options()
                .write(true)
                .create_new(true)
                .open(staging.path("history.csv"))?,
        );
        Ok(Self {
            history: HistoryWriter::new(file, &RunOutput::new(scene))?,
            staging,
            error: None,
            at,
            nearest: None,
            stop: None,
        })
    }

    /// The run is cancelled at the first batch at which `stop` says so.
    pub fn stop_when(&mut self, stop: fn() -> bool) {
        self.stop = Some(stop);
    }

    fn take(&mut self, samples: &[Sample]) -> std::io::Result<()> {
        if let Some(at) = self.at {
            let dist = |s: &Sample| (s.t - at).abs();
            if let Some(s) = samples.iter().min_by(|a, b| dist(a).total_cmp(&dist(b)))
                && self.nearest.as_ref().is_none_or(|n| dist(s) < dist(n))
            {
                self.nearest = Some(s.clone());
            }
        }
        self.history.write(samples)
    }

    /// The rows after the last batch, events.csv and summary.json of `run` (the run this
    /// observed), moved into the output folder as one result whatever the run's status
    /// (finished, failed, cancelled); the first write error, if any (the previous result then
    /// stays).
    pub fn finish(mut self, run: &Run) -> std::io::Result<Written> {
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        self.take(&run.output.samples)?;
        let rows = self.history.rows();
        self.history.finish()?;
        run.output.write_events(&self.staging.path("events.csv"))?;
        let json = run.summary_json().map_err(std::io::Error::other)?;
        std::fs::write(self.staging.path("summary.json"), json)?;
        let interim = format!(
            "{{\n  \"status\": \"writing\",\n  \"pid\": {}\n}}\n",
            std::process::id()
        );
        self.staging.commit(&interim)?;
        Ok(Written {
            rows,
            nearest: self.nearest,
        })
    }
}

impl Observer for RunFiles {
    fn batch(&mut self, samples: &[Sample], _: &[EventRecord], _: f64) -> bool {
        if self.error.is_some() {
            return false;
        }
        match self.take(samples) {
            Ok(()) => !self.stop.is_some_and(|stop| stop()),
            Err(e) => {
                self.error = Some(e);
                false
            }
        }
    }

    fn keeps_samples(&self) -> bool {
        true
    }
}

/// The size of a run's output, estimated from its settings before it runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutputEstimate {
    /// Rows on the output grid: ⌊t_end / output_dt⌋ + 2 (the last sample at t_end); for a
    /// fixed-step method at most one per step.
    pub grid_rows: f64,
    /// Rows at events, at most: a pre- and a post-event row per logged event, and
    /// `solver.max_events` bounds the log (event-driven; 0 for the fixed-step methods).
    pub event_rows: f64,
    /// Bytes of one row of history.csv, every number at its widest.
    pub row_bytes: f64,
    /// ⌈t_end / step⌉ of a fixed-step method (None for the event-driven one).
    pub steps: Option<f64>,
}

impl OutputEstimate {
    /// The estimate for `scene`'s settings.
    pub fn of(scene: &Scene) -> Self {
        let st = &scene.settings;
        let mut grid_rows = (st.t_end / st.output_dt).floor() + 2.0;
        let (steps, event_rows) = match st.method {
            Method::Event => (None, 2.0 * st.max_events as f64),
            _ => {
                let steps = (st.t_end / st.step).ceil();
                grid_rows = grid_rows.min(steps + 2.0);
                (Some(steps), 0.0)
            }
        };
        // a comma and the widest shortest round-trip number per value (t without the comma);
        // ",post-event", ",slide+" per contact, newline
        let numbers = 2 * scene.ndof()
            + 5 * scene.contacts.len()
            + 2 * scene.hysteretic.len()
            + scene.seats.len();
        let widest = (MAX_NUMBER_BYTES + 1) as f64;
        let row_bytes = widest * (numbers + 11) as f64 - 1.0 + 11.0;
        Self {
            grid_rows: nan_to_inf(grid_rows),
            event_rows,
            row_bytes: row_bytes + 7.0 * scene.contacts.len() as f64 + 1.0,
            steps: steps.map(nan_to_inf),
        }
    }

    /// Rows of history.csv at most.
    pub fn rows(&self) -> f64 {
        self.grid_rows + self.event_rows
    }

    /// Bytes of history.csv at most.
    pub fn bytes(&self) -> f64 {
        self.rows() * self.row_bytes
    }
}

fn nan_to_inf(x: f64) -> f64 {
    if x.is_nan() { f64::INFINITY } else { x }
}

/// The most a run may write: runs whose estimate is above are refused before they start.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutputBudget {
    /// The rows allowed.
    pub max_rows: f64,
    /// The bytes allowed.
    pub max_bytes: f64,
}

impl Default for OutputBudget {
    /// 5·10⁷ rows and 20 GB of history.csv.
    fn default() -> Self {
        Self {
            max_rows: 5e7,
            max_bytes: 2e10,
        }
    }
}

/// A run refused before it starts: what it would take, and the limit.
#[derive(Debug, thiserror::Error)]
pub enum LimitError {
    /// history.csv would be larger than the budget.
    #[error(
        "history.csv would hold up to {rows:.3e} rows ({grid_rows:.3e} from solver.t_end = {t_end} s / solver.output_dt = {output_dt} s, {event_rows:.3e} at events from solver.max_events = {max_events}), about {bytes:.3e} bytes: above the limit of {max_rows:.0e} rows and {max_bytes:.0e} bytes (raise solver.output_dt, lower solver.t_end or solver.max_events)"
    )]
    History {
        /// Rows it would hold.
        rows: f64,
        /// Rows on the output grid.
        grid_rows: f64,
        /// Rows at events, at most.
        event_rows: f64,
        /// Bytes it would take.
        bytes: f64,
        /// solver.t_end, s.
        t_end: f64,
        /// solver.output_dt, s.
        output_dt: f64,
        /// solver.max_events.
        max_events: usize,
        /// The rows allowed.
        max_rows: f64,
        /// The bytes allowed.
        max_bytes: f64,
    },
    /// The output grid is more than a run kept in memory may hold.
    #[error(
        "the output grid alone is {rows:.3e} rows (solver.t_end = {t_end} s / solver.output_dt = {output_dt} s), more than the {max_rows:e} a run kept in memory may hold (raise solver.output_dt or lower solver.t_end; `deckspin run` streams its history to disk)"
    )]
    Memory {
        /// Rows it would hold.
        rows: f64,
        /// solver.t_end, s.
        t_end: f64,
        /// solver.output_dt, s.
        output_dt: f64,
        /// The rows allowed.
        max_rows: f64,
    },
    /// A fixed-step run needs more steps than solver.max_steps.
    #[error(
        "solver.t_end = {t_end} s / solver.step = {step} s is {steps:.3e} steps, more than solver.max_steps = {max_steps} (raise solver.step or solver.max_steps, or lower solver.t_end)"
    )]
    Steps {
        /// Steps it needs.
        steps: f64,
        /// solver.t_end, s.
        t_end: f64,
        /// The step size, s.
        step: f64,
        /// solver.max_steps.
        max_steps: usize,
    },
    /// solver.h_max needs more steps than solver.max_steps.
    #[error(
        "solver.t_end = {t_end} s / solver.h_max = {h_max} s is at least {steps:.3e} event-driven steps, more than solver.max_steps = {max_steps} (raise solver.h_max or solver.max_steps, or lower solver.t_end)"
    )]
    MaxStep {
        /// Steps it needs.
        steps: f64,
        /// solver.t_end, s.
        t_end: f64,
        /// solver.h_max, s.
        h_max: f64,
        /// solver.max_steps.
        max_steps: usize,
    },
}

/// Rows (output samples) a run that keeps its history in memory may hold: about 1 kB each for
/// the bridge, so 1 GB (the workbench, the work–precision and stability studies; `deckspin
/// run` streams to disk instead).
pub const MEMORY_ROWS: f64 = 1e6;

/// A run that keeps its history in memory, refused when its output grid alone (t_end /
/// output_dt rows, at most one per step for a fixed-step method) is above [`MEMORY_ROWS`].
pub fn check_memory(scene: &Scene) -> Result<OutputEstimate, LimitError> {
    let est = OutputEstimate::of(scene);
    if est.grid_rows.is_nan() || est.grid_rows > MEMORY_ROWS {
        return Err(LimitError::Memory {
            rows: est.grid_rows,
            t_end: scene.settings.t_end,
            output_dt: scene.settings.output_dt,
            max_rows: MEMORY_ROWS,
        });
    }
    Ok(est)
}

/// The estimate of `scene`'s output, or why the run is refused: a fixed-step method needing
/// more than `solver.max_steps` steps, or a history above `budget`.
pub fn check_output(scene: &Scene, budget: &OutputBudget) -> Result<OutputEstimate, LimitError> {
    let st = &scene.settings;
    let est = OutputEstimate::of(scene);
    if let Some(steps) = est.steps
        && steps > st.max_steps as f64
    {
        return Err(LimitError::Steps {
            steps,
            t_end: st.t_end,
            step: st.step,
            max_steps: st.max_steps,
        });
    }
    // the event-driven method takes at least t_end / h_max steps
    if st.method == Method::Event && st.h_max > 0.0 {
        let steps = (st.t_end / st.h_max).ceil();
        if steps.is_nan() || steps > st.max_steps as f64 {
            return Err(LimitError::MaxStep {
                steps,
                t_end: st.t_end,
                h_max: st.h_max,
                max_steps: st.max_steps,
            });
        }
    }
    // negated: a NaN estimate is refused too
    if !(est.rows() <= budget.max_rows && est.bytes() <= budget.max_bytes) {
        return Err(LimitError::History {
            rows: est.rows(),
            grid_rows: est.grid_rows,
            event_rows: est.event_rows,
            bytes: est.bytes(),
            t_end: st.t_end,
            output_dt: st.output_dt,
            max_events: st.max_events,
            max_rows: budget.max_rows,
            max_bytes: budget.max_bytes,
        });
    }
    Ok(est)
}
