//! An x–y plot of a few points per series (the studies' figures): the y title and a legend
//! on top, y labels on the left, the x labels and title underneath; each series joined by a
//! line (Braille, or `.` in ASCII mode) and its points marked by its own character, so that
//! series differ without colour.

use super::common::Theme;
use crate::tui::chart::{fmt_num, fmt_sig};
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;
use ratatui::widgets::canvas::{Canvas, Context, Line as CLine};

/// Width of the y labels.
const LABEL_W: u16 = 9;

/// One series: its legend text, the character marking its points, its colour, its points
/// (joined in order).
pub(super) struct Series {
    pub name: String,
    pub mark: char,
    pub style: Style,
    pub points: Vec<(f64, f64)>,
}

pub(super) struct Plot {
    /// The y axis: what and unit, `peak |θ| [rad]`.
    pub y_title: String,
    pub x_title: String,
    pub series: Vec<Series>,
    pub xb: [f64; 2],
    pub yb: [f64; 2],
    /// The x of the study's cursor: a dim vertical line.
    pub cursor: Option<f64>,
}

/// The legend lines (at most `lines`): the y title, then `mark name` per series; series that
/// do not fit are left out whole and counted (`+2 more`).
fn legend(plot: &Plot, width: usize, lines: usize, th: &Theme) -> Vec<Line<'static>> {
    let mut out: Vec<(Vec<Span<'static>>, usize)> = vec![(
        vec![Span::styled(plot.y_title.clone(), th.bold())],
        plot.y_title.chars().count(),
    )];
    let mut left = 0;
    for s in &plot.series {
        let w = 2 + 2 + s.name.chars().count();
        let last = out.last_mut().expect("a first line");
        if last.1 + w <= width {
            last.0.push(Span::raw("  "));
            last.0
                .push(Span::styled(s.mark.to_string(), s.style.patch(th.bold())));
            last.0.push(Span::raw(format!(" {}", s.name)));
            last.1 += w;
        } else if out.len() < lines && w - 2 <= width {
            out.push((
                vec![
                    Span::styled(s.mark.to_string(), s.style.patch(th.bold())),
                    Span::raw(format!(" {}", s.name)),
                ],
                w - 2,
            ));
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

/// Draws the plot in `area` (nothing below 4 rows or 20 columns).
pub(super) fn draw_plot(frame: &mut Frame, area: Rect, plot: &Plot, th: &Theme) {
    if area.height < 4 || area.width < LABEL_W + 11 {
        return;
    }
    let head = legend(
        plot,
        area.width as usize,
        if area.height >= 8 { 2 } else { 1 },
        th,
    );
    let hh = head.len() as u16;
    frame.render_widget(Paragraph::new(head), Rect { height: hh, ..area });
    let rows = area.height - hh - 2;
    if rows < 2 {
        return;
    }
    let top = area.y + hh;
    let cw = area.width - LABEL_W - 1;
    let canvas = Rect::new(area.x + LABEL_W + 1, top, cw, rows);
    // y labels and the axis
    let (vbar, corner, hbar) = if th.ascii {
        ("|", "+", "-")
    } else {
        ("│", "└", "─")
    };
    let mut labels: Vec<Line> = (0..rows)
        .map(|_| Line::styled(format!("{:>w$}{vbar}", "", w = LABEL_W as usize), th.dim()))
        .collect();
    let lab = |v: f64| format!("{:>w$}{vbar}", short(v), w = LABEL_W as usize);
    labels[0] = Line::styled(lab(plot.yb[1]), th.dim());
    labels[rows as usize - 1] = Line::styled(lab(plot.yb[0]), th.dim());
    if rows >= 5 {
        let mid = 0.5 * (plot.yb[0] + plot.yb[1]);
        labels[(rows as usize - 1) / 2] = Line::styled(lab(mid), th.dim());
    }
    labels.push(Line::styled(
        format!(
            "{:>w$}{corner}{}",
            "",
            hbar.repeat(cw as usize),
            w = LABEL_W as usize
        ),
        th.dim(),
    ));
    labels.push(x_labels(plot, cw as usize, th));
    frame.render_widget(
        Paragraph::new(labels),
        Rect::new(area.x, top, area.width, rows + 2),
    );
    let marker = th.marker();
    let (w, h) = (cw as f64, rows as f64);
    let c = Canvas::default()
        .marker(marker)
        .x_bounds(plot.xb)
        .y_bounds(plot.yb)
        .paint(|ctx| paint(ctx, plot, (w, h), th));
    frame.render_widget(c, canvas);
}

/// An axis label: 3 significant digits in at most 8 characters.
fn short(v: f64) -> String {
    let s = fmt_sig(v, 3);
    if s.len() <= 8 { s } else { fmt_num(v, 8) }
}

/// The x axis's labels row: its ends and title (the middle dropped first when narrow).
fn x_labels(plot: &Plot, width: usize, th: &Theme) -> Line<'static> {
    let (a, b) = (short(plot.xb[0]), short(plot.xb[1]));
    let t = plot.x_title.clone();
    let (na, nb, nt) = (a.len(), b.len(), t.chars().count());
    let pad = LABEL_W as usize + 1;
    let row = if na + nt + nb + 2 <= width {
        let gap = width - na - nt - nb;
        let l = gap / 2;
        format!("{a}{}{t}{}{b}", " ".repeat(l), " ".repeat(gap - l))
    } else if nt + nb < width {
        format!("{t}{}{b}", " ".repeat(width - nt - nb))
    } else {
        t
    };
    Line::styled(format!("{}{row}", " ".repeat(pad)), th.dim())
}

/// Lines between each series' points, then the marks on top.
fn paint(ctx: &mut Context, plot: &Plot, (w, h): (f64, f64), th: &Theme) {
    let (xs, ys) = (plot.xb[1] - plot.xb[0], plot.yb[1] - plot.yb[0]);
    let finite = |p: &&(f64, f64)| p.0.is_finite() && p.1.is_finite();
    if let Some(x) = plot.cursor.filter(|x| x.is_finite()) {
        if th.ascii {
            for k in 0..(h as usize) {
                let y = plot.yb[0] + ys * k as f64 / (h - 1.0).max(1.0);
                ctx.print(x, y, Span::styled(":", th.dim()));
            }
        } else {
            ctx.draw(&CLine {
                x1: x,
                y1: plot.yb[0],
                x2: x,
                y2: plot.yb[1],
                color: th.dim().fg.unwrap_or(Color::Reset),
            });
        }
        ctx.layer();
    }
    for s in &plot.series {
        let pts: Vec<&(f64, f64)> = s.points.iter().filter(finite).collect();
        for seg in pts.windows(2) {
            let (a, b) = (*seg[0], *seg[1]);
            if th.ascii {
                // a dot in each cell the segment crosses, between its two marks
                let cells = (((b.0 - a.0) / xs * (w - 1.0)).abs())
                    .max(((b.1 - a.1) / ys * (h - 1.0)).abs())
                    .ceil() as usize;
                for k in 1..cells {
                    let f = k as f64 / cells as f64;
                    let (x, y) = (a.0 + f * (b.0 - a.0), a.1 + f * (b.1 - a.1));
                    ctx.print(x, y, Span::styled(".", s.style));
                }
            } else {
                ctx.draw(&CLine {
                    x1: a.0,
                    y1: a.1,
                    x2: b.0,
                    y2: b.1,
                    color: s.style.fg.unwrap_or(Color::Reset),
                });
            }
        }
    }
    for s in &plot.series {
        for p in s.points.iter().filter(finite) {
            let mark = Span::styled(s.mark.to_string(), s.style.patch(th.bold()));
            ctx.print(p.0, p.1, mark);
        }
    }
}
