//! `deckspin stress`: the bridge under every record pair of a folder (`stress` module).

use super::jobs::{Recorder, joined, stop_if_signalled};
use clap::Args;
use deckspin::shard::Shard;
use deckspin::shard::journal::Journal;
use deckspin::stress::{CSV_HEADER, StressRow, csv_line, stress_listed, tally};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// The bridge under every record pair of a folder × runs × ε × μ × column law.
#[derive(Args)]
pub struct StressArgs {
    #[arg(default_value = "models/four-span.toml")]
    pub model: PathBuf,
    /// Folder of AT2 records, paired by station (two consecutive names equal but for the
    /// component's last 3 characters).
    #[arg(long, default_value = "excitations/far-field")]
    pub records: PathBuf,
    /// Runs of the model's [[run]] table (comma-separated) [default: every run of the table]
    #[arg(long, value_delimiter = ',')]
    pub runs: Vec<usize>,
    /// Restitution coefficients.
    #[arg(long, default_value = "0,0.5,1", value_delimiter = ',')]
    pub eps: Vec<f64>,
    /// Friction coefficients.
    #[arg(long, default_value = "0.1,0.5,1", value_delimiter = ',')]
    pub mu: Vec<f64>,
    /// Column laws: takeda, bilinear.
    #[arg(long, default_value = "takeda,bilinear", value_delimiter = ',')]
    pub laws: Vec<String>,
    /// CSV of every run.
    #[arg(long, default_value = "out/stress.csv")]
    pub out: PathBuf,
    /// Finish a job that was stopped: the runs in its journal (OUT.journal, written as each
    /// run finishes) are not run again.
    #[arg(long)]
    pub resume: bool,
}

pub fn cmd_stress(a: &StressArgs) -> Result<(), Box<dyn std::error::Error>> {
    use deckspin::stress::{StressGrid, record_pairs, stress_size};
    let (pairs, single) = record_pairs(&a.records)
        .map_err(|e| format!("{}: cannot read the records: {e}", a.records.display()))?;
    if pairs.is_empty() {
        return Err(format!("{}: no record pairs", a.records.display()).into());
    }
    for s in &single {
        eprintln!("deckspin: {}: no partner component, left out", s.display());
    }
    // one job writes this file at a time
    let _lock = deckspin::output::files::FolderLock::for_file(&a.out)?;
    if let Some(l) = a
        .laws
        .iter()
        .find(|l| !["takeda", "bilinear"].contains(&l.as_str()))
    {
        return Err(format!("--laws: unknown column law '{l}' (takeda, bilinear)").into());
    }
    let grid = StressGrid {
        runs: a.runs.clone(),
        restitution: a.eps.clone(),
        mu: a.mu.clone(),
        laws: a.laws.clone(),
        ..StressGrid::default()
    };
    let text = deckspin::input::read_bounded(&a.model, deckspin::input::MAX_MODEL_BYTES)
        .map_err(|e| format!("{}: {e}", a.model.display()))?;
    let total = stress_size(pairs.len(), deckspin::studies::run_count(&text), &grid);
    let mut records = Vec::new();
    for p in &pairs {
        for f in [&p.longitudinal, &p.transverse] {
            let name = f.file_name().map(|n| n.to_string_lossy().into_owned());
            records.extend(name.unwrap_or_default().bytes());
            records.extend(std::fs::read(f)?);
        }
    }
    let args = format!(
        "runs={:?} eps={:?} mu={:?} laws={:?}",
        a.runs, a.eps, a.mu, a.laws
    );
    let job = deckspin::shard::JobId::new(&text, &args).with("records", &records);
    if let Some(dir) = a.out.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let (journal, done) = super::jobs::open_journal(
        &a.out,
        "stress",
        &job,
        Shard::ALL,
        total,
        CSV_HEADER,
        a.resume,
    )?;
    match finish(a, (&pairs, total), &grid, &journal, done) {
        Ok(pass) => {
            journal.finish()?;
            if pass {
                Ok(())
            } else {
                Err("some runs did not pass".into())
            }
        }
        Err(e) => {
            journal.abandon();
            Err(e)
        }
    }
}

/// The runs not in the journal's rows `done`, then the CSV and the tally; true when every run
/// passes.
fn finish(
    a: &StressArgs,
    (pairs, total): (&[deckspin::stress::RecordPair], usize),
    grid: &deckspin::stress::StressGrid,
    journal: &Journal,
    mut done: BTreeMap<usize, String>,
) -> Result<bool, Box<dyn std::error::Error>> {
    let runs = pairs.len() * grid.restitution.len() * grid.mu.len() * grid.laws.len();
    eprintln!(
        "deckspin: stress: {total} runs ({} record pairs × {} model runs × {} ε × {} μ × {} laws){}",
        pairs.len(),
        total / runs.max(1),
        grid.restitution.len(),
        grid.mu.len(),
        grid.laws.len(),
        if done.is_empty() {
            String::new()
        } else {
            format!(", {} of them in the journal", done.len())
        }
    );
    let bar = super::progress::Bar::with_lines();
    let recorder = Recorder::new(journal);
    let ran = stress_listed(
        &a.model,
        pairs,
        grid,
        &|i| done.contains_key(&i),
        &bar,
        &|i, row| recorder.record(i, &csv_line(row)),
    )?;
    bar.clear();
    stop_if_signalled(journal, total)?;
    let mut rows = BTreeMap::new();
    for (i, line) in &done {
        let row = StressRow::from_csv(line)
            .map_err(|e| format!("{}: run {i}: {e}", journal.path().display()))?;
        rows.insert(*i, row);
    }
    for (i, row) in ran {
        done.insert(i, csv_line(&row));
        rows.insert(i, row);
    }
    let csv = joined(&format!("{CSV_HEADER}\n"), &done);
    deckspin::output::files::write_atomic(&a.out, csv)?;
    let rows: Vec<StressRow> = rows.into_values().collect();
    print!("{}", tally(&rows));
    println!("wrote {}", a.out.display());
    Ok(rows.iter().all(|r| r.passes()))
}
