//! The column loop: force–deformation of one hysteretic element from the start of the time
//! window to the cursor, the previous run's loop underneath; a [`crate::plot::Chart`] of the
//! loops reduced to the plot's pixels (cached), drawn by [`super::line_plot`].

use super::cache::{Cache, Points};
use super::common::{PREVIOUS_MARK, Theme, overlay_run, series_glyph, shown_run};
use super::line_plot::{Head, Look, draw_line_plot, spread_labels};
use super::time::value_axis;
use crate::plot;
use crate::tui::app::App;
use crate::tui::chart;
use crate::tui::eng;
use crate::tui::runs::data::RunData;
use crate::tui::runs::nav;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::Paragraph;

/// Plot geometry of the loop: axis bounds, labels and resolution in dots.
struct Plot {
    xb: [f64; 2],
    yb: [f64; 2],
    /// Axis labels: the extremes of deformation and force.
    xl: Vec<String>,
    yl: Vec<String>,
    /// Width of the force labels.
    label_w: u16,
    res_x: usize,
    res_y: usize,
}

impl Plot {
    fn key(&self) -> [u64; 6] {
        [
            self.res_x as u64,
            self.res_y as u64,
            self.xb[0].to_bits(),
            self.xb[1].to_bits(),
            self.yb[0].to_bits(),
            self.yb[1].to_bits(),
        ]
    }
}

/// Draws the force–deformation chart of the selected element up to the cursor, its readout
/// (on the lower border) at `rt`.
pub(super) fn draw_loop(
    frame: &mut Frame,
    area: Rect,
    app: &App,
    cache: &mut Cache,
    rt: f64,
    th: &Theme,
) {
    let Some(run) = shown_run(app) else {
        frame.render_widget(th.block(" column "), area);
        return;
    };
    if run.element_names.is_empty() {
        frame.render_widget(
            Paragraph::new("no hysteretic elements in this model").block(th.block(" column ")),
            area,
        );
        return;
    }
    let j = app.element % run.element_names.len();
    let name = &run.element_names[j];
    let prev = overlay_run(app).filter(|p| p.id != run.id).and_then(|p| {
        p.element_names
            .iter()
            .position(|n| n == name)
            .map(|k| (p, k))
    });
    let tc = app.cursor_time();
    let (t0, _) = app.window();
    let title = format!(
        " {name} force–deformation ({}/{}, n: next) ",
        j + 1,
        run.element_names.len()
    );
    let block = th
        .block(th.text(&title))
        .title_bottom(Line::styled(loop_readout(app, run, j, rt), th.cursor()));
    let inner = block.inner(area);
    let units = loop_units(app, run, j);
    let plot = plot(run, j, prev, inner, units.clone(), th);
    let mut key = vec![run.t.len() as u64, t0.to_bits(), tc.to_bits()];
    key.extend(plot.key());
    let cur = cache.memo(format!("{}:loop{j}", run.id), key, || {
        loop_points(run, j, (t0, tc), &plot)
    });
    let prev_pts = prev.map(|(p, k)| {
        let mut key = vec![p.t.len() as u64];
        key.extend(plot.key());
        cache.memo(format!("{}:loop{k}", p.id), key, || {
            loop_points(p, k, (f64::NEG_INFINITY, f64::INFINITY), &plot)
        })
    });
    let (chart, look) = loop_plot(cur, prev_pts, &plot, units, th);
    frame.render_widget(block, area);
    draw_line_plot(frame, inner, &chart, &look, th);
}

/// Element `j`'s (deformation, force) points of `run` over `t0..=t1`, consecutive ones in one
/// pixel of the plot dropped ([`chart::dedup_pixels`]).
fn loop_points(run: &RunData, j: usize, (t0, t1): (f64, f64), plot: &Plot) -> Points {
    let (dx, fx) = (&run.el[j].0, &run.el[j].1);
    let range = chart::window(&run.t, t0, t1);
    let range = range.start..range.end.min(dx.len()).min(fx.len());
    chart::dedup_pixels(
        range.map(|i| (dx[i], fx[i])),
        plot.xb,
        plot.yb,
        plot.res_x,
        plot.res_y,
    )
}

/// The units of element `j`'s deformation and force in the model's units: m and kN (rad and
/// kN·m for a rotation; in, kip, kip·in in kip-in) in a bridge model; a scene file's force
/// unit is its author's (none printed).
fn loop_units(app: &App, run: &RunData, j: usize) -> (String, String) {
    let kn = nav::force_unit(app);
    let len = nav::length_unit(app);
    if run.element_names[j].ends_with(".theta") {
        let dot = if app.ascii { "*" } else { "·" };
        let fu = if kn.is_empty() {
            String::new()
        } else {
            format!("{kn}{dot}{len}")
        };
        ("rad".to_string(), fu)
    } else {
        (len.to_string(), kn.to_string())
    }
}

/// The element's deformation and force at the cursor (` 1.234 mm, 45.67 kN `), "" before its
/// first sample.
fn loop_readout(app: &App, run: &RunData, j: usize, tc: f64) -> String {
    let Some(k) = chart::at_or_before(&run.t, tc) else {
        return String::new();
    };
    let (Some(&d), Some(&f)) = (run.el[j].0.get(k), run.el[j].1.get(k)) else {
        return String::new();
    };
    let (du, fu) = loop_units(app, run, j);
    let e = |v: f64, u: &str| eng::eng(v, u, app.ascii);
    format!(" {}, {} ", e(d, &du), e(f, &fu))
}

/// Bounds over both runs' ranges of element `j` (`k` in the previous run) and resolution.
fn plot(
    run: &RunData,
    j: usize,
    prev: Option<(&RunData, usize)>,
    inner: Rect,
    (du, fu): (String, String),
    th: &Theme,
) -> Plot {
    let mut r = run.el_range[j];
    if let Some((p, k)) = prev {
        let q = p.el_range[k];
        r = [
            r[0].min(q[0]),
            r[1].max(q[1]),
            r[2].min(q[2]),
            r[3].max(q[3]),
        ];
    }
    let ext = |a: f64, b: f64| (a <= b).then_some([a, b]);
    // the force labels in at most a third of the width, the two deformation labels in the
    // plot's width beside them
    let third = inner.width as usize / 3;
    let (yb, yl) = value_axis(ext(r[2], r[3]), &fu, third, th.ascii);
    let label_w = (yl.iter().map(|l| l.chars().count()).max())
        .unwrap_or(0)
        .max(1) as u16;
    let cw = inner.width.saturating_sub(label_w + 1) as usize;
    let (xb, xl) = value_axis(ext(r[0], r[1]), &du, cw.saturating_sub(1) / 2, th.ascii);
    let rows = inner.height.saturating_sub(2) as usize;
    Plot {
        xb,
        yb,
        xl,
        yl,
        label_w,
        res_x: cw * th.per_cell(),
        res_y: rows * if th.ascii { 1 } else { 4 },
    }
}

/// The chart of the loop: the previous run's loop, the current one and its point at the
/// cursor (its last), on axes of the plot's ranges; the look: no header (the block names the
/// element), the labels in the model's units, the styles and marks of the time charts'.
fn loop_plot(
    cur: Points,
    prev: Option<Points>,
    plot: &Plot,
    (du, fu): (String, String),
    th: &Theme,
) -> (plot::Chart, Look) {
    let x = plot::Axis::linear("deformation", &du).with_range(plot.xb[0], plot.xb[1]);
    let y = plot::Axis::linear("force", &fu).with_range(plot.yb[0], plot.yb[1]);
    let mut chart = plot::Chart::new("force–deformation", x, y);
    let mut styles = Vec::new();
    if let Some(p) = prev {
        chart
            .series
            .push(plot::Series::line("previous run", p).glyph(PREVIOUS_MARK));
        styles.push(th.previous());
    }
    let here = cur.last().copied();
    let line = plot::Series::line("this run", cur).glyph(series_glyph(0));
    chart.series.push(line.color(2));
    styles.push(th.series(2));
    if let Some(h) = here {
        let glyph = if th.ascii { '@' } else { '█' };
        chart
            .series
            .push(plot::Series::points("at the cursor", vec![h]).glyph(glyph));
        styles.push(th.cursor());
    }
    let look = Look {
        legend: false,
        head: Head::None,
        label_w: plot.label_w,
        y_labels: spread_labels(plot.yb, &plot.yl, |v| v),
        x_labels: plot.xl.clone(),
        styles,
        glyph_lines: true,
        ..Look::default()
    };
    (chart, look)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_loop_is_a_plot_chart_of_the_elements_deformation_and_force() {
        let mut r = RunData::new(1, "#1".into(), vec![], vec![], vec!["c.x".into()], 1.0);
        r.t = vec![0.0, 0.25, 0.5, 0.75, 1.0];
        r.el[0] = (
            vec![0.0, 1e-3, 2e-3, 1e-3, -1e-3],
            vec![0.0, 5.0, 6.0, 1.0, -4.0],
        );
        r.el_range[0] = [-1e-3, 2e-3, -4.0, 6.0];
        let th = Theme {
            color: true,
            ascii: false,
        };
        let units = || ("m".to_string(), "N".to_string());
        let p = plot(&r, 0, None, Rect::new(0, 0, 60, 20), units(), &th);
        // up to the cursor at 0.5 s: the first three samples, none in one pixel
        let cur = loop_points(&r, 0, (0.0, 0.5), &p);
        let (c, look) = loop_plot(cur, None, &p, units(), &th);
        let want: Vec<(f64, f64)> = (0..3).map(|i| (r.el[0].0[i], r.el[0].1[i])).collect();
        assert_eq!(c.series.len(), 2);
        assert_eq!(c.series[0].points, want);
        // the point at the cursor, on axes of both runs' ranges
        assert_eq!(c.series[1].points, vec![want[2]]);
        assert_eq!(c.series[1].marker, plot::Marker::Circle);
        assert_eq!(c.x.range, Some((-1e-3, 2e-3)));
        assert_eq!(c.y.range, Some((-4.0, 6.0)));
        assert_eq!(look.styles, vec![th.series(2), th.cursor()]);
        assert!(matches!(look.head, Head::None));
    }
}
