//! The list of series for a time chart (`p`): every series the shown run records, filtered by
//! what is typed, `[x]` before those the chart shows, each with its unit.

use super::common::Theme;
use super::event_list::scroll;
use crate::tui::app::App;
use crate::tui::chart_prefs;
use crate::tui::runs::nav;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Clear, Paragraph};

/// Draws the list of chart `chart`'s series over `area`: the filter `query`, the rows
/// matching it, the `selected` one marked.
pub(super) fn draw_chart_picker(
    frame: &mut Frame,
    area: Rect,
    app: &App,
    (chart, query, selected): (usize, &str, usize),
    th: &Theme,
) {
    let Some(run) = app.current.as_ref() else {
        return;
    };
    let rows = chart_prefs::matching(run, query);
    let shown = app.charts.series(run, chart);
    let w = 56.min(area.width.saturating_sub(4)).max(20);
    let h = (rows.len() as u16 + 3)
        .min(area.height.saturating_sub(2))
        .max(5);
    let rect = Rect::new(
        area.x + area.width.saturating_sub(w) / 2,
        area.y + area.height.saturating_sub(h) / 2,
        w.min(area.width),
        h.min(area.height),
    );
    let title = format!(
        " chart {} series: {} of {} shown ",
        chart + 1,
        shown.len(),
        chart_prefs::matching(run, "").len()
    );
    let block = th.block(th.text(&title));
    let inner = block.inner(rect);
    frame.render_widget(Clear, rect);
    frame.render_widget(block, rect);
    if inner.height == 0 {
        return;
    }
    let filter = if query.is_empty() {
        Line::styled("filter: type a name (Space shows/hides)", th.dim())
    } else {
        Line::from(vec![
            Span::raw("filter: "),
            Span::styled(query.to_string(), th.bold()),
            Span::styled(format!("  {} found", rows.len()), th.dim()),
        ])
    };
    let mut lines = vec![filter];
    let room = inner.height.saturating_sub(1) as usize;
    let width = inner.width as usize;
    let units = nav::units(app);
    if rows.is_empty() {
        lines.push(Line::styled("no series matches", th.dim()));
    }
    let sel = selected.min(rows.len().saturating_sub(1));
    for (i, id) in rows
        .iter()
        .enumerate()
        .skip(scroll(sel, room, rows.len()))
        .take(room)
    {
        let mark = if shown.contains(id) { "[x]" } else { "[ ]" };
        let (unit, _) = chart_prefs::unit_of(id.dim(), &units, app.charts.theta, th.ascii);
        let unit = if unit.is_empty() {
            String::new()
        } else {
            format!("[{unit}]")
        };
        let pointer = if i == sel { ">" } else { " " };
        let left = format!("{pointer}{mark} {}", id.label());
        let pad = width.saturating_sub(left.chars().count() + unit.chars().count());
        let text: String = format!("{left}{}{unit}", " ".repeat(pad.max(1)))
            .chars()
            .take(width)
            .collect();
        lines.push(if i == sel {
            Line::styled(text, th.selected().patch(th.bold()))
        } else {
            Line::from(text)
        });
    }
    frame.render_widget(Paragraph::new(lines), inner);
}
