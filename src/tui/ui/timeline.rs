//! The event strip: one row per contact on the charts' time axis (events over the contact
//! state), a row of shear-key failures when there are any, the cursor column, the time axis.

use super::cache::{Cache, Key, time_key};
use super::common::{LABEL_W, Theme};
use crate::output::{ContactState, EventKind, EventRecord};
use crate::tui::chart::{self, column_of, fmt_num};
use crate::tui::run_data::RunData;
use ratatui::Frame;
use ratatui::layout::{Alignment, Rect};
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

/// Per-contact event strip: events (impact `*`, stick `S`, slip `~`, release `^`,
/// accumulation `!`) over the contact state (stuck `█`/`#`, sliding `▒`/`=`, open ` `); key
/// failures have their own row ([`key_strip`]).
pub fn event_strip(
    run: &RunData,
    contact: usize,
    t0: f64,
    t1: f64,
    width: usize,
    per_cell: usize,
    ascii: bool,
) -> Vec<char> {
    let mut rank: Vec<Option<u8>> = vec![None; width];
    let range = chart::window(&run.t, t0, t1);
    let states = &run.state[contact];
    for i in range.clone() {
        if let Some(c) = column_of(run.t[i], t0, t1, width, per_cell) {
            let r = match states[i] {
                ContactState::Stick => 2,
                ContactState::Slide(_) => 1,
                ContactState::Open => 0,
            };
            rank[c] = Some(rank[c].map_or(r, |x| x.max(r)));
        }
    }
    // a cell without samples keeps the state of the sample before it
    let last_col = run
        .t
        .get(range.end.saturating_sub(1))
        .filter(|_| range.end > range.start)
        .and_then(|&t| column_of(t, t0, t1, width, per_cell));
    let mut prev = range
        .start
        .checked_sub(1)
        .and_then(|i| states.get(i))
        .map(|s| match s {
            ContactState::Stick => 2,
            ContactState::Slide(_) => 1,
            ContactState::Open => 0,
        });
    for (c, r) in rank.iter_mut().enumerate() {
        if last_col.is_none_or(|l| c > l) {
            break;
        }
        match r {
            Some(x) => prev = Some(*x),
            None => *r = prev,
        }
    }
    let (stuck, sliding) = if ascii { ('#', '=') } else { ('█', '▒') };
    let mut out: Vec<char> = rank
        .iter()
        .map(|r| match r {
            Some(2) => stuck,
            Some(1) => sliding,
            _ => ' ',
        })
        .collect();
    let mut prio = vec![0u8; width];
    let of_contact = |e: &&EventRecord| e.contact == contact && e.kind.of_contact();
    for e in run.events.iter().filter(of_contact) {
        if let Some(c) = column_of(e.t, t0, t1, width, per_cell) {
            let (p, ch) = match e.kind {
                EventKind::Impact => (5, '*'),
                EventKind::Accumulation => (4, '!'),
                EventKind::Stick => (3, 'S'),
                EventKind::Slip => (2, '~'),
                EventKind::Release => (1, '^'),
                EventKind::KeyFailure => continue,
            };
            if p > prio[c] {
                prio[c] = p;
                out[c] = ch;
            }
        }
    }
    out
}

/// The mark of a key failure: `╳`, ASCII `X`.
pub fn key_failure_mark(ascii: bool) -> char {
    if ascii { 'X' } else { '╳' }
}

/// The shear-key row: a mark ([`key_failure_mark`]) at each key failure, blank elsewhere.
pub fn key_strip(
    run: &RunData,
    t0: f64,
    t1: f64,
    width: usize,
    per_cell: usize,
    ascii: bool,
) -> Vec<char> {
    let mut out = vec![' '; width];
    let failures = run
        .events
        .iter()
        .filter(|e| e.kind == EventKind::KeyFailure);
    for e in failures {
        if let Some(c) = column_of(e.t, t0, t1, width, per_cell) {
            out[c] = key_failure_mark(ascii);
        }
    }
    out
}

/// Label of the shear-key row.
const KEYS_LABEL: &str = "keys";

/// Draws the event strip of `run` over the window `t0..t1` with the cursor at `tc`.
pub(super) fn draw_timeline(
    frame: &mut Frame,
    area: Rect,
    run: &RunData,
    (t0, t1, tc): (f64, f64, f64),
    cache: &mut Cache,
    th: &Theme,
) {
    if area.height < 2 {
        return;
    }
    let w = area.width.saturating_sub(LABEL_W + 1) as usize;
    let per_cell = th.per_cell();
    let nc = run.contact_names.len();
    let keys = run.count(EventKind::KeyFailure) > 0;
    let room = (area.height as usize).saturating_sub(2);
    let rows = room.saturating_sub(usize::from(keys)).min(nc);
    let mut lines = vec![legend(frame, area, tc, keys, th)];
    let key = Key {
        extra: u64::from(th.ascii) + 2 * per_cell as u64,
        ..time_key(run, t0, t1, w as u16)
    };
    let strips = cache.strips(run.id, key, || {
        let mut v: Vec<Vec<char>> = (0..nc)
            .map(|i| event_strip(run, i, t0, t1, w, per_cell, th.ascii))
            .collect();
        if keys {
            v.push(key_strip(run, t0, t1, w, per_cell, th.ascii));
        }
        v
    });
    let cur_col = column_of(tc, t0, t1, w, per_cell);
    for (i, strip) in strips.iter().enumerate().take(rows) {
        let name = run.contact_names[i].as_str();
        lines.push(strip_line(name, th.series(i), strip, cur_col, th));
    }
    if let Some(strip) = strips.get(nc).filter(|_| keys && room > 0) {
        lines.push(strip_line(KEYS_LABEL, th.cursor(), strip, cur_col, th));
    }
    lines.push(time_axis(t0, t1, w, per_cell, th));
    frame.render_widget(Paragraph::new(lines), area);
}

/// The legend line (with the key-failure mark if `keys`); draws the cursor time at its right.
fn legend(frame: &mut Frame, area: Rect, tc: f64, keys: bool, th: &Theme) -> Line<'static> {
    let stuck = if th.ascii { "#" } else { "█" };
    let slide = if th.ascii { "=" } else { "▒" };
    let tnow = format!(" t = {} s", fmt_num(tc, 9));
    let mark = key_failure_mark(th.ascii);
    let (long_keys, short_keys) = if keys {
        (format!("  {mark} key failure"), format!(" {mark}key"))
    } else {
        (String::new(), String::new())
    };
    // the longest legend that leaves the cursor time whole (the time before the legend)
    let room = (area.width as usize).saturating_sub("events ".len() + tnow.len());
    let legend = [
        format!("* impact  S stick  ~ slip  ^ release  {stuck} stuck  {slide} sliding{long_keys}"),
        format!("*impact S stick ~slip ^release {stuck}stuck {slide}slide{short_keys}"),
        format!("*impact S stick ~slip ^release{short_keys}"),
        String::new(),
    ]
    .into_iter()
    .find(|l| l.chars().count() <= room)
    .unwrap_or_default();
    let head = Line::from(vec![
        Span::styled("events ", th.bold()),
        Span::styled(legend, th.dim()),
    ]);
    let tw = tnow.len() as u16;
    frame.render_widget(
        Paragraph::new(Line::styled(tnow, th.cursor())).alignment(Alignment::Right),
        Rect::new(
            area.right().saturating_sub(tw),
            area.y,
            tw.min(area.width),
            1,
        ),
    );
    head
}

/// One row: its name (in `style`), the strip, the cursor column in reverse video.
fn strip_line(
    name: &str,
    style: Style,
    strip: &[char],
    cur_col: Option<usize>,
    th: &Theme,
) -> Line<'static> {
    let name: String = name.chars().take(LABEL_W as usize - 1).collect();
    let mut spans = vec![Span::styled(
        format!("{name:>lw$} ", lw = LABEL_W as usize - 1),
        style,
    )];
    spans.push(Span::styled("│", th.dim()));
    let s: String = strip.iter().collect();
    match cur_col {
        Some(c) => {
            let a: String = strip[..c].iter().collect();
            let b: String = strip[c..=c].iter().collect();
            let d: String = strip[c + 1..].iter().collect();
            spans.push(Span::raw(a));
            spans.push(Span::styled(b, th.selected()));
            spans.push(Span::raw(d));
        }
        None => spans.push(Span::raw(s)),
    }
    Line::from(spans)
}

/// The time axis under the strips: start, middle, end.
fn time_axis(t0: f64, t1: f64, w: usize, per_cell: usize, th: &Theme) -> Line<'static> {
    let mut axis: Vec<char> = vec![' '; w];
    let ticks = [t0, 0.5 * (t0 + t1), t1];
    for (k, &t) in ticks.iter().enumerate() {
        let mut label = fmt_num(t, 7);
        if k == 2 {
            label.push_str(" s");
        }
        let n = label.chars().count();
        let Some(c) = column_of(t, t0, t1, w, per_cell) else {
            continue;
        };
        let start = match k {
            0 => c,
            1 => c.saturating_sub(n / 2),
            _ => (c + 1).saturating_sub(n),
        };
        for (j, ch) in label.chars().enumerate() {
            if start + j < w {
                axis[start + j] = ch;
            }
        }
    }
    let axis: String = axis.into_iter().collect();
    Line::from(vec![
        Span::raw(" ".repeat(LABEL_W as usize)),
        Span::styled(format!("└{axis}"), th.dim()),
    ])
}
