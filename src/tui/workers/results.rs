//! The model's results off the UI thread: the modes, and the input records with their
//! response spectrum (a period at a time, with progress, stopped by a cancel flag). The end
//! is a [`Msg::ResultDone`]; a panic is reported as a failure, the terminal left alone.

use crate::excitation::G;
use crate::scene::Scene;
use crate::suite::intensity::pseudo_acceleration;
use crate::tui::msg::{Msg, ResultData, ResultOutcome};
use crate::tui::results::{
    Component, RecordsData, ResultSpec, modes_data, record_supports, spectrum, spectrum_periods,
};
use crate::tui::workers::run::{JobBody, panic_text, spawn_job};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::Sender;

/// A running computation.
pub struct ResultHandle {
    pub id: u64,
    cancel: Arc<AtomicBool>,
}

impl ResultHandle {
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }
}

/// The records of `scene`, each with its spectrum and Sa(T₁); None when cancelled.
fn records(
    scene: &Scene,
    cancel: &AtomicBool,
    progress: &dyn Fn(usize, usize),
) -> Option<RecordsData> {
    let t1 = modes_data(scene)
        .periods
        .iter()
        .copied()
        .find(|p| p.is_finite())
        .unwrap_or(f64::NAN);
    let (recs, harmonic) = record_supports(scene);
    let periods = spectrum_periods();
    let all = recs.len() * periods.len();
    let mut done = 0;
    let mut components = Vec::new();
    for (name, acc, dt, t0, disp) in recs {
        let mut step = || {
            done += 1;
            if done % 20 == 0 {
                progress(done, all);
            }
        };
        let spectrum = spectrum(&acc, dt, &periods, cancel, &mut step)?;
        let sa_t1 = if t1.is_finite() {
            pseudo_acceleration(&acc, dt, t1, crate::tui::results::SPECTRUM_DAMPING) / G
        } else {
            f64::NAN
        };
        components.push(Component {
            name,
            t0,
            dt,
            acc_g: acc.iter().map(|a| a / G).collect(),
            disp,
            spectrum,
            sa_t1,
        });
    }
    Some(RecordsData {
        t1,
        components,
        harmonic,
    })
}

/// Computes `spec` in this thread, progress to `send`; returns its [`Msg::ResultDone`].
pub fn run(id: u64, spec: &ResultSpec, cancel: &AtomicBool, send: &dyn Fn(Msg)) -> Msg {
    let progress = |done, all| send(Msg::ResultProgress { id, done, all });
    let work = || match spec {
        ResultSpec::Modes(scene) => Some(ResultData::Modes(Box::new(modes_data(scene)))),
        ResultSpec::Records(scene) => {
            records(scene, cancel, &progress).map(|r| ResultData::Records(Box::new(r)))
        }
    };
    let outcome = match std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)) {
        Ok(Some(d)) => ResultOutcome::Done(d),
        Ok(None) => ResultOutcome::Cancelled,
        Err(p) => ResultOutcome::Failed(format!("panic: {}", panic_text(p.as_ref()))),
    };
    Msg::ResultDone { id, outcome }
}

/// Starts computation `id` in a thread sending to `tx`.
pub fn spawn(id: u64, spec: ResultSpec, tx: Sender<Msg>) -> ResultHandle {
    let body: JobBody = Box::new(move |flag, send| run(id, &spec, flag, send));
    let cancel = spawn_job(&format!("result{id}"), tx, body, |why| Msg::ResultDone {
        id,
        outcome: ResultOutcome::Failed(why),
    });
    ResultHandle { id, cancel }
}

/// Computes `spec` to its end in this thread: the messages a worker would have sent.
pub fn run_blocking(id: u64, spec: &ResultSpec) -> Vec<Msg> {
    let msgs = std::cell::RefCell::new(Vec::new());
    let done = run(id, spec, &AtomicBool::new(false), &|m| {
        msgs.borrow_mut().push(m)
    });
    let mut msgs = msgs.into_inner();
    msgs.push(done);
    msgs
}
