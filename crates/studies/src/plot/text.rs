//! Charts and grids as plain ASCII text for any terminal: a value lands in grid column
//! round(frac_x·(cols − 1)) and grid row round((1 − frac_y)·(rows − 1)) (row 0 at the top;
//! [`layout`] says where the grid sits in the text). Drawn in order: bands, bars, reference
//! lines, the lines of every series, then the marks of every series.

use super::chart::{Chart, Grid, Marker, Series, Stroke};
use super::ticks::{Span, span, y_span};

/// Character of a band's fill.
pub(crate) const BAND: char = '.';
/// Character of a vertical reference line.
pub(crate) const VERTICAL: char = ':';
/// Character of a horizontal reference line.
pub(crate) const HORIZONTAL: char = '-';

/// Where the grid of a text chart sits: grid cell (r, c) is character `gutter + 1 + c` of
/// line `top + r`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Width of the y tick labels (the `|` of the y axis follows them).
    pub gutter: usize,
    pub cols: usize,
    pub rows: usize,
    /// Line of grid row 0 (after the title and the y axis title).
    pub top: usize,
}

/// `s` in printable ASCII: Greek letters and common symbols spelled out (θ → theta,
/// μ → mu, ≥ → >=, – → -), other characters as `?`, control characters as spaces.
pub fn ascii(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        let rep = match c {
            ' '..='~' => {
                out.push(c);
                continue;
            }
            'θ' => "theta",
            'Θ' => "Theta",
            'μ' | 'µ' => "mu",
            'β' => "beta",
            'σ' => "sigma",
            'λ' => "lambda",
            'ε' => "eps",
            'Φ' => "Phi",
            'φ' => "phi",
            'Δ' => "Delta",
            '≥' => ">=",
            '≤' => "<=",
            '–' | '—' | '−' => "-",
            '×' => "x",
            '·' => "*",
            '²' => "^2",
            '³' => "^3",
            '…' => "...",
            '°' => "deg",
            '→' => "->",
            c if c.is_control() => " ",
            _ => "?",
        };
        out.push_str(rep);
    }
    out
}

/// A glyph that prints as one ASCII graphic character.
fn glyph(c: char) -> char {
    if c.is_ascii_graphic() { c } else { '*' }
}

fn legend_lines(chart: &Chart) -> Vec<String> {
    let mut v = Vec::new();
    for s in chart.series.iter().filter(|s| !s.label.is_empty()) {
        v.push(format!("  {} {}", glyph(s.glyph), ascii(&s.label)));
    }
    for b in chart.bands.iter().filter(|b| !b.label.is_empty()) {
        v.push(format!("  {BAND} {}", ascii(&b.label)));
    }
    for b in chart.bars.iter().filter(|b| !b.label.is_empty()) {
        v.push(format!("  {} {}", glyph(b.glyph), ascii(&b.label)));
    }
    for l in chart.lines.iter().filter(|l| !l.label.is_empty()) {
        let g = if l.vertical { VERTICAL } else { HORIZONTAL };
        v.push(format!("  {g} {}", ascii(&l.label)));
    }
    v
}

/// The y ticks with their labels (a row's label at each row).
fn y_ticks(chart: &Chart, sy: &Span) -> Vec<(f64, String)> {
    let t = super::ticks::y_ticks(chart, sy);
    t.into_iter().map(|(v, l)| (v, ascii(&l))).collect()
}

/// The layout of `chart` in `width` × `height` characters: the title, the y axis title, the
/// grid, the x axis, its tick labels, the x axis title, one legend line per labelled series,
/// band, set of bars and reference line; the grid takes what is left (at least 10 × 3).
pub fn layout(chart: &Chart, width: usize, height: usize) -> Layout {
    let sy = y_span(chart);
    let gutter = (y_ticks(chart, &sy).iter())
        .map(|(_, l)| l.len())
        .max()
        .unwrap_or(1);
    let extra = 5 + legend_lines(chart).len();
    Layout {
        gutter,
        cols: width.saturating_sub(gutter + 1).max(10),
        rows: height.saturating_sub(extra).max(3),
        top: 2,
    }
}

/// The grid cells of a chart, with the mapping of values to cells.
struct Canvas {
    cells: Vec<Vec<char>>,
    sx: Span,
    sy: Span,
}

impl Canvas {
    fn cols(&self) -> usize {
        self.cells[0].len()
    }
    fn rows(&self) -> usize {
        self.cells.len()
    }
    /// Fractional (column, row) of a point.
    fn at(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        let (fx, fy) = (self.sx.frac(x)?, self.sy.frac(y)?);
        Some((
            fx * (self.cols() - 1) as f64,
            (1.0 - fy) * (self.rows() - 1) as f64,
        ))
    }
    fn set(&mut self, c: f64, r: f64, g: char) {
        let (c, r) = (c.round(), r.round());
        if c >= 0.0 && r >= 0.0 && (c as usize) < self.cols() && (r as usize) < self.rows() {
            self.cells[r as usize][c as usize] = g;
        }
    }
    /// The cells of the segment (c0, r0)–(c1, r1): one per column it crosses, rows between
    /// consecutive columns filled so a steep segment stays connected.
    fn segment(&mut self, (c0, r0): (f64, f64), (c1, r1): (f64, f64), g: char) {
        if (c1 - c0).abs() < 1e-9 {
            let (a, b) = (r0.min(r1).round() as i64, r0.max(r1).round() as i64);
            for r in a..=b {
                self.set(c0, r as f64, g);
            }
            return;
        }
        let ((ca, ra), (cb, rb)) = if c0 <= c1 {
            ((c0, r0), (c1, r1))
        } else {
            ((c1, r1), (c0, r0))
        };
        let row = |k: f64| ra + (k - ca) * (rb - ra) / (cb - ca);
        let (k0, k1) = ((ca - 1e-9).ceil() as i64, (cb + 1e-9).floor() as i64);
        if k0 > k1 {
            self.set(ca, ra, g);
            self.set(cb, rb, g);
            return;
        }
        let mut prev: Option<i64> = None;
        for k in k0..=k1 {
            let r = row(k as f64).round() as i64;
            if let Some(p) = prev {
                for between in (p.min(r) + 1)..p.max(r) {
                    self.set(k as f64, between as f64, g);
                }
            }
            self.set(k as f64, r as f64, g);
            prev = Some(r);
        }
    }
    /// The lines of a series (its marks come after every series' lines).
    fn line(&mut self, s: &Series) {
        if s.stroke == Stroke::None {
            return;
        }
        let g = glyph(s.glyph);
        let pts: Vec<Option<(f64, f64)>> = s.points.iter().map(|&(x, y)| self.at(x, y)).collect();
        for w in pts.windows(2) {
            if let (Some(a), Some(b)) = (w[0], w[1]) {
                self.segment(a, b, g);
            }
        }
    }
    /// The glyph at each point of a series with markers.
    fn marks(&mut self, s: &Series) {
        if s.marker == Marker::None {
            return;
        }
        let g = glyph(s.glyph);
        for &(x, y) in &s.points {
            if let Some((c, r)) = self.at(x, y) {
                self.set(c, r, g);
            }
        }
    }
}

/// `chart` as ASCII text of `width` × `height` characters ([`layout`]; lines are not padded).
pub fn render(chart: &Chart, width: usize, height: usize) -> String {
    let l = layout(chart, width, height);
    let sx = span(&chart.x, &chart.xs());
    let sy = y_span(chart);
    let mut cv = Canvas {
        cells: vec![vec![' '; l.cols]; l.rows],
        sx,
        sy,
    };
    for b in &chart.bands {
        for w in b.points.windows(2) {
            let (Some(a0), Some(a1)) = (cv.at(w[0].0, w[0].1), cv.at(w[1].0, w[1].1)) else {
                continue;
            };
            let (Some(b0), Some(b1)) = (cv.at(w[0].0, w[0].2), cv.at(w[1].0, w[1].2)) else {
                continue;
            };
            let (k0, k1) = ((a0.0 - 1e-9).ceil() as i64, (a1.0 + 1e-9).floor() as i64);
            for k in k0..=k1 {
                let t = if a1.0 > a0.0 {
                    (k as f64 - a0.0) / (a1.0 - a0.0)
                } else {
                    0.0
                };
                let lo = a0.1 + t * (a1.1 - a0.1);
                let hi = b0.1 + t * (b1.1 - b0.1);
                cv.segment((k as f64, lo), (k as f64, hi), BAND);
            }
        }
    }
    for b in &chart.bars {
        for &(row, from, to) in &b.bars {
            let y = chart.row_y(row);
            if let (Some(p0), Some(p1)) = (cv.at(from, y), cv.at(to, y)) {
                cv.segment(p0, p1, glyph(b.glyph));
            }
        }
    }
    for line in &chart.lines {
        let (c, r) = if line.vertical {
            (sx.frac(line.at).map(|f| f * (l.cols - 1) as f64), None)
        } else {
            (
                None,
                sy.frac(line.at).map(|f| (1.0 - f) * (l.rows - 1) as f64),
            )
        };
        if let Some(c) = c {
            cv.segment((c, 0.0), (c, (l.rows - 1) as f64), VERTICAL);
        }
        if let Some(r) = r {
            cv.segment((0.0, r), ((l.cols - 1) as f64, r), HORIZONTAL);
        }
    }
    for s in &chart.series {
        cv.line(s);
    }
    for s in &chart.series {
        cv.marks(s);
    }
    let mut out = String::new();
    out += &cut(&ascii(&chart.title), width);
    out += "\n";
    out += &cut(&ascii(&chart.y.label()), width);
    out += "\n";
    let mut labels = vec![String::new(); l.rows];
    for (v, text) in y_ticks(chart, &sy) {
        if let Some(f) = sy.frac(v) {
            let r = ((1.0 - f) * (l.rows - 1) as f64).round();
            if r >= 0.0 && (r as usize) < l.rows {
                labels[r as usize] = text;
            }
        }
    }
    for (r, row) in cv.cells.iter().enumerate() {
        let line: String = row.iter().collect();
        out += &format!("{:>w$}|{}\n", labels[r], line.trim_end(), w = l.gutter);
    }
    out += &x_axis(&sx, &l);
    let title = ascii(&chart.x.label());
    let pad = (l.gutter + 1 + l.cols / 2).saturating_sub(title.len() / 2);
    out += &cut(&format!("{}{title}", " ".repeat(pad)), width);
    out += "\n";
    for line in legend_lines(chart) {
        out += &cut(&line, width);
        out += "\n";
    }
    out
}

/// The x axis line (`+` at ticks) and the tick labels under it (a label that would overlap
/// the one before is left out).
fn x_axis(sx: &Span, l: &Layout) -> String {
    let mut axis = vec!['-'; l.cols];
    let mut under = vec![' '; l.gutter + 1 + l.cols];
    let ticks = sx.ticks();
    let mut free_from = 0usize;
    for &t in &ticks {
        let Some(f) = sx.frac(t) else { continue };
        let c = (f * (l.cols - 1) as f64).round() as usize;
        if c >= l.cols {
            continue;
        }
        axis[c] = '+';
        let text = ascii(&sx.label(t, &ticks));
        let start = (l.gutter + 1 + c)
            .saturating_sub(text.len() / 2)
            .min(under.len().saturating_sub(text.len()));
        if start >= free_from && start + text.len() <= under.len() {
            for (k, ch) in text.chars().enumerate() {
                under[start + k] = ch;
            }
            free_from = start + text.len() + 1;
        }
    }
    let under: String = under.iter().collect();
    format!(
        "{}+{}\n{}\n",
        " ".repeat(l.gutter),
        axis.iter().collect::<String>(),
        under.trim_end()
    )
}

/// The first `width` characters of an ASCII line.
fn cut(s: &str, width: usize) -> String {
    s.chars()
        .take(width)
        .collect::<String>()
        .trim_end()
        .to_string()
}

/// `grid` as ASCII text at most `width` wide: a line of column numbers, then each row's label
/// and one glyph per cell (3 characters a cell), then the legend of categories.
pub fn render_grid(grid: &Grid, width: usize) -> String {
    let lw = (grid.rows.iter())
        .map(|r| ascii(&r.label).len())
        .max()
        .unwrap_or(0);
    let ncol = grid.rows.iter().map(|r| r.cells.len()).max().unwrap_or(0);
    let mut out = cut(&ascii(&grid.title), width) + "\n";
    out += &cut(&format!("{:lw$}  {}", "", ascii(&grid.columns)), width);
    out += "\n";
    let nums: String = (1..=ncol).map(|k| format!("{k:>3}")).collect();
    out += &cut(&format!("{:lw$} {nums}", ""), width);
    out += "\n";
    for r in &grid.rows {
        let cells: String = (r.cells.iter())
            .map(|c| {
                let g = grid
                    .categories
                    .get(c.category)
                    .map_or('?', |k| glyph(k.glyph));
                format!("{g:>3}")
            })
            .collect();
        out += &cut(&format!("{:<lw$} {cells}", ascii(&r.label)), width);
        out += "\n";
    }
    let legend: Vec<String> = (grid.categories.iter())
        .map(|k| format!("{} {}", glyph(k.glyph), ascii(&k.name)))
        .collect();
    out += &cut(&format!("  {}", legend.join("   ")), width);
    out += "\n";
    out
}
