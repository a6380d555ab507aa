//! The results pages of the studies view (after the studies in its list, reached with h/l):
//! the energy ledger and the contact forces of the current run (carried by the run's worker,
//! [`crate::tui::results::run`]), the modes of the form's model and its input records with their
//! 5 %-damped response spectrum (each computed by [`crate::tui::workers::results`]). Here: which
//! page is shown, what is selected on it, and the computed data with its state.

pub mod run;

use crate::excitation::G;
use crate::modal;
use crate::scene::{Motion, Scene};
use crate::suite::intensity::pseudo_acceleration;
use std::sync::atomic::{AtomicBool, Ordering};

/// A results page.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Page {
    Energy,
    Contacts,
    Modes,
    Records,
}

impl Page {
    pub const ALL: [Page; 4] = [Page::Energy, Page::Contacts, Page::Modes, Page::Records];

    /// Its name in the list.
    pub fn title(self) -> &'static str {
        match self {
            Page::Energy => "energy",
            Page::Contacts => "contacts",
            Page::Modes => "modes",
            Page::Records => "records",
        }
    }

    /// Computed by [`crate::tui::workers::results`] from the form's model (not carried by the run).
    pub fn of_model(self) -> bool {
        matches!(self, Page::Modes | Page::Records)
    }
}

/// What to compute, on the form's model.
#[derive(Clone, Debug)]
pub enum ResultSpec {
    Modes(Box<Scene>),
    Records(Box<Scene>),
}

/// The damping ratio of the response spectrum.
pub const SPECTRUM_DAMPING: f64 = 0.05;

/// The modes of a model: periods, participating mass ratios (x, y, θ) and shapes (each
/// scaled to its largest component, ±1).
#[derive(Clone, Debug, PartialEq)]
pub struct ModesData {
    pub dof_names: Vec<String>,
    pub periods: Vec<f64>,
    pub ratios: Vec<[f64; 3]>,
    pub shapes: Vec<Vec<f64>>,
}

/// One component of the input: a support's record.
#[derive(Clone, Debug, PartialEq)]
pub struct Component {
    /// The support's name.
    pub name: String,
    /// Its start (the lag) and sampling interval, s.
    pub t0: f64,
    pub dt: f64,
    /// Acceleration, g, and displacement (the model's length unit: m, in) at each sample (the
    /// support's factor applied).
    pub acc_g: Vec<f64>,
    pub disp: Vec<f64>,
    /// (T s, Sa g) of the 5 %-damped pseudo-acceleration spectrum.
    pub spectrum: Vec<(f64, f64)>,
    /// Sa at the first mode's period, g (NaN without a mode).
    pub sa_t1: f64,
}

impl Component {
    pub fn pga_g(&self) -> f64 {
        self.acc_g.iter().fold(0.0f64, |m, a| m.max(a.abs()))
    }
    pub fn pgd(&self) -> f64 {
        self.disp.iter().fold(0.0f64, |m, a| m.max(a.abs()))
    }
}

/// The input records of a model and the first mode's period.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordsData {
    pub t1: f64,
    pub components: Vec<Component>,
    /// Supports driven by a harmonic motion (no record: no spectrum).
    pub harmonic: Vec<String>,
}

/// How far a computation got.
#[derive(Clone, Debug, PartialEq)]
pub enum JobState<T> {
    Running { done: usize, all: usize },
    Cancelling,
    Ready(T),
    Cancelled,
    Failed(String),
}

/// A computation for the model text of hash `hash`; its worker's messages carry `id`.
#[derive(Clone, Debug, PartialEq)]
pub struct Job<T> {
    pub id: u64,
    pub hash: u64,
    pub state: JobState<T>,
}

impl<T> Job<T> {
    pub fn running(&self) -> bool {
        matches!(self.state, JobState::Running { .. } | JobState::Cancelling)
    }
}

/// The results pages' state.
#[derive(Clone, Debug, Default)]
pub struct Results {
    /// The page shown (None: a study of the list).
    pub page: Option<Page>,
    /// The selected contact, mode and record component.
    pub contact: usize,
    pub mode: usize,
    pub record: usize,
    /// The work-precision study shows its stability grid instead of its chart.
    pub grid: bool,
    pub modes: Option<Job<ModesData>>,
    pub records: Option<Job<RecordsData>>,
    pub next_id: u64,
}

impl Results {
    /// The running computation's id, if any.
    pub fn running_id(&self) -> Option<u64> {
        (self.modes.as_ref().filter(|j| j.running()).map(|j| j.id)).or(self
            .records
            .as_ref()
            .filter(|j| j.running())
            .map(|j| j.id))
    }
}

/// The modes of `scene` (K₀, M at its initial state, [`modal::modes`]) with their
/// participating mass ratios ([`modal::participation`]).
pub fn modes_data(scene: &Scene) -> ModesData {
    let modes = modal::modes(scene);
    let ratios = modal::participation(scene, &modes);
    ModesData {
        dof_names: scene.dof_names.clone(),
        periods: modes.iter().map(|m| m.period).collect(),
        ratios,
        shapes: modes
            .iter()
            .map(|m| {
                let big = m.shape.amax().max(1e-300);
                m.shape.iter().map(|x| x / big).collect()
            })
            .collect(),
    }
}

/// The periods of the spectrum: 60 from 0.02 to 5 s, evenly in log T.
pub fn spectrum_periods() -> Vec<f64> {
    let (a, b, n) = (0.02f64.ln(), 5.0f64.ln(), 60);
    (0..n)
        .map(|i| (a + (b - a) * i as f64 / (n - 1) as f64).exp())
        .collect()
}

/// The spectrum of `acc` (m/s², `dt` apart) at `periods`, g; None when `cancel` is set
/// before the end. `step` is told of each period done.
pub fn spectrum(
    acc: &[f64],
    dt: f64,
    periods: &[f64],
    cancel: &AtomicBool,
    step: &mut dyn FnMut(),
) -> Option<Vec<(f64, f64)>> {
    let mut out = Vec::with_capacity(periods.len());
    for &p in periods {
        if cancel.load(Ordering::Relaxed) {
            return None;
        }
        out.push((p, pseudo_acceleration(acc, dt, p, SPECTRUM_DAMPING) / G));
        step();
    }
    Some(out)
}

/// The supports of `scene` driven by records: (name, the acceleration m/s² with its factor,
/// dt, t0, displacement m); and the names of those driven harmonically.
#[allow(clippy::type_complexity)]
pub fn record_supports(
    scene: &Scene,
) -> (Vec<(String, Vec<f64>, f64, f64, Vec<f64>)>, Vec<String>) {
    let mut recs = Vec::new();
    let mut harmonic = Vec::new();
    for s in &scene.supports {
        match &s.motion {
            Motion::Record(g) => recs.push((
                s.name.clone(),
                g.acc.iter().map(|a| a * s.factor).collect(),
                g.dt,
                g.t0,
                g.disp.iter().map(|d| d * s.factor).collect(),
            )),
            Motion::Harmonic { .. } => harmonic.push(s.name.clone()),
        }
    }
    (recs, harmonic)
}
