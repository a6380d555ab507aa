//! The studies view: the list of studies on one line (the selected one marked `>`), the
//! selected study's state on the next (progress, counts, its CSV), and its panel: titled with
//! where its model came from, its figure (Fig. 7, Fig. 8, the screening maps, the ladder's
//! table and chart, the swings' tornado) or what it does before it has run. Also the list of
//! CSVs to reopen.

use super::common::{Theme, fit};
use super::line_plot::{Look, draw_line_plot};
use super::screen_map::draw_screen;
use super::study_numbers::{draw_table, readout, split};
use crate::figures::{FIG7_WITH_CONTACT, FIG7_WITHOUT_CONTACT};
use crate::plot::{Axis, Chart, Marker, Series};
use crate::study_table::{RunTable, StudyKind, StudyTable};
use crate::tui::app::{App, StatusKind};
use crate::tui::chart::bounds;
use crate::tui::results::Page;
use crate::tui::studies::points::{points, run_mark};
use crate::tui::studies::{Entry, Phase, Source, Studies, title, what};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Block, Borders, Clear, Paragraph, Wrap};
use std::path::PathBuf;

/// Draws the studies view.
pub(super) fn draw_studies(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let list = tab_lines(app, area.width as usize, th);
    let [tabs, line, panel] = Layout::vertical([
        Constraint::Length(list.len() as u16),
        Constraint::Length(1),
        Constraint::Min(0),
    ])
    .areas(area);
    frame.render_widget(Paragraph::new(list), tabs);
    if let Some(page) = app.results.page {
        return super::results::draw_page(frame, line, panel, app, page, th);
    }
    let kind = app.studies.kind();
    let entry = app.studies.entry(kind);
    let mut items: Vec<String> = info(entry, th)
        .into_iter()
        .filter(|i| !i.is_empty())
        .collect();
    let width = line.width as usize;
    // a CSV path too long for the line: its file name
    let cut = fit(&items, th.sep(), width).len() < items.join(th.sep()).len();
    if let (true, Some(last), Some(name)) = (
        cut,
        items.last_mut(),
        entry
            .and_then(|e| e.csv.as_ref())
            .and_then(|p| p.file_name()),
    ) {
        *last = format!("CSV {}", th.text(&name.to_string_lossy()));
    }
    frame.render_widget(
        Paragraph::new(Line::from(fit(&items, th.sep(), width))),
        line,
    );
    let next = if app.dirty() {
        "model: form draft (unsaved edits)".to_string()
    } else {
        format!("model: {} as saved", app.file_name())
    };
    let view = PanelView {
        grid: app.results.grid,
        cursor: app.studies.cursor(),
        quantity: app.studies.quantity,
    };
    draw_panel(frame, panel, kind, entry, &next, view, th);
}

/// How the panel is shown: work-precision's chart or grid, the cursor's row, the swings'
/// quantity.
#[derive(Clone, Copy)]
struct PanelView {
    grid: bool,
    cursor: usize,
    quantity: usize,
}

/// A study's state in a word or two.
fn state(e: Option<&Entry>) -> String {
    let Some(e) = e else {
        return "not run".into();
    };
    let (done, all) = e.progress();
    match (&e.phase, &e.source) {
        (Phase::Running, _) if all > 0 => format!("{done}/{all}"),
        (Phase::Running, _) => "running".into(),
        (Phase::Cancelling, _) => "cancelling".into(),
        (Phase::Cancelled, _) => "cancelled".into(),
        (Phase::Failed(_), _) => "failed".into(),
        (Phase::Finished, Source::Csv(_)) => "from CSV".into(),
        (Phase::Finished, Source::Form { .. }) => "done".into(),
    }
}

/// The list of studies and results pages, every name always shown: on one line when all fit
/// with their states, else the paper's studies on one line and the design studies (adequacy,
/// sensitivity) with the results pages on the next; a line too narrow for every state keeps
/// the selected one's and the others' that say more than "not run" / "not computed", then the
/// names alone (the state line under the list gives the selected one's), on two lines when
/// even they do not fit.
fn tab_lines(app: &App, width: usize, th: &Theme) -> Vec<Line<'static>> {
    let sel = crate::tui::update::list_index(app);
    let studies = (StudyKind::ALL.iter()).map(|k| (title(*k), state(app.studies.entry(*k))));
    let pages = (Page::ALL.iter()).map(|p| (p.title(), super::results::state(app, *p)));
    let items: Vec<(usize, String, String)> = (studies.chain(pages).enumerate())
        .map(|(i, (name, state))| (i, th.text(name), th.text(&state)))
        .collect();
    // on one line only with the states that say something
    if let Some(line) = tab_line(&items, sel, width, 1, th) {
        return vec![line];
    }
    let (first, second) = items.split_at(Studies::index_of(StudyKind::Adequacy));
    let mut lines = Vec::new();
    for group in [first, second] {
        if let Some(line) = tab_line(group, sel, width, 2, th) {
            lines.push(line);
            continue;
        }
        let names: Vec<(usize, String, String)> = (group.iter())
            .map(|(i, name, _)| (*i, name.clone(), String::new()))
            .collect();
        let (line, w) = tab_line_at(&names, sel, 0, th);
        if w <= width || names.len() < 2 {
            lines.push(line);
        } else {
            let (a, b) = names.split_at(names.len() / 2);
            lines.extend([a, b].map(|half| tab_line_at(half, sel, 0, th).0));
        }
    }
    lines
}

/// The items on one line in `width` columns, at the first level of detail up to `most` that
/// fits ([`tab_line_at`]).
fn tab_line(
    items: &[(usize, String, String)],
    sel: usize,
    width: usize,
    most: u8,
    th: &Theme,
) -> Option<Line<'static>> {
    (0..=most)
        .map(|level| tab_line_at(items, sel, level, th))
        .find(|(_, w)| *w <= width)
        .map(|(l, _)| l)
}

/// One line of the list and its width: `>name: state` for the selected item; the others
/// with their states (level 0), with the states that are not the default (1), or named only
/// (2).
fn tab_line_at(
    items: &[(usize, String, String)],
    sel: usize,
    level: u8,
    th: &Theme,
) -> (Line<'static>, usize) {
    let mut spans = Vec::new();
    let mut width = 0;
    for (i, name, state) in items {
        let idle = matches!(state.as_str(), "not run" | "not computed");
        let text = if state.is_empty() || (*i != sel && (level == 2 || (level == 1 && idle))) {
            name.clone()
        } else {
            format!("{name}: {state}")
        };
        let mark = if *i == sel { '>' } else { ' ' };
        let item = format!("{mark}{text}");
        if !spans.is_empty() {
            spans.push(Span::raw("  "));
            width += 2;
        }
        width += item.chars().count();
        spans.push(if *i == sel {
            Span::styled(item, th.selected().patch(th.bold()))
        } else {
            Span::raw(item)
        });
    }
    (Line::from(spans), width)
}

/// A progress bar in ASCII: `[####      ]`.
fn bar(done: usize, all: usize, width: usize) -> String {
    let full = (done * width).checked_div(all).unwrap_or(0).min(width);
    format!("[{}{}]", "#".repeat(full), " ".repeat(width - full))
}

/// The selected study's state line, as items in order of importance.
fn info(e: Option<&Entry>, th: &Theme) -> Vec<String> {
    let Some(e) = e else {
        return vec![
            "not run yet".into(),
            "Enter runs it on the form's model".into(),
            "f reopens a CSV".into(),
        ];
    };
    let (done, all) = e.progress();
    let failed = match &e.table {
        Some(StudyTable::Runs(t)) if t.failed() > 0 => format!("{} failed", t.failed()),
        _ => String::new(),
    };
    let csv = e.csv.as_ref().map_or(String::new(), |p| {
        let what = if matches!(e.source, Source::Csv(_)) {
            "read from"
        } else {
            "CSV"
        };
        format!("{what} {}", p.display())
    });
    let items = match &e.phase {
        Phase::Running if all > 0 => {
            vec![
                format!("{} {done}/{all} runs", bar(done, all, 10)),
                failed,
                "Esc cancels".into(),
            ]
        }
        Phase::Running => vec!["computing…".into()],
        Phase::Cancelling => vec![format!("cancelling after {done}/{all} runs…")],
        Phase::Finished if all > 1 => vec![format!("{done} runs"), failed, csv],
        Phase::Finished => vec!["done".into(), csv],
        Phase::Cancelled if e.table.is_none() => {
            vec![format!(
                "cancelled after {done} of {all} runs: nothing kept"
            )]
        }
        Phase::Cancelled => vec![
            format!("cancelled: {done} of {all} runs done, drawn"),
            failed,
            csv,
        ],
        Phase::Failed(_) => vec!["failed: the reason below".into()],
    };
    items.iter().map(|i| th.text(i)).collect()
}

/// The panel's title: the figure and where its model came from (`next`: the model a run
/// would use, for a study not run).
fn panel_title(kind: StudyKind, e: Option<&Entry>, next: &str) -> Vec<String> {
    let fig = match kind {
        StudyKind::Pga => "Fig. 7: peak |θ| vs PGA",
        StudyKind::Mu => "Fig. 8: increase of peak |θ| vs μ",
        StudyKind::Suite => "record suite: peak |θ| vs PGA",
        StudyKind::Screen => "screening by the impact law",
        StudyKind::Precision => "work-precision and stability",
        StudyKind::Adequacy => "model adequacy: the ladder's cost against its error",
        StudyKind::Sensitivity => "sensitivity: the swings and their tornado",
    };
    let source = match e.map(|e| &e.source) {
        None => next.to_string(),
        Some(Source::Form { edited: true, .. }) => "model: form draft (unsaved edits)".into(),
        Some(Source::Form { file, .. }) => format!("model: {file} as saved"),
        Some(Source::Csv(p)) => format!(
            "from {}",
            p.file_name().map_or(p.display().to_string(), |n| n
                .to_string_lossy()
                .into_owned())
        ),
    };
    let cancelled = match e.map(|e| &e.phase) {
        Some(Phase::Cancelled) => "cancelled".to_string(),
        _ => String::new(),
    };
    vec![fig.into(), cancelled, source]
}

fn draw_panel(
    frame: &mut Frame,
    area: Rect,
    kind: StudyKind,
    e: Option<&Entry>,
    next: &str,
    view: PanelView,
    th: &Theme,
) {
    let items: Vec<String> = (panel_title(kind, e, next).iter())
        .map(|t| th.text(t))
        .collect();
    let title = fit(&items, th.sep(), area.width.saturating_sub(2) as usize);
    let block = Block::new()
        .borders(Borders::TOP)
        .border_set(th.border())
        .border_style(th.dim())
        .title(Line::styled(title, th.bold()));
    let inner = block.inner(area);
    frame.render_widget(block, area);
    let table = e.and_then(|e| e.table.as_ref());
    match (table, e.map(|e| &e.phase)) {
        (_, Some(Phase::Failed(why))) => {
            let lines = vec![
                Line::styled(th.text(why), th.status(StatusKind::Error)),
                Line::from(""),
                Line::from(th.text(what(kind))),
            ];
            frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: true }), inner);
        }
        (Some(t @ StudyTable::Runs(r)), _) if r.done() > 0 => {
            draw_with_numbers(frame, inner, t, view, th)
        }
        (Some(StudyTable::Screen(s)), _) => draw_screen(frame, inner, s, th),
        (Some(t @ StudyTable::Precision(p)), _) if p.progress().0 > 0 => {
            draw_with_numbers(frame, inner, t, view, th)
        }
        (Some(t @ (StudyTable::Adequacy(_) | StudyTable::Sensitivity(_))), _) => {
            draw_figure(frame, inner, t, view, None, th)
        }
        (_, Some(Phase::Running | Phase::Cancelling)) => {
            let t = match kind {
                StudyKind::Screen => th.text("computing the screening…"),
                StudyKind::Adequacy | StudyKind::Sensitivity => {
                    th.text("its table comes when every run is done…")
                }
                _ => th.text("no run finished yet…"),
            };
            frame.render_widget(Paragraph::new(t), inner);
        }
        _ => {
            let lines = vec![
                Line::from(th.text(what(kind))),
                Line::from(""),
                Line::from(th.text(
                    "Enter runs it on the model in the form, its unsaved edits included; \
                     f reopens a study from its CSV.",
                )),
            ];
            frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: true }), inner);
        }
    }
}

/// A study's figure with its numbers: the chart, the table of its points beside it (or under
/// it), the readout at the cursor on the last line (work-precision's stability grid alone).
fn draw_with_numbers(
    frame: &mut Frame,
    area: Rect,
    table: &StudyTable,
    view: PanelView,
    th: &Theme,
) {
    // the stability grid is a table of its own (its verdicts)
    let grid = view.grid && matches!(table, StudyTable::Precision(_));
    let Some(p) = points(table).filter(|_| !grid) else {
        return draw_figure(frame, area, table, view, None, th);
    };
    let at = p.at(view.cursor).map(|r| r.x);
    let sp = split(area, &p, th);
    draw_figure(frame, sp.chart, table, view, at, th);
    draw_table(frame, sp.table, &p, view.cursor, th);
    let line = readout(&p, view.cursor, sp.readout.width as usize, th);
    frame.render_widget(Paragraph::new(Line::styled(line, th.bold())), sp.readout);
}

/// Fig. 7, Fig. 8, the suite's or work-precision's chart; `at`: the cursor's x.
fn draw_figure(
    frame: &mut Frame,
    area: Rect,
    table: &StudyTable,
    view: PanelView,
    at: Option<f64>,
    th: &Theme,
) {
    let t = match table {
        StudyTable::Runs(t) => t,
        StudyTable::Precision(t) => {
            return super::precision::draw_precision(frame, area, t, view.grid, th);
        }
        StudyTable::Screen(s) => return draw_screen(frame, area, s, th),
        StudyTable::Adequacy(a) => {
            return super::adequacy::draw_adequacy(frame, area, a, view.cursor, th);
        }
        StudyTable::Sensitivity(s) => {
            let at = (view.quantity, view.cursor);
            return super::tornado::draw_tornado(frame, area, s, at, th);
        }
    };
    let chart = match t.kind {
        StudyKind::Mu => fig8(t),
        StudyKind::Suite => fig_suite(t),
        _ => fig7(t),
    };
    let look = Look {
        cursor: at.filter(|x| x.is_finite()),
        ..Look::default()
    };
    draw_line_plot(frame, area, &chart, &look, th);
}

/// Bounds of a finite range, padded ([`bounds`]).
fn range(v: impl Iterator<Item = f64>) -> [f64; 2] {
    let v: Vec<f64> = v.filter(|x| x.is_finite()).collect();
    bounds(v.iter())
}

/// A series of a study's points: joined, its glyph at every point.
fn points_series(label: &str, points: Vec<(f64, f64)>, color: usize, glyph: char) -> Series {
    Series::line(label, points)
        .marker(Marker::Circle)
        .color(color)
        .glyph(glyph)
}

/// The x range 0 … 1.05 × the largest PGA of the runs.
fn pga_axis(t: &RunTable, title: &str) -> Axis {
    let hi = 1.05 * (t.runs.iter().map(|r| r.pga_x)).fold(0.0, f64::max);
    Axis::linear(title, "").with_range(0.0, hi)
}

/// The y range 0 … 1.08 × the largest peak (0 … 1 without one).
fn peak_axis(peak: f64) -> Axis {
    let hi = if peak > 0.0 { peak * 1.08 } else { 1.0 };
    Axis::linear("peak |θ| [rad]", "").with_range(0.0, hi)
}

fn fig7(t: &RunTable) -> Chart {
    let [without, with] = t.fig7();
    let peak = (with.iter().chain(&without))
        .map(|p| p.1)
        .fold(0.0, f64::max);
    let mut c = Chart::new("", pga_axis(t, "PGA x [g]"), peak_axis(peak));
    c.series = vec![
        points_series("without contact", without, 1, FIG7_WITHOUT_CONTACT),
        points_series("with contact", with, 0, FIG7_WITH_CONTACT),
    ];
    c
}

/// The record suite: each pair's peak |θ| against PGA (marked by its number, joined across
/// the levels: its IDA curve), and the median per level (`#`).
fn fig_suite(t: &RunTable) -> Chart {
    let [runs, medians] = t.suite_points();
    let peak = runs.iter().map(|p| p.1).fold(0.0, f64::max);
    let mut c = Chart::new("", pga_axis(t, "PGA [g]"), peak_axis(peak));
    let pairs = t.runs.iter().map(|r| r.run).max().unwrap_or(0);
    c.series = (1..=pairs)
        .map(|p| {
            let pts = (t.runs.iter())
                .filter(|r| r.run == p && r.is_ok())
                .map(|r| (r.pga_x, r.peak_rotation))
                .collect();
            points_series(&format!("pair {p}"), pts, p, run_mark(p))
        })
        .collect();
    c.series.push(points_series("median", medians, 0, '#'));
    c
}

fn fig8(t: &RunTable) -> Chart {
    let curves = t.fig8();
    let ys = (curves.iter()).flat_map(|c| c.points.iter().map(|p| p.1));
    let mut yb = range(ys.chain([0.0]));
    if yb[0] > 0.0 {
        yb[0] = 0.0;
    }
    let mus = t.mus();
    let lo = mus.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = mus.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let xb = if hi > lo {
        [lo, hi]
    } else {
        range(mus.into_iter())
    };
    let mut c = Chart::new(
        "",
        Axis::linear("μ [-]", "").with_range(xb[0], xb[1]),
        Axis::linear("increase of peak |θ| [%] by run (PGA x)", "").with_range(yb[0], yb[1]),
    );
    c.series = (curves.iter().enumerate())
        .map(|(i, cv)| {
            let label = format!("{} g", crate::tui::chart::fmt_sig(cv.pga_x, 3));
            points_series(&label, cv.points.clone(), i, run_mark(cv.run))
        })
        .collect();
    c
}

/// Draws the list of CSVs to reopen over the screen.
pub(super) fn draw_picker(
    frame: &mut Frame,
    area: Rect,
    title: &str,
    files: &[PathBuf],
    selected: usize,
    th: &Theme,
) {
    let names: Vec<String> = files
        .iter()
        .map(|p| th.text(&p.display().to_string()))
        .collect();
    let longest = names.iter().map(|n| n.chars().count()).max().unwrap_or(0) as u16;
    let w = (longest + 6).clamp(40, area.width.saturating_sub(4).max(10));
    let h = (files.len() as u16 + 3)
        .min(area.height.saturating_sub(2))
        .max(3);
    let rect = Rect::new(
        area.x + (area.width.saturating_sub(w)) / 2,
        area.y + (area.height.saturating_sub(h)) / 2,
        w.min(area.width),
        h,
    );
    let block = th.block(th.text(title));
    let inner = block.inner(rect);
    frame.render_widget(Clear, rect);
    frame.render_widget(block, rect);
    let rows = inner.height as usize;
    let off = selected.saturating_sub(rows.saturating_sub(1));
    let room = (inner.width as usize).saturating_sub(2);
    let lines: Vec<Line> = (names.iter().enumerate().skip(off).take(rows))
        .map(|(i, n)| {
            // a path too long keeps its end (the file's name) after `...`
            let count = n.chars().count();
            let shown = if count > room {
                let tail: String = n.chars().skip(count + 3 - room).collect();
                format!("...{tail}")
            } else {
                n.clone()
            };
            if i == selected {
                Line::styled(format!("> {shown}"), th.selected().patch(th.bold()))
            } else {
                Line::from(format!("  {shown}"))
            }
        })
        .collect();
    frame.render_widget(Paragraph::new(lines), inner);
}
