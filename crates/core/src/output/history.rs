//! history.csv: its columns and its writer.

use super::number::Numbers;
use super::{RunOutput, Sample};
use std::io::Write;
use std::path::Path;

impl RunOutput {
    /// history.csv into `path`, created or truncated (`write_all` writes it in a staging
    /// folder first, so that the run's files change as one transaction).
    pub fn write_history(&self, path: &Path) -> std::io::Result<()> {
        let file = std::io::BufWriter::new(std::fs::File::create(path)?);
        let mut w = HistoryWriter::new(file, self)?;
        w.write(&self.samples)?;
        w.finish().map(|_| ())
    }
}

/// Writes history.csv: the header, then rows as they come (a run streamed to disk writes each
/// batch of samples as the observer is handed it; [`RunOutput::write_history`] all at once).
pub struct HistoryWriter<W: Write> {
    w: W,
    rows: usize,
    /// (contact, edge) of each seat: its margin edge − g_N is a column.
    seats: Vec<(usize, f64)>,
    numbers: Numbers,
}

impl<W: Write> HistoryWriter<W> {
    /// The writer, its header written: the columns of `out`'s DOFs, contacts and elements.
    pub fn new(mut w: W, out: &RunOutput) -> std::io::Result<Self> {
        let head: Vec<String> = history_columns(out).into_iter().map(|(n, _)| n).collect();
        writeln!(w, "{}", head.join(","))?;
        let seats = out.seats.iter().map(|s| (s.contact, s.edge)).collect();
        Ok(Self {
            w,
            rows: 0,
            seats,
            numbers: Numbers::new(),
        })
    }

    /// Rows written so far.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// One row per sample, written field by field: no string per value; each number the
    /// shortest text that reads back as the same f64 ([`Numbers`]).
    pub fn write(&mut self, samples: &[Sample]) -> std::io::Result<()> {
        let w = &mut self.w;
        let n = &mut self.numbers;
        for s in samples {
            n.write(w, s.t)?;
            w.write_all(b",")?;
            w.write_all(s.kind.label().as_bytes())?;
            for &x in s.q.iter().chain(s.v.iter()) {
                n.write_field(w, x)?;
            }
            for c in &s.contacts {
                for x in [
                    c.gap,
                    c.gap_rate,
                    c.slip_rate,
                    c.normal_force,
                    c.tangential_force,
                ] {
                    n.write_field(w, x)?;
                }
                w.write_all(b",")?;
                w.write_all(c.state.label().as_bytes())?;
            }
            for &(e, f) in &s.elements {
                n.write_field(w, e)?;
                n.write_field(w, f)?;
            }
            let en = &s.energy;
            for x in [
                en.kinetic,
                en.elastic,
                en.hysteretic,
                en.damping,
                en.friction,
                en.impact_normal,
                en.impact_tangential,
                en.loads,
                en.supports,
                en.closure,
            ] {
                n.write_field(w, x)?;
            }
            for &(c, edge) in &self.seats {
                n.write_field(w, s.contacts.get(c).map_or(f64::NAN, |c| edge - c.gap))?;
            }
            w.write_all(b"\n")?;
        }
        self.rows += samples.len();
        Ok(())
    }

    /// Flushes and returns the inner writer.
    pub fn finish(mut self) -> std::io::Result<W> {
        self.w.flush()?;
        Ok(self.w)
    }
}

/// One column of history.csv: what it holds of a sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HistoryColumn {
    /// t.
    Time,
    /// The sample's kind ([`SampleKind::label`]).
    Row,
    /// q of a DOF.
    Position(usize),
    /// q̇ of a DOF.
    Velocity(usize),
    /// A number of a contact: g_N, ġ_N, ġ_T, λ_N, λ_T (0 … 4).
    Contact(usize, usize),
    /// A contact's state ([`super::ContactState::label`]).
    State(usize),
    /// A hysteretic element's deformation (0) or force (1).
    Element(usize, usize),
    /// A term of the energy ledger, in [`ENERGY_COLUMNS`]' order.
    Energy(usize),
    /// A seat's margin edge − g_N: (its contact, its edge).
    SeatMargin(usize, f64),
}

impl HistoryColumn {
    /// The column's number for sample `s` (NaN for the text columns and a missing contact).
    pub fn value(&self, s: &Sample) -> f64 {
        let en = &s.energy;
        match *self {
            HistoryColumn::Time => s.t,
            HistoryColumn::Position(i) => s.q[i],
            HistoryColumn::Velocity(i) => s.v[i],
            HistoryColumn::Contact(i, k) => {
                let c = &s.contacts[i];
                [
                    c.gap,
                    c.gap_rate,
                    c.slip_rate,
                    c.normal_force,
                    c.tangential_force,
                ][k]
            }
            HistoryColumn::Element(j, k) => [s.elements[j].0, s.elements[j].1][k],
            HistoryColumn::Energy(k) => [
                en.kinetic,
                en.elastic,
                en.hysteretic,
                en.damping,
                en.friction,
                en.impact_normal,
                en.impact_tangential,
                en.loads,
                en.supports,
                en.closure,
            ][k],
            HistoryColumn::SeatMargin(c, edge) => {
                s.contacts.get(c).map_or(f64::NAN, |c| edge - c.gap)
            }
            HistoryColumn::Row | HistoryColumn::State(_) => f64::NAN,
        }
    }

    /// A text column (the row's kind, a contact's state): [`HistoryColumn::text`], not a number.
    pub fn is_text(&self) -> bool {
        matches!(self, HistoryColumn::Row | HistoryColumn::State(_))
    }

    /// The column's text for sample `s`, for the text columns (the row's kind, a contact's
    /// state); None for the numbers.
    pub fn text(&self, s: &Sample) -> Option<&'static str> {
        match *self {
            HistoryColumn::Row => Some(s.kind.label()),
            HistoryColumn::State(i) => Some(s.contacts[i].state.label()),
            _ => None,
        }
    }
}

/// The columns of history.csv of `out`, in order, with their names: the header and what
/// each holds ([`HistoryWriter`] writes the same fields; the Python package reads them).
pub fn history_columns(out: &RunOutput) -> Vec<(String, HistoryColumn)> {
    let mut cols = vec![
        ("t".to_string(), HistoryColumn::Time),
        ("row".to_string(), HistoryColumn::Row),
    ];
    let dofs = out.dof_names.iter().enumerate();
    cols.extend(
        dofs.clone()
            .map(|(i, n)| (n.clone(), HistoryColumn::Position(i))),
    );
    cols.extend(dofs.map(|(i, n)| (format!("d/dt {n}"), HistoryColumn::Velocity(i))));
    for (i, c) in out.contact_names.iter().enumerate() {
        for (k, f) in CONTACT_COLUMNS[..5].iter().enumerate() {
            cols.push((format!("{c}.{f}"), HistoryColumn::Contact(i, k)));
        }
        cols.push((
            format!("{c}.{}", CONTACT_COLUMNS[5]),
            HistoryColumn::State(i),
        ));
    }
    for (j, e) in out.element_names.iter().enumerate() {
        cols.push((format!("{e}.deformation"), HistoryColumn::Element(j, 0)));
        cols.push((format!("{e}.force"), HistoryColumn::Element(j, 1)));
    }
    for (k, f) in ENERGY_COLUMNS.iter().enumerate() {
        cols.push((format!("energy.{f}"), HistoryColumn::Energy(k)));
    }
    // the seat margins last: a model without seats keeps its columns
    for seat in &out.seats {
        let name = out
            .contact_names
            .get(seat.contact)
            .map_or("?", String::as_str);
        cols.push((
            format!("{name}.seat_margin"),
            HistoryColumn::SeatMargin(seat.contact, seat.edge),
        ));
    }
    cols
}

/// The energy columns of history.csv, in order.
const ENERGY_COLUMNS: [&str; 10] = [
    "kinetic",
    "elastic",
    "hysteretic",
    "damping",
    "friction",
    "impact_normal",
    "impact_tangential",
    "loads",
    "supports",
    "closure",
];

/// The columns of a contact in history.csv, in order.
const CONTACT_COLUMNS: [&str; 6] = [
    "gap",
    "gap_rate",
    "slip_rate",
    "normal_force",
    "tangential_force",
    "state",
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::SampleKind;

    /// history.csv as written equals, field for field, the columns' values and texts: the
    /// writer and [`history_columns`] (what the Python package reads) hold one layout. The
    /// three-frame bridge has every kind of column: contacts closed and open, elements, seats.
    #[test]
    fn the_written_history_is_the_columns() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let mut scene = crate::load(
            &root.join("models/three-frame.toml"),
            &["solver.t_end=6".into()],
        )
        .unwrap();
        scene.settings.keep_history = true;
        let out = crate::run(&scene, &mut crate::Silent).unwrap();
        assert!(out.samples.iter().any(|s| s.kind != SampleKind::Grid));
        assert!(!out.seats.is_empty());
        let mut text = Vec::new();
        HistoryWriter::new(&mut text, &out)
            .and_then(|mut w| w.write(&out.samples).map(|_| w))
            .and_then(HistoryWriter::finish)
            .unwrap();
        let text = String::from_utf8(text).unwrap();
        let mut lines = text.lines();
        let cols = history_columns(&out);
        let head: Vec<&str> = lines.next().unwrap().split(',').collect();
        assert_eq!(
            head,
            cols.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>()
        );
        for (s, line) in out.samples.iter().zip(lines.by_ref()) {
            for ((_, col), field) in cols.iter().zip(line.split(',')) {
                match col.text(s) {
                    Some(t) => assert_eq!(field, t),
                    None => {
                        let (v, x) = (col.value(s), field.parse::<f64>().unwrap());
                        assert!(
                            v.to_bits() == x.to_bits() || (v.is_nan() && x.is_nan()),
                            "{field}"
                        );
                    }
                }
            }
            assert_eq!(line.split(',').count(), cols.len());
        }
        assert_eq!(lines.next(), None);
    }
}
