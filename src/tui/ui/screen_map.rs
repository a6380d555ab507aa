//! The screening's panel: the two L/B × skew maps (after a flush end impact; a corner struck
//! alone) side by side with this model marked `@`, as `deckspin screen` prints them, then
//! the model's flush ends and its corners struck alone as far as the height allows. The
//! maps' rows and columns are thinned evenly when the panel is smaller than them.

use super::common::{Theme, fit, fit_lines};
use crate::design::screen::{CornerAlone, Flush, MapCell, ScreenStudy};
use crate::tui::chart::{fmt_num, fmt_sig};
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::Paragraph;

/// Width of the skew labels and their bar: ` 60|`.
const LABEL_W: usize = 4;

/// `k` indices of `0..n`, evenly spread, first and last included (all when `k ≥ n`).
fn spread(n: usize, k: usize) -> Vec<usize> {
    if k >= n || n < 2 {
        return (0..n).collect();
    }
    let k = k.max(2);
    (0..k)
        .map(|i| (i * (n - 1) + (k - 1) / 2) / (k - 1))
        .collect()
}

fn flush_char(c: &MapCell) -> char {
    c.flush.glyph()
}

fn corner_char(c: &MapCell) -> char {
    c.corners().glyph()
}

/// Which cells of the map are shown, and where the model's mark goes among them.
struct Shown {
    cols: Vec<usize>,
    rows: Vec<usize>,
    mark: Option<(usize, usize)>,
}

/// Nearest shown index to `i`.
fn nearest(shown: &[usize], i: usize) -> usize {
    (0..shown.len())
        .min_by_key(|&k| shown[k].abs_diff(i))
        .unwrap_or(0)
}

/// One map's lines: title, legend (every item, on as many lines as it takes), rows (top: the
/// largest skew), x labels.
fn map_lines(
    s: &ScreenStudy,
    shown: &Shown,
    title: &str,
    legend: &[&str],
    glyph: fn(&MapCell) -> char,
    th: &Theme,
) -> Vec<Line<'static>> {
    let width = LABEL_W + shown.cols.len();
    let mut out = vec![Line::styled(th.text(title), th.bold())];
    let items: Vec<String> = legend.iter().map(|l| th.text(l)).collect();
    out.extend((fit_lines(&items, "  ", width, items.len()).into_iter()).map(Line::from));
    let bar = if th.ascii { '|' } else { '│' };
    for (r, &j) in shown.rows.iter().enumerate().rev() {
        let mut row = format!("{:>3}{bar}", fmt_num(s.skew_deg[j], 3));
        for (c, &i) in shown.cols.iter().enumerate() {
            let ch = match s.cell(i, j) {
                _ if shown.mark == Some((c, r)) => '@',
                Some(cell) => glyph(cell),
                None => ' ',
            };
            row.push(ch);
        }
        out.push(Line::from(row));
    }
    let (a, b) = (
        fmt_num(s.l_over_b[0], 5),
        fmt_num(s.l_over_b[s.l_over_b.len() - 1], 5),
    );
    let mid = "L/B, log";
    let n = shown.cols.len();
    let x = if a.len() + mid.len() + b.len() + 2 <= n {
        let gap = n - a.len() - mid.len() - b.len();
        format!(
            "{a}{}{mid}{}{b}",
            " ".repeat(gap / 2),
            " ".repeat(gap - gap / 2)
        )
    } else if a.len() + b.len() < n {
        format!("{a}{}{b}", " ".repeat(n - a.len() - b.len()))
    } else {
        String::new()
    };
    out.push(Line::styled(format!("deg {x}"), th.dim()));
    out
}

const FLUSH_LEGEND: [&str; 4] = [
    ". straight",
    "s turns, stick",
    "S turns, slide",
    "@ this model",
];
const CORNER_LEGEND: [&str; 4] = ["B both stick", "a acute only", "o obtuse only", "- neither"];

/// Draws the screening in `area`.
pub(super) fn draw_screen(frame: &mut Frame, area: Rect, s: &ScreenStudy, th: &Theme) {
    let (nl, ns) = (s.l_over_b.len(), s.skew_deg.len());
    let (w, h) = (area.width as usize, area.height as usize);
    if nl == 0 || ns == 0 || h < 8 || w < LABEL_W + 16 {
        return;
    }
    // two maps side by side, thinned to the width; one when they would be too thin
    let both = (w.saturating_sub(2) / 2).saturating_sub(LABEL_W) >= 16;
    let per = if both { (w - 2) / 2 } else { w };
    let cols = spread(nl, per - LABEL_W);
    let rows = spread(ns, (h - 5).min(ns).max(2));
    let mark = s
        .mark()
        .map(|(i, j)| (nearest(&cols, i), nearest(&rows, j)));
    let shown = Shown { cols, rows, mark };
    let flush = "after a flush end impact";
    let mut maps = vec![map_lines(s, &shown, flush, &FLUSH_LEGEND, flush_char, th)];
    if both {
        let corner = "a corner struck alone";
        maps.push(map_lines(
            s,
            &shown,
            corner,
            &CORNER_LEGEND,
            corner_char,
            th,
        ));
    }
    // a legend that takes another line: the maps keep their rows level
    let tallest = maps.iter().map(Vec::len).max().unwrap_or(0);
    let mw = (LABEL_W + shown.cols.len()) as u16;
    let maps_h = (tallest as u16).min(area.height);
    for (k, mut lines) in maps.into_iter().enumerate() {
        let legend_end = lines.len() - shown.rows.len() - 1;
        for _ in lines.len()..tallest {
            lines.insert(legend_end, Line::from(""));
        }
        let x = area.x + k as u16 * (mw + 2);
        frame.render_widget(Paragraph::new(lines), Rect::new(x, area.y, mw, maps_h));
    }
    let rest = Rect::new(area.x, area.y + maps_h, area.width, area.height - maps_h);
    let lines = model_lines(s, w, rest.height as usize, th);
    frame.render_widget(Paragraph::new(lines), rest);
}

fn outcome(f: Flush) -> &'static str {
    match f {
        Flush::Straight => "stays straight",
        Flush::RotatesSticking => "turns (corners stick)",
        Flush::RotatesSliding => "turns (corners slide)",
    }
}

/// One corner against one face, as three columns: sticks, the μ a stick needs, the spin.
fn corner_cols(c: Option<&CornerAlone>) -> String {
    match c.map(|c| (c.sticks, c)) {
        Some((Some(st), c)) => format!(
            "{:>7} {:>9} {:>10}",
            if st { "yes" } else { "no" },
            fmt_sig(c.stick_mu, 3),
            fmt_sig(c.spin, 3)
        ),
        Some((None, _)) => format!("{:>28}", "no closed form"),
        None => format!("{:>28}", ""),
    }
}

/// The corners struck alone: per contact, against a rigid face and against the face's own
/// body (the second group left out whole when narrow).
fn corner_table(s: &ScreenStudy, w: usize, th: &Theme) -> Vec<Line<'static>> {
    let names: Vec<&str> = (s.corners.iter())
        .filter(|c| c.rigid_face)
        .map(|c| c.contact.as_str())
        .collect();
    let nw = names
        .iter()
        .map(|n| n.chars().count())
        .max()
        .unwrap_or(0)
        .max(7)
        + 2;
    if names.is_empty() || nw + 28 > w {
        return Vec::new();
    }
    let both = nw + 2 * 28 + 3 <= w;
    let mut head1 = format!("{:nw$}{:>28}", "", "against a rigid face");
    let cols = format!("{:>7} {:>9} {:>10}", "sticks", th.text("μ needed"), "spin");
    let mut head2 = format!("{:nw$}{cols}", "  contact");
    if both {
        head1 += &format!("   {:>28}", "against the face's own body");
        head2 += &format!("   {cols}");
    }
    let title = "its corners struck alone at 1 m/s (spin: rad/s per m/s of approach):";
    let mut out = vec![
        Line::styled(fit(&[th.text(title)], "", w), th.bold()),
        Line::styled(head1, th.dim()),
        Line::styled(head2, th.dim()),
    ];
    for n in names {
        let find =
            |rigid: bool| (s.corners.iter()).find(|c| c.rigid_face == rigid && c.contact == n);
        let mut row = format!("{:nw$}{}", format!("  {n}"), corner_cols(find(true)));
        if both {
            row += &format!("   {}", corner_cols(find(false)));
        }
        out.push(Line::from(row));
    }
    out
}

/// The axes and μ, ε line, the model's ends and its corners, each block whole or not at all
/// (a last line says what a taller terminal would show); each line with the items that fit.
fn model_lines(s: &ScreenStudy, w: usize, rows: usize, th: &Theme) -> Vec<Line<'static>> {
    let about = [
        "rows: skew, deg".to_string(),
        "columns: L/B, log scale".into(),
        format!(
            "μ {} and ε {} of the model",
            fmt_sig(s.mu, 3),
            fmt_sig(s.restitution, 3)
        ),
    ];
    let about: Vec<String> = about.iter().map(|t| th.text(t)).collect();
    let mut ends = Vec::new();
    if !s.ends.is_empty() {
        ends.push(Line::styled(th.text("this model's flush ends:"), th.bold()));
    }
    for e in &s.ends {
        let items = [
            format!("  {} + {}", e.contacts[0], e.contacts[1]),
            th.text(&format!("→ {}", outcome(e.flush))),
            format!("L/B {}", fmt_sig(e.l_over_b, 4)),
            format!("skew {} deg", fmt_sig(e.skew_deg, 3)),
        ];
        ends.push(Line::from(fit(&items, "  ", w)));
    }
    let blocks = [
        vec![Line::styled(fit(&about, th.sep(), w), th.dim())],
        ends,
        corner_table(s, w, th),
    ];
    let mut lines: Vec<Line> = Vec::new();
    let mut left = 0;
    for b in blocks {
        if left > 0 || lines.len() + b.len() > rows {
            left += b.len();
        } else {
            lines.extend(b);
        }
    }
    if left > 0 && lines.len() < rows {
        let t = format!("({left} more lines of the model's ends and corners: a taller terminal)");
        lines.push(Line::styled(fit(&[th.text(&t)], "", w), th.dim()));
    }
    lines
}
