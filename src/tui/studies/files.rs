//! The study CSVs on disk: written as `<study>-<n>.csv` (the first free n, never over an
//! earlier file, each a transaction) in the first folder that accepts them (the model's
//! output folder, [`crate::tui::runs::out_folder`]), listed newest first (the exports beside them left
//! out), read back.

use crate::output::files::write_new;
use crate::study_csv::{read_file, to_csv};
use crate::study_table::StudyTable;
use crate::tui::runs::out_folder::is_export;
use std::path::{Path, PathBuf};

/// Writes `table` into the first of `dirs` that accepts it (the folder created if need be).
pub fn write(dirs: &[PathBuf], table: &StudyTable) -> Result<PathBuf, String> {
    let text = to_csv(table);
    let key = table.kind().key();
    let mut last = String::from("no folder to write into");
    for d in dirs {
        match write_in(d, key, &text) {
            Ok(p) => return Ok(p),
            Err(e) => last = e,
        }
    }
    Err(last)
}

fn write_in(dir: &Path, key: &str, text: &str) -> Result<PathBuf, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for n in 1..100_000 {
        let p = dir.join(format!("{key}-{n}.csv"));
        if p.exists() {
            continue;
        }
        match write_new(&p, text) {
            Ok(()) => return Ok(p),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(format!("{}: {e}", p.display())),
        }
    }
    Err(format!("{}: no free name for {key}-N.csv", dir.display()))
}

/// The CSV files of the folders that exist, newest first (then by name).
pub fn list(dirs: &[PathBuf]) -> Result<Vec<PathBuf>, String> {
    let mut found: Vec<(std::time::SystemTime, PathBuf)> = Vec::new();
    for d in dirs.iter().filter(|d| d.is_dir()) {
        let entries = std::fs::read_dir(d).map_err(|e| format!("{}: {e}", d.display()))?;
        for e in entries.flatten() {
            let p = e.path();
            if p.extension().is_some_and(|x| x == "csv") && p.is_file() && !is_export(&p) {
                let t = (e.metadata().and_then(|m| m.modified())).unwrap_or(std::time::UNIX_EPOCH);
                if !found.iter().any(|(_, q)| *q == p) {
                    found.push((t, p));
                }
            }
        }
    }
    found.sort_by(|a, b| b.0.cmp(&a.0).then_with(|| a.1.cmp(&b.1)));
    Ok(found.into_iter().map(|(_, p)| p).collect())
}

/// Reads a study's CSV: the table, or the error naming the file and line.
pub fn load(path: &Path) -> Result<Box<StudyTable>, String> {
    read_file(path).map(Box::new).map_err(|e| e.to_string())
}
