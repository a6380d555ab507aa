//! Record suites (incremental dynamic analysis): a bridge model under every record pair of a
//! folder or list ([`records`]), both components of a pair scaled by one factor so that the
//! pair's intensity — the geometric mean of its components' PGA or Sa(T, ζ), of the records as
//! the model processes them (time scale, baseline correction, taper) — equals each level
//! ([`intensity`]), crossed with the values of swept keys as `sweep`; each run to the end of
//! its longer record plus a free-vibration tail. Run `i` of the suite is pair ⌊i/(L·P)⌋,
//! level ⌊i/P⌋ mod L, point i mod P (L levels, P points). Rows ([`row`]), their statistics per
//! level and point ([`stats`]).

pub mod chart;
pub mod intensity;
pub mod metrics;
pub mod records;
pub mod row;
pub mod stats;

use crate::model::{ModelError, Motions, apply_overrides, load_str_with};
use crate::progress::Progress;
use crate::scene::{Motion, Scene};
use crate::studies::{Axis, MAX_SWEEP_RUNS, SweepTooLarge, combinations, sweep_size};
use intensity::{Measure, MeasureSpec, Period, pair_intensity};
use metrics::bent_heights;
use rayon::prelude::*;
use records::SuitePair;
use row::{Status, SuiteRow};
use std::collections::{HashMap, HashSet};
use std::ops::Range;
use std::path::{Path, PathBuf};

/// Free vibration after the end of the longer record, s, when not given (as `stress`).
pub const DEFAULT_TAIL: f64 = 2.0;

/// Keys the suite sets for each run itself: they cannot be swept or fixed.
const RESERVED: [&str; 6] = [
    "excitation.run",
    "excitation.longitudinal",
    "excitation.transverse",
    "excitation.kind",
    "solver.t_end",
    "run",
];

/// What a suite runs, besides its model and records.
#[derive(Clone, Debug)]
pub struct SuiteSpec {
    pub measure: MeasureSpec,
    /// Intensity levels, g.
    pub levels: Vec<f64>,
    /// Swept keys (`--set`), crossed with the levels.
    pub axes: Vec<Axis>,
    /// Free vibration after the end of the longer record, s.
    pub tail: f64,
}

/// A suite refused before it starts.
#[derive(Debug, thiserror::Error)]
pub enum SuiteError {
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error(
        "{path}: a record suite needs a bridge file whose [excitation] table has kind = \"record\": {reason}"
    )]
    NotRecords { path: PathBuf, reason: String },
    #[error(
        "{path}: the suite cannot append its [[run]] table (the one that scales the records): is `run` an inline array?"
    )]
    NoRunTable { path: PathBuf },
    #[error(
        "'{argument}': the suite sets {key} itself for each run (the records, their scaling, the run's end)"
    )]
    Reserved { argument: String, key: String },
    /// `excitation.window` in the model (`place`: its path) or an argument (`place`: it).
    #[error(
        "{place}: excitation.window: a suite runs each pair's records whole (their intensity and scaling are the whole records'); a window is for a single run"
    )]
    Window { place: String },
    #[error(transparent)]
    TooLarge(#[from] SweepTooLarge),
    #[error("--tail {0}: the free vibration after the records must be ≥ 0 s and finite")]
    Tail(f64),
    #[error("{path}: the model has no modes, so sa:T1 has no period")]
    NoModes { path: PathBuf },
}

/// The key an override or axis argument sets, if the suite reserves it.
pub(crate) fn reserved(key: &str) -> Option<&'static str> {
    let key = key.trim();
    RESERVED
        .into_iter()
        .find(|r| key == *r || key.strip_prefix(r).is_some_and(|s| s.starts_with('.')))
}

/// The model text with `excitation.run` blanked in place (lines kept, so that errors name the
/// file's lines): its records processed but not scaled. Refused unless `[excitation]` is a
/// table with `kind = "record"`.
fn unscaled_text(text: &str, path: &Path) -> Result<String, SuiteError> {
    let refuse = |reason: &str| SuiteError::NotRecords {
        path: path.to_path_buf(),
        reason: reason.to_string(),
    };
    let doc = toml_edit::Document::parse(text).map_err(|e| refuse(e.message()))?;
    let table = (doc.get("excitation").and_then(|e| e.as_table()))
        .ok_or_else(|| refuse("no [excitation] table"))?;
    if table.get("kind").and_then(|k| k.as_str()) != Some("record") {
        return Err(refuse("its kind is not \"record\""));
    }
    if table.contains_key("window") {
        let place = path.display().to_string();
        return Err(SuiteError::Window { place });
    }
    let mut out = text.to_string();
    if let Some(key) = table.key("run") {
        let value = table.get("run").and_then(|v| v.span());
        let (Some(k), Some(v)) = (key.span(), value) else {
            return Err(refuse("excitation.run is not a plain key = value line"));
        };
        out.replace_range(k.start..v.end, &" ".repeat(v.end - k.start));
    }
    Ok(out)
}

/// A TOML string of a path.
fn toml_string(p: &Path) -> String {
    toml_edit::Value::from(p.to_string_lossy().as_ref()).to_string()
}

/// A pair at one parameter point, ready for its levels.
#[derive(Clone, Debug)]
struct Prepared {
    /// The fixed overrides, the point's settings and the pair's records.
    overrides: Vec<String>,
    /// The pair's intensity unscaled, g, and its components' PGAs, g.
    intensity: f64,
    pga: (f64, f64),
    /// The end of the longer record plus the tail, s.
    t_end: f64,
    heights: Vec<(String, f64)>,
}

/// Why a run was refused when its suite was cancelled before it started.
pub const CANCELLED: &str = "cancelled before it ran";

/// The checks of a suite's arguments before its model is read: no reserved or windowing key
/// fixed or swept, a finite tail ≥ 0, at most [`MAX_SWEEP_RUNS`] runs ([`Suite::open`]; the
/// front ends that open a suite from text call it before [`Suite::from_text`]).
pub fn check_arguments(
    fix: &[String],
    pairs: &[SuitePair],
    spec: &SuiteSpec,
) -> Result<(), SuiteError> {
    let args = (fix.iter().map(|f| (f, f.split('=').next().unwrap_or(""))))
        .chain(spec.axes.iter().map(|a| (&a.key, a.key.as_str())));
    for (argument, key) in args {
        if let Some(r) = reserved(key) {
            let (argument, key) = (argument.clone(), r.to_string());
            return Err(SuiteError::Reserved { argument, key });
        }
        if key.trim() == "excitation.window" {
            let place = format!("'{argument}'");
            return Err(SuiteError::Window { place });
        }
    }
    if !(spec.tail.is_finite() && spec.tail >= 0.0) {
        return Err(SuiteError::Tail(spec.tail));
    }
    let names = Axis {
        key: "records".into(),
        values: pairs.iter().map(|p| p.name.clone()).collect(),
    };
    let levels = Axis {
        key: "levels".into(),
        values: spec.levels.iter().map(|l| l.to_string()).collect(),
    };
    let all: Vec<Axis> = [names, levels]
        .into_iter()
        .chain(spec.axes.clone())
        .collect();
    sweep_size(&all, MAX_SWEEP_RUNS)?;
    Ok(())
}

/// A bridge model, its record pairs, levels and swept keys: the runs of a suite.
pub struct Suite {
    path: PathBuf,
    unscaled: String,
    /// The model text with one `[[run]]` appended (index `run`, 1-based) that scales the pair.
    scaled: String,
    run: usize,
    fix: Vec<String>,
    /// The processed, unscaled records (and the record files, read once).
    motions: Motions,
    pub pairs: Vec<SuitePair>,
    pub measure: Measure,
    pub levels: Vec<f64>,
    pub axes: Vec<Axis>,
    combos: Vec<Vec<(String, String)>>,
    pub tail: f64,
}

impl Suite {
    /// The suite of the model at `path` with `fix` overrides; refused before any run when the
    /// model, an argument or the number of runs (at most [`MAX_SWEEP_RUNS`]) is.
    pub fn open(
        path: &Path,
        fix: &[String],
        pairs: Vec<SuitePair>,
        spec: SuiteSpec,
    ) -> Result<Self, SuiteError> {
        check_arguments(fix, &pairs, &spec)?;
        let text =
            crate::input::read_bounded(path, crate::input::MAX_MODEL_BYTES).map_err(|e| {
                ModelError::Io {
                    path: path.to_path_buf(),
                    source: e,
                }
            })?;
        Self::from_text(&text, path, fix, pairs, spec)
    }

    /// [`Suite::open`] of model text that is not (or not yet) the file's, such as the
    /// workbench's form draft: `path` names it in errors and anchors its record files.
    pub fn from_text(
        text: &str,
        path: &Path,
        fix: &[String],
        pairs: Vec<SuitePair>,
        spec: SuiteSpec,
    ) -> Result<Self, SuiteError> {
        let unscaled = unscaled_text(text, path)?;
        let doc: toml::Table = toml::from_str(text).unwrap_or_default();
        let runs = doc
            .get("run")
            .and_then(|r| r.as_array())
            .map_or(0, |a| a.len());
        let scaled = format!(
            "{}\n[[run]]\nname = \"suite\"\npga_x = 1.0\npga_y = 1.0\n",
            text.trim_end()
        );
        let appended = toml::from_str::<toml::Table>(&scaled).ok().and_then(|d| {
            let a = d.get("run")?.as_array()?.len();
            (a == runs + 1).then_some(())
        });
        if appended.is_none() {
            return Err(SuiteError::NoRunTable {
                path: path.to_path_buf(),
            });
        }
        let motions = Motions::default();
        // the model with its own records: refused here rather than in every run
        let scene = load_str_with(&unscaled, path, fix, &motions)?;
        let measure = match spec.measure {
            MeasureSpec::Pga => Measure::Pga,
            MeasureSpec::Sa { period, damping } => Measure::Sa {
                period: match period {
                    Period::Seconds(t) => t,
                    Period::FirstMode => first_period(&scene).ok_or(SuiteError::NoModes {
                        path: path.to_path_buf(),
                    })?,
                },
                damping,
            },
        };
        Ok(Self {
            path: path.to_path_buf(),
            unscaled,
            scaled,
            run: runs + 1,
            fix: fix.to_vec(),
            motions,
            pairs,
            measure,
            levels: spec.levels,
            combos: combinations(&spec.axes),
            axes: spec.axes,
            tail: spec.tail,
        })
    }

    /// The number of runs: pairs × levels × parameter points.
    pub fn runs(&self) -> usize {
        self.pairs.len() * self.levels.len() * self.combos.len()
    }

    /// The swept keys, in CSV order.
    pub fn keys(&self) -> Vec<String> {
        self.axes.iter().map(|a| a.key.clone()).collect()
    }

    /// (pair, level, point) of run `i`.
    fn coordinates(&self, i: usize) -> (usize, usize, usize) {
        let (nl, np) = (self.levels.len(), self.combos.len());
        (i / (nl * np), (i / np) % nl, i % np)
    }

    /// The runs `range` (cut to [`Suite::runs`]) in parallel, in order; `progress` told of each.
    pub fn run(&self, range: Range<usize>, progress: &dyn Progress) -> Vec<SuiteRow> {
        self.run_each(range, progress, &|_, _| {})
    }

    /// [`Suite::run`], `each` handed every row (by its index in the suite) as soon as it is
    /// final; once [`Progress::go_on`] says no, the runs not started are refused as
    /// [`CANCELLED`].
    pub(crate) fn run_each(
        &self,
        range: Range<usize>,
        progress: &dyn Progress,
        each: &(dyn Fn(usize, &SuiteRow) + Sync),
    ) -> Vec<SuiteRow> {
        let range = range.start.min(self.runs())..range.end.min(self.runs());
        let indices: Vec<usize> = range.collect();
        self.run_listed(&indices, progress, each)
    }

    /// [`Suite::run_each`] on the runs `indices` (those below [`Suite::runs`]), in their
    /// order: what a resumed job has left to run.
    pub fn run_listed(
        &self,
        indices: &[usize],
        progress: &dyn Progress,
        each: &(dyn Fn(usize, &SuiteRow) + Sync),
    ) -> Vec<SuiteRow> {
        let indices: Vec<usize> = (indices.iter().copied())
            .filter(|&i| i < self.runs())
            .collect();
        progress.plan(indices.len());
        // the (pair, point)s of the runs, each once
        let mut seen = HashSet::new();
        let needed: Vec<(usize, usize)> = (indices.iter())
            .map(|&i| self.coordinates(i))
            .map(|(p, _, k)| (p, k))
            .filter(|x| seen.insert(*x))
            .collect();
        let prepared: HashMap<(usize, usize), Result<Prepared, String>> = (needed.par_iter())
            .map(|&(p, k)| ((p, k), self.prepare(p, k)))
            .collect();
        indices
            .into_par_iter()
            .map(|i| {
                let (p, l, k) = self.coordinates(i);
                let cancelled = Err(CANCELLED.to_string());
                let prep = if progress.go_on() {
                    &prepared[&(p, k)]
                } else {
                    &cancelled
                };
                let row = self.run_one((p, l, k), prep);
                progress.done(1);
                each(i, &row);
                row
            })
            .collect()
    }

    /// Pair `p` at point `k`: its records' intensity unscaled, the run's end, the columns.
    fn prepare(&self, p: usize, k: usize) -> Result<Prepared, String> {
        let pair = &self.pairs[p];
        let mut overrides = self.fix.clone();
        overrides.extend(self.combos[k].iter().map(|(k, v)| format!("{k}={v}")));
        overrides.push(format!(
            "excitation.longitudinal={}",
            toml_string(&pair.longitudinal)
        ));
        overrides.push(format!(
            "excitation.transverse={}",
            toml_string(&pair.transverse)
        ));
        let scene = load_str_with(&self.unscaled, &self.path, &overrides, &self.motions)
            .map_err(|e| e.to_string())?;
        let component = |axis: &str| {
            (scene.supports.iter())
                .filter(|s| s.name.ends_with(axis))
                .find_map(|s| match &s.motion {
                    Motion::Record(m) => Some(m.clone()),
                    Motion::Harmonic { .. } => None,
                })
                .ok_or_else(|| format!("the model applies no record along {axis}"))
        };
        let (l, t) = (component(".x")?, component(".y")?);
        let pga = |m: &crate::excitation::GroundMotion| Measure::Pga.of_component(&m.acc, m.dt);
        let of = |m: &crate::excitation::GroundMotion| self.measure.of_component(&m.acc, m.dt);
        let intensity = pair_intensity(of(&l), of(&t));
        if !(intensity.is_finite() && intensity > 0.0) {
            return Err(format!(
                "the pair's {} is {intensity} g: it cannot be scaled",
                self.measure.label()
            ));
        }
        let text = apply_overrides(&self.unscaled, &overrides).map_err(|e| e.to_string())?;
        Ok(Prepared {
            intensity,
            pga: (pga(&l), pga(&t)),
            t_end: records_end(&scene) + self.tail,
            heights: bent_heights(&text),
            overrides,
        })
    }

    /// One run: the pair scaled to the level, at the point, to its records' end and the tail.
    fn run_one(
        &self,
        (p, l, k): (usize, usize, usize),
        prep: &Result<Prepared, String>,
    ) -> SuiteRow {
        let pair = &self.pairs[p];
        let level = self.levels[l];
        let mut row = SuiteRow {
            pair: pair.name.clone(),
            longitudinal: pair.longitudinal_label.clone(),
            transverse: pair.transverse_label.clone(),
            measure: self.measure.label(),
            level,
            scale: None,
            settings: self.combos[k].clone(),
            status: Status::Finished,
            metrics: [None; 11],
        };
        let prep = match prep {
            Ok(prep) => prep,
            Err(reason) => {
                row.status = Status::Refused(reason.clone());
                return row;
            }
        };
        let scale = level / prep.intensity;
        row.scale = Some(scale);
        let scene = match self.scaled_scene(prep, scale) {
            Ok(s) => s,
            Err(e) => {
                row.status = Status::Refused(e.to_string());
                return row;
            }
        };
        let (run, metrics) = metrics::run_measured(scene, &prep.heights);
        row.status = Status::of(&run.stop);
        row.metrics = metrics;
        row
    }
}

impl Suite {
    /// The scene of a prepared pair with both components scaled by `scale`, to the end of its
    /// longer record plus the tail.
    fn scaled_scene(&self, prep: &Prepared, scale: f64) -> Result<Scene, ModelError> {
        let mut ov = prep.overrides.clone();
        let r = self.run - 1;
        ov.extend([
            format!("excitation.run={}", self.run),
            format!("run.{r}.pga_x={:?}", scale * prep.pga.0),
            format!("run.{r}.pga_y={:?}", scale * prep.pga.1),
            format!("solver.t_end={:?}", prep.t_end),
        ]);
        load_str_with(
            &self.scaled,
            &self.path,
            &ov,
            &self.motions.sharing_records(),
        )
    }

    /// The scene of run `i` and its scale factor, as the suite runs it (or why it is refused).
    pub fn scene(&self, i: usize) -> Result<(Scene, f64), String> {
        if i >= self.runs() {
            return Err(format!("no run {i} (the suite has {})", self.runs()));
        }
        let (p, l, k) = self.coordinates(i);
        let prep = self.prepare(p, k)?;
        let scale = self.levels[l] / prep.intensity;
        let scene = self.scaled_scene(&prep, scale).map_err(|e| e.to_string())?;
        Ok((scene, scale))
    }
}

/// The longest period of the model's modes (`modal::modes`), s.
fn first_period(scene: &Scene) -> Option<f64> {
    (crate::modal::modes(scene).iter())
        .map(|m| m.period)
        .filter(|t| t.is_finite() && *t > 0.0)
        .reduce(f64::max)
}

/// The end of the scene's last support record, s (0 without records).
pub(crate) fn records_end(scene: &Scene) -> f64 {
    (scene.supports.iter())
        .filter_map(|s| match &s.motion {
            Motion::Record(g) => Some(g.end_time()),
            Motion::Harmonic { .. } => None,
        })
        .fold(0.0, f64::max)
}
