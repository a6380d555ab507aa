//! The time charts (rotation, gaps, x/y) with the overlaid runs (the baseline and those
//! selected in the run list) underneath and the time cursor, above the event strip.

use super::cache::Cache;
use super::common::{LABEL_W, Overlay, Theme, overlay_runs, shown_run};
use super::timeline::draw_timeline;
use crate::output::EventKind;
use crate::tui::app::App;
use crate::tui::chart::{self, bounds, fmt_num};
use crate::tui::run_data::RunData;
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Chart, Dataset, GraphType, Paragraph};

struct Series {
    name: String,
    style: Style,
    data: Vec<(f64, f64)>,
    /// The number of the overlaid run it belongs to (None: the shown run).
    overlay: Option<u64>,
}

/// What the series of one panel are drawn from: the runs, the time window, the columns.
struct Window<'a> {
    run: &'a RunData,
    overlays: Vec<Overlay<'a>>,
    t0: f64,
    t1: f64,
    cols: u16,
}

/// One chart: title, unit, series.
type TimeChart = (String, String, Vec<Series>);

/// Draws the time charts that fit and the event strip under them.
pub(super) fn draw_time_panel(
    frame: &mut Frame,
    area: Rect,
    app: &App,
    cache: &mut Cache,
    th: &Theme,
) {
    let Some(run) = shown_run(app) else {
        let msg = if app.scene.is_none() {
            "no model loaded yet: fix the file (it reloads on save)"
        } else {
            "no run yet: r runs the model"
        };
        frame.render_widget(Paragraph::new(msg).block(th.block(" charts ")), area);
        return;
    };
    let overlays = overlay_runs(app, th);
    let (t0, t1) = app.window();
    let nc = run.contact_names.len();
    let max_rows = (area.height as usize / 3).max(1);
    let strip_rows = nc.min(max_rows).min(8) as u16;
    let keys = u16::from(run.count(EventKind::KeyFailure) > 0);
    let tl_h = 2 + strip_rows.max(if nc == 0 { 0 } else { 1 }) + keys;
    let charts_h = area.height.saturating_sub(tl_h);
    let fit: usize = if charts_h >= 12 {
        3
    } else if charts_h >= 6 {
        2
    } else {
        1
    };
    let graph_w = area.width.saturating_sub(LABEL_W + 1);
    let cols = (graph_w as usize * th.per_cell()) as u16;
    let tc = app.cursor_time();
    let sp = Window {
        run,
        overlays,
        t0,
        t1,
        cols,
    };
    let mut charts: Vec<TimeChart> = Vec::new();
    charts.extend(rotation_chart(&sp, cache, th));
    charts.extend(gap_chart(&sp, cache, th));
    charts.extend(xy_chart(&sp, cache, th));
    let n_charts = fit.min(charts.len()).max(1);
    let mut cons = vec![Constraint::Ratio(1, n_charts as u32); n_charts];
    cons.push(Constraint::Length(tl_h));
    let rects = Layout::vertical(cons).split(area);
    for (i, (title, unit, series)) in charts.into_iter().take(n_charts).enumerate() {
        draw_time_chart(frame, rects[i], app, run, &title, &unit, series, tc, th);
    }
    draw_timeline(frame, rects[n_charts], run, (t0, t1, tc), cache, th);
}

/// The rotation θ(t) (and the previous run's).
fn rotation_chart(sp: &Window, cache: &mut Cache, th: &Theme) -> Option<TimeChart> {
    let (run, t0, t1, cols) = (sp.run, sp.t0, sp.t1, sp.cols);
    let r = run.rot?;
    let name = run.dof_names[r].clone();
    let mut s = Vec::new();
    for o in &sp.overlays {
        let p = o.data;
        if let Some(k) = p.dof(&name) {
            s.push(Series {
                name: format!("{name} (#{})", o.number),
                style: o.style,
                data: cache.decimated(p, &format!("q{k}"), &p.q[k], t0, t1, cols),
                overlay: Some(o.number),
            });
        }
    }
    s.push(Series {
        name: name.clone(),
        style: th.series(0),
        data: cache.decimated(run, &format!("q{r}"), &run.q[r], t0, t1, cols),
        overlay: None,
    });
    Some((name.clone(), unit_of(&name).into(), s))
}

/// The gaps g_N(t) of all contacts (and the previous run's).
fn gap_chart(sp: &Window, cache: &mut Cache, th: &Theme) -> Option<TimeChart> {
    let (run, t0, t1, cols) = (sp.run, sp.t0, sp.t1, sp.cols);
    if run.contact_names.is_empty() {
        return None;
    }
    let mut s = Vec::new();
    for o in &sp.overlays {
        let p = o.data;
        for (i, n) in p.contact_names.iter().enumerate() {
            if run.contact_names.contains(n) {
                s.push(Series {
                    name: format!("{n} (#{})", o.number),
                    style: o.style,
                    data: cache.decimated(p, &format!("g{i}"), &p.gap[i], t0, t1, cols),
                    overlay: Some(o.number),
                });
            }
        }
    }
    for (i, n) in run.contact_names.iter().enumerate() {
        s.push(Series {
            name: n.clone(),
            style: th.series(i),
            data: cache.decimated(run, &format!("g{i}"), &run.gap[i], t0, t1, cols),
            overlay: None,
        });
    }
    Some(("gaps g_N".into(), "m".into(), s))
}

/// x and y of the rotating body (and the previous run's).
fn xy_chart(sp: &Window, cache: &mut Cache, th: &Theme) -> Option<TimeChart> {
    let (run, t0, t1, cols) = (sp.run, sp.t0, sp.t1, sp.cols);
    if run.xy.is_empty() {
        return None;
    }
    let mut s = Vec::new();
    for o in &sp.overlays {
        let p = o.data;
        for &k in &run.xy {
            if let Some(pk) = p.dof(&run.dof_names[k]) {
                s.push(Series {
                    name: format!("{} (#{})", run.dof_names[k], o.number),
                    style: o.style,
                    data: cache.decimated(p, &format!("q{pk}"), &p.q[pk], t0, t1, cols),
                    overlay: Some(o.number),
                });
            }
        }
    }
    for (i, &k) in run.xy.iter().enumerate() {
        s.push(Series {
            name: run.dof_names[k].clone(),
            style: th.series(i + 4),
            data: cache.decimated(run, &format!("q{k}"), &run.q[k], t0, t1, cols),
            overlay: None,
        });
    }
    let names: Vec<&str> = run.xy.iter().map(|&k| run.dof_names[k].as_str()).collect();
    Some((names.join(" / "), "m".into(), s))
}

fn unit_of(dof: &str) -> &'static str {
    if dof.ends_with(".theta") { "rad" } else { "m" }
}

/// Value of a column at the cursor.
fn value_at(run: &RunData, y: &[f64], tc: f64) -> Option<f64> {
    chart::at_or_before(&run.t, tc).and_then(|i| y.get(i).copied())
}

/// Draws one time chart: header (title, legend, value at the cursor), series, cursor.
#[allow(clippy::too_many_arguments)]
fn draw_time_chart(
    frame: &mut Frame,
    area: Rect,
    app: &App,
    run: &RunData,
    title: &str,
    unit: &str,
    series: Vec<Series>,
    tc: f64,
    th: &Theme,
) {
    if area.height < 2 {
        return;
    }
    let (t0, t1) = app.window();
    let [head, body] = Layout::vertical([Constraint::Length(1), Constraint::Min(0)]).areas(area);
    frame.render_widget(
        Paragraph::new(chart_header(run, title, unit, &series, tc, th)),
        head,
    );
    if body.height == 0 {
        return;
    }
    let yb = bounds(series.iter().flat_map(|s| s.data.iter().map(|p| &p.1)));
    let cursor = [(tc, yb[0]), (tc, yb[1])];
    let marker = th.marker();
    let mut ds: Vec<Dataset> = series
        .iter()
        .map(|s| {
            Dataset::default()
                .marker(marker)
                .graph_type(GraphType::Line)
                .style(s.style)
                .data(&s.data)
        })
        .collect();
    if tc >= t0 && tc <= t1 {
        ds.push(
            Dataset::default()
                .marker(marker)
                .graph_type(GraphType::Line)
                .style(th.cursor())
                .data(&cursor),
        );
    }
    let lab = |v: f64| {
        Line::from(format!(
            "{:>w$}",
            fmt_num(v, LABEL_W as usize - 1),
            w = LABEL_W as usize
        ))
    };
    let chart = Chart::new(ds)
        .x_axis(Axis::default().bounds([t0, t1]))
        .y_axis(
            Axis::default()
                .bounds(yb)
                .labels(vec![lab(yb[0]), lab(yb[1])])
                .style(th.dim()),
        )
        .legend_position(None);
    frame.render_widget(chart, body);
}

/// The chart's header line: title [unit], legend, value at the cursor.
fn chart_header(
    run: &RunData,
    title: &str,
    unit: &str,
    series: &[Series],
    tc: f64,
    th: &Theme,
) -> Line<'static> {
    let mut spans = vec![Span::styled(format!("{title} [{unit}]"), th.bold())];
    let current: Vec<&Series> = series.iter().filter(|s| s.overlay.is_none()).collect();
    if current.len() > 1 {
        for s in &current {
            spans.push(Span::styled(" ━", s.style));
            spans.push(Span::raw(s.name.clone()));
        }
    }
    spans.extend(overlay_legend(series));
    if current.len() == 1 {
        let name = &current[0].name;
        let col = run.dof(name).map(|k| &run.q[k]).or_else(|| {
            run.contact_names
                .iter()
                .position(|n| n == name)
                .map(|i| &run.gap[i])
        });
        if let Some(v) = col.and_then(|c| value_at(run, c, tc)) {
            spans.push(Span::styled(
                format!("  @cursor {}", fmt_num(v, 9)),
                th.cursor(),
            ));
        }
    }
    Line::from(spans)
}

/// The legend of the overlaid runs: `┈#1` in each run's style, once per run.
fn overlay_legend(series: &[Series]) -> Vec<Span<'static>> {
    let mut seen: Vec<u64> = Vec::new();
    let mut spans = Vec::new();
    for s in series {
        if let Some(n) = s.overlay
            && !seen.contains(&n)
        {
            seen.push(n);
            spans.push(Span::styled(format!(" ┈#{n}"), s.style));
        }
    }
    spans
}
