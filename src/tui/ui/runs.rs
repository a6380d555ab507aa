//! The runs view (`#`): the run list (number, name, status, key results; the baseline marked
//! `B`, the overlaid runs `+`), the model diff of the selected run against the baseline, and
//! the comparison of the runs.

use super::common::Theme;
use super::compare::draw_compare;
use crate::tui::app::{App, Mode};
use crate::tui::runs::list::{Entry, cell};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::Line;
use ratatui::widgets::{Paragraph, Row, Table, Wrap};

/// Draws the runs view.
pub(super) fn draw_runs(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    // the list as tall as it needs (at least 5 lines), the diff and comparison the rest
    let list_h = (app.runs.list.len() as u16 + 3).clamp(5, area.height.saturating_sub(14).max(5));
    let bottom_h = area.height.saturating_sub(list_h);
    let [list, bottom] =
        Layout::vertical([Constraint::Min(0), Constraint::Length(bottom_h)]).areas(area);
    draw_list(frame, list, app, th);
    if bottom.height == 0 {
        return;
    }
    let cmp_w = (area.width * 3 / 5).min(2 + 13 + 10 * 6);
    let [diff, cmp] =
        Layout::horizontal([Constraint::Min(0), Constraint::Length(cmp_w)]).areas(bottom);
    draw_diff(frame, diff, app, th);
    draw_compare(frame, cmp, app, th);
}

/// The name cell: the name, or the one being typed.
fn name_of(app: &App, e: &Entry) -> String {
    match &app.mode {
        Mode::Naming { number, buffer } if *number == e.number => format!("{buffer}_"),
        _ => e.name.clone(),
    }
}

/// The run list, the selected run in reverse video and kept in sight.
fn draw_list(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let runs = &app.runs;
    let title = match runs.baseline {
        Some(b) => format!(" runs ({}) · baseline #{b} ", runs.list.len()),
        None => format!(" runs ({}) · no baseline ", runs.list.len()),
    };
    let block = th.block(th.text(&title));
    if runs.list.is_empty() {
        let msg = "no run kept yet: r runs the model; every run that ends is kept here";
        frame.render_widget(
            Paragraph::new(msg).wrap(Wrap { trim: true }).block(block),
            area,
        );
        return;
    }
    let rot = runs.list[0].results.rotation.ends_with(".theta");
    let peak = th.text(if rot { "peak |θ|" } else { "peak" });
    let peak_w = (peak.chars().count() as u16).max(9);
    let header = Row::new(vec![
        String::new(),
        "#".into(),
        "name".into(),
        "status".into(),
        peak,
        "impacts".into(),
        "changes".into(),
    ])
    .style(th.bold());
    let status_w = (runs.list.iter())
        .map(|e| e.ended.short().chars().count())
        .max()
        .unwrap_or(0)
        .clamp(9, 20) as u16;
    let visible = area.height.saturating_sub(3).max(1) as usize;
    let first = runs.selected.saturating_sub(visible - 1);
    let rows = runs
        .list
        .iter()
        .enumerate()
        .skip(first)
        .take(visible)
        .map(|(i, e)| {
            let mark = if Some(e.number) == runs.baseline {
                "B"
            } else if e.overlay {
                "+"
            } else {
                ""
            };
            let changes = if runs.baseline.is_none() || Some(e.number) == runs.baseline {
                String::new()
            } else {
                e.changes.len().to_string()
            };
            let row = Row::new(vec![
                mark.to_string(),
                format!("#{}", e.number),
                th.text(&name_of(app, e)),
                e.ended.short(),
                cell(e.results.peak_rot),
                e.results.impacts.to_string(),
                changes,
            ]);
            if i == runs.selected {
                row.style(th.selected())
            } else {
                row
            }
        });
    let widths = [
        Constraint::Length(1),
        Constraint::Length(5),
        Constraint::Min(12),
        Constraint::Length(status_w),
        Constraint::Length(peak_w),
        Constraint::Length(7),
        Constraint::Length(7),
    ];
    frame.render_widget(Table::new(rows, widths).header(header).block(block), area);
}

/// The model diff of the selected run against the baseline: one value per line.
fn draw_diff(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let runs = &app.runs;
    let Some(e) = runs.selected_entry() else {
        frame.render_widget(th.block(" model diff "), area);
        return;
    };
    let (title, lines) = match runs.baseline {
        None => (
            format!(" #{} · no baseline ", e.number),
            vec![Line::from("b pins the selected run as the baseline")],
        ),
        Some(b) if b == e.number => (
            format!(" #{b} is the baseline "),
            vec![Line::from(
                "the other runs' models are compared with its model",
            )],
        ),
        Some(b) if e.changes.is_empty() => (
            format!(" #{} against #{b} ", e.number),
            vec![Line::from("the same model")],
        ),
        Some(b) => (
            format!(" #{} against #{b}: {} changed ", e.number, e.changes.len()),
            e.changes
                .iter()
                .map(|c| Line::from(th.text(&c.line())))
                .collect(),
        ),
    };
    frame.render_widget(
        Paragraph::new(lines)
            .wrap(Wrap { trim: false })
            .block(th.block(th.text(&title))),
        area,
    );
}
