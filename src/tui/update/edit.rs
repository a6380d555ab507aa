//! Form actions: select a field, edit, accept or abandon the edit, revert; a variant of the
//! model ladder applied to the draft taken back whole.

use crate::tui::app::{App, Mode, StatusKind};
use crate::tui::form;
use crate::tui::keymap::Action;

/// Field and edit keys of the form view.
pub(super) fn form_action(app: &mut App, a: Action) {
    use Action as A;
    match a {
        A::FieldUp => select(app, -1),
        A::FieldDown => select(app, 1),
        A::FieldPageUp => select(app, -10),
        A::FieldPageDown => select(app, 10),
        A::FieldEdit if app.form.on_header => {
            super::find::find_action(app, A::FoldToggle);
        }
        A::FieldEdit => start_edit(app),
        A::FieldRevert => revert(app),
        A::ItemDuplicate | A::ItemRemove => list_edit(app, a == A::ItemDuplicate),
        A::EditCommit => commit(app),
        A::EditCancel => {
            app.mode = Mode::Normal;
            app.set_status(StatusKind::Info, "edit abandoned");
        }
        A::EditBackspace | A::EditClear => {
            if let Mode::Editing { buffer, .. } = &mut app.mode {
                if a == A::EditClear {
                    buffer.clear();
                } else {
                    buffer.pop();
                }
            }
            recheck(app);
        }
        _ => {}
    }
}

fn start_edit(app: &mut App) {
    if let Some(f) = app.form.selected() {
        let buffer = f.edit_text();
        app.mode = Mode::Editing {
            buffer,
            check: Ok(()),
        };
        recheck(app);
    }
}

/// Live validation of the edit buffer.
pub(super) fn recheck(app: &mut App) {
    if let Mode::Editing { buffer, .. } = &app.mode {
        let check = app.check_edit(buffer).map(|_| ());
        if let Mode::Editing { check: c, .. } = &mut app.mode {
            *c = check;
        }
    }
}

/// Moves the selection `d` rows (group headers included).
fn select(app: &mut App, d: i64) {
    app.form.move_by(d);
}

/// `Enter`: accept the edit (refused, with the reason, when invalid).
fn commit(app: &mut App) {
    let Mode::Editing { buffer, .. } = &app.mode else {
        return;
    };
    let buffer = buffer.clone();
    let Some(f) = app.form.selected().cloned() else {
        return;
    };
    match app.check_edit(&buffer) {
        Ok(text) => {
            accept_draft(app, text);
            app.mode = Mode::Normal;
            let v = app
                .form
                .selected()
                .and_then(|f| f.value.clone())
                .unwrap_or_default();
            let unit = if f.unit.is_empty()
                || ["–", "#"].contains(&f.unit.as_str())
                || f.unit.contains('|')
            {
                String::new()
            } else {
                format!(" {}", f.unit)
            };
            app.set_status(
                StatusKind::Ok,
                format!(
                    "{} = {v}{unit} (unsaved: s saves and reruns, r runs the edits)",
                    f.label
                ),
            );
        }
        Err(reason) => {
            app.mode = Mode::Editing {
                buffer,
                check: Err(reason.clone()),
            };
            app.set_status(StatusKind::Error, format!("refused: {reason}"));
        }
    }
}

/// `text` as the form's draft (its scene when it compiles), the form rebuilt.
pub(super) fn accept_draft(app: &mut App, text: String) {
    if let Ok(scene) = form::validate(&text, &app.path) {
        app.scene = Some(scene);
    }
    app.draft = text;
    app.rebuild_form();
}

/// `u`: revert the field to its saved value.
/// `+` / `-`: a copy of the selected field's list element added after it, or the element
/// removed (`tui::form::list_edit`); the draft is checked by the engine first, as an edit is.
fn list_edit(app: &mut App, add: bool) {
    let Some(f) = app.form.selected().cloned() else {
        return;
    };
    let edit = if add {
        crate::tui::form::list_edit::duplicate(&app.draft, &f.path)
    } else {
        crate::tui::form::list_edit::remove(&app.draft, &f.path)
    };
    let checked = edit.and_then(|(t, what)| match form::validate(&t, &app.path) {
        Ok(_) => Ok((t, what)),
        Err(e) => Err(format!(
            "the model would be invalid: {}",
            form::shown_error(&e)
        )),
    });
    match checked {
        Ok((t, what)) => {
            accept_draft(app, t);
            app.set_status(
                StatusKind::Ok,
                format!("{what} (unsaved: s saves, u reverts a field)"),
            );
        }
        Err(e) => app.set_status(StatusKind::Error, e),
    }
}

/// `u`: the ladder's variant just applied taken back whole (while the draft is still what it
/// made); else the field reverted to its saved value.
fn revert(app: &mut App) {
    if undo_applied(app) {
        return;
    }
    let Some(f) = app.form.selected().cloned() else {
        return;
    };
    if !f.edited() {
        app.set_status(StatusKind::Info, format!("{} is not edited", f.label));
        return;
    }
    let r = match &f.saved {
        Some(v) => form::set_value(&app.draft, &f.path, f.kind, v, form::Dim::Plain),
        None => form::remove_value(&app.draft, &f.path),
    };
    match r.and_then(|t| {
        form::validate(&t, &app.path)
            .map(|_| t)
            .map_err(|e| form::shown_error(&e))
    }) {
        Ok(t) => {
            accept_draft(app, t);
            app.set_status(StatusKind::Ok, format!("{} reverted", f.label));
        }
        Err(e) => app.set_status(StatusKind::Error, format!("cannot revert {}: {e}", f.label)),
    }
}

/// The ladder's variant last applied to the draft taken back (the draft before it restored,
/// byte for byte), when the draft is still the one it made; false when there is none.
pub(super) fn undo_applied(app: &mut App) -> bool {
    let Some(a) = app.studies.applied.take_if(|a| a.after == app.draft) else {
        return false;
    };
    accept_draft(app, a.before);
    app.generation += 1;
    let keys = match a.keys {
        1 => "1 key".to_string(),
        k => format!("{k} keys"),
    };
    let msg = format!("undid {}: {keys} as before", a.name);
    app.set_status(StatusKind::Ok, msg);
    true
}
