//! Tables handed to Python as columns: float64 and int64 values as little-endian bytes (numpy
//! reads them without a copy per value), strings as lists; history.csv's and events.csv's
//! columns at full precision, in the files' order.

use deckspin::output::{EventRecord, RunOutput};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyList, PyTuple};

/// A column of a table: float64 or int64 values as little-endian bytes, or strings.
pub(crate) enum Column {
    F64(Vec<f64>),
    I64(Vec<i64>),
    Str(Vec<String>),
}

/// (name, kind, data) per column: kind "f8" or "i8" with bytes, "str" with a list.
pub(crate) fn columns_to_py<'py>(
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

/// The columns of history.csv, in its order, at full precision (the library's layout,
/// [`deckspin::output::history_columns`]).
pub(crate) fn history_columns(out: &RunOutput) -> Vec<(String, Column)> {
    let s = &out.samples;
    (deckspin::output::history_columns(out).into_iter())
        .map(|(name, col)| {
            let values = if col.is_text() {
                Column::Str(
                    s.iter()
                        .filter_map(|x| col.text(x))
                        .map(String::from)
                        .collect(),
                )
            } else {
                Column::F64(s.iter().map(|x| col.value(x)).collect())
            };
            (name, values)
        })
        .collect()
}

/// The columns of events.csv, in its order, at full precision (an empty field is NaN).
pub(crate) fn event_columns(out: &RunOutput) -> Vec<(String, Column)> {
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
