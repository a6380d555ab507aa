//! One run of a suite and its CSV line: `pair,longitudinal,transverse,measure,level,scale,`
//! one column per swept key, then `status` and the [`METRICS`]. Numbers are their shortest
//! round-trip text (`output::number`), counts whole numbers, a value that does not apply
//! (no seats, no keys, no columns) an empty field; nothing depends on the machine or the
//! clock, so that shards merge byte for byte.

use crate::csv_error::CsvError;
use crate::output::number::Numbers;
use crate::shard::csv_line;

/// The quantities of a run, in CSV order.
pub const METRICS: [&str; 11] = [
    "peak_rotation",
    "residual_rotation",
    "peak_x",
    "peak_y",
    "min_seat_margin",
    "key_failures",
    "max_drift_ratio",
    "impacts",
    "energy_impacts",
    "energy_friction",
    "energy_columns",
];

/// The metrics that count events (written as whole numbers).
pub(crate) const COUNTS: [&str; 2] = ["key_failures", "impacts"];

/// The columns before the swept keys.
pub(crate) const LEAD: [&str; 6] = [
    "pair",
    "longitudinal",
    "transverse",
    "measure",
    "level",
    "scale",
];

/// How a run of a suite ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Status {
    Finished,
    /// The solver stopped: its error's kind (`SolverError::kind`) and text.
    Failed {
        kind: String,
        reason: String,
    },
    /// The run's model or records were refused before it started.
    Refused(String),
}

impl Status {
    /// How a run ended: finished, or failed with its error's kind and text (a cancelled run
    /// as the kind `Cancelled` at its time).
    pub fn of(stop: &crate::run::Stop) -> Self {
        use crate::run::Stop;
        match stop {
            Stop::Finished => Status::Finished,
            Stop::Failed(e) => Status::Failed {
                kind: e.kind().into(),
                reason: e.to_string(),
            },
            Stop::Cancelled { t } => Status::Failed {
                kind: "Cancelled".into(),
                reason: format!("t = {t:.9} s: cancelled"),
            },
        }
    }

    /// `finished`, `failed: KIND: reason` or `refused: reason`.
    pub fn text(&self) -> String {
        match self {
            Status::Finished => "finished".into(),
            Status::Failed { kind, reason } => format!("failed: {kind}: {reason}"),
            Status::Refused(r) => format!("refused: {r}"),
        }
    }

    /// [`Status::text`]'s inverse.
    pub fn parse(s: &str) -> Option<Self> {
        if s == "finished" {
            return Some(Status::Finished);
        }
        if let Some(r) = s.strip_prefix("refused: ") {
            return Some(Status::Refused(r.into()));
        }
        let (kind, reason) = s.strip_prefix("failed: ")?.split_once(": ")?;
        Some(Status::Failed {
            kind: kind.into(),
            reason: reason.into(),
        })
    }
}

/// One run of a suite.
#[derive(Clone, Debug, PartialEq)]
pub struct SuiteRow {
    pub pair: String,
    /// The record files as the suite names them.
    pub longitudinal: String,
    pub transverse: String,
    /// `pga` or `sa(Ts,ζ%)` (`intensity::Measure::label`).
    pub measure: String,
    /// The pair's intensity after scaling, g.
    pub level: f64,
    /// The factor on both components (none when the pair's intensity could not be found).
    pub scale: Option<f64>,
    /// The swept keys and their values.
    pub settings: Vec<(String, String)>,
    pub status: Status,
    /// In the order of [`METRICS`]; a failed run's values are those up to its failure.
    pub metrics: [Option<f64>; 11],
}

/// The CSV header of a suite sweeping `keys`.
pub fn csv_header(keys: &[String]) -> Vec<String> {
    let mut h: Vec<String> = LEAD.map(String::from).to_vec();
    h.extend(keys.iter().cloned());
    h.push("status".into());
    h.extend(METRICS.map(String::from));
    h
}

/// A row's CSV fields, in the order of [`csv_header`].
pub fn csv_fields(r: &SuiteRow) -> Vec<String> {
    let mut n = Numbers::new();
    let mut num = |x: Option<f64>, count: bool| match x {
        None => String::new(),
        Some(x) if count && x.is_finite() && x.fract() == 0.0 => format!("{}", x as i64),
        Some(x) => n.format(x).to_string(),
    };
    let mut f = vec![
        r.pair.clone(),
        r.longitudinal.clone(),
        r.transverse.clone(),
        r.measure.clone(),
        num(Some(r.level), false),
        num(r.scale, false),
    ];
    f.extend(r.settings.iter().map(|(_, v)| v.clone()));
    f.push(r.status.text());
    for (name, x) in METRICS.iter().zip(r.metrics) {
        f.push(num(x, COUNTS.contains(name)));
    }
    f
}

/// The CSV of suite rows over `keys`.
pub fn csv_text(keys: &[String], rows: &[SuiteRow]) -> String {
    let mut out = csv_line(&csv_header(keys));
    for r in rows {
        out += &csv_line(&csv_fields(r));
    }
    out
}

/// The swept keys and rows of a suite CSV ([`csv_text`]'s inverse).
pub fn read_csv(text: &str) -> Result<(Vec<String>, Vec<SuiteRow>), CsvError> {
    let mut rd = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(text.as_bytes());
    let mut records = rd.records();
    let err = |line: usize, reason: String| CsvError::new("suite", line, reason);
    let head = match records.next() {
        Some(h) => h.map_err(|e| err(1, e.to_string()))?,
        None => return Err(err(1, "empty".into())),
    };
    let head: Vec<String> = head.iter().map(String::from).collect();
    let nk = head.len().saturating_sub(LEAD.len() + 1 + METRICS.len());
    let keys = head
        .get(LEAD.len()..LEAD.len() + nk)
        .unwrap_or(&[])
        .to_vec();
    if head != csv_header(&keys) {
        return Err(err(1, "not the header of a suite CSV".into()));
    }
    let mut rows = Vec::new();
    for (j, rec) in records.enumerate() {
        let line = j + 2;
        let rec = rec.map_err(|e| err(line, e.to_string()))?;
        let f: Vec<&str> = rec.iter().collect();
        if f.len() != head.len() {
            return Err(err(
                line,
                format!("{} fields, the header has {}", f.len(), head.len()),
            ));
        }
        let num = |s: &str, what: &str| -> Result<Option<f64>, CsvError> {
            if s.is_empty() {
                return Ok(None);
            }
            (s.parse::<f64>().map(Some))
                .map_err(|_| err(line, format!("{what}: '{s}' is not a number")))
        };
        let level = num(f[4], "level")?.ok_or_else(|| err(line, "no level".into()))?;
        let at = LEAD.len() + nk;
        let status =
            Status::parse(f[at]).ok_or_else(|| err(line, format!("status '{}'", f[at])))?;
        let mut metrics = [None; 11];
        for (k, m) in METRICS.iter().enumerate() {
            metrics[k] = num(f[at + 1 + k], m)?;
        }
        rows.push(SuiteRow {
            pair: f[0].into(),
            longitudinal: f[1].into(),
            transverse: f[2].into(),
            measure: f[3].into(),
            level,
            scale: num(f[5], "scale")?,
            settings: (keys.iter().zip(&f[LEAD.len()..at]))
                .map(|(k, v)| (k.clone(), v.to_string()))
                .collect(),
            status,
            metrics,
        });
    }
    Ok((keys, rows))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(status: Status) -> SuiteRow {
        SuiteRow {
            pair: "KOBE_SHI".into(),
            longitudinal: "KOBE_SHI000.AT2".into(),
            transverse: "KOBE_SHI090.AT2".into(),
            measure: "sa(0.25s,5%)".into(),
            level: 0.30000000000000004,
            scale: Some(1.0 / 3.0),
            settings: vec![("contacts.mu".into(), "0.5".into())],
            status,
            metrics: [
                Some(1e-3),
                Some(2e-5),
                Some(0.1),
                Some(-0.0),
                None,
                Some(2.0),
                Some(0.0123),
                Some(14.0),
                Some(1.5),
                Some(0.0),
                Some(f64::NAN),
            ],
        }
    }

    #[test]
    fn rows_read_back_as_written() {
        let keys = vec!["contacts.mu".to_string()];
        let failed = Status::Failed {
            kind: "Unseated".into(),
            reason: "t = 1.5 s: the deck lost its seat at 'left_top', its gap \"x\"".into(),
        };
        let rows = vec![
            row(Status::Finished),
            row(failed),
            row(Status::Refused("a, b".into())),
        ];
        let text = csv_text(&keys, &rows);
        let mut lines = text.lines();
        assert_eq!(
            lines.next().unwrap(),
            "pair,longitudinal,transverse,measure,level,scale,contacts.mu,status,peak_rotation,\
             residual_rotation,peak_x,peak_y,min_seat_margin,key_failures,max_drift_ratio,\
             impacts,energy_impacts,energy_friction,energy_columns"
        );
        assert_eq!(
            lines.next().unwrap(),
            "KOBE_SHI,KOBE_SHI000.AT2,KOBE_SHI090.AT2,\"sa(0.25s,5%)\",0.30000000000000004,\
             0.3333333333333333,0.5,finished,0.001,0.00002,0.1,-0.0,,2,0.0123,14,1.5,0.0,NaN"
        );
        let (k, back) = read_csv(&text).unwrap();
        assert_eq!(k, keys);
        assert_eq!(back.len(), 3);
        for (a, b) in rows.iter().zip(&back) {
            assert_eq!(csv_fields(a), csv_fields(b));
            assert_eq!(a.status, b.status);
        }
        let e = read_csv("a,b\n").unwrap_err().to_string();
        assert_eq!(e, "suite CSV line 1: not the header of a suite CSV");
    }
}
