//! Runs: start, cancel, streamed batches, the end of a run.

use super::runs::keep;
use crate::output::{EventKind, EventRecord, Sample};
use crate::tui::app::{About, App, StatusKind};
use crate::tui::msg::{Effect, RunOutcome};
use crate::tui::runs::data::{RunData, RunStatus};

impl App {
    /// The first run, or the kept run of the same model text shown
    /// ([`super::stored`]'s rule).
    pub fn start(&mut self) -> Vec<Effect> {
        self.start_with(true)
    }
}

/// `r`: rerun the draft.
pub(super) fn rerun(app: &mut App) -> Vec<Effect> {
    if app.scene.is_none() {
        app.set_status(StatusKind::Error, "nothing to run: the model does not load");
        return Vec::new();
    }
    start_run(app)
}

/// `Esc`/`c`: cancel the running simulation.
pub(super) fn cancel(app: &mut App) -> Vec<Effect> {
    match app.current.as_mut() {
        Some(cur) if cur.status == RunStatus::Running => {
            cur.status = RunStatus::Cancelling;
            let (id, token) = (cur.id, cur.token);
            // about the run: its end replaces it
            let lead = match &app.status_about {
                About::Run { id: r, lead } if *r == id => lead.clone(),
                _ => String::new(),
            };
            let about = About::Run {
                id,
                lead: lead.clone(),
            };
            app.say(StatusKind::Info, &lead, format!("cancelling #{id}…"), about);
            vec![Effect::CancelRun { id: token }]
        }
        _ => {
            app.set_status(StatusKind::Info, "no run in progress");
            Vec::new()
        }
    }
}

/// New samples and events of a run (ignored unless it is the current one).
pub(super) fn on_batch(
    app: &mut App,
    run: u64,
    samples: &[Sample],
    events: &[EventRecord],
    t: f64,
) -> Vec<Effect> {
    if let Some(cur) = app.current.as_mut().filter(|c| c.token == run) {
        cur.push(samples, events, t);
        app.generation += 1;
    }
    Vec::new()
}

/// The run starts again at a finer step: its samples and events so far are dropped.
pub(super) fn on_refined(app: &mut App, run: u64, why: String) -> Vec<Effect> {
    let Some(scene) = app.scene.clone() else {
        return Vec::new();
    };
    if let Some(cur) = app.current.as_mut().filter(|c| c.token == run) {
        let (label, token) = (cur.label.clone(), cur.token);
        *cur = RunData::for_scene(cur.id, label.clone(), &scene);
        cur.token = token;
        app.generation += 1;
        app.set_status(StatusKind::Info, format!("{label} runs again: {why}"));
    }
    Vec::new()
}

/// The run going, if any, cancelled and kept in the run list with what it computed.
pub(super) fn supersede(app: &mut App) -> Vec<Effect> {
    let mut fx = Vec::new();
    if let Some(mut cur) = app.current.take_if(|c| c.running()) {
        fx.push(Effect::CancelRun { id: cur.token });
        if !cur.t.is_empty() {
            cur.status = RunStatus::Cancelled;
            fx.extend(keep(app, &cur).0);
        }
    }
    fx
}

/// Starts a run of the current draft (a run still going is cancelled and kept in the run list
/// with what it computed). Its number is that of the kept run (or the run going) of the same
/// model text, which it replaces when it ends; else the next one.
pub(super) fn start_run(app: &mut App) -> Vec<Effect> {
    let Some(scene) = app.scene.clone() else {
        return Vec::new();
    };
    let cursor = app.cursor_time();
    let going = (app.runs.started.as_ref())
        .filter(|(_, text)| *text == app.draft && app.running())
        .map(|(n, _)| *n);
    let same = app.runs.same_text(&app.draft).or(going);
    let mut fx = supersede(app);
    let id = same.unwrap_or_else(|| {
        app.next_run += 1;
        app.next_run - 1
    });
    // the worker's token: the number, unless an earlier model of the session used it
    let token = id.max(app.next_token);
    app.next_token = token + 1;
    app.runs.started = Some((id, app.draft.clone()));
    let label = if app.dirty() {
        format!("#{id} (unsaved edits)")
    } else {
        format!("#{id}")
    };
    let again = if same.is_some() {
        format!(" again: same model text, it replaces the kept #{id} when it ends")
    } else {
        String::new()
    };
    // what was said before (a reload, a merge, the runs reopened) stays in front of the run
    let lead = app.status_lead();
    app.say(
        StatusKind::Info,
        &lead,
        format!("{label} started{again}"),
        About::Run {
            id,
            lead: lead.clone(),
        },
    );
    let mut data = RunData::for_scene(id, label, &scene);
    data.token = token;
    app.current = Some(data);
    let end = app.t_end();
    if let Some((a, b)) = app.zoom
        && (b > end || a >= end)
    {
        app.zoom = None;
    }
    super::view::keep_cursor_on_rerun(app, cursor);
    app.generation += 1;
    fx.push(Effect::StartRun {
        id: token,
        scene: Box::new(scene),
    });
    fx
}

/// The end of a run: its final output, or where it was cancelled or failed.
pub(super) fn on_done(app: &mut App, run: u64, outcome: RunOutcome) -> Vec<Effect> {
    let Some(cur) = app.current.as_mut().filter(|c| c.token == run) else {
        return Vec::new();
    };
    let label = cur.label.clone();
    // the message the run started after, or one said since (a merge or a reload rerunning)
    let lead = match &app.status_about {
        About::Run { id, lead } if *id == run => lead.clone(),
        About::Run { .. } | About::Overlay(_) => String::new(),
        About::Anything => app.status.clone(),
    };
    let about = About::Run {
        id: run,
        lead: lead.clone(),
    };
    let (kind, said) = match outcome {
        RunOutcome::Finished(out) => {
            cur.finish(*out);
            let (imp, st, sl, re) = (
                cur.count(EventKind::Impact),
                cur.count(EventKind::Stick),
                cur.count(EventKind::Slip),
                cur.count(EventKind::Release),
            );
            let keys = match cur.count(EventKind::KeyFailure) {
                0 => String::new(),
                k => format!(", {k} key failures"),
            };
            let t = cur.t_sim;
            (
                StatusKind::Ok,
                format!(
                    "{label} finished at t = {t:.3} s: {imp} impacts, {st} sticks, {sl} slips, {re} releases{keys}"
                ),
            )
        }
        RunOutcome::Cancelled { t } => {
            cur.status = RunStatus::Cancelled;
            (
                StatusKind::Warn,
                format!("{label} cancelled at t = {t:.3} s"),
            )
        }
        RunOutcome::Inaccurate { output, failure } => {
            cur.finish(*output);
            cur.status = RunStatus::Failed(failure.clone());
            (StatusKind::Error, format!("{label} failed: {failure}"))
        }
        RunOutcome::Failed(e) => {
            cur.status = RunStatus::Failed(e.clone());
            (StatusKind::Error, format!("{label} failed: {e}"))
        }
    };
    app.generation += 1;
    let (fx, note) = match app.current.take() {
        Some(cur) => {
            let kept = keep(app, &cur);
            app.current = Some(cur);
            kept
        }
        None => (Vec::new(), None),
    };
    let said = match note {
        Some(note) => format!("{said} · {note}"),
        None => said,
    };
    app.say(kind, &lead, said, about);
    fx
}
