//! The status line, the key hints, the help and question overlays, the too-small screen.

use super::common::{Theme, cut_words};
use crate::tui::app::{App, Confirm, MIN_HEIGHT, MIN_WIDTH, StatusKind};
use crate::tui::help::{self, HelpLine};
use crate::tui::keymap::{self, Action, Ctx};
use ratatui::Frame;
use ratatui::layout::{Alignment, Constraint, Layout, Rect};
use ratatui::style::Color;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Clear, Paragraph};

/// Draws the "terminal too small" screen.
pub(super) fn draw_too_small(frame: &mut Frame, area: Rect, th: &Theme) {
    let lines = vec![
        Line::styled("terminal too small", th.status(StatusKind::Warn)),
        Line::from(th.text(&format!("{}×{}", area.width, area.height))),
        Line::from(th.text(&format!("deckspin needs {MIN_WIDTH}×{MIN_HEIGHT}"))),
        Line::from("enlarge it, or q to quit"),
    ];
    let h = (lines.len() as u16).min(area.height);
    let y = area.y + area.height.saturating_sub(h) / 2;
    let r = Rect::new(area.x, y, area.width, h);
    frame.render_widget(Paragraph::new(lines).alignment(Alignment::Center), r);
}

/// The watch mode as shown, and the columns it takes at the right of the status area.
fn watch_text(app: &App, width: u16) -> (String, u16) {
    let wm = if app.watch_mode.is_empty() {
        String::new()
    } else {
        format!("watch: {}", app.watch_mode)
    };
    let ww = (wm.chars().count() as u16 + 1).min(width / 3);
    (wm, ww)
}

/// The status message in lines of the status area's width, at most `max` (the last cut with
/// `…` when it needs more: the log `M` has it whole).
fn status_lines(app: &App, width: u16, max: usize, th: &Theme) -> Vec<String> {
    let (_, ww) = watch_text(app, width);
    let room = width.saturating_sub(ww).max(1) as usize;
    let mut lines = crate::tui::messages::wrap(&th.text(&app.status), room);
    if lines.len() > max {
        let rest = lines[max - 1..].join(" ");
        lines.truncate(max - 1);
        lines.push(cut_words(&rest, room, &th.text("…")));
    }
    lines
}

/// The rows the status area takes at `width` in a screen `height` rows tall: as many as the
/// message needs, up to 2 (3 from 30 rows).
pub(super) fn status_height(app: &App, width: u16, height: u16, th: &Theme) -> u16 {
    let max = if height >= 30 { 3 } else { 2 };
    status_lines(app, width, max, th).len().clamp(1, max) as u16
}

/// Draws the status message (wrapped) and the watch mode.
pub(super) fn draw_status(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let (wm, ww) = watch_text(app, area.width);
    let [l, r] = Layout::horizontal([Constraint::Min(0), Constraint::Length(ww)]).areas(area);
    let lines: Vec<Line> = status_lines(app, area.width, area.height.max(1) as usize, th)
        .into_iter()
        .map(|s| Line::styled(s, th.status(app.status_kind)))
        .collect();
    frame.render_widget(Paragraph::new(lines), l);
    frame.render_widget(
        Paragraph::new(Line::styled(wm, th.dim())).alignment(Alignment::Right),
        r,
    );
}

/// How much a key hint is worth keeping when the bar is short (lower first): help and quit,
/// the mode's own keys and cancelling a running job, the usual keys, the rest; cancel with
/// nothing running last.
fn hint_rank(a: Action, ctx: Ctx, app: &App) -> u8 {
    use Action as A;
    match a {
        A::Help => 0,
        A::Quit => 1,
        A::Cancel | A::StudyCancel if app.running() || app.studies.running().is_some() => 2,
        A::Cancel | A::StudyCancel => 9,
        A::ToggleMarker | A::Suspend => 8,
        A::NextElement | A::Export | A::ToggleOverlay | A::StudyReopen => 6,
        _ if !matches!(ctx, Ctx::Global | Ctx::Charts | Ctx::Form | Ctx::Studies) => 3,
        _ => 5,
    }
}

/// Draws the key hints: whole items only, the most useful that fit, in the keymap's order;
/// when some are left out, `?` says it lists them all.
pub(super) fn draw_hints(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let items: Vec<(Action, String, &str, u8)> = keymap::hint_items(&app.contexts())
        .into_iter()
        .map(|(a, ctx, (k, h))| (a, th.text(k), h, hint_rank(a, ctx, app)))
        .collect();
    let width = |k: &str, h: &str| k.chars().count() + h.chars().count() + 2;
    let mut order: Vec<usize> = (0..items.len()).collect();
    order.sort_by_key(|&i| items[i].3);
    let all_keys = "all keys";
    let mut keep = vec![false; items.len()];
    let mut used = 0;
    for &i in &order {
        let (a, k, h, _) = &items[i];
        // room for the longer help text in case something is left out
        let h = if *a == Action::Help { all_keys } else { h };
        if used + width(k, h) <= area.width as usize {
            used += width(k, h);
            keep[i] = true;
        }
    }
    let dropped = keep.iter().any(|k| !k);
    let mut spans = Vec::new();
    for (i, (a, k, h, _)) in items.iter().enumerate().filter(|(i, _)| keep[*i]) {
        let h = if *a == Action::Help && dropped {
            all_keys
        } else {
            h
        };
        if i > 0 || !spans.is_empty() {
            spans.push(Span::raw(" "));
        }
        spans.push(Span::styled(k.clone(), th.bold().patch(th.selected())));
        spans.push(Span::raw(format!(" {h}")));
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

/// Draws the help overlay: every key, from the keymap ([`help`]); the keys of the view shown
/// come right after those that work everywhere. Taller than the screen, it scrolls
/// (`app.help_scroll`), and its bottom border says what is above and below.
pub(super) fn draw_help(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let rows = help::rows(area.height);
    let view = app.view_ctx();
    let cols = help::columns(view, rows);
    let max = help::max_scroll(view, area.height);
    let scroll = app.help_scroll.min(max);
    let line = |l: &HelpLine| match *l {
        HelpLine::Title(t) => Line::styled(t.to_string(), th.bold().patch(th.fg(Color::Cyan))),
        HelpLine::Key(k, d) => Line::from(vec![
            Span::styled(format!(" {:<8}", th.text(k)), th.bold()),
            Span::raw(th.text(d)),
        ]),
    };
    let [c0, c1] = cols.map(|c| {
        c.iter()
            .skip(scroll)
            .take(rows)
            .map(line)
            .collect::<Vec<_>>()
    });
    let rect = centered(area, area.width.min(100), area.height);
    let mut block = th.block(th.text(" help — keys (Esc closes) "));
    if max > 0 {
        let more = match (scroll > 0, scroll < max) {
            (_, true) => format!(" ↓ more below: j, PgDn ({}/{}) ", scroll + 1, max + 1),
            _ => format!(" ↑ the end: k, PgUp ({}/{}) ", scroll + 1, max + 1),
        };
        block = block.title_bottom(Line::styled(th.text(&more), th.bold()));
    }
    let inner = block.inner(rect);
    frame.render_widget(Clear, rect);
    frame.render_widget(block, rect);
    let [a, b] = Layout::horizontal([Constraint::Percentage(50), Constraint::Percentage(50)])
        .spacing(1)
        .areas(inner);
    frame.render_widget(Paragraph::new(c0), a);
    frame.render_widget(Paragraph::new(c1), b);
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
            {
                let mut q = Vec::new();
                if app.dirty() {
                    q.push(format!("{name} has unsaved edits."));
                }
                if let Some(crate::tui::app::Mode::Editing { buffer, .. }) = &app.typing_before_quit
                {
                    let field = app.form.selected().map_or("?".into(), |f| f.label.clone());
                    q.push(format!(
                        "You are typing {field} = '{buffer}', not valid yet: n goes back to it."
                    ));
                }
                q
            },
            vec![
                ("s", "save and quit"),
                ("y", "quit without saving"),
                ("n", "stay"),
            ],
        ),
        Confirm::Recover { found, differences } => {
            let mut q = vec![format!(
                "Unsaved edits of {name} found in {} (process {}{}):",
                found.path.display(),
                found.pid,
                if found.older_than_model {
                    "; the model file is newer"
                } else {
                    ""
                }
            )];
            let shown = 6;
            q.extend(differences.iter().take(shown).map(|d| format!("  {d}")));
            if differences.len() > shown {
                q.push(format!("  ({} more)", differences.len() - shown));
            }
            if differences.is_empty() {
                q.push("  (the same values as the model)".into());
            }
            if let Some(t) = &found.typing {
                q.push(format!("  being typed: {t}"));
            }
            let keys = vec![("r", "recover"), ("k/Esc", "keep as file"), ("d", "delete")];
            (q, keys)
        }
        Confirm::OpenModel { path } => (
            vec![format!(
                "Open {} and lose your unsaved edits of {name}?",
                path.display()
            )],
            yes_no,
        ),
        Confirm::DeleteRun { number } => {
            let e = app.runs.get(*number);
            let mut q = vec![format!(
                "Delete run #{number}{}?",
                e.map_or(String::new(), |e| format!(
                    " ({}, {})",
                    e.name,
                    e.ended.short()
                ))
            )];
            if app.runs.baseline == Some(*number) {
                q.push("It is the baseline: no run is the baseline after it.".into());
            }
            if let Some(d) = &app.runs.dir {
                q.push(format!("Its files are removed from {}.", d.display()));
            }
            (q, yes_no)
        }
    }
}

/// The keys of a question laid out in rows of at most `room` characters, whole items only.
fn key_rows(keys: &[(&str, &str)], room: usize) -> Vec<Vec<(String, String)>> {
    let mut rows: Vec<Vec<(String, String)>> = vec![Vec::new()];
    let mut used = 0;
    for (k, what) in keys {
        // " k " then " what", three spaces between items
        let w = k.chars().count() + 2 + 1 + what.chars().count();
        let row = rows.last_mut().expect("a row");
        if !row.is_empty() && used + 3 + w > room {
            rows.push(Vec::new());
            used = 0;
        }
        let row = rows.last_mut().expect("a row");
        used += if row.is_empty() { w } else { 3 + w };
        row.push((k.to_string(), what.to_string()));
    }
    rows
}

/// Draws the pending question: its lines wrapped at words, whole, in a box as wide as the
/// screen allows (up to 100 columns) and as tall as they need.
pub(super) fn draw_confirm(frame: &mut Frame, area: Rect, app: &App, c: &Confirm, th: &Theme) {
    let (q, keys) = question(app, c);
    let w = area.width.saturating_sub(4).min(100);
    let inside = w.saturating_sub(2).max(10) as usize;
    let mut text: Vec<String> = (q.iter())
        .flat_map(|l| crate::tui::messages::wrap(&th.text(l), inside))
        .collect();
    // no wider than the longest line needs
    let longest = text.iter().map(|l| l.chars().count()).max().unwrap_or(0);
    let keys: Vec<(String, String)> = (keys.iter())
        .map(|(k, what)| (th.text(k), th.text(what)))
        .collect();
    let key_refs: Vec<(&str, &str)> = keys.iter().map(|(k, w)| (k.as_str(), w.as_str())).collect();
    let rows = key_rows(&key_refs, inside);
    let keys_w = (rows.iter())
        .map(|r| {
            (r.iter())
                .map(|(k, what)| k.chars().count() + 3 + what.chars().count())
                .sum::<usize>()
                + 3 * r.len().saturating_sub(1)
        })
        .max()
        .unwrap_or(0);
    let w = (longest.max(keys_w).max(20) as u16 + 2).min(w);
    text.push(String::new());
    let h = text.len() + rows.len() + 2;
    let rect = centered(area, w, h as u16);
    let block = th
        .block(" question ")
        .border_style(th.status(StatusKind::Warn));
    let inner = block.inner(rect);
    frame.render_widget(Clear, rect);
    frame.render_widget(block, rect);
    let mut lines: Vec<Line> = text.into_iter().map(Line::from).collect();
    for r in rows {
        let mut row = Vec::new();
        for (i, (k, what)) in r.into_iter().enumerate() {
            if i > 0 {
                row.push(Span::raw("   "));
            }
            row.push(Span::styled(
                format!(" {k} "),
                th.selected().patch(th.bold()),
            ));
            row.push(Span::raw(format!(" {what}")));
        }
        lines.push(Line::from(row));
    }
    frame.render_widget(Paragraph::new(lines), inner);
}
