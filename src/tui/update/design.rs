//! The keys of the two design studies: `j`/`k` (and `[`/`]`) the selected row of the ladder's
//! or the swings' table, `n` the swings' next quantity, `a` the selected variant of the ladder
//! applied to the form's model as an unsaved edit (each change marked by a comment), `u` taking
//! it back whole.

use crate::design::swings::Sensitivity;
use crate::study_table::{StudyKind, StudyTable};
use crate::tui::app::{App, StatusKind};
use crate::tui::form;
use crate::tui::keymap::Action;
use crate::tui::studies::design_rows::{order, quantity, rows, variant_of_row};
use crate::tui::studies::{Applied, Studies};

/// The keys of the design studies (`a`, `n`, `u`).
pub(super) fn action(app: &mut App, a: Action) {
    match a {
        Action::StudyApply => apply(app),
        Action::StudyQuantity => next_quantity(app),
        Action::StudyUndo => undo(app),
        _ => {}
    }
}

/// `u`: the variant applied taken back, or why there is nothing to take back.
fn undo(app: &mut App) {
    if super::edit::undo_applied(app) {
        return;
    }
    let msg = match &app.studies.applied {
        Some(a) => format!(
            "nothing to undo: the form changed since {} was applied (u in the form reverts a \
             field)",
            a.name
        ),
        None => "nothing to undo: no variant of the ladder applied".into(),
    };
    app.set_status(StatusKind::Info, msg);
}

/// The selected study's table when it is the ladder's or the swings'.
fn table(app: &App) -> Option<&StudyTable> {
    let t = app.studies.entry(app.studies.kind())?.table.as_ref()?;
    rows(t).map(|_| t)
}

/// `j`/`k`, `[`/`]` on the ladder or the swings: the cursor to the next or previous row (held
/// at the ends); false when the selected study is neither or has no table yet.
pub(super) fn step_row(app: &mut App, down: bool) -> bool {
    let Some(n) = table(app).and_then(rows) else {
        return false;
    };
    let i = app.studies.selected;
    let c = app.studies.cursor[i].min(n.saturating_sub(1));
    app.studies.cursor[i] = if down {
        (c + 1).min(n.saturating_sub(1))
    } else {
        c.saturating_sub(1)
    };
    app.generation += 1;
    true
}

/// `n`: the sensitivity study (selected if it was not) shows the next quantity of its swings; the row
/// at the cursor keeps its input.
fn next_quantity(app: &mut App) {
    app.studies.selected = Studies::index_of(StudyKind::Sensitivity);
    app.results.page = None;
    app.generation += 1;
    let s: Sensitivity = match table(app) {
        Some(StudyTable::Sensitivity(s)) if !s.quantities.is_empty() => (**s).clone(),
        _ => {
            let msg = "the sensitivity study has no swings yet: Enter runs it on the form's model";
            app.set_status(StatusKind::Info, msg);
            return;
        }
    };
    let q = quantity(&s, app.studies.quantity);
    let next = (q + 1) % s.quantities.len();
    let i = app.studies.selected;
    let input = order(&s, q).get(app.studies.cursor[i]).copied();
    app.studies.quantity = next;
    if let Some(input) = input {
        app.studies.cursor[i] = (order(&s, next).iter())
            .position(|&k| k == input)
            .unwrap_or(0);
    }
    let msg = format!(
        "sensitivity: the tornado of {} ({}/{}), n the next",
        s.quantities[next],
        next + 1,
        s.quantities.len()
    );
    app.set_status(StatusKind::Info, msg);
}

/// `a`: the ladder's variant at the cursor applied to the form's draft (each change marked
/// with a comment), refused when the model it makes does not compile.
fn apply(app: &mut App) {
    let a = match table(app) {
        Some(StudyTable::Adequacy(a)) => a,
        _ => {
            let msg = if app.studies.kind() == StudyKind::Adequacy {
                "the adequacy study has not run: Enter runs it on the form's model, then a applies a variant"
            } else {
                "a applies a variant of the model ladder: select the adequacy study (h/l) and run it"
            };
            app.set_status(StatusKind::Info, msg);
            return;
        }
    };
    let Some(v) = variant_of_row(a, app.studies.cursor()) else {
        let msg = "the full model is the form's model: select a variant (j/k) to apply";
        app.set_status(StatusKind::Info, msg);
        return;
    };
    let variant = a.variants[v].variant.clone();
    let edited = variant.text(&app.draft, true).map_err(|e| e.to_string());
    let checked = edited.and_then(|t| match form::validate(&t, &app.path) {
        Ok(_) => Ok(t),
        Err(e) => Err(format!(
            "the model would be invalid: {}",
            form::shown_error(&e)
        )),
    });
    let text = match checked {
        Ok(t) if t == app.draft => {
            let msg = format!("{}: the form's model has it already", variant.name);
            app.set_status(StatusKind::Info, msg);
            return;
        }
        Ok(t) => t,
        Err(e) => {
            let msg = format!("cannot apply {}: {e}", variant.name);
            app.set_status(StatusKind::Error, msg);
            return;
        }
    };
    let keys = variant.changes.len();
    app.studies.applied = Some(Applied {
        name: variant.name.clone(),
        keys,
        before: app.draft.clone(),
        after: text.clone(),
    });
    super::edit::accept_draft(app, text);
    app.generation += 1;
    let changed = match keys {
        1 => "1 key changed".to_string(),
        k => format!("{k} keys changed"),
    };
    let msg = format!("applied {}: {changed}; u undoes", variant.name);
    app.set_status(StatusKind::Ok, msg);
}
