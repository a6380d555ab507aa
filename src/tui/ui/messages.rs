//! The message log over the whole screen (`tui::messages`): every status message with its time,
//! wrapped, newest at the bottom.

use super::common::Theme;
use crate::tui::app::App;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::{Clear, Paragraph};

/// Draws the log in `area`, from `app.log_scroll` (past the end: the last page).
pub(super) fn draw_messages(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let width = area.width.saturating_sub(2) as usize;
    let rows = area.height.saturating_sub(2).max(1) as usize;
    let lines = crate::tui::messages::lines(&app.messages, width);
    let max = crate::tui::messages::max_scroll(lines.len(), rows);
    let scroll = app.log_scroll.min(max);
    let title = format!(
        " messages ({}) — j/k PgDn/PgUp Home/End, Esc closes ",
        app.messages.len()
    );
    let block = super::common::scrolled_block(th, &title, (scroll, rows, lines.len(), max), "");
    let shown: Vec<Line> = (lines.iter().skip(scroll).take(rows))
        .map(|(kind, l)| Line::styled(th.text(l), th.status(*kind)))
        .collect();
    let shown = if app.messages.is_empty() {
        vec![Line::raw("(no messages yet)")]
    } else {
        shown
    };
    let inner = block.inner(area);
    frame.render_widget(Clear, area);
    frame.render_widget(block, area);
    frame.render_widget(Paragraph::new(shown), inner);
}
