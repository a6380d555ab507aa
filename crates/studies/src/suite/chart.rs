//! The suite as a chart: each finished run's peak deck rotation against its level (incremental
//! dynamic analysis), with the median per level and the 16 and 84 % lines of the lognormal
//! (median · e^{∓β}).

use super::row::{Status, SuiteRow};
use super::stats::LevelStats;
use crate::plot::{Axis, Band, Chart, Marker, Series, Stroke};

/// The IDA chart of `rows` with the per-level `stats` (one parameter point: the first rows'
/// settings; a suite crossed with swept keys is drawn for its first point).
pub fn ida_chart(rows: &[SuiteRow], stats: &[LevelStats]) -> Chart {
    let settings = rows.first().map(|r| r.settings.clone()).unwrap_or_default();
    let measure = rows
        .first()
        .map_or("intensity".into(), |r| r.measure.clone());
    let mut title = "Record suite: peak deck rotation against intensity".to_string();
    if !settings.is_empty() {
        let s: Vec<String> = settings.iter().map(|(k, v)| format!("{k}={v}")).collect();
        title.push_str(&format!(" ({})", s.join(", ")));
    }
    let mut c = Chart::new(
        &title,
        Axis::linear(&measure, "g"),
        Axis::linear("peak |θ|", "rad"),
    );
    let runs: Vec<(f64, f64)> = (rows.iter())
        .filter(|r| r.settings == settings && r.status == Status::Finished)
        .filter_map(|r| r.metrics[0].map(|p| (r.level, p)))
        .collect();
    let mut median = Vec::new();
    let mut band = Vec::new();
    for s in stats.iter().filter(|s| s.settings == settings) {
        let Some((_, m)) = s.metrics.first() else {
            continue;
        };
        if let Some(med) = m.median {
            median.push((s.level, med));
            if let Some(b) = m.beta {
                band.push((s.level, med * (-b).exp(), med * b.exp()));
            }
        }
    }
    c.bands.push(Band {
        label: "16–84 % (median · e^∓β)".into(),
        points: band,
        color: 0,
    });
    c.series.push(
        Series::points("runs", runs)
            .color(7)
            .glyph('.')
            .marker(Marker::Circle),
    );
    c.series.push(
        Series::line("median", median)
            .color(3)
            .glyph('M')
            .marker(Marker::Square)
            .stroke(Stroke::Solid),
    );
    c
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::suite::stats::level_stats;

    /// [`crate::suite::stats::tests::row`] without impacts.
    fn row(level: f64, mu: &str, status: Status, peak: f64) -> SuiteRow {
        crate::suite::stats::tests::row(level, mu, status, peak, 0.0)
    }

    #[test]
    fn the_chart_holds_the_first_points_runs_their_medians_and_the_lognormal_band() {
        let failed = Status::Failed {
            kind: "StepCollapse".into(),
            reason: "r".into(),
        };
        let e = std::f64::consts::E;
        let rows = vec![
            row(0.5, "0.1", Status::Finished, 1.0),
            row(0.5, "0.1", Status::Finished, e),
            row(0.5, "0.1", Status::Finished, e * e),
            row(1.0, "0.1", Status::Finished, 2.0),
            row(1.0, "0.1", failed, 9.0),
            row(0.5, "0.5", Status::Finished, 7.0),
        ];
        let c = ida_chart(&rows, &level_stats(&rows));
        assert!(c.title.contains("contacts.mu=0.1"), "{}", c.title);
        // the finished runs of μ 0.1 only: the failed run and μ 0.5 are left out
        assert_eq!(
            c.series[0].points,
            vec![(0.5, 1.0), (0.5, e), (0.5, e * e), (1.0, 2.0)]
        );
        assert_eq!(c.series[1].points, vec![(0.5, e), (1.0, 2.0)]);
        // β of ln 1, ln e, ln e² is 1: the band is median · e^∓1 = (1, e²); one value: no β
        let b = &c.bands[0].points;
        assert_eq!(b.len(), 1);
        assert!(
            (b[0].1 - 1.0).abs() < 1e-15 && (b[0].2 - e * e).abs() < 1e-14,
            "{b:?}"
        );
    }
}
