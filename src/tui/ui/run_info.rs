//! A run's whole status over the body of the screen (`tui::runs::info`): its rows wrapped to the
//! width, scrolled from `app.info_scroll`.

use super::common::Theme;
use crate::tui::app::App;
use crate::tui::runs::info::{Info, lines};
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::{Clear, Paragraph};

/// Draws the run info in `area` (the screen between the header and the status line).
pub(super) fn draw_run_info(frame: &mut Frame, area: Rect, app: &App, info: &Info, th: &Theme) {
    let width = area.width.saturating_sub(2) as usize;
    let rows = area.height.saturating_sub(2).max(1) as usize;
    let all = lines(info, width);
    let max = all.len().saturating_sub(rows);
    let scroll = app.info_scroll.min(max);
    let title = format!(" {} — run info, Esc closes ", info.title);
    let keys = ": j/k PgDn/PgUp";
    let block = super::common::scrolled_block(th, &title, (scroll, rows, all.len(), max), keys);
    let shown: Vec<Line> = (all.iter().skip(scroll).take(rows))
        .map(|l| Line::raw(th.text(l)))
        .collect();
    let inner = block.inner(area);
    frame.render_widget(Clear, area);
    frame.render_widget(block, area);
    frame.render_widget(Paragraph::new(shown), inner);
}
