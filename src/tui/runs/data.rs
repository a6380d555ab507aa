//! The charted history of one run, in columns, with the engine's running summary
//! ([`Tally`]) of its samples.

use crate::output::{ContactState, EventKind, EventRecord, RunOutput, Sample, Summary, Tally};
use crate::run::SolverError;
use crate::scene::Scene;
use crate::tui::results::run::RunResults;
use std::sync::Arc;

/// A token for a run's data read back from disk: above any a worker is started with.
pub fn fresh_token() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1 << 40);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

/// Why a workbench run failed: the engine's typed error, or the end of its worker thread.
#[derive(Debug, thiserror::Error)]
pub enum RunFailure {
    #[error(transparent)]
    Solver(#[from] SolverError),
    #[error("the engine panicked: {0}")]
    Panic(String),
    #[error("cannot start a worker thread: {0}")]
    Thread(String),
    #[error(
        "t = {t:.9} s: the run's output comes to {rows:.3e} rows, more than the workbench keeps in memory ({limit:e}): raise solver.output_dt or lower solver.t_end (`deckspin run` streams its history to disk)"
    )]
    Memory { rows: f64, limit: f64, t: f64 },
}

/// Two failures are the same when they say the same.
impl PartialEq for RunFailure {
    fn eq(&self, other: &Self) -> bool {
        self.to_string() == other.to_string()
    }
}

#[derive(Clone, Debug, PartialEq)]
pub enum RunStatus {
    Running,
    Cancelling,
    Finished,
    Cancelled,
    Failed(Arc<RunFailure>),
}

/// The charted history of one run, in columns.
#[derive(Clone, Debug)]
pub struct RunData {
    /// The run's number in the run list (`#N`, numbered per model).
    pub id: u64,
    /// What its worker's messages carry and the drawing caches key on: unique in the session
    /// (the number, unless another model opened with `O` used it; [`fresh_token`] for a run
    /// read back from disk).
    pub token: u64,
    /// "#3" or "#3 (unsaved edits)" (the workbench's run number, not the test run).
    pub label: String,
    pub dof_names: Vec<String>,
    pub contact_names: Vec<String>,
    pub element_names: Vec<String>,
    pub t: Vec<f64>,
    pub q: Vec<Vec<f64>>,
    /// Velocities per DOF (none in a kept run, [`crate::tui::runs::list::thin`]).
    pub v: Vec<Vec<f64>>,
    pub gap: Vec<Vec<f64>>,
    /// Gap rate and slip rate per contact (none in a kept run).
    pub gap_rate: Vec<Vec<f64>>,
    pub slip_rate: Vec<Vec<f64>>,
    /// (contact, gap at which it leaves its seat) of each seat.
    pub seats: Vec<(usize, f64)>,
    pub state: Vec<Vec<ContactState>>,
    /// (deformation, force) columns per hysteretic element.
    pub el: Vec<(Vec<f64>, Vec<f64>)>,
    pub events: Vec<EventRecord>,
    pub t_sim: f64,
    pub t_end: f64,
    pub status: RunStatus,
    pub summary: Option<Summary>,
    pub steps: Option<usize>,
    /// Peaks, residuals, minimum gaps and stick times of the samples so far.
    pub tally: Tally,
    /// Impacts per contact so far.
    pub impacts: Vec<usize>,
    /// (min, max) of deformation and force per element, so far.
    pub el_range: Vec<[f64; 4]>,
    /// Index of the charted rotation DOF and of the x/y DOFs.
    pub rot: Option<usize>,
    pub xy: Vec<usize>,
    /// The energy ledger and the contact forces (the results pages).
    pub results: RunResults,
}

/// The rotation to chart: `deck.theta`, else that of the first body free in x, y and θ (a
/// bridge's first frame, not an abutment), else the first `*.theta`, else the first DOF.
pub fn rotation_dof(names: &[String]) -> Option<usize> {
    names
        .iter()
        .position(|n| n == "deck.theta")
        .or_else(|| crate::studies::free_body_rotation(names))
        .or_else(|| names.iter().position(|n| n.ends_with(".theta")))
        .or(if names.is_empty() { None } else { Some(0) })
}

/// The translations to chart: x and y of the rotation's body, else the first DOFs.
pub fn xy_dofs(names: &[String], rot: Option<usize>) -> Vec<usize> {
    let body = rot
        .and_then(|r| names[r].rsplit_once('.'))
        .map(|(b, _)| b.to_string())
        .unwrap_or_default();
    let found: Vec<usize> = ["x", "y"]
        .iter()
        .filter_map(|a| names.iter().position(|n| *n == format!("{body}.{a}")))
        .filter(|&i| Some(i) != rot)
        .collect();
    if !found.is_empty() {
        return found;
    }
    (0..names.len())
        .filter(|&i| Some(i) != rot)
        .take(2)
        .collect()
}

impl RunData {
    pub fn new(
        id: u64,
        label: String,
        dof_names: Vec<String>,
        contact_names: Vec<String>,
        element_names: Vec<String>,
        t_end: f64,
    ) -> Self {
        let rot = rotation_dof(&dof_names);
        let xy = xy_dofs(&dof_names, rot);
        let nc = contact_names.len();
        Self {
            id,
            token: id,
            label,
            q: vec![Vec::new(); dof_names.len()],
            v: vec![Vec::new(); dof_names.len()],
            gap: vec![Vec::new(); nc],
            gap_rate: vec![Vec::new(); nc],
            slip_rate: vec![Vec::new(); nc],
            seats: Vec::new(),
            state: vec![Vec::new(); nc],
            el: vec![(Vec::new(), Vec::new()); element_names.len()],
            el_range: vec![
                [
                    f64::INFINITY,
                    f64::NEG_INFINITY,
                    f64::INFINITY,
                    f64::NEG_INFINITY
                ];
                element_names.len()
            ],
            tally: Tally::default(),
            impacts: vec![0; nc],
            dof_names,
            contact_names,
            element_names,
            t: Vec::new(),
            events: Vec::new(),
            t_sim: 0.0,
            t_end,
            status: RunStatus::Running,
            summary: None,
            steps: None,
            rot,
            xy,
            results: RunResults::new(nc),
        }
    }

    pub fn for_scene(id: u64, label: String, scene: &Scene) -> Self {
        let mut d = Self::new(
            id,
            label,
            scene.dof_names.clone(),
            scene.contacts.iter().map(|c| c.name.clone()).collect(),
            scene.hysteretic.iter().map(|h| h.name.clone()).collect(),
            scene.settings.t_end,
        );
        d.seats = scene.seats.iter().map(|s| (s.contact, s.edge)).collect();
        d
    }

    /// Appends samples and events (one observer batch).
    pub fn push(&mut self, samples: &[Sample], events: &[EventRecord], t: f64) {
        for s in samples {
            self.tally.add(&s.view());
            self.results.push(s);
            self.t.push(s.t);
            for (k, col) in self.q.iter_mut().enumerate() {
                col.push(s.q.get(k).copied().unwrap_or(f64::NAN));
            }
            for (k, col) in self.v.iter_mut().enumerate() {
                col.push(s.v.get(k).copied().unwrap_or(f64::NAN));
            }
            for (i, c) in s.contacts.iter().enumerate().take(self.gap.len()) {
                self.gap[i].push(c.gap);
                self.state[i].push(c.state);
                self.gap_rate[i].push(c.gap_rate);
                self.slip_rate[i].push(c.slip_rate);
            }
            for (j, &(d, f)) in s.elements.iter().enumerate().take(self.el.len()) {
                self.el[j].0.push(d);
                self.el[j].1.push(f);
                let r = &mut self.el_range[j];
                if d.is_finite() && f.is_finite() {
                    *r = [r[0].min(d), r[1].max(d), r[2].min(f), r[3].max(f)];
                }
            }
        }
        for e in events {
            if e.kind == EventKind::Impact
                && let Some(n) = self.impacts.get_mut(e.contact)
            {
                *n += 1;
            }
        }
        self.events.extend_from_slice(events);
        if let Some(&tl) = self.t.last() {
            self.t_sim = self.t_sim.max(tl);
        }
        self.t_sim = self.t_sim.max(t.min(self.t_end));
    }

    /// Takes the final output of a run (its samples replace the streamed ones if they differ).
    pub fn finish(&mut self, out: RunOutput) {
        if out.samples.len() != self.t.len() || out.events.len() != self.events.len() {
            let mut fresh = RunData::new(
                self.id,
                self.label.clone(),
                out.dof_names.clone(),
                out.contact_names.clone(),
                out.element_names.clone(),
                self.t_end,
            );
            fresh.seats = std::mem::take(&mut self.seats);
            fresh.push(&out.samples, &out.events, out.summary.t_end);
            fresh.token = self.token;
            *self = fresh;
        }
        self.t_sim = out.summary.t_end.max(self.t_sim);
        self.steps = Some(out.summary.stats.steps_accepted);
        self.summary = Some(out.summary);
        self.status = RunStatus::Finished;
    }

    pub fn running(&self) -> bool {
        matches!(self.status, RunStatus::Running | RunStatus::Cancelling)
    }

    pub fn count(&self, kind: EventKind) -> usize {
        self.events.iter().filter(|e| e.kind == kind).count()
    }

    /// Index of a DOF, contact or element column by name.
    pub fn dof(&self, name: &str) -> Option<usize> {
        self.dof_names.iter().position(|n| n == name)
    }

    /// Name of the charted rotation DOF ("" without DOFs).
    pub fn rot_name(&self) -> &str {
        self.rot.map_or("", |r| self.dof_names[r].as_str())
    }

    /// Peak |q| of DOF `k` over the samples so far.
    pub fn q_peak(&self, k: usize) -> f64 {
        self.tally.peaks.get(k).map_or(0.0, |p| p.0)
    }

    /// Peak |rotation| and its time ([`RunData::dof_peak`] of the charted rotation).
    pub fn peak_rot(&self) -> (f64, f64) {
        self.rot.map_or((0.0, 0.0), |r| self.dof_peak(r))
    }

    /// Peak |q| of DOF `k` and its time over the samples so far; once finished, the engine's
    /// peak if larger (it also sees the dense output between samples).
    pub fn dof_peak(&self, k: usize) -> (f64, f64) {
        let mut p = self.tally.peaks.get(k).map_or((0.0, 0.0), |p| (p.0, p.1));
        if let Some(d) = (self.summary.as_ref())
            .and_then(|s| s.peaks.iter().find(|d| d.name == self.dof_names[k]))
            && d.max_abs > p.0
        {
            p = (d.max_abs, d.at);
        }
        p
    }

    /// Over the deck's bodies when it has several (a bridge's frames,
    /// [`crate::output::deck::deck_bodies`]): the largest peak |θ| and the body's name.
    pub fn peak_rot_of_frames(&self) -> Option<(f64, String)> {
        let bodies = crate::output::deck::deck_bodies(&self.dof_names);
        if bodies.len() < 2 {
            return None;
        }
        (bodies.iter())
            .map(|b| (self.dof_peak(b[2]).0, b[2]))
            .max_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(p, k)| {
                let name = &self.dof_names[k];
                (p, name.strip_suffix(".theta").unwrap_or(name).to_string())
            })
    }

    /// Rotation at the last sample.
    pub fn residual_rot(&self) -> f64 {
        self.rot
            .and_then(|r| self.tally.last_q.get(r).copied())
            .unwrap_or(0.0)
    }

    /// Stick time of contact `i` so far, s.
    pub fn stick_time(&self, i: usize) -> f64 {
        self.tally.contacts.get(i).map_or(0.0, |c| c.stick_time)
    }

    /// Minimum gap of contact `i` so far (∞ before its first sample).
    pub fn min_gap_of(&self, i: usize) -> f64 {
        self.tally
            .contacts
            .get(i)
            .map_or(f64::INFINITY, |c| c.min_gap)
    }

    pub fn total_impacts(&self) -> usize {
        self.impacts.iter().sum()
    }

    pub fn total_stick_time(&self) -> f64 {
        (0..self.contact_names.len())
            .map(|i| self.stick_time(i))
            .sum()
    }

    /// Smallest gap of all contacts so far.
    pub fn min_gap(&self) -> f64 {
        (0..self.contact_names.len())
            .map(|i| self.min_gap_of(i))
            .fold(f64::INFINITY, f64::min)
    }
}
