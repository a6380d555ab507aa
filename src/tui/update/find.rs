//! Finding one's way in the form: the first and last field, `/` search (the selection follows
//! the first match as the text is typed; Enter keeps it, Esc goes back; `n`/`N` the next and
//! previous match), groups folded and unfolded.

use crate::tui::app::{App, Mode, StatusKind};
use crate::tui::form::group_title;
use crate::tui::keymap::Action;

/// The form's navigation keys and the search's.
pub(super) fn find_action(app: &mut App, a: Action) {
    use Action as A;
    match a {
        A::FieldFirst | A::FieldLast => app.form.go_end(a == A::FieldLast),
        A::SearchStart => {
            app.mode = Mode::Search {
                query: String::new(),
                from: app.form.spot(),
            };
            app.set_status(
                StatusKind::Info,
                "search: type part of a label or path (Enter keeps, Esc goes back)",
            );
        }
        A::SearchNext | A::SearchPrev => again(app, a == A::SearchNext),
        A::SearchKeep => {
            if let Mode::Search { query, .. } = std::mem::replace(&mut app.mode, Mode::Normal) {
                if app
                    .form
                    .fields
                    .get(app.form.selected)
                    .is_some_and(|f| f.matches(&query))
                {
                    app.set_status(StatusKind::Info, format!("'{query}': n next, N previous"));
                }
                app.form.query = query;
            }
        }
        A::SearchCancel => {
            if let Mode::Search { from, .. } = std::mem::replace(&mut app.mode, Mode::Normal) {
                app.form.restore(&from);
                app.set_status(StatusKind::Info, "search abandoned");
            }
        }
        A::SearchBackspace => {
            if let Mode::Search { query, .. } = &mut app.mode {
                query.pop();
            }
            follow(app);
        }
        A::FoldToggle => {
            if let Some((g, folded)) = app.form.toggle_fold() {
                let what = if folded { "folded" } else { "unfolded" };
                app.set_status(StatusKind::Info, format!("{} {what}", group_title(&g)));
            }
        }
        A::FoldAll => {
            let folded = app.form.toggle_fold_all();
            let what = if folded {
                "all groups folded (z or Enter unfolds one)"
            } else {
                "all groups unfolded"
            };
            app.set_status(StatusKind::Info, what);
        }
        _ => {}
    }
}

/// A character typed into the search.
pub(super) fn type_char(app: &mut App, c: char) {
    if let Mode::Search { query, .. } = &mut app.mode {
        query.push(c);
    }
    follow(app);
}

/// The selection on the first match of the search from where it started (back there when
/// nothing matches).
fn follow(app: &mut App) {
    let Mode::Search { query, from } = &app.mode else {
        return;
    };
    let (query, from) = (query.clone(), from.clone());
    app.form.restore(&from);
    if query.is_empty() {
        return;
    }
    match app.form.find(&query, from.selected, true) {
        Some(i) => {
            app.form.select(i);
            let label = app.form.fields[i].label.clone();
            app.set_status(StatusKind::Info, format!("/{query}: {label}"));
        }
        None => app.set_status(StatusKind::Warn, format!("/{query}: no field matches")),
    }
}

/// `n`/`N` (and ↓/↑ while typing): the next or previous match.
fn again(app: &mut App, forward: bool) {
    let query = match &app.mode {
        Mode::Search { query, .. } => query.clone(),
        _ => app.form.query.clone(),
    };
    if query.is_empty() {
        app.set_status(StatusKind::Info, "no search yet: / searches");
        return;
    }
    let n = app.form.fields.len();
    if n == 0 {
        return;
    }
    let start = if forward {
        (app.form.selected + 1) % n
    } else {
        (app.form.selected + n - 1) % n
    };
    match app.form.find(&query, start, forward) {
        Some(i) => {
            let wrapped = if forward {
                i <= app.form.selected
            } else {
                i >= app.form.selected
            };
            app.form.select(i);
            let label = app.form.fields[i].label.clone();
            let note = if wrapped { " (from the other end)" } else { "" };
            app.set_status(StatusKind::Info, format!("/{query}: {label}{note}"));
        }
        None => app.set_status(StatusKind::Warn, format!("/{query}: no field matches")),
    }
}
