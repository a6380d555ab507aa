//! Model adequacy: the model ladder ([`ladder`]) run on a model's runs, each variant's error
//! per quantity against the full model and its cost, and the cheapest variant within a
//! tolerance.
//!
//! The error of a quantity q of a variant is, over the runs c,
//! `max_c |q_v,c − q_c| / max(|q_c|, 5 % · max_c |q_c|)` (a quantity the simplification
//! removes, e.g. key failures without keys, counts as 0; a failed run as an infinite error).

use super::cases::{CaseSet, Cases, CasesError, Measured};
use super::ladder::{self, Edit, EditError, Simplification, Timing};
use crate::progress::Progress;
use crate::suite::row::{METRICS, Status};
use rayon::prelude::*;
use std::path::Path;

/// The relative floor of an error's denominator: 5 % of the largest |value| over the runs.
pub(crate) const FLOOR: f64 = 0.05;

/// A model of the ladder: the full model (no simplification) or a set of them.
#[derive(Clone, Debug, PartialEq)]
pub struct Variant {
    /// `full`, a simplification's name, or names joined by `+`.
    pub name: String,
    pub simplifications: Vec<Simplification>,
    pub changes: Vec<(Simplification, Edit)>,
}

impl Variant {
    fn full() -> Self {
        Self {
            name: "full".into(),
            simplifications: Vec::new(),
            changes: Vec::new(),
        }
    }

    /// The variant of the simplifications `set` (those another one supersedes dropped), or none
    /// when one of them does not apply.
    pub fn of(
        doc: &toml_edit::DocumentMut,
        set: &[Simplification],
        timing: &Timing,
    ) -> Option<Self> {
        let mut set: Vec<Simplification> = set.to_vec();
        set.sort();
        set.dedup();
        let moot: Vec<Simplification> = (set.iter())
            .flat_map(|s| s.supersedes().iter().copied())
            .collect();
        set.retain(|s| !moot.contains(s));
        let mut changes = Vec::new();
        for &s in &set {
            for e in ladder::edits(doc, s, timing)? {
                changes.push((s, e));
            }
        }
        let name = (set.iter().map(|s| s.name())).collect::<Vec<_>>().join("+");
        Some(Self {
            name,
            simplifications: set,
            changes,
        })
    }

    /// The model text of this variant; `mark`: each change commented with why.
    pub fn text(&self, model: &str, mark: bool) -> Result<String, EditError> {
        ladder::apply(model, &self.changes, mark)
    }
}

/// Every single simplification that applies to the model, among `only` when given.
pub fn singles(
    doc: &toml_edit::DocumentMut,
    timing: &Timing,
    only: Option<&[Simplification]>,
) -> Vec<Variant> {
    (Simplification::ALL.into_iter())
        .filter(|s| only.is_none_or(|o| o.contains(s)))
        .filter_map(|s| Variant::of(doc, &[s], timing))
        .collect()
}

/// The combinations worth running whatever the errors: the contacts kept with the rest
/// simplified, and the plain elastic bridge (each only when all of it applies, else what does).
pub fn combinations(
    doc: &toml_edit::DocumentMut,
    timing: &Timing,
    singles: &[Variant],
) -> Vec<Variant> {
    use Simplification::*;
    let present = |s: Simplification| singles.iter().any(|v| v.simplifications == [s]);
    let mut out: Vec<Variant> = Vec::new();
    for set in [
        &[RigidAbutments, BilinearColumns][..],
        &[RigidAbutments, BilinearColumns, StrongMotion],
        &[RigidAbutments, LinearColumns, NoContacts, StrongMotion],
    ] {
        let set: Vec<Simplification> = set.iter().copied().filter(|s| present(*s)).collect();
        if set.len() < 2 {
            continue;
        }
        if let Some(v) = Variant::of(doc, &set, timing)
            && !out.iter().chain(singles).any(|o| o.name == v.name)
        {
            out.push(v);
        }
    }
    out
}

/// A variant run on every case: the runs in case order.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    pub variant: Variant,
    /// Why the variant's model was refused (then `runs` is empty).
    pub refused: Option<String>,
    pub runs: Vec<Measured>,
}

/// The cost of a variant's runs, summed over them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Cost {
    pub cpu: f64,
    pub steps: usize,
    pub events: usize,
}

impl Cost {
    /// Accepted steps plus located events: the work of an event-driven run, the same on any
    /// machine.
    pub fn work(&self) -> usize {
        self.steps + self.events
    }
}

impl Outcome {
    pub fn cost(&self) -> Cost {
        self.runs.iter().fold(Cost::default(), |c, r| Cost {
            cpu: c.cpu + r.cpu,
            steps: c.steps + r.steps,
            events: c.events + r.events,
        })
    }

    fn failed(&self) -> bool {
        self.refused.is_some() || self.runs.iter().any(|r| r.status != Status::Finished)
    }
}

/// The error of `variant` against `full` in quantity `q` (see the module's doc); none when the
/// quantity does not apply to the full model.
pub fn error(full: &Outcome, variant: &Outcome, q: &str) -> Option<f64> {
    let f: Vec<Option<f64>> = full.runs.iter().map(|r| r.get(q)).collect();
    let scale = (f.iter().flatten()).fold(None, |m: Option<f64>, x| {
        Some(m.map_or(x.abs(), |m| m.max(x.abs())))
    })?;
    if variant.failed() {
        return Some(f64::INFINITY);
    }
    let mut worst = 0.0_f64;
    for (fc, v) in f.iter().zip(&variant.runs) {
        let Some(fc) = fc else { continue };
        let vc = v.get(q).unwrap_or(0.0);
        let d = (vc - fc).abs();
        let den = fc.abs().max(FLOOR * scale);
        let e = if den > 0.0 {
            d / den
        } else if d == 0.0 {
            0.0
        } else {
            1.0
        };
        worst = worst.max(e);
    }
    Some(worst)
}

/// What to measure.
#[derive(Clone, Debug)]
pub struct Options {
    /// Quantities among [`METRICS`] (empty: every one that applies to the full model).
    pub quantities: Vec<String>,
    /// The largest error a variant may have to be called adequate, relative (0.05: 5 %).
    pub tolerance: f64,
    /// Only these simplifications (none: all that apply).
    pub only: Option<Vec<Simplification>>,
    /// After the singles, search the combination of every simplification within the
    /// tolerance (per quantity and for all of them together), dropping the worst until it
    /// holds.
    pub combine: bool,
}

/// Why a study could not start.
#[derive(Debug, thiserror::Error)]
pub enum AdequacyError {
    #[error(transparent)]
    Cases(#[from] CasesError),
    #[error("{0}")]
    Edit(#[from] EditError),
    #[error("--quantities: '{0}' is not one of {list}", list = METRICS.join(", "))]
    Quantity(String),
    #[error("--tolerance {0}: a relative error above 0 (0.05 for 5 %)")]
    Tolerance(f64),
    #[error(
        "no simplification of the ladder applies to this model (it is not a bridge file, or its abutments, columns, contacts, keys, bearings and records are as simple as the ladder goes; with --only, among those named)"
    )]
    Nothing,
    #[error("the full model failed on {case}: {reason}")]
    FullFailed { case: String, reason: String },
    #[error("cancelled")]
    Cancelled,
}

/// The ladder of a model measured.
#[derive(Clone, Debug, PartialEq)]
pub struct Adequacy {
    /// The runs' names.
    pub cases: Vec<String>,
    pub quantities: Vec<String>,
    pub tolerance: f64,
    pub full: Outcome,
    pub variants: Vec<Outcome>,
}

impl Adequacy {
    /// The error of variant `v` in quantity `q`.
    pub fn error(&self, v: usize, q: &str) -> Option<f64> {
        error(&self.full, &self.variants[v], q)
    }

    /// The largest error of variant `v` over the quantities measured.
    pub fn worst(&self, v: usize) -> f64 {
        (self.quantities.iter())
            .filter_map(|q| self.error(v, q))
            .fold(0.0, f64::max)
    }

    /// The cheapest variant within the tolerance in `q`, or in every quantity when `q` is
    /// none; none when no variant is (the full model is then the answer). Cheapest by its
    /// [`Cost::work`], which the machine's load does not change (CPU times vary by tens of
    /// per cent between two runs of one model on a shared machine), then by CPU time.
    pub fn cheapest(&self, q: Option<&str>) -> Option<usize> {
        let ok = |v: usize| match q {
            Some(q) => self.error(v, q).is_some_and(|e| e <= self.tolerance),
            None => self.worst(v) <= self.tolerance,
        };
        let full = self.full.cost().work();
        (0..self.variants.len())
            .filter(|&v| ok(v) && self.variants[v].cost().work() < full)
            .min_by(|&a, &b| {
                let (ca, cb) = (self.variants[a].cost(), self.variants[b].cost());
                (ca.work().cmp(&cb.work())).then(ca.cpu.total_cmp(&cb.cpu))
            })
    }
}

/// A model's ladder (`text` named `path`, `fix` applied to every run) measured on `cases`.
pub fn adequacy(
    text: &str,
    path: &Path,
    fix: &[String],
    cases: &Cases,
    opts: &Options,
    progress: &dyn Progress,
) -> Result<Adequacy, AdequacyError> {
    if !(opts.tolerance.is_finite() && opts.tolerance > 0.0) {
        return Err(AdequacyError::Tolerance(opts.tolerance));
    }
    for q in &opts.quantities {
        if !METRICS.contains(&q.as_str()) {
            return Err(AdequacyError::Quantity(q.clone()));
        }
    }
    let full_set = CaseSet::new(text, path, fix, cases)?;
    let labels: Vec<String> = (0..full_set.len()).map(|i| full_set.label(i)).collect();
    let timing = timing(&full_set, cases);
    let doc: toml_edit::DocumentMut = text.parse().map_err(|e| EditError::Parse(format!("{e}")))?;
    let singles = singles(&doc, &timing, opts.only.as_deref());
    if singles.is_empty() {
        return Err(AdequacyError::Nothing);
    }
    let mut planned = vec![Variant::full()];
    planned.extend(singles.iter().cloned());
    planned.extend(combinations(&doc, &timing, &singles));
    let mut outcomes = run_all(text, path, fix, cases, &planned, progress)?;
    let full = outcomes.remove(0);
    if let Some((i, r)) = (full.runs.iter().enumerate()).find(|(_, r)| r.status != Status::Finished)
    {
        return Err(AdequacyError::FullFailed {
            case: labels[i].clone(),
            reason: r.status.text(),
        });
    }
    let quantities = if opts.quantities.is_empty() {
        (METRICS.iter())
            .filter(|q| full.runs.iter().any(|r| r.get(q).is_some()))
            .map(|q| q.to_string())
            .collect()
    } else {
        opts.quantities.clone()
    };
    let mut study = Adequacy {
        cases: labels,
        quantities,
        tolerance: opts.tolerance,
        full,
        variants: outcomes,
    };
    if opts.combine {
        combine(&mut study, text, path, fix, cases, &doc, &timing, progress)?;
    }
    Ok(study)
}

/// Runs every variant on every case, in parallel; the outcomes in `planned`'s order.
fn run_all(
    text: &str,
    path: &Path,
    fix: &[String],
    cases: &Cases,
    planned: &[Variant],
    progress: &dyn Progress,
) -> Result<Vec<Outcome>, AdequacyError> {
    let sets: Vec<Result<CaseSet, String>> = (planned.par_iter())
        .map(|v| {
            let t = v.text(text, false).map_err(|e| e.to_string())?;
            CaseSet::new(&t, path, fix, cases).map_err(|e| e.to_string())
        })
        .collect();
    let jobs: Vec<(usize, usize)> = (sets.iter().enumerate())
        .filter_map(|(v, s)| s.as_ref().ok().map(|s| (v, s.len())))
        .flat_map(|(v, n)| (0..n).map(move |i| (v, i)))
        .collect();
    progress.plan(jobs.len());
    let measured: Vec<Option<Measured>> = (jobs.par_iter())
        .map(|&(v, i)| {
            if !progress.go_on() {
                return None;
            }
            let set = sets[v].as_ref().expect("listed");
            let m = set.measure(i, &[]);
            progress.done(1);
            Some(m)
        })
        .collect();
    if measured.iter().any(Option::is_none) {
        return Err(AdequacyError::Cancelled);
    }
    let mut outcomes: Vec<Outcome> = (planned.iter().zip(&sets))
        .map(|(v, s)| Outcome {
            variant: v.clone(),
            refused: s.as_ref().err().cloned(),
            runs: Vec::new(),
        })
        .collect();
    for (&(v, _), m) in jobs.iter().zip(measured) {
        outcomes[v].runs.push(m.expect("checked"));
    }
    Ok(outcomes)
}

/// For each quantity and for all together: the union of the singles within the tolerance,
/// run; while it is not within the tolerance, the single with the largest error dropped.
#[allow(clippy::too_many_arguments)]
fn combine(
    study: &mut Adequacy,
    text: &str,
    path: &Path,
    fix: &[String],
    cases: &Cases,
    doc: &toml_edit::DocumentMut,
    timing: &Timing,
    progress: &dyn Progress,
) -> Result<(), AdequacyError> {
    let targets: Vec<Option<String>> = std::iter::once(None)
        .chain(study.quantities.iter().cloned().map(Some))
        .collect();
    for q in targets {
        let err = |s: &Adequacy, v: usize| match &q {
            Some(q) => s.error(v, q).unwrap_or(0.0),
            None => s.worst(v),
        };
        let mut admitted: Vec<(Simplification, f64)> = (0..study.variants.len())
            .filter(|&v| study.variants[v].variant.simplifications.len() == 1)
            .map(|v| (study.variants[v].variant.simplifications[0], err(study, v)))
            .filter(|(_, e)| *e <= study.tolerance)
            .collect();
        while admitted.len() >= 2 {
            let set: Vec<Simplification> = admitted.iter().map(|(s, _)| *s).collect();
            let Some(v) = Variant::of(doc, &set, timing) else {
                break;
            };
            let at = match (study.variants.iter()).position(|o| o.variant.name == v.name) {
                Some(at) => at,
                None => {
                    let mut o = run_all(text, path, fix, cases, &[v], progress)?;
                    study.variants.push(o.remove(0));
                    study.variants.len() - 1
                }
            };
            if err(study, at) <= study.tolerance {
                break;
            }
            let worst = (0..admitted.len())
                .max_by(|&a, &b| admitted[a].1.total_cmp(&admitted[b].1))
                .expect("not empty");
            admitted.remove(worst);
        }
    }
    Ok(())
}

/// The strong-motion window of the model's records and its free-vibration tail, from its
/// first run's scene (the runs scale one record pair, so they share the window); none on a
/// record suite (each pair has its own, and a suite refuses a window).
fn timing(set: &CaseSet, cases: &Cases) -> Timing {
    let Ok(scene) = set.scene(0, &[]) else {
        return Timing::default();
    };
    let (end, t_end) = (crate::suite::records_end(&scene), scene.settings.t_end);
    // the part of the strong motion the run reaches: a run that ends inside its records is
    // cut there too
    let window = match cases {
        Cases::ModelRuns => scene.strong_motion_window(),
        Cases::Suite { .. } => None,
    };
    Timing {
        strong_motion: window
            .map(|(t5, t95)| (t5, t95.min(t_end)))
            .filter(|(t5, t95)| t95 > t5),
        tail: (t_end - end).max(0.0),
    }
}
