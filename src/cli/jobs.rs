//! What `suite`, `sweep` and `stress` share: their journal (library `shard::journal`), the
//! stop on a signal with the runs kept, and the output joined in run order.

use deckspin::shard::journal::Journal;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// A job of many runs stopped by a signal: its finished runs are in the journal; exit 128 +
/// the signal's number.
#[derive(Debug)]
pub struct JobInterrupted {
    pub signal: i32,
    pub kept: usize,
    pub runs: usize,
    pub journal: PathBuf,
}

impl std::fmt::Display for JobInterrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "stopped by {}: {} of {} runs kept in {}; the same command with --resume runs the rest",
            super::signals::name(self.signal),
            self.kept,
            self.runs,
            self.journal.display()
        )
    }
}

impl std::error::Error for JobInterrupted {}

/// Err when a signal asked the job to stop (its journal kept).
pub fn stop_if_signalled(journal: &Journal, runs: usize) -> Result<(), JobInterrupted> {
    match super::signals::requested() {
        Some(signal) => Err(JobInterrupted {
            signal,
            kept: journal.rows(),
            runs,
            journal: journal.path().to_path_buf(),
        }),
        None => Ok(()),
    }
}

/// Records a row in the journal; the first failure to write it is kept and told once.
pub struct Recorder<'a> {
    pub journal: &'a Journal,
    failed: std::sync::Mutex<Option<std::io::Error>>,
}

impl<'a> Recorder<'a> {
    pub fn new(journal: &'a Journal) -> Self {
        Self {
            journal,
            failed: std::sync::Mutex::new(None),
        }
    }

    /// Row `index`'s CSV `line`.
    pub fn record(&self, index: usize, line: &str) {
        if let Err(e) = self.journal.record(index, line) {
            let mut f = self.failed.lock().unwrap_or_else(|p| p.into_inner());
            if f.is_none() {
                eprintln!(
                    "deckspin: {}: {e}: the job goes on, but if it is stopped it cannot be resumed from there",
                    self.journal.path().display()
                );
                *f = Some(e);
            }
        }
    }
}

/// The CSV of `header` (with its line break) and the `rows` in run order.
pub fn joined(header: &str, rows: &BTreeMap<usize, String>) -> String {
    let mut out = header.to_string();
    for line in rows.values() {
        out += line;
    }
    out
}

/// "N runs" or "N runs (K of them from the journal)".
pub fn counted(runs: usize, resumed: usize) -> String {
    if resumed == 0 {
        format!("{runs} runs")
    } else {
        format!("{runs} runs ({resumed} of them from the journal)")
    }
}

/// [`Journal::open`], telling on stderr when a journal of another job was replaced.
pub fn open_journal(
    out: &std::path::Path,
    kind: &str,
    job: &deckspin::shard::JobId,
    shard: deckspin::shard::Shard,
    runs: usize,
    header: &str,
    resume: bool,
) -> Result<(Journal, BTreeMap<usize, String>), deckspin::shard::journal::JournalError> {
    let (journal, done) = Journal::open(out, kind, job, shard, runs, header, resume)?;
    if let Some(why) = &journal.replaced {
        eprintln!("deckspin: a journal not of this job was replaced ({why})");
    }
    Ok((journal, done))
}
