//! The swings' panel: the quantity shown (`n` the next) and its base median on the first line;
//! then one row per uncertain input, widest swing first — its name, the quantity's median at
//! the input's low and high value, the swing high − low and the swing relative to the base —
//! each row with its tornado bar beside it (`design::tornado`: from the base value to the value
//! at the low value `=` and to the value at the high value `#`, the base a `:` line), the row
//! at the cursor marked `>` and highlighted; under them the bars' axis, the legend and the
//! selected input's range and values.

use super::common::{Theme, fit, fit_lines};
use crate::design::swings::{Sensitivity, range_text};
use crate::design::tornado::{tornado, unit};
use crate::plot::Bars;
use crate::tui::chart::fmt_sig;
use crate::tui::studies::design_rows::{order, quantity};
use crate::tui::studies::points::cell;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};

/// The inputs' names: at most this wide.
const NAME_MAX: usize = 20;
/// The columns after the name: ` low` (9), ` high` (9), ` swing` (9), ` rel` (8).
const VALUES_W: usize = 35;
/// The bars keep at least this many columns, else they are left out.
const BARS_MIN: usize = 12;

/// A signed number as the table shows it (`+4.32e-3`, `-10`).
fn signed(v: Option<f64>) -> String {
    match v {
        Some(v) if v > 0.0 => format!("+{}", cell(v)),
        Some(v) => cell(v),
        None => "-".into(),
    }
}

/// A relative swing in % (`+112 %`, `-0.7 %`).
fn relative(r: Option<f64>) -> String {
    match r.map(|r| 100.0 * r) {
        Some(p) if p.abs() < 9.95 => format!("{p:+.1} %"),
        Some(p) => format!("{p:+.0} %"),
        None => "-".into(),
    }
}

/// Draws the swings of quantity `q` in `area`, `cursor` the selected row.
pub(super) fn draw_tornado(
    frame: &mut Frame,
    area: Rect,
    s: &Sensitivity,
    (q, cursor): (usize, usize),
    th: &Theme,
) {
    let Some(chart) = tornado(s, quantity(s, q)) else {
        let text = format!(
            "no quantity has a value in a run of the model itself: {} of {} runs did not finish",
            s.failed().len(),
            s.rows.len()
        );
        let p = Paragraph::new(th.text(&text)).wrap(Wrap { trim: true });
        return frame.render_widget(p, area);
    };
    if area.height < 4 || area.width < 30 {
        return;
    }
    let q = quantity(s, q);
    let order = order(s, q);
    let cursor = cursor.min(order.len().saturating_sub(1));
    let w = area.width as usize;
    let name = &s.quantities[q];
    let u = unit(name);
    let mut lines = vec![summary(s, q, w, th)];
    let names = (s.inputs.iter().map(|i| i.input.name.chars().count()))
        .chain([5])
        .max()
        .unwrap_or(5)
        .min(NAME_MAX);
    let tw = 1 + names + VALUES_W;
    let bw = w.saturating_sub(tw + 1);
    let bw = if bw >= BARS_MIN { bw } else { 0 };
    let scale = Scale::of(&chart.bars, s.base[q], bw);
    let [low, high] = [&chart.bars[0], &chart.bars[1]];
    // the heading, the rows, the axis, the legend, the readout
    let rows = (area.height as usize).saturating_sub(5).max(1);
    let text = format!(
        " {:<names$} {:>8} {:>8} {:>8} {:>7}",
        "input", "low", "high", "swing", "rel"
    );
    let mut heading = vec![Span::styled(th.text(&text), th.bold())];
    if bw > 0 {
        let what = match u {
            "" => format!(" {name}"),
            u => format!(" {name} [{u}]"),
        };
        heading.push(Span::styled(th.text(&what), th.bold()));
    }
    lines.push(Line::from(heading));
    let off = cursor.saturating_sub(rows.saturating_sub(1));
    for (row, &i) in order.iter().enumerate().skip(off).take(rows) {
        let style = if row == cursor {
            th.selected().patch(th.bold())
        } else {
            Style::default()
        };
        let mark = if row == cursor { '>' } else { ' ' };
        let text = th.text(&row_text(s, (q, i), mark, names));
        let mut spans = vec![Span::styled(text, style)];
        if let Some(sc) = scale.as_ref() {
            spans.push(Span::raw(" "));
            spans.extend(sc.bar(row, [low, high], th));
        }
        lines.push(Line::from(spans));
    }
    if let Some(sc) = scale.as_ref() {
        let axis = sc.axis(tw + 1, u);
        lines.push(Line::styled(th.text(&axis), th.dim()));
        let legend = [
            format!("{} {}", low.glyph, low.label),
            format!("{} {}", high.glyph, high.label),
            format!(": base {}", value(s.base[q], u)),
        ];
        let legend: Vec<String> = legend.iter().map(|l| th.text(l)).collect();
        lines.push(Line::styled(fit(&legend, th.sep(), w), th.dim()));
    }
    if let Some(&i) = order.get(cursor) {
        let at = format!("({}/{})", cursor + 1, order.len());
        let items: Vec<String> = (readout(s, (q, i), &at).iter())
            .map(|i| th.text(i))
            .collect();
        // on the panel's last lines, two when there is room
        let free = (area.height as usize)
            .saturating_sub(lines.len())
            .clamp(1, 2);
        let readout = fit_lines(&items, th.sep(), w, free);
        let y = (area.height as usize).saturating_sub(readout.len());
        while lines.len() < y {
            lines.push(Line::from(""));
        }
        lines.truncate(y);
        lines.extend(readout.into_iter().map(|l| Line::styled(l, th.bold())));
    }
    frame.render_widget(Paragraph::new(lines), area);
}

/// The first line: the quantity shown, its base median, the cases and runs.
fn summary(s: &Sensitivity, q: usize, w: usize, th: &Theme) -> Line<'static> {
    let name = &s.quantities[q];
    let failed = match s.failed().len() {
        0 => String::new(),
        f => format!(", {f} did not finish"),
    };
    let head = [
        format!("{name} ({}/{}; n the next)", q + 1, s.quantities.len()),
        format!("base median {}", value(s.base[q], unit(name))),
        format!("{} cases, {} runs{failed}", s.cases(), s.rows.len()),
    ];
    let head: Vec<String> = head.iter().map(|h| th.text(h)).collect();
    Line::styled(fit(&head, th.sep(), w), th.bold())
}

/// Input `i`'s row for quantity `q`: its name, the values at its low and high value, the
/// swing and the relative swing.
fn row_text(s: &Sensitivity, (q, i): (usize, usize), mark: char, names: usize) -> String {
    let input = &s.inputs[i];
    let sw = &input.swings[q];
    let label: String = input.input.name.chars().take(names).collect();
    format!(
        "{mark}{label:<names$} {:>8} {:>8} {:>8} {:>7}",
        sw.low.map_or("-".into(), cell),
        sw.high.map_or("-".into(), cell),
        signed(sw.swing()),
        relative(sw.relative())
    )
}

/// Input `i` at the cursor (`at`: its place): its range, cases, keys and values.
fn readout(s: &Sensitivity, (q, i): (usize, usize), at: &str) -> Vec<String> {
    let input = &s.inputs[i];
    let sw = &input.swings[q];
    let u = unit(&s.quantities[q]);
    vec![
        format!("> {} {at}", input.input.name),
        range_text(&input.input),
        match sw.cases {
            1 => format!("1 case, {} left out", sw.failed),
            n => format!("{n} cases, {} left out", sw.failed),
        },
        input.input.key.clone(),
        format!("low {}", value(sw.low, u)),
        format!("high {}", value(sw.high, u)),
        format!("swing {} ({})", signed(sw.swing()), relative(sw.relative())),
    ]
}

/// A value with 4 significant digits and its unit (`-` for none).
fn value(v: Option<f64>, unit: &str) -> String {
    match v {
        Some(v) if unit.is_empty() => fmt_sig(v, 4),
        Some(v) => format!("{} {unit}", fmt_sig(v, 4)),
        None => "-".into(),
    }
}

/// The bars' x scale over `width` columns: the span of every bar's ends and the base median.
struct Scale {
    lo: f64,
    hi: f64,
    width: usize,
    /// The median of the model's own runs (the tornado's line).
    base: Option<f64>,
}

impl Scale {
    fn of(bars: &[Bars], base: Option<f64>, width: usize) -> Option<Self> {
        let ends = bars
            .iter()
            .flat_map(|b| b.bars.iter().flat_map(|r| [r.1, r.2]));
        let ends: Vec<f64> = (ends.chain(base)).filter(|v| v.is_finite()).collect();
        if width == 0 || ends.is_empty() {
            return None;
        }
        let lo = ends.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = ends.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let (lo, hi) = if hi > lo {
            (lo, hi)
        } else {
            let d = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
            (lo - d, hi + d)
        };
        Some(Self {
            lo,
            hi,
            width,
            base: base.filter(|b| b.is_finite()),
        })
    }

    /// The column of `v`.
    fn col(&self, v: f64) -> usize {
        let f = ((v - self.lo) / (self.hi - self.lo)).clamp(0.0, 1.0);
        (f * (self.width - 1) as f64).round() as usize
    }

    /// Row `row`'s bars: the longer bar, then the shorter over it, then the row's base (where
    /// its bars start: the median of the model's runs over the cases its runs all finished)
    /// as a `:`.
    fn bar(&self, row: usize, sets: [&Bars; 2], th: &Theme) -> Vec<Span<'static>> {
        let mut cells: Vec<(char, Style)> = vec![(' ', Style::default()); self.width];
        let mut base = None;
        let mut bars: Vec<(usize, usize, char, Style)> = (sets.iter())
            .filter_map(|set| {
                let &(_, from, to) = set.bars.iter().find(|r| r.0 == row)?;
                base = Some(from);
                let (a, b) = (self.col(from), self.col(to));
                Some((a.min(b), a.max(b), set.glyph, th.series(set.color)))
            })
            .collect();
        bars.sort_by_key(|b| std::cmp::Reverse(b.1 - b.0));
        for (a, b, g, style) in bars {
            for c in &mut cells[a..=b] {
                *c = (g, style.patch(th.bold()));
            }
        }
        if let Some(b) = base {
            cells[self.col(b)] = (':', th.dim());
        }
        cells
            .into_iter()
            .map(|(c, st)| Span::styled(c.to_string(), st))
            .collect()
    }

    /// The axis under the bars, `indent` columns in: the least value at the left, the largest
    /// at the right, the base under its column when there is room.
    fn axis(&self, indent: usize, unit: &str) -> String {
        let lo = fmt_sig(self.lo, 3);
        let hi = fmt_sig(self.hi, 3);
        let mut line: Vec<char> = vec![' '; self.width];
        let put = |line: &mut Vec<char>, at: usize, s: &str| {
            for (k, c) in s.chars().enumerate() {
                if let Some(x) = line.get_mut(at + k) {
                    *x = c;
                }
            }
        };
        put(&mut line, 0, &lo);
        put(&mut line, self.width.saturating_sub(hi.len()), &hi);
        if let Some(b) = self.base {
            let t = format!("^{}", fmt_sig(b, 3));
            let at = self.col(b);
            let free = at > lo.len() && at + t.len() < self.width.saturating_sub(hi.len());
            if free {
                put(&mut line, at, &t);
            }
        }
        let unit = if unit.is_empty() {
            String::new()
        } else {
            format!("[{unit}]")
        };
        let tail: String = line.into_iter().collect();
        format!("{unit:>w$} {tail}", w = indent.saturating_sub(1))
    }
}
