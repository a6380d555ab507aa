//! Drawing: `draw(frame, app, cache)` renders the whole screen from the state, one file per
//! panel. Charts are decimated per screen column before their series are built, and the
//! decimated series and event strips are cached ([`Cache`]) per run length, time window and
//! plot size, so a frame stays light with 10⁵-sample histories.

mod adequacy;
mod ascii;
mod cache;
mod chart_head;
mod chart_pick;
mod common;
mod compare;
mod event_list;
mod form;
mod header;
mod line_plot;
mod loop_chart;
mod messages;
mod plan;
mod precision;
mod results;
mod results_model;
mod run_info;
mod runs;
mod screen_map;
mod side;
mod status;
mod studies;
mod study_numbers;
mod time;
mod timeline;
mod tornado;

pub use ascii::{ascii_only, ascii_symbol};
pub use cache::{Cache, READOUT_PERIOD};
pub use event_list::scroll;
pub use timeline::{
    Cell, event_strip, key_failure_mark, key_strip, priority, row_names, strip_cells,
};

use crate::tui::app::{App, MIN_HEIGHT, MIN_WIDTH, Mode, View};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};

/// Renders the workbench (in ASCII mode, nothing above 0x7E: [`ascii_only`] last, a safety
/// net for what the panels did not draw in ASCII themselves).
pub fn draw(frame: &mut Frame, app: &App, cache: &mut Cache) {
    draw_screen(frame, app, cache);
    if common::theme(app).ascii {
        ascii_only(frame.buffer_mut());
    }
}

/// Renders every panel and overlay as they draw themselves, without the last ASCII pass (in
/// ASCII mode every panel draws in ASCII alone: the tests check it with this).
pub fn draw_screen(frame: &mut Frame, app: &App, cache: &mut Cache) {
    let area = frame.area();
    let th = common::theme(app);
    if area.width < MIN_WIDTH || area.height < MIN_HEIGHT {
        status::draw_too_small(frame, area, &th);
        return;
    }
    let status_h = status::status_height(app, area.width, area.height, &th);
    let [header, mut body, status, hints] = Layout::vertical([
        Constraint::Length(1),
        Constraint::Min(0),
        Constraint::Length(status_h),
        Constraint::Length(1),
    ])
    .areas(area);
    header::draw_header(frame, header, app, &th);
    if let Some(le) = &app.load_error {
        let h = if body.height >= 18 { 5 } else { 4 };
        let [banner, rest] =
            Layout::vertical([Constraint::Length(h), Constraint::Min(0)]).areas(body);
        header::draw_error(frame, banner, le, &th);
        body = rest;
    }
    match app.view {
        View::Charts => draw_charts(frame, body, app, cache, &th),
        View::Form => form::draw_form(frame, body, app, &th),
        View::Studies => studies::draw_studies(frame, body, app, &th),
        View::Runs => runs::draw_runs(frame, body, app, &th),
    }
    status::draw_status(frame, status, app, &th);
    status::draw_hints(frame, hints, app, &th);
    match &app.mode {
        Mode::Help => status::draw_help(frame, area, app, &th),
        Mode::Messages => messages::draw_messages(frame, area, app, &th),
        Mode::Pick { files, selected } => studies::draw_picker(
            frame,
            area,
            " reopen a study — newest first ",
            files,
            *selected,
            &th,
        ),
        Mode::OpenModel { files, selected } => {
            form::draw_model_picker(frame, area, app, files, *selected, &th)
        }
        Mode::Confirm(c) => status::draw_confirm(frame, area, app, c, &th),
        Mode::ChartPick {
            chart,
            query,
            selected,
        } => chart_pick::draw_chart_picker(frame, body, app, (*chart, query, *selected), &th),
        Mode::RunInfo(info) => run_info::draw_run_info(frame, body, app, info, &th),
        _ => {}
    }
}

/// The charts view: time charts and event strip on the left, side panels on the right.
fn draw_charts(frame: &mut Frame, area: Rect, app: &App, cache: &mut Cache, th: &common::Theme) {
    let mut right_w = if area.width >= 100 {
        (area.width * 36 / 100).clamp(30, 60)
    } else {
        (area.width * 35 / 100).max(24)
    };
    if app.events_open {
        // time, a contact's name and the kind in a row; the charts keep room for their labels
        let charts_min = 3 * common::LABEL_W;
        right_w = right_w.max(36).min(area.width.saturating_sub(charts_min));
    }
    let [left, right] =
        Layout::horizontal([Constraint::Min(0), Constraint::Length(right_w)]).areas(area);
    let rt = readout_time(app, cache);
    time::draw_time_panel(frame, left, app, cache, rt, th);
    if app.events_open {
        event_list::draw_event_list(frame, right, app, th);
    } else {
        side::draw_side_panel(frame, right, app, cache, rt, th);
    }
}

/// The time of the readouts at the cursor ([`Cache::readout_time`]): held between refreshes
/// while the shown run is running and the cursor follows its end.
fn readout_time(app: &App, cache: &mut Cache) -> f64 {
    let tc = app.cursor_time();
    match common::shown_run(app) {
        Some(r) => cache.readout_time(r.token, tc, app.follow && r.running()),
        None => tc,
    }
}
