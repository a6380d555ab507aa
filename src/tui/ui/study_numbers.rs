//! A study's numbers beside its chart (under it when the panel is narrow): the table of its
//! points ([`Points`]), the row at the cursor marked `>` and highlighted, scrolled to keep it
//! in view; and the readout line, the values at the cursor with their units.

use super::common::{Theme, fit};
use crate::tui::chart::fmt_sig;
use crate::tui::studies::points::{Points, cell};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

/// The chart keeps at least this many columns beside the table; narrower, the table goes
/// under it.
const CHART_MIN_W: u16 = 40;

/// Where the chart, the table and the readout go in `area`.
pub(super) struct Split {
    pub chart: Rect,
    pub table: Rect,
    pub readout: Rect,
}

/// The widths of the columns: the label (with the cursor's `>`), x (0: none), each value.
fn widths(p: &Points, th: &Theme) -> (usize, usize, Vec<usize>) {
    let n = |s: &str| th.text(s).chars().count();
    let label = (p.rows.iter().map(|r| n(&r.label)))
        .chain([n(&p.label_head)])
        .max()
        .unwrap_or(0)
        + 1;
    let x = if p.x_name.is_empty() {
        0
    } else {
        (p.rows.iter().map(|r| cell(r.x).len()))
            .chain([n(&p.x_name) + 3 + n(&p.x_unit)])
            .max()
            .unwrap_or(0)
    };
    let values = (p.columns.iter().enumerate())
        .map(|(k, c)| {
            (p.rows.iter().map(|r| cell(r.values[k]).len()))
                .chain([2 + n(&c.head)])
                .max()
                .unwrap_or(0)
        })
        .collect();
    (label, x, values)
}

/// The table's full width.
fn table_width(p: &Points, th: &Theme) -> u16 {
    let (l, x, v) = widths(p, th);
    let x = if x > 0 { x + 1 } else { 0 };
    (l + x + v.iter().map(|w| w + 1).sum::<usize>()).min(u16::MAX as usize) as u16
}

/// The panel split: the readout on the last line; the table on the right when the chart keeps
/// [`CHART_MIN_W`] columns beside it, else under the chart (at most half the height).
pub(super) fn split(area: Rect, p: &Points, th: &Theme) -> Split {
    let [body, readout] = Layout::vertical([Constraint::Min(0), Constraint::Length(1)]).areas(area);
    let tw = table_width(p, th);
    if body.width >= tw.saturating_add(1 + CHART_MIN_W) {
        let [chart, _, table] = Layout::horizontal([
            Constraint::Min(0),
            Constraint::Length(1),
            Constraint::Length(tw),
        ])
        .areas(body);
        Split {
            chart,
            table,
            readout,
        }
    } else {
        let h = (p.rows.len() as u16 + 1).min(body.height / 2).max(2);
        let [chart, table] =
            Layout::vertical([Constraint::Min(0), Constraint::Length(h)]).areas(body);
        Split {
            chart,
            table,
            readout,
        }
    }
}

/// Draws the table in `area`: a heading, then the rows around the cursor; columns that do not
/// fit the width are left out whole (the readout has every value).
pub(super) fn draw_table(frame: &mut Frame, area: Rect, p: &Points, cursor: usize, th: &Theme) {
    if area.height < 2 || area.width < 8 {
        return;
    }
    let (lw, xw, vw) = widths(p, th);
    let width = area.width as usize;
    let mut used = lw;
    let mut head = vec![Span::styled(
        format!(" {:<w$}", th.text(&p.label_head), w = lw - 1),
        th.bold(),
    )];
    let show_x = xw > 0 && used + 1 + xw <= width;
    if show_x {
        used += 1 + xw;
        let h = th.text(&format!("{} [{}]", p.x_name, p.x_unit));
        head.push(Span::styled(format!(" {h:>xw$}"), th.bold()));
    }
    let mut shown = Vec::new();
    for (k, c) in p.columns.iter().enumerate() {
        if used + 1 + vw[k] > width {
            break;
        }
        used += 1 + vw[k];
        shown.push(k);
        let h = format!("{} {}", c.mark, th.text(&c.head));
        head.push(Span::styled(format!(" {h:>w$}", w = vw[k]), th.bold()));
    }
    let rows = area.height as usize - 1;
    let cursor = cursor.min(p.rows.len().saturating_sub(1));
    let off = cursor.saturating_sub(rows.saturating_sub(1));
    let mut lines = vec![Line::from(head)];
    for (i, r) in p.rows.iter().enumerate().skip(off).take(rows) {
        let mark = if i == cursor { '>' } else { ' ' };
        let mut s = format!("{mark}{:<w$}", th.text(&r.label), w = lw - 1);
        if show_x {
            s.push_str(&format!(" {:>xw$}", cell(r.x)));
        }
        for &k in &shown {
            s.push_str(&format!(" {:>w$}", cell(r.values[k]), w = vw[k]));
        }
        lines.push(if i == cursor {
            Line::styled(s, th.selected().patch(th.bold()))
        } else {
            Line::from(s)
        });
    }
    frame.render_widget(Paragraph::new(lines), area);
}

/// The readout at the cursor: `run 3 (3/7) · PGA x 0.4 g · o no contact 1.054e-3 rad ·
/// # contact 5.449e-4 rad`, the values with 4 significant digits; when that is too long, each
/// value after its series' mark alone and the unit once (`μ 0.3 (2/8) [%] · 1 3.97 · 2 13.2`),
/// and what still does not fit left out whole.
pub(super) fn readout(p: &Points, cursor: usize, width: usize, th: &Theme) -> String {
    let Some(r) = p.at(cursor) else {
        return String::new();
    };
    let at = cursor.min(p.rows.len() - 1) + 1;
    let value = |v: f64, unit: &str| {
        if v.is_nan() {
            "-".to_string()
        } else {
            format!("{} {unit}", fmt_sig(v, 4))
        }
    };
    let head = format!("{} {} ({at}/{})", p.label_head, r.label, p.rows.len());
    let x = (!p.x_name.is_empty()).then(|| format!("{} {}", p.x_name, value(r.x, &p.x_unit)));
    let mut items: Vec<String> = [head.clone()].into_iter().chain(x.clone()).collect();
    for (c, v) in p.columns.iter().zip(&r.values) {
        items.push(format!("{} {} {}", c.mark, c.head, value(*v, &p.unit)));
    }
    // too long with every name and unit: the marks alone, the unit once
    if items.join(th.sep()).chars().count() > width {
        items = [format!("{head} [{}]", p.unit)]
            .into_iter()
            .chain(x)
            .collect();
        for (c, v) in p.columns.iter().zip(&r.values) {
            items.push(format!("{} {}", c.mark, value(*v, "").trim_end()));
        }
    }
    let items: Vec<String> = items.iter().map(|i| th.text(i)).collect();
    fit(&items, th.sep(), width)
}
