//! `deckspin stress`: the bridge under every record pair of a folder (`stress` module).

use clap::Args;
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
}

pub fn cmd_stress(a: &StressArgs) -> Result<(), Box<dyn std::error::Error>> {
    use deckspin::stress::{StressGrid, record_pairs, stress_watched, tally};
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
    let bar = super::progress::Bar::new();
    let rows = stress_watched(&a.model, &pairs, &grid, &bar)?;
    bar.clear();
    if let Some(dir) = a.out.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let mut csv = String::from(
        "record,run,restitution,mu,law,t_end,status,max_penetration,closure_rel,rtol,approaching_after_impact,pull_rel,wall_s\n",
    );
    for r in &rows {
        csv += &format!(
            "{},{},{},{},{},{},\"{}\",{:e},{:e},{:e},{},{:e},{:.4}\n",
            r.record,
            r.run,
            r.restitution,
            r.mu,
            r.law,
            r.t_end,
            r.status.replace('"', "'"),
            r.max_penetration,
            r.closure_rel,
            r.rtol,
            r.approaching,
            r.pull_rel,
            r.wall
        );
    }
    deckspin::output::files::write_atomic(&a.out, csv)?;
    print!("{}", tally(&rows));
    println!("wrote {}", a.out.display());
    if rows.iter().all(|r| r.passes()) {
        Ok(())
    } else {
        Err("some runs did not pass".into())
    }
}
