//! Tables handed to Python as columns: float64 and int64 values as little-endian bytes (numpy
//! reads them without a copy per value), strings as lists; history.csv's and events.csv's
//! columns at full precision, in the files' order.

use deckspin::output::{EventRecord, RunOutput, Sample, SampleKind};
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

/// The columns of history.csv, in its order, at full precision.
pub(crate) fn history_columns(out: &RunOutput) -> Vec<(String, Column)> {
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
