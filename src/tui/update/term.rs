//! Keys of any terminal: Esc told apart from a key sent right after it, Ctrl-Z, the help's
//! scroll keys.

use crate::tui::app::{App, StatusKind};
use crate::tui::help;
use crate::tui::keymap::Action;
use crate::tui::msg::Effect;
use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};

/// Esc and the key typed right after it, when they came as one key with Alt.
///
/// crossterm tells a lone Esc from the start of an escape sequence by the read it arrives in:
/// an Esc that ends a read is a key, one followed by more bytes in the same read starts a
/// sequence, and Esc followed by a plain key (`ESC q`, as sent over SSH when both are typed
/// quickly) is reported as Alt+`q`. No binding takes Alt, so such a key is taken as what was
/// typed: Esc, then the key.
pub(super) fn split_alt(ev: KeyEvent) -> Option<(KeyEvent, KeyEvent)> {
    if !ev.modifiers.contains(KeyModifiers::ALT) {
        return None;
    }
    let mut key = ev;
    key.modifiers.remove(KeyModifiers::ALT);
    let esc = KeyEvent::new_with_kind(KeyCode::Esc, KeyModifiers::NONE, ev.kind);
    Some((esc, key))
}

/// Ctrl-Z: suspend (the runtime gives the terminal back and stops the process), on Unix.
pub(super) fn suspend(app: &mut App) -> Vec<Effect> {
    if cfg!(unix) {
        vec![Effect::Suspend]
    } else {
        app.set_status(StatusKind::Info, "Ctrl-Z: suspending needs a Unix shell");
        Vec::new()
    }
}

/// The help's scroll keys: a line, a page, the top, the end.
pub(super) fn scroll_help(app: &mut App, a: Action) {
    if app.mode == crate::tui::app::Mode::Messages {
        return scroll_log(app, a);
    }
    if let crate::tui::app::Mode::RunInfo(info) = &app.mode {
        let total = crate::tui::runs::info::lines(info, info_width(app.size)).len();
        let rows = info_rows(app.size);
        let page = rows.saturating_sub(1).max(1);
        app.info_scroll = scrolled(app.info_scroll, a, page, total.saturating_sub(rows));
        return;
    }
    let max = help::max_scroll(app.view_ctx(), app.size.1);
    let page = help::rows(app.size.1).saturating_sub(1).max(1);
    app.help_scroll = scrolled(app.help_scroll, a, page, max);
}

/// A scroll position moved by a help key (a line, a page, the top, the end), within 0..=max.
fn scrolled(at: usize, a: Action, page: usize, max: usize) -> usize {
    let s = at.min(max);
    match a {
        Action::HelpDown => s + 1,
        Action::HelpUp => s.saturating_sub(1),
        Action::HelpPageDown => s + page,
        Action::HelpPageUp => s.saturating_sub(page),
        Action::HelpTop => 0,
        _ => max,
    }
    .min(max)
}

/// The run info's width and rows inside its frame at the app's size (the frame is the whole
/// screen but the status and hint lines).
pub fn info_width(size: (u16, u16)) -> usize {
    size.0.saturating_sub(2).max(10) as usize
}

pub fn info_rows(size: (u16, u16)) -> usize {
    size.1.saturating_sub(5).max(1) as usize
}

/// The message log's rows at the app's size (the frame's inside).
pub fn log_rows(size: (u16, u16)) -> usize {
    size.1.saturating_sub(2).max(1) as usize
}

/// Scrolls the message log (the same keys as the help's).
fn scroll_log(app: &mut App, a: Action) {
    let width = app.size.0.saturating_sub(2) as usize;
    let total = crate::tui::messages::lines(&app.messages, width).len();
    let rows = log_rows(app.size);
    let max = crate::tui::messages::max_scroll(total, rows);
    let page = rows.saturating_sub(1).max(1);
    app.log_scroll = scrolled(app.log_scroll, a, page, max);
}
