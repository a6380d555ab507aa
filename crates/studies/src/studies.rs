//! Parameter studies (paper §4.2–4.4): sweeps over any scalar of a model in parallel (rayon),
//! peak deck rotation against PGA with and without contact (Fig. 7), and the increase of peak
//! rotation with μ (Fig. 8).

use crate::FrictionFork;
use crate::model::{self, ModelError};
use crate::output::RunOutput;
pub use crate::output::deck::{
    DeckPeaks, deck_bodies, free_body_rotation, largest_rotation_dof, rotation_dof,
};
use crate::progress::{Progress, Unwatched};
pub use csv::{csv_fields, csv_header, csv_text, row_from_csv, write_csv};

mod csv;
use crate::run::SolverError;
use crate::scene::{Scene, SceneKey};
use rayon::prelude::*;
use serde::{Serialize, Serializer};
use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Why a run of a study gave no output.
#[derive(Debug, thiserror::Error)]
pub enum RunFailure {
    /// The model with the run's overrides is invalid.
    #[error("{0}")]
    Model(#[from] ModelError),
    /// [`SolverError::Unstable`]: the method detected energy growth.
    #[error("unstable: {0}")]
    Unstable(SolverError),
    /// Any other solver error.
    #[error("failed: {0}")]
    Solver(SolverError),
    /// A run of a sequence that did not run to its end for another reason (the sequence's
    /// error: an earlier run stopped, a cancel, a state that could not be handed over).
    #[error("sequence: {0}")]
    Sequence(String),
    /// The study was cancelled ([`Progress::go_on`]) before this run started.
    #[error("cancelled before it ran")]
    Cancelled,
    /// A run of a record suite that failed or was refused: its status (`crate::suite`).
    #[error("{0}")]
    Suite(String),
    /// A failure read back from a CSV row (a resumed job's journal): its text.
    #[error("{0}")]
    Recorded(String),
}

impl From<SolverError> for RunFailure {
    fn from(e: SolverError) -> Self {
        match e {
            SolverError::Unstable { .. } => RunFailure::Unstable(e),
            e => RunFailure::Solver(e),
        }
    }
}

/// A failure shared by the rows and points that report it.
pub(crate) type Failure = Arc<RunFailure>;

/// A failure serialized as its message.
pub(crate) fn failure_text<S: Serializer>(e: &Option<Failure>, s: S) -> Result<S::Ok, S::Error> {
    match e {
        Some(e) => s.serialize_some(&e.to_string()),
        None => s.serialize_none(),
    }
}

/// One swept key and its values (`key=a:b:step` or `key=v1,v2,…`).
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    pub key: String,
    pub values: Vec<String>,
}

/// Parse `key=a:b:step` (inclusive, numeric) or `key=v1,v2,…`.
pub fn parse_axis(spec: &str) -> Result<Axis, String> {
    let (key, vals) = spec
        .split_once('=')
        .ok_or_else(|| format!("'{spec}': expected key=a:b:step or key=v1,v2"))?;
    let key = key.trim().to_string();
    let parts: Vec<&str> = vals.split(':').collect();
    let values: Vec<String> = if parts.len() == 3 {
        let num = |s: &str| {
            s.trim()
                .parse::<f64>()
                .map_err(|_| format!("'{spec}': '{s}' is not a number"))
        };
        let (a, b, h) = (num(parts[0])?, num(parts[1])?, num(parts[2])?);
        if h.is_nan() || h <= 0.0 || !a.is_finite() || !b.is_finite() || b < a {
            return Err(format!("'{spec}': need a ≤ b and step > 0"));
        }
        let n = ((b - a) / h + 1e-9).floor() as usize;
        if n > 100_000 {
            return Err(format!("'{spec}': too many values"));
        }
        (0..=n)
            .map(|i| {
                let v = a + i as f64 * h;
                let r = (v * 1e12).round() / 1e12;
                if r.fract() == 0.0 && !vals.contains('.') {
                    format!("{}", r as i64)
                } else {
                    format!("{r}")
                }
            })
            .collect()
    } else {
        vals.split(',').map(|s| s.trim().to_string()).collect()
    };
    if values.is_empty() || values.iter().any(|v| v.is_empty()) {
        return Err(format!("'{spec}': no values"));
    }
    Ok(Axis { key, values })
}

/// Most runs one sweep makes (the product of its axes' lengths): 100 000, about an hour of
/// the default model on two cores.
pub const MAX_SWEEP_RUNS: usize = 100_000;

/// A sweep refused before it starts: its axes make too many runs.
#[derive(Debug, thiserror::Error)]
#[error(
    "the sweep's axes make {runs} runs ({sizes}), more than the limit of {cap}: use fewer values or a coarser step"
)]
pub struct SweepTooLarge {
    /// The product of the axes' lengths (saturated at `u128::MAX`).
    pub runs: u128,
    /// Each axis's key and number of values, `a (n) × b (m)`.
    pub sizes: String,
    pub cap: usize,
}

/// The number of runs of a sweep over `axes`, or why it is refused (above `cap`).
pub fn sweep_size(axes: &[Axis], cap: usize) -> Result<usize, SweepTooLarge> {
    let runs = (axes.iter()).fold(1u128, |p, a| p.saturating_mul(a.values.len() as u128));
    if runs > cap as u128 {
        let sizes: Vec<String> = (axes.iter())
            .map(|a| format!("{} ({})", a.key, a.values.len()))
            .collect();
        return Err(SweepTooLarge {
            runs,
            sizes: sizes.join(" × "),
            cap,
        });
    }
    Ok(runs as usize)
}

/// What a sweep records of one run.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub settings: Vec<(String, String)>,
    pub peak_rotation: f64,
    pub residual_rotation: f64,
    pub peak_x: f64,
    pub peak_y: f64,
    pub impacts: usize,
    pub stick_time: f64,
    pub energy_closure_rel: f64,
    pub wall_time: f64,
    #[serde(serialize_with = "failure_text")]
    pub error: Option<Failure>,
}

pub fn row_of(settings: Vec<(String, String)>, r: &RunOutput) -> Row {
    let s = &r.summary;
    let deck = DeckPeaks::of(r);
    Row {
        settings,
        peak_rotation: deck.rotation,
        residual_rotation: deck.residual,
        peak_x: deck.x,
        peak_y: deck.y,
        impacts: s.stats.impacts,
        stick_time: s.contacts.iter().map(|c| c.stick_time).sum(),
        energy_closure_rel: s.energy_closure_rel,
        wall_time: s.stats.wall_time,
        error: None,
    }
}

/// A model read once, run many times with overrides.
pub struct Study {
    pub path: PathBuf,
    pub text: String,
    pub base: Vec<String>,
    /// The processed records, read once for all the runs.
    pub motions: model::Motions,
}

impl Study {
    pub fn open(path: &Path, base: &[String]) -> Result<Self, ModelError> {
        let text = std::fs::read_to_string(path).map_err(|e| ModelError::Io {
            path: path.to_path_buf(),
            source: e,
        })?;
        Self::from_text(&text, path, base)
    }

    /// A study of model text that is not (or not yet) the file's content, such as the
    /// workbench's form draft: `path` names it in errors and anchors the record files it
    /// refers to. The model is compiled once here, so a bad one fails before any run.
    pub fn from_text(text: &str, path: &Path, base: &[String]) -> Result<Self, ModelError> {
        let motions = model::Motions::default();
        model::load_str_with(text, path, base, &motions)?;
        Ok(Self {
            path: path.to_path_buf(),
            text: text.to_string(),
            base: base.to_vec(),
            motions,
        })
    }

    /// The scene with extra `key=value` overrides.
    pub fn scene(&self, set: &[String]) -> Result<Scene, ModelError> {
        let mut ov = self.base.clone();
        ov.extend(set.iter().cloned());
        model::load_str_with(&self.text, &self.path, &ov, &self.motions)
    }

    /// The scene of a sweep row: its summary is all a row needs, so no history is kept.
    fn row_scene(&self, set: &[(String, String)]) -> Result<Scene, ModelError> {
        let ov: Vec<String> = set.iter().map(|(k, v)| format!("{k}={v}")).collect();
        let mut scene = self.scene(&ov)?;
        scene.settings.keep_history = false;
        Ok(scene)
    }

    /// Run with extra `key=value` overrides: the output and the wall time of the integration.
    pub fn simulate(&self, set: &[String]) -> Result<(RunOutput, f64), RunFailure> {
        simulate_scene(&self.scene(set)?)
    }

    /// [`Study::simulate`] without the accuracy bounds (`simulate::judge`): for studies that
    /// measure the error themselves. The time is the CPU time of the thread that ran the
    /// integration ([`crate::clock::thread_cpu`]), not its wall time.
    pub fn measure(&self, set: &[String]) -> Result<(RunOutput, f64), RunFailure> {
        let scene = self.scene(set)?;
        let (r, cpu) = crate::clock::thread_cpu(|| {
            crate::simulate::integrate_unjudged(&scene, &mut crate::Silent)
        });
        Ok((r.into_result()?, cpu))
    }

    /// Run with extra overrides: the row of its summary.
    pub fn run(&self, set: &[(String, String)]) -> Row {
        match self
            .row_scene(set)
            .map_err(RunFailure::from)
            .and_then(|s| simulate_scene(&s))
        {
            Ok((r, _)) => row_of(set.to_vec(), &r),
            Err(e) => error_row(set.to_vec(), e),
        }
    }

    /// All combinations of the axes, run in parallel on all cores; rows in input order (axes
    /// from the user are first counted by [`sweep_size`] against [`MAX_SWEEP_RUNS`]). Rows whose scenes are the same
    /// ([`same_scenes`]) are run once and share the result, each row with its own settings.
    pub fn sweep(&self, axes: &[Axis]) -> Vec<Row> {
        self.sweep_counted(axes).rows
    }

    /// [`Study::sweep`], with the number of runs of the integrator it took.
    pub fn sweep_counted(&self, axes: &[Axis]) -> SweepOutcome {
        self.sweep_rows(axes, 0..usize::MAX, &Unwatched)
    }

    /// [`Study::sweep_counted`] watched by `progress`: each row is handed to it as soon as it
    /// is final (a run finished, or its model did not compile), by its index in the output,
    /// from the threads that run them; once [`Progress::go_on`] says no, the runs not yet
    /// started are skipped and their rows fail with [`RunFailure::Cancelled`] (not handed
    /// over). Runs already started finish.
    pub fn sweep_watched(&self, axes: &[Axis], progress: &dyn Watch) -> SweepOutcome {
        self.sweep_rows(axes, 0..usize::MAX, progress)
    }

    /// The rows `range` (indices of [`Study::sweep`]'s rows, cut to their number) of the
    /// sweep, `progress` told of each row as it is done (by its index within `range`): a
    /// shard of a sweep ([`crate::shard`]). Rows of the same scene within `range` run once.
    pub fn sweep_rows(
        &self,
        axes: &[Axis],
        range: Range<usize>,
        progress: &dyn Watch,
    ) -> SweepOutcome {
        let size = (axes.iter()).fold(1usize, |p, a| p.saturating_mul(a.values.len()));
        let indices: Vec<usize> = (range.start.min(size)..range.end.min(size)).collect();
        self.sweep_listed(axes, &indices, progress)
    }

    /// [`Study::sweep_rows`] on the rows `indices` (those below the sweep's size), in their
    /// order, `progress` told of each by its position in `indices`: what a resumed sweep has
    /// left to run.
    pub fn sweep_listed(
        &self,
        axes: &[Axis],
        indices: &[usize],
        progress: &dyn Watch,
    ) -> SweepOutcome {
        let all = combinations(axes);
        let combos: Vec<Vec<(String, String)>> = (indices.iter())
            .filter_map(|&i| all.get(i).cloned())
            .collect();
        let combos = &combos[..];
        progress.plan(combos.len());
        let compiled: Vec<Result<Scene, ModelError>> =
            combos.par_iter().map(|c| self.row_scene(c)).collect();
        let mut rows: Vec<Option<Row>> = vec![None; combos.len()];
        let scenes: Vec<Option<Scene>> = (compiled.into_iter().enumerate())
            .map(|(i, r)| match r {
                Ok(s) => Some(s),
                Err(e) => {
                    let row = error_row(combos[i].clone(), e.into());
                    progress.row(i, &row);
                    progress.done(1);
                    rows[i] = Some(row);
                    None
                }
            })
            .collect();
        let same = same_scenes(&scenes);
        let unique: Vec<usize> = (0..combos.len())
            .filter(|&i| scenes[i].is_some() && same[i] == i)
            .collect();
        let mut sharing: Vec<Vec<usize>> = vec![Vec::new(); combos.len()];
        for (i, &s) in same.iter().enumerate() {
            if s != i {
                sharing[s].push(i);
            }
        }
        let runs = AtomicUsize::new(0);
        let job = Job {
            combos,
            scenes: &scenes,
            runs: &runs,
            sharing: &sharing,
            progress,
        };
        // μ variants of one run share their motion until the first contact event
        let mu = FRICTION_KEY;
        let ran: Vec<(usize, Row)> = if axes.iter().any(|a| a.key == mu && a.values.len() > 1) {
            let others = |c: &[(String, String)]| -> Vec<(String, String)> {
                c.iter().filter(|(k, _)| k != mu).cloned().collect()
            };
            let mut groups: Vec<Vec<usize>> = Vec::new();
            for &i in &unique {
                match (groups.iter_mut()).find(|g| others(&combos[g[0]]) == others(&combos[i])) {
                    Some(g) => g.push(i),
                    None => groups.push(vec![i]),
                }
            }
            groups
                .par_iter()
                .flat_map(|g| job.friction_group(g))
                .collect()
        } else {
            unique.par_iter().map(|&i| (i, job.row(i, None))).collect()
        };
        for (i, r) in ran {
            rows[i] = Some(r);
        }
        let rows = (0..combos.len())
            .map(|i| {
                let mut r = rows[same[i]]
                    .clone()
                    .expect("every first of its scene has run");
                r.settings = combos[i].clone();
                r
            })
            .collect();
        SweepOutcome {
            rows,
            integrations: runs.into_inner(),
        }
    }
}

/// The rows of a sweep and the runs of the integrator they took.
#[derive(Clone, Debug)]
pub struct SweepOutcome {
    pub rows: Vec<Row>,
    /// Runs of the integrator: one per distinct scene that compiled (a row whose scene
    /// another row has is not run again).
    pub integrations: usize,
}

/// Every combination of the axes' values, the first axis varying slowest.
pub fn combinations(axes: &[Axis]) -> Vec<Vec<(String, String)>> {
    let mut combos: Vec<Vec<(String, String)>> = vec![vec![]];
    for ax in axes {
        combos = combos
            .into_iter()
            .flat_map(|c| {
                ax.values.iter().map(move |v| {
                    let mut c = c.clone();
                    c.push((ax.key.clone(), v.clone()));
                    c
                })
            })
            .collect();
    }
    combos
}

/// The rows of a sweep to run: their settings and compiled scenes, a count of the runs, the
/// rows that share each row's scene, and who watches.
struct Job<'a> {
    combos: &'a [Vec<(String, String)>],
    scenes: &'a [Option<Scene>],
    runs: &'a AtomicUsize,
    /// For each row run, the later rows with the same scene.
    sharing: &'a [Vec<usize>],
    progress: &'a dyn Watch,
}

impl Job<'_> {
    /// Row `i` (its scene compiled), through `fork` when it allows it; skipped when the
    /// progress says stop. The row and those sharing its scene go to the progress.
    fn row(&self, i: usize, fork: Option<&FrictionFork>) -> Row {
        let settings = self.combos[i].clone();
        if !self.progress.go_on() {
            return error_row(settings, RunFailure::Cancelled);
        }
        let scene = self.scenes[i]
            .as_ref()
            .expect("a row that runs has compiled");
        let forked = fork.and_then(|f| f.run(scene));
        self.runs.fetch_add(1, Ordering::Relaxed);
        let result = match forked {
            Some(r) => r.map_err(RunFailure::from),
            None => simulate_scene(scene).map(|(r, _)| r),
        };
        self.progress.done(1 + self.sharing[i].len());
        let row = match result {
            Ok(r) => row_of(settings, &r),
            Err(e) => error_row(settings, e),
        };
        self.progress.row(i, &row);
        for &j in &self.sharing[i] {
            let mut shared = row.clone();
            shared.settings = self.combos[j].clone();
            self.progress.row(j, &shared);
        }
        row
    }

    /// Rows that differ only in `contacts.mu`, through a [`FrictionFork`] when they allow it.
    fn friction_group(&self, group: &[usize]) -> Vec<(usize, Row)> {
        let fork = (self.scenes[group[0]].as_ref())
            .filter(|_| group.len() > 1 && self.progress.go_on())
            .and_then(|s| FrictionFork::new(s).ok());
        group
            .par_iter()
            .map(|&i| (i, self.row(i, fork.as_ref())))
            .collect()
    }
}

/// For each scene, the index of the first scene equal to it, itself when no scene before is
/// (rows that did not compile are their own). Equal: the same bodies, contacts, elements,
/// supports, loads, initial state and settings ([`SceneKey`]); the title, which names the
/// run, is not compared.
pub(crate) fn same_scenes(scenes: &[Option<Scene>]) -> Vec<usize> {
    let keys: Vec<Option<SceneKey>> = (scenes.par_iter())
        .map(|s| s.as_ref().map(SceneKey::of))
        .collect();
    let mut firsts: HashMap<&str, Vec<usize>> = HashMap::new();
    (0..scenes.len())
        .map(|i| {
            let Some(k) = &keys[i] else { return i };
            let known = firsts.entry(k.text.as_str()).or_default();
            let same = known.iter().copied().find(|&j| {
                let kj = keys[j].as_ref().expect("listed keys exist");
                kj.same(k)
            });
            same.unwrap_or_else(|| {
                known.push(i);
                i
            })
        })
        .collect()
}

/// A sweep's watcher: its counts of runs ([`Progress`]) and each row as soon as it is final,
/// by its index in the sweep's output (the workbench draws them as they come). Called from
/// the threads that run the rows.
pub trait Watch: Progress {
    /// Row `index` is final.
    fn row(&self, index: usize, row: &Row) {
        let _ = (index, row);
    }
}

impl Watch for Unwatched {}

/// A watcher whose runs were planned already and whose indices start at `by` (a study made of
/// several sweeps, one after another): passes on the runs done, the rows and the cancel.
struct Offset<'a> {
    inner: &'a dyn Watch,
    by: usize,
}

impl Progress for Offset<'_> {
    fn plan(&self, _: usize) {}
    fn done(&self, runs: usize) {
        self.inner.done(runs)
    }
    fn go_on(&self) -> bool {
        self.inner.go_on()
    }
}

impl Watch for Offset<'_> {
    fn row(&self, index: usize, row: &Row) {
        self.inner.row(index + self.by, row);
    }
}

/// The sweep key whose variants share their motion until the first contact ([`FrictionFork`]).
pub(crate) const FRICTION_KEY: &str = "contacts.mu";

fn simulate_scene(scene: &Scene) -> Result<(RunOutput, f64), RunFailure> {
    let t0 = std::time::Instant::now();
    let r = crate::simulate(scene, &mut crate::Silent)?;
    Ok((r, t0.elapsed().as_secs_f64()))
}

fn error_row(settings: Vec<(String, String)>, e: RunFailure) -> Row {
    Row {
        settings,
        peak_rotation: f64::NAN,
        residual_rotation: f64::NAN,
        peak_x: f64::NAN,
        peak_y: f64::NAN,
        impacts: 0,
        stick_time: f64::NAN,
        energy_closure_rel: f64::NAN,
        wall_time: f64::NAN,
        error: Some(Arc::new(e)),
    }
}

/// The swept keys of a sweep over `axes`.
pub fn axis_keys(axes: &[Axis]) -> Vec<String> {
    axes.iter().map(|a| a.key.clone()).collect()
}

/// A plain text table of sweep rows.
pub fn table(rows: &[Row]) -> String {
    let mut out = String::new();
    if let Some(r) = rows.first() {
        for (k, _) in &r.settings {
            out += &format!("{k:>22} ");
        }
    }
    out += &format!(
        "{:>12} {:>12} {:>8} {:>9} {:>9}\n",
        "peak θ", "resid θ", "impacts", "stick s", "wall ms"
    );
    for r in rows {
        for (_, v) in &r.settings {
            out += &format!("{v:>22} ");
        }
        match &r.error {
            Some(e) => out += &format!("error: {e}\n"),
            None => {
                out += &format!(
                    "{:>12.4e} {:>12.4e} {:>8} {:>9.3} {:>9.1}\n",
                    r.peak_rotation,
                    r.residual_rotation,
                    r.impacts,
                    r.stick_time,
                    r.wall_time * 1e3
                )
            }
        }
    }
    out
}

/// Number of `[[run]]` entries of a bridge model.
pub fn run_count(text: &str) -> usize {
    toml::from_str::<toml::Table>(text)
        .ok()
        .and_then(|t| t.get("run").and_then(|r| r.as_array()).map(|a| a.len()))
        .unwrap_or(0)
}

/// Fig. 7: peak deck rotation per run with and without contact. Rows: run, pga_x, pga_y,
/// peak without contact, peak with contact.
pub fn rotation_vs_pga(study: &Study, progress: &dyn Watch) -> Vec<(usize, f64, f64, Row, Row)> {
    let pgas = run_pgas(&study.text);
    let n = pgas.len();
    let runs: Vec<String> = (1..=n).map(|i| i.to_string()).collect();
    let axes = [
        Axis {
            key: "excitation.run".into(),
            values: runs,
        },
        Axis {
            key: "contacts.enabled".into(),
            values: vec!["false".into(), "true".into()],
        },
    ];
    // row 2 (k − 1) is run k without contact, 2 (k − 1) + 1 with contact
    let rows = study.sweep_rows(&axes, 0..usize::MAX, progress).rows;
    rows.chunks(2)
        .enumerate()
        .map(|(i, pair)| {
            let (px, py) = pgas.get(i).copied().unwrap_or((f64::NAN, f64::NAN));
            (i + 1, px, py, pair[0].clone(), pair[1].clone())
        })
        .collect()
}

/// (pga_x, pga_y) of each `[[run]]` of a bridge model (NaN where not given): as many as
/// [`run_count`] counts.
pub fn run_pgas(text: &str) -> Vec<(f64, f64)> {
    toml::from_str::<toml::Table>(text)
        .ok()
        .and_then(|t| {
            t.get("run").and_then(|r| r.as_array()).map(|a| {
                a.iter()
                    .map(|r| {
                        let g = |k: &str| r.get(k).and_then(|v| v.as_float()).unwrap_or(f64::NAN);
                        (g("pga_x"), g("pga_y"))
                    })
                    .collect()
            })
        })
        .unwrap_or_default()
}

/// Fig. 8: percent increase of peak rotation over the no-contact peak, per run and μ.
pub struct MuStudy {
    pub mus: Vec<f64>,
    pub pgas: Vec<(f64, f64)>,
    /// Peak rotation without contact per run.
    pub baseline: Vec<Row>,
    /// rows[run][mu].
    pub rows: Vec<Vec<Row>>,
}

impl MuStudy {
    pub fn increase(&self, run: usize, mu: usize) -> f64 {
        100.0 * (self.rows[run][mu].peak_rotation / self.baseline[run].peak_rotation - 1.0)
    }
    pub fn mean_increase(&self, mu: usize) -> f64 {
        let n = self.rows.len() as f64;
        (0..self.rows.len())
            .map(|r| self.increase(r, mu))
            .sum::<f64>()
            / n
    }
}

/// The μ values of the paper's Fig. 8: 0, 0.1, …, 0.7.
pub fn fig8_mus() -> Vec<f64> {
    (0..=7).map(|i| i as f64 / 10.0).collect()
}

/// Fig. 8: the peak rotation of each run without contact, and with contact for each μ;
/// `progress` gets rows `0..n` (the n runs without contact), then row
/// `n + (k − 1) · mus.len() + j` (run k with `mus[j]`).
pub fn increase_vs_mu(study: &Study, mus: &[f64], progress: &dyn Watch) -> MuStudy {
    let pgas = run_pgas(&study.text);
    let n = pgas.len();
    let runs: Vec<String> = (1..=n).map(|i| i.to_string()).collect();
    let baseline = [
        Axis {
            key: "excitation.run".into(),
            values: runs.clone(),
        },
        Axis {
            key: "contacts.enabled".into(),
            values: vec!["false".into()],
        },
    ];
    let varied = [
        Axis {
            key: "excitation.run".into(),
            values: runs,
        },
        Axis {
            key: "contacts.mu".into(),
            values: mus.iter().map(|m| format!("{m}")).collect(),
        },
    ];
    // both planned before either runs, so that the bar's length is the job's
    progress.plan(sweep_size(&baseline, usize::MAX).unwrap_or(0));
    progress.plan(sweep_size(&varied, usize::MAX).unwrap_or(0));
    let first = Offset {
        inner: progress,
        by: 0,
    };
    let baseline = study.sweep_rows(&baseline, 0..usize::MAX, &first).rows;
    let then = Offset {
        inner: progress,
        by: n,
    };
    let rows = study.sweep_rows(&varied, 0..usize::MAX, &then).rows;
    MuStudy {
        mus: mus.to_vec(),
        pgas,
        baseline,
        rows: rows.chunks(mus.len()).map(|c| c.to_vec()).collect(),
    }
}
