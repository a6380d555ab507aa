//! history.csv: its columns and its writer.

use super::number::Numbers;
use super::{RunOutput, Sample, SampleKind};
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
        writeln!(w, "{}", history_header(out).join(","))?;
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
            let kind: &[u8] = match s.kind {
                SampleKind::Grid => b",grid",
                SampleKind::PreEvent => b",pre-event",
                SampleKind::PostEvent => b",post-event",
            };
            n.write(w, s.t)?;
            w.write_all(kind)?;
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

/// The header of history.csv.
fn history_header(out: &RunOutput) -> Vec<String> {
    let mut head = vec!["t".to_string(), "row".to_string()];
    head.extend(out.dof_names.iter().cloned());
    head.extend(out.dof_names.iter().map(|n| format!("d/dt {n}")));
    for c in &out.contact_names {
        head.extend(CONTACT_COLUMNS.iter().map(|f| format!("{c}.{f}")));
    }
    for e in &out.element_names {
        head.push(format!("{e}.deformation"));
        head.push(format!("{e}.force"));
    }
    head.extend(ENERGY_COLUMNS.iter().map(|f| format!("energy.{f}")));
    // the seat margins last: a model without seats keeps its columns
    for s in &out.seats {
        let name = out.contact_names.get(s.contact).map_or("?", String::as_str);
        head.push(format!("{name}.seat_margin"));
    }
    head
}
