//! The runs a model study measures (`adequacy`, `sensitivity`): the model's own `[[run]]`s, or
//! a record suite's slice (pairs × levels, `suite::Suite`); of each run its quantities
//! (`suite::row::METRICS`, `suite::metrics::metrics`) and its cost (CPU time of the run's
//! thread, accepted steps, located events).

use crate::model::records::Motions;
use crate::model::{self, ModelError};
use crate::scene::Scene;
use crate::suite::intensity::MeasureSpec;
use crate::suite::metrics::{bent_heights, run_measured};
use crate::suite::records::SuitePair;
use crate::suite::row::{METRICS, Status};
use crate::suite::{Suite, SuiteError, SuiteSpec};
use std::path::{Path, PathBuf};

/// Which runs a study measures.
#[derive(Clone, Debug)]
pub enum Cases {
    /// Every `[[run]]` of the model (`excitation.run = 1..=n`), or the model as it is when it
    /// has no `[[run]]` table or no recorded excitation.
    ModelRuns,
    /// Every pair of a record suite scaled to each level (`deckspin suite`).
    Suite {
        pairs: Vec<SuitePair>,
        measure: MeasureSpec,
        levels: Vec<f64>,
        tail: f64,
    },
}

/// One run measured: its quantities in the order of [`METRICS`] and its cost.
#[derive(Clone, Debug, PartialEq)]
pub struct Measured {
    pub status: Status,
    pub metrics: [Option<f64>; 11],
    /// CPU seconds of the run's thread (its integration, not the model's compilation).
    pub cpu: f64,
    pub steps: usize,
    /// Events located (impacts, stick, slip, release, branch changes).
    pub events: usize,
}

impl Measured {
    /// A run that did not start: `reason`.
    pub fn refused(reason: String) -> Self {
        Self {
            status: Status::Refused(reason),
            metrics: [None; 11],
            cpu: 0.0,
            steps: 0,
            events: 0,
        }
    }

    /// The quantity `name` (one of [`METRICS`]).
    pub fn get(&self, name: &str) -> Option<f64> {
        let i = METRICS.iter().position(|m| *m == name)?;
        self.metrics[i]
    }
}

/// A model text compiled for a study: its runs as scenes.
pub(crate) struct CaseSet {
    path: PathBuf,
    text: String,
    fix: Vec<String>,
    heights: Vec<(String, f64)>,
    motions: Motions,
    runs: Runs,
}

enum Runs {
    /// `excitation.run` of each case (none: the model as it is).
    Model(Vec<Option<usize>>),
    Suite(Box<Suite>),
}

/// Why a model's cases could not be compiled.
#[derive(Debug, thiserror::Error)]
pub enum CasesError {
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error(transparent)]
    Suite(#[from] SuiteError),
}

/// `excitation.run` of each of the model's runs: `1..=n` for a recorded excitation with `n`
/// `[[run]]` tables, else one case, the model as it is.
fn model_runs(text: &str) -> Vec<Option<usize>> {
    let doc: toml::Table = toml::from_str(text).unwrap_or_default();
    let recorded = (doc.get("excitation").and_then(|e| e.get("kind")))
        .and_then(|k| k.as_str())
        .is_some_and(|k| k == "record");
    let n = (doc.get("run").and_then(|r| r.as_array())).map_or(0, Vec::len);
    if recorded && n > 0 {
        (1..=n).map(Some).collect()
    } else {
        vec![None]
    }
}

impl CaseSet {
    /// The cases of model `text` (named `path` in errors, its records relative to it) with the
    /// fixed overrides `fix`; the model is compiled once here, so a bad one fails before any run.
    pub fn new(text: &str, path: &Path, fix: &[String], cases: &Cases) -> Result<Self, CasesError> {
        let motions = Motions::default();
        let runs = match cases {
            Cases::ModelRuns => {
                model::load_str_with(text, path, fix, &motions)?;
                Runs::Model(model_runs(text))
            }
            Cases::Suite {
                pairs,
                measure,
                levels,
                tail,
            } => {
                let spec = SuiteSpec {
                    measure: *measure,
                    levels: levels.clone(),
                    axes: Vec::new(),
                    tail: *tail,
                };
                let suite = Suite::from_text(text, path, fix, pairs.clone(), spec)?;
                Runs::Suite(Box::new(suite))
            }
        };
        Ok(Self {
            path: path.to_path_buf(),
            text: text.to_string(),
            fix: fix.to_vec(),
            heights: bent_heights(text),
            motions,
            runs,
        })
    }

    /// The number of runs.
    pub fn len(&self) -> usize {
        match &self.runs {
            Runs::Model(r) => r.len(),
            Runs::Suite(s) => s.runs(),
        }
    }

    /// A name for run `i`: the `[[run]]`'s name, or the suite's pair and level.
    pub fn label(&self, i: usize) -> String {
        match &self.runs {
            Runs::Model(r) => match r.get(i).copied().flatten() {
                Some(k) => run_name(&self.text, k),
                None => "model".into(),
            },
            Runs::Suite(s) => {
                let (p, l) = (i / s.levels.len(), i % s.levels.len());
                format!("{} at {}", s.pairs[p].name, s.levels[l])
            }
        }
    }

    /// The scene of run `i`, with the extra overrides `set` (model runs only: a suite's
    /// overrides are its `fix`).
    pub fn scene(&self, i: usize, set: &[String]) -> Result<Scene, String> {
        match &self.runs {
            Runs::Model(r) => {
                let mut ov = self.fix.clone();
                if let Some(k) = r.get(i).copied().flatten() {
                    ov.push(format!("excitation.run={k}"));
                }
                ov.extend(set.iter().cloned());
                let m = self.motions.sharing_records();
                model::load_str_with(&self.text, &self.path, &ov, &m).map_err(|e| e.to_string())
            }
            Runs::Suite(s) => s.scene(i).map(|(scene, _)| scene),
        }
    }

    /// Run `i` measured (with the extra overrides `set`, as [`CaseSet::scene`]).
    pub fn measure(&self, i: usize, set: &[String]) -> Measured {
        match self.scene(i, set) {
            Ok(scene) => measure_scene(&scene, &self.heights),
            Err(reason) => Measured::refused(reason),
        }
    }
}

/// The `name` of the `k`-th `[[run]]` (1-based), else `run k`.
fn run_name(text: &str, k: usize) -> String {
    let doc: toml::Table = toml::from_str(text).unwrap_or_default();
    (doc.get("run").and_then(|r| r.as_array()))
        .and_then(|a| a.get(k - 1))
        .and_then(|r| r.get("name"))
        .and_then(|n| n.as_str())
        .map_or_else(|| format!("run {k}"), str::to_string)
}

/// One scene run and measured: its quantities (the column drift by the bents' `heights`) and
/// its cost.
pub fn measure_scene(scene: &Scene, heights: &[(String, f64)]) -> Measured {
    let ((run, metrics), cpu) = crate::clock::thread_cpu(|| run_measured(scene.clone(), heights));
    let stats = &run.output.summary.stats;
    Measured {
        status: Status::of(&run.stop),
        metrics,
        cpu,
        steps: stats.steps_accepted,
        events: stats.events_located,
    }
}
