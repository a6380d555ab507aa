//! The statistics of a suite per intensity level and parameter point: runs, finished, failed
//! by reason, refused, and per metric the median over the finished runs (zeros included) and
//! the lognormal dispersion β = the sample standard deviation (n − 1) of ln x over the
//! positive finished values, with their number (`positive`): a zero (no impact, no failed
//! key, no friction) has no logarithm, so β describes the runs where the quantity occurred;
//! with fewer than 2 positive values β is absent.

use super::row::{METRICS, Status, SuiteRow};
use crate::output::number::Numbers;
use crate::shard::csv_line;
use serde::Serialize;
use std::collections::HashMap;

/// Median and dispersion of one metric at one level.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MetricStats {
    pub median: Option<f64>,
    pub beta: Option<f64>,
    pub positive: usize,
}

/// The statistics of the runs at one level and parameter point.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LevelStats {
    pub measure: String,
    pub level: f64,
    #[serde(serialize_with = "as_map")]
    pub settings: Vec<(String, String)>,
    pub count: usize,
    pub finished: usize,
    pub failed: usize,
    pub refused: usize,
    /// Failed runs by the solver error's kind, in name order.
    #[serde(serialize_with = "as_map")]
    pub failures: Vec<(String, usize)>,
    /// In the order of [`METRICS`].
    #[serde(serialize_with = "as_map")]
    pub metrics: Vec<(String, MetricStats)>,
}

/// (name, value) pairs as a JSON object, in their order.
fn as_map<S: serde::Serializer, V: Serialize>(v: &[(String, V)], s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeMap;
    let mut m = s.serialize_map(Some(v.len()))?;
    for (k, x) in v {
        m.serialize_entry(k, x)?;
    }
    m.end()
}

/// The median of `v` (the mean of the two middle values of an even count).
pub fn median(v: &[f64]) -> Option<f64> {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(s[n / 2]),
        _ => Some(0.5 * (s[n / 2 - 1] + s[n / 2])),
    }
}

/// β: the sample standard deviation of ln x over the positive values, and their number.
pub(crate) fn dispersion(v: &[f64]) -> (Option<f64>, usize) {
    let logs: Vec<f64> = v.iter().filter(|x| **x > 0.0).map(|x| x.ln()).collect();
    let n = logs.len();
    if n < 2 {
        return (None, n);
    }
    let mean = logs.iter().sum::<f64>() / n as f64;
    let ss: f64 = logs.iter().map(|l| (l - mean) * (l - mean)).sum();
    (Some((ss / (n - 1) as f64).sqrt()), n)
}

/// A swept key and its value.
type Setting = (String, String);

/// One [`LevelStats`] per level and parameter point, in the order they first appear.
pub fn level_stats(rows: &[SuiteRow]) -> Vec<LevelStats> {
    let mut groups: Vec<Vec<&SuiteRow>> = Vec::new();
    let mut index: HashMap<(u64, &[Setting]), usize> = HashMap::new();
    for r in rows {
        let key = (r.level.to_bits(), r.settings.as_slice());
        let g = *index.entry(key).or_insert_with(|| {
            groups.push(Vec::new());
            groups.len() - 1
        });
        groups[g].push(r);
    }
    groups.iter().map(|g| group_stats(g)).collect()
}

fn group_stats(g: &[&SuiteRow]) -> LevelStats {
    let finished: Vec<&&SuiteRow> = g.iter().filter(|r| r.status == Status::Finished).collect();
    let mut failures: Vec<(String, usize)> = Vec::new();
    for r in g {
        if let Status::Failed { kind, .. } = &r.status {
            match failures.iter_mut().find(|(k, _)| k == kind) {
                Some(f) => f.1 += 1,
                None => failures.push((kind.clone(), 1)),
            }
        }
    }
    failures.sort();
    let metrics = (METRICS.iter().enumerate())
        .map(|(k, name)| {
            let v: Vec<f64> = (finished.iter())
                .filter_map(|r| r.metrics[k])
                .filter(|x| x.is_finite())
                .collect();
            let (beta, positive) = dispersion(&v);
            let median = median(&v);
            (
                name.to_string(),
                MetricStats {
                    median,
                    beta,
                    positive,
                },
            )
        })
        .collect();
    LevelStats {
        measure: g[0].measure.clone(),
        level: g[0].level,
        settings: g[0].settings.clone(),
        count: g.len(),
        finished: finished.len(),
        failed: failures.iter().map(|f| f.1).sum(),
        refused: g
            .iter()
            .filter(|r| matches!(r.status, Status::Refused(_)))
            .count(),
        failures,
        metrics,
    }
}

/// The statistics as CSV: `measure,level,` the swept keys, `count,finished,failed,refused,
/// failures` (`Kind=n;…`), then `M_median,M_beta,M_positive` per metric M.
pub fn stats_csv(keys: &[String], stats: &[LevelStats]) -> String {
    let mut head: Vec<String> = vec!["measure".into(), "level".into()];
    head.extend(keys.iter().cloned());
    head.extend(["count", "finished", "failed", "refused", "failures"].map(String::from));
    for m in METRICS {
        head.extend([
            format!("{m}_median"),
            format!("{m}_beta"),
            format!("{m}_positive"),
        ]);
    }
    let mut out = csv_line(&head);
    let mut n = Numbers::new();
    let mut num = |x: Option<f64>| x.map_or(String::new(), |x| n.format(x).to_string());
    for s in stats {
        let mut f = vec![s.measure.clone(), num(Some(s.level))];
        f.extend(s.settings.iter().map(|(_, v)| v.clone()));
        let failures: Vec<String> = s.failures.iter().map(|(k, c)| format!("{k}={c}")).collect();
        f.extend([s.count, s.finished, s.failed, s.refused].map(|c| c.to_string()));
        f.push(failures.join(";"));
        for (_, m) in &s.metrics {
            f.extend([num(m.median), num(m.beta), m.positive.to_string()]);
        }
        out += &csv_line(&f);
    }
    out
}

/// The statistics as JSON (`null` where a value is absent).
pub fn stats_json(stats: &[LevelStats]) -> String {
    serde_json::to_string_pretty(stats).unwrap_or_default() + "\n"
}

/// A short table: per level and point the runs, how they ended, and the medians (β) of the
/// peak rotation, the column drift ratio and the impacts.
pub fn stats_table(stats: &[LevelStats]) -> String {
    let mut out = String::new();
    let keys: Vec<&str> = (stats.first().into_iter())
        .flat_map(|s| s.settings.iter().map(|(k, _)| k.as_str()))
        .collect();
    out += &format!("{:>8}", "level");
    for k in &keys {
        out += &format!(" {k:>14.14}");
    }
    out += &format!(
        " {:>5} {:>5} {:>5} {:>5} {:>22} {:>22} {:>9}\n",
        "runs", "done", "fail", "refd", "peak θ median (β)", "drift median (β)", "impacts"
    );
    let cell = |m: &MetricStats| match (m.median, m.beta) {
        (Some(x), Some(b)) => format!("{x:.4e} ({b:.3})"),
        (Some(x), None) => format!("{x:.4e} (–)"),
        _ => "–".into(),
    };
    for s in stats {
        out += &format!("{:>8}", format!("{}", s.level));
        for (_, v) in &s.settings {
            out += &format!(" {v:>14.14}");
        }
        let m = |name: &str| &s.metrics[METRICS.iter().position(|x| *x == name).unwrap_or(0)].1;
        let impacts = m("impacts").median.map_or("–".into(), |x| format!("{x}"));
        out += &format!(
            " {:>5} {:>5} {:>5} {:>5} {:>22} {:>22} {:>9}\n",
            s.count,
            s.finished,
            s.failed,
            s.refused,
            cell(m("peak_rotation")),
            cell(m("max_drift_ratio")),
            impacts
        );
    }
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A run at `level` with `contacts.mu` = `mu`, its peak rotation and impacts.
    pub(crate) fn row(level: f64, mu: &str, status: Status, peak: f64, impacts: f64) -> SuiteRow {
        let mut metrics = [None; 11];
        metrics[0] = Some(peak);
        metrics[7] = Some(impacts);
        SuiteRow {
            pair: "p".into(),
            longitudinal: "l".into(),
            transverse: "t".into(),
            measure: "pga".into(),
            level,
            scale: Some(1.0),
            settings: vec![("contacts.mu".into(), mu.into())],
            status,
            metrics,
        }
    }

    #[test]
    fn medians_and_dispersions_match_hand_computation() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), Some(2.5));
        assert_eq!(median(&[]), None);
        // ln 1, ln e, ln e²: mean 1, squares 1 + 0 + 1 over n − 1 = 2: β = 1
        let e = std::f64::consts::E;
        let (b, n) = dispersion(&[1.0, e, e * e, 0.0]);
        assert!((b.unwrap() - 1.0).abs() < 1e-15);
        assert_eq!(n, 3);
        assert_eq!(dispersion(&[0.0, 2.0]), (None, 1));
    }

    #[test]
    fn levels_group_runs_count_failures_and_skip_unfinished_values() {
        let fail = |k: &str| Status::Failed {
            kind: k.into(),
            reason: "t = 1 s".into(),
        };
        let e = std::f64::consts::E;
        let rows = vec![
            row(0.1, "0.3", Status::Finished, 1.0, 0.0),
            row(0.1, "0.5", Status::Finished, 7.0, 1.0),
            row(0.2, "0.3", fail("Unseated"), 99.0, 5.0),
            row(0.1, "0.3", Status::Finished, e * e, 4.0),
            row(0.2, "0.3", Status::Refused("bad".into()), 0.0, 0.0),
            row(0.2, "0.3", fail("StepTooSmall"), 99.0, 5.0),
            row(0.2, "0.3", fail("Unseated"), 99.0, 5.0),
            row(0.2, "0.3", Status::Finished, 3.0, 2.0),
        ];
        let s = level_stats(&rows);
        assert_eq!(s.len(), 3);
        let (a, b, c) = (&s[0], &s[1], &s[2]);
        assert_eq!(
            (a.level, a.settings[0].1.as_str(), a.count, a.finished),
            (0.1, "0.3", 2, 2)
        );
        // peaks 1 and e²: median (1 + e²)/2, β = std of (0, 2) = √2
        let peak = &a.metrics[0].1;
        assert_eq!(peak.median, Some(0.5 * (1.0 + e * e)));
        assert!((peak.beta.unwrap() - 2f64.sqrt()).abs() < 1e-15);
        // impacts 0 and 4: the zero is in the median, not in β
        let impacts = &a.metrics[7].1;
        assert_eq!(
            (impacts.median, impacts.beta, impacts.positive),
            (Some(2.0), None, 1)
        );
        assert_eq!((b.settings[0].1.as_str(), b.count), ("0.5", 1));
        assert_eq!((c.count, c.finished, c.failed, c.refused), (5, 1, 3, 1));
        let want = vec![("StepTooSmall".to_string(), 1), ("Unseated".to_string(), 2)];
        assert_eq!(c.failures, want);
        // only the finished run's values
        assert_eq!(c.metrics[0].1.median, Some(3.0));
        let csv = stats_csv(&["contacts.mu".into()], &s);
        let line = csv.lines().nth(3).unwrap();
        assert!(
            line.starts_with("pga,0.2,0.3,5,1,3,1,StepTooSmall=1;Unseated=2,3.0,,1,"),
            "{line}"
        );
        let json = stats_json(&s);
        assert!(
            json.contains("\"failures\": {\n      \"StepTooSmall\": 1,\n      \"Unseated\": 2\n"),
            "{json}"
        );
    }
}
