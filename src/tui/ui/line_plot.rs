//! A line plot for the results pages: curves over linear or log axes (time histories, the
//! response spectrum, work-precision), with reference lines (the zero line, a period, the
//! 1 % error) and stems (impulses). Each curve carries its own mark, printed along it and in
//! the legend, so curves differ without colour; the y labels are the data's own extremes.

use super::common::Theme;
use crate::tui::chart::fmt_sig;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;
use ratatui::widgets::canvas::{Canvas, Context, Line as CLine};

/// Width of the y labels.
const LABEL_W: u16 = 9;

/// Where a curve's mark is printed: at every point (a few points), or at a few points spread
/// along it (a history).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Marks {
    Every,
    Spread,
}

pub(super) struct Curve {
    pub name: String,
    pub mark: char,
    pub style: Style,
    pub points: Vec<(f64, f64)>,
    pub marks: Marks,
}

/// A reference line: horizontal at y (or vertical at x), its label.
pub(super) struct RefLine {
    pub vertical: bool,
    pub at: f64,
    pub label: String,
}

pub(super) struct LinePlot {
    /// What and unit of the y axis: `energy [kJ]`.
    pub y_title: String,
    pub x_title: String,
    pub curves: Vec<Curve>,
    pub lines: Vec<RefLine>,
    /// (x, y) stems from 0, drawn with `stem_mark`.
    pub stems: Vec<(f64, f64)>,
    pub stem_mark: char,
    pub log_x: bool,
    pub log_y: bool,
    /// The x range (default: the data's).
    pub x_range: Option<[f64; 2]>,
    /// The curves' marks and names in the legend (off where a table beside the plot names
    /// them).
    pub legend: bool,
}

impl LinePlot {
    pub fn new(y_title: String, x_title: String) -> Self {
        Self {
            y_title,
            x_title,
            curves: Vec::new(),
            lines: Vec::new(),
            stems: Vec::new(),
            stem_mark: '|',
            log_x: false,
            log_y: false,
            x_range: None,
            legend: true,
        }
    }
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

/// The data's bounds on the axes [x lo, x hi, y lo, y hi] (a linear y range holds 0; a flat
/// range is widened).
fn extent(p: &LinePlot) -> [f64; 4] {
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
    for c in &p.curves {
        for &(x, y) in &c.points {
            if let (Some(x), Some(y)) = (on(x, p.log_x), on(y, p.log_y)) {
                add(Some(x), Some(y));
            }
        }
    }
    for &(x, y) in &p.stems {
        add(on(x, p.log_x), on(y, p.log_y));
        add(None, on(0.0, p.log_y));
    }
    for l in &p.lines {
        if l.vertical {
            add(on(l.at, p.log_x), None);
        } else {
            add(None, on(l.at, p.log_y));
        }
    }
    if let Some([a, e]) = p.x_range
        && let (Some(a), Some(e)) = (on(a, p.log_x), on(e, p.log_x))
    {
        (b[0], b[1]) = (a, e);
    }
    if !p.log_y && b[2] <= b[3] {
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

/// The legend: the y title, then `mark name` per curve; what does not fit is left out whole
/// and counted.
fn legend(p: &LinePlot, width: usize, lines: usize, th: &Theme) -> Vec<Line<'static>> {
    let mut out: Vec<(Vec<Span<'static>>, usize)> = vec![(
        vec![Span::styled(p.y_title.clone(), th.bold())],
        p.y_title.chars().count(),
    )];
    let mut left = 0;
    for c in p.curves.iter().filter(|_| p.legend) {
        let w = 4 + c.name.chars().count();
        let mark = Span::styled(c.mark.to_string(), c.style.patch(th.bold()));
        let name = Span::raw(format!(" {}", c.name));
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

/// Draws the plot in `area` (nothing below 5 rows or 24 columns).
pub(super) fn draw_line_plot(frame: &mut Frame, area: Rect, p: &LinePlot, th: &Theme) {
    if area.height < 5 || area.width < LABEL_W + 15 {
        return;
    }
    let legend_rows = if area.height >= 10 { 2 } else { 1 };
    let head = legend(p, area.width as usize, legend_rows, th);
    let hh = head.len() as u16;
    frame.render_widget(Paragraph::new(head), Rect { height: hh, ..area });
    let rows = area.height - hh - 2;
    if rows < 2 {
        return;
    }
    let b = extent(p);
    let top = area.y + hh;
    let cw = area.width - LABEL_W - 1;
    let (vbar, corner, hbar) = if th.ascii {
        ("|", "+", "-")
    } else {
        ("│", "└", "─")
    };
    let w = LABEL_W as usize;
    let mut labels: Vec<Line> = (0..rows)
        .map(|_| Line::styled(format!("{:>w$}{vbar}", ""), th.dim()))
        .collect();
    let lab = |v: f64| Line::styled(format!("{:>w$}{vbar}", label(v, p.log_y)), th.dim());
    labels[0] = lab(b[3]);
    labels[rows as usize - 1] = lab(b[2]);
    labels.push(Line::styled(
        format!("{:>w$}{corner}{}", "", hbar.repeat(cw as usize)),
        th.dim(),
    ));
    let (xa, xb) = (label(b[0], p.log_x), label(b[1], p.log_x));
    let title = th.text(&p.x_title);
    let room = cw as usize;
    let (na, nb, nt) = (xa.len(), xb.len(), title.chars().count());
    let row = if na + nt + nb + 2 <= room {
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
    };
    labels.push(Line::styled(format!("{:>w$} {row}", ""), th.dim()));
    frame.render_widget(
        Paragraph::new(labels),
        Rect::new(area.x, top, area.width, rows + 2),
    );
    let canvas = Rect::new(area.x + LABEL_W + 1, top, cw, rows);
    let marker = th.marker();
    let size = (cw as f64, rows as f64);
    let c = Canvas::default()
        .marker(marker)
        .x_bounds([b[0], b[1]])
        .y_bounds([b[2], b[3]])
        .paint(|ctx| paint(ctx, p, b, size, th));
    frame.render_widget(c, canvas);
}

/// A segment: Braille line, or in ASCII mode `mark` in each cell it crosses.
fn segment(
    ctx: &mut Context,
    (a, e): ((f64, f64), (f64, f64)),
    mark: &'static str,
    style: Style,
    scale: (f64, f64),
    th: &Theme,
) {
    if th.ascii {
        let cells = (((e.0 - a.0) * scale.0).abs())
            .max(((e.1 - a.1) * scale.1).abs())
            .ceil() as usize;
        for k in 0..=cells {
            let f = k as f64 / cells.max(1) as f64;
            ctx.print(
                a.0 + f * (e.0 - a.0),
                a.1 + f * (e.1 - a.1),
                Span::styled(mark, style),
            );
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

fn paint(ctx: &mut Context, p: &LinePlot, b: [f64; 4], (w, h): (f64, f64), th: &Theme) {
    // cells per unit along x and y
    let scale = ((w - 1.0) / (b[1] - b[0]), (h - 1.0) / (b[3] - b[2]));
    for l in &p.lines {
        let Some(v) = on(l.at, if l.vertical { p.log_x } else { p.log_y }) else {
            continue;
        };
        let (a, e) = if l.vertical {
            ((v, b[2]), (v, b[3]))
        } else {
            ((b[0], v), (b[1], v))
        };
        // in ASCII mode a horizontal line (the zero line) as `-`, a vertical one as `:`: neither
        // is a curve's line (`.`) nor its mark
        let mark = if l.vertical { ":" } else { "-" };
        segment(ctx, (a, e), mark, th.dim(), scale, th);
        let at = if l.vertical { (v, b[3]) } else { (b[0], v) };
        ctx.print(at.0, at.1, Span::styled(th.text(&l.label), th.dim()));
    }
    ctx.layer();
    let pt = |x: f64, y: f64| Some((on(x, p.log_x)?, on(y, p.log_y)?));
    let y0 = on(0.0, p.log_y).unwrap_or(b[2]);
    for &(x, y) in &p.stems {
        if let Some((x, y)) = pt(x, y) {
            segment(ctx, ((x, y0), (x, y)), ".", th.series(5), scale, th);
            ctx.print(
                x,
                y,
                Span::styled(p.stem_mark.to_string(), th.series(5).patch(th.bold())),
            );
        }
    }
    for c in &p.curves {
        let pts: Vec<(f64, f64)> = c.points.iter().filter_map(|&(x, y)| pt(x, y)).collect();
        for s in pts.windows(2) {
            segment(ctx, (s[0], s[1]), ".", c.style, scale, th);
        }
    }
    ctx.layer();
    for c in &p.curves {
        let pts: Vec<(f64, f64)> = c.points.iter().filter_map(|&(x, y)| pt(x, y)).collect();
        let every = match c.marks {
            Marks::Every => 1,
            Marks::Spread => (pts.len() / 5).max(1),
        };
        let mark = Span::styled(c.mark.to_string(), c.style.patch(th.bold()));
        for (i, q) in pts.iter().enumerate() {
            if i % every == every / 2 || c.marks == Marks::Every {
                ctx.print(q.0, q.1, mark.clone());
            }
        }
    }
}
