//! View actions: switch view, markers, overlay; time cursor, zoom, charted element.

use crate::tui::app::{App, StatusKind, View};
use crate::tui::keymap::Action;

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
            let m = if app.ascii { "ASCII (dots)" } else { "Braille" };
            app.set_status(StatusKind::Info, format!("chart markers: {m}"));
        }
        Action::ToggleOverlay => {
            app.overlay = !app.overlay;
            app.generation += 1;
            let m = if app.overlay { "shown" } else { "hidden" };
            app.set_status(StatusKind::Info, format!("overlaid runs {m}"));
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
    pan_to_cursor(app);
}

fn cursor_end(app: &mut App) {
    app.follow = true;
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
