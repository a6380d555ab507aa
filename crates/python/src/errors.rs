//! Errors as the exceptions of `deckspin._errors`: a model's (file, line, field), a job refused
//! before it starts, a suite's arguments.

use deckspin::model::ModelError;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::path::Path;

/// The name a model given as text has in errors (in the folder `base`, if given).
pub(crate) const TEXT_NAME: &str = "<text>";

/// An exception class of `deckspin._errors` (pure Python, no import of this module).
fn error_class<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("deckspin._errors")?.getattr(name)
}

/// `deckspin.ModelError` with `file`, `line`, `column`, `field`, `argument` and `reason`; an
/// error of a `set=` override names the model's file `model`.
pub(crate) fn model_error(py: Python<'_>, e: &ModelError, model: &Path) -> PyErr {
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
pub(crate) fn error(py: Python<'_>, class: &str, message: String) -> PyErr {
    match error_class(py, class).and_then(|c| c.call1((message,))) {
        Ok(inst) => PyErr::from_value(inst),
        Err(e) => e,
    }
}

/// A suite refused before it starts, as its exception.
pub(crate) fn suite_error(py: Python<'_>, e: deckspin::suite::SuiteError, model: &Path) -> PyErr {
    use deckspin::suite::SuiteError;
    match e {
        SuiteError::Model(m) => model_error(py, &m, model),
        SuiteError::TooLarge(t) => error(py, "LimitError", t.to_string()),
        other => PyValueError::new_err(other.to_string()),
    }
}
