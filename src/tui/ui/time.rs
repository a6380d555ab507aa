//! The time charts with the overlaid runs underneath and the time cursor, above the event
//! strip: three charts of any series a run records (by default the rotation, the gaps, x and
//! y; [`crate::tui::chart_prefs`]), each with its y zoom and log scale, θ in the unit chosen;
//! the y axis is the shown run's, the overlaid runs' extremes beyond it are in the header.

use super::cache::Cache;
use super::chart_head::{Series, chart_header};
use super::common::{LABEL_W, Overlay, Theme, overlay_runs, shown_run};
use super::timeline::draw_timeline;
use crate::output::EventKind;
use crate::tui::app::App;
use crate::tui::chart;
use crate::tui::chart_prefs::{self, ChartSpec, ThetaUnit, Units};
use crate::tui::eng::{self, Scale};
use crate::tui::runs::data::RunData;
use crate::tui::runs::nav;
use crate::tui::runs::series::{self, SeriesId};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::Style;
use ratatui::symbols::Marker;
use ratatui::text::Line;
use ratatui::widgets::{Axis, Chart, Dataset, GraphType, Paragraph};

/// What the series of one panel are drawn from: the runs, the time window, the columns, the
/// units.
struct Window<'a> {
    run: &'a RunData,
    overlays: Vec<Overlay<'a>>,
    t0: f64,
    t1: f64,
    /// The time of the values at the cursor in the headers ([`super::Cache::readout_time`]).
    rt: f64,
    cols: u16,
    /// The model's units, θ's.
    units: Units,
    theta: ThetaUnit,
}

/// One chart: its number (0–2), title, unit (`fixed`: one that takes no prefix, θ in mrad or
/// degrees), series.
struct TimeChart {
    k: usize,
    title: String,
    unit: String,
    fixed: bool,
    series: Vec<Series>,
}

/// Draws the time charts that fit and the event strip under them; the readouts at `rt`.
pub(super) fn draw_time_panel(
    frame: &mut Frame,
    area: Rect,
    app: &App,
    cache: &mut Cache,
    rt: f64,
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
    // legend, readout, rows, axis
    let tl_h = 3 + strip_rows.max(if nc == 0 { 0 } else { 1 }) + keys;
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
        rt,
        cols,
        units: nav::units(app),
        theta: app.charts.theta,
    };
    let charts: Vec<TimeChart> = (0..chart_prefs::CHARTS)
        .filter_map(|k| chart_of(&sp, cache, th, k, &app.charts.series(run, k)))
        .collect();
    let n_charts = fit.min(charts.len()).max(1);
    let mut cons = vec![Constraint::Ratio(1, n_charts as u32); n_charts];
    cons.push(Constraint::Length(tl_h));
    let rects = Layout::vertical(cons).split(area);
    for (i, c) in charts.into_iter().take(n_charts).enumerate() {
        let spec = &app.charts.charts[c.k];
        let focused = app.charts.focus == c.k;
        draw_time_chart(frame, rects[i], (t0, t1, tc), c, (spec, focused), th);
    }
    let kn = nav::force_unit(app);
    draw_timeline(frame, rects[n_charts], run, (t0, t1, tc, rt), kn, cache, th);
}

/// One series of `r` (column `y`, cached as `what`) over the window, with its value at the
/// cursor, times `f` (to the chart's unit); `overlay`: the number of the overlaid run it
/// belongs to.
fn series(
    sp: &Window,
    cache: &mut Cache,
    (r, what, y, f): (&RunData, String, &[f64], f64),
    (name, style): (String, Style),
    overlay: Option<u64>,
) -> Series {
    let mut data = cache.decimated(r, &what, y, sp.t0, sp.t1, sp.cols);
    if f != 1.0 {
        data.iter_mut().for_each(|p| p.1 *= f);
    }
    Series {
        name,
        style,
        data,
        overlay,
        now: value_at(r, y, sp.rt).map(|v| v * f),
    }
}

/// Chart `k` of the series `ids` (and the overlaid runs' of the same names); None without
/// series.
fn chart_of(
    sp: &Window,
    cache: &mut Cache,
    th: &Theme,
    k: usize,
    ids: &[SeriesId],
) -> Option<TimeChart> {
    let first = ids.first()?;
    let (unit, f) = chart_prefs::unit_of(first.dim(), &sp.units, sp.theta, th.ascii);
    let mut s = Vec::new();
    for o in &sp.overlays {
        for id in ids {
            if let Some(col) = series::column(o.data, id) {
                let name = series::name_in(id, ids);
                let c = (o.data, id.key(), col.as_ref(), f);
                s.push(series(sp, cache, c, (name, o.style), Some(o.number)));
            }
        }
    }
    // the colours of the default charts: the gaps by contact, x and y after them
    let offset = if k == 2 { 4 } else { 0 };
    for (i, id) in ids.iter().enumerate() {
        if let Some(col) = series::column(sp.run, id) {
            let name = series::name_in(id, ids);
            let c = (sp.run, id.key(), col.as_ref(), f);
            s.push(series(sp, cache, c, (name, th.series(i + offset)), None));
        }
    }
    Some(TimeChart {
        k,
        title: series::title(ids),
        unit,
        fixed: first.angular() && sp.theta != ThetaUnit::Rad,
        series: s,
    })
}

/// Value of a column at the cursor.
fn value_at(run: &RunData, y: &[f64], tc: f64) -> Option<f64> {
    chart::at_or_before(&run.t, tc).and_then(|i| y.get(i).copied())
}

/// The smallest and largest value the series show (None when they show nothing).
pub(super) fn extremes<'a>(values: impl IntoIterator<Item = &'a f64>) -> Option<[f64; 2]> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &v in values.into_iter().filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    (lo <= hi).then_some([lo, hi])
}

/// The y axis of data whose extremes are `ext`: its bounds (the extremes themselves, so that
/// the top and bottom rows are the largest and smallest values; a flat set is padded around
/// its value) and its labels, low and high, formatted with one precision that fits `width`
/// columns (a flat set is labelled once, in the middle).
pub(super) fn value_axis(
    ext: Option<[f64; 2]>,
    unit: &str,
    width: usize,
    ascii: bool,
) -> ([f64; 2], Vec<String>) {
    let Some([lo, hi]) = ext else {
        return ([-1.0, 1.0], vec![String::new(), String::new()]);
    };
    let fmt = |v: f64| {
        (1..=eng::SIG)
            .rev()
            .map(|sig| eng::eng_sig(v, unit, sig, ascii))
            .find(|s| s.chars().count() <= width)
    };
    let same = |a: f64, b: f64| {
        (2..=eng::SIG)
            .rev()
            .find_map(|sig| {
                let (x, y) = (
                    eng::eng_sig(a, unit, sig, ascii),
                    eng::eng_sig(b, unit, sig, ascii),
                );
                (x.chars().count() <= width && y.chars().count() <= width).then_some((x, y))
            })
            .unwrap_or_else(|| (fmt(a).unwrap_or_default(), fmt(b).unwrap_or_default()))
    };
    if hi > lo {
        let (top, bottom) = same(hi, lo);
        return ([lo, hi], vec![bottom, top]);
    }
    let d = if lo != 0.0 { lo.abs() * 0.1 } else { 1e-6 };
    let label = fmt(lo).unwrap_or_default();
    ([lo - d, hi + d], vec![String::new(), label, String::new()])
}

/// A value on a chart's y axis: itself, or on a log scale log₁₀ |v| (None for 0 and
/// non-finite values, which a log scale leaves out).
fn on_axis(v: f64, log: bool) -> Option<f64> {
    match (v.is_finite(), log) {
        (false, _) => None,
        (true, false) => Some(v),
        (true, true) => (v != 0.0).then(|| v.abs().log10()),
    }
}

/// The y axis of a chart: its bounds on the axis and its labels, low to high. `ext`: the
/// extremes of the shown run's points on the axis; `centre`: where a y zoom centres (the
/// first series' value at the cursor, on the axis); `zoom`: the range is the data's / 2^zoom;
/// on a log scale the labels are the values 10^bound.
fn y_axis(
    ext: Option<[f64; 2]>,
    (centre, zoom, log): (Option<f64>, u32, bool),
    (unit, fixed): (&str, bool),
    ascii: bool,
) -> ([f64; 2], Vec<String>) {
    let w = LABEL_W as usize - 1;
    let Some([lo, hi]) = ext else {
        return value_axis(None, unit, w, ascii);
    };
    let value_axis = |b: Option<[f64; 2]>, unit: &str, w: usize, ascii: bool| {
        if fixed {
            fixed_axis(b, unit, w)
        } else {
            value_axis(b, unit, w, ascii)
        }
    };
    let bounds = if zoom == 0 {
        [lo, hi]
    } else {
        let mid = centre
            .filter(|c| (lo..=hi).contains(c))
            .unwrap_or(0.5 * (lo + hi));
        let half = 0.5 * (hi - lo) / f64::from(1u32 << zoom.min(30));
        [mid - half, mid + half]
    };
    if !log {
        return value_axis(Some(bounds), unit, w, ascii);
    }
    let lin = bounds.map(|b| 10f64.powf(b));
    let (_, labels) = value_axis(Some(lin), unit, w, ascii);
    let b = if bounds[1] > bounds[0] {
        bounds
    } else {
        [bounds[0] - 0.05, bounds[1] + 0.05]
    };
    (b, labels)
}

/// [`value_axis`] in a unit that takes no prefix (θ in mrad or degrees): plain numbers.
fn fixed_axis(ext: Option<[f64; 2]>, unit: &str, width: usize) -> ([f64; 2], Vec<String>) {
    let Some([lo, hi]) = ext else {
        return ([-1.0, 1.0], vec![String::new(), String::new()]);
    };
    let fmt = |v: f64| {
        (1..=eng::SIG)
            .rev()
            .map(|sig| format!("{} {unit}", chart::fmt_sig(v, sig)))
            .find(|s| s.chars().count() <= width)
            .unwrap_or_default()
    };
    if hi > lo {
        return ([lo, hi], vec![fmt(lo), fmt(hi)]);
    }
    let d = if lo != 0.0 { lo.abs() * 0.1 } else { 1e-6 };
    (
        [lo - d, hi + d],
        vec![String::new(), fmt(lo), String::new()],
    )
}

/// The extremes of each overlaid run's points that reach beyond the axis `yb` (in the chart's
/// unit, not on the axis): (run number, [low, high]).
fn beyond(series: &[Series], yb: [f64; 2], log: bool) -> Vec<(u64, [f64; 2])> {
    let mut out: Vec<(u64, [f64; 2])> = Vec::new();
    for s in series {
        let Some(n) = s.overlay else { continue };
        let Some(e) = extremes(s.data.iter().map(|p| &p.1)) else {
            continue;
        };
        match out.iter_mut().find(|o| o.0 == n) {
            Some(o) => o.1 = [o.1[0].min(e[0]), o.1[1].max(e[1])],
            None => out.push((n, e)),
        }
    }
    let outside = |v: f64| on_axis(v, log).is_some_and(|a| a < yb[0] || a > yb[1]);
    out.retain(|(_, [lo, hi])| outside(*lo) || outside(*hi));
    out
}

/// Draws one time chart: header (title, legend, values at the cursor, the overlaid runs'
/// extremes beyond the axis), series, zero line, cursor. `spec`: its y zoom and log scale;
/// `focused`: the chart the keys `p`, `Y`, `y`, `g` act on (its title in reverse video).
fn draw_time_chart(
    frame: &mut Frame,
    area: Rect,
    (t0, t1, tc): (f64, f64, f64),
    c: TimeChart,
    (spec, focused): (&ChartSpec, bool),
    th: &Theme,
) {
    if area.height < 2 {
        return;
    }
    let (log, unit, series) = (spec.log, c.unit.as_str(), c.series);
    let [head, body] = Layout::vertical([Constraint::Length(1), Constraint::Min(0)]).areas(area);
    // the axis is the shown run's (the overlaid runs' when it shows nothing yet)
    let shown = |s: &&Series| s.overlay.is_none();
    let values = |all: bool| -> Vec<f64> {
        (series.iter().filter(|s| all || shown(s)))
            .flat_map(|s| s.data.iter().map(|p| p.1))
            .collect()
    };
    let mut raw = values(false);
    if extremes(&raw).is_none() {
        raw = values(true);
    }
    let ext = extremes(&raw);
    let big = ext.map_or(0.0, |[a, b]| a.abs().max(b.abs()));
    let scale = if c.fixed {
        Scale::fixed(big, unit)
    } else {
        Scale::new(big, unit, th.ascii)
    };
    let on: Vec<f64> = raw.iter().filter_map(|&v| on_axis(v, log)).collect();
    let centre = (series.iter().find(shown))
        .and_then(|s| s.now)
        .and_then(|v| on_axis(v, log));
    let axis = (centre, spec.y_zoom, log);
    let (yb, labels) = y_axis(extremes(&on), axis, (unit, c.fixed), th.ascii);
    let title = if log {
        format!("log|{}|", c.title)
    } else {
        c.title.clone()
    };
    let style = if focused {
        th.bold().patch(th.selected())
    } else {
        th.bold()
    };
    let far = beyond(&series, yb, log);
    let line = chart_header(
        (&title, style),
        &scale,
        &series,
        &far,
        head.width as usize,
        th,
    );
    frame.render_widget(Paragraph::new(line), head);
    if body.height == 0 {
        return;
    }
    let data: Vec<Vec<(f64, f64)>> = (series.iter())
        .map(|s| {
            (s.data.iter())
                .filter_map(|&(t, y)| on_axis(y, log).map(|y| (t, y)))
                .collect()
        })
        .collect();
    let zero = [(t0, 0.0), (t1, 0.0)];
    let cursor = [(tc, yb[0]), (tc, yb[1])];
    let marker = th.marker();
    let line = |data| {
        Dataset::default()
            .marker(marker)
            .graph_type(GraphType::Line)
            .data(data)
    };
    let has_zero = !log && yb[0] < 0.0 && yb[1] > 0.0;
    let mut ds: Vec<Dataset> = Vec::new();
    if has_zero {
        ds.push(line(&zero).marker(th.zero_marker()).style(th.dim()));
    }
    // without colour, each series by its own mark (the overlaid runs', the k-th current one's)
    let mut k = 0;
    ds.extend(series.iter().zip(&data).map(|(s, d)| {
        let marker = if s.overlay.is_some() {
            th.previous_marker()
        } else {
            k += 1;
            th.series_marker(k - 1)
        };
        line(d).marker(marker).style(s.style)
    }));
    if tc >= t0 && tc <= t1 {
        ds.push(line(&cursor).marker(th.cursor_marker()).style(th.cursor()));
    }
    let w = LABEL_W as usize;
    let labels: Vec<Line> = labels
        .iter()
        .map(|l| Line::from(format!("{l:>w$}")))
        .collect();
    let chart = Chart::new(ds)
        .x_axis(Axis::default().bounds([t0, t1]))
        .y_axis(Axis::default().bounds(yb).labels(labels).style(th.dim()))
        .legend_position(None);
    frame.render_widget(chart, body);
    th.own_ascii(frame.buffer_mut(), body);
    if has_zero {
        zero_label(frame, body, yb, th);
    }
}

/// `0` in the label column at the row of the zero line (unless that is the top or bottom row,
/// which carry the extremes).
fn zero_label(frame: &mut Frame, body: Rect, yb: [f64; 2], th: &Theme) {
    let dots = match th.marker() {
        Marker::Braille => 4.0,
        Marker::HalfBlock => 2.0,
        _ => 1.0,
    };
    let res = f64::from(body.height) * dots;
    // the canvas rounds to its dots, as it drew the line
    let dot = (yb[1] * (res - 1.0) / (yb[1] - yb[0])).round();
    let row = (dot / dots).floor() as u16;
    if row == 0 || row + 1 >= body.height || body.width <= LABEL_W {
        return;
    }
    let w = LABEL_W as usize;
    frame.render_widget(
        Paragraph::new(Line::styled(format!("{:>w$}", "0"), th.dim())),
        Rect::new(body.x, body.y + row, LABEL_W, 1),
    );
}
