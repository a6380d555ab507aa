//! The update function: `update(app, msg)` changes the state and returns effects (start or
//! cancel a run, save, export, quit) for [`super::effects::perform`]; nothing here touches the
//! terminal, threads or (except for validating model text) the file system.

mod charts;
mod design;
mod edit;
mod file;
mod find;
mod info;
mod open;
mod reconcile;
mod results;
mod run;
mod runs;
mod stored;
mod study;
mod term;
mod view;

use crate::tui::app::{App, Confirm, Mode, StatusKind};
use crate::tui::keymap::{self, Action};
use crate::tui::msg::{Effect, Msg};
use crossterm::event::{KeyCode, KeyEvent, KeyEventKind, KeyModifiers};
use std::path::PathBuf;

/// The index of the entry shown in the studies view's list (the studies, then the results
/// pages).
pub fn list_index(app: &App) -> usize {
    results::index(app)
}

/// Handles one message (and asks for the series of kept runs it made needed); then a status
/// message whose state has changed goes (it stays in the log `M`).
pub fn update(app: &mut App, msg: Msg) -> Vec<Effect> {
    let mut fx = on_msg(app, msg);
    fx.extend(stored::want_series(app));
    app.drop_stale_status();
    fx
}

fn on_msg(app: &mut App, msg: Msg) -> Vec<Effect> {
    match msg {
        Msg::Key(ev) => on_key(app, ev),
        Msg::Action(a) => on_action(app, a),
        Msg::Resize(w, h) => {
            app.size = (w, h);
            Vec::new()
        }
        Msg::Batch {
            run,
            samples,
            events,
            t,
        } => run::on_batch(app, run, &samples, &events, t),
        Msg::RunDone { run, outcome } => run::on_done(app, run, outcome),
        Msg::Refined { run, why } => run::on_refined(app, run, why),
        Msg::FileChanged(text) => file::on_file_changed(app, text),
        Msg::FileUnreadable(e) => {
            app.set_status(
                StatusKind::Warn,
                format!(
                    "cannot read {}: {e} (keeping the last good model)",
                    app.file_name()
                ),
            );
            Vec::new()
        }
        Msg::WatchMode(m) => {
            app.watch_mode = m;
            Vec::new()
        }
        Msg::Saved { text, result } => file::on_saved(app, text, result),
        Msg::SaveConflict(disk) => reconcile::on_save_conflict(app, disk),
        Msg::Exported(r) => on_exported(app, r),
        Msg::StudyRow { id, index, row } => study::on_row(app, id, index, &row),
        Msg::StudyProgress { id, done, all } => study::on_progress(app, id, done, all),
        Msg::StudyDone { id, outcome } => study::on_done(app, id, outcome),
        Msg::StudyWritten { id, result } => study::on_written(app, id, result),
        Msg::StudyFiles(r) => study::on_files(app, r),
        Msg::StudyLoaded { path, result } => study::on_loaded(app, path, result),
        Msg::RunsStored(r) => runs::on_stored(app, r),
        Msg::ChartsStored(r) => charts::on_stored(app, r),
        Msg::SeriesLoaded { dir, loaded } => stored::on_loaded(app, dir, loaded),
        Msg::StudyPoint { id, index, point } => results::on_point(app, id, index, *point),
        Msg::ResultProgress { id, done, all } => results::on_progress(app, id, done, all),
        Msg::ResultDone { id, outcome } => results::on_done(app, id, outcome),
        Msg::ModelFiles(r) => open::on_files(app, r),
        Msg::ModelRead { path, result } => open::on_read(app, path, result),
        // the runtime ends the loop on it (see `signals`)
        Msg::Signal(_) => Vec::new(),
    }
}

/// The export finished: the written paths, or the failure.
fn on_exported(app: &mut App, r: Result<Vec<PathBuf>, String>) -> Vec<Effect> {
    match r {
        Ok(paths) => {
            let what = ["the window", "the whole run", "the events"];
            let list: Vec<String> = (paths.iter().enumerate())
                .map(|(i, p)| match what.get(i) {
                    Some(w) => format!("{} ({w})", p.display()),
                    None => p.display().to_string(),
                })
                .collect();
            // export-<n>-…: a number above 1 says the earlier exports were kept
            let n = (paths.first().and_then(|p| p.file_name()))
                .map(|f| f.to_string_lossy().into_owned())
                .and_then(|f| {
                    let rest = f.strip_prefix(crate::tui::runs::out_folder::EXPORT_PREFIX)?;
                    rest.split('-').next()?.parse::<usize>().ok()
                })
                .unwrap_or(1);
            let kept = match n {
                1 => String::new(),
                2 => "; export-1 kept (a new number, nothing overwritten)".into(),
                n => format!(
                    "; export-1 to -{} kept (a new number, nothing overwritten)",
                    n - 1
                ),
            };
            app.set_status(
                StatusKind::Ok,
                format!("exported {}{kept}", list.join(", ")),
            );
        }
        Err(e) => app.set_status(StatusKind::Error, format!("export failed: {e}")),
    }
    Vec::new()
}

/// A key: Ctrl-C, a keymap binding, or a character typed into the edit buffer.
fn on_key(app: &mut App, ev: KeyEvent) -> Vec<Effect> {
    if ev.kind == KeyEventKind::Release {
        return Vec::new();
    }
    // Esc and a key in one read (Alt+key): Esc, then the key
    if let Some((esc, key)) = term::split_alt(ev) {
        let mut fx = on_key(app, esc);
        if !app.quit {
            fx.extend(on_key(app, key));
        }
        return fx;
    }
    // Ctrl-Z suspends from anywhere (raw mode turned the terminal's own Ctrl-Z off)
    if ev.code == KeyCode::Char('z') && ev.modifiers.contains(KeyModifiers::CONTROL) {
        return on_action(app, Action::Suspend);
    }
    // Ctrl-C quits from anywhere (asking first when there are unsaved edits)
    if ev.code == KeyCode::Char('c') && ev.modifiers.contains(KeyModifiers::CONTROL) {
        return on_action(app, Action::Quit);
    }
    if let Some(a) = keymap::lookup(&app.contexts(), &ev) {
        return on_action(app, a);
    }
    if let Mode::Editing { buffer, .. } = &mut app.mode
        && let KeyCode::Char(c) = ev.code
        && !ev.modifiers.contains(KeyModifiers::CONTROL)
    {
        buffer.push(c);
        edit::recheck(app);
    }
    if let KeyCode::Char(c) = ev.code
        && !ev.modifiers.contains(KeyModifiers::CONTROL)
    {
        runs::name_type(app, c);
    }
    if let Mode::Search { .. } = app.mode
        && let KeyCode::Char(c) = ev.code
        && !ev.modifiers.contains(KeyModifiers::CONTROL)
    {
        find::type_char(app, c);
    }
    if let Mode::ChartPick { .. } = app.mode
        && let KeyCode::Char(c) = ev.code
        && !ev.modifiers.contains(KeyModifiers::CONTROL)
    {
        charts::type_char(app, c);
    }
    Vec::new()
}

/// Dispatches an action to its handler.
fn on_action(app: &mut App, a: Action) -> Vec<Effect> {
    use Action as A;
    match a {
        A::Quit => ask_quit(app),
        A::Help | A::Messages => open_help_or_log(app, a),
        A::CloseHelp | A::CloseMessages => set_mode(app, Mode::Normal),
        A::Rerun => run::rerun(app),
        A::Cancel => run::cancel(app),
        A::Save => file::save(app),
        A::Export => file::export(app),
        A::Yes | A::No => answer(app, a == A::Yes),
        A::SwapRecover | A::SwapKeep | A::SwapDelete => file::answer_swap(app, a),
        A::KeepMine | A::KeepMineAll => reconcile::answer_conflict(app, true, a == A::KeepMineAll),
        A::TakeTheirs | A::TakeTheirsAll => {
            reconcile::answer_conflict(app, false, a == A::TakeTheirsAll)
        }
        A::SwitchView | A::SwitchViewBack | A::ToggleMarker | A::ToggleOverlay => {
            view::toggle(app, a);
            Vec::new()
        }
        A::CursorLeft
        | A::CursorRight
        | A::CursorLeftFast
        | A::CursorRightFast
        | A::CursorHome
        | A::CursorEnd
        | A::ZoomIn
        | A::ZoomOut
        | A::ZoomReset
        | A::NextElement
        | A::PrevElement => {
            view::chart_action(app, a);
            Vec::new()
        }
        A::FieldUp
        | A::FieldDown
        | A::FieldPageUp
        | A::FieldPageDown
        | A::FieldEdit
        | A::FieldRevert
        | A::ItemDuplicate
        | A::ItemRemove
        | A::EditCommit
        | A::EditCancel
        | A::EditBackspace
        | A::EditClear => {
            edit::form_action(app, a);
            Vec::new()
        }
        A::StudyPrev
        | A::StudyNext
        | A::StudyRun
        | A::StudyCancel
        | A::StudyReopen
        | A::StudyMore
        | A::StudyFewer
        | A::StudyPointPrev
        | A::StudyPointNext
        | A::StudyApply
        | A::StudyUndo
        | A::StudyQuantity
        | A::PickUp
        | A::PickDown
        | A::PickLoad
        | A::PickClose => study::study_action(app, a),
        A::RunsView
        | A::RunUp
        | A::RunDown
        | A::RunOverlay
        | A::RunBaseline
        | A::RunRename
        | A::RunsToCharts
        | A::RunDelete
        | A::RunInfo
        | A::CloseRunInfo
        | A::NameCommit
        | A::NameCancel
        | A::NameBackspace
        | A::NameClear => runs::runs_action(app, a),
        A::NextEvent
        | A::PrevEvent
        | A::ToggleEvents
        | A::EventUp
        | A::EventDown
        | A::EventPageUp
        | A::EventPageDown
        | A::EventGo => {
            view::event_action(app, a);
            Vec::new()
        }
        // any terminal
        A::HelpDown | A::HelpUp | A::HelpPageDown | A::HelpPageUp | A::HelpTop | A::HelpBottom => {
            term::scroll_help(app, a);
            Vec::new()
        }
        A::Suspend => term::suspend(app),
        A::ResultUp | A::ResultDown | A::ResultGrid => results::action(app, a),
        A::FieldFirst
        | A::FieldLast
        | A::SearchStart
        | A::SearchNext
        | A::SearchPrev
        | A::SearchKeep
        | A::SearchCancel
        | A::SearchBackspace
        | A::FoldToggle
        | A::FoldAll => {
            find::find_action(app, a);
            Vec::new()
        }
        A::SaveQuit => file::save_and_quit(app),
        A::OpenModel | A::ModelUp | A::ModelDown | A::ModelOpen | A::ModelClose => {
            open::open_action(app, a)
        }
        // the rest: the time charts' focus, list of series, y axis and θ's unit
        _ => charts::chart_action(app, a),
    }
}

/// The help at its top, or the message log at its newest message.
fn open_help_or_log(app: &mut App, a: Action) -> Vec<Effect> {
    if a == Action::Help {
        app.help_scroll = 0;
        set_mode(app, Mode::Help)
    } else {
        app.log_scroll = usize::MAX;
        set_mode(app, Mode::Messages)
    }
}

fn set_mode(app: &mut App, mode: Mode) -> Vec<Effect> {
    app.mode = mode;
    Vec::new()
}

/// Quit, or ask first when there are unsaved edits. A value being typed counts: a valid one is
/// accepted into the draft first (so the question's `s` saves it and `n` keeps it); one that
/// is not valid yet is given back on `n` (`App::typing_before_quit`).
fn ask_quit(app: &mut App) -> Vec<Effect> {
    if let Mode::Editing { buffer, .. } = &app.mode {
        let buffer = buffer.clone();
        if app.check_edit(&buffer).is_ok() {
            edit::form_action(app, Action::EditCommit);
        } else {
            app.typing_before_quit = Some(app.mode.clone());
            app.mode = Mode::Confirm(Confirm::Quit);
            let field = app.form.selected().map_or("?".into(), |f| f.label.clone());
            app.set_status(
                StatusKind::Warn,
                format!(
                    "you are typing {field} = '{buffer}' (not valid yet): y quits without it, n goes back to it"
                ),
            );
            return Vec::new();
        }
    }
    if app.dirty() {
        app.mode = Mode::Confirm(Confirm::Quit);
        app.set_status(
            StatusKind::Warn,
            "unsaved edits: s saves and quits, y quits without saving, n stays",
        );
        Vec::new()
    } else {
        quit(app)
    }
}

fn quit(app: &mut App) -> Vec<Effect> {
    file::quit_now(app)
}

/// The answer to a yes/no question (quit, save over a change on disk).
fn answer(app: &mut App, yes: bool) -> Vec<Effect> {
    let Mode::Confirm(c) = std::mem::replace(&mut app.mode, Mode::Normal) else {
        return Vec::new();
    };
    match (c, yes) {
        (Confirm::Quit, true) => quit(app),
        (Confirm::Quit, false) => {
            app.set_status(StatusKind::Info, "not quitting");
            if let Some(m) = app.typing_before_quit.take() {
                app.mode = m;
                edit::recheck(app);
            }
            Vec::new()
        }
        (Confirm::SaveConflict { text }, yes) => reconcile::answer_save_conflict(app, text, yes),
        (Confirm::OpenModel { path }, yes) => open::answer(app, path, yes),
        (Confirm::DeleteRun { number }, yes) => runs::answer_delete(app, number, yes),
        (c @ (Confirm::Merge { .. } | Confirm::Recover { .. }), _) => {
            // answered with m/t/M/T, not y/n
            app.mode = Mode::Confirm(c);
            Vec::new()
        }
    }
}
