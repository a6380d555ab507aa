//! A sweep's rows as CSV ([`csv_text`]) and back ([`row_from_csv`], a resumed job's journal).

use super::{Row, RunFailure};
use crate::shard::csv_line;
use std::path::Path;
use std::sync::Arc;

/// The CSV columns of sweep rows: the swept keys, then what a row records (no wall time:
/// a sweep's CSV is the same for every run of it, so that its shards merge byte for byte).
pub fn csv_header(keys: &[String]) -> Vec<String> {
    let mut head = keys.to_vec();
    head.extend(
        [
            "peak_rotation",
            "residual_rotation",
            "peak_x",
            "peak_y",
            "impacts",
            "stick_time",
            "energy_closure_rel",
            "error",
        ]
        .map(String::from),
    );
    head
}

/// A row's CSV fields, in the order of [`csv_header`].
pub fn csv_fields(r: &Row) -> Vec<String> {
    let mut rec: Vec<String> = r.settings.iter().map(|(_, v)| v.clone()).collect();
    rec.extend([
        format!("{:.6e}", r.peak_rotation),
        format!("{:.6e}", r.residual_rotation),
        format!("{:.6e}", r.peak_x),
        format!("{:.6e}", r.peak_y),
        r.impacts.to_string(),
        format!("{:.4}", r.stick_time),
        format!("{:.3e}", r.energy_closure_rel),
        r.error.as_ref().map_or(String::new(), |e| e.to_string()),
    ]);
    rec
}

/// The CSV of a sweep over `keys`.
pub fn csv_text(keys: &[String], rows: &[Row]) -> String {
    let mut out = csv_line(&csv_header(keys));
    for r in rows {
        out += &csv_line(&csv_fields(r));
    }
    out
}

/// A sweep row read back from its CSV line ([`csv_fields`] of the swept `keys`): its
/// numbers as written (so written again they are the same text), no wall time.
pub fn row_from_csv(keys: &[String], line: &str) -> Result<Row, String> {
    let fields = crate::shard::csv_fields_of(line)?;
    let f: Vec<&str> = fields.iter().map(String::as_str).collect();
    let n = keys.len();
    if f.len() != n + 8 {
        return Err(format!(
            "{} fields, a sweep row of {n} keys has {}",
            f.len(),
            n + 8
        ));
    }
    let num = |k: usize| -> Result<f64, String> {
        (f[k].parse::<f64>()).map_err(|_| format!("field {}: '{}' is not a number", k + 1, f[k]))
    };
    Ok(Row {
        settings: (keys.iter().zip(&f))
            .map(|(k, v)| (k.clone(), v.to_string()))
            .collect(),
        peak_rotation: num(n)?,
        residual_rotation: num(n + 1)?,
        peak_x: num(n + 2)?,
        peak_y: num(n + 3)?,
        impacts: (f[n + 4].parse())
            .map_err(|_| format!("impacts: '{}' is not a whole number", f[n + 4]))?,
        stick_time: num(n + 5)?,
        energy_closure_rel: num(n + 6)?,
        wall_time: f64::NAN,
        error: (!f[n + 7].is_empty()).then(|| Arc::new(RunFailure::Recorded(f[n + 7].into()))),
    })
}

/// CSV of sweep rows ([`csv_text`]).
pub fn write_csv(keys: &[String], rows: &[Row], path: &Path) -> std::io::Result<()> {
    crate::output::files::write_atomic(path, csv_text(keys, rows))
}
