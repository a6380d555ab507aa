//! The status line, the key hints, the help and question overlays, the too-small screen.

use super::common::Theme;
use crate::tui::app::{App, Confirm, MIN_HEIGHT, MIN_WIDTH, StatusKind};
use crate::tui::keymap;
use ratatui::Frame;
use ratatui::layout::{Alignment, Constraint, Layout, Rect};
use ratatui::style::Color;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Clear, Paragraph, Wrap};

/// Draws the "terminal too small" screen.
pub(super) fn draw_too_small(frame: &mut Frame, area: Rect, th: &Theme) {
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

/// Draws the status line and the watch mode.
pub(super) fn draw_status(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let wm = if app.watch_mode.is_empty() {
        String::new()
    } else {
        format!("watch: {}", app.watch_mode)
    };
    let ww = (wm.chars().count() as u16 + 1).min(area.width / 3);
    let [l, r] = Layout::horizontal([Constraint::Min(0), Constraint::Length(ww)]).areas(area);
    frame.render_widget(
        Paragraph::new(Line::styled(
            th.text(&app.status),
            th.status(app.status_kind),
        )),
        l,
    );
    frame.render_widget(
        Paragraph::new(Line::styled(wm, th.dim())).alignment(Alignment::Right),
        r,
    );
}

/// Draws the key hints that fit.
pub(super) fn draw_hints(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
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

/// Draws the help overlay: every key, from the keymap; the keys of the view shown come right
/// after those that work everywhere.
pub(super) fn draw_help(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let view = app.view_ctx().title();
    let mut help = keymap::help();
    if let Some(i) = help.iter().position(|(t, _)| *t == view) {
        let group = help.remove(i);
        help.insert(1.min(help.len()), group);
    }
    let groups: Vec<Vec<Line>> = help
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
    let rect = centered(area, area.width.min(100), area.height);
    let block = th.block(" help — keys (Esc closes) ");
    let inner = block.inner(rect);
    let (c0, c1) = help_columns(groups, inner.height as usize, th);
    frame.render_widget(Clear, rect);
    frame.render_widget(block, rect);
    let [a, b] = Layout::horizontal([Constraint::Percentage(50), Constraint::Percentage(50)])
        .spacing(1)
        .areas(inner);
    frame.render_widget(Paragraph::new(c0), a);
    frame.render_widget(Paragraph::new(c1), b);
}

/// The help's two columns of `rows` lines: split in the middle when every line fits, else
/// whole groups in order, each into the first column with room for it; the groups left out
/// (keys of other modes, shown in the hint bar there) are counted on the last line.
fn help_columns<'a>(
    groups: Vec<Vec<Line<'a>>>,
    rows: usize,
    th: &Theme,
) -> (Vec<Line<'a>>, Vec<Line<'a>>) {
    let all: usize = groups.iter().map(Vec::len).sum();
    if all <= 2 * rows {
        let lines: Vec<Line> = groups.into_iter().flatten().collect();
        let half = lines.len().div_ceil(2);
        return (lines[..half].to_vec(), lines[half..].to_vec());
    }
    let mut cols: [Vec<Line>; 2] = [Vec::new(), Vec::new()];
    let mut left = 0;
    for g in groups {
        // the second column keeps a line for the count of the groups left out
        let room = |k: usize, c: &Vec<Line>| c.len() + g.len() + k <= rows;
        match (room(0, &cols[0]), room(1, &cols[1])) {
            (true, _) => cols[0].extend(g),
            (_, true) => cols[1].extend(g),
            _ => left += 1,
        }
    }
    if left > 0 {
        let note = format!("({left} more groups: a taller terminal)");
        cols[1].push(Line::styled(note, th.dim()));
    }
    let [a, b] = cols;
    (a, b)
}

/// The question's lines and its keys (key, meaning).
fn question(app: &App, c: &Confirm) -> (Vec<String>, Vec<(&'static str, &'static str)>) {
    let yes_no = vec![("y", "yes"), ("n", "no")];
    let name = app.file_name();
    match c {
        Confirm::Merge { conflicts, .. } => {
            let v = |x: &Option<String>| x.clone().unwrap_or_else(|| "(none)".into());
            let mut q = vec![format!(
                "{name} changed on disk, and so did this value here:"
            )];
            if let Some(c) = conflicts.first() {
                q.push(format!(
                    "{}: yours {}, on disk {}",
                    crate::tui::form::label_of(&c.path),
                    v(&c.mine),
                    v(&c.theirs)
                ));
            }
            if conflicts.len() > 1 {
                q.push(format!("({} more after this one)", conflicts.len() - 1));
            }
            let keys = vec![
                ("m", "keep mine"),
                ("t", "take theirs"),
                ("M", "mine for all"),
                ("T", "theirs for all"),
            ];
            (q, keys)
        }
        Confirm::SaveConflict { .. } => (
            vec![
                format!("Not saved: {name} changed on disk since your edits were made on it."),
                "Merge that change into your edits first (then s saves)?".to_string(),
            ],
            yes_no,
        ),
        Confirm::Quit => (
            vec![format!("{name} has unsaved edits.")],
            vec![
                ("s", "save and quit"),
                ("y", "quit without saving"),
                ("n", "stay"),
            ],
        ),
        Confirm::OpenModel { path } => (
            vec![format!(
                "Open {} and lose your unsaved edits of {name}?",
                path.display()
            )],
            yes_no,
        ),
    }
}

/// Draws the pending question.
pub(super) fn draw_confirm(frame: &mut Frame, area: Rect, app: &App, c: &Confirm, th: &Theme) {
    let (q, keys) = question(app, c);
    let w = (area.width.saturating_sub(8)).min(64);
    // each line, wrapped to the inside width, then a blank line, the keys and the borders
    let inside = w.saturating_sub(2).max(1) as usize;
    let rows: usize = q
        .iter()
        .map(|l| l.chars().count().div_ceil(inside).max(1))
        .sum();
    let rect = centered(area, w, rows as u16 + 4);
    let block = th
        .block(" question ")
        .border_style(th.status(StatusKind::Warn));
    let inner = block.inner(rect);
    frame.render_widget(Clear, rect);
    frame.render_widget(block, rect);
    let mut lines: Vec<Line> = q.into_iter().map(Line::from).collect();
    let mut row = Vec::new();
    for (i, (k, what)) in keys.into_iter().enumerate() {
        if i > 0 {
            row.push(Span::raw("   "));
        }
        row.push(Span::styled(
            format!(" {k} "),
            th.selected().patch(th.bold()),
        ));
        row.push(Span::raw(format!(" {what}")));
    }
    lines.extend([Line::from(""), Line::from(row)]);
    frame.render_widget(Paragraph::new(lines).wrap(Wrap { trim: true }), inner);
}
