//! A run's series as a table of columns, the one layout of every CSV of sampled quantities the
//! program writes: a header of column names as `history.csv` names them ([`super::history_columns`]:
//! `t`, `<dof>`, `<contact>.gap`, `<element>.deformation`, `<element>.force`, …), then a line per
//! sample, each number its shortest round trip ([`super::number::Numbers`]; a column kept in
//! single precision holds the shortest text of its f32). `history.csv` is written sample by
//! sample ([`super::HistoryWriter`]); a table the program already holds, whole
//! ([`columns_csv`]), and any such table is read back by [`read_columns`].

use super::number::Numbers;

/// A column of a table: its name, its values, and whether it is kept in single precision.
#[derive(Clone, Copy, Debug)]
pub struct Column<'a> {
    /// The column's name (history.csv's).
    pub name: &'a str,
    /// One value per sample (a missing one is written `NaN`).
    pub values: &'a [f64],
    /// Written as the shortest text of the f32 nearest each value.
    pub single: bool,
}

/// Why a series table does not read: each error names the line (from 1, the header's is 1).
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SeriesError {
    /// No header, or one whose first column is not `t`.
    #[error("line 1: the first column is not t")]
    NoTime,
    /// A field that is not a number.
    #[error("line {line}: `{text}` is not a number (column {column})")]
    Number {
        /// The line, from 1.
        line: usize,
        /// The column's name.
        column: String,
        /// The field as written.
        text: String,
    },
    /// A line with another number of fields than the header.
    #[error("line {line}: {found} values, the header names {expected}")]
    Width {
        /// The line, from 1.
        line: usize,
        /// Fields on the line.
        found: usize,
        /// Columns of the header.
        expected: usize,
    },
}

/// The table as CSV text: the names, then one line per row of the longest column.
pub fn columns_csv(columns: &[Column]) -> String {
    let rows = columns.iter().map(|c| c.values.len()).max().unwrap_or(0);
    let names: Vec<&str> = columns.iter().map(|c| c.name).collect();
    let mut out = names.join(",");
    out.push('\n');
    let mut n = Numbers::new();
    for i in 0..rows {
        for (j, c) in columns.iter().enumerate() {
            if j > 0 {
                out.push(',');
            }
            let v = c.values.get(i).copied().unwrap_or(f64::NAN);
            if c.single {
                out.push_str(n.format_single(v as f32));
            } else {
                n.push(&mut out, v);
            }
        }
        out.push('\n');
    }
    out
}

/// The columns of a table written by [`columns_csv`] (or `history.csv`'s numeric ones, all of
/// them numbers): (name, values) in the file's order; the first is `t`.
pub fn read_columns(text: &str) -> Result<Vec<(String, Vec<f64>)>, SeriesError> {
    let mut lines = text.lines();
    let head: Vec<&str> = lines
        .next()
        .unwrap_or("")
        .split(',')
        .map(str::trim)
        .collect();
    if head.first() != Some(&"t") {
        return Err(SeriesError::NoTime);
    }
    let mut cols: Vec<(String, Vec<f64>)> =
        head.iter().map(|h| (h.to_string(), Vec::new())).collect();
    for (k, line) in lines.enumerate() {
        let line_no = k + 2;
        if line.trim().is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split(',').collect();
        if fields.len() != cols.len() {
            return Err(SeriesError::Width {
                line: line_no,
                found: fields.len(),
                expected: cols.len(),
            });
        }
        for ((name, values), f) in cols.iter_mut().zip(fields) {
            let v = f.trim().parse::<f64>().map_err(|_| SeriesError::Number {
                line: line_no,
                column: name.clone(),
                text: f.to_string(),
            })?;
            values.push(v);
        }
    }
    Ok(cols)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_reads_back_exact_and_single_columns() {
        let t = [0.0, 0.1, 1.0 / 3.0];
        let q = [1e-300, -2.5e-7, f64::NAN];
        let g = [0.012345678901234, 7.0, -1e9];
        let text = columns_csv(&[
            Column {
                name: "t",
                values: &t,
                single: false,
            },
            Column {
                name: "deck.theta",
                values: &q,
                single: false,
            },
            Column {
                name: "left_top.gap",
                values: &g,
                single: true,
            },
        ]);
        assert!(
            text.starts_with("t,deck.theta,left_top.gap\n0.0,1e-300,0.012345679\n"),
            "{text}"
        );
        let back = read_columns(&text).unwrap();
        assert_eq!(back[0].1, t);
        assert_eq!(back[1].1[..2], q[..2]);
        assert!(back[1].1[2].is_nan());
        // the single column reads back as the same f32s
        let single = |v: &[f64]| v.iter().map(|&x| x as f32).collect::<Vec<f32>>();
        assert_eq!(single(&back[2].1), single(&g));
        assert_ne!(back[2].1[0], g[0], "kept in single precision");
        assert_eq!(back[2].0, "left_top.gap");
    }

    #[test]
    fn a_bad_table_names_its_line_and_column() {
        assert_eq!(read_columns("x,y\n"), Err(SeriesError::NoTime));
        let e = read_columns("t,deck.theta\n0,1\n0.1,abc\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "line 3: `abc` is not a number (column deck.theta)"
        );
        let e = read_columns("t,deck.theta\n0\n").unwrap_err();
        assert_eq!(e.to_string(), "line 2: 1 values, the header names 2");
    }
}
