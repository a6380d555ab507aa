//! Drawing: `draw(frame, app)` renders the whole screen from the state. Charts are decimated
//! per screen column before datasets are built, and the decimated series and event strips are
//! cached per run length, time window and plot size, so a frame stays light with 10⁵-sample
//! histories.

use super::app::{
    App, Confirm, Digest, MIN_HEIGHT, MIN_WIDTH, Mode, RunData, RunStatus, StatusKind, View,
};
use super::chart::{self, bounds, column_of, downsample_minmax, fmt_num};
use super::keymap;
use crate::output::{ContactState, EventKind};
use ratatui::Frame;
use ratatui::layout::{Alignment, Constraint, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::symbols::{Marker, border};
use ratatui::text::{Line, Span};
use ratatui::widgets::canvas::{Canvas, Context, Line as CLine};
use ratatui::widgets::{
    Axis, Block, Chart, Clear, Dataset, GraphType, Paragraph, Row, Table, Wrap,
};
use std::collections::HashMap;

/// Width of the y-axis labels of the time charts (the event strip uses the same offset).
const LABEL_W: u16 = 9;

/// Drawing caches (decimated series, loops, scales, event strips), each entry keyed by what
/// it depends on (run, its length, time window, plot size, …).
#[derive(Default)]
pub struct Cache {
    series: HashMap<String, (Key, Points)>,
    strips: HashMap<u64, (Key, Vec<Vec<char>>)>,
    memo: HashMap<String, (Vec<u64>, Points)>,
}

type Points = Vec<(f64, f64)>;

/// Cached computation of points under `name`, recomputed when `key` changes.
fn memo(
    app: &App,
    name: String,
    key: Vec<u64>,
    f: impl FnOnce() -> Vec<(f64, f64)>,
) -> Vec<(f64, f64)> {
    if let Some((k, v)) = app.cache.borrow().memo.get(&name)
        && *k == key
    {
        return v.clone();
    }
    let v = f();
    let mut cache = app.cache.borrow_mut();
    if cache.memo.len() > 64 {
        cache.memo.clear();
    }
    cache.memo.insert(name, (key, v.clone()));
    v
}

#[derive(Clone, Copy, PartialEq, Debug)]
struct Key {
    len: usize,
    events: usize,
    t0: u64,
    t1: u64,
    cols: u16,
    extra: u64,
}

/// Colours: the 16 named ANSI colours, or none at all (NO_COLOR).
struct Theme {
    color: bool,
    ascii: bool,
}

const PALETTE: [Color; 8] = [
    Color::Cyan,
    Color::Yellow,
    Color::Green,
    Color::Magenta,
    Color::Blue,
    Color::Red,
    Color::LightCyan,
    Color::LightGreen,
];

impl Theme {
    fn fg(&self, c: Color) -> Style {
        if self.color {
            Style::default().fg(c)
        } else {
            Style::default()
        }
    }
    fn series(&self, i: usize) -> Style {
        self.fg(PALETTE[i % PALETTE.len()])
    }
    fn previous(&self) -> Style {
        if self.color {
            Style::default().fg(Color::DarkGray)
        } else {
            Style::default().add_modifier(Modifier::DIM)
        }
    }
    fn cursor(&self) -> Style {
        if self.color {
            Style::default().fg(Color::LightRed)
        } else {
            Style::default().add_modifier(Modifier::BOLD)
        }
    }
    fn bold(&self) -> Style {
        Style::default().add_modifier(Modifier::BOLD)
    }
    fn dim(&self) -> Style {
        if self.color {
            Style::default().fg(Color::DarkGray)
        } else {
            Style::default().add_modifier(Modifier::DIM)
        }
    }
    fn status(&self, k: StatusKind) -> Style {
        match k {
            StatusKind::Info => Style::default(),
            StatusKind::Ok => self.fg(Color::Green),
            StatusKind::Warn => self.fg(Color::Yellow).add_modifier(Modifier::BOLD),
            StatusKind::Error => self.fg(Color::Red).add_modifier(Modifier::BOLD),
        }
    }
    fn selected(&self) -> Style {
        Style::default().add_modifier(Modifier::REVERSED)
    }
    fn marker(&self) -> Marker {
        if self.ascii {
            Marker::Dot
        } else {
            Marker::Braille
        }
    }
    fn per_cell(&self) -> usize {
        if self.ascii { 1 } else { 2 }
    }
    fn border(&self) -> border::Set<'static> {
        if self.ascii {
            border::Set {
                top_left: "+",
                top_right: "+",
                bottom_left: "+",
                bottom_right: "+",
                vertical_left: "|",
                vertical_right: "|",
                horizontal_top: "-",
                horizontal_bottom: "-",
            }
        } else {
            border::PLAIN
        }
    }
    fn block<'a>(&self, title: impl Into<Line<'a>>) -> Block<'a> {
        Block::bordered()
            .border_set(self.border())
            .border_style(self.dim())
            .title(title.into().style(self.bold()))
    }
}

fn theme(app: &App) -> Theme {
    Theme {
        color: app.opts.color,
        ascii: app.ascii,
    }
}

/// Renders the workbench.
pub fn draw(frame: &mut Frame, app: &App) {
    let area = frame.area();
    let th = theme(app);
    if area.width < MIN_WIDTH || area.height < MIN_HEIGHT {
        draw_too_small(frame, area, &th);
        return;
    }
    let [header, mut body, status, hints] = Layout::vertical([
        Constraint::Length(1),
        Constraint::Min(0),
        Constraint::Length(1),
        Constraint::Length(1),
    ])
    .areas(area);
    draw_header(frame, header, app, &th);
    if let Some(le) = &app.load_error {
        let h = if body.height >= 18 { 5 } else { 4 };
        let [banner, rest] =
            Layout::vertical([Constraint::Length(h), Constraint::Min(0)]).areas(body);
        draw_error(frame, banner, le, &th);
        body = rest;
    }
    match app.view {
        View::Charts => draw_charts(frame, body, app, &th),
        View::Form => draw_form(frame, body, app, &th),
    }
    draw_status(frame, status, app, &th);
    draw_hints(frame, hints, app, &th);
    match &app.mode {
        Mode::Help => draw_help(frame, area, &th),
        Mode::Confirm(c) => draw_confirm(frame, area, app, c, &th),
        _ => {}
    }
}

fn draw_too_small(frame: &mut Frame, area: Rect, th: &Theme) {
    let lines = vec![
        Line::styled("terminal too small", th.status(StatusKind::Warn)),
        Line::from(format!("{}×{}", area.width, area.height)),
        Line::from(format!("deckspin needs {MIN_WIDTH}×{MIN_HEIGHT}")),
        Line::from("enlarge it, or q to quit"),
    ];
    let h = (lines.len() as u16).min(area.height);
    let y = area.y + area.height.saturating_sub(h) / 2;
    let r = Rect::new(area.x, y, area.width, h);
    frame.render_widget(Paragraph::new(lines).alignment(Alignment::Center), r);
}

fn gauge(frac: f64, width: usize, ascii: bool) -> String {
    let frac = frac.clamp(0.0, 1.0);
    let cells = frac * width as f64;
    let full = cells.floor() as usize;
    let mut s = String::new();
    if ascii {
        s.push('[');
        s.push_str(&"#".repeat(full));
        s.push_str(&" ".repeat(width - full));
        s.push(']');
    } else {
        const PART: [&str; 8] = ["", "▏", "▎", "▍", "▌", "▋", "▊", "▉"];
        s.push('▕');
        s.push_str(&"█".repeat(full));
        let mut used = full;
        if full < width {
            let p = ((cells - full as f64) * 8.0).floor() as usize;
            if p > 0 {
                s.push_str(PART[p]);
                used += 1;
            }
        }
        s.push_str(&" ".repeat(width - used));
        s.push('▏');
    }
    s
}

fn run_progress(app: &App, th: &Theme) -> Line<'static> {
    let Some(r) = &app.current else {
        return Line::styled("no run", th.dim());
    };
    let ev = r.events.len();
    let label = format!("run {}", r.id);
    match &r.status {
        RunStatus::Running | RunStatus::Cancelling => {
            let mut spans = vec![
                Span::styled(label, th.bold()),
                Span::raw(" "),
                Span::styled(
                    gauge(r.t_sim / r.t_end.max(1e-300), 10, th.ascii),
                    th.fg(Color::Cyan),
                ),
                Span::raw(format!(
                    " {}/{} s · {ev} events",
                    fmt_t(r.t_sim),
                    fmt_t(r.t_end)
                )),
            ];
            if r.status == RunStatus::Cancelling {
                spans.push(Span::styled(" · cancelling", th.status(StatusKind::Warn)));
            }
            Line::from(spans)
        }
        RunStatus::Finished => Line::from(vec![
            Span::styled(label, th.bold()),
            Span::styled(" done", th.status(StatusKind::Ok)),
            Span::raw(format!(" · {} s · {ev} events", fmt_t(r.t_sim))),
        ]),
        RunStatus::Cancelled => Line::from(vec![
            Span::styled(label, th.bold()),
            Span::styled(
                format!(" cancelled at {} s", fmt_t(r.t_sim)),
                th.status(StatusKind::Warn),
            ),
        ]),
        RunStatus::Failed(_) => Line::from(vec![
            Span::styled(label, th.bold()),
            Span::styled(
                format!(" failed at {} s", fmt_t(r.t_sim)),
                th.status(StatusKind::Error),
            ),
        ]),
    }
}

fn fmt_t(t: f64) -> String {
    format!("{t:.2}")
}

fn draw_header(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let right = run_progress(app, th);
    let rw = (right.width() as u16).min(area.width * 3 / 5);
    let [l, r] = Layout::horizontal([Constraint::Min(0), Constraint::Length(rw + 1)]).areas(area);
    let mut name = app.file_name();
    if app.dirty() {
        name.push_str(" [+]");
    }
    let view = match app.view {
        View::Charts => "charts",
        View::Form => "form",
    };
    let fixed = 8 + 3 + name.chars().count() + 3 + 3 + view.len();
    let room = (l.width as usize).saturating_sub(fixed);
    let mut title = app.title();
    if title.chars().count() > room {
        title = title
            .chars()
            .take(room.saturating_sub(1))
            .collect::<String>()
            + "…";
    }
    let left = Line::from(vec![
        Span::styled("deckspin", th.bold().patch(th.fg(Color::Cyan))),
        Span::styled(" │ ", th.dim()),
        Span::styled(name, th.bold()),
        Span::styled(" │ ", th.dim()),
        Span::raw(title),
        Span::styled(format!(" │ {view}"), th.dim()),
    ]);
    frame.render_widget(Paragraph::new(left), l);
    frame.render_widget(Paragraph::new(right).alignment(Alignment::Right), r);
}

fn draw_error(frame: &mut Frame, area: Rect, le: &super::app::LoadError, th: &Theme) {
    let err = th.status(StatusKind::Error);
    let title = match (le.line, le.column) {
        (Some(l), Some(c)) => {
            format!(" model error at line {l}, column {c} — showing the last good model ")
        }
        _ => " model error — showing the last good model ".to_string(),
    };
    let block = th.block(Line::styled(title, err)).border_style(err);
    let inner = block.inner(area);
    let mut lines = vec![Line::styled(le.detail.clone(), err)];
    if let (Some(l), Some(src)) = (le.line, &le.source_line) {
        let prefix = format!("{l:>5} │ ");
        lines.push(Line::from(vec![
            Span::styled(prefix.clone(), th.dim()),
            Span::raw(src.clone()),
        ]));
        if let Some(c) = le.column {
            let pad = prefix.chars().count() + src.chars().take(c.saturating_sub(1)).count();
            lines.push(Line::styled(format!("{}^", " ".repeat(pad)), err));
        }
    }
    frame.render_widget(block, area);
    frame.render_widget(Paragraph::new(lines), inner);
}

fn draw_status(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let wm = if app.watch_mode.is_empty() {
        String::new()
    } else {
        format!("watch: {}", app.watch_mode)
    };
    let ww = (wm.chars().count() as u16 + 1).min(area.width / 3);
    let [l, r] = Layout::horizontal([Constraint::Min(0), Constraint::Length(ww)]).areas(area);
    frame.render_widget(
        Paragraph::new(Line::styled(app.status.clone(), th.status(app.status_kind))),
        l,
    );
    frame.render_widget(
        Paragraph::new(Line::styled(wm, th.dim())).alignment(Alignment::Right),
        r,
    );
}

fn draw_hints(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let mut spans = Vec::new();
    let mut used = 0usize;
    for (k, h) in keymap::hints(&app.contexts()) {
        let w = k.chars().count() + h.chars().count() + 3;
        if used + w > area.width as usize {
            break;
        }
        spans.push(Span::styled(
            format!(" {k}"),
            th.bold().patch(th.selected()),
        ));
        spans.push(Span::raw(format!(" {h} ")));
        used += w;
    }
    frame.render_widget(Paragraph::new(Line::from(spans)), area);
}

fn centered(area: Rect, w: u16, h: u16) -> Rect {
    let w = w.min(area.width);
    let h = h.min(area.height);
    Rect::new(
        area.x + (area.width - w) / 2,
        area.y + (area.height - h) / 2,
        w,
        h,
    )
}

fn draw_help(frame: &mut Frame, area: Rect, th: &Theme) {
    let groups: Vec<Vec<Line>> = keymap::help()
        .into_iter()
        .map(|(title, rows)| {
            let mut g = vec![Line::styled(
                title.to_string(),
                th.bold().patch(th.fg(Color::Cyan)),
            )];
            for (k, d) in rows {
                g.push(Line::from(vec![
                    Span::styled(format!(" {k:<8}"), th.bold()),
                    Span::raw(d.to_string()),
                ]));
            }
            g
        })
        .collect();
    let all: Vec<Line> = groups.into_iter().flatten().collect();
    let half = all.len().div_ceil(2);
    let (c0, c1) = (all[..half].to_vec(), all[half..].to_vec());
    let rect = centered(area, area.width.min(100), area.height);
    let block = th.block(" help — keys (Esc closes) ");
    let inner = block.inner(rect);
    frame.render_widget(Clear, rect);
    frame.render_widget(block, rect);
    let [a, b] =
        Layout::horizontal([Constraint::Percentage(50), Constraint::Percentage(50)]).areas(inner);
    frame.render_widget(Paragraph::new(c0), a);
    frame.render_widget(Paragraph::new(c1), b);
}

fn draw_confirm(frame: &mut Frame, area: Rect, app: &App, c: &Confirm, th: &Theme) {
    let q = match c {
        Confirm::Reload { .. } => vec![
            format!("{} changed on disk.", app.file_name()),
            "Reload it and discard your unsaved edits?".to_string(),
        ],
        Confirm::Quit => vec!["Quit and lose your unsaved edits?".to_string()],
    };
    let w = (area.width.saturating_sub(8)).min(64);
    let rect = centered(area, w, q.len() as u16 + 4);
    let block = th
        .block(" question ")
        .border_style(th.status(StatusKind::Warn));
    let inner = block.inner(rect);
    frame.render_widget(Clear, rect);
    frame.render_widget(block, rect);
    let mut lines: Vec<Line> = q.into_iter().map(Line::from).collect();
    lines.extend([
        Line::from(""),
        Line::from(vec![
            Span::styled(" y ", th.selected().patch(th.bold())),
            Span::raw(" yes   "),
            Span::styled(" n ", th.selected().patch(th.bold())),
            Span::raw(" no"),
        ]),
    ]);
    frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: true }), inner);
}

// ---------------------------------------------------------------------------------------------
// charts view

fn draw_charts(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let right_w = if area.width >= 100 {
        (area.width * 36 / 100).clamp(30, 60)
    } else {
        (area.width * 35 / 100).max(24)
    };
    let [left, right] =
        Layout::horizontal([Constraint::Min(0), Constraint::Length(right_w)]).areas(area);
    draw_time_panel(frame, left, app, th);
    draw_side_panel(frame, right, app, th);
}

/// The run whose layout (names) drives the charts: the current one, else the previous.
fn shown_run(app: &App) -> Option<&RunData> {
    app.current.as_ref().or(app.previous.as_ref())
}

fn overlay_run(app: &App) -> Option<&RunData> {
    if app.overlay {
        app.previous.as_ref()
    } else {
        None
    }
}

struct Series {
    name: String,
    style: Style,
    data: Vec<(f64, f64)>,
}

fn time_key(r: &RunData, t0: f64, t1: f64, cols: u16) -> Key {
    Key {
        len: r.t.len(),
        events: r.events.len(),
        t0: t0.to_bits(),
        t1: t1.to_bits(),
        cols,
        extra: 0,
    }
}

/// Decimated column of a run (cached).
fn decimated(
    app: &App,
    r: &RunData,
    what: &str,
    y: &[f64],
    t0: f64,
    t1: f64,
    cols: u16,
) -> Vec<(f64, f64)> {
    let key = time_key(r, t0, t1, cols);
    let name = format!("{}:{what}", r.id);
    let mut cache = app.cache.borrow_mut();
    if let Some((k, v)) = cache.series.get(&name)
        && *k == key
    {
        return v.clone();
    }
    let v = downsample_minmax(&r.t, y, t0, t1, cols as usize);
    if cache.series.len() > 256 {
        cache.series.clear();
    }
    cache.series.insert(name, (key, v.clone()));
    v
}

fn draw_time_panel(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
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
    let tl_h = 2 + strip_rows.max(if nc == 0 { 0 } else { 1 });
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

    // rotation
    let mut charts: Vec<(String, String, Vec<Series>)> = Vec::new();
    if let Some(r) = run.rot {
        let name = run.dof_names[r].clone();
        let mut s = Vec::new();
        if let Some(p) = prev
            && let Some(k) = p.dof(&name)
        {
            s.push(Series {
                name: format!("{} (previous)", name),
                style: th.previous(),
                data: decimated(app, p, &format!("q{k}"), &p.q[k], t0, t1, cols),
            });
        }
        s.push(Series {
            name: name.clone(),
            style: th.series(0),
            data: decimated(app, run, &format!("q{r}"), &run.q[r], t0, t1, cols),
        });
        charts.push((name.clone(), unit_of(&name).into(), s));
    }
    // gaps
    if nc > 0 {
        let mut s = Vec::new();
        if let Some(p) = prev {
            for (i, n) in p.contact_names.iter().enumerate() {
                if run.contact_names.contains(n) {
                    s.push(Series {
                        name: format!("{n} (previous)"),
                        style: th.previous(),
                        data: decimated(app, p, &format!("g{i}"), &p.gap[i], t0, t1, cols),
                    });
                }
            }
        }
        for (i, n) in run.contact_names.iter().enumerate() {
            s.push(Series {
                name: n.clone(),
                style: th.series(i),
                data: decimated(app, run, &format!("g{i}"), &run.gap[i], t0, t1, cols),
            });
        }
        charts.push(("gaps g_N".into(), "m".into(), s));
    }
    // x / y
    if !run.xy.is_empty() {
        let mut s = Vec::new();
        if let Some(p) = prev {
            for &k in &run.xy {
                if let Some(pk) = p.dof(&run.dof_names[k]) {
                    s.push(Series {
                        name: format!("{} (previous)", run.dof_names[k]),
                        style: th.previous(),
                        data: decimated(app, p, &format!("q{pk}"), &p.q[pk], t0, t1, cols),
                    });
                }
            }
        }
        for (i, &k) in run.xy.iter().enumerate() {
            s.push(Series {
                name: run.dof_names[k].clone(),
                style: th.series(i + 4),
                data: decimated(app, run, &format!("q{k}"), &run.q[k], t0, t1, cols),
            });
        }
        let names: Vec<&str> = run.xy.iter().map(|&k| run.dof_names[k].as_str()).collect();
        charts.push((names.join(" / "), "m".into(), s));
    }
    let n_charts = fit.min(charts.len()).max(1);
    let mut cons = vec![Constraint::Ratio(1, n_charts as u32); n_charts];
    cons.push(Constraint::Length(tl_h));
    let rects = Layout::vertical(cons).split(area);
    for (i, (title, unit, series)) in charts.into_iter().take(n_charts).enumerate() {
        draw_time_chart(frame, rects[i], app, run, &title, &unit, series, tc, th);
    }
    draw_timeline(frame, rects[n_charts], app, run, t0, t1, tc, th);
}

fn unit_of(dof: &str) -> &'static str {
    if dof.ends_with(".theta") { "rad" } else { "m" }
}

/// Value of a column at the cursor.
fn value_at(run: &RunData, y: &[f64], tc: f64) -> Option<f64> {
    chart::at_or_before(&run.t, tc).and_then(|i| y.get(i).copied())
}

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
    // header: title [unit], legend, value at the cursor
    let mut spans = vec![Span::styled(format!("{title} [{unit}]"), th.bold())];
    let current: Vec<&Series> = series
        .iter()
        .filter(|s| !s.name.ends_with("(previous)"))
        .collect();
    if current.len() > 1 {
        for s in &current {
            spans.push(Span::styled(" ━", s.style));
            spans.push(Span::raw(s.name.clone()));
        }
    }
    if series.iter().any(|s| s.name.ends_with("(previous)")) {
        spans.push(Span::styled(" ┈prev", th.previous()));
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
            spans.push(Span::styled(
                format!("  @cursor {}", fmt_num(v, 9)),
                th.cursor(),
            ));
        }
    }
    frame.render_widget(Paragraph::new(Line::from(spans)), head);
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

/// Per-contact event strip: events (impact `*`, stick `S`, slip `~`, release `^`,
/// accumulation `!`) over the contact state (stuck `█`/`#`, sliding `▒`/`=`, open ` `).
pub fn event_strip(
    run: &RunData,
    contact: usize,
    t0: f64,
    t1: f64,
    width: usize,
    per_cell: usize,
    ascii: bool,
) -> Vec<char> {
    let mut rank: Vec<Option<u8>> = vec![None; width];
    let range = chart::window(&run.t, t0, t1);
    let states = &run.state[contact];
    for i in range.clone() {
        if let Some(c) = column_of(run.t[i], t0, t1, width, per_cell) {
            let r = match states[i] {
                ContactState::Stick => 2,
                ContactState::Slide(_) => 1,
                ContactState::Open => 0,
            };
            rank[c] = Some(rank[c].map_or(r, |x| x.max(r)));
        }
    }
    // a cell without samples keeps the state of the sample before it
    let last_col = run
        .t
        .get(range.end.saturating_sub(1))
        .filter(|_| range.end > range.start)
        .and_then(|&t| column_of(t, t0, t1, width, per_cell));
    let mut prev = range
        .start
        .checked_sub(1)
        .and_then(|i| states.get(i))
        .map(|s| match s {
            ContactState::Stick => 2,
            ContactState::Slide(_) => 1,
            ContactState::Open => 0,
        });
    for (c, r) in rank.iter_mut().enumerate() {
        if last_col.is_none_or(|l| c > l) {
            break;
        }
        match r {
            Some(x) => prev = Some(*x),
            None => *r = prev,
        }
    }
    let (stuck, sliding) = if ascii { ('#', '=') } else { ('█', '▒') };
    let mut out: Vec<char> = rank
        .iter()
        .map(|r| match r {
            Some(2) => stuck,
            Some(1) => sliding,
            _ => ' ',
        })
        .collect();
    let mut prio = vec![0u8; width];
    for e in run.events.iter().filter(|e| e.contact == contact) {
        if let Some(c) = column_of(e.t, t0, t1, width, per_cell) {
            let (p, ch) = match e.kind {
                EventKind::Impact => (5, '*'),
                EventKind::Accumulation => (4, '!'),
                EventKind::Stick => (3, 'S'),
                EventKind::Slip => (2, '~'),
                EventKind::Release => (1, '^'),
            };
            if p > prio[c] {
                prio[c] = p;
                out[c] = ch;
            }
        }
    }
    out
}

#[allow(clippy::too_many_arguments)]
fn draw_timeline(
    frame: &mut Frame,
    area: Rect,
    app: &App,
    run: &RunData,
    t0: f64,
    t1: f64,
    tc: f64,
    th: &Theme,
) {
    if area.height < 2 {
        return;
    }
    let w = area.width.saturating_sub(LABEL_W + 1) as usize;
    let per_cell = th.per_cell();
    let nc = run.contact_names.len();
    let rows = (area.height as usize).saturating_sub(2).min(nc);
    let stuck = if th.ascii { "#" } else { "█" };
    let slide = if th.ascii { "=" } else { "▒" };
    let tnow = format!(" t = {} s", fmt_num(tc, 9));
    let legend = if area.width as usize >= 60 + tnow.len() {
        format!("* impact  S stick  ~ slip  ^ release  {stuck} stuck  {slide} sliding")
    } else {
        format!("*impact S stick ~slip ^release {stuck}stuck {slide}slide")
    };
    let head = Line::from(vec![
        Span::styled("events ", th.bold()),
        Span::styled(legend, th.dim()),
    ]);
    let tw = tnow.len() as u16;
    frame.render_widget(
        Paragraph::new(Line::styled(tnow, th.cursor())).alignment(Alignment::Right),
        Rect::new(
            area.right().saturating_sub(tw),
            area.y,
            tw.min(area.width),
            1,
        ),
    );
    let mut lines = vec![head];
    let key = Key {
        extra: u64::from(th.ascii),
        ..time_key(run, t0, t1, w as u16)
    };
    let strips = {
        let mut cache = app.cache.borrow_mut();
        match cache.strips.get(&run.id) {
            Some((k, v)) if *k == key => v.clone(),
            _ => {
                let v: Vec<Vec<char>> = (0..nc)
                    .map(|i| event_strip(run, i, t0, t1, w, per_cell, th.ascii))
                    .collect();
                if cache.strips.len() > 8 {
                    cache.strips.clear();
                }
                cache.strips.insert(run.id, (key, v.clone()));
                v
            }
        }
    };
    let cur_col = column_of(tc, t0, t1, w, per_cell);
    for (i, strip) in strips.iter().enumerate().take(rows) {
        let name: String = run.contact_names[i]
            .chars()
            .take(LABEL_W as usize - 1)
            .collect();
        let mut spans = vec![Span::styled(
            format!("{name:>lw$} ", lw = LABEL_W as usize - 1),
            th.series(i),
        )];
        spans.push(Span::styled("│", th.dim()));
        let s: String = strip.iter().collect();
        match cur_col {
            Some(c) => {
                let a: String = strip[..c].iter().collect();
                let b: String = strip[c..=c].iter().collect();
                let d: String = strip[c + 1..].iter().collect();
                spans.push(Span::raw(a));
                spans.push(Span::styled(b, th.selected()));
                spans.push(Span::raw(d));
            }
            None => spans.push(Span::raw(s)),
        }
        lines.push(Line::from(spans));
    }
    // time axis
    let mut axis: Vec<char> = vec![' '; w];
    let ticks = [t0, 0.5 * (t0 + t1), t1];
    for (k, &t) in ticks.iter().enumerate() {
        let mut label = fmt_num(t, 7);
        if k == 2 {
            label.push_str(" s");
        }
        let n = label.chars().count();
        let Some(c) = column_of(t, t0, t1, w, per_cell) else {
            continue;
        };
        let start = match k {
            0 => c,
            1 => c.saturating_sub(n / 2),
            _ => (c + 1).saturating_sub(n),
        };
        for (j, ch) in label.chars().enumerate() {
            if start + j < w {
                axis[start + j] = ch;
            }
        }
    }
    let axis: String = axis.into_iter().collect();
    lines.push(Line::from(vec![
        Span::raw(" ".repeat(LABEL_W as usize)),
        Span::styled(format!("└{axis}"), th.dim()),
    ]));
    frame.render_widget(Paragraph::new(lines), area);
}

fn draw_side_panel(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let has_loop = shown_run(app).is_some_and(|r| !r.element_names.is_empty());
    if !has_loop {
        // no hysteretic elements: plan view and the comparison
        let sum_h = 9.min(area.height / 2);
        let [plan, sum] =
            Layout::vertical([Constraint::Min(0), Constraint::Length(sum_h)]).areas(area);
        draw_plan(frame, plan, app, th);
        draw_summary(frame, sum, app, th);
        return;
    }
    let with_summary = area.height >= 28;
    let sum_h = if with_summary { 9 } else { 0 };
    let rest = area.height - sum_h;
    let plan_h = (rest * 45 / 100).max(6);
    let [plan, lp, sum] = Layout::vertical([
        Constraint::Length(plan_h),
        Constraint::Min(0),
        Constraint::Length(sum_h),
    ])
    .areas(area);
    draw_plan(frame, plan, app, th);
    draw_loop(frame, lp, app, th);
    if with_summary {
        draw_summary(frame, sum, app, th);
    }
}

/// Scale factor of the plan view: the largest displacement (or gap) drawn as ~6 % of the view.
fn plan_scale(app: &App, half: f64) -> f64 {
    let Some(scene) = &app.scene else {
        return 1.0;
    };
    let mut d: f64 = 0.0;
    for c in &scene.contacts {
        d = d.max(contact_gap0(scene, c).abs());
    }
    if let Some(r) = shown_run(app) {
        for (k, n) in r.dof_names.iter().enumerate() {
            let m = r.q_peak[k];
            d = d.max(if n.ends_with(".theta") {
                m * half * 0.5
            } else {
                m
            });
        }
    }
    if d <= 0.0 {
        return 1.0;
    }
    let s = 0.06 * half / d;
    let n = chart::nice_factor(s);
    if n > s { n / 2.0 } else { n }.max(1.0)
}

fn body_ref(scene: &crate::scene::Scene, b: crate::scene::BodyRef) -> nalgebra::Vector2<f64> {
    match b {
        crate::scene::BodyRef::Body(i) => scene.bodies[i].reference,
        crate::scene::BodyRef::Ground => nalgebra::Vector2::zeros(),
    }
}

/// Initial gap of a contact (q = 0).
fn contact_gap0(scene: &crate::scene::Scene, c: &crate::scene::Contact) -> f64 {
    let xa = body_ref(scene, c.point_body);
    let xb = body_ref(scene, c.face_body);
    c.face_normal.dot(&(xa + c.point - xb - c.face_point))
}

fn draw_plan(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    use crate::scene::BodyRef;
    use nalgebra::Vector2;
    let tc = app.cursor_time();
    let Some(scene) = &app.scene else {
        frame.render_widget(Paragraph::new("no model").block(th.block(" plan ")), area);
        return;
    };
    let inner = th.block("").inner(area);
    // extents of the reference configuration
    let mut pts: Vec<Vector2<f64>> = scene.bodies.iter().map(|b| b.reference).collect();
    for c in &scene.contacts {
        pts.push(body_ref(scene, c.point_body) + c.point);
    }
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for p in &pts {
        x0 = x0.min(p.x);
        x1 = x1.max(p.x);
        y0 = y0.min(p.y);
        y1 = y1.max(p.y);
    }
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let mut hx = (0.5 * (x1 - x0)).max(0.5 * (y1 - y0)).max(0.5) * 1.2;
    let (w, h) = (inner.width.max(1) as f64, inner.height.max(1) as f64);
    let mut hy = 2.0 * hx * h / w;
    let need_y = (0.5 * (y1 - y0)).max(0.05 * hx) * 1.4;
    if hy < need_y {
        hy = need_y;
        hx = hy * w / (2.0 * h);
        hx = hx.max(0.5 * (x1 - x0) * 1.2);
    }
    let s = plan_scale(app, hx);
    let run = shown_run(app);
    let idx = run.and_then(|r| chart::at_or_before(&r.t, tc));
    let disp = |b: usize| -> (Vector2<f64>, f64) {
        let body = &scene.bodies[b];
        let get = |a: usize| -> f64 {
            match (body.dofs[a], run, idx) {
                (Some(k), Some(r), Some(i)) => {
                    let name = &scene.dof_names[k];
                    r.dof(name)
                        .and_then(|kk| r.q[kk].get(i).copied())
                        .unwrap_or(0.0)
                }
                _ => 0.0,
            }
        };
        (Vector2::new(get(0), get(1)), get(2))
    };
    let place = |b: BodyRef, p: Vector2<f64>| -> Vector2<f64> {
        match b {
            BodyRef::Ground => p,
            BodyRef::Body(i) => {
                let (u, th_) = disp(i);
                let a = s * th_;
                let r = Vector2::new(a.cos() * p.x - a.sin() * p.y, a.sin() * p.x + a.cos() * p.y);
                scene.bodies[i].reference + s * u + r
            }
        }
    };
    let rot = |b: BodyRef, v: Vector2<f64>| -> Vector2<f64> {
        match b {
            BodyRef::Ground => v,
            BodyRef::Body(i) => {
                let a = s * disp(i).1;
                Vector2::new(a.cos() * v.x - a.sin() * v.y, a.sin() * v.x + a.cos() * v.y)
            }
        }
    };
    let states: Vec<ContactState> = (0..scene.contacts.len())
        .map(|ci| {
            match (run, idx) {
                (Some(r), Some(i)) => r
                    .contact_names
                    .iter()
                    .position(|n| *n == scene.contacts[ci].name)
                    .and_then(|k| r.state[k].get(i).copied()),
                _ => None,
            }
            .unwrap_or(ContactState::Open)
        })
        .collect();
    let body_color = th.series(0).fg.unwrap_or(Color::Reset);
    let face_color = if th.color { Color::Gray } else { Color::Reset };
    let stick_style = th.status(StatusKind::Error);
    let contact_style = th.status(StatusKind::Warn);
    let (stuck_sym, touch_sym) = if th.ascii { ("S", "*") } else { ("■", "●") };
    let face_len = 0.06 * hx.max(hy);
    let depth = 0.03 * hx;
    let title = format!(" plan ×{} t={} s ", fmt_num(s, 8), fmt_num(tc, 7));
    let canvas = Canvas::default()
        .block(th.block(title))
        .marker(th.marker())
        .x_bounds([cx - hx, cx + hx])
        .y_bounds([cy - hy, cy + hy])
        .paint(|ctx: &mut Context| {
            // faces (exaggerated gaps) with a block behind each
            for c in &scene.contacts {
                let g0 = contact_gap0(scene, c);
                let fp = body_ref(scene, c.point_body) + c.point
                    - s * g0 * c.face_normal
                    - body_ref(scene, c.face_body);
                let f = place(c.face_body, fp);
                let n = rot(c.face_body, c.face_normal);
                let t = Vector2::new(-n.y, n.x) * face_len;
                let (a, b) = (f + t, f - t);
                let (a2, b2) = (a - n * depth, b - n * depth);
                for (p, q) in [(a, b), (a, a2), (b, b2), (a2, b2)] {
                    ctx.draw(&CLine::new(p.x, p.y, q.x, q.y, face_color));
                }
            }
            ctx.layer();
            // bodies: polygon through their contact points, else a cross
            for bi in 0..scene.bodies.len() {
                let mut cps: Vec<Vector2<f64>> = scene
                    .contacts
                    .iter()
                    .filter(|c| c.point_body == BodyRef::Body(bi))
                    .map(|c| c.point)
                    .collect();
                let centre = place(BodyRef::Body(bi), Vector2::zeros());
                if cps.len() >= 3 {
                    cps.sort_by(|p, q| p.y.atan2(p.x).total_cmp(&q.y.atan2(q.x)));
                    for k in 0..cps.len() {
                        let p = place(BodyRef::Body(bi), cps[k]);
                        let q = place(BodyRef::Body(bi), cps[(k + 1) % cps.len()]);
                        ctx.draw(&CLine::new(p.x, p.y, q.x, q.y, body_color));
                    }
                } else if !scene
                    .contacts
                    .iter()
                    .any(|c| c.face_body == BodyRef::Body(bi))
                {
                    let e = 0.02 * hx;
                    ctx.draw(&CLine::new(
                        centre.x - e,
                        centre.y,
                        centre.x + e,
                        centre.y,
                        body_color,
                    ));
                    ctx.draw(&CLine::new(
                        centre.x,
                        centre.y - e,
                        centre.x,
                        centre.y + e,
                        body_color,
                    ));
                    for p in &cps {
                        let q = place(BodyRef::Body(bi), *p);
                        ctx.draw(&CLine::new(centre.x, centre.y, q.x, q.y, body_color));
                    }
                }
            }
            // contact points in contact / stuck
            for (ci, c) in scene.contacts.iter().enumerate() {
                let p = place(c.point_body, c.point);
                match states[ci] {
                    ContactState::Stick => {
                        ctx.print(p.x, p.y, Span::styled(stuck_sym, stick_style))
                    }
                    ContactState::Slide(_) => {
                        ctx.print(p.x, p.y, Span::styled(touch_sym, contact_style))
                    }
                    ContactState::Open => {}
                }
            }
        });
    frame.render_widget(canvas, area);
}

fn draw_loop(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let Some(run) = shown_run(app) else {
        frame.render_widget(th.block(" column "), area);
        return;
    };
    if run.element_names.is_empty() {
        frame.render_widget(
            Paragraph::new("no hysteretic elements in this model").block(th.block(" column ")),
            area,
        );
        return;
    }
    let j = app.element % run.element_names.len();
    let name = &run.element_names[j];
    let prev = overlay_run(app).filter(|p| p.id != run.id).and_then(|p| {
        p.element_names
            .iter()
            .position(|n| n == name)
            .map(|k| (p, k))
    });
    let tc = app.cursor_time();
    let (t0, _) = app.window();
    let unit_f = if app
        .scene
        .as_ref()
        .is_some_and(|s| s.bodies.iter().any(|b| b.name == "deck"))
    {
        " kN"
    } else {
        ""
    };
    let title = format!(
        " {name} force–deformation ({}/{}, n: next) ",
        j + 1,
        run.element_names.len()
    );
    let block = th.block(title);
    let inner = block.inner(area);
    let (dx, fx) = (&run.el[j].0, &run.el[j].1);
    let mut r = run.el_range[j];
    if let Some((p, k)) = prev {
        let q = p.el_range[k];
        r = [
            r[0].min(q[0]),
            r[1].max(q[1]),
            r[2].min(q[2]),
            r[3].max(q[3]),
        ];
    }
    let xb = bounds(&[r[0], r[1]]);
    let yb = bounds(&[r[2], r[3]]);
    let res_x = inner.width as usize * th.per_cell();
    let res_y = inner.height as usize * if th.ascii { 1 } else { 4 };
    let geo = [
        res_x as u64,
        res_y as u64,
        xb[0].to_bits(),
        xb[1].to_bits(),
        yb[0].to_bits(),
        yb[1].to_bits(),
    ];
    let mut key = vec![run.t.len() as u64, t0.to_bits(), tc.to_bits()];
    key.extend(geo);
    let cur = memo(app, format!("{}:loop{j}", run.id), key, || {
        let range = chart::window(&run.t, t0, tc);
        chart::dedup_pixels(range.map(|i| (dx[i], fx[i])), xb, yb, res_x, res_y)
    });
    let prev_pts = prev.map(|(p, k)| {
        let mut key = vec![p.t.len() as u64];
        key.extend(geo);
        memo(app, format!("{}:loop{k}", p.id), key, || {
            chart::dedup_pixels(
                p.el[k].0.iter().copied().zip(p.el[k].1.iter().copied()),
                xb,
                yb,
                res_x,
                res_y,
            )
        })
    });
    let here = cur.last().map(|p| [*p]);
    let marker = th.marker();
    let mut ds = Vec::new();
    if let Some(p) = &prev_pts {
        ds.push(
            Dataset::default()
                .marker(marker)
                .graph_type(GraphType::Line)
                .style(th.previous())
                .data(p),
        );
    }
    ds.push(
        Dataset::default()
            .marker(marker)
            .graph_type(GraphType::Line)
            .style(th.series(2))
            .data(&cur),
    );
    if let Some(h) = &here {
        ds.push(
            Dataset::default()
                .marker(Marker::Block)
                .graph_type(GraphType::Scatter)
                .style(th.cursor())
                .data(h),
        );
    }
    let chart = Chart::new(ds)
        .block(block)
        .x_axis(
            Axis::default()
                .bounds(xb)
                .labels(vec![
                    Line::from(fmt_num(xb[0], 7)),
                    Line::from(fmt_num(xb[1], 7)),
                ])
                .style(th.dim()),
        )
        .y_axis(
            Axis::default()
                .bounds(yb)
                .labels(vec![
                    Line::from(format!("{}{unit_f}", fmt_num(yb[0], 7))),
                    Line::from(format!("{}{unit_f}", fmt_num(yb[1], 7))),
                ])
                .style(th.dim()),
        )
        .legend_position(None);
    frame.render_widget(chart, area);
}

fn digest_rows(cur: Option<&Digest>, prev: Option<&Digest>) -> Vec<[String; 3]> {
    let rot = cur
        .or(prev)
        .map(|d| {
            if d.rot_name.ends_with(".theta") {
                "θ".to_string()
            } else {
                d.rot_name.clone()
            }
        })
        .unwrap_or_else(|| "θ".into());
    type Get = fn(&Digest) -> String;
    let rows: [(String, Get); 6] = [
        (format!("peak |{rot}|"), |d| chart::fmt_sig(d.peak_rot, 4)),
        ("  at t [s]".into(), |d| chart::fmt_sig(d.peak_rot_at, 4)),
        (format!("residual {rot}"), |d| {
            chart::fmt_sig(d.residual_rot, 4)
        }),
        ("impacts".into(), |d| d.total_impacts().to_string()),
        ("stick [s]".into(), |d| {
            chart::fmt_sig(d.total_stick_time(), 4)
        }),
        ("min gap [m]".into(), |d| {
            // below a nanometre is closed contact (round-off noise otherwise)
            let g = d.min_gap();
            match g {
                g if !g.is_finite() => "—".into(),
                g if g.abs() < 1e-9 => "0".into(),
                g => chart::fmt_sig(g, 4),
            }
        }),
    ];
    let f = |d: Option<&Digest>, g: Get| d.map_or("—".to_string(), g);
    rows.into_iter()
        .map(|(n, g)| [n, f(cur, g), f(prev, g)])
        .collect()
}

fn draw_summary(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let cur = app.current.as_ref();
    let prev = app.previous.as_ref();
    let rows = digest_rows(cur.map(|r| &r.digest), prev.map(|r| &r.digest));
    let longest = rows.iter().map(|r| r[0].chars().count()).max().unwrap_or(0) as u16;
    let label_w = longest.clamp(12, (area.width / 3).max(12));
    let value_w = (area.width.saturating_sub(2 + label_w + 2) / 2).clamp(4, 12);
    let header = Row::new(vec![
        String::new(),
        cur.map_or("current".into(), |r| format!("run {}", r.id)),
        prev.map_or("previous".into(), |r| format!("run {}", r.id)),
    ])
    .style(th.bold());
    let table = Table::new(
        rows.into_iter().map(|r| Row::new(r.to_vec())),
        [
            Constraint::Length(label_w),
            Constraint::Length(value_w),
            Constraint::Length(value_w),
        ],
    )
    .header(header)
    .block(th.block(" current vs previous "));
    frame.render_widget(table, area);
}

// ---------------------------------------------------------------------------------------------
// form view

fn draw_form(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let left_w = (area.width * 55 / 100).max(34);
    let [left, right] =
        Layout::horizontal([Constraint::Length(left_w), Constraint::Min(0)]).areas(area);
    let title = if app.dirty() {
        " parameters — edited (* unsaved; s saves) "
    } else {
        " parameters "
    };
    let block = th.block(title);
    let inner = block.inner(left);
    frame.render_widget(block, left);
    let fields = &app.form.fields;
    let rows = inner.height as usize;
    let n = fields.len();
    let sel = app.form.selected.min(n.saturating_sub(1));
    let off = sel.saturating_sub(rows / 2).min(n.saturating_sub(rows));
    let lw = (inner.width as usize).saturating_sub(2);
    let label_w = (lw * 45 / 100).clamp(8, 26);
    let unit_w = 8;
    let value_w = lw.saturating_sub(label_w + unit_w + 2);
    let mut lines = Vec::new();
    for (i, f) in fields.iter().enumerate().skip(off).take(rows) {
        let mark = if f.edited() { "*" } else { " " };
        let editing = i == sel && matches!(app.mode, Mode::Editing { .. });
        let value = match (&app.mode, editing) {
            (Mode::Editing { buffer, .. }, true) => format!("{buffer}_"),
            _ => f.value.clone().unwrap_or_else(|| "(default)".into()),
        };
        let label: String = f.label.chars().take(label_w).collect();
        let value: String = if value.chars().count() > value_w {
            value
                .chars()
                .skip(value.chars().count() - value_w)
                .collect()
        } else {
            value
        };
        let unit: String = if f.unit.contains('|') {
            String::new()
        } else {
            f.unit.chars().take(unit_w).collect()
        };
        let text = format!("{mark}{label:<label_w$} {value:>value_w$} {unit:<unit_w$}");
        let mut style = if f.curated {
            Style::default()
        } else {
            th.dim()
        };
        if f.edited() {
            style = style.patch(th.fg(Color::Yellow));
        }
        if i == sel {
            style = style.patch(th.selected());
        }
        lines.push(Line::styled(text, style));
    }
    if n == 0 {
        lines.push(Line::from("the file is not valid TOML: nothing to edit"));
    }
    frame.render_widget(Paragraph::new(lines), inner);

    let sum_h = if right.height >= 20 { 9 } else { 0 };
    let [detail, sum] =
        Layout::vertical([Constraint::Min(0), Constraint::Length(sum_h)]).areas(right);
    draw_field_detail(frame, detail, app, th);
    if sum_h > 0 {
        draw_summary(frame, sum, app, th);
    }
}

fn draw_field_detail(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let block = th.block(" field ");
    let Some(f) = app.form.selected() else {
        frame.render_widget(block, area);
        return;
    };
    let mut lines = vec![
        Line::styled(f.path.clone(), th.bold()),
        Line::from(format!(
            "{}{}",
            f.kind.name(),
            if f.unit.is_empty() {
                String::new()
            } else {
                format!(", {}", f.unit)
            }
        )),
        Line::from(vec![
            Span::styled("saved: ", th.dim()),
            Span::raw(
                f.saved
                    .clone()
                    .unwrap_or_else(|| "(absent: default)".into()),
            ),
        ]),
    ];
    if f.edited() {
        lines.push(Line::from(vec![
            Span::styled("draft: ", th.dim()),
            Span::styled(
                f.value.clone().unwrap_or_else(|| "(absent)".into()),
                th.fg(Color::Yellow),
            ),
        ]));
    }
    match &app.mode {
        Mode::Editing { buffer, check } => {
            lines.push(Line::from(vec![
                Span::styled("> ", th.bold()),
                Span::raw(format!("{buffer}_")),
            ]));
            match check {
                Ok(()) => lines.push(Line::styled(
                    "✓ valid — Enter accepts",
                    th.status(StatusKind::Ok),
                )),
                Err(e) => {
                    let prefix = format!("{}:", app.path.display());
                    let short = e
                        .strip_prefix(&prefix)
                        .map_or(e.clone(), |r| format!("at {r}"));
                    lines.push(Line::styled(
                        format!("✗ {short}"),
                        th.status(StatusKind::Error),
                    ));
                }
            }
        }
        _ => lines.push(Line::styled(
            "Enter edits · u reverts · s saves · r runs",
            th.dim(),
        )),
    }
    if !f.note.is_empty() {
        lines.push(Line::from(""));
        lines.push(Line::styled(format!("# {}", f.note), th.dim()));
    }
    frame.render_widget(
        Paragraph::new(lines)
            .wrap(Wrap { trim: false })
            .block(block),
        area,
    );
}
