//! The help overlay's lines and layout: every key of the keymap in groups (the view's own
//! keys right after those that work everywhere), in two columns that scroll together when the
//! help is taller than the screen. Shared by the drawing and by the scroll keys, so that both
//! agree on how far the help scrolls.

use super::keymap::{self, Ctx};

/// One line of the help.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HelpLine {
    /// A group's title (its context).
    Title(&'static str),
    /// A key and what it does.
    Key(&'static str, &'static str),
}

/// The groups of the help shown over `view`: everywhere, the view's own keys, then the rest.
pub fn groups(view: Ctx) -> Vec<Vec<HelpLine>> {
    let mut help = keymap::help();
    if let Some(i) = help.iter().position(|(t, _)| *t == view.title()) {
        let group = help.remove(i);
        help.insert(1.min(help.len()), group);
    }
    help.into_iter()
        .map(|(title, rows)| {
            let mut g = vec![HelpLine::Title(title)];
            g.extend(rows.into_iter().map(|(k, d)| HelpLine::Key(k, d)));
            g
        })
        .collect()
}

/// The rows inside the help overlay on a screen `height` rows tall (its borders take two).
pub fn rows(height: u16) -> usize {
    height.saturating_sub(2) as usize
}

/// The two columns of the help for `rows` rows: when every line fits, the lines split in the
/// middle; else whole groups in order, the first column taking groups as long as that evens
/// the two out (the columns then scroll together).
pub fn columns(view: Ctx, rows: usize) -> [Vec<HelpLine>; 2] {
    let groups = groups(view);
    let all: usize = groups.iter().map(Vec::len).sum();
    if all <= 2 * rows {
        let mut left: Vec<HelpLine> = groups.into_iter().flatten().collect();
        let right = left.split_off(all.div_ceil(2));
        return [left, right];
    }
    let [mut left, mut right] = [Vec::new(), Vec::new()];
    for g in groups {
        let gap = |l: usize| l.abs_diff(all - l);
        if right.is_empty() && (left.is_empty() || gap(left.len() + g.len()) < gap(left.len())) {
            left.extend(g);
        } else {
            right.extend(g);
        }
    }
    [left, right]
}

/// How far the help over `view` scrolls on a screen `height` rows tall (0: it fits).
pub fn max_scroll(view: Ctx, height: u16) -> usize {
    let rows = rows(height);
    let cols = columns(view, rows);
    cols.iter()
        .map(Vec::len)
        .max()
        .unwrap_or(0)
        .saturating_sub(rows)
}
