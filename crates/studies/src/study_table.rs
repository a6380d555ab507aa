//! The paper's studies as tables that a front end fills while they run, draws, writes and
//! reads back ([`crate::study_csv`]): one row per run of the PGA study (Fig. 7: peak |θ|
//! against PGA, with and without contact) and of the μ study (Fig. 8: peak |θ| for each μ and
//! without contact, whose ratio is the increase), and the screening by the impact law
//! ([`ScreenStudy`]), the model ladder ([`Adequacy`]) and the swings of the uncertain inputs
//! ([`Sensitivity`]). [`run_study`] runs one, watched by a [`Watch`].

use crate::design::adequacy::{Adequacy, Options, adequacy};
use crate::design::cases::Cases;
use crate::design::screen::{ScreenStudy, screen_study};
use crate::design::sensitivity::{self, Choice};
use crate::design::swings::Sensitivity;
use crate::precision_study::{PrecisionTable, run_precision};
use crate::studies::{Row, RunFailure, Study, Watch, increase_vs_mu, rotation_vs_pga, run_pgas};
use crate::suite::intensity::MeasureSpec;
use crate::suite::records::{SuitePair, suite_pairs};
use crate::suite::row::{Status as SuiteStatus, SuiteRow};
use crate::suite::stats::median;
use crate::suite::{CANCELLED, Suite, SuiteSpec};
use std::path::{Path, PathBuf};

/// A study of the workbench's list.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StudyKind {
    /// Fig. 7: peak |θ| against PGA with contact and without.
    Pga,
    /// Fig. 8: the increase of peak |θ| over no contact against μ, one curve per run.
    Mu,
    /// A record suite, a chosen subset ([`SuiteSubset`]): peak |θ| against PGA for each pair,
    /// and the median per level (`crate::suite`).
    Suite,
    /// The screening by the impact law: the L/B × skew maps, the model's ends and corners.
    Screen,
    /// Work–precision and stability: every method over its quick knobs against the
    /// event-driven reference ([`crate::precision_study`]).
    Precision,
    /// Model adequacy: the model ladder on the model's `[[run]]`s, each variant's error per
    /// quantity against the full model and its cost ([`crate::design::adequacy`]).
    Adequacy,
    /// Sensitivity: every default uncertain input at its low and high value on the model's
    /// `[[run]]`s, the swings and their tornado ([`crate::design::sensitivity`]).
    Sensitivity,
}

impl StudyKind {
    /// Every study, in the order the workbench lists them.
    pub const ALL: [StudyKind; 7] = [
        StudyKind::Pga,
        StudyKind::Mu,
        StudyKind::Screen,
        StudyKind::Suite,
        StudyKind::Precision,
        StudyKind::Adequacy,
        StudyKind::Sensitivity,
    ];

    /// The name of its CSV files (`pga-3.csv`) and the value of their `study` column.
    pub fn key(self) -> &'static str {
        match self {
            StudyKind::Pga => "pga",
            StudyKind::Mu => "mu",
            StudyKind::Suite => "suite",
            StudyKind::Screen => "screen",
            StudyKind::Precision => "precision",
            StudyKind::Adequacy => "adequacy",
            StudyKind::Sensitivity => "sensitivity",
        }
    }
}

/// The tolerance of the workbench's adequacy study (as `deckspin adequacy`'s default): a
/// variant within 5 % of the full model in a quantity is adequate for it.
pub(crate) const ADEQUACY_TOLERANCE: f64 = 0.05;

/// How one run of a study ended.
#[derive(Clone, Debug, PartialEq)]
pub enum PointStatus {
    Ok,
    /// Not run (yet, or the study was cancelled before it).
    NotRun,
    /// The run failed: the reason.
    Failed(String),
}

/// One run of the PGA or μ study.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyRun {
    /// The `[[run]]` number, from 1.
    pub run: usize,
    /// Target PGAs of the run, g (NaN where the model does not give them).
    pub pga_x: f64,
    pub pga_y: f64,
    pub contact: bool,
    /// `contacts.mu` of the run (the μ study); None: the model's own μ.
    pub mu: Option<f64>,
    /// Peak |θ| of the deck, rad (NaN unless the run finished).
    pub peak_rotation: f64,
    /// θ at the end of the run, rad.
    pub residual_rotation: f64,
    pub impacts: usize,
    pub status: PointStatus,
}

impl StudyRun {
    fn planned(run: usize, (pga_x, pga_y): (f64, f64), contact: bool, mu: Option<f64>) -> Self {
        Self {
            run,
            pga_x,
            pga_y,
            contact,
            mu,
            peak_rotation: f64::NAN,
            residual_rotation: f64::NAN,
            impacts: 0,
            status: PointStatus::NotRun,
        }
    }

    pub fn is_ok(&self) -> bool {
        self.status == PointStatus::Ok
    }
}

/// One curve of Fig. 8: a run's increase of peak |θ| over its no-contact peak, % against μ.
#[derive(Clone, Debug, PartialEq)]
pub struct Fig8Curve {
    pub run: usize,
    pub pga_x: f64,
    /// (μ, increase %), for the μ whose run and whose run without contact both finished.
    pub points: Vec<(f64, f64)>,
}

/// The runs of the PGA or μ study, in the order of their progress index ([`RunTable::record`]).
#[derive(Clone, Debug, PartialEq)]
pub struct RunTable {
    /// [`StudyKind::Pga`] or [`StudyKind::Mu`].
    pub kind: StudyKind,
    pub runs: Vec<StudyRun>,
}

/// The subset of a record suite the workbench runs: the first `pairs` pairs of the folder
/// `records` (paired as `deckspin suite` pairs them) at each PGA of `levels` (g).
#[derive(Clone, Debug, PartialEq)]
pub struct SuiteSubset {
    pub records: PathBuf,
    pub pairs: usize,
    pub levels: Vec<f64>,
}

impl SuiteSubset {
    /// The far-field set of the project, found from the model's folder (`../excitations/
    /// far-field`, then `excitations/far-field` beside the model), 4 pairs, 0.2 … 1.2 g by 0.2.
    pub fn near(model: &Path) -> Self {
        let dir = model.parent().unwrap_or(Path::new("."));
        let up = dir.join("../excitations/far-field");
        let records = if up.is_dir() {
            up
        } else {
            dir.join("excitations/far-field")
        };
        Self {
            records,
            pairs: 4,
            levels: (1..=6).map(|i| 0.2 * i as f64).collect(),
        }
    }

    /// Its pairs: the first [`SuiteSubset::pairs`] of the folder.
    pub fn read_pairs(&self) -> Result<Vec<SuitePair>, String> {
        let (pairs, _) = suite_pairs(&self.records).map_err(|e| e.to_string())?;
        if pairs.is_empty() {
            return Err(format!("{}: no record pairs", self.records.display()));
        }
        Ok(pairs.into_iter().take(self.pairs.max(1)).collect())
    }
}

/// A suite's run as a sweep's row (what the studies' tables and the workbench take).
pub(crate) fn suite_row(r: &SuiteRow) -> Row {
    let m = |k: usize| r.metrics[k].unwrap_or(f64::NAN);
    let error = match &r.status {
        SuiteStatus::Finished => None,
        SuiteStatus::Refused(why) if why == CANCELLED => Some(RunFailure::Cancelled),
        s => Some(RunFailure::Suite(s.text())),
    };
    Row {
        settings: vec![("records".into(), r.pair.clone())],
        peak_rotation: m(0),
        residual_rotation: m(1),
        peak_x: m(2),
        peak_y: m(3),
        impacts: r.metrics[7].map_or(0, |x| x as usize),
        stick_time: f64::NAN,
        energy_closure_rel: f64::NAN,
        wall_time: f64::NAN,
        error: error.map(std::sync::Arc::new),
    }
}

impl RunTable {
    /// The suite subset, nothing run: for each pair (run = its number, from 1), each level as
    /// `pga_x` ([`Suite::run`]'s order).
    pub fn suite_plan(pairs: usize, levels: &[f64]) -> Self {
        let runs = (1..=pairs)
            .flat_map(|p| {
                (levels.iter()).map(move |&l| StudyRun::planned(p, (l, f64::NAN), true, None))
            })
            .collect();
        Self {
            kind: StudyKind::Suite,
            runs,
        }
    }

    /// The suite: (level, peak |θ|) of every finished run, and the median per level of the
    /// levels with a finished run.
    pub fn suite_points(&self) -> [Vec<(f64, f64)>; 2] {
        let runs: Vec<(f64, f64)> = (self.runs.iter())
            .filter(|r| r.is_ok())
            .map(|r| (r.pga_x, r.peak_rotation))
            .collect();
        let mut levels: Vec<f64> = runs.iter().map(|p| p.0).collect();
        levels.sort_by(f64::total_cmp);
        levels.dedup();
        let medians = (levels.iter())
            .filter_map(|&l| {
                let v: Vec<f64> = runs.iter().filter(|p| p.0 == l).map(|p| p.1).collect();
                median(&v).map(|m| (l, m))
            })
            .collect();
        [runs, medians]
    }

    /// The PGA study of a bridge model's text, nothing run: for each `[[run]]`, without
    /// contact then with contact ([`rotation_vs_pga`]'s order).
    pub fn pga_plan(text: &str) -> Self {
        let runs = (run_pgas(text).into_iter().enumerate())
            .flat_map(|(i, p)| [false, true].map(|c| StudyRun::planned(i + 1, p, c, None)))
            .collect();
        Self {
            kind: StudyKind::Pga,
            runs,
        }
    }

    /// The μ study, nothing run: each `[[run]]` without contact, then each run with each μ
    /// ([`increase_vs_mu`]'s order).
    pub fn mu_plan(text: &str, mus: &[f64]) -> Self {
        let pgas = run_pgas(text);
        let baseline =
            (pgas.iter().enumerate()).map(|(i, &p)| StudyRun::planned(i + 1, p, false, None));
        let with = (pgas.iter().enumerate()).flat_map(|(i, &p)| {
            mus.iter()
                .map(move |&m| StudyRun::planned(i + 1, p, true, Some(m)))
        });
        Self {
            kind: StudyKind::Mu,
            runs: baseline.chain(with).collect(),
        }
    }

    /// Row `index` of the study's sweeps finished (or failed, or was skipped by a cancel);
    /// false when there is no such row.
    pub fn record(&mut self, index: usize, row: &Row) -> bool {
        let Some(r) = self.runs.get_mut(index) else {
            return false;
        };
        r.status = match row.error.as_deref() {
            None => PointStatus::Ok,
            Some(RunFailure::Cancelled) => PointStatus::NotRun,
            Some(e) => PointStatus::Failed(e.to_string()),
        };
        r.peak_rotation = row.peak_rotation;
        r.residual_rotation = row.residual_rotation;
        r.impacts = row.impacts;
        true
    }

    /// Runs finished or failed (not [`PointStatus::NotRun`]).
    pub fn done(&self) -> usize {
        (self.runs.iter())
            .filter(|r| r.status != PointStatus::NotRun)
            .count()
    }

    pub fn failed(&self) -> usize {
        (self.runs.iter())
            .filter(|r| matches!(r.status, PointStatus::Failed(_)))
            .count()
    }

    /// Fig. 7: (PGA x, peak |θ|) of the finished runs without contact and with contact, in run
    /// order (runs without a PGA left out).
    pub fn fig7(&self) -> [Vec<(f64, f64)>; 2] {
        let points = |contact: bool| {
            (self.runs.iter())
                .filter(|r| r.contact == contact && r.is_ok() && r.pga_x.is_finite())
                .map(|r| (r.pga_x, r.peak_rotation))
                .collect()
        };
        [points(false), points(true)]
    }

    /// Fig. 8: for each run, 100 (peak(μ) / peak without contact − 1) against μ, as
    /// [`crate::studies::MuStudy::increase`] computes it.
    pub fn fig8(&self) -> Vec<Fig8Curve> {
        let mut curves: Vec<Fig8Curve> = Vec::new();
        for base in self.runs.iter().filter(|r| !r.contact) {
            let points = (self.runs.iter())
                .filter(|r| r.run == base.run && r.contact && r.is_ok() && base.is_ok())
                .filter_map(|r| {
                    let mu = r.mu?;
                    Some((mu, 100.0 * (r.peak_rotation / base.peak_rotation - 1.0)))
                })
                .collect();
            curves.push(Fig8Curve {
                run: base.run,
                pga_x: base.pga_x,
                points,
            });
        }
        curves
    }

    /// The μ values of the runs with contact, in order of first appearance.
    pub fn mus(&self) -> Vec<f64> {
        let mut out: Vec<f64> = Vec::new();
        for m in self.runs.iter().filter_map(|r| r.mu) {
            if !out.iter().any(|x| x.to_bits() == m.to_bits()) {
                out.push(m);
            }
        }
        out
    }
}

/// A study's results, complete or in part.
#[derive(Clone, Debug, PartialEq)]
pub enum StudyTable {
    Runs(RunTable),
    Screen(Box<ScreenStudy>),
    Precision(PrecisionTable),
    /// The model ladder measured (it comes whole: the errors need every run).
    Adequacy(Box<Adequacy>),
    /// The swings (runs cancelled before they started are refused as
    /// [`crate::suite::CANCELLED`]).
    Sensitivity(Box<Sensitivity>),
}

impl StudyTable {
    pub fn kind(&self) -> StudyKind {
        match self {
            StudyTable::Runs(t) => t.kind,
            StudyTable::Screen(_) => StudyKind::Screen,
            StudyTable::Precision(_) => StudyKind::Precision,
            StudyTable::Adequacy(_) => StudyKind::Adequacy,
            StudyTable::Sensitivity(_) => StudyKind::Sensitivity,
        }
    }

    /// (runs done, runs in all): the screening counts as one; the ladder's runs are all done
    /// (its table comes whole); the swings' runs cancelled before they started are not.
    pub fn progress(&self) -> (usize, usize) {
        match self {
            StudyTable::Runs(t) => (t.done(), t.runs.len()),
            StudyTable::Screen(_) => (1, 1),
            StudyTable::Precision(t) => t.progress(),
            StudyTable::Adequacy(a) => {
                let runs = (std::iter::once(&a.full).chain(&a.variants))
                    .map(|o| o.runs.len())
                    .sum();
                (runs, runs)
            }
            StudyTable::Sensitivity(s) => {
                let cancelled = SuiteStatus::Refused(CANCELLED.into());
                let done = s.rows.iter().filter(|r| r.status != cancelled).count();
                (done, s.rows.len())
            }
        }
    }
}

/// Runs study `kind` of `study` (μ values `mus` for the μ study), telling `progress` of each
/// row by its index in the table ([`RunTable::pga_plan`], [`RunTable::mu_plan`]); the
/// screening compiles the model once and runs nothing; the ladder and the swings count their
/// runs to `progress` (`plan`, `done`). The table is complete, rows skipped by a cancel marked
/// [`PointStatus::NotRun`] (a ladder cancelled has no table: an error).
pub fn run_study(
    kind: StudyKind,
    study: &Study,
    mus: &[f64],
    suite: &SuiteSubset,
    progress: &dyn Watch,
) -> Result<StudyTable, String> {
    Ok(match kind {
        StudyKind::Suite => StudyTable::Runs(run_suite(study, suite, progress)?),
        StudyKind::Pga => {
            let mut t = RunTable::pga_plan(&study.text);
            let rows = rotation_vs_pga(study, progress);
            for (k, (_, _, _, without, with)) in rows.iter().enumerate() {
                t.record(2 * k, without);
                t.record(2 * k + 1, with);
            }
            StudyTable::Runs(t)
        }
        StudyKind::Mu => {
            let mut t = RunTable::mu_plan(&study.text, mus);
            let m = increase_vs_mu(study, mus, progress);
            let rows = m.baseline.iter().chain(m.rows.iter().flatten());
            for (i, row) in rows.enumerate() {
                t.record(i, row);
            }
            StudyTable::Runs(t)
        }
        StudyKind::Screen => {
            let scene = study.scene(&[]).map_err(|e| e.to_string())?;
            StudyTable::Screen(Box::new(screen_study(&scene)))
        }
        StudyKind::Precision => StudyTable::Precision(run_precision(study, progress, &|_, _| {})?),
        StudyKind::Adequacy => {
            let opts = Options {
                quantities: Vec::new(),
                tolerance: ADEQUACY_TOLERANCE,
                only: None,
                combine: true,
            };
            let cases = Cases::ModelRuns;
            let a = adequacy(
                &study.text,
                &study.path,
                &study.base,
                &cases,
                &opts,
                progress,
            );
            StudyTable::Adequacy(Box::new(a.map_err(|e| e.to_string())?))
        }
        StudyKind::Sensitivity => {
            let (cases, choice) = (Cases::ModelRuns, Choice::default());
            let s = sensitivity::Study::from_text(
                &study.text,
                &study.path,
                &study.base,
                &cases,
                &choice,
            )
            .map_err(|e| e.to_string())?;
            StudyTable::Sensitivity(Box::new(s.run(progress)))
        }
    })
}

/// The suite subset on the study's model (its text and overrides), each row to `progress`.
fn run_suite(
    study: &Study,
    subset: &SuiteSubset,
    progress: &dyn Watch,
) -> Result<RunTable, String> {
    let pairs = subset.read_pairs()?;
    let n = pairs.len();
    let spec = SuiteSpec {
        measure: MeasureSpec::Pga,
        levels: subset.levels.clone(),
        axes: Vec::new(),
        tail: 2.0,
    };
    let suite = Suite::from_text(&study.text, &study.path, &study.base, pairs, spec)
        .map_err(|e| e.to_string())?;
    let mut t = RunTable::suite_plan(n, &subset.levels);
    let rows = suite.run_each(0..suite.runs(), progress, &|i, r| {
        progress.row(i, &suite_row(r))
    });
    for (i, r) in rows.iter().enumerate() {
        t.record(i, &suite_row(r));
    }
    Ok(t)
}
