//! CSV export of the charted data and the event log.

use super::chart;
use super::run_data::RunData;
use crate::output::number::Numbers;
use std::path::PathBuf;

/// CSV of what is charted (full resolution, in the time window) and of the event log (the
/// engine's `events.csv` columns).
pub fn export_csv(run: &RunData, window: (f64, f64), element: usize) -> (String, String) {
    let (t0, t1) = window;
    let mut cols: Vec<(String, &Vec<f64>)> = Vec::new();
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
    let mut chart = String::from("t");
    for (n, _) in &cols {
        chart.push(',');
        chart.push_str(n);
    }
    chart.push('\n');
    let mut n = Numbers::new();
    for i in chart::window(&run.t, t0, t1) {
        n.push(&mut chart, run.t[i]);
        for (_, c) in &cols {
            chart.push(',');
            n.push(&mut chart, c[i]);
        }
        chart.push('\n');
    }
    let ev = crate::output::events_csv(&run.events, &run.contact_names, &run.element_names);
    (chart, ev)
}

/// The export files of an [`super::msg::Effect::Export`]: (file name, content).
pub fn export_files(
    stem: &str,
    run: &RunData,
    window: (f64, f64),
    element: usize,
) -> Vec<(String, String)> {
    let (chart, events) = export_csv(run, window, element);
    vec![
        (format!("{stem}-chart.csv"), chart),
        (format!("{stem}-events.csv"), events),
    ]
}

/// Writes export files into the first directory that accepts all of them.
pub fn write_exports(dirs: &[PathBuf], files: &[(String, String)]) -> Result<Vec<PathBuf>, String> {
    let mut last = String::from("no directory");
    for d in dirs {
        let mut written = Vec::new();
        let mut ok = true;
        for (name, content) in files {
            let p = d.join(name);
            if let Err(e) = std::fs::write(&p, content) {
                last = format!("{}: {e}", p.display());
                ok = false;
                break;
            }
            written.push(p);
        }
        if ok {
            return Ok(written);
        }
    }
    Err(last)
}
