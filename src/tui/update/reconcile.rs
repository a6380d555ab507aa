//! Changes on disk merged with the unsaved edits: values changed only on disk are taken
//! (keeping the user's edits and the value being typed), values changed on both sides are
//! asked about one by one, and a save that finds an unmerged change on disk asks first.

use super::edit::recheck;
use super::run::start_run;
use crate::tui::app::{App, Confirm, Conflict, LoadError, Mode, StatusKind, hash_text};
use crate::tui::form;
use crate::tui::form::merge;
use crate::tui::msg::Effect;

/// What was going on when a change arrived, to give back afterwards.
struct Before {
    /// The field path and the value being typed.
    typing: Option<(String, String)>,
    /// Conflicts of an earlier change still unanswered.
    pending: Vec<Conflict>,
    /// Another mode (help, the quit question) to return to.
    other: Option<Mode>,
}

fn take_mode(app: &mut App) -> Before {
    let mut b = Before {
        typing: None,
        pending: Vec::new(),
        other: None,
    };
    match std::mem::replace(&mut app.mode, Mode::Normal) {
        Mode::Editing { buffer, .. } => {
            b.typing = app.form.selected().map(|f| (f.path.clone(), buffer));
        }
        Mode::Confirm(Confirm::Merge { conflicts, resume }) => {
            b.pending = conflicts;
            b.typing = resume;
        }
        // the save question is answered by the merge itself
        Mode::Confirm(Confirm::SaveConflict { .. }) | Mode::Normal => {}
        m => b.other = Some(m),
    }
    b
}

/// `theirs` arrived from disk while there are unsaved edits or a value is being typed.
pub(super) fn merge_outside(app: &mut App, theirs: String) -> Vec<Effect> {
    app.disk_hash = hash_text(&theirs);
    if let Err(e) = form::validate(&theirs, &app.path) {
        let le = LoadError::new(&e, &theirs);
        app.set_status(
            StatusKind::Error,
            format!(
                "{} changed on disk but does not load: not merged, your edits are kept \
                 (s would overwrite it): {}",
                app.file_name(),
                le.message
            ),
        );
        app.load_error = Some(le);
        return Vec::new();
    }
    let merged = match merge::merge(&app.text, &app.draft, &theirs) {
        Ok(m) => m,
        Err(e) => {
            app.set_status(StatusKind::Error, format!("cannot merge the change: {e}"));
            return Vec::new();
        }
    };
    let before = take_mode(app);
    let mut conflicts = merged.conflicts;
    for c in before.pending {
        if conflicts.iter().any(|n| n.path == c.path) {
            continue;
        }
        let theirs_now = merge::value_of(&theirs, &c.path).map(|v| form::show(&v));
        let mine_now = merge::value_of(&merged.text, &c.path).map(|v| form::show(&v));
        if theirs_now != mine_now {
            conflicts.push(Conflict {
                theirs: theirs_now,
                ..c
            });
        }
    }
    app.text = theirs;
    app.draft = merged.text;
    app.load_error = None;
    set_scene(app);
    app.rebuild_form();
    let mut note = describe(&merged.taken, &merged.failed, !conflicts.is_empty());
    if let Some((path, _)) = &before.typing
        && merged.taken.contains(path)
    {
        let v = merge::value_of(&app.text, path).map_or("(removed)".into(), |v| form::show(&v));
        note.push_str(&format!(
            "; {} changed on disk to {v} while you typed: Enter keeps yours, Esc takes it",
            form::label_of(path)
        ));
    }
    if !conflicts.is_empty() {
        app.mode = Mode::Confirm(Confirm::Merge {
            conflicts,
            resume: before.typing,
        });
        ask(app, &note);
        return Vec::new();
    }
    resume(app, before.typing, before.other);
    finish(app, &note)
}

/// "merged a, b from disk into your edits" (and what could not be kept); nothing said of the
/// values taken when none was and `asking` (the question about the conflicts says it all).
fn describe(taken: &[String], failed: &[(String, String)], asking: bool) -> String {
    let mut s = if taken.is_empty() && asking {
        String::new()
    } else if taken.is_empty() {
        "the change on disk needed no merge".to_string()
    } else {
        let mut list = (taken.iter().take(3))
            .map(|p| form::label_of(p))
            .collect::<Vec<_>>()
            .join(", ");
        if taken.len() > 3 {
            list.push_str(&format!(" and {} more", taken.len() - 3));
        }
        format!("merged {list} from disk into your edits")
    };
    for (p, e) in failed {
        if !s.is_empty() {
            s.push_str("; ");
        }
        s.push_str(&format!(
            "your edit of {} could not be kept ({e}): the disk's stays",
            form::label_of(p)
        ));
    }
    s
}

/// The draft's scene (the last good one stays when the draft does not load).
fn set_scene(app: &mut App) {
    if let Ok(scene) = form::validate(&app.draft, &app.path) {
        app.scene = Some(scene);
    }
}

/// Gives back the value being typed (on its field), or the mode that was open.
fn resume(app: &mut App, typing: Option<(String, String)>, other: Option<Mode>) {
    app.mode = other.unwrap_or(Mode::Normal);
    if let Some((path, buffer)) = typing {
        if let Some(i) = app.form.index_of(&path) {
            app.form.select(i);
        }
        app.mode = Mode::Editing {
            buffer,
            check: Ok(()),
        };
        recheck(app);
    }
}

/// All merged and answered: rerun the merged model (when it loads).
fn finish(app: &mut App, note: &str) -> Vec<Effect> {
    match form::validate(&app.draft, &app.path) {
        Ok(_) => {
            let fx = start_run(app);
            app.set_status(StatusKind::Ok, format!("{note} — rerunning (s saves)"));
            fx
        }
        Err(e) => {
            let msg = form::error_with_column(&e, &app.draft).0;
            app.set_status(
                StatusKind::Warn,
                format!("{note}; the merged model does not load: {msg}"),
            );
            Vec::new()
        }
    }
}

/// Puts the first pending conflict in the status line.
fn ask(app: &mut App, note: &str) {
    let Mode::Confirm(Confirm::Merge { conflicts, .. }) = &app.mode else {
        return;
    };
    let Some(c) = conflicts.first() else { return };
    let v = |x: &Option<String>| x.clone().unwrap_or_else(|| "(none)".into());
    let more = if conflicts.len() > 1 {
        format!(" (1 of {})", conflicts.len())
    } else {
        String::new()
    };
    let lead = if note.is_empty() {
        String::new()
    } else {
        format!("{note}; ")
    };
    let msg = format!(
        "{lead}{} changed on disk and here{more}: yours {}, on disk {} — m keeps mine, \
         t takes theirs, M/T for all",
        form::label_of(&c.path),
        v(&c.mine),
        v(&c.theirs)
    );
    app.set_status(StatusKind::Warn, msg);
}

/// The answer to a conflict: keep mine or take theirs, for the first or for all.
pub(super) fn answer_conflict(app: &mut App, keep_mine: bool, all: bool) -> Vec<Effect> {
    let Mode::Confirm(Confirm::Merge {
        mut conflicts,
        resume: typing,
    }) = std::mem::replace(&mut app.mode, Mode::Normal)
    else {
        return Vec::new();
    };
    let n = if all { conflicts.len() } else { 1 };
    let mut failed = Vec::new();
    for c in conflicts.drain(..n.min(conflicts.len())) {
        if keep_mine {
            continue;
        }
        let theirs = merge::value_of(&app.text, &c.path);
        match merge::apply(&app.draft, &c.path, theirs.as_ref()) {
            Ok(t) => app.draft = t,
            Err(e) => failed.push(format!(
                "cannot take {} from disk: {e}",
                form::label_of(&c.path)
            )),
        }
    }
    set_scene(app);
    app.rebuild_form();
    let note = if failed.is_empty() {
        format!(
            "{} on disk",
            if keep_mine {
                "kept yours over the change"
            } else {
                "took the value"
            }
        )
    } else {
        failed.join("; ")
    };
    if !conflicts.is_empty() {
        app.mode = Mode::Confirm(Confirm::Merge {
            conflicts,
            resume: typing,
        });
        ask(app, &note);
        return Vec::new();
    }
    resume(app, typing, None);
    finish(app, &format!("{note}; merge done"))
}

/// `s` found `disk` on disk, not the version the edits were based on: ask.
pub(super) fn on_save_conflict(app: &mut App, disk: String) -> Vec<Effect> {
    app.expected_save = None;
    // a save to quit stops here: the question comes first
    app.quit_after_save = false;
    let loads = form::validate(&disk, &app.path).is_ok();
    let q = if loads {
        "merge it into your edits first? (y: merge, then s saves; n: do not save)"
    } else {
        "it does not load: overwrite it with your version? (y/n)"
    };
    app.set_status(
        StatusKind::Warn,
        format!(
            "not saved: {} changed on disk since your edits were made on it; {q}",
            app.file_name()
        ),
    );
    app.mode = Mode::Confirm(Confirm::SaveConflict { text: disk });
    Vec::new()
}

/// The answer to the save question.
pub(super) fn answer_save_conflict(app: &mut App, disk: String, yes: bool) -> Vec<Effect> {
    if !yes {
        app.set_status(
            StatusKind::Info,
            format!(
                "not saved: {} changed on disk (s asks again)",
                app.file_name()
            ),
        );
        return Vec::new();
    }
    if form::validate(&disk, &app.path).is_ok() {
        return merge_outside(app, disk);
    }
    app.expected_save = Some(hash_text(&app.draft));
    app.set_status(StatusKind::Info, format!("saving {}…", app.path.display()));
    vec![Effect::Save {
        path: app.path.clone(),
        text: app.draft.clone(),
        base: Some(hash_text(&disk)),
    }]
}
