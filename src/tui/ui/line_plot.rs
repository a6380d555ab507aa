//! The workbench's renderer of the library's charts ([`crate::plot::Chart`], the same data the
//! CLI draws as SVG and text): series over linear or log axes (time histories, the response
//! spectrum, work-precision, the model ladder's cost and error, the live time charts, the
//! column loop), with reference lines (the zero line, a period, the 1 % error) and, from the
//! [`Look`], stems (impulses), a study's cursor or the time cursor, the header, the labels and
//! the styles a panel gives; the studies' figures (Fig. 7, Fig. 8, a record suite) too. Each
//! series carries its own glyph, printed along it and in the legend (or, in the time charts
//! without colour, drawn as its line), so series differ without colour; the y labels are the
//! data's own extremes unless the panel gives its own.

use super::common::{CURSOR_MARK, Theme};
use crate::plot::{Chart, Marker, Scale};
use crate::tui::chart::fmt_sig;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;
use ratatui::widgets::canvas::{Canvas, Context, Line as CLine};

/// Width of the y labels unless the [`Look`] says.
const LABEL_W: u16 = 9;

/// The line above the plot.
#[derive(Clone, Debug, Default)]
pub(super) enum Head {
    /// The y axis's title and the legend.
    #[default]
    Legend,
    /// The panel's own (a time chart's: its title and the values at the cursor).
    Line(Line<'static>),
    /// Nothing (the column loop, named by its block).
    None,
}

/// What the workbench adds to a chart: the legend (off where a table beside the plot names
/// the series), the series drawn as selected, stems from 0 (impulses) with their mark, a
/// cursor, and what a panel draws its own way (header, label width and labels, the x axis,
/// the series' styles, lines drawn in their glyphs).
#[derive(Clone, Debug)]
pub(super) struct Look {
    pub legend: bool,
    pub selected: Option<usize>,
    pub stems: Vec<(f64, f64)>,
    pub stem_mark: char,
    /// The x of a cursor: a study's, a dim vertical line under the series.
    pub cursor: Option<f64>,
    /// The cursor is the time cursor, which the readouts follow: drawn over the series in the
    /// cursor's style (`|` where series are told apart by marks).
    pub time_cursor: bool,
    pub head: Head,
    /// The x axis's line and labels (off where the panel below gives the time axis: the time
    /// charts over the event strip).
    pub x_axis: bool,
    /// Width of the y labels.
    pub label_w: u16,
    /// The y labels as (value, text), each on the row its value is drawn on (the first one
    /// given keeps a row two fall on); empty: the extremes with 3 significant digits.
    pub y_labels: Vec<(f64, String)>,
    /// The x labels, spread evenly from the left end of the axis to its right end, with their
    /// unit (the axis's title shown without it); empty: the extremes with 3 significant
    /// digits.
    pub x_labels: Vec<String>,
    /// The styles of the first series, in place of their palette colours (the overlaid runs',
    /// the loop's point at the cursor).
    pub styles: Vec<Style>,
    /// Where series are told apart by marks (ASCII mode, no colour), each series' line drawn
    /// in its glyph; and no glyphs spread along lines in any mode (the time charts, whose
    /// headers name the marks, and the column loop).
    pub glyph_lines: bool,
}

impl Default for Look {
    fn default() -> Self {
        Self {
            legend: true,
            selected: None,
            stems: Vec::new(),
            stem_mark: '|',
            cursor: None,
            time_cursor: false,
            head: Head::Legend,
            x_axis: true,
            label_w: LABEL_W,
            y_labels: Vec::new(),
            x_labels: Vec::new(),
            styles: Vec::new(),
            glyph_lines: false,
        }
    }
}

/// Labels spread evenly from `bounds[0]` (the first) to `bounds[1]` (the last) as (value,
/// text) for [`Look::y_labels`], the empty ones left out; `value` maps a bound to the data's
/// value (10^b of a log axis's bound).
pub(super) fn spread_labels(
    bounds: [f64; 2],
    labels: &[String],
    value: impl Fn(f64) -> f64,
) -> Vec<(f64, String)> {
    let n = labels.len();
    (labels.iter().enumerate())
        .filter(|(_, l)| !l.is_empty())
        .map(|(i, l)| {
            let f = if n > 1 {
                i as f64 / (n - 1) as f64
            } else {
                0.5
            };
            (value(bounds[0] + f * (bounds[1] - bounds[0])), l.clone())
        })
        .collect()
}

/// A value on an axis: its log10 on a log axis (None for values a log axis cannot show).
fn on(v: f64, log: bool) -> Option<f64> {
    match (v.is_finite(), log) {
        (false, _) => None,
        (true, true) if v > 0.0 => Some(v.log10()),
        (true, true) => None,
        (true, false) => Some(v),
    }
}

/// (log x, log y) of a chart.
fn logs(c: &Chart) -> (bool, bool) {
    (c.x.scale == Scale::Log, c.y.scale == Scale::Log)
}

/// The data's bounds on the axes [x lo, x hi, y lo, y hi] (a linear y range of the data holds
/// 0; a flat range is widened; a fixed range of the chart is kept as it is).
fn extent(c: &Chart, look: &Look) -> [f64; 4] {
    let (log_x, log_y) = logs(c);
    let mut b = [
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    let mut add = |x: Option<f64>, y: Option<f64>| {
        if let Some(x) = x {
            b[0] = b[0].min(x);
            b[1] = b[1].max(x);
        }
        if let Some(y) = y {
            b[2] = b[2].min(y);
            b[3] = b[3].max(y);
        }
    };
    for s in &c.series {
        for &(x, y) in &s.points {
            if let (Some(x), Some(y)) = (on(x, log_x), on(y, log_y)) {
                add(Some(x), Some(y));
            }
        }
    }
    for &(x, y) in &look.stems {
        add(on(x, log_x), on(y, log_y));
        add(None, on(0.0, log_y));
    }
    for l in &c.lines {
        if l.vertical {
            add(on(l.at, log_x), None);
        } else {
            add(None, on(l.at, log_y));
        }
    }
    if let Some((a, e)) = c.x.range
        && let (Some(a), Some(e)) = (on(a, log_x), on(e, log_x))
    {
        (b[0], b[1]) = (a, e);
    }
    if let Some((a, e)) = c.y.range
        && let (Some(a), Some(e)) = (on(a, log_y), on(e, log_y))
    {
        (b[2], b[3]) = (a, e);
    }
    if !log_y && c.y.range.is_none() && b[2] <= b[3] {
        b[2] = b[2].min(0.0);
        b[3] = b[3].max(0.0);
    }
    for k in [0, 2] {
        if b[k] > b[k + 1] {
            (b[k], b[k + 1]) = (0.0, 1.0);
        } else if b[k + 1] - b[k] <= 1e-12 * b[k].abs().max(b[k + 1].abs()) {
            let d = if b[k] == 0.0 { 1.0 } else { 0.1 * b[k].abs() };
            (b[k], b[k + 1]) = (b[k] - d, b[k + 1] + d);
        }
    }
    b
}

/// The style of series `i`: its palette colour, the look's, or the selection's.
fn style_of(c: &Chart, look: &Look, i: usize, th: &Theme) -> Style {
    if look.selected == Some(i) {
        th.selected().patch(th.bold())
    } else if let Some(s) = look.styles.get(i) {
        *s
    } else {
        th.series(c.series[i].color)
    }
}

/// An axis label: the value (10^v on a log axis), 3 significant digits, at most 8 characters.
fn label(v: f64, log: bool) -> String {
    let x = if log { 10f64.powf(v) } else { v };
    let s = fmt_sig(x, 3);
    if s.chars().count() <= 8 {
        s
    } else {
        format!("{x:.1e}")
    }
}

/// The legend: the y axis's title, then `glyph label` per series; what does not fit is left
/// out whole and counted.
fn legend(c: &Chart, look: &Look, width: usize, lines: usize, th: &Theme) -> Vec<Line<'static>> {
    let y_title = th.text(&c.y.label());
    let mut out: Vec<(Vec<Span<'static>>, usize)> = vec![(
        vec![Span::styled(y_title.clone(), th.bold())],
        y_title.chars().count(),
    )];
    let mut left = 0;
    for (i, s) in c.series.iter().enumerate().filter(|_| look.legend) {
        let name = th.text(&s.label);
        let w = 4 + name.chars().count();
        let mark = Span::styled(
            s.glyph.to_string(),
            style_of(c, look, i, th).patch(th.bold()),
        );
        let name = Span::raw(format!(" {name}"));
        let last = out.last_mut().expect("a first line");
        if last.1 + w <= width {
            last.0.extend([Span::raw("  "), mark, name]);
            last.1 += w;
        } else if out.len() < lines && w - 2 <= width {
            out.push((vec![mark, name], w - 2));
        } else {
            left += 1;
        }
    }
    if left > 0 {
        let more = format!("  +{left} more");
        let last = out.last_mut().expect("a first line");
        if last.1 + more.len() <= width {
            last.0.push(Span::styled(more, th.dim()));
        }
    }
    out.into_iter().map(|(s, _)| Line::from(s)).collect()
}

/// The row (0 at the top, `rows` of them) a y value `a` on the axis is drawn on, as the canvas
/// draws a horizontal line there: Braille dots rounded, 4 to a row, or (in ASCII mode, where
/// lines are printed) rows rounded.
fn row_of(a: f64, b: [f64; 4], rows: u16, th: &Theme) -> usize {
    let f = ((b[3] - a) / (b[3] - b[2])).clamp(0.0, 1.0);
    let rows = rows as usize;
    if th.ascii {
        ((f * (rows - 1) as f64).round() as usize).min(rows - 1)
    } else {
        let dots = 4 * rows;
        (((f * (dots - 1) as f64).round() as usize) / 4).min(rows - 1)
    }
}

/// The row of x labels in `room` columns: the first label at the left, the last at the right,
/// the axis's title between them where it fits; a lone middle label (a flat range's)
/// centred.
fn x_row(labels: &[String], title: &str, room: usize) -> String {
    if let [a, mid, e] = labels
        && a.is_empty()
        && e.is_empty()
    {
        return format!("{mid:^room$}");
    }
    let (xa, xb) = match labels {
        [] => ("", ""),
        [a] => (a.as_str(), ""),
        [a, .., e] => (a.as_str(), e.as_str()),
    };
    let (na, nb, nt) = (
        xa.chars().count(),
        xb.chars().count(),
        title.chars().count(),
    );
    if na + nt + nb + 2 <= room {
        let gap = room - na - nt - nb;
        format!(
            "{xa}{}{title}{}{xb}",
            " ".repeat(gap / 2),
            " ".repeat(gap - gap / 2)
        )
    } else if na + nb < room {
        format!("{xa}{}{xb}", " ".repeat(room - na - nb))
    } else {
        String::new()
    }
}

/// Draws the chart in `area` (nothing below 5 rows, 2 without the x axis, or below the labels
/// and 15 columns).
pub(super) fn draw_line_plot(frame: &mut Frame, area: Rect, c: &Chart, look: &Look, th: &Theme) {
    let lw = look.label_w;
    let (min_h, min_rows, axis_rows) = if look.x_axis { (5, 2, 2) } else { (2, 1, 0) };
    if area.height < min_h || area.width < lw + 15 {
        return;
    }
    let (log_x, log_y) = logs(c);
    let head = match &look.head {
        Head::Legend => {
            let legend_rows = if area.height >= 10 { 2 } else { 1 };
            legend(c, look, area.width as usize, legend_rows, th)
        }
        Head::Line(l) => vec![l.clone()],
        Head::None => Vec::new(),
    };
    let hh = head.len() as u16;
    if hh > 0 {
        frame.render_widget(Paragraph::new(head), Rect { height: hh, ..area });
    }
    let rows = area.height.saturating_sub(hh + axis_rows);
    if rows < min_rows {
        return;
    }
    let b = extent(c, look);
    let top = area.y + hh;
    let cw = area.width - lw - 1;
    let (vbar, corner, hbar) = if th.ascii {
        ("|", "+", "-")
    } else {
        ("│", "└", "─")
    };
    let w = lw as usize;
    let mut labels: Vec<Line> = (0..rows)
        .map(|_| Line::styled(format!("{:>w$}{vbar}", ""), th.dim()))
        .collect();
    let mut taken = vec![false; rows as usize];
    let mut put = |row: usize, text: &str| {
        if !taken[row] {
            taken[row] = true;
            labels[row] = Line::styled(format!("{text:>w$}{vbar}"), th.dim());
        }
    };
    if look.y_labels.is_empty() {
        put(0, &label(b[3], log_y));
        put(rows as usize - 1, &label(b[2], log_y));
    }
    let tol = 1e-9 * (b[3] - b[2]);
    for (v, text) in &look.y_labels {
        if let Some(a) = on(*v, log_y).filter(|a| *a >= b[2] - tol && *a <= b[3] + tol) {
            put(row_of(a, b, rows, th), text);
        }
    }
    if look.x_axis {
        labels.push(Line::styled(
            format!("{:>w$}{corner}{}", "", hbar.repeat(cw as usize)),
            th.dim(),
        ));
        let xl = if look.x_labels.is_empty() {
            vec![label(b[0], log_x), label(b[1], log_x)]
        } else {
            look.x_labels.clone()
        };
        // the panel's own labels carry their unit: the axis's title alone beside them
        let title = if look.x_labels.is_empty() {
            c.x.label()
        } else {
            c.x.title.clone()
        };
        let row = x_row(&xl, &th.text(&title), cw as usize);
        labels.push(Line::styled(format!("{:>w$} {row}", ""), th.dim()));
    }
    frame.render_widget(
        Paragraph::new(labels),
        Rect::new(area.x, top, area.width, rows + axis_rows),
    );
    let canvas = Rect::new(area.x + lw + 1, top, cw, rows);
    let marker = th.marker();
    let size = (cw as f64, rows as f64);
    let canvas_widget = Canvas::default()
        .marker(marker)
        .x_bounds([b[0], b[1]])
        .y_bounds([b[2], b[3]])
        .paint(|ctx| paint(ctx, c, look, b, size, th));
    frame.render_widget(canvas_widget, canvas);
}

/// The canvas's cells over the bounds [x lo, x hi, y lo, y hi]: `size` (columns, rows), `dots`
/// of its marker per cell (2 × 4 Braille dots, 1 × 1 in ASCII mode).
#[derive(Clone, Copy)]
struct Cells {
    b: [f64; 4],
    size: (f64, f64),
    dots: (f64, f64),
}

impl Cells {
    /// Cells per unit along x and y.
    fn scale(&self) -> (f64, f64) {
        (
            (self.size.0 - 1.0) / (self.b[1] - self.b[0]),
            (self.size.1 - 1.0) / (self.b[3] - self.b[2]),
        )
    }

    /// Prints `span` in the cell of (x, y) as the canvas rounds it: to its dots when `dots`
    /// (a mark on a line the canvas draws), to cells otherwise (a line printed cell by cell);
    /// nothing outside the bounds. The canvas truncates a printed label's position: the point
    /// is moved into its cell first.
    fn print(&self, ctx: &mut Context, (x, y): (f64, f64), span: Span<'static>, dots: bool) {
        let [l, r, lo, hi] = self.b;
        if !(l..=r).contains(&x) || !(lo..=hi).contains(&y) {
            return;
        }
        let (gx, gy) = if dots { self.dots } else { (1.0, 1.0) };
        // the cell of a fraction `f` of `n` cells of `g` dots
        let cell = |f: f64, n: f64, g: f64| ((f * (n * g - 1.0)).round() / g).floor();
        let cx = cell((x - l) / (r - l), self.size.0, gx);
        let cy = cell((hi - y) / (hi - lo), self.size.1, gy);
        let (sx, sy) = self.scale();
        let x = if sx > 0.0 { l + (cx + 1e-6) / sx } else { x };
        let y = if sy > 0.0 { hi - (cy + 1e-6) / sy } else { y };
        ctx.print(x.clamp(l, r), y.clamp(lo, hi), span);
    }

    /// The part of segment (a, e) inside the bounds (Liang–Barsky), if any.
    fn clip(&self, a: (f64, f64), e: (f64, f64)) -> Option<((f64, f64), (f64, f64))> {
        let [l, r, lo, hi] = self.b;
        let (dx, dy) = (e.0 - a.0, e.1 - a.1);
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        for (p, q) in [
            (-dx, a.0 - l),
            (dx, r - a.0),
            (-dy, a.1 - lo),
            (dy, hi - a.1),
        ] {
            if p == 0.0 {
                if q < 0.0 {
                    return None;
                }
            } else {
                let t = q / p;
                if p < 0.0 {
                    t0 = t0.max(t);
                } else {
                    t1 = t1.min(t);
                }
            }
        }
        (t0 <= t1).then(|| {
            let at = |t: f64| (a.0 + t * dx, a.1 + t * dy);
            (at(t0), at(t1))
        })
    }
}

/// A segment: a Braille line, or `mark` printed in each cell it crosses within the bounds (in
/// ASCII mode, and for a line drawn in its glyph).
fn segment(
    ctx: &mut Context,
    (a, e): ((f64, f64), (f64, f64)),
    mark: Option<&str>,
    style: Style,
    cells: Cells,
) {
    if let Some(mark) = mark {
        let Some((a, e)) = cells.clip(a, e) else {
            return;
        };
        let scale = cells.scale();
        let n = (((e.0 - a.0) * scale.0).abs())
            .max(((e.1 - a.1) * scale.1).abs())
            .ceil() as usize;
        for k in 0..=n {
            let f = k as f64 / n.max(1) as f64;
            let p = (a.0 + f * (e.0 - a.0), a.1 + f * (e.1 - a.1));
            cells.print(ctx, p, Span::styled(mark.to_string(), style), false);
        }
    } else {
        let color = style.fg.unwrap_or(Color::Reset);
        ctx.draw(&CLine {
            x1: a.0,
            y1: a.1,
            x2: e.0,
            y2: e.1,
            color,
        });
    }
}

fn paint(ctx: &mut Context, c: &Chart, look: &Look, b: [f64; 4], size: (f64, f64), th: &Theme) {
    let (log_x, log_y) = logs(c);
    let dots = if th.ascii { (1.0, 1.0) } else { (2.0, 4.0) };
    let cells = Cells { b, size, dots };
    // in ASCII mode a horizontal line (the zero line) as `-`, a vertical one as `:`: neither
    // is a curve's line (`.`) nor its mark
    let ascii = |mark: &'static str| th.ascii.then_some(mark);
    for l in &c.lines {
        let Some(v) = on(l.at, if l.vertical { log_x } else { log_y }) else {
            continue;
        };
        let (a, e) = if l.vertical {
            ((v, b[2]), (v, b[3]))
        } else {
            ((b[0], v), (b[1], v))
        };
        let mark = if l.vertical { ":" } else { "-" };
        segment(ctx, (a, e), ascii(mark), th.dim(), cells);
        if !l.label.is_empty() {
            let at = if l.vertical { (v, b[3]) } else { (b[0], v) };
            cells.print(ctx, at, Span::styled(th.text(&l.label), th.dim()), true);
        }
    }
    let cursor = look.cursor.and_then(|x| on(x, log_x));
    let across = |x: f64| ((x, b[2]), (x, b[3]));
    if let Some(x) = cursor.filter(|_| !look.time_cursor) {
        segment(ctx, across(x), ascii(":"), th.dim(), cells);
    }
    ctx.layer();
    let pt = |x: f64, y: f64| Some((on(x, log_x)?, on(y, log_y)?));
    let y0 = on(0.0, log_y).unwrap_or(b[2]);
    for &(x, y) in &look.stems {
        if let Some((x, y)) = pt(x, y) {
            segment(ctx, ((x, y0), (x, y)), ascii("."), th.series(5), cells);
            let mark = look.stem_mark.to_string();
            cells.print(
                ctx,
                (x, y),
                Span::styled(mark, th.series(5).patch(th.bold())),
                true,
            );
        }
    }
    let points = |i: usize| -> Vec<(f64, f64)> {
        (c.series[i].points.iter())
            .filter_map(|&(x, y)| pt(x, y))
            .collect()
    };
    for (i, s) in c.series.iter().enumerate() {
        if s.stroke == crate::plot::Stroke::None {
            continue;
        }
        let glyph = s.glyph.to_string();
        let mark = if look.glyph_lines && th.marks() {
            Some(glyph.as_str())
        } else {
            ascii(".")
        };
        let style = style_of(c, look, i, th);
        for w in points(i).windows(2) {
            segment(ctx, (w[0], w[1]), mark, style, cells);
        }
        // each series over the ones before it, not mixed into their cells
        if look.glyph_lines {
            ctx.layer();
        }
    }
    ctx.layer();
    // a series with markers has its glyph at every point; a line without, at a few spread
    // along it (unless its line is drawn in it, or names no mark)
    for (i, s) in c.series.iter().enumerate() {
        if look.glyph_lines && s.marker == Marker::None {
            continue;
        }
        let pts = points(i);
        let every = if s.marker == Marker::None {
            (pts.len() / 5).max(1)
        } else {
            1
        };
        let style = style_of(c, look, i, th).patch(th.bold());
        let mark = Span::styled(s.glyph.to_string(), style);
        for (k, q) in pts.iter().enumerate() {
            if every == 1 || k % every == every / 2 {
                cells.print(ctx, *q, mark.clone(), true);
            }
        }
    }
    // the time cursor over everything
    if let Some(x) = cursor.filter(|_| look.time_cursor) {
        ctx.layer();
        let mark = CURSOR_MARK.to_string();
        segment(
            ctx,
            across(x),
            th.marks().then_some(&mark),
            th.cursor(),
            cells,
        );
    }
}
