//! A time chart's header line: its title and unit, the value of each series at the cursor,
//! the overlaid runs' values and their extremes beyond the axis.

use super::common::Theme;
use crate::tui::eng::Scale;
use ratatui::style::Style;
use ratatui::text::{Line, Span};

/// One series of a time chart as drawn.
pub(super) struct Series {
    pub name: String,
    pub style: Style,
    /// Its points in the chart's unit.
    pub data: Vec<(f64, f64)>,
    /// The number of the overlaid run it belongs to (None: the shown run).
    pub overlay: Option<u64>,
    /// Its value at the cursor, in the chart's unit.
    pub now: Option<f64>,
}

/// The chart's header line: title [unit of the readouts] in `style`, and the value of each
/// series at the cursor in that unit, with one precision — named when they fit, the earlier
/// runs' values after them, with their extremes when these reach beyond the axis (`far`:
/// `┈#1 0.12 (-3.842…1.20)`); what does not fit whole is left out.
pub(super) fn chart_header(
    (title, style): (&str, Style),
    scale: &Scale,
    series: &[Series],
    far: &[(u64, [f64; 2])],
    width: usize,
    th: &Theme,
) -> Line<'static> {
    let head = Span::styled(format!("{title} [{}]", scale.unit), style);
    // in ASCII a dash would read as a minus sign: the values alone, in the legend's order
    let (glyph, dotted) = if th.ascii { ("", "") } else { ("━", "┈") };
    let current: Vec<&Series> = series.iter().filter(|s| s.overlay.is_none()).collect();
    let value = |s: &Series| s.now.map_or("—".to_string(), |v| scale.fmt(v));
    let named = current.len() > 1;
    // without colour, the series' own mark (as drawn) before its value
    let sample = |k: usize| {
        if th.marks() {
            format!(" [{}]", th.legend_mark(k))
        } else {
            format!(" {glyph}")
        }
    };
    // names: 2 whole, 1 their initials (left_top: lt), 0 none, 3 the initials alone
    let item = |(k, s): (usize, &&Series), names: u8| -> Vec<Span<'static>> {
        let mut v = vec![Span::styled(sample(k), s.style)];
        match names {
            2 => v.push(Span::raw(format!("{} ", s.name))),
            1 => v.push(Span::raw(format!("{} ", initials(&s.name)))),
            // without colour a series needs its name more than its value
            3 => {
                v.push(Span::raw(initials(&s.name)));
                return v;
            }
            _ => {}
        }
        v.push(Span::styled(value(s), th.cursor()));
        v
    };
    // one item per overlaid run: its number and its values
    let mut numbers: Vec<(u64, Style)> = Vec::new();
    for s in series {
        if let Some(n) = s.overlay
            && !numbers.iter().any(|(m, _)| *m == n)
        {
            numbers.push((n, s.style));
        }
    }
    // each overlaid run's item with its extremes beyond the axis, and without them
    let prev_items = |with_range: bool| -> Vec<Vec<Span<'static>>> {
        (numbers.iter())
            .map(|&(n, style)| {
                let vals: Vec<String> = (series.iter())
                    .filter(|s| s.overlay == Some(n))
                    .map(value)
                    .collect();
                let dotted = if th.marks() {
                    format!("[{}]", th.previous_mark())
                } else {
                    dotted.to_string()
                };
                let range = (far.iter().filter(|_| with_range).find(|f| f.0 == n))
                    .map(|(_, [lo, hi])| {
                        th.text(&format!(" ({}…{})", scale.fmt(*lo), scale.fmt(*hi)))
                    })
                    .unwrap_or_default();
                vec![Span::styled(
                    format!(" {dotted}#{n} {}{range}", vals.join(" ")),
                    style,
                )]
            })
            .collect()
    };
    let (prev_long, prev_short) = (prev_items(true), prev_items(false));
    // prev: 2 the overlaid runs with their extremes beyond the axis, 1 without, 0 none
    let items = |names: u8, prev: u8| -> Vec<Vec<Span<'static>>> {
        let mut v: Vec<Vec<Span>> = current
            .iter()
            .enumerate()
            .map(|ks| item(ks, names))
            .collect();
        match prev {
            2 => v.extend(prev_long.iter().cloned()),
            1 => v.extend(prev_short.iter().cloned()),
            _ => {}
        }
        v
    };
    let wide = |it: &[Span]| it.iter().map(|s| s.content.chars().count()).sum::<usize>();
    let room = width.saturating_sub(wide(std::slice::from_ref(&head)));
    let total = |v: &Vec<Vec<Span>>| v.iter().map(|i| wide(i)).sum::<usize>();
    let mut variants = Vec::new();
    let mut names: Vec<u8> = Vec::new();
    if named {
        names.extend([2, 1]);
        if th.marks() {
            names.push(3);
        }
    }
    names.push(0);
    for n in names {
        variants.extend([items(n, 2), items(n, 1), items(n, 0)]);
    }
    let chosen = variants.iter().find(|v| total(v) <= room).cloned();
    let mut spans = vec![head];
    match chosen {
        Some(v) => spans.extend(v.into_iter().flatten()),
        None => {
            let mut used = 0;
            for it in items(0, 0) {
                if used + wide(&it) > room {
                    break;
                }
                used += wide(&it);
                spans.extend(it);
            }
        }
    }
    Line::from(spans)
}

/// A series name by its initials: the first letter of each `_`-separated word of its last
/// dotted part (`left_top` → `lt`, `deck.x` → `x`).
fn initials(name: &str) -> String {
    let last = name.rsplit('.').next().unwrap_or(name);
    last.split('_').filter_map(|w| w.chars().next()).collect()
}
