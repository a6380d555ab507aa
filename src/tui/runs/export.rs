//! CSV export of the charted data in the window, of the whole run and of the event log, into
//! the model's output folder ([`crate::tui::runs::out_folder`]) under a new number each time.

use crate::output::files::write_new;
use crate::output::series::{Column, columns_csv};
use crate::tui::chart;
use crate::tui::runs::data::RunData;
use crate::tui::runs::out_folder::EXPORT_PREFIX;
use std::path::{Path, PathBuf};

/// CSV of what is charted (full resolution, in the time window) and of the event log (the
/// engine's `events.csv` columns); both in the layout of the engine's files
/// ([`crate::output::series`]).
pub fn export_csv(run: &RunData, window: (f64, f64), element: usize) -> (String, String) {
    let (t0, t1) = window;
    let rows = chart::window(&run.t, t0, t1);
    let mut cols: Vec<(String, &[f64])> = vec![("t".into(), &run.t)];
    if let Some(r) = run.rot {
        cols.push((run.dof_names[r].clone(), &run.q[r]));
    }
    for (i, n) in run.contact_names.iter().enumerate() {
        cols.push((format!("{n}.gap"), &run.gap[i]));
    }
    for &k in &run.xy {
        cols.push((run.dof_names[k].clone(), &run.q[k]));
    }
    if !run.element_names.is_empty() {
        let j = element % run.element_names.len();
        cols.push((
            format!("{}.deformation", run.element_names[j]),
            &run.el[j].0,
        ));
        cols.push((format!("{}.force", run.element_names[j]), &run.el[j].1));
    }
    let columns: Vec<Column> = (cols.iter())
        .map(|(name, v)| Column {
            name,
            values: v.get(rows.clone()).unwrap_or(&[]),
            single: false,
        })
        .collect();
    let chart = columns_csv(&columns);
    let ev = crate::output::events_csv(&run.events, &run.contact_names, &run.element_names);
    (chart, ev)
}

/// A run's series by the names of `history.csv`: `t`, every DOF, every contact's gap, every
/// element's deformation and force, in the model's order.
pub fn series_columns(run: &RunData) -> Vec<(String, &[f64])> {
    let mut cols: Vec<(String, &[f64])> = vec![("t".into(), &run.t)];
    for (k, n) in run.dof_names.iter().enumerate() {
        cols.push((n.clone(), &run.q[k]));
    }
    for (i, n) in run.contact_names.iter().enumerate() {
        cols.push((format!("{n}.gap"), &run.gap[i]));
    }
    for (j, n) in run.element_names.iter().enumerate() {
        cols.push((format!("{n}.deformation"), &run.el[j].0));
        cols.push((format!("{n}.force"), &run.el[j].1));
    }
    cols
}

/// CSV of the whole run: every sample (not only the window), [`series_columns`]; the time
/// exactly, the rest exactly or (`single`) in single precision.
pub fn series_csv(run: &RunData, single: bool) -> String {
    let cols = series_columns(run);
    let columns: Vec<Column> = (cols.iter().enumerate())
        .map(|(j, (name, values))| Column {
            name,
            values,
            single: single && j > 0,
        })
        .collect();
    columns_csv(&columns)
}

/// The export files of an [`crate::tui::msg::Effect::Export`]: (kind, content) — `chart` the
/// charted columns in the window, `history` the whole run, `events` the event log; written as
/// `export-<n>-<kind>.csv`.
pub fn export_files(run: &RunData, window: (f64, f64), element: usize) -> Vec<(String, String)> {
    let (chart, events) = export_csv(run, window, element);
    vec![
        ("chart".into(), chart),
        ("history".into(), series_csv(run, false)),
        ("events".into(), events),
    ]
}

/// Writes export files `export-<n>-<kind>.csv` into the first directory of `dirs` that
/// accepts them (created if need be), `n` the first number none of them has: an earlier export
/// is never overwritten. Each file is a transaction ([`write_new`]).
pub fn write_exports(dirs: &[PathBuf], files: &[(String, String)]) -> Result<Vec<PathBuf>, String> {
    let mut last = String::from("no directory");
    for d in dirs {
        match write_in(d, files) {
            Ok(p) => return Ok(p),
            Err(e) => last = e,
        }
    }
    Err(last)
}

fn write_in(d: &Path, files: &[(String, String)]) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(d).map_err(|e| format!("{}: {e}", d.display()))?;
    'numbers: for n in 1..100_000 {
        let paths: Vec<PathBuf> = (files.iter())
            .map(|(kind, _)| d.join(format!("{EXPORT_PREFIX}{n}-{kind}.csv")))
            .collect();
        if paths.iter().any(|p| std::fs::symlink_metadata(p).is_ok()) {
            continue;
        }
        for (k, (p, (_, content))) in paths.iter().zip(files).enumerate() {
            match write_new(p, content) {
                Ok(()) => {}
                // taken in the meantime: the next number
                Err(e) if k == 0 && e.kind() == std::io::ErrorKind::AlreadyExists => {
                    continue 'numbers;
                }
                Err(e) => return Err(format!("{}: {e}", p.display())),
            }
        }
        return Ok(paths);
    }
    Err(format!("{}: no free export number", d.display()))
}
