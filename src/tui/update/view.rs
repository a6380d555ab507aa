//! View actions: switch view, markers, overlay; time cursor, zoom, charted element; the jumps
//! from event to event and the event list.

use crate::tui::app::{App, StatusKind, View};
use crate::tui::keymap::Action;
use crate::tui::runs::data::RunData;
use crate::tui::runs::nav;

/// `Tab`, `S-Tab`, `m`, `o`.
pub(super) fn toggle(app: &mut App, a: Action) {
    match a {
        Action::SwitchView => {
            app.view = match app.view {
                View::Charts | View::Runs => View::Form,
                View::Form => View::Studies,
                View::Studies => View::Charts,
            };
        }
        Action::SwitchViewBack => {
            app.view = match app.view {
                View::Charts | View::Runs => View::Studies,
                View::Form => View::Charts,
                View::Studies => View::Form,
            };
        }
        Action::ToggleMarker => {
            app.ascii = !app.ascii;
            app.generation += 1;
            let m = if app.ascii {
                "ASCII (nothing above 0x7E)"
            } else {
                "Unicode (Braille, box drawing)"
            };
            app.set_status(StatusKind::Info, format!("drawing: {m}"));
        }
        Action::ToggleOverlay => {
            app.overlay = !app.overlay;
            app.generation += 1;
            let m = if app.overlay { "shown" } else { "hidden" };
            app.say_overlay(StatusKind::Info, format!("overlaid runs {m}"));
        }
        _ => {}
    }
}

/// Cursor, zoom and element keys of the charts view.
pub(super) fn chart_action(app: &mut App, a: Action) {
    use Action as A;
    match a {
        A::CursorLeft => move_cursor(app, -0.01),
        A::CursorRight => move_cursor(app, 0.01),
        A::CursorLeftFast => move_cursor(app, -0.1),
        A::CursorRightFast => move_cursor(app, 0.1),
        A::CursorHome => {
            app.follow = false;
            app.cursor = 0.0;
            app.event_sel = None;
            pan_to_cursor(app);
        }
        A::CursorEnd => cursor_end(app),
        A::ZoomIn => zoom(app, 0.5),
        A::ZoomOut => zoom(app, 2.0),
        A::ZoomReset => app.zoom = None,
        A::NextElement => cycle_element(app, true),
        A::PrevElement => cycle_element(app, false),
        _ => {}
    }
}

fn move_cursor(app: &mut App, frac: f64) {
    let (a, b) = app.window();
    let now = app.cursor_time();
    app.follow = false;
    app.cursor = (now + frac * (b - a)).clamp(0.0, app.t_end());
    app.event_sel = None;
    pan_to_cursor(app);
}

fn cursor_end(app: &mut App) {
    app.follow = true;
    app.event_sel = None;
    if let Some((a, b)) = app.zoom {
        let end = app.t_end();
        app.zoom = Some((end - (b - a), end));
    }
}

fn pan_to_cursor(app: &mut App) {
    if let Some((a, b)) = app.zoom {
        let w = b - a;
        let c = app.cursor;
        if c < a {
            app.zoom = Some((c, c + w));
        } else if c > b {
            app.zoom = Some((c - w, c));
        }
    }
}

fn zoom(app: &mut App, factor: f64) {
    let end = app.t_end();
    let (a, b) = app.window();
    let w = ((b - a) * factor).max(end * 1e-4);
    if w >= end {
        app.zoom = None;
        return;
    }
    let c = app.cursor_time().clamp(a, b);
    let frac = if b > a { (c - a) / (b - a) } else { 0.5 };
    let mut lo = c - frac * w;
    lo = lo.clamp(0.0, end - w);
    app.zoom = Some((lo, lo + w));
}

/// `n`/`N`: the next or previous hysteretic element in the loop chart.
fn cycle_element(app: &mut App, next: bool) {
    let n = app.current.as_ref().map_or(0, |r| r.element_names.len());
    if n == 0 {
        app.set_status(StatusKind::Info, "this model has no hysteretic elements");
        return;
    }
    app.element = if next {
        (app.element + 1) % n
    } else {
        (app.element + n - 1) % n
    };
    let name = app
        .current
        .as_ref()
        .map(|r| r.element_names[app.element].clone());
    app.set_status(
        StatusKind::Info,
        format!("column element: {}", name.unwrap_or_default()),
    );
}

/// A new run starts; `cursor` is where the cursor was. Without a zoom the cursor follows the
/// new run; with one, the window stays and the cursor stays in it (where it was, or at the
/// window's nearer edge), showing the same instant of the new run.
pub(super) fn keep_cursor_on_rerun(app: &mut App, cursor: f64) {
    match app.zoom {
        None => app.follow = true,
        Some((a, b)) => {
            app.follow = false;
            app.cursor = cursor.clamp(a, b);
        }
    }
}

/// The run whose events the cursor steps through: the one the charts are drawn from.
fn event_run(app: &App) -> Option<&RunData> {
    app.current.as_ref()
}

/// `]`, `[`, `E` and the event list's keys.
pub(super) fn event_action(app: &mut App, a: Action) {
    use Action as A;
    match a {
        A::NextEvent => jump(app, true),
        A::PrevEvent => jump(app, false),
        A::ToggleEvents => {
            app.events_open = !app.events_open;
            app.event_sel = None;
            let m = if app.events_open {
                "event list open: ↑↓ select, Enter moves the cursor there, E closes"
            } else {
                "event list closed"
            };
            app.set_status(StatusKind::Info, m);
        }
        A::EventUp => select(app, -1),
        A::EventDown => select(app, 1),
        A::EventPageUp => select(app, -10),
        A::EventPageDown => select(app, 10),
        A::EventGo => go_to_selected(app),
        _ => {}
    }
}

/// `]`/`[`: the cursor to the next / previous instant with events, the window moved to show
/// it; the status line says what happened there.
fn jump(app: &mut App, forward: bool) {
    let tc = app.cursor_time();
    let kn = nav::force_unit(app);
    let ascii = app.ascii;
    let Some(run) = event_run(app) else {
        app.set_status(StatusKind::Info, "no run yet: r runs the model");
        return;
    };
    let t = if forward {
        nav::next_time(run, tc)
    } else {
        nav::prev_time(run, tc)
    };
    let Some(t) = t else {
        let m = if forward {
            "no event after the cursor"
        } else {
            "no event before the cursor"
        };
        app.set_status(StatusKind::Info, m);
        return;
    };
    let status = nav::jump_status(run, t, kn, ascii);
    let row = nav::first_row_at(&nav::in_time_order(run), run, t);
    set_cursor(app, t);
    app.event_sel = row;
    app.set_status(StatusKind::Info, status);
}

/// The cursor at `t`, not following; a window that does not hold it is centred on it.
fn set_cursor(app: &mut App, t: f64) {
    app.follow = false;
    app.cursor = t;
    if let Some((a, b)) = app.zoom
        && (t < a || t > b)
    {
        let w = b - a;
        let lo = (t - 0.5 * w).clamp(0.0, (app.t_end() - w).max(0.0));
        app.zoom = Some((lo, lo + w));
    }
}

/// Moves the event list's selection by `by` rows (from the row at the cursor).
fn select(app: &mut App, by: i64) {
    let tc = app.cursor_time();
    let Some(run) = event_run(app) else {
        return;
    };
    let n = run.events.len();
    if n == 0 {
        app.set_status(StatusKind::Info, "no events in this run");
        return;
    }
    let order = nav::in_time_order(run);
    let now = app
        .event_sel
        .or_else(|| nav::row_at(&order, run, tc))
        .map_or(-1, |i| i as i64);
    app.event_sel = Some((now + by).clamp(0, n as i64 - 1) as usize);
}

/// `Enter` in the event list: the cursor to the selected event.
fn go_to_selected(app: &mut App) {
    let tc = app.cursor_time();
    let kn = nav::force_unit(app);
    let ascii = app.ascii;
    let Some(run) = event_run(app) else {
        return;
    };
    let order = nav::in_time_order(run);
    let Some(row) = app.event_sel.or_else(|| nav::row_at(&order, run, tc)) else {
        app.set_status(StatusKind::Info, "no event selected");
        return;
    };
    let Some(&i) = order.get(row) else {
        return;
    };
    let t = run.events[i].t;
    let status = nav::jump_status(run, t, kn, ascii);
    set_cursor(app, t);
    app.event_sel = Some(row);
    app.set_status(StatusKind::Info, status);
}
