//! Stored runs shown without running. The rule: a run is stored once per model text. At the
//! start, on opening a model (`O`) and on a save or a reload, a kept run whose model text is
//! the draft's and that ended by itself (finished, inexact or failed: the same text gives the
//! same result) is shown instead of running again (`#4 reused: same model text`); `r` always
//! runs, under the number of the kept run of the same text, which it replaces when it ends (a
//! cancelled rerun does not replace a run that ended by itself). A kept run's series are read
//! from its file when it is shown or overlaid.

use super::run::{start_run, supersede};
use crate::tui::app::{About, App, StatusKind};
use crate::tui::msg::Effect;
use crate::tui::runs::data::RunData;
use crate::tui::runs::list::Series;
use crate::tui::runs::store as run_store;
use std::path::PathBuf;

/// What an automatic run did: reused run `n`, or started one.
pub(crate) enum Ran {
    Reused(u64),
    Started,
}

impl Ran {
    /// For the status line after `what` (`saved …`, `reloaded …`).
    pub(crate) fn say(&self, what: String) -> String {
        match self {
            Ran::Reused(n) => format!("{what} — #{n} reused: same model text (r reruns it)"),
            Ran::Started => format!("{what} — rerunning"),
        }
    }
}

/// Runs the draft, or shows the kept run of the same model text (see the module's rule).
pub(crate) fn run_or_reuse(app: &mut App) -> (Vec<Effect>, Ran) {
    match app.runs.reusable(&app.draft) {
        Some(n) => {
            let mut fx = supersede(app);
            fx.extend(show(app, n));
            // what was said before (the runs reopened, a reload) stays in front of it
            let lead = app.status_lead();
            app.say(
                StatusKind::Ok,
                &lead,
                format!("#{n} reused: same model text (r reruns it)"),
                About::Anything,
            );
            (fx, Ran::Reused(n))
        }
        None => (start_run(app), Ran::Started),
    }
}

/// Shows kept run `n` on the charts and selects it in the run list (its series asked for
/// when still on disk).
pub(crate) fn show(app: &mut App, n: u64) -> Vec<Effect> {
    let Some(i) = app.runs.list.iter().position(|e| e.number == n) else {
        return Vec::new();
    };
    let mut d = app.runs.list[i].data.clone();
    d.label = format!("#{n}");
    app.current = Some(d);
    app.runs.selected = i;
    app.follow = true;
    app.zoom = None;
    app.event_sel = None;
    app.generation += 1;
    want_series(app)
}

/// The kept runs whose series are needed (the baseline, the overlaid runs, the shown run) and
/// still on disk: asked for.
pub(crate) fn want_series(app: &mut App) -> Vec<Effect> {
    let Some(dir) = app.runs.dir.clone() else {
        return Vec::new();
    };
    let shown = app.current.as_ref().map(|c| c.token);
    let base = app.runs.baseline;
    let mut runs = Vec::new();
    for e in &mut app.runs.list {
        let needed = Some(e.number) == base || e.overlay || Some(e.data.token) == shown;
        if needed && e.series == Series::OnDisk {
            e.series = Series::Asked;
            runs.push((e.number, e.data.t_end));
        }
    }
    if runs.is_empty() {
        Vec::new()
    } else {
        vec![Effect::LoadSeries { dir, runs }]
    }
}

/// Series read back: into their runs (and onto the charts when shown).
pub(super) fn on_loaded(
    app: &mut App,
    dir: PathBuf,
    loaded: Vec<(u64, Result<RunData, String>)>,
) -> Vec<Effect> {
    if app.runs.dir.as_ref() != Some(&dir) {
        // another model's, opened before
        return Vec::new();
    }
    let mut bad = Vec::new();
    for (n, r) in loaded {
        let Some(e) = app.runs.get_mut(n).filter(|e| e.series == Series::Asked) else {
            continue;
        };
        match r {
            Ok(mut d) => {
                d.token = e.data.token;
                run_store::stored_status(&mut d, &e.ended, e.results.t_sim);
                e.data = d;
                e.series = Series::InMemory;
                let data = e.data.clone();
                if let Some(cur) = app.current.as_mut().filter(|c| c.token == data.token) {
                    let label = std::mem::take(&mut cur.label);
                    *cur = data;
                    cur.label = label;
                }
                app.generation += 1;
            }
            Err(why) => {
                e.series = Series::Unreadable(why.clone());
                bad.push(format!("#{n}: {why}"));
            }
        }
    }
    if !bad.is_empty() {
        app.set_status(
            StatusKind::Warn,
            format!("a kept run's series do not read: {}", bad.join("; ")),
        );
    }
    Vec::new()
}

impl App {
    /// The start: the draft run, or the kept run of the same model text shown (see the
    /// module's rule); with `run` false (`--no-run`) nothing runs: the kept run of the same
    /// text is shown when there is one.
    pub fn start_with(&mut self, run: bool) -> Vec<Effect> {
        if self.scene.is_none() {
            return Vec::new();
        }
        let mut fx = if run {
            run_or_reuse(self).0
        } else {
            match self.runs.reusable(&self.draft) {
                Some(n) => {
                    let fx = show(self, n);
                    self.set_status(
                        StatusKind::Ok,
                        format!("#{n} shown: same model text, not run (r runs it)"),
                    );
                    fx
                }
                None => {
                    self.runs.selected = self.runs.list.len().saturating_sub(1);
                    let s = format!("{} not run (--no-run): r runs it", self.file_name());
                    self.set_status(StatusKind::Info, s);
                    Vec::new()
                }
            }
        };
        fx.extend(want_series(self));
        // diffs computed at the opening: stored with their runs for the next one
        let rediffed = std::mem::take(&mut self.runs_rediffed);
        fx.extend(super::runs::store(self, &rediffed, false, Vec::new()));
        fx
    }
}
