//! The workbench's run history: every finished, cancelled or failed run kept as `#N` with its
//! name, status, key results, the model text it ran and a decimated copy of its charted series;
//! one pinned baseline that every comparison and overlay is against; the model diff of each
//! run against it. Bounded: the newest [`KEEP`] runs plus the baseline. Stored on disk by
//! [`crate::tui::runs::store`].

use crate::tui::chart;
use crate::tui::form;
use crate::tui::form::spec as form_spec;
use crate::tui::runs::data::{RunData, RunStatus};
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// Runs kept (the baseline is kept besides, however old).
pub const KEEP: usize = 50;
/// Runs overlaid on the charts besides the baseline.
pub const MAX_OVERLAY: usize = 4;
/// A kept run's series hold at most this many samples (the minimum and the maximum of the
/// rotation in each of half as many equal slices, the first and last sample besides).
pub const MAX_SAMPLES: usize = 2000;

/// How a kept run ended.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "status", content = "reason", rename_all = "lowercase")]
pub enum Ended {
    Finished,
    Cancelled,
    Failed(String),
    /// Finished, but outside the accuracy bounds (`SolverError::Inaccurate`): its reason.
    Inaccurate(String),
}

impl Ended {
    /// The status column of the run list: the word, and for a failure its short reason
    /// (`failed: Painlevé`).
    pub fn short(&self) -> String {
        match self {
            Ended::Failed(why) => format!("failed: {}", short_reason(why)),
            _ => self.word().into(),
        }
    }

    /// The whole reason of a failure or of a run outside its accuracy bounds.
    pub fn reason(&self) -> Option<&str> {
        match self {
            Ended::Failed(why) | Ended::Inaccurate(why) => Some(why),
            _ => None,
        }
    }

    pub fn word(&self) -> &'static str {
        match self {
            Ended::Finished => "done",
            Ended::Cancelled => "cancelled",
            Ended::Failed(_) => "failed",
            Ended::Inaccurate(_) => "inexact",
        }
    }
}

/// A failure's reason in a word or two, from the engine's message (`SolverError`,
/// `RunFailure`); else its first words.
pub fn short_reason(why: &str) -> String {
    const KNOWN: [(&str, &str); 17] = [
        ("Painlevé", "Painlevé"),
        ("step collapse", "collapse"),
        ("LCP failed", "LCP"),
        ("fell below the minimum", "step < min"),
        ("events", "max events"),
        ("initial penetration", "penetration"),
        ("non-finite", "non-finite"),
        ("too stiff", "too stiff"),
        ("stopped advancing", "stalled"),
        ("unstable", "unstable"),
        ("did not converge", "no converge"),
        ("lost its seat", "unseated"),
        ("outside the accuracy", "inaccurate"),
        ("panicked", "panic"),
        ("in memory", "memory"),
        ("worker thread", "thread"),
        ("steps", "max steps"),
    ];
    let body = match why.split_once(" s: ") {
        Some((head, rest)) if head.starts_with("t = ") => rest,
        _ => why,
    };
    // the engine's own words first (the message's head), then the whole of it
    for text in [body.split(':').next().unwrap_or(body), body] {
        if let Some((_, w)) = KNOWN.iter().find(|(k, _)| text.contains(k)) {
            return (*w).into();
        }
    }
    let first: String = body
        .split_whitespace()
        .take(2)
        .collect::<Vec<_>>()
        .join(" ");
    if first.chars().count() > 12 {
        first.chars().take(11).chain(['…']).collect()
    } else {
        first
    }
}

/// A hash of a model text that stays the same from build to build (64-bit FNV-1a).
pub fn text_hash(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// A failure that is a finished run outside its accuracy bounds.
pub fn is_inaccurate(e: &crate::tui::runs::data::RunFailure) -> bool {
    matches!(
        e,
        crate::tui::runs::data::RunFailure::Solver(crate::run::SolverError::Inaccurate { .. })
    )
}

/// The key results of a run (None: not known, e.g. the residual of a run still going).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Results {
    /// The charted rotation DOF and the translations (`deck.theta`, `deck.x`, `deck.y`).
    pub rotation: String,
    pub translations: Vec<String>,
    pub peak_rot: Option<f64>,
    pub peak_rot_t: Option<f64>,
    /// A bridge of several frames: the largest peak |θ| over them and that frame's name.
    #[serde(default)]
    pub peak_frames: Option<(f64, String)>,
    /// Rotation at the end of a finished run.
    pub residual_rot: Option<f64>,
    /// Peak |x|, |y| of the translations.
    pub peak_xy: Vec<Option<f64>>,
    pub impacts: usize,
    /// Stick time of all contacts, s.
    pub stick_time: Option<f64>,
    /// Smallest gap of all contacts, m.
    pub min_gap: Option<f64>,
    /// The engine's relative energy closure of a run that ran to its end (finished, or
    /// failed outside its accuracy bounds).
    pub closure: Option<f64>,
    /// The bound `solver.max_closure` that closure broke (None: within it, or not judged).
    #[serde(default)]
    pub closure_over: Option<f64>,
    /// Simulated time reached, s.
    pub t_sim: f64,
    pub events: usize,
}

fn finite(v: f64) -> Option<f64> {
    v.is_finite().then_some(v)
}

impl Results {
    /// The results of a run so far.
    pub fn of(r: &RunData) -> Results {
        let finished = r.status == RunStatus::Finished;
        // a run outside its accuracy bounds ran to its end: its summary is whole
        let bounds = match &r.status {
            RunStatus::Failed(e) => match e.as_ref() {
                crate::tui::runs::data::RunFailure::Solver(
                    crate::run::SolverError::Inaccurate { bounds, .. },
                ) => Some(bounds.as_slice()),
                _ => None,
            },
            _ => None,
        };
        let ended = finished || bounds.is_some();
        let (peak, at) = r.peak_rot();
        let has_rot = r.rot.is_some();
        Results {
            rotation: r.rot_name().to_string(),
            translations: r.xy.iter().map(|&k| r.dof_names[k].clone()).collect(),
            peak_rot: has_rot.then_some(peak),
            peak_rot_t: has_rot.then_some(at),
            peak_frames: r.peak_rot_of_frames(),
            residual_rot: (ended && has_rot).then(|| r.residual_rot()),
            peak_xy: r.xy.iter().map(|&k| finite(r.q_peak(k))).collect(),
            impacts: r.total_impacts(),
            stick_time: (!r.contact_names.is_empty()).then(|| r.total_stick_time()),
            min_gap: finite(r.min_gap()),
            closure: r
                .summary
                .as_ref()
                .filter(|_| ended)
                .and_then(|s| finite(s.energy_closure_rel)),
            closure_over: (bounds.unwrap_or_default().iter())
                .find(|b| b.setting == "max_closure")
                .map(|b| b.limit),
            t_sim: r.t_sim,
            events: r.events.len(),
        }
    }
}

/// One value that differs between two model texts, by dotted path (None: absent).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Change {
    pub path: String,
    pub old: Option<String>,
    pub new: Option<String>,
}

impl Change {
    /// `contacts.mu: 0.3 → 0.5`; a list element by its label, numbered from 1 as in the form
    /// (`contacts gap 1 (left_top): 0.0127 → 0.006` for `contacts.gaps.0`).
    pub fn line(&self) -> String {
        let v = |s: &Option<String>| s.clone().unwrap_or_else(|| "(none)".into());
        format!("{}: {} → {}", self.shown(), v(&self.old), v(&self.new))
    }

    /// The path as a user reads it: list elements numbered from 1 ([`form_spec::one_based`]).
    pub fn shown(&self) -> String {
        form_spec::one_based(&self.path)
    }
}

/// The scalar values that differ between two model texts, by dotted path (array elements as
/// `contacts.gaps.2`): those of `new` in its order, then those only in `old`.
pub fn model_diff(old: &str, new: &str) -> Vec<Change> {
    if old == new {
        return Vec::new();
    }
    model_diff_from(form::scalars(old).as_deref(), new)
}

/// [`model_diff`] from the old text's scalars (None: not TOML), read once for many diffs.
fn model_diff_from(a: Option<&[(String, toml_edit::Value)]>, new: &str) -> Vec<Change> {
    let (Some(a), Some(b)) = (a, form::scalars(new)) else {
        return vec![Change {
            path: "(the file is not TOML)".into(),
            old: None,
            new: None,
        }];
    };
    let show = |v: &toml_edit::Value| form::show(v);
    let mut out = Vec::new();
    for (p, v) in &b {
        let before = a.iter().find(|(q, _)| q == p).map(|(_, w)| show(w));
        let after = show(v);
        if before.as_deref() != Some(after.as_str()) {
            out.push(Change {
                path: p.clone(),
                old: before,
                new: Some(after),
            });
        }
    }
    for (p, v) in a {
        if !b.iter().any(|(q, _)| q == p) {
            out.push(Change {
                path: p.clone(),
                old: Some(show(v)),
                new: None,
            });
        }
    }
    out
}

/// A run's default name: its first change (`contacts.mu=0.5`, `+2` more), or what it equals.
pub fn derived_name(changes: &[Change], against: Option<u64>) -> String {
    let Some(first) = changes.first() else {
        return match against {
            Some(b) => format!("same as #{b}"),
            None => "as saved".into(),
        };
    };
    let mut s = match &first.new {
        Some(v) => format!("{}={v}", first.shown()),
        None => format!("{} removed", first.shown()),
    };
    if changes.len() > 1 {
        s.push_str(&format!(" +{}", changes.len() - 1));
    }
    s
}

/// The indices of at most [`MAX_SAMPLES`] samples of `y` that keep its shape: per slice the
/// minimum and the maximum, in order; the first and the last sample.
pub fn thin_indices(y: &[f64]) -> Vec<usize> {
    let n = y.len();
    if n <= MAX_SAMPLES {
        return (0..n).collect();
    }
    let slices = MAX_SAMPLES / 2 - 1;
    let mut out = vec![0];
    for s in 0..slices {
        let (a, b) = (s * n / slices, ((s + 1) * n / slices).min(n));
        if a >= b {
            continue;
        }
        let (mut lo, mut hi) = (a, a);
        for i in a..b {
            if y[i] < y[lo] {
                lo = i;
            }
            if y[i] > y[hi] {
                hi = i;
            }
        }
        for i in [lo.min(hi), lo.max(hi)] {
            if *out.last().unwrap_or(&usize::MAX) != i {
                out.push(i);
            }
        }
    }
    if *out.last().unwrap_or(&0) != n - 1 {
        out.push(n - 1);
    }
    out
}

/// The part of a run that is overlaid on the charts: the rotation, the translations, the gaps
/// and the hysteretic elements, at most [`MAX_SAMPLES`] samples (no events, no contact
/// states).
pub fn thin(r: &RunData) -> RunData {
    let idx = match r.rot {
        Some(k) => thin_indices(&r.q[k]),
        None => thin_indices(&r.t),
    };
    let pick = |c: &[f64]| {
        idx.iter()
            .map(|&i| c.get(i).copied().unwrap_or(f64::NAN))
            .collect()
    };
    let dofs: Vec<usize> = r.rot.into_iter().chain(r.xy.iter().copied()).collect();
    let mut d = RunData::new(
        r.id,
        r.label.clone(),
        dofs.iter().map(|&k| r.dof_names[k].clone()).collect(),
        r.contact_names.clone(),
        r.element_names.clone(),
        r.t_end,
    );
    d.t = pick(&r.t);
    d.q = dofs.iter().map(|&k| pick(&r.q[k])).collect();
    d.gap = r.gap.iter().map(|g| pick(g)).collect();
    d.state = vec![Vec::new(); r.contact_names.len()];
    d.el = r.el.iter().map(|(a, b)| (pick(a), pick(b))).collect();
    d.el_range = r.el_range.clone();
    d.seats = r.seats.clone();
    // kept without velocities and rates: a kept run keeps what its charts need most
    d.v = Vec::new();
    d.gap_rate = Vec::new();
    d.slip_rate = Vec::new();
    d.impacts = r.impacts.clone();
    d.t_sim = r.t_sim;
    d.token = r.token;
    d.status = r.status.clone();
    d.summary = r.summary.clone();
    d.steps = r.steps;
    d
}

/// One kept run.
#[derive(Clone, Debug)]
pub struct Entry {
    pub number: u64,
    pub name: String,
    /// The name was given by the user (else derived from the diff).
    pub named: bool,
    /// The model text it ran (the draft, unsaved edits included).
    pub model: String,
    pub ended: Ended,
    pub results: Results,
    /// Its charted series, thinned ([`thin`]).
    pub data: RunData,
    /// Selected for the overlay and the comparison.
    pub overlay: bool,
    /// Its model against the baseline's.
    pub changes: Vec<Change>,
    /// The [`text_hash`] of the baseline's model text `changes` are against (None: no
    /// baseline); stored with them, so that opening the list does not diff every run again.
    pub diff_base: Option<u64>,
    /// Whether `data` holds its series or they are still on disk.
    pub series: Series,
}

/// Where a kept run's series are: in `data`, or in its file, read when it is shown or
/// overlaid.
#[derive(Clone, Debug, PartialEq)]
pub enum Series {
    InMemory,
    OnDisk,
    /// Asked for ([`crate::tui::msg::Effect::LoadSeries`]), not back yet.
    Asked,
    /// The file does not read: why.
    Unreadable(String),
}

impl Entry {
    /// The entry of a run that ended, with the model text it ran.
    pub fn of_run(r: &RunData, model: String) -> Entry {
        let ended = match &r.status {
            RunStatus::Finished => Ended::Finished,
            RunStatus::Failed(e) if is_inaccurate(e) => Ended::Inaccurate(e.to_string()),
            RunStatus::Failed(e) => Ended::Failed(e.to_string()),
            _ => Ended::Cancelled,
        };
        Entry {
            number: r.id,
            name: String::new(),
            named: false,
            model,
            ended,
            results: Results::of(r),
            data: thin(r),
            overlay: false,
            changes: Vec::new(),
            diff_base: None,
            series: Series::InMemory,
        }
    }
}

/// The run list.
#[derive(Clone, Debug, Default)]
pub struct Runs {
    /// Oldest first.
    pub list: Vec<Entry>,
    pub baseline: Option<u64>,
    /// Index of the run selected in the list.
    pub selected: usize,
    /// Where the runs are stored (None: not stored, e.g. a model given as text).
    pub dir: Option<PathBuf>,
    /// The run going and the model text it runs.
    pub started: Option<(u64, String)>,
}

impl Runs {
    pub fn get(&self, n: u64) -> Option<&Entry> {
        self.list.iter().find(|e| e.number == n)
    }

    pub fn get_mut(&mut self, n: u64) -> Option<&mut Entry> {
        self.list.iter_mut().find(|e| e.number == n)
    }

    pub fn baseline_entry(&self) -> Option<&Entry> {
        self.baseline.and_then(|b| self.get(b))
    }

    pub fn selected_entry(&self) -> Option<&Entry> {
        self.list.get(self.selected)
    }

    /// The newest run of model text `text` that ended by itself (finished, inexact or failed:
    /// the same text gives the same result; a cancelled run is not reused).
    pub fn reusable(&self, text: &str) -> Option<u64> {
        (self.list.iter().rev())
            .find(|e| e.model == text && e.ended != Ended::Cancelled)
            .map(|e| e.number)
    }

    /// The newest run of model text `text`, whatever its end.
    pub fn same_text(&self, text: &str) -> Option<u64> {
        (self.list.iter().rev())
            .find(|e| e.model == text)
            .map(|e| e.number)
    }

    /// Takes run `n` off the list (the numbers of the others stay; the baseline's removal
    /// leaves none).
    pub fn remove(&mut self, n: u64) -> Option<Entry> {
        let i = self.list.iter().position(|e| e.number == n)?;
        let e = self.list.remove(i);
        if self.baseline == Some(n) {
            self.baseline = None;
            self.rediff();
        }
        self.selected = self.selected.min(self.list.len().saturating_sub(1));
        Some(e)
    }

    /// The largest number kept.
    pub fn last_number(&self) -> u64 {
        self.list.iter().map(|e| e.number).max().unwrap_or(0)
    }

    /// Adds a run (unless named, named from its diff against the baseline, or against the
    /// `saved` model text when there is none) and drops the oldest beyond [`KEEP`] (never the
    /// baseline); returns the numbers dropped.
    pub fn add(&mut self, mut e: Entry, saved: &str) -> Vec<u64> {
        // a run replacing the baseline (a rerun of its text) is not compared with itself
        let base = (self.baseline_entry())
            .filter(|b| b.number != e.number)
            .map(|b| (b.number, b.model.clone()));
        if let Some((_, m)) = &base {
            e.changes = model_diff(m, &e.model);
            e.diff_base = Some(text_hash(m));
        }
        if !e.named {
            e.name = match &base {
                Some((b, _)) => derived_name(&e.changes, Some(*b)),
                None => derived_name(&model_diff(saved, &e.model), None),
            };
        }
        self.list.retain(|x| x.number != e.number);
        self.list.push(e);
        self.list.sort_by_key(|x| x.number);
        self.bound()
    }

    /// Drops the oldest runs beyond [`KEEP`] (never the baseline).
    pub fn bound(&mut self) -> Vec<u64> {
        let mut dropped = Vec::new();
        let extra = |l: &Vec<Entry>, b: Option<u64>| {
            l.len() - usize::from(b.is_some_and(|b| l.iter().any(|e| e.number == b)))
        };
        while extra(&self.list, self.baseline) > KEEP {
            let Some(i) = self
                .list
                .iter()
                .position(|x| Some(x.number) != self.baseline)
            else {
                break;
            };
            dropped.push(self.list.remove(i).number);
        }
        self.selected = self.selected.min(self.list.len().saturating_sub(1));
        dropped
    }

    /// Pins run `n` as the baseline; every run's diff is then against it. Returns the runs
    /// whose diff changed (their metadata to store again).
    pub fn pin(&mut self, n: u64) -> Vec<u64> {
        self.baseline = Some(n);
        if let Some(e) = self.get_mut(n) {
            e.overlay = false;
        }
        self.rediff()
    }

    /// Every run's diff against the baseline, except those already against its text (the
    /// baseline's scalars read once).
    fn rediff(&mut self) -> Vec<u64> {
        let base = self.baseline_entry().map(|b| b.model.clone());
        let hash = base.as_deref().map(text_hash);
        let mut scalars = None;
        let mut changed = Vec::new();
        for e in &mut self.list {
            if e.diff_base == hash {
                continue;
            }
            e.changes = match &base {
                Some(m) if *m == e.model => Vec::new(),
                Some(m) => model_diff_from(
                    scalars.get_or_insert_with(|| form::scalars(m)).as_deref(),
                    &e.model,
                ),
                None => Vec::new(),
            };
            e.diff_base = hash;
            changed.push(e.number);
        }
        changed
    }

    /// Toggles run `n` in the overlay; refused beyond [`MAX_OVERLAY`] runs.
    pub fn toggle_overlay(&mut self, n: u64) -> Result<bool, String> {
        let count = self.list.iter().filter(|e| e.overlay).count();
        let base = self.baseline;
        let e = self.get_mut(n).ok_or("no such run")?;
        if Some(n) == base {
            return Err(format!("#{n} is the baseline: always overlaid"));
        }
        if !e.overlay && count >= MAX_OVERLAY {
            return Err(format!(
                "at most {MAX_OVERLAY} runs overlaid besides the baseline: space on one of them first"
            ));
        }
        e.overlay = !e.overlay;
        Ok(e.overlay)
    }

    /// The runs overlaid: the baseline, then those selected, oldest first.
    pub fn overlays(&self) -> Vec<&Entry> {
        let mut v: Vec<&Entry> = self.baseline_entry().into_iter().collect();
        v.extend(
            self.list
                .iter()
                .filter(|e| e.overlay && Some(e.number) != self.baseline),
        );
        v
    }
}

/// A number for the run tables (`—` unknown, `0` for |v| < 1e-9).
pub fn cell(v: Option<f64>) -> String {
    match v {
        None => "—".into(),
        Some(v) if v.abs() < 1e-9 => "0".into(),
        Some(v) => chart::fmt_sig(v, 4),
    }
}
