//! The journal of a job of many runs (`suite`, `sweep`, `stress`): each finished run's CSV row
//! is appended to `OUT.journal` as it finishes, so that a job stopped by a signal, a kill or a
//! power loss is resumed (`--resume`) without running again what is done, and its output is
//! the one an uninterrupted job writes, byte for byte (rows are joined in run order at the end).
//!
//! Layout: the line `#deckspin-journal kind=KIND shard=K/N runs=M` with the job's fingerprint
//! ([`JobId`] fields), the line `run,HEADER`, then one line `INDEX,ROW` per finished run in the
//! order they finished. A last line without its line break (cut by a kill) is dropped.

use super::{JobId, Shard};
use std::collections::BTreeMap;
use std::fs::File;
use std::io::Write;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Why a journal cannot be opened or resumed.
#[derive(Debug, thiserror::Error)]
pub enum JournalError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error(
        "{path} holds {done} of {runs} runs of an interrupted job: add --resume to finish it, or delete the journal to start again"
    )]
    Exists {
        path: PathBuf,
        done: usize,
        runs: usize,
    },
    #[error(
        "{path}:1: the journal is of another job ({what} is {found}, this job's is {expected}): delete it, or resume with the job's own arguments"
    )]
    OtherJob {
        path: PathBuf,
        what: String,
        found: String,
        expected: String,
    },
    #[error("{path}:{line}: {reason}")]
    Corrupt {
        path: PathBuf,
        line: usize,
        reason: String,
    },
}

/// An open journal: rows are appended from any thread.
#[derive(Debug)]
pub struct Journal {
    path: PathBuf,
    file: Mutex<File>,
    /// Rows it holds (resumed and recorded).
    rows: AtomicUsize,
    /// Why the journal found at its name was replaced (another job's, not resumed).
    pub replaced: Option<String>,
}

/// `OUT.journal`: the journal beside the output `out`.
pub(crate) fn journal_path(out: &Path) -> PathBuf {
    let mut name = out.file_name().unwrap_or_default().to_os_string();
    name.push(".journal");
    out.with_file_name(name)
}

/// The first line of a journal of this job.
fn first_line(kind: &str, job: &JobId, shard: Shard, runs: usize) -> String {
    let mut s = format!("#deckspin-journal kind={kind} shard={shard} runs={runs}");
    for (name, value) in &job.fields {
        s += &format!(" {name}={value}");
    }
    s
}

/// The first field where two first lines differ: (name, found, expected).
fn first_difference(found: &str, expected: &str) -> (String, String, String) {
    let fields = |s: &str| -> Vec<(String, String)> {
        (s.split(' ').skip(1))
            .map(|f| match f.split_once('=') {
                Some((n, v)) => (n.to_string(), v.to_string()),
                None => (f.to_string(), String::new()),
            })
            .collect()
    };
    let (f, e) = (fields(found), fields(expected));
    for (name, value) in &e {
        let other = f.iter().find(|(n, _)| n == name).map(|(_, v)| v.clone());
        if other.as_ref() != Some(value) {
            let what = match name.as_str() {
                "model" => "the model text's fingerprint".to_string(),
                "records" => "the records' fingerprint".to_string(),
                "args" => "the arguments' fingerprint".to_string(),
                "version" => "deckspin's version".to_string(),
                n => n.to_string(),
            };
            return (
                what,
                other.unwrap_or_else(|| "absent".into()),
                value.clone(),
            );
        }
    }
    ("the first line".into(), found.into(), expected.into())
}

impl Journal {
    /// Opens the journal of the job writing `out` (`kind`, `job`, `shard` of `runs` runs, CSV
    /// `header` without its line break): a new one, or with `resume` the one an interrupted
    /// run of the same job left, returning its rows by run index. Without `resume`, a journal
    /// of this job that holds rows is refused ([`JournalError::Exists`]) and one of another
    /// job replaced ([`Journal::replaced`] says why); with it, a journal of another job is
    /// refused naming what differs.
    pub fn open(
        out: &Path,
        kind: &str,
        job: &JobId,
        shard: Shard,
        runs: usize,
        header: &str,
        resume: bool,
    ) -> Result<(Journal, BTreeMap<usize, String>), JournalError> {
        let path = journal_path(out);
        let io = |source| JournalError::Io {
            path: path.clone(),
            source,
        };
        let first = first_line(kind, job, shard, runs);
        let head = format!("{first}\nrun,{header}\n");
        let old = match std::fs::read(&path) {
            Ok(b) => Some(b),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
            Err(e) => return Err(io(e)),
        };
        let mut done = BTreeMap::new();
        let mut keep = head.len();
        let mut replaced = None;
        if let Some(bytes) = old {
            let text = String::from_utf8_lossy(&bytes);
            let range = shard.range(runs);
            match read_rows(&path, &text, &first, header, range) {
                // a journal of this job that holds rows is not thrown away unasked
                Ok((rows, _)) if !resume && !rows.is_empty() => {
                    return Err(JournalError::Exists {
                        path,
                        done: rows.len(),
                        runs: shard.range(runs).len(),
                    });
                }
                Ok((rows, complete)) => {
                    done = rows;
                    keep = complete;
                }
                Err(e) if resume => return Err(e),
                // another job's (or no journal): this job replaces it, as its output
                Err(JournalError::OtherJob { what, .. }) => {
                    replaced = Some(format!("{}: {what} differs", path.display()))
                }
                Err(e) => replaced = Some(e.to_string()),
            }
        }
        if done.is_empty() {
            crate::output::files::write_atomic(&path, &head).map_err(io)?;
        } else {
            // drop a last line cut by a kill before appending
            let f = File::options().write(true).open(&path).map_err(io)?;
            f.set_len(keep as u64).map_err(io)?;
        }
        let file = File::options().append(true).open(&path).map_err(io)?;
        Ok((
            Journal {
                path,
                file: Mutex::new(file),
                rows: AtomicUsize::new(done.len()),
                replaced,
            },
            done,
        ))
    }

    /// Appends run `index`'s CSV `line` (with its line break) in one write.
    pub fn record(&self, index: usize, line: &str) -> std::io::Result<()> {
        let text = format!("{index},{line}");
        let mut f = self.file.lock().unwrap_or_else(|p| p.into_inner());
        f.write_all(text.as_bytes())?;
        self.rows.fetch_add(1, Ordering::Relaxed);
        Ok(())
    }

    /// Rows the journal holds.
    pub fn rows(&self) -> usize {
        self.rows.load(Ordering::Relaxed)
    }

    /// The job stopped on an error: a journal that holds no row is removed (one that holds
    /// rows stays, for a resume).
    pub fn abandon(self) {
        if self.rows() == 0 {
            let _ = std::fs::remove_file(&self.path);
        }
    }

    /// The journal's file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The job is written: the journal is removed.
    pub fn finish(self) -> std::io::Result<()> {
        std::fs::remove_file(&self.path)
    }
}

/// The rows of a journal's `text` (first line `first`, CSV `header`) by run index, each in
/// `range`, and the length in bytes of its complete lines.
fn read_rows(
    path: &Path,
    text: &str,
    first: &str,
    header: &str,
    range: Range<usize>,
) -> Result<(BTreeMap<usize, String>, usize), JournalError> {
    let corrupt = |line: usize, reason: String| JournalError::Corrupt {
        path: path.to_path_buf(),
        line,
        reason,
    };
    let mut lines = text.split_inclusive('\n');
    let found = lines.next().unwrap_or("").trim_end_matches('\n');
    if !found.starts_with("#deckspin-journal ") {
        return Err(corrupt(1, "not a deckspin journal".into()));
    }
    if found != first {
        let (what, found, expected) = first_difference(found, first);
        return Err(JournalError::OtherJob {
            path: path.to_path_buf(),
            what,
            found,
            expected,
        });
    }
    let mut at = found.len() + 1;
    match lines.next() {
        Some(h) if h.trim_end_matches('\n') == format!("run,{header}") && h.ends_with('\n') => {
            at += h.len();
        }
        // cut inside its header: nothing was journaled
        Some(h) if !h.ends_with('\n') => return Ok((BTreeMap::new(), 0)),
        None => return Ok((BTreeMap::new(), 0)),
        Some(_) => return Err(corrupt(2, "the CSV header is not this job's".into())),
    }
    let mut rows = BTreeMap::new();
    for (j, line) in lines.enumerate() {
        if !line.ends_with('\n') {
            // the last line, cut by a kill: that run is run again
            break;
        }
        let (i, row) = line
            .split_once(',')
            .ok_or_else(|| corrupt(j + 3, "no run index".into()))?;
        let i: usize = i
            .parse()
            .map_err(|_| corrupt(j + 3, format!("run index '{i}' is not a whole number")))?;
        if !range.contains(&i) {
            let reason = format!("run {i} is not within runs {}..{}", range.start, range.end);
            return Err(corrupt(j + 3, reason));
        }
        rows.entry(i).or_insert_with(|| row.to_string());
        at += line.len();
    }
    Ok((rows, at))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d =
            std::env::temp_dir().join(format!("deckspin-journal-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn rows_survive_a_cut_last_line_and_another_job_is_refused() {
        let d = dir("cut");
        let out = d.join("o.csv");
        let job = JobId::new("model", "args");
        let open = |resume| Journal::open(&out, "sweep", &job, Shard::ALL, 5, "a,b", resume);
        let (j, done) = open(false).unwrap();
        assert!(done.is_empty());
        j.record(3, "x,y\n").unwrap();
        j.record(1, "p,q\n").unwrap();
        drop(j);
        // a kill inside the third row
        let p = journal_path(&out);
        let mut f = File::options().append(true).open(&p).unwrap();
        f.write_all(b"4,half").unwrap();
        drop(f);
        assert!(matches!(
            open(false),
            Err(JournalError::Exists {
                done: 2,
                runs: 5,
                ..
            })
        ));
        let (j, done) = open(true).unwrap();
        let want: BTreeMap<usize, String> =
            [(1, "p,q\n".to_string()), (3, "x,y\n".to_string())].into();
        assert_eq!(done, want);
        j.record(4, "r,s\n").unwrap();
        drop(j);
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(text.ends_with("3,x,y\n1,p,q\n4,r,s\n"), "{text:?}");
        // another model
        let other = JobId::new("model 2", "args");
        let e = Journal::open(&out, "sweep", &other, Shard::ALL, 5, "a,b", true).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("the model text's fingerprint"), "{msg}");
        let (j, _) = open(true).unwrap();
        j.finish().unwrap();
        assert!(!p.exists());
        let _ = std::fs::remove_dir_all(&d);
    }
}
