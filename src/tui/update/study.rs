//! Studies: one started on the form's model, its rows as they come, its cancel, its end and
//! its CSV; a study reopened from its CSV (the files listed, one chosen, read).

use crate::studies::Row;
use crate::study_table::{StudyKind, StudyTable};
use crate::tui::app::{App, Mode, StatusKind, View};
use crate::tui::keymap::Action;
use crate::tui::msg::{Effect, StudyOutcome};
use crate::tui::runs::out_folder::{out_dirs, reopen_dirs};
use crate::tui::studies::points::points;
use crate::tui::studies::{self as study, Entry, Phase, Source, Studies, StudySpec, title};
use std::path::PathBuf;

/// The most record pairs the workbench's suite takes (the far-field set has 19).
const MAX_SUITE_PAIRS: usize = 50;

/// The keys of the studies view and of the list of CSVs.
pub(super) fn study_action(app: &mut App, a: Action) -> Vec<Effect> {
    match a {
        Action::StudyPrev | Action::StudyNext => {
            return super::results::step(app, a == Action::StudyNext);
        }
        Action::StudyRun if app.results.page.is_some() => {
            return super::results::action(app, a);
        }
        Action::StudyRun => return start(app),
        Action::StudyMore | Action::StudyFewer => {
            let mut sub = app.studies.suite_for(&app.path);
            sub.pairs = if a == Action::StudyMore {
                (sub.pairs + 1).min(MAX_SUITE_PAIRS)
            } else {
                sub.pairs.saturating_sub(1).max(1)
            };
            let msg = format!(
                "suite: {} record pairs × {} levels from {}",
                sub.pairs,
                sub.levels.len(),
                sub.records.display()
            );
            app.studies.suite = Some(sub);
            app.studies.selected = Studies::index_of(StudyKind::Suite);
            app.results.page = None;
            app.set_status(StatusKind::Info, msg);
        }
        Action::StudyPointPrev | Action::StudyPointNext => {
            step_point(app, a == Action::StudyPointNext)
        }
        Action::StudyApply | Action::StudyUndo | Action::StudyQuantity => {
            super::design::action(app, a)
        }
        Action::StudyCancel => {
            if let Some(fx) = super::results::cancel(app) {
                return fx;
            }
            return cancel(app);
        }
        Action::StudyReopen => {
            let dirs = reopen_dirs(&app.path);
            let shown = dirs[0].display().to_string();
            app.set_status(
                StatusKind::Info,
                format!("looking for study CSVs in {shown}…"),
            );
            return vec![Effect::ListStudies { dirs }];
        }
        Action::PickUp | Action::PickDown => {
            if let Mode::Pick { files, selected } = &mut app.mode {
                let k = files.len().max(1);
                *selected = if a == Action::PickDown {
                    (*selected + 1) % k
                } else {
                    (*selected + k - 1) % k
                };
            }
        }
        Action::PickLoad => {
            let Mode::Pick { files, selected } = std::mem::replace(&mut app.mode, Mode::Normal)
            else {
                return Vec::new();
            };
            if let Some(path) = files.get(selected).cloned() {
                app.set_status(StatusKind::Info, format!("reading {}…", path.display()));
                return vec![Effect::LoadStudy { path }];
            }
        }
        Action::PickClose => app.mode = Mode::Normal,
        _ => {}
    }
    Vec::new()
}

/// `[` / `]`: the selected study's cursor to the previous or next point of its table (held at
/// the ends); the readout under the table gives the values there.
fn step_point(app: &mut App, next: bool) {
    if app.results.page.is_some() || super::design::step_row(app, next) {
        return;
    }
    let kind = app.studies.kind();
    let points = (app.studies.entry(kind))
        .and_then(|e| e.table.as_ref())
        .and_then(points);
    let Some(p) = points else {
        let msg = match kind {
            StudyKind::Screen => "the screening has no points to step through",
            _ => "no points yet: Enter runs the study, f reopens one",
        };
        app.set_status(StatusKind::Info, msg);
        return;
    };
    let i = app.studies.selected;
    let last = p.rows.len() - 1;
    let c = app.studies.cursor[i].min(last);
    app.studies.cursor[i] = if next {
        (c + 1).min(last)
    } else {
        c.saturating_sub(1)
    };
    app.generation += 1;
}

/// `Enter`: the selected study on the form's model (edits included), in a worker.
fn start(app: &mut App) -> Vec<Effect> {
    let kind = app.studies.kind();
    if let Some((k, _)) = app.studies.running() {
        let msg = format!("the {} study is running: Esc cancels it first", title(k));
        app.set_status(StatusKind::Warn, msg);
        return Vec::new();
    }
    let suite = app.studies.suite_for(&app.path);
    let table = match study::plan(kind, &app.draft, &app.studies.mus, &suite) {
        Ok(None) if kind == StudyKind::Precision => super::results::precision_plan(app),
        Ok(t) => t.map(StudyTable::Runs),
        Err(e) => {
            app.set_status(StatusKind::Error, e);
            return Vec::new();
        }
    };
    let id = app.studies.next_id;
    app.studies.next_id += 1;
    let edited = app.dirty();
    let file = app.file_name();
    let on = if edited {
        format!("the form's model ({file} with unsaved edits)")
    } else {
        format!("{file} as saved")
    };
    app.set_status(
        StatusKind::Info,
        format!("{} study started on {on}", title(kind)),
    );
    app.studies.cursor[Studies::index_of(kind)] = 0;
    app.studies.entries[Studies::index_of(kind)] = Some(Entry {
        id,
        source: Source::Form { file, edited },
        phase: Phase::Running,
        table,
        csv: None,
        count: (0, 0),
    });
    app.generation += 1;
    let spec = StudySpec {
        kind,
        text: app.draft.clone(),
        path: app.path.clone(),
        overrides: app.studies.overrides.clone(),
        mus: app.studies.mus.clone(),
        suite,
    };
    vec![Effect::StartStudy {
        id,
        spec: Box::new(spec),
    }]
}

/// `Esc` in the studies view: cancel the running study (the runs started finish).
fn cancel(app: &mut App) -> Vec<Effect> {
    let found = (StudyKind::ALL.iter().zip(app.studies.entries.iter_mut()))
        .find_map(|(k, e)| e.as_mut().filter(|e| e.running()).map(|e| (*k, e)));
    match found {
        Some((k, e)) if e.phase == Phase::Running => {
            e.phase = Phase::Cancelling;
            let id = e.id;
            let msg = format!("cancelling the {} study (runs started finish)…", title(k));
            app.set_status(StatusKind::Info, msg);
            vec![Effect::CancelStudy { id }]
        }
        Some((k, _)) => {
            let msg = format!("the {} study is being cancelled", title(k));
            app.set_status(StatusKind::Info, msg);
            Vec::new()
        }
        None => {
            app.set_status(StatusKind::Info, "no study in progress (c cancels the run)");
            Vec::new()
        }
    }
}

/// A row of study `id` is final.
pub(super) fn on_row(app: &mut App, id: u64, index: usize, row: &Row) -> Vec<Effect> {
    if let Some(e) = app.studies.by_id(id).filter(|e| e.running())
        && let Some(StudyTable::Runs(t)) = &mut e.table
        && t.record(index, row)
    {
        app.generation += 1;
    }
    Vec::new()
}

/// Study `id` (the ladder, the swings) has done `done` of its `all` runs.
pub(super) fn on_progress(app: &mut App, id: u64, done: usize, all: usize) -> Vec<Effect> {
    if let Some(e) = app
        .studies
        .by_id(id)
        .filter(|e| e.running() && e.table.is_none())
    {
        e.count = (done, all);
        app.generation += 1;
    }
    Vec::new()
}

/// "14 of 14 runs, 1 failed" (the screening: "done").
fn counts(e: &Entry) -> String {
    match &e.table {
        Some(StudyTable::Runs(t)) => {
            let failed = match t.failed() {
                0 => String::new(),
                f => format!(", {f} failed"),
            };
            format!("{} of {} runs{failed}", t.done(), t.runs.len())
        }
        Some(StudyTable::Screen(_)) => "done".into(),
        Some(StudyTable::Precision(t)) => {
            let (done, all) = t.progress();
            format!("{done} of {all} points")
        }
        Some(StudyTable::Adequacy(a)) => {
            format!("{} variants on {} runs", a.variants.len(), a.cases.len())
        }
        Some(t @ StudyTable::Sensitivity(s)) => {
            let (done, all) = t.progress();
            let failed = (s.failed().len()).saturating_sub(all - done);
            let failed = match failed {
                0 => String::new(),
                f => format!(", {f} failed"),
            };
            format!("{done} of {all} runs{failed}")
        }
        None => "nothing".into(),
    }
}

/// The end of study `id`: keep its table, write its CSV.
pub(super) fn on_done(app: &mut App, id: u64, outcome: StudyOutcome) -> Vec<Effect> {
    let dirs = out_dirs(&app.path);
    let Some(kind) = kind_of(app, id) else {
        return Vec::new();
    };
    let Some(e) = app.studies.by_id(id) else {
        return Vec::new();
    };
    let name = title(kind);
    let (status, msg) = match outcome {
        StudyOutcome::Finished(t) | StudyOutcome::Cancelled(t) => {
            let (done, all) = t.progress();
            e.phase = if done < all {
                Phase::Cancelled
            } else {
                Phase::Finished
            };
            e.table = Some(*t.clone());
            let what = if done < all { "cancelled" } else { "finished" };
            let msg = format!("{name} {what}: {}", counts(e));
            // the ladder's cursor on the cheapest variant within the tolerance
            if let StudyTable::Adequacy(a) = &*t {
                let row = a.cheapest(None).map_or(0, |v| v + 1);
                app.studies.cursor[Studies::index_of(kind)] = row;
            }
            if done > 0 {
                app.generation += 1;
                app.set_status(StatusKind::Info, format!("{msg} — writing its CSV…"));
                return vec![Effect::WriteStudy { id, dirs, table: t }];
            }
            let k = if done < all {
                StatusKind::Warn
            } else {
                StatusKind::Ok
            };
            (k, msg)
        }
        StudyOutcome::Abandoned => {
            e.phase = Phase::Cancelled;
            let why = "nothing kept: its errors need every run";
            (StatusKind::Warn, format!("{name} cancelled: {why}"))
        }
        StudyOutcome::Failed(why) => {
            e.phase = Phase::Failed(why.clone());
            (StatusKind::Error, format!("{name} failed: {why}"))
        }
    };
    app.generation += 1;
    app.set_status(status, msg);
    Vec::new()
}

fn kind_of(app: &App, id: u64) -> Option<StudyKind> {
    (StudyKind::ALL.iter().zip(&app.studies.entries))
        .find(|(_, e)| e.as_ref().is_some_and(|e| e.id == id))
        .map(|(k, _)| *k)
}

/// Study `id`'s CSV was written (or not).
pub(super) fn on_written(app: &mut App, id: u64, result: Result<PathBuf, String>) -> Vec<Effect> {
    let Some(kind) = kind_of(app, id) else {
        return Vec::new();
    };
    let Some(e) = app.studies.by_id(id) else {
        return Vec::new();
    };
    let what = if e.phase == Phase::Cancelled {
        "cancelled"
    } else {
        "finished"
    };
    let msg = format!("{} {what}: {}", title(kind), counts(e));
    match result {
        Ok(p) => {
            let shown = p.display().to_string();
            e.csv = Some(p);
            let k = if what == "cancelled" {
                StatusKind::Warn
            } else {
                StatusKind::Ok
            };
            app.set_status(k, format!("{msg}; CSV {shown}"));
        }
        Err(err) => app.set_status(
            StatusKind::Error,
            format!("{msg}; its CSV not written: {err}"),
        ),
    }
    Vec::new()
}

/// The study CSVs found: choose one (the list), or say there are none.
pub(super) fn on_files(app: &mut App, result: Result<Vec<PathBuf>, String>) -> Vec<Effect> {
    match result {
        Ok(files) if files.is_empty() => {
            let dirs = reopen_dirs(&app.path);
            let shown = dirs[0].display().to_string();
            let msg = format!("no study CSVs in {shown} yet (a finished study writes one)");
            app.set_status(StatusKind::Info, msg);
        }
        Ok(files) if app.mode == Mode::Normal => {
            let n = files.len();
            app.set_status(
                StatusKind::Info,
                format!("{n} study CSVs, newest first: Enter opens one"),
            );
            app.mode = Mode::Pick { files, selected: 0 };
        }
        Ok(_) => {}
        Err(e) => app.set_status(StatusKind::Error, format!("cannot list study CSVs: {e}")),
    }
    Vec::new()
}

/// A study's CSV was read: show it in its entry (unless that study is running).
pub(super) fn on_loaded(
    app: &mut App,
    path: PathBuf,
    result: Result<Box<StudyTable>, String>,
) -> Vec<Effect> {
    let table = match result {
        Ok(t) => t,
        Err(e) => {
            app.set_status(StatusKind::Error, format!("cannot open the study: {e}"));
            return Vec::new();
        }
    };
    let kind = table.kind();
    if app.studies.entry(kind).is_some_and(Entry::running) {
        let msg = format!(
            "{} not opened: the {} study is running (Esc cancels it)",
            path.display(),
            title(kind)
        );
        app.set_status(StatusKind::Warn, msg);
        return Vec::new();
    }
    let (done, all) = table.progress();
    let id = app.studies.next_id;
    app.studies.next_id += 1;
    let entry = Entry {
        id,
        source: Source::Csv(path.clone()),
        phase: if done < all {
            Phase::Cancelled
        } else {
            Phase::Finished
        },
        table: Some(*table),
        csv: Some(path.clone()),
        count: (0, 0),
    };
    let msg = format!(
        "opened {}: {} study, {}{}",
        path.display(),
        title(kind),
        counts(&entry),
        if done < all {
            " (a cancelled study)"
        } else {
            ""
        }
    );
    app.studies.selected = Studies::index_of(kind);
    app.results.page = None;
    app.studies.cursor[app.studies.selected] = 0;
    app.studies.entries[app.studies.selected] = Some(entry);
    app.view = View::Studies;
    app.generation += 1;
    app.set_status(StatusKind::Ok, msg);
    Vec::new()
}
