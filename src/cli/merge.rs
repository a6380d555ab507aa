//! `deckspin merge`: the part files of a sharded `suite`, `sweep` or `sensitivity` joined into
//! the output of the unsharded job (library `shard`).

use clap::Args;
use std::path::PathBuf;

/// Join the part files of a sharded job.
#[derive(Args)]
pub struct MergeArgs {
    /// The merged CSV (a suite's statistics go beside it, as `suite` writes them); for a
    /// `sensitivity`, its output folder.
    pub out: PathBuf,
    /// Every part file of the job (`--shard K/N` outputs), in any order.
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
}

pub fn cmd_merge(a: &MergeArgs) -> Result<(), Box<dyn std::error::Error>> {
    use deckspin::output::files::FolderLock;
    let merged = deckspin::shard::merge_files(&a.parts)?;
    // one job writes this file (a sensitivity's: this folder) at a time
    let _lock = if merged.kind == "sensitivity" {
        std::fs::create_dir_all(&a.out)?;
        FolderLock::acquire(&a.out)?
    } else {
        FolderLock::for_file(&a.out)?
    };
    if let Some(dir) = a.out.parent() {
        std::fs::create_dir_all(dir)?;
    }
    let wrote = match merged.kind.as_str() {
        "suite" => {
            let (keys, rows) = deckspin::suite::row::read_csv(&merged.csv)?;
            super::suite::write_outputs(&a.out, &merged.csv, &keys, &rows)?
        }
        "sensitivity" => {
            super::sensitivity::write_outputs(&a.out, &merged.csv)?;
            let runs = super::sensitivity::RUNS_FILE;
            format!(
                "{}/{{sensitivity.csv,{runs},tornado*.svg}}",
                a.out.display()
            )
        }
        _ => {
            deckspin::output::files::write_atomic(&a.out, &merged.csv)?;
            a.out.display().to_string()
        }
    };
    println!(
        "merged {} parts of a {} of {} runs; wrote {wrote}",
        a.parts.len(),
        merged.kind,
        merged.runs
    );
    Ok(())
}
