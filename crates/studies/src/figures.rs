//! The studies' charts as `plot` data: the Fig. 7 analog (peak deck rotation against target
//! PGA, with and without contact), the Fig. 8 analog (percent increase of peak rotation over
//! no contact against μ), the work–precision diagram (CPU time against error, log–log, one
//! curve per method and contact stiffness) and the stability grid (method × knob → ok /
//! inaccurate / unstable / failed).

use crate::methods::Method;
use crate::plot::{Axis, Category, Cell, Chart, Grid, GridRow, Marker, RefLine, Series, Stroke};
use crate::precision::{Point, Verdict, knob_family, knob_step, verdict};
use crate::studies::{MuStudy, Row};

/// Fig. 7's mark of the runs without contact, in the CLI's text charts and the workbench's.
pub const FIG7_WITHOUT_CONTACT: char = 'o';
/// Fig. 7's mark of the runs with contact (a square in the SVG), in both.
pub const FIG7_WITH_CONTACT: char = '#';

/// Fig. 7: rows (run, PGA x, PGA y, without contact, with contact) against the longitudinal
/// target PGA; marked [`FIG7_WITHOUT_CONTACT`] and [`FIG7_WITH_CONTACT`].
pub fn rotation_vs_pga(rows: &[(usize, f64, f64, Row, Row)]) -> Chart {
    let mut c = Chart::new(
        "Peak deck rotation vs target PGA (Fig. 7 analog)",
        Axis::linear("target PGA, longitudinal", "g"),
        Axis::linear("peak deck rotation |θ|", "rad"),
    );
    let mut sorted: Vec<&(usize, f64, f64, Row, Row)> = rows.iter().collect();
    sorted.sort_by(|a, b| a.1.total_cmp(&b.1));
    let pts = |f: fn(&Row, &Row) -> f64| -> Vec<(f64, f64)> {
        sorted.iter().map(|r| (r.1, f(&r.3, &r.4))).collect()
    };
    c.series.push(
        Series::line("without contact", pts(|a, _| a.peak_rotation))
            .marker(Marker::Circle)
            .color(0)
            .glyph(FIG7_WITHOUT_CONTACT),
    );
    c.series.push(
        Series::line("with contact", pts(|_, b| b.peak_rotation))
            .marker(Marker::Square)
            .color(3)
            .glyph(FIG7_WITH_CONTACT),
    );
    c
}

/// Fig. 8: the increase per run (labelled by `runs`, the `[[run]]` numbers) and its mean
/// against μ, with the no-contact level at 0 %.
pub fn increase_vs_mu(m: &MuStudy, runs: &[usize]) -> Chart {
    let mut c = Chart::new(
        "Increase of peak rotation over no contact vs friction (Fig. 8 analog)",
        Axis::linear("friction coefficient μ", ""),
        Axis::linear("increase of peak rotation", "%"),
    );
    c.lines.push(RefLine::horizontal(0.0, "no contact", 7));
    for r in 0..m.rows.len() {
        let label = runs.get(r).copied().unwrap_or(r + 1);
        let pts = (0..m.mus.len())
            .map(|k| (m.mus[k], m.increase(r, k)))
            .collect();
        let glyph = std::char::from_digit((label % 36) as u32, 36).unwrap_or('?');
        c.series.push(
            Series::line(&format!("run {label} ({:.2} g)", m.pgas[r].0), pts)
                .marker(Marker::Circle)
                .color(r)
                .glyph(glyph),
        );
    }
    let mean = (0..m.mus.len())
        .map(|k| (m.mus[k], m.mean_increase(k)))
        .collect();
    c.series.push(
        Series::line("mean", mean)
            .stroke(Stroke::Dashed)
            .marker(Marker::Square)
            .color(7)
            .glyph('*'),
    );
    c
}

/// The work–precision diagram: CPU time (s) against the `metric` error, log–log, one curve
/// per method and contact stiffness (knob order, coarse to fine), a dashed line at `tol`.
/// Points that failed, or whose error or time is not positive, are left out.
pub fn work_precision(points: &[Point], metric: &str, tol: f64) -> Chart {
    let unit = if metric == "impact" { "s" } else { "" };
    let what = match metric {
        "impact" => "first impact time error",
        "rms" => "RMS history error (relative)",
        _ => "peak error (relative)",
    };
    let mut c = Chart::new(
        "Work-precision",
        Axis::log("CPU time", "s"),
        Axis::log(what, unit),
    );
    let tol_label = if metric == "impact" {
        format!("{tol} s")
    } else {
        format!("{} %", 100.0 * tol)
    };
    c.lines.push(RefLine::horizontal(tol, &tol_label, 7));
    let markers = [
        Marker::Circle,
        Marker::Square,
        Marker::Triangle,
        Marker::Cross,
    ];
    for (i, m) in Method::ALL.into_iter().enumerate() {
        let mut families: Vec<&str> = Vec::new();
        for p in points.iter().filter(|p| p.method == m) {
            if !families.contains(&knob_family(&p.knob)) {
                families.push(knob_family(&p.knob));
            }
        }
        for (j, fam) in families.into_iter().enumerate() {
            let pts: Vec<(f64, f64)> = (points.iter())
                .filter(|p| p.method == m && knob_family(&p.knob) == fam && p.is_ok())
                .map(|p| (p.cpu_s, p.error(metric)))
                .filter(|(t, e)| *t > 0.0 && *e > 0.0 && t.is_finite() && e.is_finite())
                .collect();
            if pts.is_empty() {
                continue;
            }
            let label = if fam.is_empty() {
                m.title().to_string()
            } else {
                format!("{} {fam}", m.title())
            };
            c.series.push(
                Series::line(&label, pts)
                    .marker(markers[j % markers.len()])
                    .color(i)
                    .glyph(m.letter()),
            );
        }
    }
    c
}

/// The stability grid: a row per method and contact stiffness, a cell per knob (coarse to
/// fine) with its [`verdict`] against `tol`.
pub fn stability(points: &[Point], tol: f64) -> Grid {
    let categories = [
        ("ok", 'o', 2),
        ("inaccurate", 'i', 1),
        ("unstable", 'U', 3),
        ("failed", 'F', 7),
    ]
    .map(|(name, glyph, color)| Category {
        name: name.into(),
        glyph,
        color,
    })
    .to_vec();
    let mut rows: Vec<GridRow> = Vec::new();
    for p in points {
        let fam = knob_family(&p.knob);
        let label = if fam.is_empty() {
            p.method.name().to_string()
        } else {
            format!("{} {fam}", p.method.name())
        };
        let category = match verdict(p, tol) {
            Verdict::Ok { .. } => 0,
            Verdict::Inaccurate { .. } => 1,
            Verdict::Unstable => 2,
            Verdict::Failed(_) => 3,
        };
        let cell = Cell {
            label: knob_step(&p.knob).to_string(),
            category,
        };
        match rows.iter_mut().find(|r| r.label == label) {
            Some(r) => r.cells.push(cell),
            None => rows.push(GridRow {
                label,
                cells: vec![cell],
            }),
        }
    }
    Grid {
        title: format!(
            "Stability: method × knob (inaccurate: peak or history error above {} %)",
            100.0 * tol
        ),
        columns: "knob, coarse to fine".into(),
        rows,
        categories,
    }
}
