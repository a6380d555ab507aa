//! `deckspin._native`: the Python binding of the deckspin library (PyO3). The pure-Python
//! package `deckspin` (python/deckspin) wraps it: tables as pandas DataFrames or numpy arrays,
//! `set=` values as `--set` text, exceptions raised with the partial results attached.
//!
//! Every run and job here releases the GIL; a run takes it back at most ten times a second
//! (`interval`) to look for Ctrl-C (`Python::check_signals`) and to call the progress callback.
//! No error crosses the FFI as a panic: model errors become `deckspin.ModelError` (file, line,
//! field), refused jobs `deckspin.LimitError`, bad arguments `ValueError`.

mod columns;
mod errors;
mod jobs;

use columns::{columns_to_py, event_columns, history_columns};
use deckspin::model::{self, ModelError, Motions};
use deckspin::output::{EventRecord, Sample};
use deckspin::run::{Observer, Run, Stop};
use deckspin::scene::Scene;
use errors::{TEXT_NAME, error, model_error};
use jobs::{Raised, modes, suite, sweep};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyList;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// A model: its text, the path that names it and anchors its record files, its `--set`
/// overrides, and the scene they compile to.
#[pyclass(module = "deckspin._native", frozen)]
pub struct NativeModel {
    text: String,
    path: PathBuf,
    set: Vec<String>,
    scene: Scene,
    warnings: Vec<String>,
}

impl NativeModel {
    /// The scene with `extra` overrides after the model's (compiled as `deckspin run` does).
    fn scene_with(&self, py: Python<'_>, extra: &[String]) -> PyResult<(Scene, Vec<String>)> {
        if extra.is_empty() {
            return Ok((self.scene.clone(), self.warnings.clone()));
        }
        let mut set = self.set.clone();
        set.extend(extra.iter().cloned());
        let loaded = py
            .detach(|| model::load_str_checked(&self.text, &self.path, &set, &Motions::default()))
            .map_err(|e| model_error(py, &e, &self.path))?;
        let warnings = loaded.warnings.iter().map(|w| w.to_string()).collect();
        Ok((loaded.scene, warnings))
    }
}

/// Compile a model: the file `path`, or `text` (then named `<text>` in errors, its record
/// files relative to `base`, else to the current directory), with the `set` overrides.
#[pyfunction]
#[pyo3(signature = (path, text, base, set))]
fn load(
    py: Python<'_>,
    path: Option<PathBuf>,
    text: Option<String>,
    base: Option<PathBuf>,
    set: Vec<String>,
) -> PyResult<NativeModel> {
    let (text, path) = match (path, text) {
        (Some(path), None) => {
            let text = deckspin::input::read_bounded(&path, deckspin::input::MAX_MODEL_BYTES)
                .map_err(|source| {
                    let e = ModelError::Io {
                        path: path.clone(),
                        source,
                    };
                    model_error(py, &e, &path)
                })?;
            (text, path)
        }
        (None, Some(text)) => {
            let path = match base {
                Some(b) => b.join(TEXT_NAME),
                None => PathBuf::from(TEXT_NAME),
            };
            (text, path)
        }
        _ => {
            return Err(PyValueError::new_err(
                "give a model path or text=, not both",
            ));
        }
    };
    let loaded = py
        .detach(|| model::load_str_checked(&text, &path, &set, &Motions::default()))
        .map_err(|e| model_error(py, &e, &path))?;
    Ok(NativeModel {
        warnings: loaded.warnings.iter().map(|w| w.to_string()).collect(),
        scene: loaded.scene,
        text,
        path,
        set,
    })
}

#[pymethods]
impl NativeModel {
    #[getter]
    fn title(&self) -> String {
        self.scene.title.clone()
    }
    #[getter]
    fn path(&self) -> String {
        self.path.to_string_lossy().into_owned()
    }
    #[getter]
    fn text(&self) -> String {
        self.text.clone()
    }
    #[getter]
    fn set(&self) -> Vec<String> {
        self.set.clone()
    }
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }
    #[getter]
    fn dof_names(&self) -> Vec<String> {
        self.scene.dof_names.clone()
    }
    #[getter]
    fn contact_names(&self) -> Vec<String> {
        self.scene.contacts.iter().map(|c| c.name.clone()).collect()
    }
    #[getter]
    fn t_end(&self) -> f64 {
        self.scene.settings.t_end
    }
    #[getter]
    fn method(&self) -> &'static str {
        self.scene.settings.method.name()
    }

    /// Run as `deckspin run` does (the same checks, the same refinement of a step the method
    /// chose): (the run, an exception to raise or None). The exception is the KeyboardInterrupt
    /// of a Ctrl-C or what the progress callback raised; the run is then cancelled where it was.
    #[pyo3(signature = (method, progress, interval))]
    fn run(
        &self,
        py: Python<'_>,
        method: Option<String>,
        progress: Option<Py<PyAny>>,
        interval: f64,
    ) -> PyResult<(NativeRun, Raised)> {
        use deckspin::run::{OutputBudget, check_memory, check_output};
        let mut extra = Vec::new();
        if let Some(m) = &method {
            if deckspin::methods::Method::parse(m).is_none() {
                let names = deckspin::methods::Method::names(", ");
                return Err(PyValueError::new_err(format!(
                    "method '{m}': unknown method ({names})"
                )));
            }
            extra.push(format!("solver.method=\"{m}\""));
        }
        let (mut scene, warnings) = self.scene_with(py, &extra)?;
        let refused = |e: deckspin::run::LimitError| error(py, "LimitError", e.to_string());
        check_output(&scene, &OutputBudget::default()).map_err(refused)?;
        // the run's history is kept in memory (`deckspin run` streams it to disk)
        check_memory(&scene).map_err(refused)?;
        let mut watch = Watch::new(progress, scene.settings.t_end, interval);
        let mut notes = Vec::new();
        let (run, cpu) = py.detach(|| {
            let mut refinements = 0;
            let mut cpu = 0.0;
            loop {
                if let Some(why) = &scene.settings.step_chosen {
                    notes.push(why.clone());
                }
                let (run, c) = deckspin::clock::thread_cpu(|| {
                    deckspin::simulate::integrate(&scene, &mut watch)
                });
                cpu += c;
                if refinements < deckspin::simulate::MAX_REFINEMENTS
                    && watch.raised.is_none()
                    && let Some(next) = deckspin::simulate::refined(&scene, &run)
                {
                    refinements += 1;
                    scene = next;
                    continue;
                }
                break (run, cpu);
            }
        });
        let raised = watch.raised.take().map(|e| e.into_value(py).into_any());
        Ok((
            NativeRun {
                run,
                cpu,
                notes,
                warnings,
                method: scene.settings.method.name(),
            },
            raised,
        ))
    }
}

/// Watches a run: every `interval` seconds at most it takes the GIL, looks for a signal
/// (Ctrl-C) and calls the progress callback with (t, t_end); either raising, or the callback
/// returning False, cancels the run.
struct Watch {
    progress: Option<Py<PyAny>>,
    t_end: f64,
    interval: Duration,
    last: Instant,
    /// The exception that cancelled the run.
    raised: Option<PyErr>,
}

impl Watch {
    fn new(progress: Option<Py<PyAny>>, t_end: f64, interval: f64) -> Self {
        let interval = Duration::from_secs_f64(interval.clamp(0.01, 60.0));
        Self {
            progress,
            t_end,
            interval,
            last: Instant::now(),
            raised: None,
        }
    }
}

impl Observer for Watch {
    fn batch(&mut self, _: &[Sample], _: &[EventRecord], t: f64) -> bool {
        if self.raised.is_some() {
            return false;
        }
        if self.last.elapsed() < self.interval {
            return true;
        }
        self.last = Instant::now();
        Python::attach(|py| {
            if let Err(e) = py.check_signals() {
                self.raised = Some(e);
                return false;
            }
            let Some(cb) = &self.progress else {
                return true;
            };
            match cb.call1(py, (t, self.t_end)) {
                Ok(v) => !matches!(v.extract::<bool>(py), Ok(false)),
                Err(e) => {
                    self.raised = Some(e);
                    false
                }
            }
        })
    }
}

/// What a run computed, however it ended.
#[pyclass(module = "deckspin._native", frozen)]
pub struct NativeRun {
    run: Run,
    /// CPU seconds of the integration (the thread that ran it), refinements included.
    cpu: f64,
    /// Why the method chose its step (fixed-step methods), per attempt.
    notes: Vec<String>,
    warnings: Vec<String>,
    method: &'static str,
}

#[pymethods]
impl NativeRun {
    /// "finished", "cancelled" or "failed".
    #[getter]
    fn status(&self) -> &'static str {
        self.run.stop.label()
    }
    #[getter]
    fn cpu_time(&self) -> f64 {
        self.cpu
    }
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.notes.clone()
    }
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }
    #[getter]
    fn method(&self) -> &'static str {
        self.method
    }
    /// (t, kind, reason) of a failed run, else None.
    #[getter]
    fn failure(&self) -> Option<(f64, &'static str, String)> {
        self.run.failure().map(|f| (f.t, f.kind, f.reason))
    }
    /// The instant a cancelled run stopped at, else None.
    #[getter]
    fn cancelled_at(&self) -> Option<f64> {
        match self.run.stop {
            Stop::Cancelled { t } => Some(t),
            _ => None,
        }
    }
    /// summary.json's text, as `deckspin run` writes it.
    fn summary_json(&self) -> PyResult<String> {
        self.run
            .summary_json()
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }
    /// history.csv's text, as `deckspin run` writes it.
    fn history_csv(&self, py: Python<'_>) -> PyResult<String> {
        let out = &self.run.output;
        let bytes = py
            .detach(|| {
                let mut w = deckspin::output::HistoryWriter::new(Vec::new(), out)?;
                w.write(&out.samples)?;
                w.finish()
            })
            .map_err(|e| PyOSError::new_err(e.to_string()))?;
        String::from_utf8(bytes).map_err(|e| PyValueError::new_err(e.to_string()))
    }
    /// events.csv's text, as `deckspin run` writes it.
    fn events_csv(&self) -> String {
        let out = &self.run.output;
        deckspin::output::events_csv(&out.events, &out.contact_names, &out.element_names)
    }
    fn history_columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let cols = py.detach(|| history_columns(&self.run.output));
        columns_to_py(py, cols)
    }
    fn event_columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        columns_to_py(py, event_columns(&self.run.output))
    }
    /// history.csv, events.csv and summary.json in `dir` (created), as `deckspin run`.
    fn write(&self, py: Python<'_>, dir: PathBuf) -> PyResult<()> {
        py.detach(|| self.run.write_all(&dir)).map_err(|e| {
            PyOSError::new_err(format!("{}: cannot write results: {e}", dir.display()))
        })
    }
}

/// The methods a run may use.
#[pyfunction]
fn methods() -> Vec<&'static str> {
    deckspin::methods::Method::ALL
        .iter()
        .map(|m| m.name())
        .collect()
}

/// The μ values of the paper's Fig. 8 (0, 0.1, …, 0.7).
#[pyfunction]
fn fig8_mus() -> Vec<f64> {
    deckspin::studies::fig8_mus()
}

/// The library's version.
#[pyfunction]
fn version() -> &'static str {
    env!("CARGO_PKG_VERSION")
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<NativeModel>()?;
    m.add_class::<NativeRun>()?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(suite, m)?)?;
    m.add_function(wrap_pyfunction!(modes, m)?)?;
    m.add_function(wrap_pyfunction!(methods, m)?)?;
    m.add_function(wrap_pyfunction!(fig8_mus, m)?)?;
    m.add_function(wrap_pyfunction!(version, m)?)?;
    Ok(())
}
