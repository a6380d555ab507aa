//! The event strip: the legend, the readout at the cursor (contact states, last impact), one
//! row per contact on the charts' time axis (events over the contact state, a column of
//! several impacts counted), a row of shear-key failures when there are any, the cursor
//! column, the time axis.

use super::cache::{Cache, Key, time_key};
use super::common::{LABEL_W, Theme, fit};
use crate::output::{ContactState, EventKind, EventRecord};
use crate::tui::chart::{self, column_of, fmt_num};
use crate::tui::runs::data::RunData;
use crate::tui::runs::nav;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::Style;
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

/// One column of an event strip: the mark drawn, the event kind it shows (None: the contact
/// state only) and the number of impacts it stands for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cell {
    pub mark: char,
    pub kind: Option<EventKind>,
    pub impacts: usize,
}

/// Which event a column shows when it holds several, whatever the markers: an impact, then an
/// accumulation, a release, a slip, a stick (0: not drawn in a contact's row).
pub fn priority(kind: EventKind) -> u8 {
    match kind {
        EventKind::Impact => 5,
        EventKind::Accumulation => 4,
        EventKind::Release => 3,
        EventKind::Slip => 2,
        EventKind::Stick => 1,
        EventKind::KeyFailure => 0,
    }
}

/// The strip's mark of one event of a kind.
pub(super) fn kind_mark(kind: EventKind, ascii: bool) -> char {
    match kind {
        EventKind::Impact => '*',
        EventKind::Accumulation => '!',
        EventKind::Release => '^',
        EventKind::Slip => '~',
        EventKind::Stick => 'S',
        EventKind::KeyFailure => key_failure_mark(ascii),
    }
}

/// The mark of `n` events: its symbol for one, the count 2–9, `+` for ten or more.
fn count_mark(symbol: char, n: usize) -> char {
    match n {
        0 | 1 => symbol,
        2..=9 => char::from(b'0' + n as u8),
        _ => '+',
    }
}

/// The contact-state rank of each column (2 stuck, 1 sliding, 0 open; None before the first
/// sample and after the last): the highest state of its samples, else the state before.
fn state_ranks(
    run: &RunData,
    contact: usize,
    (t0, t1): (f64, f64),
    width: usize,
    per_cell: usize,
) -> Vec<Option<u8>> {
    let rank_of = |s: &ContactState| match s {
        ContactState::Stick => 2,
        ContactState::Slide(_) => 1,
        ContactState::Open => 0,
    };
    let mut rank: Vec<Option<u8>> = vec![None; width];
    let range = chart::window(&run.t, t0, t1);
    let states = &run.state[contact];
    for i in range.clone() {
        // a run shown from the run list keeps no contact states
        if let Some(c) = column_of(run.t[i], t0, t1, width, per_cell)
            && let Some(s) = states.get(i)
        {
            let r = rank_of(s);
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
        .map(rank_of);
    for (c, r) in rank.iter_mut().enumerate() {
        if last_col.is_none_or(|l| c > l) {
            break;
        }
        match r {
            Some(x) => prev = Some(*x),
            None => *r = prev,
        }
    }
    rank
}

/// Per-contact event strip: events (impact `*`, or the number of impacts `2`–`9`, `+` for ten
/// or more; accumulation `!`, release `^`, slip `~`, stick `S`) over the contact state (stuck
/// `█`/`#`, sliding `▒`/`=`, open ` `); a column holding several events shows the first of
/// [`priority`], the same with either marker. Key failures have their own row ([`key_strip`]).
pub fn strip_cells(
    run: &RunData,
    contact: usize,
    t0: f64,
    t1: f64,
    width: usize,
    per_cell: usize,
    ascii: bool,
) -> Vec<Cell> {
    let (stuck, sliding) = if ascii { ('#', '=') } else { ('█', '▒') };
    let mut out: Vec<Cell> = state_ranks(run, contact, (t0, t1), width, per_cell)
        .iter()
        .map(|r| Cell {
            mark: match r {
                Some(2) => stuck,
                Some(1) => sliding,
                _ => ' ',
            },
            kind: None,
            impacts: 0,
        })
        .collect();
    let of_contact = |e: &&EventRecord| e.contact == contact && e.kind.of_contact();
    for e in run.events.iter().filter(of_contact) {
        let Some(cell) = column_of(e.t, t0, t1, width, per_cell).map(|c| &mut out[c]) else {
            continue;
        };
        if e.kind == EventKind::Impact {
            cell.impacts += 1;
        }
        if cell.kind.is_none_or(|k| priority(e.kind) > priority(k)) {
            cell.kind = Some(e.kind);
        }
    }
    for cell in &mut out {
        cell.mark = match cell.kind {
            Some(EventKind::Impact) => count_mark('*', cell.impacts),
            Some(k) if k.of_contact() => kind_mark(k, ascii),
            _ => cell.mark,
        };
    }
    out
}

/// The marks of [`strip_cells`].
pub fn event_strip(
    run: &RunData,
    contact: usize,
    t0: f64,
    t1: f64,
    width: usize,
    per_cell: usize,
    ascii: bool,
) -> Vec<char> {
    strip_cells(run, contact, t0, t1, width, per_cell, ascii)
        .into_iter()
        .map(|c| c.mark)
        .collect()
}

/// The mark of a key failure: `╳`, ASCII `X`.
pub fn key_failure_mark(ascii: bool) -> char {
    if ascii { 'X' } else { '╳' }
}

/// The shear-key row: a mark ([`key_failure_mark`]) at each key failure (the count 2–9, `+`
/// for ten or more, in a column of several), blank elsewhere.
pub fn key_strip(
    run: &RunData,
    t0: f64,
    t1: f64,
    width: usize,
    per_cell: usize,
    ascii: bool,
) -> Vec<char> {
    let mut n = vec![0usize; width];
    let failures = run
        .events
        .iter()
        .filter(|e| e.kind == EventKind::KeyFailure);
    for e in failures {
        if let Some(c) = column_of(e.t, t0, t1, width, per_cell) {
            n[c] += 1;
        }
    }
    let mark = key_failure_mark(ascii);
    n.iter()
        .map(|&k| if k == 0 { ' ' } else { count_mark(mark, k) })
        .collect()
}

/// Label of the shear-key row.
const KEYS_LABEL: &str = "keys";

/// Draws the event strip of `run` over the window `t0..t1` with the cursor at `tc`: the
/// legend, the readout at `rt` (the cursor time, or the instant held while a running run is
/// followed; when `area` has a line for it), one row per contact, the key failures, the time
/// axis. `kn`: the model's force unit (none when empty).
pub(super) fn draw_timeline(
    frame: &mut Frame,
    area: Rect,
    run: &RunData,
    (t0, t1, tc, rt): (f64, f64, f64, f64),
    kn: &str,
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
    let with_readout = area.height >= 4;
    let room = (area.height as usize).saturating_sub(2 + usize::from(with_readout));
    let rows = room.saturating_sub(usize::from(keys)).min(nc);
    let mut lines = vec![legend(area.width as usize, keys, th)];
    if with_readout {
        lines.push(readout(run, rt, kn, area.width as usize, th));
    }
    let key = Key {
        extra: u64::from(th.ascii),
        ..time_key(run, t0, t1, w as u16)
    };
    let strips = cache.strips(run.token, key, || {
        let mut v: Vec<Vec<char>> = (0..nc)
            .map(|i| event_strip(run, i, t0, t1, w, per_cell, th.ascii))
            .collect();
        if keys {
            v.push(key_strip(run, t0, t1, w, per_cell, th.ascii));
        }
        v
    });
    let cur_col = column_of(tc, t0, t1, w, per_cell);
    let labels = row_names(&run.contact_names, LABEL_W as usize - 1);
    for (i, strip) in strips.iter().enumerate().take(rows) {
        lines.push(strip_line(&labels[i], th.series(i), strip, cur_col, th));
    }
    if let Some(strip) = strips.get(nc).filter(|_| keys && room > 0) {
        lines.push(strip_line(KEYS_LABEL, th.cursor(), strip, cur_col, th));
    }
    lines.push(time_axis(t0, t1, w, per_cell, th));
    frame.render_widget(Paragraph::new(lines), area);
}

/// The legend line: as many of its items as fit whole in `width` (the key-failure mark if
/// `keys`).
fn legend(width: usize, keys: bool, th: &Theme) -> Line<'static> {
    let stuck = if th.ascii { "#" } else { "█" };
    let slide = if th.ascii { "=" } else { "▒" };
    let mark = key_failure_mark(th.ascii);
    let long = [
        "* impact".to_string(),
        "2-9 impacts".into(),
        "S stick".into(),
        "~ slip".into(),
        "^ release".into(),
        format!("{stuck} stuck"),
        format!("{slide} sliding"),
        if keys {
            format!("{mark} key failure")
        } else {
            String::new()
        },
    ];
    let short = [
        "*impact".to_string(),
        "2-9 impacts".into(),
        "S stick".into(),
        "~slip".into(),
        "^release".into(),
        format!("{stuck}stuck"),
        format!("{slide}sliding"),
        if keys {
            format!("{mark}key")
        } else {
            String::new()
        },
    ];
    let room = width.saturating_sub("events ".len());
    let whole = |items: &[String], sep: &str| {
        let s = fit(items, sep, room);
        (s.chars().count() == fit(items, sep, usize::MAX).chars().count()).then_some(s)
    };
    let text = whole(&long, "  ")
        .or_else(|| whole(&short, " "))
        .unwrap_or_else(|| fit(&short, " ", room));
    Line::from(vec![
        Span::styled("events ", th.bold()),
        Span::styled(text, th.dim()),
    ])
}

/// The readout line at the cursor: its time, the state of each contact, the last impact
/// before it with its normal impulse; whole items only, every contact named when they fit.
fn readout(run: &RunData, tc: f64, kn: &str, width: usize, th: &Theme) -> Line<'static> {
    let time = format!("t = {} s ", nav::fmt_time(tc));
    let room = width.saturating_sub(time.chars().count());
    let last = nav::last_impact(run, tc).map(|e| {
        let imp = nav::impulse(e, kn, th.ascii).unwrap_or_default();
        let name = nav::subject(run, e);
        let mid = format!("last impact {name} {imp}");
        let long = format!("{mid} at {} s", chart::fmt_sig(e.t, 4));
        let short = format!("last impact {} {imp}", row_name(&name, 8));
        [long, mid, short]
    });
    let all = nav::contact_items(run, tc, true);
    let all_fit = fit(&all, th.sep(), room).chars().count() == all.join(th.sep()).chars().count();
    let items = if all_fit {
        all
    } else {
        nav::contact_items(run, tc, false)
    };
    let mut text = fit(&items, th.sep(), room);
    if let Some(variants) = last {
        let sep = if text.is_empty() { "" } else { th.sep() };
        let left = room.saturating_sub(text.chars().count() + sep.chars().count());
        if let Some(l) = variants.into_iter().find(|l| l.chars().count() <= left) {
            text.push_str(sep);
            text.push_str(&l);
        }
    }
    Line::from(vec![Span::styled(time, th.cursor()), Span::raw(text)])
}

/// A contact's name in `w` columns: whole, else each word but the last cut to its first letter
/// (`right_bottom` → `r_bottom`), else its first `w` characters.
pub(super) fn row_name(name: &str, w: usize) -> String {
    if name.chars().count() <= w {
        return name.to_string();
    }
    let parts: Vec<&str> = name.split('_').collect();
    if let Some((last, first)) = parts.split_last() {
        let mut short: String = first
            .iter()
            .filter_map(|p| p.chars().next())
            .flat_map(|c| [c, '_'])
            .collect();
        short.push_str(last);
        if short.chars().count() <= w {
            return short;
        }
    }
    name.chars().take(w).collect()
}

/// A word cut to its first letter and its digits (`joint12` → `j12`, `left` → `l`).
fn initial_and_digits(word: &str) -> String {
    let mut c = word.chars();
    let first = c.next().map(String::from).unwrap_or_default();
    first + &c.filter(char::is_ascii_digit).collect::<String>()
}

/// Labels of the rows `names` in `w` columns, each distinct from the others: a name as
/// [`row_name`] shortens it; where two come out the same (`joint1_bottom` and `joint2_bottom`
/// both `j_bottom`), each word but the last cut to its first letter and its digits
/// (`j1_bottom`), else the name's last `w` characters, else its first characters and its
/// number among the rows (`joint~3`).
pub fn row_names(names: &[String], w: usize) -> Vec<String> {
    if w == 0 {
        return vec![String::new(); names.len()];
    }
    let level = |k: usize, i: usize| -> String {
        let name = names[i].as_str();
        match k {
            0 => row_name(name, w),
            1 => {
                let parts: Vec<&str> = name.split('_').collect();
                let Some((last, first)) = parts.split_last() else {
                    return row_name(name, w);
                };
                let mut s: String = first.iter().map(|p| initial_and_digits(p) + "_").collect();
                s.push_str(last);
                if s.chars().count() <= w {
                    s
                } else {
                    row_name(name, w)
                }
            }
            2 => {
                let n = name.chars().count();
                name.chars().skip(n.saturating_sub(w)).collect()
            }
            _ => {
                let tail = format!("~{}", i + 1);
                let keep = w.saturating_sub(tail.chars().count());
                name.chars().take(keep).collect::<String>() + &tail
            }
        }
    };
    let mut labels: Vec<String> = (0..names.len()).map(|i| level(0, i)).collect();
    for k in 1..=3 {
        let dups: Vec<usize> = (0..labels.len())
            .filter(|&i| labels.iter().filter(|l| **l == labels[i]).count() > 1)
            .collect();
        if dups.is_empty() {
            break;
        }
        for i in dups {
            labels[i] = level(k, i);
        }
    }
    labels
}

/// One row: its label (in `style`, [`row_names`]), the strip, the cursor column in reverse video.
fn strip_line(
    name: &str,
    style: Style,
    strip: &[char],
    cur_col: Option<usize>,
    th: &Theme,
) -> Line<'static> {
    let lw = LABEL_W as usize - 1;
    let mut spans = vec![Span::styled(format!("{name:>lw$} "), style)];
    spans.push(Span::styled(if th.ascii { "|" } else { "│" }, th.dim()));
    let s: String = strip.iter().collect();
    match cur_col.filter(|&c| c < strip.len()) {
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
        Span::styled(
            format!("{}{axis}", if th.ascii { '+' } else { '└' }),
            th.dim(),
        ),
    ])
}
