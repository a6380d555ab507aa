//! Charts and grids as SVG text (SVG 1.1, no fonts or libraries needed): a value v lands at
//! pixel x = left + frac(v)·width, y = top + (1 − frac(v))·height of the plot area
//! ([`plot_area`], `ticks::Span::frac`).

use super::chart::{Axis, Band, Bars, Chart, Grid, Marker, RefLine, Series, Stroke, color};
use super::ticks::{Span, span, y_span, y_ticks};
use std::fmt::Write as _;

/// Left margin: y tick labels and the y axis title, px.
pub(crate) const MARGIN_LEFT: f64 = 72.0;
/// Top margin: the title, px.
pub(crate) const MARGIN_TOP: f64 = 36.0;
/// Bottom margin: x tick labels and the x axis title, px.
pub(crate) const MARGIN_BOTTOM: f64 = 52.0;
/// Right margin without a legend, px.
pub(crate) const MARGIN_RIGHT: f64 = 24.0;
/// Width of a character at the legend's font size (11 px), px: an estimate, no font is read.
pub(crate) const CHAR_WIDTH: f64 = 7.0;
/// Smallest canvas drawn, px (a smaller request is widened to it).
pub(crate) const MIN_SIZE: (f64, f64) = (320.0, 200.0);

/// The plot area inside the canvas, px.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Area {
    pub left: f64,
    pub top: f64,
    pub width: f64,
    pub height: f64,
}

impl Area {
    /// The pixel of (fx, fy), the fractions of the x and y spans.
    pub fn pixel(&self, fx: f64, fy: f64) -> (f64, f64) {
        (
            self.left + fx * self.width,
            self.top + (1.0 - fy) * self.height,
        )
    }
}

/// The legend's labels: series, bands, bars, reference lines.
fn legend_labels(c: &Chart) -> Vec<&str> {
    let s = c.series.iter().map(|s| s.label.as_str());
    let b = c.bands.iter().map(|b| b.label.as_str());
    let r = c.bars.iter().map(|b| b.label.as_str());
    let l = c.lines.iter().map(|l| l.label.as_str());
    s.chain(b)
        .chain(r)
        .chain(l)
        .filter(|l| !l.is_empty())
        .collect()
}

/// The plot area of `chart` on a `width` × `height` canvas: margins [`MARGIN_LEFT`] (with
/// labelled rows, 36 px + 1.1 [`CHAR_WIDTH`] per character of the longest, if wider, at most
/// 45 % of the width), [`MARGIN_TOP`], [`MARGIN_BOTTOM`]; on the right the legend, 44 px +
/// [`CHAR_WIDTH`] per character of its longest label (at most 45 % of the width), or
/// [`MARGIN_RIGHT`] without one.
pub fn plot_area(chart: &Chart, width: f64, height: f64) -> Area {
    let (w, h) = (width.max(MIN_SIZE.0), height.max(MIN_SIZE.1));
    let longest = (legend_labels(chart).iter())
        .map(|l| l.chars().count())
        .max();
    let right = longest.map_or(MARGIN_RIGHT, |n| {
        (44.0 + CHAR_WIDTH * n as f64).min(0.45 * w)
    });
    let rows = chart.rows.iter().map(|l| l.chars().count()).max();
    let left = rows.map_or(MARGIN_LEFT, |n| {
        (36.0 + 1.1 * CHAR_WIDTH * n as f64).clamp(MARGIN_LEFT, 0.45 * w)
    });
    Area {
        left,
        top: MARGIN_TOP,
        width: w - left - right,
        height: h - MARGIN_TOP - MARGIN_BOTTOM,
    }
}

/// Text with `&`, `<`, `>`, `"` and `'` escaped for XML.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 && c != '\n' && c != '\t' => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

fn header(out: &mut String, w: f64, h: f64) {
    let _ = writeln!(out, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(out, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
}

/// `chart` as an SVG document of `width` × `height` px.
pub fn render(chart: &Chart, width: f64, height: f64) -> String {
    let (w, h) = (width.max(MIN_SIZE.0), height.max(MIN_SIZE.1));
    let a = plot_area(chart, w, h);
    let sx = span(&chart.x, &chart.xs());
    let sy = y_span(chart);
    let mut out = String::new();
    header(&mut out, w, h);
    let _ = writeln!(
        out,
        r#"<text class="title" x="{:.2}" y="22" text-anchor="middle" font-size="14">{}</text>"#,
        w / 2.0,
        escape(&chart.title)
    );
    let _ = writeln!(
        out,
        r#"<defs><clipPath id="plot-area"><rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}"/></clipPath></defs>"#,
        a.left, a.top, a.width, a.height
    );
    let ty = y_ticks(chart, &sy);
    axes(&mut out, &a, (&chart.x, &sx), (&chart.y, &sy, &ty), h);
    out += "<g clip-path=\"url(#plot-area)\">\n";
    for b in &chart.bands {
        band(&mut out, &a, &sx, &sy, b);
    }
    for b in &chart.bars {
        bars(&mut out, &a, (&sx, &sy), chart, b);
    }
    for l in &chart.lines {
        ref_line(&mut out, &a, &sx, &sy, l);
    }
    for s in &chart.series {
        series_line(&mut out, &a, &sx, &sy, s);
    }
    out += "</g>\n";
    for s in &chart.series {
        markers(&mut out, &a, &sx, &sy, s);
    }
    legend(&mut out, chart, &a);
    out += "</svg>\n";
    out
}

/// A y axis, its span and its ticks with their text.
type YAxis<'a> = (&'a Axis, &'a Span, &'a [(f64, String)]);

/// Grid lines, ticks and their labels, the frame and the axis titles.
fn axes(out: &mut String, a: &Area, x: (&Axis, &Span), y: YAxis, h: f64) {
    out.push_str("<g class=\"axes\">\n");
    let (bottom, right) = (a.top + a.height, a.left + a.width);
    let tx = x.1.ticks();
    for &t in &tx {
        let Some(f) = x.1.frac(t) else { continue };
        let px = a.left + f * a.width;
        let _ = writeln!(
            out,
            r##"<line x1="{px:.2}" y1="{:.2}" x2="{px:.2}" y2="{bottom:.2}" stroke="#e5e5e5"/><line x1="{px:.2}" y1="{bottom:.2}" x2="{px:.2}" y2="{:.2}" stroke="black"/><text x="{px:.2}" y="{:.2}" text-anchor="middle">{}</text>"##,
            a.top,
            bottom + 5.0,
            bottom + 18.0,
            escape(&x.1.label(t, &tx))
        );
    }
    for (t, label) in y.2 {
        let Some(f) = y.1.frac(*t) else { continue };
        let py = a.top + (1.0 - f) * a.height;
        let _ = writeln!(
            out,
            r##"<line x1="{:.2}" y1="{py:.2}" x2="{right:.2}" y2="{py:.2}" stroke="#e5e5e5"/><line x1="{:.2}" y1="{py:.2}" x2="{:.2}" y2="{py:.2}" stroke="black"/><text x="{:.2}" y="{:.2}" text-anchor="end">{}</text>"##,
            a.left,
            a.left - 5.0,
            a.left,
            a.left - 8.0,
            py + 4.0,
            escape(label)
        );
    }
    let _ = writeln!(
        out,
        r#"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="none" stroke="black"/>"#,
        a.left, a.top, a.width, a.height
    );
    let _ = writeln!(
        out,
        r#"<text class="x-title" x="{:.2}" y="{:.2}" text-anchor="middle">{}</text>"#,
        a.left + a.width / 2.0,
        h - 12.0,
        escape(&x.0.label())
    );
    let _ = writeln!(
        out,
        r#"<text class="y-title" transform="translate(16 {:.2}) rotate(-90)" text-anchor="middle">{}</text>"#,
        a.top + a.height / 2.0,
        escape(&y.0.label())
    );
    out.push_str("</g>\n");
}

/// The pixel of a data point, `None` when it cannot be drawn.
fn pixel(a: &Area, sx: &Span, sy: &Span, x: f64, y: f64) -> Option<(f64, f64)> {
    Some(a.pixel(sx.frac(x)?, sy.frac(y)?))
}

fn band(out: &mut String, a: &Area, sx: &Span, sy: &Span, b: &Band) {
    // runs of drawable points, each a polygon: the upper edge forward, the lower edge back
    type Edge = ((f64, f64), (f64, f64));
    let mut runs: Vec<Vec<Edge>> = vec![Vec::new()];
    for &(x, lo, hi) in &b.points {
        match (pixel(a, sx, sy, x, lo), pixel(a, sx, sy, x, hi)) {
            (Some(l), Some(h)) => runs.last_mut().expect("one run").push((l, h)),
            _ => runs.push(Vec::new()),
        }
    }
    for run in runs.iter().filter(|r| r.len() > 1) {
        let mut pts: Vec<String> = run.iter().map(|(_, h)| xy(*h)).collect();
        pts.extend(run.iter().rev().map(|(l, _)| xy(*l)));
        let _ = writeln!(
            out,
            r#"<polygon class="band" points="{}" fill="{}" fill-opacity="0.2" stroke="none"/>"#,
            pts.join(" "),
            color(b.color)
        );
    }
}

/// Each bar a rectangle from its `from` to its `to`, 0.6 of its row's height.
fn bars(out: &mut String, a: &Area, (sx, sy): (&Span, &Span), c: &Chart, b: &Bars) {
    let half = 0.3 * a.height / c.rows.len().max(1) as f64;
    for &(row, from, to) in &b.bars {
        let y = c.row_y(row);
        let (Some(p0), Some(p1)) = (pixel(a, sx, sy, from, y), pixel(a, sx, sy, to, y)) else {
            continue;
        };
        let _ = writeln!(
            out,
            r#"<rect class="bar" data-label="{}" x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="{}" fill-opacity="0.85"/>"#,
            escape(&b.label),
            p0.0.min(p1.0),
            p0.1 - half,
            (p1.0 - p0.0).abs(),
            2.0 * half,
            color(b.color)
        );
    }
}

fn xy(p: (f64, f64)) -> String {
    format!("{:.2},{:.2}", p.0, p.1)
}

fn ref_line(out: &mut String, a: &Area, sx: &Span, sy: &Span, l: &RefLine) {
    let f = if l.vertical {
        sx.frac(l.at)
    } else {
        sy.frac(l.at)
    };
    let Some(f) = f else { return };
    let ((x1, y1), (x2, y2)) = if l.vertical {
        (a.pixel(f, 0.0), a.pixel(f, 1.0))
    } else {
        (a.pixel(0.0, f), a.pixel(1.0, f))
    };
    let _ = writeln!(
        out,
        r#"<line class="ref" x1="{x1:.2}" y1="{y1:.2}" x2="{x2:.2}" y2="{y2:.2}" stroke="{}" stroke-width="1.2" stroke-dasharray="6 4"/>"#,
        color(l.color)
    );
}

fn series_line(out: &mut String, a: &Area, sx: &Span, sy: &Span, s: &Series) {
    if s.stroke == Stroke::None {
        return;
    }
    let dash = if s.stroke == Stroke::Dashed {
        r#" stroke-dasharray="8 4""#
    } else {
        ""
    };
    let mut runs: Vec<Vec<String>> = vec![Vec::new()];
    for &(x, y) in &s.points {
        match pixel(a, sx, sy, x, y) {
            Some(p) => runs.last_mut().expect("one run").push(xy(p)),
            None => runs.push(Vec::new()),
        }
    }
    for run in runs.iter().filter(|r| r.len() > 1) {
        let _ = writeln!(
            out,
            r#"<polyline class="series" data-label="{}" points="{}" fill="none" stroke="{}" stroke-width="1.8"{dash}/>"#,
            escape(&s.label),
            run.join(" "),
            color(s.color)
        );
    }
}

/// Marks at the points inside the plot area (they are not clipped, so none is cut in half).
fn markers(out: &mut String, a: &Area, sx: &Span, sy: &Span, s: &Series) {
    if s.marker == Marker::None {
        return;
    }
    let inside = |f: f64| (-1e-9..=1.0 + 1e-9).contains(&f);
    let _ = writeln!(
        out,
        r#"<g class="markers" data-label="{}" fill="{}" stroke="{}">"#,
        escape(&s.label),
        color(s.color),
        color(s.color)
    );
    for &(x, y) in &s.points {
        let (Some(fx), Some(fy)) = (sx.frac(x), sy.frac(y)) else {
            continue;
        };
        if inside(fx) && inside(fy) {
            mark(out, s.marker, a.pixel(fx, fy));
        }
    }
    out.push_str("</g>\n");
}

fn mark(out: &mut String, m: Marker, (x, y): (f64, f64)) {
    let _ = match m {
        Marker::None => Ok(()),
        Marker::Circle => writeln!(out, r#"<circle cx="{x:.2}" cy="{y:.2}" r="3.5"/>"#),
        Marker::Square => writeln!(
            out,
            r#"<rect x="{:.2}" y="{:.2}" width="7" height="7"/>"#,
            x - 3.5,
            y - 3.5
        ),
        Marker::Triangle => writeln!(
            out,
            r#"<polygon points="{:.2},{:.2} {:.2},{:.2} {:.2},{:.2}"/>"#,
            x,
            y - 4.0,
            x - 4.0,
            y + 3.0,
            x + 4.0,
            y + 3.0
        ),
        Marker::Cross => writeln!(
            out,
            r#"<path d="M{:.2} {:.2}L{:.2} {:.2}M{:.2} {:.2}L{:.2} {:.2}" fill="none" stroke-width="1.5"/>"#,
            x - 3.5,
            y - 3.5,
            x + 3.5,
            y + 3.5,
            x - 3.5,
            y + 3.5,
            x + 3.5,
            y - 3.5
        ),
    };
}

/// An entry of the legend.
enum Entry<'a> {
    Series(&'a Series),
    Band(&'a Band),
    Bars(&'a Bars),
    Line(&'a RefLine),
}

/// The sample drawn left of a legend label whose middle is at (x0, y).
fn sample(e: &Entry, x0: f64, y: f64) -> String {
    let dashed = |s: Stroke| {
        if s == Stroke::Dashed {
            r#" stroke-dasharray="8 4""#
        } else {
            ""
        }
    };
    match e {
        Entry::Series(s) => {
            let mut out = String::new();
            if s.stroke != Stroke::None {
                out += &format!(
                    r#"<line x1="{x0:.2}" y1="{y:.2}" x2="{:.2}" y2="{y:.2}" stroke="{}" stroke-width="1.8"{}/>"#,
                    x0 + 24.0,
                    color(s.color),
                    dashed(s.stroke)
                );
            }
            if s.marker != Marker::None {
                let mut m = format!(r#"<g fill="{0}" stroke="{0}">"#, color(s.color));
                mark(&mut m, s.marker, (x0 + 12.0, y));
                out += m.trim_end();
                out += "</g>";
            }
            out
        }
        Entry::Band(b) => format!(
            r#"<rect x="{x0:.2}" y="{:.2}" width="24" height="10" fill="{}" fill-opacity="0.2"/>"#,
            y - 5.0,
            color(b.color)
        ),
        Entry::Bars(b) => format!(
            r#"<rect x="{x0:.2}" y="{:.2}" width="24" height="10" fill="{}" fill-opacity="0.85"/>"#,
            y - 5.0,
            color(b.color)
        ),
        Entry::Line(l) => format!(
            r#"<line x1="{x0:.2}" y1="{y:.2}" x2="{:.2}" y2="{y:.2}" stroke="{}" stroke-width="1.2" stroke-dasharray="6 4"/>"#,
            x0 + 24.0,
            color(l.color)
        ),
    }
}

/// One legend row per labelled series, band, set of bars and reference line, right of the
/// plot area.
fn legend(out: &mut String, c: &Chart, a: &Area) {
    let x0 = a.left + a.width + 14.0;
    let entries = (c.series.iter().map(|s| (Entry::Series(s), &s.label)))
        .chain(c.bands.iter().map(|b| (Entry::Band(b), &b.label)))
        .chain(c.bars.iter().map(|b| (Entry::Bars(b), &b.label)))
        .chain(c.lines.iter().map(|l| (Entry::Line(l), &l.label)))
        .filter(|(_, label)| !label.is_empty());
    out.push_str("<g class=\"legend\" font-size=\"11\">\n");
    for (i, (e, label)) in entries.enumerate() {
        let y = a.top + 10.0 + 18.0 * i as f64;
        let _ = writeln!(
            out,
            r#"{}<text x="{:.2}" y="{:.2}">{}</text>"#,
            sample(&e, x0, y),
            x0 + 30.0,
            y + 4.0,
            escape(label)
        );
    }
    out.push_str("</g>\n");
}

/// Cell size of a grid, px.
pub(crate) const GRID_CELL: (f64, f64) = (96.0, 26.0);

/// `grid` as an SVG document: a row label, then one cell per column, filled with its
/// category's colour and showing its text; the legend of categories below.
pub fn render_grid(grid: &Grid) -> String {
    let (cw, ch) = GRID_CELL;
    let longest = (grid.rows.iter())
        .map(|r| r.label.chars().count())
        .max()
        .unwrap_or(0);
    let left = 16.0 + CHAR_WIDTH * longest as f64;
    let ncol = grid.rows.iter().map(|r| r.cells.len()).max().unwrap_or(0);
    let top = 64.0;
    // the title at 14 px: about 8 px a character
    let title_w = 8.0 * grid.title.chars().count() as f64 + 32.0;
    let w = (left + cw * ncol as f64 + 16.0)
        .max(title_w)
        .max(MIN_SIZE.0);
    let h = top + ch * grid.rows.len() as f64 + 24.0 + 18.0 * grid.categories.len() as f64;
    let mut out = String::new();
    header(&mut out, w, h);
    let _ = writeln!(
        out,
        r#"<text class="title" x="{:.2}" y="22" text-anchor="middle" font-size="14">{}</text>"#,
        w / 2.0,
        escape(&grid.title)
    );
    let _ = writeln!(
        out,
        r#"<text x="{:.2}" y="44" text-anchor="middle">{}</text>"#,
        left + cw * ncol as f64 / 2.0,
        escape(&grid.columns)
    );
    for (i, r) in grid.rows.iter().enumerate() {
        let y = top + ch * i as f64;
        let _ = writeln!(
            out,
            r#"<text x="{:.2}" y="{:.2}" text-anchor="end">{}</text>"#,
            left - 8.0,
            y + ch / 2.0 + 4.0,
            escape(&r.label)
        );
        for (j, c) in r.cells.iter().enumerate() {
            let x = left + cw * j as f64;
            let fill = grid
                .categories
                .get(c.category)
                .map_or("#ffffff", |k| color(k.color));
            let _ = writeln!(
                out,
                r#"<rect class="cell" x="{x:.2}" y="{y:.2}" width="{cw}" height="{ch}" fill="{fill}" fill-opacity="0.75" stroke="white"/><text x="{:.2}" y="{:.2}" text-anchor="middle" font-size="10">{}</text>"#,
                x + cw / 2.0,
                y + ch / 2.0 + 3.5,
                escape(&c.label)
            );
        }
    }
    let y0 = top + ch * grid.rows.len() as f64 + 24.0;
    for (k, cat) in grid.categories.iter().enumerate() {
        let y = y0 + 18.0 * k as f64;
        let _ = writeln!(
            out,
            r#"<rect x="{left:.2}" y="{:.2}" width="24" height="12" fill="{}" fill-opacity="0.75"/><text x="{:.2}" y="{:.2}" font-size="11">{}</text>"#,
            y - 10.0,
            color(cat.color),
            left + 30.0,
            y,
            escape(&cat.name)
        );
    }
    out.push_str("</svg>\n");
    out
}
