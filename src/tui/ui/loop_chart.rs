//! The column loop: force–deformation of one hysteretic element from the start of the time
//! window to the cursor, the previous run's loop underneath.

use super::cache::{Cache, Points};
use super::common::{Theme, overlay_run, shown_run};
use crate::tui::app::App;
use crate::tui::chart::{self, bounds, fmt_num};
use crate::tui::run_data::RunData;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::text::Line;
use ratatui::widgets::{Axis, Chart, Dataset, GraphType, Paragraph};

/// Plot geometry of the loop: axis bounds and resolution in dots.
struct Plot {
    xb: [f64; 2],
    yb: [f64; 2],
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

/// Draws the force–deformation chart of the selected element.
pub(super) fn draw_loop(frame: &mut Frame, area: Rect, app: &App, cache: &mut Cache, th: &Theme) {
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
    let inner = th.block("").inner(area);
    let plot = plot(run, j, prev, inner, th);
    // the force unit on the y labels when it fits whole there, else in the title
    let (labels, unit_in_labels) = y_labels(&plot, force_unit(app), inner.width / 3);
    let unit = if unit_in_labels { "" } else { force_unit(app) };
    let block = th.block(loop_title(
        name,
        j,
        run.element_names.len(),
        unit,
        area.width,
        th,
    ));
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
    let chart = with_axes(Chart::new(ds).block(block), &plot, labels, th);
    frame.render_widget(chart, area);
}

/// Force unit of the y labels: kN for bridge models (a `deck` body).
fn force_unit(app: &App) -> &'static str {
    if app
        .scene
        .as_ref()
        .is_some_and(|s| s.bodies.iter().any(|b| b.name == "deck"))
    {
        " kN"
    } else {
        ""
    }
}

/// The title that fits in `width` columns: the longest of the element's name with
/// `force–deformation`, its number and the key, down to the name alone (never cut).
fn loop_title(name: &str, j: usize, n: usize, unit: &str, width: u16, th: &Theme) -> String {
    let unit = if unit.is_empty() {
        String::new()
    } else {
        format!(" [{}]", unit.trim())
    };
    let long = [
        format!(" {name} force–deformation{unit} ({}/{n}, n: next) ", j + 1),
        format!(" {name} force–def.{unit} ({}/{n}) ", j + 1),
        format!(" {name}{unit} ({}/{n}) ", j + 1),
        format!(" {name}{unit} "),
    ];
    let room = width.saturating_sub(2) as usize;
    long.into_iter()
        .map(|t| th.text(&t))
        .find(|t| t.chars().count() <= room)
        .unwrap_or_default()
}

/// The y labels (lower, upper) in at most `budget` columns (ratatui gives the y labels a
/// third of the chart's width) and whether they carry the unit: the number with its unit
/// when both fit whole, else the number alone (the unit then goes in the title).
fn y_labels(plot: &Plot, unit: &str, budget: u16) -> ([String; 2], bool) {
    let budget = budget as usize;
    let nums = |w: usize| plot.yb.map(|v| fmt_num(v, w));
    let fits = |l: &[String; 2], extra: usize| l.iter().all(|s| s.len() + extra <= budget);
    if !unit.is_empty() {
        let with = nums(budget.saturating_sub(unit.len()).min(7));
        if fits(&with, unit.len()) {
            return (with.map(|s| format!("{s}{unit}")), true);
        }
    }
    (nums(budget.clamp(1, 7)), unit.is_empty())
}

/// Deformation and force axes with their end labels.
fn with_axes<'a>(chart: Chart<'a>, plot: &Plot, y: [String; 2], th: &Theme) -> Chart<'a> {
    let [y0, y1] = y;
    chart
        .x_axis(
            Axis::default()
                .bounds(plot.xb)
                .labels(vec![
                    Line::from(fmt_num(plot.xb[0], 7)),
                    Line::from(fmt_num(plot.xb[1], 7)),
                ])
                .style(th.dim()),
        )
        .y_axis(
            Axis::default()
                .bounds(plot.yb)
                .labels(vec![Line::from(y0), Line::from(y1)])
                .style(th.dim()),
        )
        .legend_position(None)
}

/// Bounds over both runs' ranges of element `j` (`k` in the previous run) and resolution.
fn plot(run: &RunData, j: usize, prev: Option<(&RunData, usize)>, inner: Rect, th: &Theme) -> Plot {
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
    Plot {
        xb: bounds(&[r[0], r[1]]),
        yb: bounds(&[r[2], r[3]]),
        res_x: inner.width as usize * th.per_cell(),
        res_y: inner.height as usize * if th.marks() { 1 } else { 4 },
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
