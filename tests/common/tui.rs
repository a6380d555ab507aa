//! What the workbench's tests share: the model files, the short bridge they run, keys and
//! actions, one frame drawn on ratatui's TestBackend and read back, the snapshots' settings.

use super::root;
use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use deckspin::tui::keymap::Action;
use deckspin::tui::runs::data::{RunData, RunStatus};
use deckspin::tui::{self, App, Effect, Msg, form, update};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use std::path::{Path, PathBuf};

pub fn bridge_path() -> PathBuf {
    root().join("models/four-span.toml")
}

pub fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Sets a value in model text the way the form does (a number as a float, else a string).
pub fn set(text: &str, path: &str, value: &str) -> String {
    let kind = if value.parse::<f64>().is_ok() {
        form::Kind::Float
    } else {
        form::Kind::Str
    };
    form::set_value(text, path, kind, value, form::Dim::Plain)
        .unwrap_or_else(|e| panic!("{path}={value}: {e}"))
}

/// The four-span bridge shortened to 2 s with all four gaps `gap` (m).
pub fn short_bridge(gap: &str) -> String {
    let mut t = set(&read(&bridge_path()), "solver.t_end", "2.0");
    for i in 0..4 {
        t = set(&t, &format!("contacts.gaps.{i}"), gap);
    }
    t
}

/// Run `id` of `text` (loaded as if from `path`) to its end.
pub fn run_of(text: &str, path: &Path, id: u64) -> RunData {
    let mut app = App::new_from_text(text, path);
    app.next_run = id;
    let fx = app.start();
    tui::execute_blocking(&mut app, fx);
    let run = app.current.expect("a run");
    assert_eq!(run.status, RunStatus::Finished, "{}", app.status);
    run
}

/// The messages of the run that `fx` starts, computed on this thread to its end.
pub fn messages_of_started_run(fx: Vec<Effect>) -> Vec<Msg> {
    let Some(Effect::StartRun { id, scene }) = fx
        .into_iter()
        .find(|e| matches!(e, Effect::StartRun { .. }))
    else {
        panic!("no run started")
    };
    tui::workers::run::run_blocking(id, &scene)
}

pub fn key(c: char) -> Msg {
    Msg::Key(KeyEvent::new(KeyCode::Char(c), KeyModifiers::NONE))
}

pub fn code(c: KeyCode) -> Msg {
    Msg::Key(KeyEvent::new(c, KeyModifiers::NONE))
}

pub fn act(app: &mut App, a: Action) -> Vec<Effect> {
    update(app, Msg::Action(a))
}

/// One frame of `app` at `w`×`h` (a fresh drawing cache).
pub fn render(app: &mut App, w: u16, h: u16) -> Terminal<TestBackend> {
    update(app, Msg::Resize(w, h));
    let mut t = Terminal::new(TestBackend::new(w, h)).unwrap();
    let mut cache = tui::ui::Cache::default();
    t.draw(|f| tui::ui::draw(f, app, &mut cache)).unwrap();
    t
}

/// The screen's lines.
pub fn lines(t: &Terminal<TestBackend>) -> Vec<String> {
    let b = t.backend().buffer();
    (0..b.area.height)
        .map(|y| (0..b.area.width).map(|x| b[(x, y)].symbol()).collect())
        .collect()
}

/// The screen as text, a newline after each line.
pub fn screen(t: &Terminal<TestBackend>) -> String {
    lines(t).iter().map(|l| format!("{l}\n")).collect()
}

/// Snapshots in tests/snapshots, named without the test file's name.
pub fn snapshot_settings() -> insta::Settings {
    let mut s = insta::Settings::clone_current();
    s.set_snapshot_path(root().join("tests/snapshots"));
    s.set_prepend_module_to_snapshot(false);
    s
}
