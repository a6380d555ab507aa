//! Scale-out: a job of M runs cut into N shards of contiguous runs (shard K holds runs
//! ⌊(K−1)M/N⌋ … ⌊KM/N⌋ − 1, 0-based), each written as a part file that carries its run
//! indices, and the parts merged into the CSV the unsharded job writes, byte for byte.
//!
//! A part file: the line `#deckspin-part kind=KIND shard=K/N runs=M` followed by the job's
//! fingerprint (`NAME=VALUE` fields, [`JobId`]: the model text's hash, the records' contents',
//! the arguments', deckspin's version), then the job's CSV with a first column `run` (the run's
//! index in the unsharded job), then the line `#deckspin-end rows=R`. Rows are one line each
//! (fields hold no line breaks), so merging is sorting lines by index and dropping that column;
//! parts of another job are refused by the field that differs, and a part cut short (no end
//! line, or a row count that is not R) is refused.

pub mod journal;

use std::ops::Range;
use std::path::{Path, PathBuf};

/// Most shards a job is cut into.
pub(crate) const MAX_SHARDS: usize = 1_000_000;

/// Shard `k` (1-based) of `n`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub k: usize,
    pub n: usize,
}

/// A `--shard` argument that is not `K/N` with 1 ≤ K ≤ N ≤ [`MAX_SHARDS`].
#[derive(Debug, thiserror::Error)]
#[error("--shard '{argument}': {reason} (expected K/N with 1 ≤ K ≤ N ≤ {MAX_SHARDS}, e.g. 3/8)")]
pub struct ShardArgError {
    pub argument: String,
    pub reason: String,
}

impl Shard {
    /// The whole job as one shard.
    pub const ALL: Shard = Shard { k: 1, n: 1 };

    /// `K/N`.
    pub fn parse(argument: &str) -> Result<Self, ShardArgError> {
        let err = |reason: &str| ShardArgError {
            argument: argument.to_string(),
            reason: reason.to_string(),
        };
        let (k, n) = argument.split_once('/').ok_or_else(|| err("no '/'"))?;
        let num = |s: &str, what: &str| {
            s.trim()
                .parse::<usize>()
                .map_err(|_| err(&format!("{what} '{s}' is not a whole number")))
        };
        let (k, n) = (num(k, "K")?, num(n, "N")?);
        if n == 0 || n > MAX_SHARDS {
            return Err(err(&format!("N = {n} is out of range")));
        }
        if k == 0 || k > n {
            return Err(err(&format!("K = {k} is not within 1..={n}")));
        }
        Ok(Shard { k, n })
    }

    /// The indices of this shard's runs in a job of `runs`: ⌊(K−1)M/N⌋ .. ⌊KM/N⌋.
    pub fn range(&self, runs: usize) -> Range<usize> {
        let at = |k: usize| (k as u128 * runs as u128 / self.n as u128) as usize;
        at(self.k - 1)..at(self.k)
    }

    /// The whole job.
    pub fn is_all(&self) -> bool {
        self.n == 1
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

/// One CSV line (with its `\n`): fields quoted where they need it, line breaks inside a field
/// written as blanks.
pub fn csv_line<S: AsRef<str>>(fields: &[S]) -> String {
    let mut w = csv::WriterBuilder::new().from_writer(Vec::new());
    let clean = fields.iter().map(|f| f.as_ref().replace(['\n', '\r'], " "));
    // writing to memory cannot fail
    let _ = w.write_record(clean);
    let bytes = w.into_inner().unwrap_or_default();
    String::from_utf8(bytes).unwrap_or_default()
}

/// The fields of one CSV line ([`csv_line`]'s inverse).
pub(crate) fn csv_fields_of(line: &str) -> Result<Vec<String>, String> {
    let mut rd = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(line.as_bytes());
    let rec = (rd.records().next())
        .ok_or("an empty line")?
        .map_err(|e| e.to_string())?;
    Ok(rec.iter().map(String::from).collect())
}

/// What makes two parts parts of one job: named values without spaces, compared field by
/// field at the merge.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct JobId {
    pub fields: Vec<(String, String)>,
}

impl JobId {
    /// deckspin's version, the model text's hash and the arguments' (each an FNV-1a of its
    /// bytes, [`fingerprint`]).
    pub fn new(model_text: &str, arguments: &str) -> Self {
        Self {
            fields: vec![
                ("version".into(), env!("CARGO_PKG_VERSION").into()),
                ("model".into(), fingerprint(model_text.as_bytes())),
                ("args".into(), fingerprint(arguments.as_bytes())),
            ],
        }
    }

    /// One more field, its value a fingerprint of `bytes`.
    pub fn with(mut self, name: &str, bytes: &[u8]) -> Self {
        self.fields.push((name.into(), fingerprint(bytes)));
        self
    }
}

/// A 64-bit FNV-1a hash of `bytes` as 16 hex digits (stable across builds and platforms).
pub fn fingerprint(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// The text of a part file: shard `shard` of the job `job` of `kind` with `runs` runs;
/// `header` the job's CSV header line, `rows` (index, CSV line) of the shard's runs.
pub fn part_text(
    kind: &str,
    job: &JobId,
    shard: Shard,
    runs: usize,
    header: &str,
    rows: &[(usize, String)],
) -> String {
    let mut out = format!("#deckspin-part kind={kind} shard={shard} runs={runs}");
    for (name, value) in &job.fields {
        out += &format!(" {name}={value}");
    }
    out += &format!("\nrun,{header}");
    for (i, line) in rows {
        out += &format!("{i},{line}");
    }
    out += &format!("#deckspin-end rows={}\n", rows.len());
    out
}

/// Why parts could not be merged.
#[derive(Debug, thiserror::Error)]
pub enum MergeError {
    #[error("{path}: cannot read: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("no parts given")]
    NoParts,
    #[error(
        "{path}:1: not a part file (its first line must be `#deckspin-part kind=… shard=K/N runs=M`, as `--shard` writes it)"
    )]
    NotAPart { path: PathBuf },
    #[error("{path}: {what} is {found}, but {first} has {expected}: parts of different jobs")]
    Mismatch {
        path: PathBuf,
        what: &'static str,
        found: String,
        first: PathBuf,
        expected: String,
    },
    #[error("shard {shard} is given twice: {first} and {second}")]
    Duplicate {
        shard: Shard,
        first: PathBuf,
        second: PathBuf,
    },
    #[error("shards missing: {missing} of {n} (give every part of the job)")]
    Missing { missing: String, n: usize },
    #[error("{path}:{line}: {reason}")]
    Row {
        path: PathBuf,
        line: usize,
        reason: String,
    },
    #[error("{path}: shard {shard} must hold runs {from}..{to}, it holds {found} rows")]
    Incomplete {
        path: PathBuf,
        shard: Shard,
        from: usize,
        to: usize,
        found: usize,
    },
}

/// The parts joined: the job's kind and its CSV as the unsharded job writes it.
#[derive(Debug, PartialEq)]
pub struct Merged {
    pub kind: String,
    pub runs: usize,
    pub csv: String,
}

/// A part file read: its first line's fields and its lines after it.
struct Part<'a> {
    path: &'a Path,
    kind: String,
    shard: Shard,
    runs: usize,
    /// The job's fingerprint fields (all but kind, shard and runs).
    job: Vec<(&'a str, &'a str)>,
    header: &'a str,
    rows: Vec<&'a str>,
}

fn read_part<'a>(path: &'a Path, text: &'a str) -> Result<Part<'a>, MergeError> {
    let not = || MergeError::NotAPart {
        path: path.to_path_buf(),
    };
    let mut lines = text.split_inclusive('\n');
    let first = lines.next().ok_or_else(not)?.trim_end();
    let rest = first.strip_prefix("#deckspin-part ").ok_or_else(not)?;
    let field = |name: &str| {
        (rest.split(' '))
            .find_map(|f| f.strip_prefix(name)?.strip_prefix('='))
            .ok_or_else(not)
    };
    let shard = Shard::parse(field("shard")?).map_err(|_| not())?;
    let runs = field("runs")?.parse().map_err(|_| not())?;
    let job = (rest.split(' '))
        .filter_map(|f| f.split_once('='))
        .filter(|(n, _)| !["kind", "shard", "runs"].contains(n))
        .collect();
    let header = lines.next().and_then(|h| h.strip_prefix("run,"));
    let mut rows: Vec<&str> = lines.collect();
    // the end line: a part cut short (inside its last row or number) has none
    let last_line = rows.len() + 2;
    let cut = |reason: String| MergeError::Row {
        path: path.to_path_buf(),
        line: last_line,
        reason,
    };
    let end = rows
        .pop()
        .ok_or_else(|| cut("no rows and no end line".into()))?;
    let count = (end.strip_suffix('\n'))
        .and_then(|e| e.strip_prefix("#deckspin-end rows="))
        .and_then(|n| n.parse::<usize>().ok());
    match count {
        None => {
            return Err(cut(
                "the part ends without its `#deckspin-end` line: it was cut short".into(),
            ));
        }
        Some(n) if n != rows.len() => {
            return Err(cut(format!(
                "the part holds {} rows, its end line says {n}",
                rows.len()
            )));
        }
        Some(_) => {}
    }
    Ok(Part {
        path,
        kind: field("kind")?.to_string(),
        shard,
        runs,
        job,
        header: header.ok_or_else(not)?,
        rows,
    })
}

/// Joins part files (path, text) into the job's CSV: every shard of the job exactly once,
/// every run of each shard exactly once.
pub fn merge(parts: &[(PathBuf, String)]) -> Result<Merged, MergeError> {
    let parts: Vec<Part> = (parts.iter())
        .map(|(p, t)| read_part(p, t))
        .collect::<Result<_, _>>()?;
    let first = parts.first().ok_or(MergeError::NoParts)?;
    let mut by_shard: Vec<Option<&Part>> = vec![None; first.shard.n];
    for p in &parts {
        let mismatch = |what, found: String, expected: String| MergeError::Mismatch {
            path: p.path.to_path_buf(),
            what,
            found,
            first: first.path.to_path_buf(),
            expected,
        };
        if p.kind != first.kind {
            return Err(mismatch("the kind", p.kind.clone(), first.kind.clone()));
        }
        if p.shard.n != first.shard.n {
            let (a, b) = (p.shard.n.to_string(), first.shard.n.to_string());
            return Err(mismatch("the number of shards", a, b));
        }
        if p.runs != first.runs {
            let (a, b) = (p.runs.to_string(), first.runs.to_string());
            return Err(mismatch("the number of runs", a, b));
        }
        for (name, value) in &first.job {
            let found = p.job.iter().find(|(n, _)| n == name).map(|(_, v)| *v);
            if found != Some(*value) {
                let what: &'static str = match *name {
                    "model" => "the model text's fingerprint",
                    "records" => "the records' fingerprint",
                    "args" => "the arguments' fingerprint (measure, levels, --set, --fix, method)",
                    "version" => "deckspin's version",
                    _ => "a fingerprint field",
                };
                let found = found.unwrap_or("absent").to_string();
                return Err(mismatch(what, found, format!("{name}={value}")));
            }
        }
        if p.job.len() != first.job.len() {
            let (a, b) = (p.job.len().to_string(), first.job.len().to_string());
            return Err(mismatch("the number of fingerprint fields", a, b));
        }
        if p.header != first.header {
            let (a, b) = (p.header.trim_end().into(), first.header.trim_end().into());
            return Err(mismatch("the header", a, b));
        }
        let slot = &mut by_shard[p.shard.k - 1];
        if let Some(q) = slot {
            return Err(MergeError::Duplicate {
                shard: p.shard,
                first: q.path.to_path_buf(),
                second: p.path.to_path_buf(),
            });
        }
        *slot = Some(p);
    }
    let missing: Vec<String> = (by_shard.iter().enumerate())
        .filter(|(_, p)| p.is_none())
        .map(|(k, _)| (k + 1).to_string())
        .collect();
    if !missing.is_empty() {
        return Err(MergeError::Missing {
            missing: missing.join(", "),
            n: first.shard.n,
        });
    }
    let mut csv = first.header.to_string();
    for p in by_shard.into_iter().flatten() {
        csv += &shard_rows(p)?;
    }
    Ok(Merged {
        kind: first.kind.clone(),
        runs: first.runs,
        csv,
    })
}

/// The rows of one part in run order, without their index: exactly the runs of its shard.
fn shard_rows(p: &Part) -> Result<String, MergeError> {
    let range = p.shard.range(p.runs);
    let mut rows: Vec<Option<&str>> = vec![None; range.len()];
    for (j, line) in p.rows.iter().enumerate() {
        let bad = |reason: String| MergeError::Row {
            path: p.path.to_path_buf(),
            line: j + 3,
            reason,
        };
        let (i, rest) = line
            .split_once(',')
            .ok_or_else(|| bad("no run index".into()))?;
        let i: usize = i
            .parse()
            .map_err(|_| bad(format!("run index '{i}' is not a whole number")))?;
        if !range.contains(&i) {
            let (a, b, s) = (range.start, range.end, p.shard);
            return Err(bad(format!("run {i} is not in shard {s} (runs {a}..{b})")));
        }
        let slot = &mut rows[i - range.start];
        if slot.is_some() {
            return Err(bad(format!("run {i} is given twice")));
        }
        *slot = Some(rest);
    }
    if rows.iter().any(Option::is_none) {
        return Err(MergeError::Incomplete {
            path: p.path.to_path_buf(),
            shard: p.shard,
            from: range.start,
            to: range.end,
            found: p.rows.len(),
        });
    }
    Ok(rows.into_iter().flatten().collect())
}

/// Reads the part files and [`merge`]s them.
pub fn merge_files(paths: &[PathBuf]) -> Result<Merged, MergeError> {
    let parts = (paths.iter())
        .map(|p| {
            std::fs::read_to_string(p)
                .map(|t| (p.clone(), t))
                .map_err(|e| MergeError::Io {
                    path: p.clone(),
                    source: e,
                })
        })
        .collect::<Result<Vec<_>, _>>()?;
    merge(&parts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_cut_every_job_into_contiguous_disjoint_slices() {
        for runs in [0, 1, 2, 7, 285] {
            for n in [1, 2, 3, 8, 300] {
                let mut next = 0;
                for k in 1..=n {
                    let r = Shard { k, n }.range(runs);
                    assert_eq!(r.start, next, "{k}/{n} of {runs}");
                    next = r.end;
                    // sizes differ by at most one
                    assert!(r.len() == runs / n || r.len() == runs / n + 1);
                }
                assert_eq!(next, runs);
            }
        }
        assert_eq!(Shard { k: 2, n: 4 }.range(10), 2..5);
    }

    #[test]
    fn bad_shards_name_the_argument() {
        for (arg, what) in [
            ("3", "no '/'"),
            ("0/4", "K = 0"),
            ("5/4", "K = 5"),
            ("1/0", "N = 0"),
            ("a/4", "K 'a'"),
            ("1/-2", "N '-2'"),
        ] {
            let e = Shard::parse(arg).unwrap_err().to_string();
            assert!(e.starts_with(&format!("--shard '{arg}': ")), "{e}");
            assert!(e.contains(what), "{e}");
        }
        assert_eq!(Shard::parse(" 2/3").unwrap(), Shard { k: 2, n: 3 });
    }

    fn parts(n: usize, rows: &[&str]) -> Vec<(PathBuf, String)> {
        (1..=n)
            .map(|k| {
                let s = Shard { k, n };
                let mine: Vec<(usize, String)> = (s.range(rows.len()))
                    .rev()
                    .map(|i| (i, rows[i].to_string()))
                    .collect();
                let job = JobId::new("model", "args");
                let text = part_text("sweep", &job, s, rows.len(), "a,b\n", &mine);
                (PathBuf::from(format!("p{k}.csv")), text)
            })
            .collect()
    }

    #[test]
    fn parts_merge_into_the_whole_and_refuse_gaps_and_doubles() {
        let rows = ["1,x\n", "2,\"y,z\"\n", "3,w\n", "4,v\n", "5,u\n"];
        let whole: String = std::iter::once("a,b\n").chain(rows).collect();
        let p = parts(3, &rows);
        let mut shuffled = vec![p[2].clone(), p[0].clone(), p[1].clone()];
        assert_eq!(merge(&shuffled).unwrap().csv, whole);
        shuffled.push(p[0].clone());
        let e = merge(&shuffled).unwrap_err().to_string();
        assert_eq!(e, "shard 1/3 is given twice: p1.csv and p1.csv");
        let e = merge(&p[..2]).unwrap_err().to_string();
        assert_eq!(e, "shards missing: 3 of 3 (give every part of the job)");
        let mut cut = p.clone();
        cut[1].1 = (cut[1].1.replace("2,3,w\n", "")).replace("rows=2", "rows=1");
        let e = merge(&cut).unwrap_err().to_string();
        assert!(
            e.contains("shard 2/3 must hold runs 1..3, it holds 1 rows"),
            "{e}"
        );
        // a row gone without the end line's count: the part is refused as it is
        let mut short = p.clone();
        short[1].1 = short[1].1.replace("2,3,w\n", "");
        let e = merge(&short).unwrap_err().to_string();
        assert!(
            e.contains("the part holds 1 rows, its end line says 2"),
            "{e}"
        );
        // cut inside its last number: no end line
        let mut torn = p.clone();
        let at = torn[1].1.rfind("#deckspin-end").unwrap() - 2;
        torn[1].1.truncate(at);
        let e = merge(&torn).unwrap_err().to_string();
        assert!(e.contains("cut short"), "{e}");
        // a part of another job: its model's fingerprint differs
        let mut alien = p.clone();
        let other = fingerprint(b"model 2");
        alien[2].1 = alien[2].1.replacen(&fingerprint(b"model"), &other, 1);
        let e = merge(&alien).unwrap_err().to_string();
        assert!(
            e.contains("the model text's fingerprint is") && e.contains(&other),
            "{e}"
        );
        let other = parts(2, &rows);
        let e = merge(&[p[0].clone(), other[1].clone()]).unwrap_err();
        assert!(e.to_string().contains("the number of shards is 2"), "{e}");
        let e = merge(&[(PathBuf::from("x.csv"), "a,b\n".into())]).unwrap_err();
        assert!(e.to_string().starts_with("x.csv:1: not a part file"), "{e}");
    }

    #[test]
    fn csv_lines_quote_what_needs_it_and_keep_one_line() {
        assert_eq!(
            csv_line(&["a", "b,c", "d\"e", "f\ng"]),
            "a,\"b,c\",\"d\"\"e\",f g\n"
        );
        assert_eq!(csv_line(&["", "x"]), ",x\n");
    }
}
