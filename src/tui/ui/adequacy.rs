//! The model ladder's panel: the cheapest variant within the tolerance on the first line; the
//! table of the full model and its variants (their chart letter, name, CPU time, how many times
//! faster, the worst error over the quantities, then as many quantities' errors as fit),
//! the row at the cursor marked `>` and highlighted; beside it the chart of CPU time against
//! the worst error (`design::adequacy_report::chart`, each variant by its letter, the
//! tolerance and the full model's CPU time as lines); under both the selected variant's cost
//! and its error in every quantity, and what `a` does with it.

use super::common::{Theme, fit, fit_lines};
use super::line_plot::{Look, draw_line_plot};
use crate::design::adequacy::{Adequacy, Outcome};
use crate::design::adequacy_report::{chart, percent, short};
use crate::plot::Chart;
use crate::tui::studies::design_rows::variant_of_row;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::Style;
use ratatui::text::Line;
use ratatui::widgets::Paragraph;

/// The chart keeps at least this many columns beside the table, else it is left out.
const CHART_MIN_W: usize = 34;
/// The variant names' column: at least, at most.
const NAME_MIN: usize = 12;
const NAME_MAX: usize = 26;
/// The columns after the name: ` CPU s` (8), ` faster` (7), ` worst` (8); a quantity's (9).
const COST_W: usize = 23;
const QUANTITY_W: usize = 9;
/// The readout's lines under the table (its first line the variant, the rest its errors).
const READOUT_LINES: usize = 3;

/// The chart's letter of variant `v` (as `adequacy_report::chart` marks it).
fn letter(v: usize) -> char {
    char::from(b'a' + (v % 26) as u8)
}

/// How many times faster than the full model.
fn faster(a: &Adequacy, o: &Outcome) -> String {
    format!("{:.1}×", a.full.cost().cpu / o.cost().cpu)
}

/// Draws the ladder's panel in `area`, `cursor` the selected row (0 the full model).
pub(super) fn draw_adequacy(
    frame: &mut Frame,
    area: Rect,
    a: &Adequacy,
    cursor: usize,
    th: &Theme,
) {
    if area.height < 4 || area.width < 20 {
        return;
    }
    let w = area.width as usize;
    let cursor = cursor.min(a.variants.len());
    let head = Line::styled(fit(&summary(a, th), th.sep(), w), th.bold());
    frame.render_widget(Paragraph::new(head), Rect { height: 1, ..area });
    let readout = readout(a, cursor, w, th);
    let rh = (readout.len() as u16).min(area.height - 2);
    let body = Rect::new(area.x, area.y + 1, area.width, area.height - 1 - rh);
    let under = Rect::new(area.x, body.y + body.height, area.width, rh);
    frame.render_widget(Paragraph::new(readout), under);
    // a variant's letter, a space and its name
    let names = (a
        .variants
        .iter()
        .map(|o| 2 + o.variant.name.chars().count()))
    .max()
    .unwrap_or(0)
    .clamp(NAME_MIN, NAME_MAX);
    // the chart beside the table when it keeps its columns; the table's name column gives way
    // first, down to its least
    let room = w.saturating_sub(2 + CHART_MIN_W);
    let (names, chart_w) = if room >= 2 + NAME_MIN + COST_W {
        (names.min(room - 2 - COST_W), true)
    } else {
        (names, false)
    };
    let fixed = 2 + names + COST_W;
    let free = if chart_w { room } else { w }.saturating_sub(fixed);
    let shown = (free / QUANTITY_W).min(a.quantities.len());
    let tw = (fixed + shown * QUANTITY_W).min(w) as u16;
    let table_area = Rect { width: tw, ..body };
    draw_table(frame, table_area, a, (cursor, names, shown), th);
    if chart_w {
        let x = body.x + tw + 2;
        let cw = (body.x + body.width).saturating_sub(x);
        let (chart, look) = plot(a, cursor);
        draw_line_plot(
            frame,
            Rect::new(x, body.y, cw, body.height),
            &chart,
            &look,
            th,
        );
    }
}

/// The first line: the cheapest variant within the tolerance in every quantity, the runs.
fn summary(a: &Adequacy, th: &Theme) -> Vec<String> {
    let tol = format!("{} %", 100.0 * a.tolerance);
    let cheapest = match a.cheapest(None) {
        Some(v) => {
            let o = &a.variants[v];
            format!(
                "cheapest within {tol}: {} {} ({} faster, worst {})",
                letter(v),
                o.variant.name,
                faster(a, o),
                percent(Some(a.worst(v)))
            )
        }
        None => format!("cheapest within {tol}: the full model (no variant within it is cheaper)"),
    };
    let runs = format!("{} runs: {}", a.cases.len(), a.cases.join(", "));
    [cheapest, runs].iter().map(|s| th.text(s)).collect()
}

/// `s` cut to `w` characters (`~` at the end when cut).
fn cut(s: &str, w: usize) -> String {
    if s.chars().count() <= w {
        s.to_string()
    } else {
        let head: String = s.chars().take(w.saturating_sub(1)).collect();
        format!("{head}~")
    }
}

/// The table: a heading, then the full model and the variants around the cursor; `shown`
/// quantity columns after the worst error.
fn draw_table(
    frame: &mut Frame,
    area: Rect,
    a: &Adequacy,
    (cursor, names, shown): (usize, usize, usize),
    th: &Theme,
) {
    if area.height < 2 {
        return;
    }
    let mut head = format!(
        "  {:<names$} {:>7} {:>6} {:>7}",
        "variant", "CPU s", "faster", "worst"
    );
    for q in a.quantities.iter().take(shown) {
        head.push_str(&format!(" {:>8}", short(q)));
    }
    let rows = area.height as usize - 1;
    let off = cursor.saturating_sub(rows.saturating_sub(1));
    let mut lines = vec![Line::styled(th.text(&head), th.bold())];
    for row in (0..=a.variants.len()).skip(off).take(rows) {
        let mark = if row == cursor { '>' } else { ' ' };
        let text = match variant_of_row(a, row) {
            None => {
                let c = a.full.cost().cpu;
                let mut s = format!(
                    "{mark} {:<names$} {c:>7.3} {:>6} {:>7}",
                    "  full", "1.0×", "-"
                );
                s.push_str(&" ".repeat(shown * QUANTITY_W));
                s
            }
            Some(v) => variant_row(a, v, mark, (names, shown)),
        };
        let style = match variant_of_row(a, row) {
            _ if row == cursor => th.selected().patch(th.bold()),
            Some(v) if a.worst(v) <= a.tolerance && a.variants[v].refused.is_none() => {
                th.status(crate::tui::app::StatusKind::Ok)
            }
            _ => Style::default(),
        };
        lines.push(Line::styled(th.text(&text), style));
    }
    frame.render_widget(Paragraph::new(lines), area);
}

/// Variant `v`'s row.
fn variant_row(a: &Adequacy, v: usize, mark: char, (names, shown): (usize, usize)) -> String {
    let o = &a.variants[v];
    let name = cut(&o.variant.name, names.saturating_sub(2));
    let name = format!("{} {name}", letter(v));
    if o.refused.is_some() {
        let mut s = format!(
            "{mark} {name:<names$} {:>7} {:>6} {:>7}",
            "-", "-", "refused"
        );
        s.push_str(&" ".repeat(shown * QUANTITY_W));
        return s;
    }
    let mut s = format!(
        "{mark} {name:<names$} {:>7.3} {:>6} {:>7}",
        o.cost().cpu,
        faster(a, o),
        percent(Some(a.worst(v)))
    );
    for q in a.quantities.iter().take(shown) {
        s.push_str(&format!(" {:>8}", percent(a.error(v, q))));
    }
    s
}

/// Under the table: the row at the cursor (its letter, name, cost, what `a` does), then its
/// error in every quantity.
fn readout(a: &Adequacy, cursor: usize, w: usize, th: &Theme) -> Vec<Line<'static>> {
    let n = a.variants.len() + 1;
    let at = format!("({}/{n})", cursor + 1);
    let Some(v) = variant_of_row(a, cursor) else {
        let c = a.full.cost();
        let items = [
            format!("> full model {at}"),
            format!("CPU {:.3} s", c.cpu),
            format!("{} steps, {} events", c.steps, c.events),
            "the reference of every error: j/k select a variant, a applies it".into(),
        ];
        let items: Vec<String> = items.iter().map(|s| th.text(s)).collect();
        return vec![Line::styled(fit(&items, th.sep(), w), th.bold())];
    };
    let o = &a.variants[v];
    let c = o.cost();
    let keys = match o.variant.changes.len() {
        1 => "1 key".to_string(),
        k => format!("{k} keys"),
    };
    let mut first = vec![format!("> {} {} {at}", letter(v), o.variant.name)];
    if let Some(why) = &o.refused {
        first.push(format!("refused: {why}"));
    } else {
        first.push(format!("{} faster", faster(a, o)));
        first.push(format!("a applies it to the form ({keys})"));
        first.push(format!("CPU {:.3} s", c.cpu));
        first.push(format!("{} steps, {} events", c.steps, c.events));
    }
    let first: Vec<String> = first.iter().map(|s| th.text(s)).collect();
    let mut out = vec![Line::styled(fit(&first, th.sep(), w), th.bold())];
    if o.refused.is_none() {
        let errors: Vec<String> = (a.quantities.iter())
            .map(|q| th.text(&format!("{} {}", short(q), percent(a.error(v, q)))))
            .collect();
        let lines = fit_lines(&errors, th.sep(), w, READOUT_LINES - 1);
        out.extend(lines.into_iter().map(Line::from));
    }
    out
}

/// The chart `deckspin adequacy` draws (CPU time against the worst error), its axes titled
/// for the panel, and the selected variant highlighted; its legend is the table's letter
/// column.
fn plot(a: &Adequacy, cursor: usize) -> (Chart, Look) {
    let mut c = chart(a, None);
    (c.y.title, c.y.unit) = ("worst error [-], log".into(), String::new());
    (c.x.title, c.x.unit) = ("CPU time [s], log".into(), String::new());
    let selected = variant_of_row(a, cursor).map(letter);
    let look = Look {
        legend: false,
        selected: c.series.iter().position(|s| Some(s.glyph) == selected),
        ..Look::default()
    };
    (c, look)
}
