//! The run list: a run kept when it ends, the baseline pinned, runs overlaid, named; their
//! files written beside the model.

use crate::tui::app::{App, Confirm, Mode, StatusKind, View};
use crate::tui::keymap::Action;
use crate::tui::msg::Effect;
use crate::tui::runs::data::RunData;
use crate::tui::runs::list::{Ended, Entry, derived_name};
use crate::tui::runs::store::Job;

/// Longest name of a run, in characters.
const NAME_MAX: usize = 48;

/// The model text run `id` ran (the draft when it was started).
fn model_of(app: &mut App, id: u64) -> String {
    match app.runs.started.take() {
        Some((n, text)) if n == id => text,
        other => {
            app.runs.started = other;
            app.draft.clone()
        }
    }
}

/// Keeps run `r`, which ended (finished, cancelled or failed, or superseded by a new run):
/// into the list, pinned as the baseline when there is none and it finished; its files
/// written. Returns the effects and, when it became the baseline, a note for the status line.
/// A run of the same number (a rerun of the same model text) replaces the kept one, its name
/// and overlay kept, unless it was cancelled and the kept one ended by itself.
pub(super) fn keep(app: &mut App, r: &RunData) -> (Vec<Effect>, Option<String>) {
    let model = model_of(app, r.id);
    let mut entry = Entry::of_run(r, model);
    let n = entry.number;
    if let Some(old) = app.runs.get(n) {
        if entry.ended == Ended::Cancelled && old.ended != Ended::Cancelled {
            return (Vec::new(), Some(format!("the kept #{n} stays")));
        }
        (entry.name, entry.named) = (old.name.clone(), old.named);
        entry.overlay = old.overlay;
    }
    let finished = entry.ended == Ended::Finished;
    let mut dropped = app.runs.add(entry, &app.text);
    let mut note = None;
    let mut rediffed = Vec::new();
    if app.runs.baseline.is_none() && finished {
        rediffed = app.runs.pin(n);
        note = Some(format!("#{n} is the baseline (# lists the runs)"));
    }
    app.runs.selected = app.runs.list.len().saturating_sub(1);
    dropped.append(&mut app.runs_older);
    let mut fx = store(app, &[n], true, dropped);
    rediffed.retain(|&k| k != n);
    fx.extend(store(app, &rediffed, false, Vec::new()));
    (fx, note)
}

/// The effect writing runs `numbers` (with `full`, their model and series too).
pub(super) fn store(app: &App, numbers: &[u64], full: bool, remove: Vec<u64>) -> Vec<Effect> {
    let Some(dir) = app.runs.dir.clone() else {
        return Vec::new();
    };
    let jobs: Vec<Job> = numbers
        .iter()
        .filter_map(|&n| app.runs.get(n))
        .map(|e| Job {
            entry: Box::new(e.clone()),
            baseline: app.runs.baseline == Some(e.number),
            full,
        })
        .collect();
    if jobs.is_empty() && remove.is_empty() {
        return Vec::new();
    }
    vec![Effect::StoreRuns { dir, jobs, remove }]
}

/// The files were written, or not.
pub(super) fn on_stored(app: &mut App, r: Result<(), String>) -> Vec<Effect> {
    if let Err(e) = r {
        app.set_status(StatusKind::Warn, format!("the run list is not stored: {e}"));
    }
    Vec::new()
}

/// `d`: delete the selected run, asking first (the question names it; the baseline's says
/// that no run is the baseline after it).
fn ask_delete(app: &mut App) -> Vec<Effect> {
    let Some(e) = app.runs.selected_entry() else {
        return nothing(app);
    };
    let n = e.number;
    let what = format!("#{n} ({}, {})", e.name, e.ended.short());
    let q = if app.runs.baseline == Some(n) {
        format!(
            "delete {what}, the baseline (no run is the baseline after it), and its files? (y/n)"
        )
    } else {
        format!("delete {what} and its files? (y/n)")
    };
    app.mode = Mode::Confirm(Confirm::DeleteRun { number: n });
    app.set_status(StatusKind::Warn, q);
    Vec::new()
}

/// The answer to "delete run `n`?": the run off the list, its files removed (the numbers of
/// the others stay).
pub(super) fn answer_delete(app: &mut App, n: u64, yes: bool) -> Vec<Effect> {
    if !yes {
        app.set_status(StatusKind::Info, format!("#{n} kept"));
        return Vec::new();
    }
    let was_base = app.runs.baseline == Some(n);
    if app.runs.remove(n).is_none() {
        return Vec::new();
    }
    if let Some(cur) = app.current.as_mut().filter(|c| c.id == n && !c.running()) {
        cur.label = format!("#{n} (deleted)");
    }
    app.generation += 1;
    let whence = app.runs.dir.as_ref().map_or(String::new(), |d| {
        format!(" and its files from {}", d.display())
    });
    app.set_status(StatusKind::Ok, format!("#{n} deleted{whence}"));
    let mut fx = store(app, &[], false, vec![n]);
    if was_base {
        // the others' diffs were against it
        let all: Vec<u64> = app.runs.list.iter().map(|e| e.number).collect();
        fx.extend(store(app, &all, false, Vec::new()));
    }
    fx
}

/// `i`: the whole status of the selected run (in the run list) or of the shown run.
fn open_info(app: &mut App) -> Vec<Effect> {
    let n = if app.view == View::Runs {
        app.runs.selected_entry().map(|e| e.number)
    } else {
        app.current.as_ref().map(|c| c.id)
    };
    match n.and_then(|n| super::info::of(app, n)) {
        Some(info) => {
            app.info_scroll = 0;
            app.mode = Mode::RunInfo(Box::new(info));
        }
        None => {
            nothing(app);
        }
    }
    Vec::new()
}

/// The keys of the run list and of naming a run.
pub(super) fn runs_action(app: &mut App, a: Action) -> Vec<Effect> {
    use Action as A;
    let len = app.runs.list.len();
    let sel = app.runs.selected_entry().map(|e| e.number);
    match a {
        A::RunsView => {
            app.view = if app.view == View::Runs {
                View::Charts
            } else {
                View::Runs
            };
            if len == 0 && app.view == View::Runs {
                app.set_status(StatusKind::Info, "no run kept yet: r runs the model");
            }
        }
        A::RunsToCharts => app.view = View::Charts,
        A::RunDelete => return ask_delete(app),
        A::RunInfo => return open_info(app),
        A::CloseRunInfo => app.mode = Mode::Normal,
        A::RunUp => app.runs.selected = app.runs.selected.saturating_sub(1),
        A::RunDown => app.runs.selected = (app.runs.selected + 1).min(len.saturating_sub(1)),
        A::RunOverlay => {
            let Some(n) = sel else {
                return nothing(app);
            };
            match app.runs.toggle_overlay(n) {
                Ok(on) => {
                    app.generation += 1;
                    let s = if on {
                        format!("#{n} overlaid on the charts and compared")
                    } else {
                        format!("#{n} taken off the overlay")
                    };
                    app.say_overlay(StatusKind::Info, s);
                }
                Err(e) => app.set_status(StatusKind::Warn, e),
            }
        }
        A::RunBaseline => {
            let Some(n) = sel else {
                return nothing(app);
            };
            let old = app.runs.baseline;
            if old == Some(n) {
                app.set_status(StatusKind::Info, format!("#{n} is the baseline already"));
                return Vec::new();
            }
            let mut changed = app.runs.pin(n);
            app.generation += 1;
            app.say_overlay(
                StatusKind::Ok,
                format!("#{n} is the baseline: diffs, overlay and comparison are against it"),
            );
            // the baseline flags and the diffs stored with the runs
            changed.extend(old.into_iter().chain([n]));
            changed.sort_unstable();
            changed.dedup();
            return store(app, &changed, false, Vec::new());
        }
        A::RunRename => {
            let Some(e) = app.runs.selected_entry() else {
                return nothing(app);
            };
            let number = e.number;
            app.mode = Mode::Naming {
                number,
                buffer: e.name.clone(),
            };
            app.set_status(
                StatusKind::Info,
                format!("name #{number}: Enter keeps it (empty: the derived name), Esc leaves it"),
            );
        }
        A::NameCommit => return name_commit(app),
        A::NameCancel => {
            app.mode = Mode::Normal;
            app.set_status(StatusKind::Info, "name unchanged");
        }
        A::NameBackspace | A::NameClear => {
            if let Mode::Naming { buffer, .. } = &mut app.mode {
                if a == A::NameClear {
                    buffer.clear();
                } else {
                    buffer.pop();
                }
            }
        }
        _ => {}
    }
    Vec::new()
}

fn nothing(app: &mut App) -> Vec<Effect> {
    app.set_status(StatusKind::Info, "no run kept yet: r runs the model");
    Vec::new()
}

/// A character typed into a run's name.
pub(super) fn name_type(app: &mut App, c: char) {
    if let Mode::Naming { buffer, .. } = &mut app.mode
        && !c.is_control()
        && buffer.chars().count() < NAME_MAX
    {
        buffer.push(c);
    }
}

/// `Enter` while naming: the name kept (an empty one gives back the derived name).
fn name_commit(app: &mut App) -> Vec<Effect> {
    let Mode::Naming { number, buffer } = std::mem::replace(&mut app.mode, Mode::Normal) else {
        return Vec::new();
    };
    let base = app.runs.baseline;
    let Some(e) = app.runs.get_mut(number) else {
        return Vec::new();
    };
    let name = buffer.trim();
    if name.is_empty() {
        e.named = false;
        e.name = derived_name(&e.changes, base.filter(|b| *b != number));
    } else {
        e.named = true;
        e.name = name.to_string();
    }
    let s = format!("#{number} named {}", e.name);
    app.set_status(StatusKind::Ok, s);
    store(app, &[number], false, Vec::new())
}
