//! The right-hand panels of the charts view (plan view, column loop, comparison) and the
//! current-vs-previous table.

use super::cache::Cache;
use super::common::{Theme, shown_run};
use super::loop_chart::draw_loop;
use super::plan::draw_plan;
use crate::tui::app::App;
use crate::tui::chart;
use crate::tui::run_data::RunData;
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::widgets::{Row, Table};

/// Draws the plan view, the column loop (if any) and the comparison (if it fits).
pub(super) fn draw_side_panel(
    frame: &mut Frame,
    area: Rect,
    app: &App,
    cache: &mut Cache,
    th: &Theme,
) {
    let has_loop = shown_run(app).is_some_and(|r| !r.element_names.is_empty());
    if !has_loop {
        // no hysteretic elements: plan view and the comparison
        let sum_h = 9.min(area.height / 2);
        let [plan, sum] =
            Layout::vertical([Constraint::Min(0), Constraint::Length(sum_h)]).areas(area);
        draw_plan(frame, plan, app, th);
        draw_summary(frame, sum, app, th);
        return;
    }
    let with_summary = area.height >= 28;
    let sum_h = if with_summary { 9 } else { 0 };
    let rest = area.height - sum_h;
    let plan_h = (rest * 45 / 100).max(6);
    let [plan, lp, sum] = Layout::vertical([
        Constraint::Length(plan_h),
        Constraint::Min(0),
        Constraint::Length(sum_h),
    ])
    .areas(area);
    draw_plan(frame, plan, app, th);
    draw_loop(frame, lp, app, cache, th);
    if with_summary {
        draw_summary(frame, sum, app, th);
    }
}

/// Rows of the comparison table: label, current run's value, previous run's value.
fn compare_rows(cur: Option<&RunData>, prev: Option<&RunData>) -> Vec<[String; 3]> {
    let rot = cur
        .or(prev)
        .map(|d| {
            if d.rot_name().ends_with(".theta") {
                "θ".to_string()
            } else {
                d.rot_name().to_string()
            }
        })
        .unwrap_or_else(|| "θ".into());
    type Get = fn(&RunData) -> String;
    let rows: [(String, Get); 6] = [
        (format!("peak |{rot}|"), |d| {
            chart::fmt_sig(d.peak_rot().0, 4)
        }),
        ("  at t [s]".into(), |d| chart::fmt_sig(d.peak_rot().1, 4)),
        (format!("residual {rot}"), |d| {
            chart::fmt_sig(d.residual_rot(), 4)
        }),
        ("impacts".into(), |d| d.total_impacts().to_string()),
        ("stick [s]".into(), |d| {
            chart::fmt_sig(d.total_stick_time(), 4)
        }),
        ("min gap [m]".into(), |d| {
            // below a nanometre is closed contact (round-off noise otherwise)
            let g = d.min_gap();
            match g {
                g if !g.is_finite() => "—".into(),
                g if g.abs() < 1e-9 => "0".into(),
                g => chart::fmt_sig(g, 4),
            }
        }),
    ];
    let f = |d: Option<&RunData>, g: Get| d.map_or("—".to_string(), g);
    rows.into_iter()
        .map(|(n, g)| [n, f(cur, g), f(prev, g)])
        .collect()
}

/// Draws the current-vs-previous table.
pub(super) fn draw_summary(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let cur = app.current.as_ref();
    let prev = app.previous.as_ref();
    let rows: Vec<[String; 3]> = (compare_rows(cur, prev).into_iter())
        .map(|r| r.map(|c| th.text(&c)))
        .collect();
    let longest = rows.iter().map(|r| r[0].chars().count()).max().unwrap_or(0) as u16;
    let label_w = longest.clamp(12, (area.width / 3).max(12));
    let value_w = (area.width.saturating_sub(2 + label_w + 2) / 2).clamp(4, 12);
    let header = Row::new(vec![
        String::new(),
        cur.map_or("current".into(), |r| format!("run {}", r.id)),
        prev.map_or("previous".into(), |r| format!("run {}", r.id)),
    ])
    .style(th.bold());
    let table = Table::new(
        rows.into_iter().map(|r| Row::new(r.to_vec())),
        [
            Constraint::Length(label_w),
            Constraint::Length(value_w),
            Constraint::Length(value_w),
        ],
    )
    .header(header)
    .block(th.block(" current vs previous "));
    frame.render_widget(table, area);
}
