//! Studies off the UI thread: `study_table::run_study` on the form's model in a thread of its
//! own, with its runs on a pool of threads named like the simulation's (a panic there is
//! reported, the terminal left alone). Each row is a [`Msg::StudyRow`] as soon as it is
//! final; the end a [`Msg::StudyDone`] with the whole table. A study whose table comes whole
//! at its end (the ladder, the swings) counts its runs in [`Msg::StudyProgress`] instead. A
//! cancel flag, read before each run starts, skips the runs not started.

use crate::precision_study::run_precision;
use crate::progress::Progress;
use crate::studies::{Row, Study, Watch};
use crate::study_table::{StudyKind, StudyTable, run_study};
use crate::tui::form::shown_error;
use crate::tui::msg::{Msg, StudyOutcome};
use crate::tui::studies::StudySpec;
use crate::tui::workers::run::{JobBody, THREAD_PREFIX, panic_text, spawn_job};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::mpsc::Sender;
use std::sync::{Arc, Mutex};

/// A running study.
pub struct StudyHandle {
    pub id: u64,
    cancel: Arc<AtomicBool>,
}

impl StudyHandle {
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }
}

/// Forwards each final row (and, when `count`, the runs planned and done); stops when
/// cancelled.
struct Watcher<'a> {
    id: u64,
    cancel: &'a AtomicBool,
    send: &'a (dyn Fn(Msg) + Sync),
    count: bool,
    done: AtomicUsize,
    all: AtomicUsize,
}

impl Watcher<'_> {
    fn tell(&self) {
        let (done, all) = (
            self.done.load(Ordering::Relaxed),
            self.all.load(Ordering::Relaxed),
        );
        (self.send)(Msg::StudyProgress {
            id: self.id,
            done: done.min(all),
            all,
        });
    }
}

impl Progress for Watcher<'_> {
    fn plan(&self, runs: usize) {
        if self.count {
            self.all.fetch_add(runs, Ordering::Relaxed);
            self.tell();
        }
    }
    fn done(&self, runs: usize) {
        if self.count {
            self.done.fetch_add(runs, Ordering::Relaxed);
            self.tell();
        }
    }
    fn go_on(&self) -> bool {
        !self.cancel.load(Ordering::Relaxed)
    }
}

impl Watch for Watcher<'_> {
    fn row(&self, index: usize, row: &Row) {
        (self.send)(Msg::StudyRow {
            id: self.id,
            index,
            row: Box::new(row.clone()),
        });
    }
}

/// Runs study `id` in this thread (its runs on a pool of named threads), sending its rows to
/// `send`; returns its [`Msg::StudyDone`].
pub fn run(id: u64, spec: &StudySpec, cancel: &AtomicBool, send: &(dyn Fn(Msg) + Sync)) -> Msg {
    let work = || {
        let study = Study::from_text(&spec.text, &spec.path, &spec.overrides)
            .map_err(|e| shown_error(&e))?;
        let watch = Watcher {
            id,
            cancel,
            send,
            count: matches!(spec.kind, StudyKind::Adequacy | StudyKind::Sensitivity),
            done: AtomicUsize::new(0),
            all: AtomicUsize::new(0),
        };
        let point = |index: usize, p: &crate::precision::Point| {
            let point = Box::new(p.clone());
            send(Msg::StudyPoint { id, index, point })
        };
        let go = || match spec.kind {
            // one point at a time, each to the view as it is final (its CPU time alone)
            StudyKind::Precision => {
                run_precision(&study, &watch, &point).map(StudyTable::Precision)
            }
            _ => run_study(spec.kind, &study, &spec.mus, &spec.suite, &watch),
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .thread_name(move |i| format!("{THREAD_PREFIX}-study{id}-{i}"))
            .build();
        match pool {
            Ok(p) => p.install(go),
            Err(_) => go(),
        }
        .map_err(|e| e.to_string())
    };
    let outcome = match std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)) {
        Ok(Ok(table)) => {
            let (done, all) = table.progress();
            if done < all {
                StudyOutcome::Cancelled(Box::new(table))
            } else {
                StudyOutcome::Finished(Box::new(table))
            }
        }
        // a study that stops on a cancel without a table (the ladder) ends cancelled
        Ok(Err(_)) if cancel.load(Ordering::Relaxed) => StudyOutcome::Abandoned,
        Ok(Err(e)) => StudyOutcome::Failed(e),
        Err(p) => StudyOutcome::Failed(format!("panic: {}", panic_text(p.as_ref()))),
    };
    Msg::StudyDone { id, outcome }
}

/// Starts study `id` in a thread sending to `tx`.
pub fn spawn(id: u64, spec: StudySpec, tx: Sender<Msg>) -> StudyHandle {
    let body: JobBody = Box::new(move |flag, send| run(id, &spec, flag, send));
    let cancel = spawn_job(&format!("study{id}"), tx, body, |why| Msg::StudyDone {
        id,
        outcome: StudyOutcome::Failed(why),
    });
    StudyHandle { id, cancel }
}

/// Runs study `id` to its end in this thread and returns the messages a worker would have
/// sent (for tests and headless use).
pub fn run_blocking(id: u64, spec: &StudySpec) -> Vec<Msg> {
    let msgs = Mutex::new(Vec::new());
    let send = |m: Msg| msgs.lock().unwrap_or_else(|p| p.into_inner()).push(m);
    let done = run(id, spec, &AtomicBool::new(false), &send);
    let mut msgs = msgs.into_inner().unwrap_or_else(|p| p.into_inner());
    msgs.push(done);
    msgs
}
