//! The time charts (rotation, gaps, x/y) with the previous run underneath and the time
//! cursor, above the event strip.

use super::cache::Cache;
use super::common::{LABEL_W, Theme, fit_spans, overlay_run, shown_run};
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
}

/// What the series of one panel are drawn from: the runs, the time window, the columns.
struct Window<'a> {
    run: &'a RunData,
    prev: Option<&'a RunData>,
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
    let prev = overlay_run(app).filter(|p| p.id != run.id);
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
        prev,
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
    if let Some(p) = sp.prev
        && let Some(k) = p.dof(&name)
    {
        s.push(Series {
            name: format!("{} (previous)", name),
            style: th.previous(),
            data: cache.decimated(p, &format!("q{k}"), &p.q[k], t0, t1, cols),
        });
    }
    s.push(Series {
        name: name.clone(),
        style: th.series(0),
        data: cache.decimated(run, &format!("q{r}"), &run.q[r], t0, t1, cols),
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
    if let Some(p) = sp.prev {
        for (i, n) in p.contact_names.iter().enumerate() {
            if run.contact_names.contains(n) {
                s.push(Series {
                    name: format!("{n} (previous)"),
                    style: th.previous(),
                    data: cache.decimated(p, &format!("g{i}"), &p.gap[i], t0, t1, cols),
                });
            }
        }
    }
    for (i, n) in run.contact_names.iter().enumerate() {
        s.push(Series {
            name: n.clone(),
            style: th.series(i),
            data: cache.decimated(run, &format!("g{i}"), &run.gap[i], t0, t1, cols),
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
    if let Some(p) = sp.prev {
        for &k in &run.xy {
            if let Some(pk) = p.dof(&run.dof_names[k]) {
                s.push(Series {
                    name: format!("{} (previous)", run.dof_names[k]),
                    style: th.previous(),
                    data: cache.decimated(p, &format!("q{pk}"), &p.q[pk], t0, t1, cols),
                });
            }
        }
    }
    for (i, &k) in run.xy.iter().enumerate() {
        s.push(Series {
            name: run.dof_names[k].clone(),
            style: th.series(i + 4),
            data: cache.decimated(run, &format!("q{k}"), &run.q[k], t0, t1, cols),
        });
    }
    let names: Vec<&str> = run.xy.iter().map(|&k| run.dof_names[k].as_str()).collect();
    Some((names.join(" / "), "m".into(), s))
}

/// The initials of a name's words (`left_top` lt, `deck.x` dx).
fn initials(name: &str) -> String {
    name.split(['_', '.', ' ', '-'])
        .filter_map(|w| w.chars().next())
        .collect()
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
        Paragraph::new(chart_header(run, title, unit, &series, tc, th, head.width)),
        head,
    );
    if body.height == 0 {
        return;
    }
    let yb = bounds(series.iter().flat_map(|s| s.data.iter().map(|p| &p.1)));
    let cursor = [(tc, yb[0]), (tc, yb[1])];
    // without colour, each series by its own mark (the previous run's, the k-th current one's)
    let mut k = 0;
    let mut ds: Vec<Dataset> = series
        .iter()
        .map(|s| {
            let marker = if s.name.ends_with("(previous)") {
                th.previous_marker()
            } else {
                k += 1;
                th.series_marker(k - 1)
            };
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
                .marker(th.cursor_marker())
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

/// The chart's header line in `width` columns: title [unit], legend, value at the cursor
/// (whole items only: one that does not fit is left out).
fn chart_header(
    run: &RunData,
    title: &str,
    unit: &str,
    series: &[Series],
    tc: f64,
    th: &Theme,
    width: u16,
) -> Line<'static> {
    let mut items = vec![vec![Span::styled(
        th.text(&format!("{title} [{unit}]")),
        th.bold(),
    )]];
    let current: Vec<&Series> = series
        .iter()
        .filter(|s| !s.name.ends_with("(previous)"))
        .collect();
    let has_prev = series.iter().any(|s| s.name.ends_with("(previous)"));
    let sample = |m: String| {
        if th.marks() {
            format!(" [{m}]")
        } else {
            format!(" {m}")
        }
    };
    if current.len() == 1 && th.marks() {
        // one series, named by the title: its mark alone
        items.push(vec![Span::styled(
            th.text(&sample(th.legend_mark(0))),
            current[0].style,
        )]);
    }
    if current.len() == 1 && has_prev {
        let prev = format!("{}prev", sample(th.previous_mark()));
        items.push(vec![Span::styled(th.text(&prev), th.previous())]);
    } else if current.len() > 1 {
        let legend = |name: &dyn Fn(&str) -> String| -> Vec<Vec<Span<'static>>> {
            let mut l: Vec<Vec<Span>> = (current.iter().enumerate())
                .map(|(k, s)| {
                    vec![
                        Span::styled(th.text(&sample(th.legend_mark(k))), s.style),
                        Span::raw(th.text(&name(&s.name))),
                    ]
                })
                .collect();
            if has_prev {
                let prev = format!("{}prev", sample(th.previous_mark()));
                l.push(vec![Span::styled(th.text(&prev), th.previous())]);
            }
            l
        };
        let full = legend(&|n| n.to_string());
        let w = |l: &[Vec<Span>]| l.iter().flatten().map(Span::width).sum::<usize>();
        // names too long for the line: their initials (left_top: lt), never a cut name
        if w(&items) + w(&full) <= width as usize {
            items.extend(full);
        } else {
            items.extend(legend(&initials));
        }
    }
    if current.len() == 1 {
        let name = &current[0].name;
        let col = run.dof(name).map(|k| &run.q[k]).or_else(|| {
            run.contact_names
                .iter()
                .position(|n| n == name)
                .map(|i| &run.gap[i])
        });
        if let Some(v) = col.and_then(|c| value_at(run, c, tc)) {
            items.push(vec![Span::styled(
                format!("  @cursor {}", fmt_num(v, 9)),
                th.cursor(),
            )]);
        }
    }
    fit_spans(items, width as usize)
}
