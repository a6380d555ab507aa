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
    // the charted columns, picked from the run's series by their place in it: t, the dofs,
    // the gaps, then (deformation, force) per element
    let all = series_columns(run);
    let (nd, ng) = (run.dof_names.len(), run.contact_names.len());
    let mut pick = vec![0];
    pick.extend(run.rot.map(|r| 1 + r));
    pick.extend((0..ng).map(|i| 1 + nd + i));
    pick.extend(run.xy.iter().map(|&k| 1 + k));
    if !run.element_names.is_empty() {
        let j = element % run.element_names.len();
        pick.extend([1 + nd + ng + 2 * j, 2 + nd + ng + 2 * j]);
    }
    let columns: Vec<Column> = (pick.iter().filter_map(|&p| all.get(p)))
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_chart_export_is_the_charted_columns_of_the_runs_series() {
        let dofs = ["deck.x", "deck.y", "deck.theta", "abut.x"]
            .map(String::from)
            .to_vec();
        let mut r = RunData::new(
            1,
            "#1".into(),
            dofs,
            vec!["lt".into(), "rb".into()],
            vec!["c1.x".into(), "c2.y".into()],
            1.0,
        );
        r.t = vec![0.0, 0.5, 1.0];
        for (k, q) in r.q.iter_mut().enumerate() {
            *q = vec![k as f64, 10.0 + k as f64, 20.0 + k as f64];
        }
        for (i, g) in r.gap.iter_mut().enumerate() {
            *g = vec![0.1 * i as f64; 3];
        }
        for (j, e) in r.el.iter_mut().enumerate() {
            *e = (vec![j as f64; 3], vec![-(j as f64); 3]);
        }
        // the second element selected; the window holds the last two samples
        let (chart, _) = export_csv(&r, (0.5, 1.0), 1);
        let mut lines = chart.lines();
        assert_eq!(
            lines.next().unwrap(),
            "t,deck.theta,lt.gap,rb.gap,deck.x,deck.y,c2.y.deformation,c2.y.force"
        );
        assert_eq!(lines.next().unwrap(), "0.5,12.0,0.0,0.1,10.0,11.0,1.0,-1.0");
        assert_eq!(lines.count(), 1);
        // every name is one of the whole series' names
        let all: Vec<String> = series_columns(&r).into_iter().map(|(n, _)| n).collect();
        assert!(
            chart
                .lines()
                .next()
                .unwrap()
                .split(',')
                .all(|n| all.iter().any(|a| a == n))
        );
    }
}
