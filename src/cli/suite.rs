//! `deckspin suite`: a record suite (incremental dynamic analysis, library `suite`), or a
//! shard of it.

use super::jobs::{Recorder, counted, joined, stop_if_signalled};
use super::progress::Bar;
use clap::Args;
use deckspin::shard::journal::Journal;
use deckspin::shard::{Shard, csv_line, part_text};
use deckspin::studies::parse_axis;
use deckspin::suite::intensity::{parse_levels, parse_measure};
use deckspin::suite::records::suite_pairs;
use deckspin::suite::row::{Status, SuiteRow, csv_fields, csv_header, read_csv};
use deckspin::suite::stats::{level_stats, stats_csv, stats_json, stats_table};
use deckspin::suite::{CANCELLED, DEFAULT_TAIL, Suite, SuiteSpec};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A record suite: the bridge under every record pair scaled to each intensity level.
#[derive(Args)]
pub struct SuiteArgs {
    pub model: PathBuf,
    /// A folder of .AT2 records (paired by station: sorted names equal but for their last 3
    /// characters, the first longitudinal) or a list file (`longitudinal transverse [name]`
    /// per line, paths relative to it, # comments).
    #[arg(long)]
    pub records: PathBuf,
    /// Intensity measure: pga, sa:T (T in s) or sa:T1 (the model's first mode period).
    #[arg(long)]
    pub measure: String,
    /// Damping ratio of Sa (sa:… only; default 0.05).
    #[arg(long)]
    pub damping: Option<f64>,
    /// Intensity levels, g: a:b:step (inclusive) or v1,v2,…
    #[arg(long)]
    pub levels: String,
    /// Swept keys crossed with the levels: key=a:b:step or key=v1,v2 (repeatable).
    #[arg(long = "set", value_name = "KEY=RANGE")]
    pub set: Vec<String>,
    /// Fixed overrides applied to every run.
    #[arg(long = "fix", value_name = "KEY=VALUE")]
    pub fix: Vec<String>,
    /// Free vibration after the end of the longer record of each pair, s.
    #[arg(long, default_value_t = DEFAULT_TAIL)]
    pub tail: f64,
    /// CSV of every run; the statistics go beside it (STEM-stats.csv, STEM-stats.json).
    /// With --shard: the part file, for `deckspin merge`.
    #[arg(long, default_value = "out/suite.csv")]
    pub out: PathBuf,
    /// Run only shard K of N (contiguous blocks of runs), written with their run indices.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Finish a job that was stopped: the runs in its journal (OUT.journal, written as
    /// each run finishes) are not run again.
    #[arg(long)]
    pub resume: bool,
}

use super::CliResult;

/// The fingerprint of a suite's job: the model text, the records' names and contents in pair
/// order, the measure, levels, damping, tail and swept and fixed keys, deckspin's version.
fn suite_job(
    a: &SuiteArgs,
    pairs: &[deckspin::suite::records::SuitePair],
) -> Result<deckspin::shard::JobId, Box<dyn std::error::Error>> {
    let model_text = std::fs::read_to_string(&a.model)?;
    let args = format!(
        "measure={} damping={:?} levels={} tail={} set={:?} fix={:?}",
        a.measure, a.damping, a.levels, a.tail, a.set, a.fix
    );
    let mut records = Vec::new();
    for p in pairs {
        for f in [&p.longitudinal, &p.transverse] {
            let name = f.file_name().map(|n| n.to_string_lossy().into_owned());
            records.extend(name.unwrap_or_default().bytes());
            records.extend(std::fs::read(f)?);
        }
    }
    Ok(deckspin::shard::JobId::new(&model_text, &args).with("records", &records))
}

pub fn cmd_suite(a: &SuiteArgs) -> CliResult {
    let shard = a.shard.as_deref().map(Shard::parse).transpose()?;
    let shard = shard.unwrap_or(Shard::ALL);
    let measure = parse_measure(&a.measure, a.damping)?;
    let levels = parse_levels(&a.levels)?;
    let axes = (a.set.iter())
        .map(|s| parse_axis(s).map_err(|e| format!("--set {e}")))
        .collect::<Result<Vec<_>, _>>()?;
    let (pairs, single) = suite_pairs(&a.records)?;
    // one job writes this file at a time
    let _lock = deckspin::output::files::FolderLock::for_file(&a.out)?;
    for s in &single {
        eprintln!("deckspin: {}: no partner component, left out", s.display());
    }
    let pairs_for_job = pairs.clone();
    let spec = SuiteSpec {
        measure,
        levels,
        axes,
        tail: a.tail,
    };
    let suite = Suite::open(&a.model, &a.fix, pairs, spec)?;
    let total = suite.runs();
    let keys = suite.keys();
    let header = csv_line(&csv_header(&keys));
    let job = suite_job(a, &pairs_for_job)?;
    if let Some(dir) = a.out.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let (journal, mut done) = super::jobs::open_journal(
        &a.out,
        "suite",
        &job,
        shard,
        total,
        header.trim_end(),
        a.resume,
    )?;
    let result = finish(
        a,
        &suite,
        &journal,
        &mut done,
        (shard, total),
        (&keys, &header),
        &job,
    );
    match result {
        Ok(()) => Ok(journal.finish()?),
        Err(e) => {
            journal.abandon();
            Err(e)
        }
    }
}

/// The runs of the suite's shard not in the journal's rows `done`, then its outputs.
fn finish(
    a: &SuiteArgs,
    suite: &Suite,
    journal: &Journal,
    done: &mut BTreeMap<usize, String>,
    (shard, total): (Shard, usize),
    (keys, header): (&[String], &str),
    job: &deckspin::shard::JobId,
) -> CliResult {
    let range = shard.range(total);
    let resumed = done.len();
    let todo: Vec<usize> = range.clone().filter(|i| !done.contains_key(i)).collect();
    let t0 = std::time::Instant::now();
    let bar = Bar::new();
    let recorder = Recorder::new(journal);
    let fresh = std::sync::Mutex::new(Vec::new());
    let cancelled = Status::Refused(CANCELLED.into());
    suite.run_listed(&todo, &bar, &|i, row| {
        if row.status != cancelled {
            let line = csv_line(&csv_fields(row));
            recorder.record(i, &line);
            fresh
                .lock()
                .unwrap_or_else(|p| p.into_inner())
                .push((i, line));
        }
    });
    bar.clear();
    stop_if_signalled(journal, range.len())?;
    done.extend(fresh.into_inner().unwrap_or_else(|p| p.into_inner()));
    let wall = t0.elapsed().as_secs_f64();
    let text = joined(header, done);
    let (_, rows) = read_csv(&text)?;
    let wrote = if shard.is_all() {
        write_outputs(&a.out, &text, keys, &rows)?
    } else {
        let lines: Vec<(usize, String)> = done.iter().map(|(i, l)| (*i, l.clone())).collect();
        let text = part_text("suite", job, shard, total, header, &lines);
        deckspin::output::files::write_atomic(&a.out, text)?;
        format!(
            "{} (shard {shard}: runs {}..{} of {total}; join the parts with `deckspin merge`)",
            a.out.display(),
            range.start,
            range.end
        )
    };
    println!("{}", tally(&rows));
    eprintln!(
        "{} in {wall:.2} s wall on {} threads",
        counted(rows.len(), resumed),
        rayon::current_num_threads()
    );
    println!("wrote {wrote}");
    Ok(())
}

/// Runs, finished, failed, refused.
fn tally(rows: &[SuiteRow]) -> String {
    let count = |f: &dyn Fn(&Status) -> bool| rows.iter().filter(|r| f(&r.status)).count();
    format!(
        "{} runs: {} finished, {} failed, {} refused",
        rows.len(),
        count(&|s| *s == Status::Finished),
        count(&|s| matches!(s, Status::Failed { .. })),
        count(&|s| matches!(s, Status::Refused(_)))
    )
}

/// The statistics files beside the suite CSV `out`: STEM-stats.csv and STEM-stats.json.
pub fn stats_paths(out: &Path) -> (PathBuf, PathBuf) {
    let stem = out
        .file_stem()
        .map_or("suite".into(), |s| s.to_string_lossy().into_owned());
    (
        out.with_file_name(format!("{stem}-stats.csv")),
        out.with_file_name(format!("{stem}-stats.json")),
    )
}

/// The suite CSV `csv` (of `rows`) and its statistics (CSV, JSON); the statistics table
/// printed. Returns what was written.
pub fn write_outputs(
    out: &Path,
    csv: &str,
    keys: &[String],
    rows: &[SuiteRow],
) -> Result<String, std::io::Error> {
    deckspin::output::files::write_atomic(out, csv)?;
    let stats = level_stats(rows);
    let (stats_file, json) = stats_paths(out);
    deckspin::output::files::write_atomic(&stats_file, stats_csv(keys, &stats))?;
    deckspin::output::files::write_atomic(&json, stats_json(&stats))?;
    print!("{}", stats_table(&stats));
    let svg = out.with_extension("svg");
    super::show::chart(&deckspin::suite::chart::ida_chart(rows, &stats), &svg)?;
    Ok(format!(
        "{}, {}, {}, {}",
        out.display(),
        stats_file.display(),
        json.display(),
        svg.display()
    ))
}
