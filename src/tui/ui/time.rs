//! The time charts with the overlaid runs underneath and the time cursor, above the event
//! strip: three charts of any series a run records (by default the rotation, the gaps, x and
//! y; [`crate::tui::chart_prefs`]), each with its y zoom and log scale, θ in the unit chosen;
//! the y axis is the shown run's, the overlaid runs' extremes beyond it are in the header.
//! Each is a [`crate::plot::Chart`] of the decimated series ([`Cache::decimated`]) drawn by
//! [`super::line_plot`] under the chart's header ([`chart_header`]).

use super::cache::Cache;
use super::chart_head::{Series, chart_header};
use super::common::{
    LABEL_W, Overlay, PREVIOUS_MARK, Theme, overlay_runs, series_glyph, shown_run,
};
use super::line_plot::{Head, Look, draw_line_plot, spread_labels};
use super::timeline::draw_timeline;
use crate::output::EventKind;
use crate::plot;
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
use ratatui::widgets::Paragraph;

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

/// The values the y axis spans: the shown run's, or the overlaid runs' while it shows nothing.
fn axis_values(series: &[Series]) -> Vec<f64> {
    let values = |all: bool| -> Vec<f64> {
        (series.iter().filter(|s| all || s.overlay.is_none()))
            .flat_map(|s| s.data.iter().map(|p| p.1))
            .collect()
    };
    let raw = values(false);
    if extremes(&raw).is_some() {
        raw
    } else {
        values(true)
    }
}

/// The chart a time chart is drawn from, and what the workbench adds to it: the library's
/// [`plot::Chart`] of the series over the window `t0..t1` (a log scale's of their magnitudes),
/// the y axis's range (the y zoom around the first series' value at the cursor) and the zero
/// line; the look: the time cursor at `tc`, the y labels in the chart's unit, the series'
/// styles and marks. Also the y axis's bounds on the axis (log₁₀ on a log scale).
fn time_plot(
    c: &TimeChart,
    (t0, t1, tc): (f64, f64, f64),
    spec: &ChartSpec,
    th: &Theme,
) -> (plot::Chart, Look, [f64; 2]) {
    let log = spec.log;
    let on: Vec<f64> = (axis_values(&c.series).into_iter())
        .filter_map(|v| on_axis(v, log))
        .collect();
    let centre = (c.series.iter().find(|s| s.overlay.is_none()))
        .and_then(|s| s.now)
        .and_then(|v| on_axis(v, log));
    let axis = (centre, spec.y_zoom, log);
    let (yb, labels) = y_axis(extremes(&on), axis, (&c.unit, c.fixed), th.ascii);
    // a bound on the axis as a value of the data
    let value = |a: f64| if log { 10f64.powf(a) } else { a };
    let title = if log {
        format!("log|{}|", c.title)
    } else {
        c.title.clone()
    };
    let y = if log {
        plot::Axis::log(&title, &c.unit)
    } else {
        plot::Axis::linear(&title, &c.unit)
    };
    let x = plot::Axis::linear("t", "s").with_range(t0, t1);
    let mut chart = plot::Chart::new(&title, x, y.with_range(value(yb[0]), value(yb[1])));
    let mut y_labels = spread_labels(yb, &labels, value);
    if !log && yb[0] < 0.0 && yb[1] > 0.0 {
        chart.lines.push(plot::RefLine::horizontal(0.0, "", 7));
        y_labels.push((0.0, "0".into()));
    }
    // without colour, each series by its own mark (the overlaid runs', the k-th current one's)
    let mut k = 0;
    for s in &c.series {
        let glyph = if s.overlay.is_some() {
            PREVIOUS_MARK
        } else {
            k += 1;
            series_glyph(k - 1)
        };
        let points = if log {
            s.data.iter().map(|&(t, y)| (t, y.abs())).collect()
        } else {
            s.data.clone()
        };
        chart
            .series
            .push(plot::Series::line(&s.name, points).glyph(glyph));
    }
    let look = Look {
        legend: false,
        cursor: (t0..=t1).contains(&tc).then_some(tc),
        time_cursor: true,
        x_axis: false,
        label_w: LABEL_W,
        y_labels,
        styles: c.series.iter().map(|s| s.style).collect(),
        glyph_lines: true,
        ..Look::default()
    };
    (chart, look, yb)
}

/// Draws one time chart from its [`time_plot`]: header (title, legend, values at the cursor,
/// the overlaid runs' extremes beyond the axis), series, zero line, cursor. `spec`: its y
/// zoom and log scale; `focused`: the chart the keys `p`, `Y`, `y`, `g` act on (its title in
/// reverse video).
fn draw_time_chart(
    frame: &mut Frame,
    area: Rect,
    window: (f64, f64, f64),
    c: TimeChart,
    (spec, focused): (&ChartSpec, bool),
    th: &Theme,
) {
    if area.height < 2 {
        return;
    }
    let (chart, mut look, yb) = time_plot(&c, window, spec, th);
    // the readouts' unit and precision from the shown run's largest magnitude
    let ext = extremes(&axis_values(&c.series));
    let big = ext.map_or(0.0, |[a, b]| a.abs().max(b.abs()));
    let scale = if c.fixed {
        Scale::fixed(big, &c.unit)
    } else {
        Scale::new(big, &c.unit, th.ascii)
    };
    let style = if focused {
        th.bold().patch(th.selected())
    } else {
        th.bold()
    };
    let far = beyond(&c.series, yb, spec.log);
    let head = chart_header(
        (&chart.title, style),
        &scale,
        &c.series,
        &far,
        area.width as usize,
        th,
    );
    look.head = Head::Line(head);
    draw_line_plot(frame, area, &chart, &look, th);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tui::chart_prefs::Units;
    use crate::tui::runs::series::Kind;

    /// A run of θ over 0 … 1 s (values of both signs, one 0) and another one to overlay.
    fn runs() -> (RunData, RunData) {
        let names = || vec!["deck.theta".to_string(), "deck.x".to_string()];
        let mut a = RunData::new(2, "#2".into(), names(), vec![], vec![], 1.0);
        a.t = vec![0.0, 0.25, 0.5, 0.75, 1.0];
        a.q[0] = vec![0.0, 2e-3, -1e-3, 4e-3, 3e-3];
        a.q[1] = vec![0.0; 5];
        let mut b = RunData::new(1, "#1".into(), names(), vec![], vec![], 1.0);
        b.token = 1;
        b.t = a.t.clone();
        b.q[0] = vec![0.0, 9e-3, -5e-3, 1e-3, 0.0];
        b.q[1] = vec![0.0; 5];
        (a, b)
    }

    /// The chart of θ of run `a` with run `b` overlaid, the cursor at 0.5 s.
    fn theta_chart(a: &RunData, b: &RunData, spec: &ChartSpec, th: &Theme) -> (plot::Chart, Look) {
        let sp = Window {
            run: a,
            overlays: vec![Overlay {
                data: b,
                number: 1,
                style: th.previous(),
            }],
            t0: 0.0,
            t1: 1.0,
            rt: 0.5,
            cols: 80,
            units: Units {
                length: "m",
                force: "N",
                energy: "J",
            },
            theta: ThetaUnit::Rad,
        };
        let ids = [SeriesId::new(Kind::Q, "deck.theta")];
        let c = chart_of(&sp, &mut Cache::default(), th, 0, &ids).expect("a chart");
        let (chart, look, _) = time_plot(&c, (0.0, 1.0, 0.5), spec, th);
        (chart, look)
    }

    #[test]
    fn a_time_chart_is_a_plot_chart_of_the_runs_over_the_window() {
        let (a, b) = runs();
        let th = Theme {
            color: true,
            ascii: false,
        };
        let (c, look) = theta_chart(&a, &b, &ChartSpec::default(), &th);
        // the overlaid run's series under the shown run's, each point a sample
        assert_eq!(c.series.len(), 2);
        let pts = |r: &RunData| -> Vec<(f64, f64)> {
            r.t.iter().copied().zip(r.q[0].iter().copied()).collect()
        };
        assert_eq!(c.series[0].points, pts(&b));
        assert_eq!(c.series[1].points, pts(&a));
        assert_eq!(c.series[0].glyph, PREVIOUS_MARK);
        assert_eq!(look.styles, vec![th.previous(), th.series(0)]);
        // the window on x; on y the shown run's extremes, not the overlaid run's
        assert_eq!(c.x.range, Some((0.0, 1.0)));
        assert_eq!(c.y.scale, plot::Scale::Linear);
        assert_eq!(c.y.range, Some((-1e-3, 4e-3)));
        assert_eq!(c.title, "deck.theta");
        // the zero line and its label, the time cursor, no x axis (the event strip's)
        assert_eq!(c.lines, vec![plot::RefLine::horizontal(0.0, "", 7)]);
        assert!(look.y_labels.iter().any(|l| *l == (0.0, "0".to_string())));
        assert_eq!((look.cursor, look.time_cursor), (Some(0.5), true));
        assert!(!look.x_axis && look.glyph_lines);
    }

    #[test]
    fn a_log_time_chart_plots_the_magnitudes_on_a_log_axis() {
        let (a, b) = runs();
        let th = Theme {
            color: false,
            ascii: true,
        };
        let spec = ChartSpec {
            log: true,
            ..ChartSpec::default()
        };
        let (c, look) = theta_chart(&a, &b, &spec, &th);
        assert_eq!(c.y.scale, plot::Scale::Log);
        assert_eq!(c.title, "log|deck.theta|");
        // |θ| of the shown run (its 0 left to the axis, which leaves it out)
        let mags: Vec<f64> = a.q[0].iter().map(|v| v.abs()).collect();
        let ys: Vec<f64> = c.series[1].points.iter().map(|p| p.1).collect();
        assert_eq!(ys, mags);
        let (lo, hi) = c.y.range.expect("a fixed range");
        assert!(
            (lo - 1e-3).abs() < 1e-12 && (hi - 4e-3).abs() < 1e-12,
            "{lo} {hi}"
        );
        // no zero line on a log axis; each series by its mark
        assert!(c.lines.is_empty());
        assert_eq!((c.series[0].glyph, c.series[1].glyph), (':', '.'));
        assert_eq!(look.y_labels.len(), 2);
    }

    #[test]
    fn a_y_zoom_narrows_the_charts_range_around_the_cursors_value() {
        let (a, b) = runs();
        let th = Theme {
            color: true,
            ascii: false,
        };
        let spec = ChartSpec {
            y_zoom: 1,
            ..ChartSpec::default()
        };
        let (c, _) = theta_chart(&a, &b, &spec, &th);
        // half the range, centred on θ at 0.5 s (-1e-3)
        let (lo, hi) = c.y.range.expect("a fixed range");
        assert!(
            (lo - -2.25e-3).abs() < 1e-12 && (hi - 0.25e-3).abs() < 1e-12,
            "{lo} {hi}"
        );
    }
}
