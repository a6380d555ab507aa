//! The work-precision study's panel: the log-log chart of CPU time against the peak error,
//! one curve per method (and contact stiffness), the 1 % line ([`figures::work_precision`]);
//! or, with `g`, the stability grid, method × knob → ok / inaccurate / unstable / failed
//! ([`figures::stability`]) with the one legend and threshold `precision` and `stability`
//! share ([`INACCURATE_ABOVE`]).

use super::common::Theme;
use super::line_plot::{Look, draw_line_plot};
use crate::figures;
use crate::precision::INACCURATE_ABOVE;
use crate::precision_study::PrecisionTable;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

/// The error of the chart's reference line (as `deckspin precision`'s summary: 1 %).
pub(super) const CHART_TOL: f64 = 0.01;

/// The chart (or the grid when `grid`) of the points done so far.
pub(super) fn draw_precision(
    frame: &mut Frame,
    area: Rect,
    t: &PrecisionTable,
    grid: bool,
    th: &Theme,
) {
    let points = t.done_points();
    if grid {
        return draw_grid(frame, area, t, th);
    }
    // the chart `deckspin precision` draws, its axes titled for the panel
    let mut chart = figures::work_precision(&points, "peak", CHART_TOL);
    (chart.y.title, chart.y.unit) = (
        "peak error of the watched rotation [-], log (g: stability grid)".into(),
        String::new(),
    );
    (chart.x.title, chart.x.unit) = ("CPU time [s], log".into(), String::new());
    if chart.series.is_empty() {
        let msg = th.text("no point with a finite error yet…");
        frame.render_widget(Paragraph::new(msg), area);
        return;
    }
    draw_line_plot(frame, area, &chart, &Look::default(), th);
}

/// The stability grid as text: a row per method (and contact stiffness), its knobs coarse to
/// fine each with its verdict's glyph; the legend and the threshold first.
fn draw_grid(frame: &mut Frame, area: Rect, t: &PrecisionTable, th: &Theme) {
    let g = figures::stability(&t.done_points(), INACCURATE_ABOVE);
    let mut lines = vec![Line::styled(
        th.text(&format!(
            "stability: method x knob (inaccurate: peak or history error above {} %)",
            100.0 * INACCURATE_ABOVE
        )),
        th.bold(),
    )];
    let legend: Vec<Span> = (g.categories.iter())
        .flat_map(|c| {
            [
                Span::styled(c.glyph.to_string(), th.series(c.color).patch(th.bold())),
                Span::raw(format!(" {}   ", c.name)),
            ]
        })
        .collect();
    lines.push(Line::from(legend));
    let lw = g
        .rows
        .iter()
        .map(|r| r.label.chars().count())
        .max()
        .unwrap_or(0);
    for r in &g.rows {
        let mut spans = vec![Span::raw(format!("{:<lw$} ", r.label))];
        for c in &r.cells {
            let cat = &g.categories[c.category.min(g.categories.len() - 1)];
            spans.push(Span::raw(format!(" {}:", c.label)));
            spans.push(Span::styled(
                cat.glyph.to_string(),
                th.series(cat.color).patch(th.bold()),
            ));
        }
        lines.push(Line::from(spans));
    }
    let (done, all) = t.progress();
    if done < all {
        lines.push(Line::styled(
            format!("{done} of {all} points so far"),
            th.dim(),
        ));
    }
    lines.push(Line::styled(
        th.text(&format!("columns: {}", g.columns)),
        th.dim(),
    ));
    frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: false }), area);
}
