//! The form view: the parameter list and the selected field's details (path, type, unit,
//! saved value, comment, live verdict while typing).

use super::common::Theme;
use super::side::draw_summary;
use crate::tui::app::{App, Mode, StatusKind};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::{Color, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

/// Draws the form view.
pub(super) fn draw_form(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let left_w = (area.width * 55 / 100).max(34);
    let [left, right] =
        Layout::horizontal([Constraint::Length(left_w), Constraint::Min(0)]).areas(area);
    let title = if app.dirty() {
        " parameters — edited (* unsaved; s saves) "
    } else {
        " parameters "
    };
    let block = th.block(th.text(title));
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
        let label: String = th.text(&f.label).chars().take(label_w).collect();
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
            th.text(&f.unit).chars().take(unit_w).collect()
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

/// Draws the selected field's details.
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
                format!(", {}", th.text(&f.unit))
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
                    th.text("✓ valid — Enter accepts"),
                    th.status(StatusKind::Ok),
                )),
                Err(e) => {
                    let prefix = format!("{}:", app.path.display());
                    let short = e
                        .strip_prefix(&prefix)
                        .map_or(e.clone(), |r| format!("at {r}"));
                    lines.push(Line::styled(
                        th.text(&format!("✗ {short}")),
                        th.status(StatusKind::Error),
                    ));
                }
            }
        }
        _ => lines.push(Line::styled(
            th.text("Enter edits · u reverts · s saves · r runs"),
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
