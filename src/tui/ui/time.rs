//! The time charts (rotation, gaps, x/y) with the previous run underneath and the time
//! cursor, above the event strip.

use super::cache::Cache;
use super::common::{LABEL_W, Overlay, Theme, overlay_runs, shown_run};
use super::timeline::draw_timeline;
use crate::output::EventKind;
use crate::tui::app::App;
use crate::tui::chart;
use crate::tui::eng::{self, Scale};
use crate::tui::nav;
use crate::tui::run_data::RunData;
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::Style;
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Axis, Chart, Dataset, GraphType, Paragraph};

struct Series {
    name: String,
    style: Style,
    data: Vec<(f64, f64)>,
    /// The number of the overlaid run it belongs to (None: the shown run).
    overlay: Option<u64>,
    /// Its value at the cursor.
    now: Option<f64>,
}

/// What the series of one panel are drawn from: the runs, the time window, the columns.
struct Window<'a> {
    run: &'a RunData,
    overlays: Vec<Overlay<'a>>,
    t0: f64,
    t1: f64,
    /// The time of the values at the cursor in the headers ([`super::Cache::readout_time`]).
    rt: f64,
    cols: u16,
    /// The model's length unit (m, in).
    len: &'static str,
}

/// One chart: title, unit, series.
type TimeChart = (String, String, Vec<Series>);

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
        len: nav::length_unit(app),
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
        draw_time_chart(frame, rects[i], (t0, t1, tc), &title, &unit, series, th);
    }
    let kn = nav::force_unit(app);
    draw_timeline(frame, rects[n_charts], run, (t0, t1, tc, rt), kn, cache, th);
}

/// One series of `r` (column `y`, cached as `what`) over the window, with its value at the
/// cursor; `overlay`: the number of the overlaid run it belongs to.
fn series(
    sp: &Window,
    cache: &mut Cache,
    (r, what, y): (&RunData, String, &[f64]),
    (name, style): (String, Style),
    overlay: Option<u64>,
) -> Series {
    Series {
        name,
        style,
        data: cache.decimated(r, &what, y, sp.t0, sp.t1, sp.cols),
        overlay,
        now: value_at(r, y, sp.rt),
    }
}

/// The rotation θ(t) (and the overlaid runs').
fn rotation_chart(sp: &Window, cache: &mut Cache, th: &Theme) -> Option<TimeChart> {
    let run = sp.run;
    let r = run.rot?;
    let name = run.dof_names[r].clone();
    let mut s = Vec::new();
    for o in &sp.overlays {
        let p = o.data;
        if let Some(k) = p.dof(&name) {
            let col = (p, format!("q{k}"), p.q[k].as_slice());
            s.push(series(
                sp,
                cache,
                col,
                (name.clone(), o.style),
                Some(o.number),
            ));
        }
    }
    let col = (run, format!("q{r}"), run.q[r].as_slice());
    s.push(series(sp, cache, col, (name.clone(), th.series(0)), None));
    Some((name.clone(), unit_of(&name, sp.len).into(), s))
}

/// The gaps g_N(t) of all contacts (and the overlaid runs').
fn gap_chart(sp: &Window, cache: &mut Cache, th: &Theme) -> Option<TimeChart> {
    let run = sp.run;
    if run.contact_names.is_empty() {
        return None;
    }
    let mut s = Vec::new();
    for o in &sp.overlays {
        let p = o.data;
        for n in &run.contact_names {
            if let Some(i) = p.contact_names.iter().position(|m| m == n) {
                let col = (p, format!("g{i}"), p.gap[i].as_slice());
                s.push(series(sp, cache, col, (n.clone(), o.style), Some(o.number)));
            }
        }
    }
    for (i, n) in run.contact_names.iter().enumerate() {
        let col = (run, format!("g{i}"), run.gap[i].as_slice());
        s.push(series(sp, cache, col, (n.clone(), th.series(i)), None));
    }
    Some(("gaps g_N".into(), sp.len.into(), s))
}

/// x and y of the rotating body (and the overlaid runs').
fn xy_chart(sp: &Window, cache: &mut Cache, th: &Theme) -> Option<TimeChart> {
    let run = sp.run;
    if run.xy.is_empty() {
        return None;
    }
    let mut s = Vec::new();
    for o in &sp.overlays {
        let p = o.data;
        for &k in &run.xy {
            if let Some(pk) = p.dof(&run.dof_names[k]) {
                let col = (p, format!("q{pk}"), p.q[pk].as_slice());
                let name = run.dof_names[k].clone();
                s.push(series(sp, cache, col, (name, o.style), Some(o.number)));
            }
        }
    }
    for (i, &k) in run.xy.iter().enumerate() {
        let col = (run, format!("q{k}"), run.q[k].as_slice());
        let name = run.dof_names[k].clone();
        s.push(series(sp, cache, col, (name, th.series(i + 4)), None));
    }
    let names: Vec<&str> = run.xy.iter().map(|&k| run.dof_names[k].as_str()).collect();
    Some((names.join(" / "), sp.len.into(), s))
}

/// The unit of a DOF: rad for a rotation, else `len`.
fn unit_of(dof: &str, len: &'static str) -> &'static str {
    if dof.ends_with(".theta") { "rad" } else { len }
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

/// Draws one time chart: header (title, legend, values at the cursor), series, zero line,
/// cursor.
fn draw_time_chart(
    frame: &mut Frame,
    area: Rect,
    (t0, t1, tc): (f64, f64, f64),
    title: &str,
    unit: &str,
    series: Vec<Series>,
    th: &Theme,
) {
    if area.height < 2 {
        return;
    }
    let [head, body] = Layout::vertical([Constraint::Length(1), Constraint::Min(0)]).areas(area);
    let ext = extremes(series.iter().flat_map(|s| s.data.iter().map(|p| &p.1)));
    let big = ext.map_or(0.0, |[a, b]| a.abs().max(b.abs()));
    let scale = Scale::new(big, unit, th.ascii);
    frame.render_widget(
        Paragraph::new(chart_header(
            title,
            &scale,
            &series,
            head.width as usize,
            th,
        )),
        head,
    );
    if body.height == 0 {
        return;
    }
    let (yb, labels) = value_axis(ext, unit, LABEL_W as usize - 1, th.ascii);
    let zero = [(t0, 0.0), (t1, 0.0)];
    let cursor = [(tc, yb[0]), (tc, yb[1])];
    let marker = th.marker();
    let line = |data| {
        Dataset::default()
            .marker(marker)
            .graph_type(GraphType::Line)
            .data(data)
    };
    let has_zero = yb[0] < 0.0 && yb[1] > 0.0;
    let mut ds: Vec<Dataset> = Vec::new();
    if has_zero {
        ds.push(line(&zero).marker(th.zero_marker()).style(th.dim()));
    }
    // without colour, each series by its own mark (the overlaid runs', the k-th current one's)
    let mut k = 0;
    ds.extend(series.iter().map(|s| {
        let marker = if s.overlay.is_some() {
            th.previous_marker()
        } else {
            k += 1;
            th.series_marker(k - 1)
        };
        line(&s.data).marker(marker).style(s.style)
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

/// The chart's header line: title [unit of the readouts], and the value of each series at the
/// cursor in that unit, with one precision — named when they fit, the earlier run's values
/// after them; what does not fit whole is left out.
fn chart_header(
    title: &str,
    scale: &Scale,
    series: &[Series],
    width: usize,
    th: &Theme,
) -> Line<'static> {
    let head = Span::styled(format!("{title} [{}]", scale.unit), th.bold());
    // in ASCII a dash would read as a minus sign: the values alone, in the legend's order
    let (glyph, dotted) = if th.ascii { ("", "") } else { ("━", "┈") };
    let current: Vec<&Series> = series.iter().filter(|s| s.overlay.is_none()).collect();
    let value = |s: &Series| s.now.map_or("—".to_string(), |v| scale.fmt(v));
    let named = current.len() > 1;
    // without colour, the series' own mark (as drawn) before its value
    let sample = |k: usize| {
        if th.marks() {
            format!(" [{}]", th.legend_mark(k))
        } else {
            format!(" {glyph}")
        }
    };
    // names: 2 whole, 1 their initials (left_top: lt), 0 none, 3 the initials alone
    let item = |(k, s): (usize, &&Series), names: u8| -> Vec<Span<'static>> {
        let mut v = vec![Span::styled(sample(k), s.style)];
        match names {
            2 => v.push(Span::raw(format!("{} ", s.name))),
            1 => v.push(Span::raw(format!("{} ", initials(&s.name)))),
            // without colour a series needs its name more than its value
            3 => {
                v.push(Span::raw(initials(&s.name)));
                return v;
            }
            _ => {}
        }
        v.push(Span::styled(value(s), th.cursor()));
        v
    };
    // one item per overlaid run: its number and its values
    let mut numbers: Vec<(u64, Style)> = Vec::new();
    for s in series {
        if let Some(n) = s.overlay
            && !numbers.iter().any(|(m, _)| *m == n)
        {
            numbers.push((n, s.style));
        }
    }
    let prev_items: Vec<Vec<Span<'static>>> = (numbers.iter())
        .map(|&(n, style)| {
            let vals: Vec<String> = (series.iter())
                .filter(|s| s.overlay == Some(n))
                .map(value)
                .collect();
            let dotted = if th.marks() {
                format!("[{}]", th.previous_mark())
            } else {
                dotted.to_string()
            };
            vec![Span::styled(
                format!(" {dotted}#{n} {}", vals.join(" ")),
                style,
            )]
        })
        .collect();
    let items = |names: u8, with_prev: bool| -> Vec<Vec<Span<'static>>> {
        let mut v: Vec<Vec<Span>> = current
            .iter()
            .enumerate()
            .map(|ks| item(ks, names))
            .collect();
        if with_prev {
            v.extend(prev_items.iter().cloned());
        }
        v
    };
    let wide = |it: &[Span]| it.iter().map(|s| s.content.chars().count()).sum::<usize>();
    let room = width.saturating_sub(wide(std::slice::from_ref(&head)));
    let total = |v: &Vec<Vec<Span>>| v.iter().map(|i| wide(i)).sum::<usize>();
    let mut variants = Vec::new();
    if named {
        variants.extend([
            items(2, true),
            items(2, false),
            items(1, true),
            items(1, false),
        ]);
        if th.marks() {
            variants.extend([items(3, true), items(3, false)]);
        }
    }
    variants.extend([items(0, true), items(0, false)]);
    let chosen = variants.iter().find(|v| total(v) <= room).cloned();
    let mut spans = vec![head];
    match chosen {
        Some(v) => spans.extend(v.into_iter().flatten()),
        None => {
            let mut used = 0;
            for it in items(0, false) {
                if used + wide(&it) > room {
                    break;
                }
                used += wide(&it);
                spans.extend(it);
            }
        }
    }
    Line::from(spans)
}

/// A series name by its initials: the first letter of each `_`-separated word of its last
/// dotted part (`left_top` → `lt`, `deck.x` → `x`).
fn initials(name: &str) -> String {
    let last = name.rsplit('.').next().unwrap_or(name);
    last.split('_').filter_map(|w| w.chars().next()).collect()
}
