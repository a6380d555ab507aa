//! `deckspin._native`: the Python binding of the deckspin library (PyO3). The pure-Python
//! package `deckspin` (python/deckspin) wraps it: tables as pandas DataFrames or numpy arrays,
//! `set=` values as `--set` text, exceptions raised with the partial results attached.
//!
//! Every run and job here releases the GIL; a run takes it back at most ten times a second
//! (`interval`) to look for Ctrl-C (`Python::check_signals`) and to call the progress callback.
//! No error crosses the FFI as a panic: model errors become `deckspin.ModelError` (file, line,
//! field), refused jobs `deckspin.LimitError`, bad arguments `ValueError`.

use deckspin::model::{self, ModelError, Motions};
use deckspin::output::{EventRecord, RunOutput, Sample, SampleKind};
use deckspin::progress::Progress;
use deckspin::run::{Observer, Run, Stop};
use deckspin::scene::Scene;
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyList, PyTuple};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// The name a model given as text has in errors (in the folder `base`, if given).
const TEXT_NAME: &str = "<text>";

/// An exception class of `deckspin._errors` (pure Python, no import of this module).
fn error_class<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("deckspin._errors")?.getattr(name)
}

/// `deckspin.ModelError` with `file`, `line`, `column`, `field`, `argument` and `reason`; an
/// error of a `set=` override names the model's file `model`.
fn model_error(py: Python<'_>, e: &ModelError, model: &Path) -> PyErr {
    let build = || -> PyResult<PyErr> {
        let cls = error_class(py, "ModelError")?;
        // (file, column, field, argument, reason); the line is the error's own
        let (file, column, field, argument, reason): Place = match e {
            ModelError::Io { path, source } => (
                Some(path),
                None,
                None,
                None,
                format!("cannot read: {source}"),
            ),
            ModelError::Parse {
                path,
                column,
                message,
                ..
            } => (Some(path), Some(*column), None, None, message.clone()),
            ModelError::Invalid {
                path,
                field,
                reason,
                ..
            } => (Some(path), None, Some(field), None, reason.clone()),
            ModelError::Override { key, reason } => {
                (Some(model), None, Some(key), Some(key), reason.clone())
            }
            ModelError::OverrideInvalid {
                argument,
                field,
                reason,
            } => (
                Some(model),
                None,
                Some(field),
                Some(argument),
                reason.clone(),
            ),
            ModelError::Record {
                path,
                field,
                record,
                source,
                ..
            } => (
                Some(path),
                None,
                Some(field),
                None,
                format!("{record}: {source}"),
            ),
            ModelError::Excitation { path, source } => {
                (Some(path), None, None, None, source.to_string())
            }
        };
        let inst = cls.call1((e.to_string(),))?;
        inst.setattr("file", file.map(|p| p.to_string_lossy().into_owned()))?;
        inst.setattr("line", e.line())?;
        inst.setattr("column", column)?;
        inst.setattr("field", field)?;
        inst.setattr("argument", argument)?;
        inst.setattr("reason", reason)?;
        Ok(PyErr::from_value(inst))
    };
    build().unwrap_or_else(|err| err)
}

/// Where a model error is: file, column, field, argument, and the reason without the place.
type Place<'a> = (
    Option<&'a Path>,
    Option<usize>,
    Option<&'a String>,
    Option<&'a String>,
    String,
);

/// An exception of `deckspin._errors` by class name, with its message.
fn error(py: Python<'_>, class: &str, message: String) -> PyErr {
    match error_class(py, class).and_then(|c| c.call1((message,))) {
        Ok(inst) => PyErr::from_value(inst),
        Err(e) => e,
    }
}

/// A suite refused before it starts, as its exception.
fn suite_error(py: Python<'_>, e: deckspin::suite::SuiteError, model: &Path) -> PyErr {
    use deckspin::suite::SuiteError;
    match e {
        SuiteError::Model(m) => model_error(py, &m, model),
        SuiteError::TooLarge(t) => error(py, "LimitError", t.to_string()),
        other => PyValueError::new_err(other.to_string()),
    }
}

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

/// A column of a table: float64 or int64 values as little-endian bytes, or strings.
enum Column {
    F64(Vec<f64>),
    I64(Vec<i64>),
    Str(Vec<String>),
}

/// (name, kind, data) per column: kind "f8" or "i8" with bytes, "str" with a list.
fn columns_to_py<'py>(
    py: Python<'py>,
    cols: Vec<(String, Column)>,
) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for (name, col) in cols {
        let item: Bound<'py, PyTuple> = match col {
            Column::F64(v) => {
                let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
                (name, "f8", PyBytes::new(py, &bytes)).into_pyobject(py)?
            }
            Column::I64(v) => {
                let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
                (name, "i8", PyBytes::new(py, &bytes)).into_pyobject(py)?
            }
            Column::Str(v) => (name, "str", PyList::new(py, v)?).into_pyobject(py)?,
        };
        list.append(item)?;
    }
    Ok(list)
}

/// The columns of history.csv, in its order, at full precision.
fn history_columns(out: &RunOutput) -> Vec<(String, Column)> {
    let s = &out.samples;
    let f = |g: &dyn Fn(&Sample) -> f64| Column::F64(s.iter().map(g).collect());
    let mut cols = vec![
        ("t".to_string(), f(&|x| x.t)),
        (
            "row".to_string(),
            Column::Str(
                (s.iter())
                    .map(|x| match x.kind {
                        SampleKind::Grid => "grid",
                        SampleKind::PreEvent => "pre-event",
                        SampleKind::PostEvent => "post-event",
                    })
                    .map(String::from)
                    .collect(),
            ),
        ),
    ];
    for (i, n) in out.dof_names.iter().enumerate() {
        cols.push((n.clone(), f(&|x| x.q[i])));
    }
    for (i, n) in out.dof_names.iter().enumerate() {
        cols.push((format!("d/dt {n}"), f(&|x| x.v[i])));
    }
    type Field = fn(&deckspin::output::ContactSample) -> f64;
    let fields: [(&str, Field); 5] = [
        ("gap", |c| c.gap),
        ("gap_rate", |c| c.gap_rate),
        ("slip_rate", |c| c.slip_rate),
        ("normal_force", |c| c.normal_force),
        ("tangential_force", |c| c.tangential_force),
    ];
    for (i, c) in out.contact_names.iter().enumerate() {
        for (name, g) in fields {
            cols.push((format!("{c}.{name}"), f(&|x| g(&x.contacts[i]))));
        }
        let states = s.iter().map(|x| x.contacts[i].state.label().to_string());
        cols.push((format!("{c}.state"), Column::Str(states.collect())));
    }
    for (i, e) in out.element_names.iter().enumerate() {
        cols.push((format!("{e}.deformation"), f(&|x| x.elements[i].0)));
        cols.push((format!("{e}.force"), f(&|x| x.elements[i].1)));
    }
    type Energy = fn(&deckspin::output::EnergySample) -> f64;
    let energies: [(&str, Energy); 10] = [
        ("kinetic", |e| e.kinetic),
        ("elastic", |e| e.elastic),
        ("hysteretic", |e| e.hysteretic),
        ("damping", |e| e.damping),
        ("friction", |e| e.friction),
        ("impact_normal", |e| e.impact_normal),
        ("impact_tangential", |e| e.impact_tangential),
        ("loads", |e| e.loads),
        ("supports", |e| e.supports),
        ("closure", |e| e.closure),
    ];
    for (name, g) in energies {
        cols.push((format!("energy.{name}"), f(&|x| g(&x.energy))));
    }
    for seat in &out.seats {
        let name = out
            .contact_names
            .get(seat.contact)
            .map_or("?", String::as_str);
        let (c, edge) = (seat.contact, seat.edge);
        let margin = f(&|x| x.contacts.get(c).map_or(f64::NAN, |k| edge - k.gap));
        cols.push((format!("{name}.seat_margin"), margin));
    }
    cols
}

/// The columns of events.csv, in its order, at full precision (an empty field is NaN).
fn event_columns(out: &RunOutput) -> Vec<(String, Column)> {
    let e = &out.events;
    let f = |g: &dyn Fn(&EventRecord) -> f64| Column::F64(e.iter().map(g).collect());
    let s = |g: &dyn Fn(&EventRecord) -> String| Column::Str(e.iter().map(g).collect());
    let name = |r: &EventRecord| {
        let names = if r.kind.of_contact() {
            &out.contact_names
        } else {
            &out.element_names
        };
        names.get(r.contact).map_or("?", String::as_str).to_string()
    };
    vec![
        ("t".into(), f(&|r| r.t)),
        ("contact".into(), s(&name)),
        ("kind".into(), s(&|r| r.kind.label().to_string())),
        ("normal_impulse".into(), f(&|r| r.normal)),
        ("tangential_impulse".into(), f(&|r| r.tangential)),
        ("gap_rate_before".into(), f(&|r| r.gap_rate_before)),
        ("gap_rate_after".into(), f(&|r| r.gap_rate_after)),
        ("slip_rate_after".into(), f(&|r| r.slip_rate_after)),
        (
            "sticks".into(),
            s(&|r| {
                r.sticks
                    .map_or("", |b| if b { "stick" } else { "slip" })
                    .into()
            }),
        ),
        (
            "accumulation_time".into(),
            f(&|r| if r.info.is_finite() { r.info } else { f64::NAN }),
        ),
    ]
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

/// The exception a job's watcher caught (Ctrl-C's KeyboardInterrupt, or the callback's), to
/// be raised by the Python wrapper with the partial result attached.
type Raised = Option<Py<PyAny>>;

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
fn sweep<'py>(
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
fn suite(
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
fn modes<'py>(py: Python<'py>, model: &NativeModel) -> PyResult<Bound<'py, PyList>> {
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
