//! Run results: time history (output grid plus every event instant), event log, energy ledger
//! and summary; writers for `history.csv`, `events.csv` and `summary.json`.

use crate::hysteresis::{Hysteretic, Law};
use crate::scene::Scene;
use serde::Serialize;
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

pub mod deck;
pub mod files;
mod history;
pub mod number;
pub mod series;
mod summary;

pub use history::{HistoryColumn, HistoryWriter, history_columns};
pub use summary::{ContactSummary, DofPeak, RunStats, SeatSummary, Summary};

/// State of one contact.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum ContactState {
    /// No force: g_N > 0, or released.
    Open,
    /// Sticking (ġ_T = 0), or the transition to it.
    Stick,
    /// Closed and sliding with ġ_T of this sign (0: frictionless).
    Slide(f64),
}

impl ContactState {
    /// Its name in outputs (`open`, `stick`, `slide`).
    pub fn label(&self) -> &'static str {
        match self {
            ContactState::Open => "open",
            ContactState::Stick => "stick",
            ContactState::Slide(s) if *s > 0.0 => "slide+",
            ContactState::Slide(s) if *s < 0.0 => "slide-",
            ContactState::Slide(_) => "slide",
        }
    }
}

/// Where a sample was taken.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum SampleKind {
    /// On the output grid.
    Grid,
    /// Just before an event.
    PreEvent,
    /// Just after an event.
    PostEvent,
}

impl SampleKind {
    /// Its name in history.csv's `row` column.
    pub fn label(&self) -> &'static str {
        match self {
            SampleKind::Grid => "grid",
            SampleKind::PreEvent => "pre-event",
            SampleKind::PostEvent => "post-event",
        }
    }
}

/// A contact at a sample.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct ContactSample {
    /// g_N, m.
    pub gap: f64,
    /// ġ_N.
    pub gap_rate: f64,
    /// ġ_T.
    pub slip_rate: f64,
    /// λ_N, λ_T (continuous contact forces; 0 when open).
    pub normal_force: f64,
    /// λ_T.
    pub tangential_force: f64,
    /// Open, stick or slide.
    pub state: ContactState,
}

/// Energy ledger at one instant. Balance: T + V + W_hyst + D_damp + D_fric + D_imp
/// = E₀ + W_loads + W_supports.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct EnergySample {
    /// Kinetic energy T.
    pub kinetic: f64,
    /// Linear springs ½ k e².
    pub elastic: f64,
    /// Work of the constant loads.
    pub loads: f64,
    /// Work delivered by the moving supports.
    pub supports: f64,
    /// Energy dissipated in the dashpots and by mass-proportional damping.
    pub damping: f64,
    /// Work absorbed by hysteretic elements (stored + dissipated).
    pub hysteretic: f64,
    /// Dissipated by contact forces during continuous contact (sliding friction).
    pub friction: f64,
    /// Lost in impacts, normal and tangential parts (Λᵀ(ġ⁺ + ġ⁻)/2).
    pub impact_normal: f64,
    /// Energy change by the tangential impulses.
    pub impact_tangential: f64,
    /// The initial energy.
    pub initial: f64,
    /// Left minus right side of the balance.
    pub closure: f64,
}

impl EnergySample {
    /// Every term finite (none overflowed).
    pub fn is_finite(&self) -> bool {
        [
            self.kinetic,
            self.elastic,
            self.loads,
            self.supports,
            self.damping,
            self.hysteretic,
            self.friction,
            self.impact_normal,
            self.impact_tangential,
            self.initial,
            self.closure,
        ]
        .iter()
        .all(|x| x.is_finite())
    }

    /// The closure: what the ledger does not account for (0 for an exact run).
    pub fn balance(&self) -> f64 {
        (self.kinetic
            + self.elastic
            + self.hysteretic
            + self.damping
            + self.friction
            + self.impact_normal
            + self.impact_tangential)
            - (self.initial + self.loads + self.supports)
    }
    /// The energy scale the closure is measured against.
    pub fn scale(&self) -> f64 {
        self.kinetic
            + self.elastic
            + self.hysteretic.abs()
            + self.damping.abs()
            + self.friction.abs()
            + self.impact_normal.abs()
            + self.impact_tangential.abs()
            + self.initial.abs()
            + self.loads.abs()
            + self.supports.abs()
    }
}

/// The state at one instant of the output.
#[derive(Clone, Debug, Serialize)]
pub struct Sample {
    /// Time, s.
    pub t: f64,
    /// What kind.
    pub kind: SampleKind,
    /// Positions q.
    pub q: Vec<f64>,
    /// Velocities q̇.
    pub v: Vec<f64>,
    /// Per contact.
    pub contacts: Vec<ContactSample>,
    /// (deformation, force) of each hysteretic element.
    pub elements: Vec<(f64, f64)>,
    /// The energy ledger.
    pub energy: EnergySample,
}

/// What happened at an event of the log.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum EventKind {
    /// An impact.
    Impact,
    /// Sticking (ġ_T = 0), or the transition to it.
    Stick,
    /// The transition from stick to slip.
    Slip,
    /// A detachment.
    Release,
    /// An accumulation of impacts closed by the rule.
    Accumulation,
    /// A shear key's deformation beyond its gap reached its failure displacement (hysteresis
    /// rule G5): `EventRecord::contact` is the hysteretic element's index.
    KeyFailure,
}

impl EventKind {
    /// Its name in events.csv.
    pub fn label(&self) -> &'static str {
        match self {
            EventKind::Impact => "impact",
            EventKind::Stick => "stick",
            EventKind::Slip => "slip",
            EventKind::Release => "release",
            EventKind::Accumulation => "accumulation",
            EventKind::KeyFailure => "key failure",
        }
    }

    /// An event of a contact (all but a key failure, which is a hysteretic element's).
    pub fn of_contact(&self) -> bool {
        *self != EventKind::KeyFailure
    }
}

/// An event of the log (events.csv).
#[derive(Clone, Debug, Serialize)]
pub struct EventRecord {
    /// Time, s.
    pub t: f64,
    /// The contact's index (a key failure: the hysteretic element's).
    pub contact: usize,
    /// What kind.
    pub kind: EventKind,
    /// Λ_N, Λ_T for impacts (N·s).
    pub normal: f64,
    /// Λ_T.
    pub tangential: f64,
    /// ġ_N⁻.
    pub gap_rate_before: f64,
    /// ġ_N⁺.
    pub gap_rate_after: f64,
    /// ġ_T⁺.
    pub slip_rate_after: f64,
    /// After the event: does the contact stick?
    pub sticks: Option<bool>,
    /// Accumulation events: estimated accumulation time t∞.
    pub info: f64,
}

impl EventRecord {
    /// The failure of key `element` at `t`: no impulse, no contact rates.
    pub(crate) fn key_failure(t: f64, element: usize) -> Self {
        Self {
            t,
            contact: element,
            kind: EventKind::KeyFailure,
            normal: 0.0,
            tangential: 0.0,
            gap_rate_before: f64::NAN,
            gap_rate_after: f64::NAN,
            slip_rate_after: f64::NAN,
            sticks: None,
            info: f64::NAN,
        }
    }
}

/// A shear key that failed: its hysteretic element, when, and the largest force it carried.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct KeyFailure {
    /// The element's name.
    pub element: String,
    /// Time, s.
    pub t: f64,
    /// The largest force it carried.
    pub peak_force: f64,
}

/// The event log as CSV (events.csv): one row per event, impulses for impacts; the `contact`
/// column of a key failure names its hysteretic element.
pub fn events_csv(
    events: &[EventRecord],
    contact_names: &[String],
    element_names: &[String],
) -> String {
    use std::fmt::Write as _;
    let mut out = String::from(
        "t,contact,kind,normal_impulse,tangential_impulse,gap_rate_before,gap_rate_after,slip_rate_after,sticks,accumulation_time\n",
    );
    for e in events {
        let _ = writeln!(
            out,
            "{:.15e},{},{},{:.12e},{:.12e},{:.12e},{:.12e},{:.12e},{},{}",
            e.t,
            (if e.kind.of_contact() {
                contact_names
            } else {
                element_names
            })
            .get(e.contact)
            .map_or("?", String::as_str),
            e.kind.label(),
            e.normal,
            e.tangential,
            e.gap_rate_before,
            e.gap_rate_after,
            e.slip_rate_after,
            e.sticks.map_or("", |s| if s { "stick" } else { "slip" }),
            if e.info.is_finite() {
                format!("{:.15e}", e.info)
            } else {
                String::new()
            }
        );
    }
    out
}

/// One sample as the engine measures it, borrowed from its buffers.
#[derive(Clone, Copy, Debug)]
pub struct SampleView<'a> {
    /// Time, s.
    pub t: f64,
    /// What kind.
    pub kind: SampleKind,
    /// Positions q.
    pub q: &'a [f64],
    /// Velocities q̇.
    pub v: &'a [f64],
    /// Per contact.
    pub contacts: &'a [ContactSample],
    /// (deformation, force) per hysteretic element.
    pub elements: &'a [(f64, f64)],
    /// The energy ledger.
    pub energy: EnergySample,
}

impl Sample {
    /// The sample as a view (what the running summary reads).
    pub fn view(&self) -> SampleView<'_> {
        SampleView {
            t: self.t,
            kind: self.kind,
            q: &self.q,
            v: &self.v,
            contacts: &self.contacts,
            elements: &self.elements,
            energy: self.energy,
        }
    }
}

/// Running extremes of one contact over the samples.
#[derive(Clone, Copy, Debug)]
pub struct ContactTally {
    /// Smallest g_N, m.
    pub min_gap: f64,
    /// Largest g_N, m.
    pub max_gap: f64,
    /// When g_N was largest, s.
    pub max_gap_at: f64,
    /// Largest λ_N.
    pub max_normal_force: f64,
    /// Smallest λ_N.
    pub min_normal_force: f64,
    /// Time stuck, s.
    pub stick_time: f64,
    /// Time sliding, s.
    pub slide_time: f64,
    /// State at the previous sample (it holds until the next one).
    state: ContactState,
}

/// The summary of the samples recorded so far, updated sample by sample, so that a run that
/// keeps no history (a sweep's) still reports its peaks, residuals and contact times.
#[derive(Clone, Debug, Default)]
pub struct Tally {
    /// (max |q|, its time, max |q̇|) per DOF.
    pub peaks: Vec<(f64, f64, f64)>,
    /// Per contact.
    pub contacts: Vec<ContactTally>,
    /// Largest |energy balance| of a sample.
    pub closure: f64,
    /// Time of the last sample.
    pub last_t: Option<f64>,
    /// q of the last sample.
    pub last_q: Vec<f64>,
    /// The ledger of the last sample.
    pub last_energy: EnergySample,
}

impl Tally {
    /// The sample `s` into the running extremes.
    pub fn add(&mut self, s: &SampleView) {
        if self.peaks.len() != s.q.len() {
            self.peaks.resize(s.q.len(), (0.0, 0.0, 0.0));
        }
        for ((p, q), v) in self.peaks.iter_mut().zip(s.q).zip(s.v) {
            if q.abs() > p.0 {
                p.0 = q.abs();
                p.1 = s.t;
            }
            p.2 = p.2.max(v.abs());
        }
        if self.contacts.len() != s.contacts.len() {
            self.contacts.resize(
                s.contacts.len(),
                ContactTally {
                    min_gap: f64::INFINITY,
                    max_gap: f64::NEG_INFINITY,
                    max_gap_at: 0.0,
                    max_normal_force: 0.0,
                    min_normal_force: 0.0,
                    stick_time: 0.0,
                    slide_time: 0.0,
                    state: ContactState::Open,
                },
            );
        }
        for (c, x) in self.contacts.iter_mut().zip(s.contacts) {
            c.min_gap = c.min_gap.min(x.gap);
            if x.gap > c.max_gap {
                (c.max_gap, c.max_gap_at) = (x.gap, s.t);
            }
            c.max_normal_force = c.max_normal_force.max(x.normal_force);
            c.min_normal_force = c.min_normal_force.min(x.normal_force);
            if let Some(t0) = self.last_t {
                let dt = s.t - t0;
                match c.state {
                    ContactState::Stick => c.stick_time += dt,
                    ContactState::Slide(_) => c.slide_time += dt,
                    ContactState::Open => {}
                }
            }
            c.state = x.state;
        }
        self.closure = self.closure.max(s.energy.closure.abs());
        self.last_t = Some(s.t);
        self.last_q.clear();
        self.last_q.extend_from_slice(s.q);
        self.last_energy = s.energy;
    }
}

/// The state a run ended in, however it ended: t, q and q̇ as the method held them (not a
/// sample's copy: a streamed run keeps no samples).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FinalState {
    /// Time, s.
    pub t: f64,
    /// Positions q.
    pub q: Vec<f64>,
    /// Velocities q̇.
    pub v: Vec<f64>,
}

/// Everything a run produces.
#[derive(Clone, Debug)]
pub struct RunOutput {
    /// The model's title.
    pub title: String,
    /// Per DOF, its name.
    pub dof_names: Vec<String>,
    /// Per contact, its name.
    pub contact_names: Vec<String>,
    /// Per hysteretic element, its name.
    pub element_names: Vec<String>,
    /// The seats.
    pub seats: Vec<crate::scene::Seat>,
    /// The samples kept.
    pub samples: Vec<Sample>,
    /// The event log.
    pub events: Vec<EventRecord>,
    /// The run's counts.
    pub stats: RunStats,
    /// Each accumulation's contact and time.
    pub accumulation_times: Vec<(usize, f64)>,
    /// The failed keys so far (`None` without `key` elements).
    pub key_failures: Option<Vec<KeyFailure>>,
    /// The hysteretic laws (branch and memory) the run ended with.
    pub final_laws: Vec<Hysteretic>,
    /// The state the run ended in (with `final_laws`: what a run that continues it starts
    /// from, `sequence`).
    pub final_state: FinalState,
    /// (max |q|, time) per DOF over every step, dense output included (empty for fixed-step
    /// methods, whose samples are their steps).
    pub step_peaks: Vec<(f64, f64)>,
    /// Store every sample in `samples` (else only the running summary is kept). A run whose
    /// observer keeps the samples ([`crate::run::Observer::keeps_samples`]) holds only those
    /// not handed over yet: at its end, those after the last batch.
    pub keep_history: bool,
    /// The summary so far, over every recorded sample.
    pub tally: Tally,
    /// The summary.
    pub summary: Summary,
    /// The leading `samples` already handed to an observer that keeps them
    /// ([`crate::run::Observer::keeps_samples`]): the next sample recorded drops them.
    pub(crate) handed: Handed,
    /// Samples already handed over, their storage reused by the next ones.
    pub(crate) spare: Spare,
}

/// A count of samples shared by a run's output and its batcher (which only borrows the
/// output): set when a batch is handed over, read and reset by the next [`RunOutput::record`].
#[derive(Debug, Default)]
pub(crate) struct Handed(AtomicUsize);

impl Handed {
    pub(crate) fn get(&self) -> usize {
        self.0.load(Ordering::Relaxed)
    }

    pub(crate) fn set(&self, n: usize) {
        self.0.store(n, Ordering::Relaxed);
    }

    fn take(&self) -> usize {
        self.0.swap(0, Ordering::Relaxed)
    }
}

impl Clone for Handed {
    fn clone(&self) -> Self {
        Self(AtomicUsize::new(self.get()))
    }
}

/// Samples whose vectors a new sample reuses (a clone starts without any).
#[derive(Default)]
pub(crate) struct Spare(Vec<Sample>);

impl Clone for Spare {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl std::fmt::Debug for Spare {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} spare samples", self.0.len())
    }
}

/// Capacity a streamed output's sample buffer is brought back to when it holds more (the
/// engine reserves room for the whole history when it keeps one).
const STREAMED_CAPACITY: usize = 1024;

impl RunOutput {
    /// An empty output of `scene`'s names.
    pub fn new(scene: &Scene) -> Self {
        Self {
            title: scene.title.clone(),
            dof_names: scene.dof_names.clone(),
            contact_names: scene.contacts.iter().map(|c| c.name.clone()).collect(),
            element_names: scene.hysteretic.iter().map(|c| c.name.clone()).collect(),
            seats: scene.seats.clone(),
            samples: Vec::new(),
            events: Vec::new(),
            stats: RunStats::default(),
            accumulation_times: Vec::new(),
            key_failures: (scene.hysteretic.iter())
                .any(|h| matches!(h.law.law(), Law::Key { .. }))
                .then(Vec::new),
            final_laws: Vec::new(),
            final_state: FinalState::default(),
            step_peaks: Vec::new(),
            keep_history: true,
            tally: Tally::default(),
            summary: Summary::default(),
            handed: Handed::default(),
            spare: Spare::default(),
        }
    }

    /// Index of a DOF by name.
    pub fn dof(&self, name: &str) -> Option<usize> {
        self.dof_names.iter().position(|n| n == name)
    }

    /// Records one sample: it updates the running summary ([`Tally`]) and, when the output
    /// keeps its history, is stored.
    pub fn record(&mut self, s: SampleView) {
        self.tally.add(&s);
        if self.keep_history {
            self.drop_handed();
            let Some(mut to) = self.spare.0.pop() else {
                self.samples.push(Sample {
                    t: s.t,
                    kind: s.kind,
                    q: s.q.to_vec(),
                    v: s.v.to_vec(),
                    contacts: s.contacts.to_vec(),
                    elements: s.elements.to_vec(),
                    energy: s.energy,
                });
                return;
            };
            (to.t, to.kind, to.energy) = (s.t, s.kind, s.energy);
            for (a, b) in [(&mut to.q, s.q), (&mut to.v, s.v)] {
                a.clear();
                a.extend_from_slice(b);
            }
            to.contacts.clear();
            to.contacts.extend_from_slice(s.contacts);
            to.elements.clear();
            to.elements.extend_from_slice(s.elements);
            self.samples.push(to);
        }
    }

    /// Drops the samples handed to an observer that keeps them (at every new sample, and when
    /// the run ends: `samples` then holds only those recorded after the last batch).
    pub(crate) fn drop_handed(&mut self) {
        let handed = self.handed.take().min(self.samples.len());
        if handed > 0 {
            let room = STREAMED_CAPACITY.saturating_sub(self.spare.0.len());
            let mut gone = self.samples.drain(..handed);
            self.spare.0.extend(gone.by_ref().take(room));
            drop(gone);
            if self.samples.capacity() > 4 * STREAMED_CAPACITY {
                self.samples.shrink_to(STREAMED_CAPACITY);
            }
        }
    }

    /// Notes the failure of key `element` at `t` having carried `peak_force` (the event is
    /// logged by the integrator).
    pub(crate) fn note_key_failure(&mut self, t: f64, element: usize, peak_force: f64) {
        let name = self.element_names.get(element).cloned().unwrap_or_default();
        if let Some(list) = self.key_failures.as_mut() {
            list.push(KeyFailure {
                element: name,
                t,
                peak_force,
            });
        }
    }

    /// Time of the last recorded sample.
    pub(crate) fn last_sample_time(&self) -> Option<f64> {
        self.tally.last_t
    }

    /// Fill the summary from the recorded samples and the events.
    pub fn finish(&mut self, energy_scale: f64) {
        let tally = &self.tally;
        let mut peaks: Vec<DofPeak> = self
            .dof_names
            .iter()
            .enumerate()
            .map(|(k, n)| {
                let (max_abs, at, max_abs_velocity) =
                    tally.peaks.get(k).copied().unwrap_or_default();
                DofPeak {
                    name: n.clone(),
                    max_abs,
                    at,
                    residual: tally.last_q.get(k).copied().unwrap_or(0.0),
                    max_abs_velocity,
                }
            })
            .collect();
        let mut contacts: Vec<ContactSummary> = self
            .contact_names
            .iter()
            .enumerate()
            .map(|(i, n)| {
                let c = tally.contacts.get(i);
                ContactSummary {
                    name: n.clone(),
                    min_gap: c.map_or(f64::INFINITY, |c| c.min_gap),
                    max_gap: c.map_or(f64::NEG_INFINITY, |c| c.max_gap),
                    max_gap_at: c.map_or(0.0, |c| c.max_gap_at),
                    max_normal_force: c.map_or(0.0, |c| c.max_normal_force),
                    min_normal_force: c.map_or(0.0, |c| c.min_normal_force),
                    max_normal_impulse: 0.0,
                    impacts: 0,
                    stick_time: c.map_or(0.0, |c| c.stick_time),
                    slide_time: c.map_or(0.0, |c| c.slide_time),
                }
            })
            .collect();
        for (p, &(m, t)) in peaks.iter_mut().zip(&self.step_peaks) {
            if m > p.max_abs {
                p.max_abs = m;
                p.at = t;
            }
        }
        for e in &self.events {
            if e.kind == EventKind::Impact {
                contacts[e.contact].impacts += 1;
                contacts[e.contact].max_normal_impulse =
                    contacts[e.contact].max_normal_impulse.max(e.normal);
            }
        }
        let max_penetration = contacts.iter().map(|c| -c.min_gap).fold(0.0f64, f64::max);
        let max_pull = (contacts.iter())
            .map(|c| -c.min_normal_force)
            .fold(0.0f64, f64::max);
        let seats = (self.seats.iter())
            .map(|s| SeatSummary {
                contact: contacts[s.contact].name.clone(),
                width: s.width,
                min_margin: s.edge - contacts[s.contact].max_gap,
                at: contacts[s.contact].max_gap_at,
                required: s.required.map(|r| r.0),
                percent: s.required.map(|r| r.1),
            })
            .collect();
        let closure = tally.closure;
        self.summary = Summary {
            title: self.title.clone(),
            t_end: tally.last_t.unwrap_or(0.0),
            peaks,
            contacts,
            seats,
            max_penetration,
            max_pull,
            energy_final: tally.last_energy,
            energy_closure_abs: closure,
            energy_closure_rel: if energy_scale > 0.0 {
                closure / energy_scale
            } else {
                0.0
            },
            accumulation_times: self
                .accumulation_times
                .iter()
                .map(|(i, t)| (self.contact_names[*i].clone(), *t))
                .collect(),
            stats: self.stats.clone(),
            step_control: self.step_control(),
            key_failures: self.key_failures.clone(),
        };
    }

    /// [`Summary::step_control`] from the counts in `stats`.
    fn step_control(&self) -> Vec<(String, usize)> {
        let n = self.dof_names.len();
        let mut out: Vec<(String, usize)> = (self.stats.step_control.iter().enumerate())
            .filter(|(_, c)| **c > 0)
            .map(|(i, &c)| {
                let name = match self.dof_names.get(i % n.max(1)) {
                    Some(d) if i < n => d.clone(),
                    Some(d) => format!("d/dt {d}"),
                    None => format!("y[{i}]"),
                };
                (name, c)
            })
            .collect();
        out.sort_by_key(|e| std::cmp::Reverse(e.1));
        out
    }

    /// events.csv into `path`, as one transaction.
    pub(crate) fn write_events(&self, path: &Path) -> std::io::Result<()> {
        let csv = events_csv(&self.events, &self.contact_names, &self.element_names);
        files::write_atomic(path, csv)
    }

    /// summary.json into `path`, as one transaction.
    pub(crate) fn write_summary(&self, path: &Path) -> std::io::Result<()> {
        let s = serde_json::to_string_pretty(&self.summary).map_err(std::io::Error::other)?;
        files::write_atomic(path, s)
    }

    /// history.csv, events.csv, summary.json in `dir` (created), as one transaction
    /// ([`files::Staging`]).
    pub fn write_all(&self, dir: &Path) -> std::io::Result<()> {
        let staging = files::Staging::begin(dir)?;
        self.write_history(&staging.path("history.csv"))?;
        self.write_events(&staging.path("events.csv"))?;
        self.write_summary(&staging.path("summary.json"))?;
        staging.commit(&format!(
            "{{\n  \"status\": \"writing\",\n  \"pid\": {}\n}}\n",
            std::process::id()
        ))
    }
}
