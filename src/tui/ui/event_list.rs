//! The event list (`E`, in place of the side panels): every event of the run in time order —
//! time, contact (or key element), kind, the normal impulse of an impact — the selected row
//! following the cursor until moved, kept in view.

use super::common::{Theme, shown_run};
use super::timeline::{kind_mark, row_names};
use crate::tui::app::App;
use crate::tui::runs::data::RunData;
use crate::tui::runs::nav;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::Paragraph;

/// Width of the time column (`0.952341`, `12.3456`).
const TIME_W: usize = 8;

/// Column widths of the list in `width` columns: contact, kind, impulse (0: left out). When a
/// contact's name (shortened as in the strip) and the kind's word do not fit, the kind is its
/// strip mark (width 1).
fn columns(run: &RunData, width: usize) -> (usize, usize, usize) {
    let contact = run
        .events
        .iter()
        .map(|e| nav::subject(run, e).chars().count())
        .max()
        .unwrap_or(0)
        .max(7);
    let kind = run
        .events
        .iter()
        .map(|e| e.kind.label().len())
        .max()
        .unwrap_or(4)
        .max(4);
    let impulse = 11;
    let base = TIME_W + 1 + kind + 1;
    if base + contact + 1 + impulse <= width {
        (contact, kind, impulse)
    } else if base + contact.min(8) <= width {
        (width.saturating_sub(base).min(contact), kind, 0)
    } else {
        (width.saturating_sub(TIME_W + 3).min(contact), 1, 0)
    }
}

/// The first row shown so that `sel` is in a view of `rows` rows of `n`.
pub fn scroll(sel: usize, rows: usize, n: usize) -> usize {
    if rows == 0 || n <= rows {
        return 0;
    }
    sel.saturating_sub(rows / 2).min(n - rows)
}

/// Draws the event list of the shown run.
pub(super) fn draw_event_list(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let Some(run) = shown_run(app) else {
        frame.render_widget(
            Paragraph::new("no run yet").block(th.block(" events ")),
            area,
        );
        return;
    };
    let order = nav::in_time_order(run);
    let n = order.len();
    let sel = app
        .event_sel
        .or_else(|| nav::row_at(&order, run, app.cursor_time()))
        .map(|s| s.min(n.saturating_sub(1)));
    let title = match sel {
        Some(s) if n > 0 => format!(" events {}/{n} ", s + 1),
        _ => format!(" events ({n}) "),
    };
    let block = th.block(title);
    let inner = block.inner(area);
    frame.render_widget(block, area);
    if inner.height == 0 || inner.width == 0 {
        return;
    }
    let width = inner.width as usize;
    let (cw, kw, iw) = columns(run, width);
    let kn = nav::force_unit(app);
    let mut lines = vec![Line::styled(
        format!(
            "{:>TIME_W$} {:<cw$} {:<kw$}{}",
            "t [s]",
            "contact",
            if kw > 1 { "kind" } else { "" },
            if iw > 0 {
                format!(" {:>iw$}", "impulse")
            } else {
                String::new()
            }
        ),
        th.bold(),
    )];
    if n == 0 {
        lines.push(Line::styled("no events", th.dim()));
    }
    let rows = inner.height.saturating_sub(1) as usize;
    let first = scroll(sel.unwrap_or(0), rows, n);
    // the rows' names as distinct as the strip's
    let (contacts, elements) = (
        row_names(&run.contact_names, cw),
        row_names(&run.element_names, cw),
    );
    let label = |e: &crate::output::EventRecord| {
        let names = if e.kind.of_contact() {
            &contacts
        } else {
            &elements
        };
        (names.get(e.contact).cloned()).unwrap_or_else(|| nav::subject(run, e))
    };
    for (r, &i) in order.iter().enumerate().skip(first).take(rows) {
        let e = &run.events[i];
        let imp = if iw > 0 {
            let s = nav::impulse(e, kn, th.ascii).unwrap_or_default();
            format!(" {s:>iw$}")
        } else {
            String::new()
        };
        let kind = if kw > 1 {
            e.kind.label().to_string()
        } else {
            kind_mark(e.kind, th.ascii).to_string()
        };
        let text = format!(
            "{:>TIME_W$} {:<cw$} {kind:<kw$}{imp}",
            nav::fmt_time(e.t),
            label(e),
        );
        let style = if Some(r) == sel {
            th.selected()
        } else {
            Default::default()
        };
        lines.push(Line::styled(text, style));
    }
    frame.render_widget(Paragraph::new(lines), inner);
}
