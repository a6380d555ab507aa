//! Run sequences: the shake-table test applied its runs to one specimen, so run k+1 starts from
//! the final state of run k — q, q̇ and every hysteretic element's state (branch and memory),
//! hence the gaps — optionally with the gaps re-measured before it (`[[run]] gaps`).
//!
//! The hand-over is relative to the ground: every run's supports start at u_g = 0, so the state
//! handed over is q(T) − Σ_s r_s u_{g,s}(T), q̇(T) − Σ_s r_s u̇_{g,s}(T), with r_s the quasi-static
//! influence of support s (`modal::support_influence`, K₀ r_s = Σ k J). For rigid-body support
//! motion this keeps every element deformation and gap. A record that has ended at rest at zero
//! displacement (the baseline's promise, |d_end| ≤ END_TOLERANCE·PGD) counts as zero: the state
//! is then handed over unchanged, bit for bit.

use crate::excitation::END_TOLERANCE;
use crate::hysteresis::Hysteretic;
use crate::model::{self, ModelError};
use crate::output::RunOutput;
use crate::run::{FailureReport, Observer, Run, Silent, Stop};
use crate::scene::{Motion, Scene, Support};
use crate::studies::{MuStudy, RunFailure, Study, row_of};
use nalgebra::DVector;
use rayon::prelude::*;
use std::path::Path;
use std::sync::Arc;

/// Why a sequence could not start, or stopped before its last run (naming that run).
#[derive(Debug, thiserror::Error)]
pub enum SequenceError {
    /// The model itself (before any run).
    #[error("{0}")]
    Load(#[source] ModelError),
    #[error("run '{run}': {source}")]
    Model {
        run: String,
        #[source]
        source: ModelError,
    },
    #[error("run '{run}' failed ({}): {}", failure.kind, failure.reason)]
    Failed { run: String, failure: FailureReport },
    #[error("run '{run}' cancelled at t = {t:.9} s")]
    Cancelled { run: String, t: f64 },
    #[error("run '{run}': {given} gaps for {contacts} contacts")]
    Gaps {
        run: String,
        given: usize,
        contacts: usize,
    },
    /// The scene of a run does not match the state handed to it (a different model).
    #[error("run '{run}': cannot start from the previous run's state: {reason}")]
    Mismatch { run: String, reason: String },
    #[error("{}: no [[run]] tables: a sequence runs a bridge file's runs", path.display())]
    NoRuns { path: std::path::PathBuf },
    #[error("--runs {spec}: {reason}")]
    Runs { spec: String, reason: String },
}

/// One run of a sequence, before it starts: its scene as if it ran alone, and the gaps to set
/// at its start (corners in the order of `scene.contacts`).
#[derive(Clone, Debug)]
pub struct Stage {
    pub name: String,
    pub scene: Scene,
    pub gaps: Option<Vec<f64>>,
}

/// The state one run hands to the next, relative to the ground.
#[derive(Clone, Debug)]
pub struct Handover {
    pub q: DVector<f64>,
    pub v: DVector<f64>,
    /// Each hysteretic element's law with its state (branch and memory).
    pub laws: Vec<Hysteretic>,
    /// Σ_s r_s u_{g,s}(T) and Σ_s r_s u̇_{g,s}(T), subtracted from q(T) and q̇(T).
    pub ground: DVector<f64>,
    pub ground_rate: DVector<f64>,
}

/// (u_g, u̇_g) of a support at the end `t` of a run: zero for a record that has ended at rest
/// at zero displacement (|d_end| ≤ END_TOLERANCE·PGD), else `Support::at`.
pub fn ground_at_end(s: &Support, t: f64) -> (f64, f64) {
    if let Motion::Record(g) = &s.motion
        && t >= g.end_time()
    {
        let pgd = g.disp.iter().fold(0.0f64, |m, d| m.max(d.abs()));
        if g.disp
            .last()
            .is_some_and(|d| d.abs() <= END_TOLERANCE * pgd)
        {
            return (0.0, 0.0);
        }
    }
    let (d, v, _) = s.at(t);
    (d, v)
}

/// The state `out` (a run of `scene`) ended in, relative to the ground (module docs; a scene
/// whose K₀ is singular has no influence r_s, and nothing is subtracted); None when the run
/// recorded no final state (it failed before its first step).
pub fn handover(scene: &Scene, out: &RunOutput) -> Option<Handover> {
    let end = &out.final_state;
    let n = scene.ndof();
    if end.q.len() != n || end.v.len() != n || out.final_laws.len() != scene.hysteretic.len() {
        return None;
    }
    let (mut ground, mut ground_rate) = (DVector::zeros(n), DVector::zeros(n));
    let at: Vec<(f64, f64)> = (scene.supports.iter())
        .map(|s| ground_at_end(s, end.t))
        .collect();
    if at.iter().any(|&(d, v)| d != 0.0 || v != 0.0) {
        for (k, s, r) in crate::modal::support_influence(scene) {
            ground[k] += r * at[s].0;
            ground_rate[k] += r * at[s].1;
        }
    }
    Some(Handover {
        q: DVector::from_column_slice(&end.q) - &ground,
        v: DVector::from_column_slice(&end.v) - &ground_rate,
        laws: out.final_laws.clone(),
        ground,
        ground_rate,
    })
}

/// `scene` starting from `h`: q0, v0 and each element's law (with its state) replaced. The
/// scene must have the same DOFs and the same element laws (parameters) as the run handing over.
pub(crate) fn start_from(scene: &mut Scene, h: &Handover) -> Result<(), String> {
    let n = scene.ndof();
    if h.q.len() != n || h.v.len() != n {
        return Err(format!("{} DOFs handed to a scene of {n}", h.q.len()));
    }
    if h.laws.len() != scene.hysteretic.len() {
        let (a, b) = (h.laws.len(), scene.hysteretic.len());
        return Err(format!("{a} hysteretic elements handed to a scene of {b}"));
    }
    for (el, law) in scene.hysteretic.iter_mut().zip(&h.laws) {
        if el.law.law() != law.law() {
            return Err(format!("element '{}' has another law", el.name));
        }
        el.law = law.clone();
    }
    scene.q0.copy_from(&h.q);
    scene.v0.copy_from(&h.v);
    Ok(())
}

/// Each contact's gap g_N at the scene's initial pose q0.
pub fn start_gaps(scene: &Scene) -> Vec<f64> {
    let fr = scene.frame(0.0, &scene.q0, &scene.v0);
    (scene.contacts.iter())
        .map(|c| scene.contact_kinematics(&fr, c).gap)
        .collect()
}

/// Moves the faces of the first `gaps.len()` contacts (a bridge's four abutment corners come
/// first, its joints after them) along their normals so that contact i's gap at the initial
/// pose q0 is `gaps[i]`: g_N = n·(P − O), so O − δ n with δ = gap − g_N(q0) gives the gap asked
/// for. A seat moves with its face (its edge by δ). Err((given, contacts)) when there are more
/// gaps than contacts.
pub(crate) fn set_gaps(scene: &mut Scene, gaps: &[f64]) -> Result<(), (usize, usize)> {
    if gaps.len() > scene.contacts.len() {
        return Err((gaps.len(), scene.contacts.len()));
    }
    let now = start_gaps(scene);
    for (i, c) in scene.contacts.iter_mut().enumerate().take(gaps.len()) {
        let delta = gaps[i] - now[i];
        c.face_point -= delta * c.face_normal;
        for s in scene.seats.iter_mut().filter(|s| s.contact == i) {
            s.edge += delta;
        }
    }
    Ok(())
}

/// One run of a sequence as it went.
#[derive(Debug)]
pub struct SequenceRun {
    pub name: String,
    /// Each contact's gap at the start.
    pub start_gaps: Vec<f64>,
    pub run: Run,
}

/// A sequence in progress: the runs so far and the state the last one handed over.
#[derive(Debug, Default)]
pub struct Sequence {
    pub runs: Vec<SequenceRun>,
    pub carry: Option<Handover>,
}

impl Sequence {
    pub fn new() -> Self {
        Self::default()
    }

    /// The scene of `stage`, started from the state the last run handed over (none: as given),
    /// with the stage's gaps set (a scene without contacts has none to set).
    pub fn prepare(&self, stage: Stage) -> Result<Scene, SequenceError> {
        let Stage {
            name,
            mut scene,
            gaps,
        } = stage;
        if let Some(h) = &self.carry {
            start_from(&mut scene, h).map_err(|reason| SequenceError::Mismatch {
                run: name.clone(),
                reason,
            })?;
        }
        if let Some(g) = gaps.filter(|_| !scene.contacts.is_empty()) {
            set_gaps(&mut scene, &g).map_err(|(given, contacts)| SequenceError::Gaps {
                run: name.clone(),
                given,
                contacts,
            })?;
        }
        Ok(scene)
    }

    /// Runs a prepared scene (`simulate::integrate`) and keeps the run, however it ends. A
    /// finished run hands its final state to the next; one that did not finish ends the
    /// sequence (the error names it).
    pub fn run(
        &mut self,
        name: &str,
        scene: &Scene,
        observer: &mut dyn Observer,
    ) -> Result<(), SequenceError> {
        let run = crate::simulate::integrate(scene, observer);
        let result = match &run.stop {
            Stop::Finished => match handover(scene, &run.output) {
                Some(h) => {
                    self.carry = Some(h);
                    Ok(())
                }
                None => Err(SequenceError::Mismatch {
                    run: name.to_string(),
                    reason: "the run recorded no final state".into(),
                }),
            },
            Stop::Cancelled { t } => Err(SequenceError::Cancelled {
                run: name.to_string(),
                t: *t,
            }),
            Stop::Failed(e) => Err(SequenceError::Failed {
                run: name.to_string(),
                failure: e.into(),
            }),
        };
        self.runs.push(SequenceRun {
            name: name.to_string(),
            start_gaps: start_gaps(scene),
            run,
        });
        result
    }
}

/// Runs `stages` in order, each from the state the previous one handed over, without
/// observers: the sequence, and the error that ended it early (what ran is kept).
pub fn run_stages(stages: Vec<Stage>) -> (Sequence, Option<SequenceError>) {
    let mut seq = Sequence::new();
    for stage in stages {
        let name = stage.name.clone();
        let r = seq
            .prepare(stage)
            .and_then(|scene| seq.run(&name, &scene, &mut Silent));
        if let Err(e) = r {
            return (seq, Some(e));
        }
    }
    (seq, None)
}

fn model_error(source: ModelError) -> SequenceError {
    SequenceError::Load(source)
}

/// One `[[run]]` table of a bridge file.
#[derive(Clone, Debug, PartialEq)]
pub struct RunInfo {
    /// 1-based, as `excitation.run`.
    pub index: usize,
    pub name: String,
    pub pga_x: f64,
    pub pga_y: f64,
    pub gaps: Option<Vec<f64>>,
}

/// A bridge model whose `[[run]]` tables make the stages of sequences.
pub struct BridgeSequence {
    pub study: Study,
    pub runs: Vec<RunInfo>,
}

impl BridgeSequence {
    /// The model with `set` applied, validated (`[[run]] gaps` included), and its runs.
    pub fn open(path: &Path, set: &[String]) -> Result<Self, SequenceError> {
        let study = Study::open(path, set).map_err(model_error)?;
        Self::from_study(study)
    }

    /// The runs of a study's model (its text with its `base` overrides), validated.
    pub fn from_study(study: Study) -> Result<Self, SequenceError> {
        study.scene(&[]).map_err(model_error)?;
        let text = model::apply_overrides(&study.text, &study.base).map_err(model_error)?;
        let file: Option<model::bridge::BridgeFile> = toml::from_str(&text).ok();
        let runs: Vec<RunInfo> = (file.map(|f| f.runs).unwrap_or_default().into_iter())
            .enumerate()
            .map(|(i, r)| RunInfo {
                index: i + 1,
                name: r.name,
                pga_x: r.pga_x,
                pga_y: r.pga_y,
                gaps: r.gaps,
            })
            .collect();
        if runs.is_empty() {
            return Err(SequenceError::NoRuns { path: study.path });
        }
        Ok(Self { study, runs })
    }

    /// The stage of run `index` (1-based) with extra overrides.
    pub fn stage(&self, index: usize, set: &[String]) -> Result<Stage, SequenceError> {
        let info = self.info(index)?;
        let mut ov = vec![format!("excitation.run={index}")];
        ov.extend(set.iter().cloned());
        let scene = (self.study.scene(&ov)).map_err(|source| SequenceError::Model {
            run: info.name.clone(),
            source,
        })?;
        Ok(Stage {
            name: info.name.clone(),
            scene,
            gaps: info.gaps.clone(),
        })
    }

    fn info(&self, index: usize) -> Result<&RunInfo, SequenceError> {
        self.runs
            .get(index.wrapping_sub(1))
            .ok_or_else(|| SequenceError::Runs {
                spec: index.to_string(),
                reason: format!("no run {index} (1..={})", self.runs.len()),
            })
    }

    /// `--runs`: `a..b` (inclusive), `a,b,c` or `a`; empty: every run. Each once, in 1..=n.
    pub fn parse_runs(&self, spec: Option<&str>) -> Result<Vec<usize>, SequenceError> {
        let n = self.runs.len();
        let Some(spec) = spec else {
            return Ok((1..=n).collect());
        };
        let bad = |reason: String| SequenceError::Runs {
            spec: spec.to_string(),
            reason,
        };
        let num = |s: &str| {
            (s.trim().parse::<usize>()).map_err(|_| bad(format!("'{}' is not a run number", s)))
        };
        let runs: Vec<usize> = match spec.split_once("..") {
            Some((a, b)) => (num(a)?..=num(b)?).collect(),
            None => spec.split(',').map(num).collect::<Result<_, _>>()?,
        };
        if runs.is_empty() {
            return Err(bad("no runs".into()));
        }
        if let Some(r) = runs.iter().find(|r| !(1..=n).contains(*r)) {
            return Err(bad(format!("no run {r} (1..={n})")));
        }
        if let Some((i, r)) = (runs.iter().enumerate()).find(|(i, r)| runs[..*i].contains(r)) {
            return Err(bad(format!("run {r} given twice (position {})", i + 1)));
        }
        Ok(runs)
    }

    /// The runs `runs` in one sequence with extra overrides, without observers (`keep_history`
    /// false: the summaries only).
    pub(crate) fn run_silent(
        &self,
        runs: &[usize],
        set: &[String],
    ) -> (Sequence, Option<SequenceError>) {
        let mut seq = Sequence::new();
        for &k in runs {
            let r = self.stage(k, set).and_then(|mut stage| {
                stage.scene.settings.keep_history = false;
                let name = stage.name.clone();
                let scene = seq.prepare(stage)?;
                seq.run(&name, &scene, &mut Silent)
            });
            if let Err(e) = r {
                return (seq, Some(e));
            }
        }
        (seq, None)
    }

    /// The table rows of a sequence of `runs` (the runs it did not reach left out).
    pub fn rows(&self, seq: &Sequence, runs: &[usize]) -> Vec<SequenceRow> {
        (seq.runs.iter().zip(runs))
            .map(|(r, &k)| SequenceRow::of(&self.runs[k - 1], r))
            .collect()
    }
}

/// One row of the sequence table.
#[derive(Clone, Debug)]
pub struct SequenceRow {
    pub run: usize,
    pub name: String,
    pub pga_x: f64,
    pub pga_y: f64,
    pub peak_rotation: f64,
    pub residual_rotation: f64,
    pub impacts: usize,
    pub start_gaps: Vec<f64>,
    /// `finished`, `cancelled` or `failed (Kind at t = … s)`.
    pub status: String,
}

impl SequenceRow {
    pub fn of(info: &RunInfo, r: &SequenceRun) -> Self {
        let row = row_of(Vec::new(), &r.run.output);
        let status = match &r.run.stop {
            Stop::Failed(e) => format!("failed ({} at t = {:.6} s)", e.kind(), e.time()),
            s => s.label().to_string(),
        };
        Self {
            run: info.index,
            name: r.name.clone(),
            pga_x: info.pga_x,
            pga_y: info.pga_y,
            peak_rotation: row.peak_rotation,
            residual_rotation: row.residual_rotation,
            impacts: row.impacts,
            start_gaps: r.start_gaps.clone(),
            status,
        }
    }
}

fn gaps_text(g: &[f64], sep: &str) -> String {
    let v: Vec<String> = g.iter().map(|x| format!("{x:.6e}")).collect();
    v.join(sep)
}

/// The sequence table as text.
pub fn table(rows: &[SequenceRow]) -> String {
    let mut out = format!(
        "{:>4} {:>7} {:>7} {:>12} {:>12} {:>8}  {:<55} status\n",
        "run", "PGA x", "PGA y", "peak |θ|", "resid θ", "impacts", "gaps at start (m)"
    );
    for r in rows {
        out += &format!(
            "{:>4} {:>7.3} {:>7.3} {:>12.4e} {:>12.4e} {:>8}  {:<55} {}\n",
            r.run,
            r.pga_x,
            r.pga_y,
            r.peak_rotation,
            r.residual_rotation,
            r.impacts,
            gaps_text(&r.start_gaps, " "),
            r.status
        );
    }
    out
}

/// The sequence table as CSV: run, name, PGAs, peak |θ|, residual θ, impacts, the gaps at the
/// start (`;`-separated, corners in contact order), status.
pub fn csv(rows: &[SequenceRow]) -> String {
    let mut out = String::from(
        "run,name,pga_x,pga_y,peak_rotation,residual_rotation,impacts,start_gaps,status\n",
    );
    for r in rows {
        out += &format!(
            "{},{},{},{},{:.9e},{:.9e},{},{},\"{}\"\n",
            r.run,
            r.name,
            r.pga_x,
            r.pga_y,
            r.peak_rotation,
            r.residual_rotation,
            r.impacts,
            gaps_text(&r.start_gaps, ";"),
            r.status
        );
    }
    out
}

/// The study rows of a sequence, one per run of `runs`: a run that failed keeps its partial
/// summary and its error; the runs after it carry the same error.
fn study_rows(
    mut seq: Sequence,
    error: Option<SequenceError>,
    runs: &[usize],
    set: &[(String, String)],
) -> Vec<crate::studies::Row> {
    // the first run without a full row: the one that stopped, else the one never started
    let stopped = matches!(
        error,
        Some(SequenceError::Failed { .. } | SequenceError::Cancelled { .. })
    );
    let first_bad = seq.runs.len() - usize::from(stopped && !seq.runs.is_empty());
    let failure: Option<Arc<RunFailure>> = error.map(|e| {
        let last = seq.runs.last_mut().map(|r| &mut r.run.stop);
        Arc::new(match (e, last) {
            (SequenceError::Failed { .. }, Some(stop @ Stop::Failed(_))) => {
                match std::mem::replace(stop, Stop::Finished) {
                    Stop::Failed(s) => RunFailure::from(s),
                    other => RunFailure::Sequence(other.label().into()),
                }
            }
            (SequenceError::Model { source, .. }, _) => RunFailure::Model(source),
            (e, _) => RunFailure::Sequence(e.to_string()),
        })
    });
    let mut rows = Vec::new();
    for (i, &k) in runs.iter().enumerate() {
        let mut settings = set.to_vec();
        settings.push(("excitation.run".into(), k.to_string()));
        let mut row = match seq.runs.get(i) {
            Some(r) => row_of(settings, &r.run.output),
            None => nan_row(settings),
        };
        if i >= first_bad {
            row.error = failure.clone();
        }
        rows.push(row);
    }
    rows
}

fn nan_row(settings: Vec<(String, String)>) -> crate::studies::Row {
    crate::studies::Row {
        settings,
        peak_rotation: f64::NAN,
        residual_rotation: f64::NAN,
        peak_x: f64::NAN,
        peak_y: f64::NAN,
        impacts: 0,
        stick_time: f64::NAN,
        energy_closure_rel: f64::NAN,
        wall_time: f64::NAN,
        error: None,
    }
}

impl BridgeSequence {
    /// Study rows of one sequence of `runs` with the overrides `set`.
    fn study_sequence(&self, runs: &[usize], set: &[(String, String)]) -> Vec<crate::studies::Row> {
        let ov: Vec<String> = set.iter().map(|(k, v)| format!("{k}={v}")).collect();
        let (seq, error) = self.run_silent(runs, &ov);
        study_rows(seq, error, runs, set)
    }

    /// Fig. 7 analog of the sequence: `runs` in one sequence without contact and one with
    /// contact, in parallel. Rows: run, pga_x, pga_y, no contact, contact.
    pub fn rotation_vs_pga(
        &self,
        runs: &[usize],
    ) -> Vec<(usize, f64, f64, crate::studies::Row, crate::studies::Row)> {
        let sets = [false, true].map(|c| vec![("contacts.enabled".into(), c.to_string())]);
        let mut both: Vec<Vec<crate::studies::Row>> = sets
            .par_iter()
            .map(|s| self.study_sequence(runs, s))
            .collect();
        let with = both.pop().unwrap_or_default();
        let without = both.pop().unwrap_or_default();
        (runs.iter().zip(without).zip(with))
            .map(|((&k, a), b)| {
                let i = &self.runs[k - 1];
                (k, i.pga_x, i.pga_y, a, b)
            })
            .collect()
    }

    /// Fig. 8 analog of the sequence: one sequence of `runs` per μ and one without contact,
    /// in parallel.
    pub fn increase_vs_mu(&self, mus: &[f64], runs: &[usize]) -> MuStudy {
        let mut sets: Vec<Vec<(String, String)>> =
            vec![vec![("contacts.enabled".into(), "false".into())]];
        sets.extend(
            mus.iter()
                .map(|m| vec![("contacts.mu".into(), format!("{m}"))]),
        );
        let mut seqs: Vec<Vec<crate::studies::Row>> = sets
            .par_iter()
            .map(|s| self.study_sequence(runs, s))
            .collect();
        let baseline = seqs.remove(0);
        let rows = (0..runs.len())
            .map(|r| seqs.iter().map(|s| s[r].clone()).collect())
            .collect();
        MuStudy {
            mus: mus.to_vec(),
            pgas: (runs.iter())
                .map(|&k| (self.runs[k - 1].pga_x, self.runs[k - 1].pga_y))
                .collect(),
            baseline,
            rows,
        }
    }
}
