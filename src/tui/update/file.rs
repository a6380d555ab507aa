//! The model file: save, saved, changed on disk, reload; the export request.

use super::reconcile::merge_outside;
use super::stored::run_or_reuse;
use crate::tui::app::{App, Confirm, LoadError, Mode, StatusKind, hash_text};
use crate::tui::form;
use crate::tui::msg::Effect;
use std::path::PathBuf;

/// `s`: write the draft (validated first).
pub(super) fn save(app: &mut App) -> Vec<Effect> {
    if !app.dirty() && app.load_error.is_none() {
        app.set_status(StatusKind::Info, "no unsaved edits");
        return Vec::new();
    }
    if let Err(e) = form::validate(&app.draft, &app.path) {
        app.set_status(
            StatusKind::Error,
            format!("not saved: {}", form::error_with_column(&e, &app.draft).0),
        );
        return Vec::new();
    }
    app.expected_save = Some(hash_text(&app.draft));
    app.set_status(StatusKind::Info, format!("saving {}…", app.path.display()));
    // written only over the version the edits are based on (or a broken one already seen)
    vec![Effect::Save {
        path: app.path.clone(),
        text: app.draft.clone(),
        base: Some(app.disk_hash),
    }]
}

/// Quits: the running simulation and study cancelled.
pub(super) fn quit_now(app: &mut App) -> Vec<Effect> {
    app.quit = true;
    let mut fx = Vec::new();
    if let Some(cur) = app.current.as_ref().filter(|c| c.running()) {
        fx.push(Effect::CancelRun { id: cur.token });
    }
    if let Some((_, e)) = app.studies.running() {
        fx.push(Effect::CancelStudy { id: e.id });
    }
    if let Some(id) = app.results.running_id() {
        fx.push(Effect::CancelResult { id });
    }
    fx.push(Effect::Quit);
    fx
}

/// `s` in the quit question: save, and quit once saved (a draft the engine refuses, a failed
/// save or a change on disk stop the quit, with the reason).
pub(super) fn save_and_quit(app: &mut App) -> Vec<Effect> {
    app.mode = Mode::Normal;
    if !app.dirty() {
        return quit_now(app);
    }
    let fx = save(app);
    if fx.is_empty() {
        let why = app.status.clone();
        app.set_status(StatusKind::Error, format!("{why} — not quitting"));
    } else {
        app.quit_after_save = true;
        app.set_status(
            StatusKind::Info,
            format!("saving {} to quit…", app.file_name()),
        );
    }
    fx
}

/// The save finished: rerun (or quit, when asked to), or report the failure.
pub(super) fn on_saved(
    app: &mut App,
    text: String,
    result: Result<PathBuf, String>,
) -> Vec<Effect> {
    app.expected_save = None;
    let quitting = std::mem::take(&mut app.quit_after_save);
    match result {
        Ok(p) => {
            app.disk_hash = hash_text(&text);
            app.text = text;
            app.load_error = None;
            app.rebuild_form();
            if quitting {
                return quit_now(app);
            }
            let (fx, ran) = run_or_reuse(app);
            app.set_status(StatusKind::Ok, ran.say(format!("saved {}", p.display())));
            fx
        }
        Err(e) => {
            let not = if quitting { " — not quitting" } else { "" };
            app.set_status(StatusKind::Error, format!("save failed: {e}{not}"));
            Vec::new()
        }
    }
}

/// The file changed on disk: reload, merge with the unsaved edits (or the value being typed),
/// or ignore (same content).
pub(super) fn on_file_changed(app: &mut App, text: String) -> Vec<Effect> {
    let h = hash_text(&text);
    if h == app.disk_hash {
        return Vec::new();
    }
    if app.expected_save == Some(h) {
        app.disk_hash = h;
        return Vec::new();
    }
    let editing = matches!(app.mode, Mode::Editing { .. });
    let pending = matches!(
        app.mode,
        Mode::Confirm(Confirm::Merge { .. } | Confirm::SaveConflict { .. })
    );
    if app.dirty() || editing || pending {
        return merge_outside(app, text);
    }
    apply_reload(app, text)
}

/// Reloads `text`: rerun, or keep the last good model and show the error.
pub(super) fn apply_reload(app: &mut App, text: String) -> Vec<Effect> {
    app.disk_hash = hash_text(&text);
    match form::validate(&text, &app.path) {
        Ok(scene) => {
            app.text = text.clone();
            app.draft = text;
            app.scene = Some(scene);
            app.load_error = None;
            app.rebuild_form();
            app.mode = Mode::Normal;
            let (fx, ran) = run_or_reuse(app);
            let s = ran.say(format!("reloaded {}", app.file_name()));
            app.set_status(StatusKind::Ok, s);
            fx
        }
        Err(e) => {
            let le = LoadError::new(&e, &text);
            app.set_status(
                StatusKind::Error,
                format!("reload failed, keeping the last good model: {}", le.message),
            );
            app.load_error = Some(le);
            Vec::new()
        }
    }
}

/// `e`: export the shown run (its window, the whole run, its events) into the output folder.
pub(super) fn export(app: &mut App) -> Vec<Effect> {
    let Some(run) = app.current.as_ref().filter(|r| !r.t.is_empty()) else {
        app.set_status(StatusKind::Info, "nothing to export yet");
        return Vec::new();
    };
    let fx = vec![Effect::Export {
        dirs: crate::tui::runs::out_folder::out_dirs(&app.path),
        run: Box::new(run.clone()),
        window: app.window(),
        element: app.element,
    }];
    app.set_status(StatusKind::Info, "exporting…");
    fx
}

/// The answer to the swap file found at the start: its edits as the draft (`r`), kept in a
/// recovery file with the model opened as on disk (`k`), or deleted (`d`).
pub(super) fn answer_swap(app: &mut App, a: crate::tui::keymap::Action) -> Vec<Effect> {
    use crate::tui::form::swap;
    use crate::tui::keymap::Action as A;
    let Mode::Confirm(Confirm::Recover { found, differences }) =
        std::mem::replace(&mut app.mode, Mode::Normal)
    else {
        return Vec::new();
    };
    let typed = found
        .typing
        .as_ref()
        .map_or(String::new(), |t| format!("; you were typing {t}"));
    match a {
        A::SwapRecover => {
            let _ = std::fs::remove_file(&found.path);
            if let Ok(scene) = form::validate(&found.text, &app.path) {
                app.scene = Some(scene);
            }
            app.draft = found.text;
            app.rebuild_form();
            app.set_status(
                StatusKind::Warn,
                format!(
                    "recovered {} unsaved change(s) from {} (s saves them){typed}",
                    differences.len(),
                    found.path.display()
                ),
            );
        }
        A::SwapKeep => match crate::tui::signals::write_recovery(&app.path, &found.text) {
            Ok(p) => {
                let _ = std::fs::remove_file(&found.path);
                app.set_status(
                    StatusKind::Info,
                    format!(
                        "the swap's edits kept in {}; {} opened as on disk{typed}",
                        p.display(),
                        app.file_name()
                    ),
                );
            }
            Err(e) => {
                app.set_status(
                    StatusKind::Error,
                    format!(
                        "cannot keep the swap's edits ({e}): {} is left as it is",
                        found.path.display()
                    ),
                );
            }
        },
        _ => {
            swap::remove_all(&app.path);
            let _ = std::fs::remove_file(&found.path);
            app.set_status(
                StatusKind::Info,
                format!("deleted the swap file {}", found.path.display()),
            );
        }
    }
    Vec::new()
}
