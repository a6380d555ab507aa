//! A study's numbers as a table of points, the one the studies view draws beside its chart and
//! its cursor steps through: one row per point along x (a `[[run]]` of the PGA study, a μ of
//! the μ study, a PGA level of the suite, a point of work-precision), one column per series of
//! the chart, each value the study's own number (NaN where there is none: not run, failed).
//! The screening has no such table (its maps and blocks are its numbers).

use crate::figures::{FIG7_WITH_CONTACT, FIG7_WITHOUT_CONTACT};
use crate::study_table::{RunTable, StudyKind, StudyTable};
use crate::suite::stats::median;

/// One column of values: the mark of its series on the chart and its heading.
#[derive(Clone, Debug, PartialEq)]
pub struct Column {
    pub mark: char,
    /// Its heading in the table and its name in the readout.
    pub head: String,
}

/// One point along x: its label (the run, the μ, the level, the method and knob), x and the
/// value of each column.
#[derive(Clone, Debug, PartialEq)]
pub struct PointRow {
    pub label: String,
    pub x: f64,
    pub values: Vec<f64>,
}

/// A study's table of points.
#[derive(Clone, Debug, PartialEq)]
pub struct Points {
    /// The heading of the labels (`run`, `μ`, `PGA`, `point`).
    pub label_head: String,
    /// What x is (`PGA x`) and its unit (`g`); empty when the label is x itself.
    pub x_name: String,
    pub x_unit: String,
    /// The unit of the values (`rad`, `%`, `-`).
    pub unit: String,
    pub columns: Vec<Column>,
    pub rows: Vec<PointRow>,
}

impl Points {
    /// The row at `cursor`, held within the table.
    pub fn at(&self, cursor: usize) -> Option<&PointRow> {
        self.rows.get(cursor.min(self.rows.len().saturating_sub(1)))
    }
}

/// The character marking run k's points: 1–9, then a–z.
pub fn run_mark(k: usize) -> char {
    match k {
        1..=9 => char::from(b'0' + k as u8),
        10..=35 => char::from(b'a' + (k - 10) as u8),
        _ => '+',
    }
}

/// A number as the table shows it: 3 significant digits (scientific below 0.01 and from 1e5),
/// `-` for none.
pub fn cell(v: f64) -> String {
    let a = v.abs();
    if v.is_nan() {
        "-".into()
    } else if a.is_finite() && a != 0.0 && !(1e-2..1e5).contains(&a) {
        format!("{v:.2e}")
    } else {
        crate::tui::chart::fmt_sig(v, 3)
    }
}

/// The table of a study (None: the screening, or nothing to show yet).
pub fn points(table: &StudyTable) -> Option<Points> {
    let p = match table {
        StudyTable::Runs(t) => match t.kind {
            StudyKind::Mu => mu_points(t),
            StudyKind::Suite => suite_points(t),
            _ => pga_points(t),
        },
        StudyTable::Precision(t) => {
            let rows = (t.planned.iter().zip(&t.points))
                .map(|((m, knob), p)| {
                    let ok = p.as_ref().filter(|p| p.is_ok());
                    PointRow {
                        label: format!("{} {knob}", m.letter()),
                        x: ok.map_or(f64::NAN, |p| p.cpu_s),
                        values: vec![ok.map_or(f64::NAN, |p| p.peak_error)],
                    }
                })
                .collect();
            Points {
                label_head: "method, knob".into(),
                x_name: "CPU".into(),
                x_unit: "s".into(),
                unit: "-".into(),
                columns: vec![Column {
                    mark: '*',
                    head: "peak error".into(),
                }],
                rows,
            }
        }
        // their own tables: the screening's maps, the ladder's variants, the swings' inputs
        StudyTable::Screen(_) | StudyTable::Adequacy(_) | StudyTable::Sensitivity(_) => {
            return None;
        }
    };
    (!p.rows.is_empty()).then_some(p)
}

/// Fig. 7: a row per `[[run]]`, its peak |θ| without contact and with.
fn pga_points(t: &RunTable) -> Points {
    let mut rows: Vec<PointRow> = Vec::new();
    for r in &t.runs {
        let i = match rows.iter().position(|p| p.label == r.run.to_string()) {
            Some(i) => i,
            None => {
                rows.push(PointRow {
                    label: r.run.to_string(),
                    x: r.pga_x,
                    values: vec![f64::NAN; 2],
                });
                rows.len() - 1
            }
        };
        if r.is_ok() {
            rows[i].values[usize::from(r.contact)] = r.peak_rotation;
        }
    }
    Points {
        label_head: "run".into(),
        x_name: "PGA x".into(),
        x_unit: "g".into(),
        unit: "rad".into(),
        columns: vec![
            Column {
                mark: FIG7_WITHOUT_CONTACT,
                head: "no contact".into(),
            },
            Column {
                mark: FIG7_WITH_CONTACT,
                head: "contact".into(),
            },
        ],
        rows,
    }
}

/// Fig. 8: a row per μ, the increase of each run's curve at it.
fn mu_points(t: &RunTable) -> Points {
    let curves = t.fig8();
    let rows = (t.mus().into_iter())
        .map(|mu| PointRow {
            label: crate::tui::chart::fmt_sig(mu, 3),
            x: mu,
            values: (curves.iter())
                .map(|c| {
                    (c.points.iter())
                        .find(|p| p.0.to_bits() == mu.to_bits())
                        .map_or(f64::NAN, |p| p.1)
                })
                .collect(),
        })
        .collect();
    Points {
        label_head: "μ".into(),
        x_name: String::new(),
        x_unit: String::new(),
        unit: "%".into(),
        columns: (curves.iter())
            .map(|c| Column {
                mark: run_mark(c.run),
                head: format!("{} g", crate::tui::chart::fmt_sig(c.pga_x, 2)),
            })
            .collect(),
        rows,
    }
}

/// The suite: a row per PGA level, each pair's peak |θ| and their median.
fn suite_points(t: &RunTable) -> Points {
    let mut levels: Vec<f64> = t.runs.iter().map(|r| r.pga_x).collect();
    levels.sort_by(f64::total_cmp);
    levels.dedup_by(|a, b| a.to_bits() == b.to_bits());
    let pairs = t.runs.iter().map(|r| r.run).max().unwrap_or(0);
    let rows = (levels.iter())
        .map(|&l| {
            let at = |p: usize| {
                (t.runs.iter())
                    .find(|r| r.run == p && r.pga_x.to_bits() == l.to_bits() && r.is_ok())
                    .map_or(f64::NAN, |r| r.peak_rotation)
            };
            let mut values: Vec<f64> = (1..=pairs).map(at).collect();
            let ok: Vec<f64> = values.iter().copied().filter(|v| !v.is_nan()).collect();
            values.push(median(&ok).unwrap_or(f64::NAN));
            PointRow {
                label: format!("{} g", crate::tui::chart::fmt_sig(l, 3)),
                x: l,
                values,
            }
        })
        .collect();
    let mut columns: Vec<Column> = (1..=pairs)
        .map(|p| Column {
            mark: run_mark(p),
            head: format!("pair {p}"),
        })
        .collect();
    columns.push(Column {
        mark: '#',
        head: "median".into(),
    });
    Points {
        label_head: "PGA".into(),
        x_name: String::new(),
        x_unit: String::new(),
        unit: "rad".into(),
        columns,
        rows,
    }
}
