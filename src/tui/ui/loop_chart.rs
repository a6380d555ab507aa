//! The column loop: force–deformation of one hysteretic element from the start of the time
//! window to the cursor, the previous run's loop underneath.

use super::cache::{Cache, Points};
use super::common::{Theme, overlay_run, shown_run};
use super::time::value_axis;
use crate::tui::app::App;
use crate::tui::chart;
use crate::tui::eng;
use crate::tui::runs::data::RunData;
use crate::tui::runs::nav;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::{Axis, Chart, Dataset, GraphType, Paragraph};

/// Plot geometry of the loop: axis bounds and resolution in dots.
struct Plot {
    xb: [f64; 2],
    yb: [f64; 2],
    /// Axis labels: the extremes of deformation and force.
    xl: Vec<String>,
    yl: Vec<String>,
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
        .block(title)
        .title_bottom(Line::styled(loop_readout(app, run, j, rt), th.cursor()));
    let inner = block.inner(area);
    let plot = plot(run, j, prev, inner, loop_units(app, run, j), th);
    let mut key = vec![run.t.len() as u64, t0.to_bits(), tc.to_bits()];
    key.extend(plot.key());
    let (dx, fx) = (&run.el[j].0, &run.el[j].1);
    let cur = cache.memo(format!("{}:loop{j}", run.id), key, || {
        let range = chart::window(&run.t, t0, tc);
        chart::dedup_pixels(
            range.map(|i| (dx[i], fx[i])),
            plot.xb,
            plot.yb,
            plot.res_x,
            plot.res_y,
        )
    });
    let prev_pts = prev.map(|(p, k)| {
        let mut key = vec![p.t.len() as u64];
        key.extend(plot.key());
        cache.memo(format!("{}:loop{k}", p.id), key, || {
            chart::dedup_pixels(
                p.el[k].0.iter().copied().zip(p.el[k].1.iter().copied()),
                plot.xb,
                plot.yb,
                plot.res_x,
                plot.res_y,
            )
        })
    });
    let here = cur.last().map(|p| [*p]);
    let ds = datasets(&cur, prev_pts.as_ref(), here.as_ref(), th);
    let chart = with_axes(Chart::new(ds).block(block), &plot, th);
    frame.render_widget(chart, area);
    th.own_ascii(frame.buffer_mut(), area);
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

/// Deformation and force axes labelled with the extremes they span.
fn with_axes<'a>(chart: Chart<'a>, plot: &Plot, th: &Theme) -> Chart<'a> {
    let lines = |l: &[String]| l.iter().map(|s| Line::from(s.clone())).collect::<Vec<_>>();
    chart
        .x_axis(
            Axis::default()
                .bounds(plot.xb)
                .labels(lines(&plot.xl))
                .style(th.dim()),
        )
        .y_axis(
            Axis::default()
                .bounds(plot.yb)
                .labels(lines(&plot.yl))
                .style(th.dim()),
        )
        .legend_position(None)
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
    // ratatui gives the y labels (and the first x label) at most a third of the width, and
    // the last x label half of the plot
    let third = inner.width as usize / 3;
    let xw = third.min((inner.width as usize).saturating_sub(third + 1) / 2);
    let (xb, xl) = value_axis(ext(r[0], r[1]), &du, xw, th.ascii);
    let (yb, yl) = value_axis(ext(r[2], r[3]), &fu, third, th.ascii);
    Plot {
        xb,
        yb,
        xl,
        yl,
        res_x: inner.width as usize * th.per_cell(),
        res_y: inner.height as usize * if th.ascii { 1 } else { 4 },
    }
}

/// The previous loop, the current one, the point at the cursor.
fn datasets<'a>(
    cur: &'a Points,
    prev: Option<&'a Points>,
    here: Option<&'a [(f64, f64); 1]>,
    th: &Theme,
) -> Vec<Dataset<'a>> {
    let mut ds = Vec::new();
    if let Some(p) = prev {
        ds.push(
            Dataset::default()
                .marker(th.previous_marker())
                .graph_type(GraphType::Line)
                .style(th.previous())
                .data(p),
        );
    }
    ds.push(
        Dataset::default()
            .marker(th.series_marker(0))
            .graph_type(GraphType::Line)
            .style(th.series(2))
            .data(cur),
    );
    if let Some(h) = here {
        ds.push(
            Dataset::default()
                .marker(th.point_marker())
                .graph_type(GraphType::Scatter)
                .style(th.cursor())
                .data(h),
        );
    }
    ds
}
