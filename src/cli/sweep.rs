//! `deckspin sweep`: every combination of swept scalars (`studies::Study::sweep_rows`), or a
//! shard of them.

use super::jobs::{Recorder, counted, joined, stop_if_signalled};
use super::progress::Bar;
use clap::Args;
use deckspin::shard::journal::Journal;
use deckspin::shard::{Shard, csv_line, part_text};
use deckspin::studies::{
    MAX_SWEEP_RUNS, Row, Study, axis_keys, csv_fields, csv_header, parse_axis, row_from_csv,
    sweep_size, table,
};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// Run a model over every combination of swept scalars, in parallel (at most 100 000).
#[derive(Args)]
pub struct SweepArgs {
    pub model: PathBuf,
    /// key=a:b:step or key=v1,v2,... (repeatable: the cartesian product is run).
    #[arg(long = "set", value_name = "KEY=RANGE", required = true)]
    pub set: Vec<String>,
    /// Fixed overrides applied to every run.
    #[arg(long = "fix", value_name = "KEY=VALUE")]
    pub fix: Vec<String>,
    /// CSV output (with --shard: the part file, for `deckspin merge`).
    #[arg(long, default_value = "out/sweep.csv")]
    pub out: PathBuf,
    /// Run only shard K of N (contiguous blocks of rows), written with their row indices.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Finish a job that was stopped: the rows in its journal (OUT.journal, written as each
    /// row is final) are not run again.
    #[arg(long)]
    pub resume: bool,
}

pub fn cmd_sweep(a: &SweepArgs) -> Result<(), Box<dyn std::error::Error>> {
    let shard = a.shard.as_deref().map(Shard::parse).transpose()?;
    let shard = shard.unwrap_or(Shard::ALL);
    let axes = (a.set.iter())
        .map(|s| parse_axis(s))
        .collect::<Result<Vec<_>, _>>()?;
    let total = sweep_size(&axes, MAX_SWEEP_RUNS)?;
    // one job writes this file at a time
    let _lock = deckspin::output::files::FolderLock::for_file(&a.out)?;
    let study = Study::open(&a.model, &a.fix)?;
    let keys = axis_keys(&axes);
    let header = csv_line(&csv_header(&keys));
    let model_text = deckspin::input::read_bounded(&a.model, deckspin::input::MAX_MODEL_BYTES)?;
    let args = format!("set={:?} fix={:?}", a.set, a.fix);
    let job = deckspin::shard::JobId::new(&model_text, &args);
    if let Some(dir) = a.out.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let (journal, mut done) = super::jobs::open_journal(
        &a.out,
        "sweep",
        &job,
        shard,
        total,
        header.trim_end(),
        a.resume,
    )?;
    let sweep = Sweep {
        a,
        study: &study,
        axes: &axes,
        keys: &keys,
        header: &header,
        job: &job,
        shard,
        total,
    };
    match sweep.finish(&journal, &mut done) {
        Ok(failed) => {
            journal.finish()?;
            if failed {
                return Err("some runs failed (see the table)".into());
            }
            Ok(())
        }
        Err(e) => {
            journal.abandon();
            Err(e)
        }
    }
}

/// A sweep's job, its journal opened.
struct Sweep<'a> {
    a: &'a SweepArgs,
    study: &'a Study,
    axes: &'a [deckspin::studies::Axis],
    keys: &'a [String],
    header: &'a str,
    job: &'a deckspin::shard::JobId,
    shard: Shard,
    total: usize,
}

/// Passes the counts and the cancel on to the bar, each final row to the journal.
struct Journaled<'a> {
    bar: &'a Bar,
    recorder: &'a Recorder<'a>,
    /// The sweep's row index of each position of the list run.
    todo: &'a [usize],
}

impl deckspin::progress::Progress for Journaled<'_> {
    fn plan(&self, runs: usize) {
        self.bar.plan(runs)
    }
    fn done(&self, runs: usize) {
        self.bar.done(runs)
    }
    fn go_on(&self) -> bool {
        self.bar.go_on()
    }
}

impl deckspin::studies::Watch for Journaled<'_> {
    fn row(&self, index: usize, row: &deckspin::studies::Row) {
        if let Some(&i) = self.todo.get(index) {
            self.recorder.record(i, &csv_line(&csv_fields(row)));
        }
    }
}

impl Sweep<'_> {
    /// The rows of the shard not in the journal's rows `done`, then the output; true when a
    /// row failed.
    fn finish(
        &self,
        journal: &Journal,
        done: &mut BTreeMap<usize, String>,
    ) -> Result<bool, Box<dyn std::error::Error>> {
        let (a, shard, total) = (self.a, self.shard, self.total);
        let range = shard.range(total);
        let resumed = done.len();
        let todo: Vec<usize> = range.clone().filter(|i| !done.contains_key(i)).collect();
        let t0 = std::time::Instant::now();
        let bar = Bar::new();
        let recorder = Recorder::new(journal);
        let watch = Journaled {
            bar: &bar,
            recorder: &recorder,
            todo: &todo,
        };
        let ran = self.study.sweep_listed(self.axes, &todo, &watch).rows;
        bar.clear();
        stop_if_signalled(journal, range.len())?;
        let wall = t0.elapsed().as_secs_f64();
        let mut rows: BTreeMap<usize, Row> = BTreeMap::new();
        for (i, line) in done.iter() {
            let row = row_from_csv(self.keys, line)
                .map_err(|e| format!("{}: run {i}: {e}", journal.path().display()))?;
            rows.insert(*i, row);
        }
        for (&i, r) in todo.iter().zip(ran) {
            done.insert(i, csv_line(&csv_fields(&r)));
            rows.insert(i, r);
        }
        let rows: Vec<Row> = rows.into_values().collect();
        print!("{}", table(&rows));
        let text = if shard.is_all() {
            joined(self.header, done)
        } else {
            let lines: Vec<(usize, String)> = done.iter().map(|(i, l)| (*i, l.clone())).collect();
            part_text("sweep", self.job, shard, total, self.header, &lines)
        };
        deckspin::output::files::write_atomic(&a.out, text)?;
        let what = if shard.is_all() {
            String::new()
        } else {
            format!(
                " (shard {shard}: rows {}..{} of {total}; join the parts with `deckspin merge`)",
                range.start, range.end
            )
        };
        println!(
            "{} in {:.3} s on {} threads; wrote {}{what}",
            counted(rows.len(), resumed),
            wall,
            rayon::current_num_threads(),
            a.out.display()
        );
        Ok(rows.iter().any(|r| r.error.is_some()))
    }
}
