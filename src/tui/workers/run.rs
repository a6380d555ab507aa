//! Simulation runs off the UI thread with `simulate::integrate` (the method the model's
//! `solver.method` names): the engine's observer forwards each batch of new samples and events
//! as a [`Msg::Batch`]; the end of the run is a [`Msg::RunDone`]. A run is cancelled through a
//! flag the observer checks at every batch.

use crate::output::{EventRecord, Sample};
use crate::run::{Observer, Run, Stop};
use crate::scene::Scene;
use crate::tui::msg::{Msg, RunOutcome};
use crate::tui::runs::data::RunFailure;
use std::cell::RefCell;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::Sender;

/// Prefix of worker thread names (the panic hook leaves the terminal alone for these).
pub const THREAD_PREFIX: &str = "deckspin-worker";

thread_local! {
    /// Message of a panic on this worker thread (set by the panic hook).
    pub static LAST_PANIC: RefCell<Option<String>> = const { RefCell::new(None) };
}

/// Test hook: `DECKSPIN_TEST_PANIC=ui` panics on the UI thread after the first frame,
/// `=worker` inside the simulation thread (the end-to-end test checks the terminal is restored
/// and the worker's panic is reported as a failed run).
pub(crate) fn test_panic(place: &str) -> bool {
    std::env::var("DECKSPIN_TEST_PANIC").is_ok_and(|v| v == place)
}

/// A running simulation.
pub struct RunHandle {
    pub id: u64,
    cancel: Arc<AtomicBool>,
}

impl RunHandle {
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }
}

// A workbench run keeps at most `run::MEMORY_ROWS` rows in memory. A run whose output grid
// alone is larger is refused before it starts; one that reaches the limit through its events
// stops there with `RunFailure::Memory`, its samples so far shown.
use crate::run::MEMORY_ROWS;

/// Forwards batches to a sink; stops the run when cancelled, when the sink is gone or at
/// [`MEMORY_ROWS`].
struct Stream<F: FnMut(Msg) -> bool> {
    id: u64,
    cancel: Option<Arc<AtomicBool>>,
    sink: F,
    /// Rows forwarded so far.
    rows: usize,
    /// The run reached [`MEMORY_ROWS`] at this instant.
    full: Option<f64>,
}

impl<F: FnMut(Msg) -> bool> Stream<F> {
    fn cancelled(&self) -> bool {
        self.cancel
            .as_ref()
            .is_some_and(|c| c.load(Ordering::Relaxed))
    }
}

impl<F: FnMut(Msg) -> bool> Observer for Stream<F> {
    fn batch(&mut self, samples: &[Sample], events: &[EventRecord], t: f64) -> bool {
        if self.cancelled() {
            return false;
        }
        self.rows += samples.len();
        if self.rows as f64 > MEMORY_ROWS {
            self.full = Some(t);
            return false;
        }
        let alive = (self.sink)(Msg::Batch {
            run: self.id,
            samples: samples.to_vec(),
            events: events.to_vec(),
            t,
        });
        alive && !self.cancelled()
    }
}

/// The end of a run; `full`: it stopped at [`MEMORY_ROWS`] at that instant.
fn outcome(r: Run, full: Option<f64>) -> RunOutcome {
    if let (Some(t), Stop::Cancelled { .. }) = (full, &r.stop) {
        let (rows, limit) = (MEMORY_ROWS + 1.0, MEMORY_ROWS);
        return RunOutcome::Failed(Arc::new(RunFailure::Memory { rows, limit, t }));
    }
    match r.stop {
        Stop::Finished => RunOutcome::Finished(Box::new(r.output)),
        Stop::Cancelled { t } => RunOutcome::Cancelled { t },
        Stop::Failed(e @ crate::run::SolverError::Inaccurate { .. }) => RunOutcome::Inaccurate {
            output: Box::new(r.output),
            failure: Arc::new(RunFailure::Solver(e)),
        },
        Stop::Failed(e) => RunOutcome::Failed(Arc::new(RunFailure::Solver(e))),
    }
}

/// The message of a panic caught on a worker thread.
pub(crate) fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    LAST_PANIC
        .with(|l| l.borrow_mut().take())
        .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// A job's body in its thread: given its cancel flag and a sender of its messages, it returns
/// its last message.
pub type JobBody = Box<dyn FnOnce(&AtomicBool, &(dyn Fn(Msg) + Sync)) -> Msg + Send>;

/// Starts `body` in a thread named `name` (under [`THREAD_PREFIX`], so that a panic in it is
/// the job's to report) with a new cancel flag, its messages and its last one sent to `tx`;
/// when the thread cannot start, `failed` with the reason is sent instead. Returns the flag.
/// (The studies' and the results pages' workers.)
pub fn spawn_job(
    name: &str,
    tx: Sender<Msg>,
    body: JobBody,
    failed: impl FnOnce(String) -> Msg,
) -> Arc<AtomicBool> {
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    let tx2 = tx.clone();
    let spawned = std::thread::Builder::new()
        .name(format!("{THREAD_PREFIX}-{name}"))
        .spawn(move || {
            let send = |m: Msg| {
                let _ = tx.send(m);
            };
            let done = body(&flag, &send);
            let _ = tx.send(done);
        });
    if let Err(e) = spawned {
        let _ = tx2.send(failed(format!("cannot start a thread: {e}")));
    }
    cancel
}

/// Starts run `id` of `scene` in a worker thread sending to `tx`.
pub fn spawn(id: u64, scene: Scene, tx: Sender<Msg>) -> RunHandle {
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    let tx2 = tx.clone();
    let spawned = std::thread::Builder::new()
        .name(format!("{THREAD_PREFIX}-{id}"))
        .spawn(move || {
            let sink_tx = tx.clone();
            let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                let mut obs = Stream {
                    id,
                    cancel: Some(flag),
                    sink: |m| sink_tx.send(m).is_ok(),
                    rows: 0,
                    full: None,
                };
                if test_panic("worker") {
                    panic!("DECKSPIN_TEST_PANIC=worker: a panic in the simulation thread");
                }
                if let Some(refused) = refuse(&scene) {
                    return (None, Some(refused));
                }
                let run = integrate_refined(id, scene, &mut obs);
                (Some((run, obs.full)), None)
            }));
            let outcome = match result {
                Ok((Some((r, full)), _)) => outcome(r, full),
                Ok((None, refused)) => refused.unwrap_or(RunOutcome::Cancelled { t: 0.0 }),
                Err(p) => RunOutcome::Failed(Arc::new(RunFailure::Panic(panic_text(p.as_ref())))),
            };
            let _ = tx.send(Msg::RunDone { run: id, outcome });
        });
    if let Err(e) = spawned {
        let _ = tx2.send(Msg::RunDone {
            run: id,
            outcome: RunOutcome::Failed(Arc::new(RunFailure::Thread(e.to_string()))),
        });
    }
    RunHandle { id, cancel }
}

/// Runs `scene` to completion in this thread and returns the messages a worker would have sent
/// (for tests and headless use).
pub fn run_blocking(id: u64, scene: &Scene) -> Vec<Msg> {
    let mut msgs = Vec::new();
    let r = {
        if let Some(refused) = refuse(scene) {
            msgs.push(Msg::RunDone {
                run: id,
                outcome: refused,
            });
            return msgs;
        }
        let mut obs = Stream {
            id,
            cancel: None,
            sink: |m| {
                msgs.push(m);
                true
            },
            rows: 0,
            full: None,
        };
        let run = integrate_refined(id, scene.clone(), &mut obs);
        (run, obs.full)
    };
    msgs.push(Msg::RunDone {
        run: id,
        outcome: outcome(r.0, r.1),
    });
    msgs
}

/// `simulate::integrate`, then again at a finer step while the judge finds a run of a step
/// the method chose outside its bounds (`simulate::refined`, at most
/// `simulate::MAX_REFINEMENTS` times, as `deckspin run` does); each restart is announced.
fn integrate_refined<F: FnMut(Msg) -> bool>(id: u64, mut scene: Scene, obs: &mut Stream<F>) -> Run {
    let mut refinements = 0;
    loop {
        let run = crate::simulate::integrate(&scene, obs);
        if refinements < crate::simulate::MAX_REFINEMENTS
            && !obs.cancelled()
            && obs.full.is_none()
            && let Some(next) = crate::simulate::refined(&scene, &run)
        {
            refinements += 1;
            let why = next.settings.step_chosen.clone().unwrap_or_default();
            if !(obs.sink)(Msg::Refined { run: id, why }) {
                return run;
            }
            obs.rows = 0;
            scene = next;
            continue;
        }
        return run;
    }
}

/// A run whose output grid alone (t_end / output_dt rows) is above [`MEMORY_ROWS`], refused
/// before it starts.
fn refuse(scene: &Scene) -> Option<RunOutcome> {
    let e = crate::run::check_memory(scene).err()?;
    let crate::run::LimitError::Memory { rows, max_rows, .. } = e else {
        return None;
    };
    let failure = RunFailure::Memory {
        rows,
        limit: max_rows,
        t: 0.0,
    };
    Some(RunOutcome::Failed(Arc::new(failure)))
}
