//! Jobs of many runs, in parallel inside the library (rayon), on a thread of their own while the
//! calling thread watches for Ctrl-C and calls the progress callback: sweeps, suites; and the
//! modes of a model.

use crate::NativeModel;
use crate::columns::{Column, columns_to_py};
use crate::errors::{error, model_error, suite_error};
use deckspin::progress::Progress;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyList;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Duration;

/// The exception a job's watcher caught (Ctrl-C's KeyboardInterrupt, or the callback's), to
/// be raised by the Python wrapper with the partial result attached.
pub(crate) type Raised = Option<Py<PyAny>>;

/// Counts of a job's runs for the poller, and its cancel.
#[derive(Default)]
struct Counts {
    planned: AtomicUsize,
    done: AtomicUsize,
    cancel: AtomicBool,
}

impl Progress for Counts {
    fn plan(&self, runs: usize) {
        self.planned.fetch_add(runs, Ordering::Relaxed);
    }
    fn done(&self, runs: usize) {
        self.done.fetch_add(runs, Ordering::Relaxed);
    }
    fn go_on(&self) -> bool {
        !self.cancel.load(Ordering::Relaxed)
    }
}

impl deckspin::studies::Watch for Counts {}

/// Runs `job` on a thread of its own, the GIL released; the calling thread wakes every
/// `interval` seconds to look for Ctrl-C and to call `progress(done, planned)`. A signal or
/// an exception of the callback (or its False) cancels the runs not started; those running
/// finish. Returns the job's result and the exception to raise, if any.
fn poll<T: Send>(
    py: Python<'_>,
    progress: Option<Py<PyAny>>,
    interval: f64,
    job: impl FnOnce(&Counts) -> T + Send,
) -> PyResult<(T, Raised)> {
    let counts = Counts::default();
    let interval = Duration::from_secs_f64(interval.clamp(0.01, 60.0));
    let mut raised: Option<PyErr> = None;
    let out = py.detach(|| {
        std::thread::scope(|s| {
            let (tx, rx) = std::sync::mpsc::channel();
            let counts = &counts;
            let worker = s.spawn(move || {
                let out = job(counts);
                let _ = tx.send(());
                out
            });
            // wakes when the job ends (or its thread stops) or every interval
            while let Err(std::sync::mpsc::RecvTimeoutError::Timeout) = rx.recv_timeout(interval) {
                if counts.cancel.load(Ordering::Relaxed) {
                    continue;
                }
                Python::attach(|py| {
                    let go = match py.check_signals() {
                        Err(e) => Err(e),
                        Ok(()) => match &progress {
                            None => Ok(true),
                            Some(cb) => {
                                let planned = counts.planned.load(Ordering::Relaxed);
                                let done = counts.done.load(Ordering::Relaxed);
                                (cb.call1(py, (done, planned)))
                                    .map(|v| !matches!(v.extract::<bool>(py), Ok(false)))
                            }
                        },
                    };
                    match go {
                        Ok(true) => {}
                        Ok(false) => counts.cancel.store(true, Ordering::Relaxed),
                        Err(e) => {
                            raised = Some(e);
                            counts.cancel.store(true, Ordering::Relaxed);
                        }
                    }
                });
            }
            // joined here, so that a panic of the job is a value, not a panic of the scope
            worker.join().ok()
        })
    });
    let raised = raised.map(|e| e.into_value(py).into_any());
    match out {
        Some(out) => Ok((out, raised)),
        None => Err(PyRuntimeError::new_err(
            "internal error: a job's thread stopped without a result",
        )),
    }
}

/// `deckspin sweep`: every combination of `axes` (`key=a:b:step` or `key=v1,v2,…`) on the
/// model, in parallel: (columns, runs of the integrator, exception to raise or None).
#[pyfunction]
#[pyo3(signature = (model, axes, progress, interval))]
pub(crate) fn sweep<'py>(
    py: Python<'py>,
    model: &NativeModel,
    axes: Vec<String>,
    progress: Option<Py<PyAny>>,
    interval: f64,
) -> PyResult<(Bound<'py, PyList>, usize, Raised)> {
    use deckspin::studies::{MAX_SWEEP_RUNS, Study, parse_axis, sweep_size};
    let axes = (axes.iter())
        .map(|s| parse_axis(s))
        .collect::<Result<Vec<_>, _>>()
        .map_err(PyValueError::new_err)?;
    sweep_size(&axes, MAX_SWEEP_RUNS).map_err(|e| error(py, "LimitError", e.to_string()))?;
    let study = py
        .detach(|| Study::from_text(&model.text, &model.path, &model.set))
        .map_err(|e| model_error(py, &e, &model.path))?;
    let (outcome, raised) = poll(py, progress, interval, |counts| {
        study.sweep_watched(&axes, counts)
    })?;
    let rows = &outcome.rows;
    let mut cols: Vec<(String, Column)> = Vec::new();
    for (k, a) in axes.iter().enumerate() {
        let values = rows.iter().map(|r| r.settings[k].1.clone()).collect();
        cols.push((a.key.clone(), Column::Str(values)));
    }
    type Field = fn(&deckspin::studies::Row) -> f64;
    let fields: [(&str, Field); 6] = [
        ("peak_rotation", |r| r.peak_rotation),
        ("residual_rotation", |r| r.residual_rotation),
        ("peak_x", |r| r.peak_x),
        ("peak_y", |r| r.peak_y),
        ("stick_time", |r| r.stick_time),
        ("energy_closure_rel", |r| r.energy_closure_rel),
    ];
    for (name, g) in &fields[..4] {
        cols.push((name.to_string(), Column::F64(rows.iter().map(g).collect())));
    }
    cols.push((
        "impacts".into(),
        Column::I64(rows.iter().map(|r| r.impacts as i64).collect()),
    ));
    for (name, g) in &fields[4..] {
        cols.push((name.to_string(), Column::F64(rows.iter().map(g).collect())));
    }
    cols.push((
        "wall_time".into(),
        Column::F64(rows.iter().map(|r| r.wall_time).collect()),
    ));
    cols.push((
        "error".into(),
        Column::Str(
            (rows.iter())
                .map(|r| r.error.as_ref().map_or(String::new(), |e| e.to_string()))
                .collect(),
        ),
    ));
    Ok((columns_to_py(py, cols)?, outcome.integrations, raised))
}

/// `deckspin suite`: the bridge under every record pair of `records` scaled to each level of
/// `measure`, × `axes`, in parallel: (the runs' CSV, the statistics' CSV, the paired records'
/// files left out, exception to raise or None).
#[pyfunction]
#[pyo3(signature = (model, records, measure, levels, damping, axes, tail, progress, interval))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn suite(
    py: Python<'_>,
    model: &NativeModel,
    records: PathBuf,
    measure: String,
    levels: String,
    damping: Option<f64>,
    axes: Vec<String>,
    tail: f64,
    progress: Option<Py<PyAny>>,
    interval: f64,
) -> PyResult<(String, String, Vec<String>, Raised)> {
    use deckspin::suite::intensity::{parse_levels, parse_measure};
    use deckspin::suite::{Suite, SuiteSpec};
    let bad = |e: String| PyValueError::new_err(e);
    let measure = parse_measure(&measure, damping).map_err(|e| bad(e.to_string()))?;
    let levels = parse_levels(&levels).map_err(|e| bad(e.to_string()))?;
    let axes = (axes.iter())
        .map(|s| deckspin::studies::parse_axis(s).map_err(|e| format!("set {e}")))
        .collect::<Result<Vec<_>, _>>()
        .map_err(bad)?;
    let (pairs, single) = deckspin::suite::records::suite_pairs(&records)
        .map_err(|e| error(py, "DeckspinError", e.to_string()))?;
    let spec = SuiteSpec {
        measure,
        levels,
        axes,
        tail,
    };
    deckspin::suite::check_arguments(&model.set, &pairs, &spec)
        .map_err(|e| suite_error(py, e, &model.path))?;
    let suite = py
        .detach(|| Suite::from_text(&model.text, &model.path, &model.set, pairs, spec))
        .map_err(|e| suite_error(py, e, &model.path))?;
    let (rows, raised) = poll(py, progress, interval, |counts| {
        suite.run(0..usize::MAX, counts)
    })?;
    let keys = suite.keys();
    let csv = deckspin::suite::row::csv_text(&keys, &rows);
    let stats = deckspin::suite::stats::level_stats(&rows);
    let stats = deckspin::suite::stats::stats_csv(&keys, &stats);
    let single = single.iter().map(|p| p.to_string_lossy().into_owned());
    Ok((csv, stats, single.collect(), raised))
}

/// `deckspin modes`: the periods, frequencies and shapes (each scaled to its largest
/// component, as the CLI's table) of the model's initial system.
#[pyfunction]
pub(crate) fn modes<'py>(py: Python<'py>, model: &NativeModel) -> PyResult<Bound<'py, PyList>> {
    let scene = &model.scene;
    let modes = py.detach(|| deckspin::modal::modes(scene));
    let mut cols = vec![
        (
            "mode".to_string(),
            Column::I64((1..=modes.len() as i64).collect()),
        ),
        (
            "period".to_string(),
            Column::F64(modes.iter().map(|m| m.period).collect()),
        ),
        (
            "frequency".to_string(),
            Column::F64(
                (modes.iter())
                    .map(|m| m.omega / (2.0 * std::f64::consts::PI))
                    .collect(),
            ),
        ),
        (
            "omega".to_string(),
            Column::F64(modes.iter().map(|m| m.omega).collect()),
        ),
    ];
    for (i, n) in scene.dof_names.iter().enumerate() {
        let shape = (modes.iter())
            .map(|m| m.shape[i] / m.shape.amax().max(1e-300))
            .collect();
        cols.push((n.clone(), Column::F64(shape)));
    }
    columns_to_py(py, cols)
}
