//! A model's ladder as text: the table of variants (cost, error per quantity), the cheapest
//! variant within the tolerance per quantity, the CSVs, and the chart of cost against error.

use super::adequacy::{Adequacy, Outcome};
use crate::output::number::Numbers;
use crate::plot::{Axis, Chart, Marker, RefLine, Series};
use crate::shard::csv_line;
use crate::suite::row::METRICS;

/// A quantity's short heading in the table.
pub fn short(q: &str) -> &'static str {
    match q {
        "peak_rotation" => "rotation",
        "residual_rotation" => "residual",
        "peak_x" => "x",
        "peak_y" => "y",
        "min_seat_margin" => "seat",
        "key_failures" => "keys",
        "max_drift_ratio" => "drift",
        "impacts" => "impacts",
        "energy_impacts" => "E_impact",
        "energy_friction" => "E_fric",
        "energy_columns" => "E_cols",
        _ => "?",
    }
}

/// An error as a percentage for the table: `0`, `0.31 %`, `>999 %`, `failed`.
pub fn percent(e: Option<f64>) -> String {
    match e {
        None => "–".into(),
        Some(e) if e.is_infinite() => "failed".into(),
        Some(0.0) => "0".into(),
        Some(e) if e * 100.0 >= 999.5 => ">999 %".into(),
        Some(e) if e * 100.0 >= 9.95 => format!("{:.0} %", e * 100.0),
        Some(e) if e * 100.0 >= 0.995 => format!("{:.1} %", e * 100.0),
        Some(e) if e * 100.0 >= 0.01 => format!("{:.2} %", e * 100.0),
        Some(e) => format!("{:.1e} %", e * 100.0),
    }
}

/// How many times faster than the full model (CPU time).
fn speedup(s: &Adequacy, o: &Outcome) -> f64 {
    s.full.cost().cpu / o.cost().cpu
}

/// The table of the full model and every variant, then the cheapest within the tolerance.
pub fn table(s: &Adequacy) -> String {
    let name_w = (s.variants.iter().map(|o| o.variant.name.len()))
        .chain([4])
        .max()
        .unwrap_or(4);
    let mut out = format!(
        "{} runs ({}), tolerance {} %; error = largest over the runs of |variant − full| / |full|\n\n",
        s.cases.len(),
        s.cases.join(", "),
        100.0 * s.tolerance
    );
    out += &format!(
        "{:<name_w$}  {:>8} {:>8} {:>7} {:>6}",
        "variant", "CPU s", "steps", "events", "faster"
    );
    for q in &s.quantities {
        out += &format!(" {:>9}", short(q));
    }
    out.push('\n');
    let full = s.full.cost();
    out += &format!(
        "{:<name_w$}  {:>8.3} {:>8} {:>7} {:>6}",
        "full", full.cpu, full.steps, full.events, "1.0×"
    );
    for _ in &s.quantities {
        out += &format!(" {:>9}", "");
    }
    out.push('\n');
    for (v, o) in s.variants.iter().enumerate() {
        let c = o.cost();
        if let Some(why) = &o.refused {
            out += &format!("{:<name_w$}  refused: {why}\n", o.variant.name);
            continue;
        }
        out += &format!(
            "{:<name_w$}  {:>8.3} {:>8} {:>7} {:>6}",
            o.variant.name,
            c.cpu,
            c.steps,
            c.events,
            format!("{:.1}×", speedup(s, o))
        );
        for q in &s.quantities {
            out += &format!(" {:>9}", percent(s.error(v, q)));
        }
        out.push('\n');
    }
    out += &format!("\ncheapest within {} %:\n", 100.0 * s.tolerance);
    let qs: Vec<Option<&str>> = (s.quantities.iter().map(|q| Some(q.as_str())))
        .chain([None])
        .collect();
    for q in qs {
        let what = q.unwrap_or("every quantity above");
        let line = match s.cheapest(q) {
            Some(v) => {
                let o = &s.variants[v];
                let e = q.map_or_else(|| s.worst(v), |q| s.error(v, q).unwrap_or(0.0));
                format!(
                    "{} ({:.1}× faster, error {})",
                    o.variant.name,
                    speedup(s, o),
                    percent(Some(e))
                )
            }
            None => "the full model (no variant is within the tolerance and cheaper)".into(),
        };
        out += &format!("  {what:<22} {line}\n");
    }
    out
}

/// `adequacy.csv`: a row per variant: name, simplifications, status, cost, speed-up and the
/// error of each quantity (relative; empty where the quantity does not apply).
pub fn variants_csv(s: &Adequacy) -> String {
    let mut n = Numbers::new();
    let mut head = vec![
        "variant".to_string(),
        "status".into(),
        "cpu_s".into(),
        "steps".into(),
        "events".into(),
        "speedup".into(),
    ];
    head.extend(s.quantities.iter().map(|q| format!("error_{q}")));
    let mut out = csv_line(&head);
    let full = std::iter::once((None, &s.full));
    for (v, o) in full.chain(s.variants.iter().enumerate().map(|(v, o)| (Some(v), o))) {
        let c = o.cost();
        let status = match &o.refused {
            Some(why) => format!("refused: {why}"),
            None => (o.runs.iter().find(|r| r.status.text() != "finished"))
                .map_or("finished".into(), |r| r.status.text()),
        };
        let mut f = vec![
            o.variant.name.clone(),
            status,
            n.format(c.cpu).to_string(),
            c.steps.to_string(),
            c.events.to_string(),
            n.format(speedup(s, o)).to_string(),
        ];
        for q in &s.quantities {
            let e = v.map_or(Some(0.0), |v| s.error(v, q));
            f.push(e.map_or(String::new(), |e| n.format(e).to_string()));
        }
        out += &csv_line(&f);
    }
    out
}

/// `adequacy-runs.csv`: a row per variant and run: its status, cost and every quantity.
pub fn runs_csv(s: &Adequacy) -> String {
    let mut n = Numbers::new();
    let mut head: Vec<String> = ["variant", "run", "status", "cpu_s", "steps", "events"]
        .map(String::from)
        .to_vec();
    head.extend(METRICS.iter().map(|m| m.to_string()));
    let mut out = csv_line(&head);
    for o in std::iter::once(&s.full).chain(&s.variants) {
        for (r, case) in o.runs.iter().zip(&s.cases) {
            let mut f = vec![
                o.variant.name.clone(),
                case.clone(),
                r.status.text(),
                n.format(r.cpu).to_string(),
                r.steps.to_string(),
                r.events.to_string(),
            ];
            for m in r.metrics {
                f.push(m.map_or(String::new(), |x| n.format(x).to_string()));
            }
            out += &csv_line(&f);
        }
    }
    out
}

/// The least error drawn on the chart's log axis (an error of exactly 0 is drawn there).
pub(crate) const CHART_FLOOR: f64 = 1e-9;

/// CPU time against error: a point per variant at its error in `q`, or with none its largest
/// error over the quantities (`CHART_FLOOR` for 0), the tolerance and the full model's time as
/// lines.
pub fn chart(s: &Adequacy, q: Option<&str>) -> Chart {
    let what = match q {
        Some(q) => format!("error in {q} (relative)"),
        None => "largest error over the quantities (relative)".into(),
    };
    let mut c = Chart::new(
        "Model adequacy: cost against error",
        Axis::log("CPU time of the runs", "s"),
        Axis::log(&what, ""),
    );
    let tol = format!("{} %", 100.0 * s.tolerance);
    c.lines.push(RefLine::horizontal(s.tolerance, &tol, 7));
    c.lines
        .push(RefLine::vertical(s.full.cost().cpu, "full model", 7));
    let markers = [
        Marker::Circle,
        Marker::Square,
        Marker::Triangle,
        Marker::Cross,
    ];
    let glyphs: Vec<char> = ('a'..='z').collect();
    for (v, o) in s.variants.iter().enumerate() {
        let cpu = o.cost().cpu;
        let e = match q {
            Some(q) => s.error(v, q).unwrap_or(f64::NAN),
            None => s.worst(v),
        };
        let positive = cpu.partial_cmp(&0.0) == Some(std::cmp::Ordering::Greater);
        if o.refused.is_some() || !positive || !e.is_finite() {
            continue;
        }
        c.series.push(
            Series::points(&o.variant.name, vec![(cpu, e.max(CHART_FLOOR))])
                .marker(markers[v % markers.len()])
                .color(v)
                .glyph(glyphs[v % glyphs.len()]),
        );
    }
    c
}
