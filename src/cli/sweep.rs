//! `deckspin sweep`: every combination of swept scalars (`studies::Study::sweep_rows`), or a
//! shard of them.

use super::progress::Bar;
use clap::Args;
use deckspin::shard::{Shard, csv_line, part_text};
use deckspin::studies::{
    MAX_SWEEP_RUNS, Study, axis_keys, csv_fields, csv_header, csv_text, parse_axis, sweep_size,
    table,
};
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
    let range = shard.range(total);
    let t0 = std::time::Instant::now();
    let bar = Bar::new();
    let rows = study.sweep_rows(&axes, range.clone(), &bar).rows;
    bar.clear();
    let wall = t0.elapsed().as_secs_f64();
    print!("{}", table(&rows));
    if let Some(dir) = a.out.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let keys = axis_keys(&axes);
    let text = if shard.is_all() {
        csv_text(&keys, &rows)
    } else {
        let lines: Vec<(usize, String)> = (range.clone().zip(&rows))
            .map(|(i, r)| (i, csv_line(&csv_fields(r))))
            .collect();
        let model_text = std::fs::read_to_string(&a.model)?;
        let args = format!("set={:?} fix={:?}", a.set, a.fix);
        let job = deckspin::shard::JobId::new(&model_text, &args);
        let header = csv_line(&csv_header(&keys));
        part_text("sweep", &job, shard, total, &header, &lines)
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
        "{} runs in {:.3} s on {} threads; wrote {}{what}",
        rows.len(),
        wall,
        rayon::current_num_threads(),
        a.out.display()
    );
    if rows.iter().any(|r| r.error.is_some()) {
        return Err("some runs failed (see the table)".into());
    }
    Ok(())
}
