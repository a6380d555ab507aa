//! The results pages: h/l through the studies and then the pages, j/k the contact, mode or
//! record shown, Enter (re)computes the modes or the records of the form's model in a worker,
//! Esc cancels it; the work-precision study's points as they come and `g` its grid.

use crate::precision::Point;
use crate::precision_study::PrecisionTable;
use crate::study_table::{StudyKind, StudyTable};
use crate::tui::app::{App, StatusKind, hash_text};
use crate::tui::keymap::Action;
use crate::tui::msg::{Effect, ResultData, ResultOutcome};
use crate::tui::results::ResultSpec;
use crate::tui::results::{Job, JobState, Page};

/// Entries of the list: the studies, then the pages.
fn entries() -> usize {
    StudyKind::ALL.len() + Page::ALL.len()
}

/// The index of the entry shown in the list of studies and pages.
pub(crate) fn index(app: &App) -> usize {
    match app.results.page {
        Some(p) => StudyKind::ALL.len() + Page::ALL.iter().position(|q| *q == p).unwrap_or(0),
        None => app.studies.selected,
    }
}

/// h/l: the entry before or after (wrapping); a model page not computed for this model
/// starts its computation.
pub(super) fn step(app: &mut App, forward: bool) -> Vec<Effect> {
    let n = entries();
    let i = (index(app) + if forward { 1 } else { n - 1 }) % n;
    let studies = StudyKind::ALL.len();
    if i < studies {
        app.studies.selected = i;
        app.results.page = None;
        return Vec::new();
    }
    let page = Page::ALL[i - studies];
    app.results.page = Some(page);
    app.generation += 1;
    if page.of_model() && !fresh(app, page) {
        return start(app, page);
    }
    Vec::new()
}

/// The page's data is for the form's model as it is now (or being computed for it).
fn fresh(app: &App, page: Page) -> bool {
    let h = hash_text(&app.draft);
    let ok =
        |id_hash: Option<(u64, bool)>| id_hash.is_some_and(|(hash, failed)| hash == h && !failed);
    match page {
        Page::Modes => ok(app
            .results
            .modes
            .as_ref()
            .map(|j| (j.hash, ended_badly(&j.state)))),
        Page::Records => ok(app
            .results
            .records
            .as_ref()
            .map(|j| (j.hash, ended_badly(&j.state)))),
        _ => true,
    }
}

fn ended_badly<T>(s: &JobState<T>) -> bool {
    matches!(s, JobState::Cancelled | JobState::Failed(_))
}

/// Starts the computation of a model page on the form's model (its unsaved edits included).
pub(super) fn start(app: &mut App, page: Page) -> Vec<Effect> {
    let busy = match page {
        Page::Modes => app.results.modes.as_ref().is_some_and(Job::running),
        _ => app.results.records.as_ref().is_some_and(Job::running),
    };
    if busy {
        app.set_status(
            StatusKind::Warn,
            "this page is computing: Esc cancels it first",
        );
        return Vec::new();
    }
    let Some(scene) = app.scene.clone() else {
        app.set_status(
            StatusKind::Error,
            "the model does not load: nothing to compute",
        );
        return Vec::new();
    };
    app.results.next_id += 1;
    let id = app.results.next_id;
    let hash = hash_text(&app.draft);
    let (spec, what) = match page {
        Page::Modes => {
            app.results.modes = Some(Job {
                id,
                hash,
                state: JobState::Running { done: 0, all: 0 },
            });
            (ResultSpec::Modes(Box::new(scene)), "modes")
        }
        Page::Records => {
            app.results.records = Some(Job {
                id,
                hash,
                state: JobState::Running { done: 0, all: 0 },
            });
            (
                ResultSpec::Records(Box::new(scene)),
                "input records and their spectrum",
            )
        }
        _ => return Vec::new(),
    };
    app.generation += 1;
    app.set_status(
        StatusKind::Info,
        format!("computing the {what} of the form's model…"),
    );
    vec![Effect::StartResult {
        id,
        spec: Box::new(spec),
    }]
}

/// Esc on a results page: cancels the page's computation (else any running); None when
/// none runs.
pub(super) fn cancel(app: &mut App) -> Option<Vec<Effect>> {
    let r = &app.results;
    r.page?;
    let shown = match r.page {
        Some(Page::Modes) => r.modes.as_ref().filter(|j| j.running()).map(|j| j.id),
        Some(Page::Records) => r.records.as_ref().filter(|j| j.running()).map(|j| j.id),
        _ => None,
    };
    let id = shown.or(r.running_id())?;
    set_state(app, id, JobState::Cancelling, JobState::Cancelling);
    app.set_status(StatusKind::Info, "cancelling the results computation…");
    Some(vec![Effect::CancelResult { id }])
}

/// The keys of the results pages (j/k, g) and Enter on a page.
pub(super) fn action(app: &mut App, a: Action) -> Vec<Effect> {
    let r = &mut app.results;
    let down = a == Action::ResultDown;
    let bump = |i: &mut usize, n: usize| {
        let n = n.max(1);
        *i = if down { (*i + 1) % n } else { (*i + n - 1) % n };
    };
    match (a, r.page) {
        (Action::ResultGrid, _) => {
            r.grid = !r.grid;
            if r.page.is_none() {
                app.studies.selected = crate::tui::studies::Studies::index_of(StudyKind::Precision);
            }
        }
        (Action::ResultUp | Action::ResultDown, None) => {
            // the rows of the ladder's and the swings' tables
            super::design::step_row(app, down);
            return Vec::new();
        }
        (Action::ResultUp | Action::ResultDown, Some(Page::Contacts)) => {
            let n = app.current.as_ref().map_or(0, |c| c.contact_names.len());
            bump(&mut r.contact, n);
        }
        (Action::ResultUp | Action::ResultDown, Some(Page::Modes)) => {
            let n = match r.modes.as_ref().map(|j| &j.state) {
                Some(JobState::Ready(m)) => m.periods.len(),
                _ => 0,
            };
            bump(&mut r.mode, n);
        }
        (Action::ResultUp | Action::ResultDown, Some(Page::Records)) => {
            let n = match r.records.as_ref().map(|j| &j.state) {
                Some(JobState::Ready(d)) => d.components.len(),
                _ => 0,
            };
            bump(&mut r.record, n);
        }
        (Action::StudyRun, Some(p)) if p.of_model() => return start(app, p),
        (Action::StudyRun, Some(_)) => app.set_status(
            StatusKind::Info,
            "this page shows the current run: r reruns it",
        ),
        _ => {}
    }
    app.generation += 1;
    Vec::new()
}

/// The work-precision study's plan on the form's model (None: it does not compile).
pub(super) fn precision_plan(app: &App) -> Option<StudyTable> {
    let s = app.scene.as_ref()?;
    let (t_end, k) = (s.settings.t_end, s.settings.contact_stiffness);
    Some(StudyTable::Precision(PrecisionTable::plan(t_end, k)))
}

/// A point of work-precision study `id` is final.
pub(super) fn on_point(app: &mut App, id: u64, index: usize, point: Point) -> Vec<Effect> {
    if let Some(e) = app.studies.by_id(id).filter(|e| e.running())
        && let Some(StudyTable::Precision(t)) = &mut e.table
        && t.record(index, point)
    {
        app.generation += 1;
    }
    Vec::new()
}

/// Progress of computation `id`.
pub(super) fn on_progress(app: &mut App, id: u64, done: usize, all: usize) -> Vec<Effect> {
    let r = &mut app.results;
    if let Some(j) = r
        .modes
        .as_mut()
        .filter(|j| j.id == id && matches!(j.state, JobState::Running { .. }))
    {
        j.state = JobState::Running { done, all };
    }
    if let Some(j) = r
        .records
        .as_mut()
        .filter(|j| j.id == id && matches!(j.state, JobState::Running { .. }))
    {
        j.state = JobState::Running { done, all };
    }
    app.generation += 1;
    Vec::new()
}

/// The end of computation `id`.
pub(super) fn on_done(app: &mut App, id: u64, outcome: ResultOutcome) -> Vec<Effect> {
    let r = &mut app.results;
    let (status, msg) = match outcome {
        ResultOutcome::Done(ResultData::Modes(m)) => {
            match r.modes.as_mut().filter(|j| j.id == id) {
                Some(j) => {
                    let t1 = m.periods.first().copied().unwrap_or(f64::NAN);
                    let msg = format!(
                        "modes: {} modes, T1 = {} s",
                        m.periods.len(),
                        crate::tui::chart::fmt_sig(t1, 4)
                    );
                    r.mode = r.mode.min(m.periods.len().saturating_sub(1));
                    j.state = JobState::Ready(*m);
                    (StatusKind::Ok, msg)
                }
                None => return Vec::new(),
            }
        }
        ResultOutcome::Done(ResultData::Records(d)) => {
            match r.records.as_mut().filter(|j| j.id == id) {
                Some(j) => {
                    let msg = format!(
                        "input records: {} components with their 5 % spectrum",
                        d.components.len()
                    );
                    r.record = r.record.min(d.components.len().saturating_sub(1));
                    j.state = JobState::Ready(*d);
                    (StatusKind::Ok, msg)
                }
                None => return Vec::new(),
            }
        }
        ResultOutcome::Cancelled => {
            set_state(app, id, JobState::Cancelled, JobState::Cancelled);
            (
                StatusKind::Warn,
                "results computation cancelled: Enter computes it again".into(),
            )
        }
        ResultOutcome::Failed(why) => {
            let msg = format!("results computation failed: {why}");
            set_state(
                app,
                id,
                JobState::Failed(why.clone()),
                JobState::Failed(why),
            );
            (StatusKind::Error, msg)
        }
    };
    app.generation += 1;
    app.set_status(status, msg);
    Vec::new()
}

fn set_state(
    app: &mut App,
    id: u64,
    modes: JobState<crate::tui::results::ModesData>,
    records: JobState<crate::tui::results::RecordsData>,
) {
    let r = &mut app.results;
    if let Some(j) = r.modes.as_mut().filter(|j| j.id == id) {
        j.state = modes;
    }
    if let Some(j) = r.records.as_mut().filter(|j| j.id == id) {
        j.state = records;
    }
}
