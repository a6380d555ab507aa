//! The model file: save, saved, changed on disk, reload; the export request.

use super::reconcile::merge_outside;
use super::run::start_run;
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

/// The save finished: rerun, or report the failure.
pub(super) fn on_saved(
    app: &mut App,
    text: String,
    result: Result<PathBuf, String>,
) -> Vec<Effect> {
    app.expected_save = None;
    match result {
        Ok(p) => {
            app.disk_hash = hash_text(&text);
            app.text = text;
            app.load_error = None;
            app.rebuild_form();
            let fx = start_run(app);
            app.set_status(StatusKind::Ok, format!("saved {} — rerunning", p.display()));
            fx
        }
        Err(e) => {
            app.set_status(StatusKind::Error, format!("save failed: {e}"));
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
            let fx = start_run(app);
            app.set_status(
                StatusKind::Ok,
                format!("reloaded {} — rerunning", app.file_name()),
            );
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

/// `e`: export the shown run.
pub(super) fn export(app: &mut App) -> Vec<Effect> {
    let Some(run) = app.current.as_ref().filter(|r| !r.t.is_empty()) else {
        app.set_status(StatusKind::Info, "nothing to export yet");
        return Vec::new();
    };
    let stem = app
        .path
        .file_stem()
        .map_or("model".into(), |s| s.to_string_lossy().into_owned());
    let mut dirs = Vec::new();
    if let Some(d) = app.path.parent() {
        dirs.push(if d.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            d.to_path_buf()
        });
    }
    dirs.push(PathBuf::from("."));
    let fx = vec![Effect::Export {
        dirs,
        stem,
        run: Box::new(run.clone()),
        window: app.window(),
        element: app.element,
    }];
    app.set_status(StatusKind::Info, "exporting…");
    fx
}
