//! A sensitivity study's runs as rows (`sensitivity-runs.csv`) and what they say: per input
//! and quantity the values at its low, base and high value and the swing between them
//! (`sensitivity.csv`, the table). Everything here is computed from the rows alone, so the
//! outputs of a merged sharded study are those of the whole study, byte for byte.
//!
//! The runs CSV: `input,key,relative,low,high,side,case,status`, one column per quantity,
//! `steps,events`; the base runs first (input `base`), then each input's low runs and its high
//! runs, every group in case order. Numbers are their shortest round-trip text, counts whole
//! numbers, a value that does not apply an empty field.

use crate::csv_error::CsvError;
use crate::output::number::Numbers;
use crate::shard::csv_line;
use crate::suite::row::{COUNTS, Status};
use crate::suite::stats::median;

/// Which value of an input a run took.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    Base,
    Low,
    High,
}

impl Side {
    pub fn text(self) -> &'static str {
        match self {
            Side::Base => "base",
            Side::Low => "low",
            Side::High => "high",
        }
    }

    fn parse(s: &str) -> Option<Self> {
        [Side::Base, Side::Low, Side::High]
            .into_iter()
            .find(|x| x.text() == s)
    }
}

/// An input as its rows name it.
#[derive(Clone, Debug, PartialEq)]
pub struct InputInfo {
    pub name: String,
    /// The override paths it moves (several joined by `+`; `levels`: a suite's intensities).
    pub key: String,
    /// `low` and `high` are factors on the model's value.
    pub relative: bool,
    pub low: f64,
    pub high: f64,
}

/// One run of a study.
#[derive(Clone, Debug, PartialEq)]
pub struct RunRow {
    /// `None`: a base run.
    pub input: Option<InputInfo>,
    pub side: Side,
    /// The case's name (the `[[run]]`'s, or a suite's pair and level).
    pub case: String,
    pub status: Status,
    /// One per quantity of the study (a failed run's: up to its failure).
    pub values: Vec<Option<f64>>,
    pub steps: usize,
    pub events: usize,
    /// CPU seconds of the run's thread; `None` when read back from a CSV (not written there:
    /// it is not the same twice).
    pub cpu: Option<f64>,
}

/// The runs CSV's columns before the quantities.
pub(crate) const LEAD: [&str; 8] = [
    "input", "key", "relative", "low", "high", "side", "case", "status",
];

/// The runs CSV's header for `quantities`.
pub fn runs_header(quantities: &[String]) -> Vec<String> {
    let mut h: Vec<String> = LEAD.map(String::from).to_vec();
    h.extend(quantities.iter().cloned());
    h.extend(["steps".to_string(), "events".to_string()]);
    h
}

/// `x` as the CSVs write it: shortest round trip, a count as a whole number, `None` empty.
fn num(n: &mut Numbers, x: Option<f64>, count: bool) -> String {
    match x {
        None => String::new(),
        Some(x) if count && x.is_finite() && x.fract() == 0.0 => format!("{}", x as i64),
        Some(x) => n.format(x).to_string(),
    }
}

/// A row's fields in the order of [`runs_header`] (`quantities` tells the counts).
pub fn run_fields(quantities: &[String], r: &RunRow) -> Vec<String> {
    let mut n = Numbers::new();
    let mut f = match &r.input {
        Some(i) => vec![
            i.name.clone(),
            i.key.clone(),
            i.relative.to_string(),
            num(&mut n, Some(i.low), false),
            num(&mut n, Some(i.high), false),
        ],
        None => vec![
            "base".into(),
            String::new(),
            String::new(),
            String::new(),
            String::new(),
        ],
    };
    f.extend([r.side.text().into(), r.case.clone(), r.status.text()]);
    for (q, x) in quantities.iter().zip(&r.values) {
        f.push(num(&mut n, *x, COUNTS.contains(&q.as_str())));
    }
    f.extend([r.steps.to_string(), r.events.to_string()]);
    f
}

/// The runs CSV of `rows`.
pub fn runs_csv(quantities: &[String], rows: &[RunRow]) -> String {
    let mut out = csv_line(&runs_header(quantities));
    for r in rows {
        out += &csv_line(&run_fields(quantities, r));
    }
    out
}

/// The quantities and rows of a runs CSV ([`runs_csv`]'s inverse).
pub fn read_runs(text: &str) -> Result<(Vec<String>, Vec<RunRow>), CsvError> {
    let mut rd = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(text.as_bytes());
    let mut records = rd.records();
    let err = |line: usize, reason: String| CsvError::new("sensitivity runs", line, reason);
    let head = match records.next() {
        Some(h) => h.map_err(|e| err(1, e.to_string()))?,
        None => return Err(err(1, "empty".into())),
    };
    let head: Vec<String> = head.iter().map(String::from).collect();
    let nq = head.len().saturating_sub(LEAD.len() + 2);
    let quantities = head[LEAD.len().min(head.len())..].iter().take(nq).cloned();
    let quantities: Vec<String> = quantities.collect();
    if head != runs_header(&quantities) {
        return Err(err(1, "not the header of a sensitivity runs CSV".into()));
    }
    let mut rows = Vec::new();
    for (j, rec) in records.enumerate() {
        let line = j + 2;
        let rec = rec.map_err(|e| err(line, e.to_string()))?;
        let f: Vec<&str> = rec.iter().collect();
        if f.len() != head.len() {
            let why = format!("{} fields, the header has {}", f.len(), head.len());
            return Err(err(line, why));
        }
        rows.push(read_row(&f, nq).map_err(|why| err(line, why))?);
    }
    Ok((quantities, rows))
}

fn read_row(f: &[&str], nq: usize) -> Result<RunRow, String> {
    let opt = |s: &str, what: &str| -> Result<Option<f64>, String> {
        if s.is_empty() {
            return Ok(None);
        }
        (s.parse::<f64>().map(Some)).map_err(|_| format!("{what}: '{s}' is not a number"))
    };
    let count = |s: &str, what: &str| {
        (s.parse::<usize>()).map_err(|_| format!("{what}: '{s}' is not a count"))
    };
    let side = Side::parse(f[5]).ok_or_else(|| format!("side '{}'", f[5]))?;
    let input = if side == Side::Base {
        None
    } else {
        Some(InputInfo {
            name: f[0].into(),
            key: f[1].into(),
            relative: f[2] == "true",
            low: opt(f[3], "low")?.ok_or("no low value")?,
            high: opt(f[4], "high")?.ok_or("no high value")?,
        })
    };
    let status = Status::parse(f[7]).ok_or_else(|| format!("status '{}'", f[7]))?;
    let at = LEAD.len();
    let values = (0..nq)
        .map(|k| opt(f[at + k], "a quantity"))
        .collect::<Result<_, _>>()?;
    Ok(RunRow {
        input,
        side,
        case: f[6].into(),
        status,
        values,
        steps: count(f[at + nq], "steps")?,
        events: count(f[at + nq + 1], "events")?,
        cpu: None,
    })
}

/// One quantity of one input: its medians at the low, base and high value over the cases
/// whose three runs all finished with a value.
#[derive(Clone, Debug, PartialEq)]
pub struct Swing {
    pub quantity: String,
    pub low: Option<f64>,
    pub base: Option<f64>,
    pub high: Option<f64>,
    /// Cases the medians are taken over.
    pub cases: usize,
    /// Cases left out: one of their three runs failed, was refused or is missing.
    pub failed: usize,
}

impl Swing {
    /// value(high) − value(low).
    pub fn swing(&self) -> Option<f64> {
        Some(self.high? - self.low?)
    }

    /// The swing over |value(base)| (none at a base of 0).
    pub fn relative(&self) -> Option<f64> {
        let b = self.base?.abs();
        (b > 0.0).then(|| self.swing().map(|s| s / b)).flatten()
    }
}

/// An input and its swing in each quantity.
#[derive(Clone, Debug, PartialEq)]
pub struct InputSwings {
    pub input: InputInfo,
    /// In the order of [`Sensitivity::quantities`].
    pub swings: Vec<Swing>,
}

/// What a sensitivity study found.
#[derive(Clone, Debug, PartialEq)]
pub struct Sensitivity {
    /// The quantities that apply (a value in some base run), the first the sort key.
    pub quantities: Vec<String>,
    /// The median of each quantity over the finished base runs.
    pub base: Vec<Option<f64>>,
    /// Widest first: by |swing| of the first quantity (inputs without one last).
    pub inputs: Vec<InputSwings>,
    /// Every run, in run order.
    pub rows: Vec<RunRow>,
}

/// The rows of input `name` on `side`, in case order.
fn side_rows<'a>(rows: &'a [RunRow], name: &str, side: Side) -> Vec<&'a RunRow> {
    (rows.iter())
        .filter(|r| r.side == side && r.input.as_ref().is_some_and(|i| i.name == name))
        .collect()
}

/// The swings of every input in `rows` (a runs CSV's, whose columns are `quantities`).
pub fn summarize(quantities: &[String], rows: Vec<RunRow>) -> Sensitivity {
    let base: Vec<&RunRow> = rows.iter().filter(|r| r.side == Side::Base).collect();
    let applies: Vec<usize> = (0..quantities.len())
        .filter(|&q| {
            base.iter()
                .any(|r| r.values.get(q).copied().flatten().is_some())
        })
        .collect();
    let mut infos: Vec<InputInfo> = Vec::new();
    for i in rows.iter().filter_map(|r| r.input.as_ref()) {
        if !infos.iter().any(|o| o.name == i.name) {
            infos.push(i.clone());
        }
    }
    let mut inputs: Vec<InputSwings> = Vec::new();
    for info in infos {
        let low = side_rows(&rows, &info.name, Side::Low);
        let high = side_rows(&rows, &info.name, Side::High);
        let swings = (applies.iter())
            .map(|&q| {
                let (mut l, mut b, mut h, mut failed) = (vec![], vec![], vec![], 0);
                for k in 0..base.len() {
                    let runs = [base.get(k), low.get(k), high.get(k)]
                        .map(|r| r.copied().filter(|r| r.status == Status::Finished));
                    let [Some(rb), Some(rl), Some(rh)] = runs else {
                        failed += 1;
                        continue;
                    };
                    if let (Some(vb), Some(vl), Some(vh)) =
                        (rb.values[q], rl.values[q], rh.values[q])
                    {
                        b.push(vb);
                        l.push(vl);
                        h.push(vh);
                    }
                }
                Swing {
                    quantity: quantities[q].clone(),
                    low: median(&l),
                    base: median(&b),
                    high: median(&h),
                    cases: b.len(),
                    failed,
                }
            })
            .collect();
        inputs.push(InputSwings {
            input: info,
            swings,
        });
    }
    sort_by_swing(&mut inputs, 0);
    let base = (applies.iter())
        .map(|&q| {
            let v: Vec<f64> = (base.iter())
                .filter(|r| r.status == Status::Finished)
                .filter_map(|r| r.values[q])
                .collect();
            median(&v)
        })
        .collect();
    Sensitivity {
        quantities: applies.iter().map(|&q| quantities[q].clone()).collect(),
        base,
        inputs,
        rows,
    }
}

/// Widest first by |swing| of quantity `q` (stable; inputs without a swing last).
pub fn sort_by_swing(inputs: &mut [InputSwings], q: usize) {
    let key = |s: &InputSwings| s.swings.get(q).and_then(Swing::swing).map(f64::abs);
    inputs.sort_by(|a, b| match (key(a), key(b)) {
        (Some(x), Some(y)) => y.total_cmp(&x),
        (Some(_), None) => std::cmp::Ordering::Less,
        (None, Some(_)) => std::cmp::Ordering::Greater,
        (None, None) => std::cmp::Ordering::Equal,
    });
}

/// The columns of `sensitivity.csv`.
pub(crate) const SUMMARY_HEADER: [&str; 13] = [
    "input",
    "key",
    "relative",
    "low",
    "high",
    "quantity",
    "value_low",
    "value_base",
    "value_high",
    "swing",
    "relative_swing",
    "cases",
    "failed",
];

impl Sensitivity {
    /// `sensitivity.csv`: one row per input (widest first) and quantity.
    pub fn csv(&self) -> String {
        let mut n = Numbers::new();
        let mut out = csv_line(&SUMMARY_HEADER);
        for s in &self.inputs {
            let i = &s.input;
            for w in &s.swings {
                let count = COUNTS.contains(&w.quantity.as_str());
                out += &csv_line(&[
                    i.name.clone(),
                    i.key.clone(),
                    i.relative.to_string(),
                    num(&mut n, Some(i.low), false),
                    num(&mut n, Some(i.high), false),
                    w.quantity.clone(),
                    num(&mut n, w.low, count),
                    num(&mut n, w.base, count),
                    num(&mut n, w.high, count),
                    num(&mut n, w.swing(), count),
                    num(&mut n, w.relative(), false),
                    w.cases.to_string(),
                    w.failed.to_string(),
                ]);
            }
        }
        out
    }

    /// The runs that did not finish.
    pub fn failed(&self) -> Vec<&RunRow> {
        (self.rows.iter())
            .filter(|r| r.status != Status::Finished)
            .collect()
    }

    /// CPU seconds of the runs made here (runs read back from a CSV count 0).
    pub fn cpu(&self) -> f64 {
        self.rows.iter().filter_map(|r| r.cpu).sum()
    }

    /// The number of cases (base runs).
    pub fn cases(&self) -> usize {
        self.rows.iter().filter(|r| r.side == Side::Base).count()
    }
}

/// An input's range as text: `0.3..0.7`, or `x0.5..x1.5` for factors.
pub fn range_text(i: &InputInfo) -> String {
    let x = if i.relative { "x" } else { "" };
    format!("{x}{}..{x}{}", i.low, i.high)
}

/// The table of the swings: an input a line (widest first), its range, then per quantity the
/// swing and the relative swing; the base medians above, the failed runs below.
pub fn table(s: &Sensitivity) -> String {
    let name_w = (s.inputs.iter().map(|i| i.input.name.chars().count()))
        .chain([5])
        .max()
        .unwrap_or(5);
    let range_w = (s.inputs.iter().map(|i| range_text(&i.input).len()))
        .chain([5])
        .max()
        .unwrap_or(5);
    let col_w = |q: &str| q.len().max(20);
    let mut out = format!("{:<name_w$}  {:<range_w$}", "input", "range");
    for q in &s.quantities {
        out += &format!("  {:>w$}", q, w = col_w(q));
    }
    out += &format!("\n{:<name_w$}  {:<range_w$}", "base", "median");
    for (q, b) in s.quantities.iter().zip(&s.base) {
        let v = match b {
            Some(b) if COUNTS.contains(&q.as_str()) => format!("{b}"),
            Some(b) => format!("{b:.4e}"),
            None => "-".into(),
        };
        out += &format!("  {v:>w$}", w = col_w(q));
    }
    out += "\n";
    for i in &s.inputs {
        let r = range_text(&i.input);
        out += &format!("{:<name_w$}  {r:<range_w$}", i.input.name);
        for (q, w) in s.quantities.iter().zip(&i.swings) {
            let d = match w.swing() {
                Some(d) if COUNTS.contains(&q.as_str()) => format!("{d:+}"),
                Some(d) => format!("{d:+.3e}"),
                None => "-".into(),
            };
            let v = match w.relative() {
                Some(rel) => format!("{d} ({:+.1} %)", 100.0 * rel),
                None => d,
            };
            out += &format!("  {v:>w$}", w = col_w(q));
        }
        out += "\n";
    }
    let failed = s.failed();
    if !failed.is_empty() {
        out += &format!(
            "{} of {} runs did not finish (left out of the medians):\n",
            failed.len(),
            s.rows.len()
        );
        for r in failed.iter().take(10) {
            let name = r.input.as_ref().map_or("base", |i| i.name.as_str());
            let side = r.side.text();
            out += &format!("  {name} {side} {}: {}\n", r.case, r.status.text());
        }
        if failed.len() > 10 {
            out += &format!(
                "  … and {} more (sensitivity-runs.csv)\n",
                failed.len() - 10
            );
        }
    }
    out
}
