//! The right-hand panels of the charts view (plan view, column loop, the comparison of runs).

use super::cache::Cache;
use super::common::{Theme, shown_run};
use super::compare::draw_compare;
use super::loop_chart::draw_loop;
use super::plan::draw_plan;
use crate::tui::app::App;
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};

/// Draws the plan view (at `rt`), the column loop (if any; its readout at `rt`) and the
/// comparison (if it fits).
pub(super) fn draw_side_panel(
    frame: &mut Frame,
    area: Rect,
    app: &App,
    cache: &mut Cache,
    rt: f64,
    th: &Theme,
) {
    let has_loop = shown_run(app).is_some_and(|r| !r.element_names.is_empty());
    if !has_loop {
        // no hysteretic elements: plan view and the comparison
        let sum_h = 9.min(area.height / 2);
        let [plan, sum] =
            Layout::vertical([Constraint::Min(0), Constraint::Length(sum_h)]).areas(area);
        draw_plan(frame, plan, app, rt, th);
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
    draw_plan(frame, plan, app, rt, th);
    draw_loop(frame, lp, app, cache, rt, th);
    if with_summary {
        draw_summary(frame, sum, app, th);
    }
}

/// Draws the comparison of the runs (the baseline, the shown run, those selected).
pub(super) fn draw_summary(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    draw_compare(frame, area, app, th);
}
