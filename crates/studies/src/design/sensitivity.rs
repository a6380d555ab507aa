//! Which uncertain inputs the answer is most sensitive to: every input at its low and its
//! high value (all else at the model's), on every case (`design::cases`: the model's `[[run]]`s
//! or a record suite's slice), beside the model itself; per input and quantity the swing
//! value(high) − value(low) of the medians over the cases (`design::swings`), drawn as a
//! tornado (`design::tornado`).
//!
//! The inputs are the model's `[[uncertain]]` tables (`model::uncertain`), or when it has
//! none the defaults of [`default_inputs`]; `Choice` picks some by name and adds others. Run
//! `i` of a study of C cases and n inputs is variant ⌊i/C⌋ (0 the model, 2j + 1 input j at
//! its low value, 2j + 2 at its high value) on case i mod C. Every variant is compiled before
//! any run, so a low or high value the model refuses stops the study at once.

use super::cases::{CaseSet, Cases, CasesError};
use super::swings::{InputInfo, RunRow, Sensitivity, Side, summarize};
use crate::model::uncertain::{UncertainSpec, check_key, side_overrides};
use crate::model::{ModelError, apply_overrides, locate};
use crate::progress::Progress;
use crate::suite::intensity::MeasureSpec;
use crate::suite::row::METRICS;
use crate::suite::{CANCELLED, reserved};
use rayon::prelude::*;
use std::path::Path;

/// The quantities of a study when none are asked for (those that apply to the model are
/// kept: a quantity no base run has, such as the seat margin of a model without seats, is
/// left out of the swings).
pub(crate) const DEFAULT_QUANTITIES: [&str; 7] = [
    "peak_rotation",
    "residual_rotation",
    "peak_x",
    "peak_y",
    "min_seat_margin",
    "impacts",
    "max_drift_ratio",
];

/// Most runs one study makes (as a sweep, `studies::MAX_SWEEP_RUNS`).
pub(crate) const MAX_RUNS: usize = crate::studies::MAX_SWEEP_RUNS;

/// What an input moves.
#[derive(Clone, Debug, PartialEq)]
pub enum Target {
    /// Override paths moved together.
    Keys(Vec<String>),
    /// A record suite's intensity levels (always by factors).
    Levels,
}

/// Where an input comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum Origin {
    /// The model's `[[uncertain]]` table `entry` (0-based).
    Model { entry: usize },
    /// A default ([`default_inputs`]) and why it is one.
    Default { why: &'static str },
    /// `--add` (`Choice::add`), as given.
    Added { argument: String },
}

/// An uncertain input.
#[derive(Clone, Debug, PartialEq)]
pub struct Input {
    pub name: String,
    pub target: Target,
    pub low: f64,
    pub high: f64,
    /// `low` and `high` are factors on the model's values.
    pub relative: bool,
    pub origin: Origin,
}

impl Input {
    /// The paths it moves, joined by `+` (`levels` for a suite's intensities).
    pub fn key(&self) -> String {
        match &self.target {
            Target::Keys(k) => k.join("+"),
            Target::Levels => "levels".into(),
        }
    }

    /// The input as its rows name it.
    pub fn info(&self) -> InputInfo {
        InputInfo {
            name: self.name.clone(),
            key: self.key(),
            relative: self.relative,
            low: self.low,
            high: self.high,
        }
    }

    fn relative_keys(name: &str, keys: &[&str], low: f64, high: f64, why: &'static str) -> Self {
        Self {
            name: name.into(),
            target: Target::Keys(keys.iter().map(|k| k.to_string()).collect()),
            low,
            high,
            relative: true,
            origin: Origin::Default { why },
        }
    }
}

/// Which inputs and quantities a study takes.
#[derive(Clone, Debug, Default)]
pub struct Choice {
    /// The inputs kept, by name, in this order (`None`: all of them).
    pub inputs: Option<Vec<String>>,
    /// Inputs added: `KEY=LOW:HIGH` (absolute) or `KEY=xLOW:xHIGH` (factors on the model's
    /// value); several keys moved together joined by `+`.
    pub add: Vec<String>,
    /// Of `suite::row::METRICS` (`None`: [`DEFAULT_QUANTITIES`]).
    pub quantities: Option<Vec<String>>,
}

/// A study refused before it starts.
#[derive(Debug, thiserror::Error)]
pub enum SensitivityError {
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error(transparent)]
    Cases(#[from] CasesError),
    /// An input's low or high value makes a model that is refused.
    #[error("{what}: {side} = {value} gives no valid model: {source}")]
    Side {
        /// The input: its file, line and field, its default, or its argument.
        what: String,
        side: &'static str,
        value: String,
        source: Box<CasesError>,
    },
    #[error("{what}: {reason}")]
    Input { what: String, reason: String },
    #[error(
        "--add '{argument}': {reason} (expected KEY=LOW:HIGH, or KEY=xLOW:xHIGH for factors on the model's value)"
    )]
    Add { argument: String, reason: String },
    #[error("--inputs: no input '{name}' (the study's: {known})")]
    Unknown { name: String, known: String },
    #[error("--quantities: '{name}' is not one of {known}")]
    Quantity { name: String, known: String },
    #[error(
        "no uncertain input applies to the model: give [[uncertain]] tables or --add KEY=LOW:HIGH"
    )]
    NoInputs,
    #[error(
        "{runs} runs ({cases} cases × (1 + 2 × {inputs} inputs)), more than the limit of {cap}"
    )]
    TooLarge {
        runs: usize,
        cases: usize,
        inputs: usize,
        cap: usize,
    },
}

/// Why each default is one (docs/sensitivity.md says the same).
pub mod why {
    pub(crate) const GAPS: &str = "as-built gaps differ from the design gap (tolerances, temperature, \
        shrinkage and creep), and a deck turns only once a corner has closed its gap";
    pub(crate) const JOINT_GAPS: &str = "the gaps of the expansion joints, for the same reasons";
    pub(crate) const MU: &str = "concrete on concrete at an abutment: about 0.3 to 0.7 around the \
        0.5 usually taken; a μ outside that range is varied by ×0.5/×1.5";
    pub(crate) const RESTITUTION: &str = "from a perfectly plastic impact (contacts of finite \
        duration) to a moderately elastic one";
    pub(crate) const STIFFNESS: &str = "a cracked-section stiffness is an estimate (E_c, I_cr/I_g)";
    pub(crate) const YIELD: &str = "material strengths and the axial load scatter";
    pub(crate) const DAMPING: &str = "damping is the least known property of a structure: a factor \
        of two either way";
    pub(crate) const ACTUATORS: &str = "an assumed value (the actuators' servo stiffness, or the \
        backwall's stem and piles)";
    pub(crate) const BACKFILL: &str = "Caltrans' passive backfill stiffness scatters by about a factor \
        of two";
    pub const PGA: &str = "a scaled record's intensity is known within about ±20 %; the \
        other inputs are read against it";
}

/// A number of the model `text` at `key`, if it is one.
fn number(text: &str, key: &str) -> Option<f64> {
    use crate::model::uncertain::{Leaf, resolve};
    match resolve(text, key).ok()?.first()?.1 {
        Leaf::Number(x) => Some(x),
        _ => None,
    }
}

/// Whether `key` names numbers in `text` (an array of them included).
fn present(text: &str, key: &str) -> bool {
    check_key(text, key, true).is_ok()
}

/// The default inputs of model `text` (its overrides applied) that apply to it; `suite` the
/// measure of a record suite's levels, when the cases are a suite's.
pub(crate) fn default_inputs(text: &str, suite: Option<&MeasureSpec>) -> Vec<Input> {
    let doc: toml::Table = toml::from_str(text).unwrap_or_default();
    let get = |t: &str, k: &str| doc.get(t).and_then(|t| t.get(k)).cloned();
    let contacts = get("contacts", "enabled").and_then(|v| v.as_bool()) != Some(false);
    let mut v = Vec::new();
    let gaps = |k: &str| {
        let all = crate::model::uncertain::resolve(text, k).unwrap_or_default();
        all.iter().any(|(_, l)| match l {
            crate::model::uncertain::Leaf::Numbers(x) => x.iter().any(|g| *g > 0.0),
            crate::model::uncertain::Leaf::Number(g) => *g > 0.0,
            _ => false,
        })
    };
    if contacts && gaps("contacts.gaps") {
        v.push(Input::relative_keys(
            "gaps",
            &["contacts.gaps"],
            0.5,
            1.5,
            why::GAPS,
        ));
    }
    if contacts && gaps("joint.*.gaps") {
        let w = why::JOINT_GAPS;
        v.push(Input::relative_keys(
            "joint_gaps",
            &["joint.*.gaps"],
            0.5,
            1.5,
            w,
        ));
    }
    if let Some(mu) = number(text, "contacts.mu").filter(|_| contacts) {
        if (0.3..=0.7).contains(&mu) {
            v.push(Input {
                relative: false,
                ..Input::relative_keys("mu", &["contacts.mu"], 0.3, 0.7, why::MU)
            });
        } else if mu > 0.0 {
            v.push(Input::relative_keys(
                "mu",
                &["contacts.mu"],
                0.5,
                1.5,
                why::MU,
            ));
        }
    }
    if contacts && number(text, "contacts.restitution").is_some() {
        let key = ["contacts.restitution"];
        v.push(Input {
            relative: false,
            ..Input::relative_keys("restitution", &key, 0.0, 0.5, why::RESTITUTION)
        });
    }
    let plain = [
        (
            "column_stiffness",
            "column.law.stiffness",
            0.8,
            1.2,
            why::STIFFNESS,
        ),
        (
            "column_yield",
            "column.law.yield_force",
            0.8,
            1.2,
            why::YIELD,
        ),
        ("damping", "damping.ratio", 0.5, 2.0, why::DAMPING),
    ];
    for (name, key, lo, hi, w) in plain {
        if number(text, key).is_some_and(|x| x > 0.0) {
            v.push(Input::relative_keys(name, &[key], lo, hi, w));
        }
    }
    let kind = get("abutment", "kind").and_then(|k| k.as_str().map(String::from));
    let kind = kind.unwrap_or_else(|| "actuators".into());
    let k = "abutment.actuator_stiffness";
    if kind != "rigid" && number(text, k).is_some_and(|x| x > 0.0) {
        v.push(Input::relative_keys(
            "actuator_stiffness",
            &[k],
            0.5,
            2.0,
            why::ACTUATORS,
        ));
    }
    let k = "abutment.backfill_stiffness";
    if kind == "backfill" && number(text, k).is_some_and(|x| x > 0.0) {
        v.push(Input::relative_keys(
            "backfill_stiffness",
            &[k],
            0.5,
            2.0,
            why::BACKFILL,
        ));
    }
    v.extend(intensity_input(text, suite));
    v
}

/// The intensity as an input: a suite's levels, the `[[run]]`s' target PGAs of a recorded
/// excitation, or a harmonic excitation's amplitudes; ×0.8/×1.2.
fn intensity_input(text: &str, suite: Option<&MeasureSpec>) -> Option<Input> {
    if let Some(m) = suite {
        let name = if matches!(m, MeasureSpec::Pga) {
            "pga"
        } else {
            "intensity"
        };
        return Some(Input {
            target: Target::Levels,
            ..Input::relative_keys(name, &[], 0.8, 1.2, why::PGA)
        });
    }
    let doc: toml::Table = toml::from_str(text).unwrap_or_default();
    let kind = (doc.get("excitation").and_then(|e| e.get("kind"))).and_then(|k| k.as_str());
    let keys: &[&str] = match kind {
        Some("record") => &["run.*.pga_x", "run.*.pga_y"],
        Some("harmonic") => &["excitation.amplitude_x", "excitation.amplitude_y"],
        _ => return None,
    };
    let keys: Vec<&str> = keys.iter().copied().filter(|k| present(text, k)).collect();
    let name = if kind == Some("record") {
        "pga"
    } else {
        "amplitude"
    };
    (!keys.is_empty()).then(|| Input::relative_keys(name, &keys, 0.8, 1.2, why::PGA))
}

/// The model's `[[uncertain]]` tables as inputs.
fn declared(text: &str) -> Vec<Input> {
    #[derive(serde::Deserialize)]
    struct Tables {
        #[serde(default)]
        uncertain: Vec<UncertainSpec>,
    }
    let t: Tables = toml::from_str(text).unwrap_or(Tables {
        uncertain: Vec::new(),
    });
    (t.uncertain.iter().enumerate())
        .map(|(entry, s)| Input {
            name: s.label(),
            target: Target::Keys(s.key.list()),
            low: s.low,
            high: s.high,
            relative: s.relative,
            origin: Origin::Model { entry },
        })
        .collect()
}

/// An `--add` argument as an input.
fn added(text: &str, argument: &str) -> Result<Input, SensitivityError> {
    let err = |reason: &str| SensitivityError::Add {
        argument: argument.into(),
        reason: reason.into(),
    };
    let (key, range) = argument.split_once('=').ok_or_else(|| err("no '='"))?;
    let (lo, hi) = range
        .split_once(':')
        .ok_or_else(|| err("no ':' in the range"))?;
    let (lo, hi) = (lo.trim(), hi.trim());
    let relative = lo.starts_with('x') && hi.starts_with('x');
    let (lo, hi) = (lo.trim_start_matches('x'), hi.trim_start_matches('x'));
    let num = |s: &str| s.parse::<f64>().ok().filter(|x| x.is_finite());
    let (Some(low), Some(high)) = (num(lo), num(hi)) else {
        return Err(err("LOW and HIGH must be finite numbers"));
    };
    if low >= high {
        return Err(err("LOW must be below HIGH"));
    }
    let keys: Vec<String> = key.split('+').map(|k| k.trim().to_string()).collect();
    for k in &keys {
        check_key(text, k, relative).map_err(|why| err(&why))?;
    }
    Ok(Input {
        name: key.trim().into(),
        target: Target::Keys(keys),
        low,
        high,
        relative,
        origin: Origin::Added {
            argument: argument.into(),
        },
    })
}

/// The inputs of a study: the model's (or the defaults), those named in `choice.inputs`,
/// then those added.
pub fn inputs(
    text: &str,
    suite: Option<&MeasureSpec>,
    choice: &Choice,
) -> Result<Vec<Input>, SensitivityError> {
    let mut all = declared(text);
    if all.is_empty() {
        all = default_inputs(text, suite);
    }
    if let Some(names) = &choice.inputs {
        let known = || all.iter().map(|i| i.name.as_str()).collect::<Vec<_>>();
        let picked = (names.iter().map(|n| n.trim()))
            .map(|n| {
                (all.iter().find(|i| i.name == n).cloned()).ok_or_else(|| {
                    SensitivityError::Unknown {
                        name: n.into(),
                        known: known().join(", "),
                    }
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        all = picked;
    }
    for a in &choice.add {
        all.push(added(text, a)?);
    }
    if all.is_empty() {
        return Err(SensitivityError::NoInputs);
    }
    Ok(all)
}

/// The quantities of `choice`, checked against `suite::row::METRICS`.
fn quantities(choice: &Choice) -> Result<Vec<String>, SensitivityError> {
    let q: Vec<String> = match &choice.quantities {
        Some(q) => q.iter().map(|s| s.trim().to_string()).collect(),
        None => DEFAULT_QUANTITIES.map(String::from).to_vec(),
    };
    for name in &q {
        if !METRICS.contains(&name.as_str()) {
            let known = METRICS.join(", ");
            return Err(SensitivityError::Quantity {
                name: name.clone(),
                known,
            });
        }
    }
    Ok(q)
}

/// A sensitivity study, every variant compiled.
pub struct Study {
    inputs: Vec<Input>,
    quantities: Vec<String>,
    /// The model, then each input at its low and its high value.
    variants: Vec<CaseSet>,
    /// The cases' names.
    labels: Vec<String>,
}

/// The study's input, side and value of variant `v` (0: the model).
fn variant(inputs: &[Input], v: usize) -> Option<(&Input, Side, f64)> {
    let i = inputs.get(v.checked_sub(1)? / 2)?;
    Some(if v % 2 == 1 {
        (i, Side::Low, i.low)
    } else {
        (i, Side::High, i.high)
    })
}

impl Study {
    /// The study of the model file at `path` with the fixed overrides `fix` on `cases`.
    pub fn open(
        path: &Path,
        fix: &[String],
        cases: &Cases,
        choice: &Choice,
    ) -> Result<Self, SensitivityError> {
        let text =
            crate::input::read_bounded(path, crate::input::MAX_MODEL_BYTES).map_err(|e| {
                ModelError::Io {
                    path: path.to_path_buf(),
                    source: e,
                }
            })?;
        Self::from_text(&text, path, fix, cases, choice)
    }

    /// [`Study::open`] of model text (`path` names it in errors and anchors its records).
    pub fn from_text(
        text: &str,
        path: &Path,
        fix: &[String],
        cases: &Cases,
        choice: &Choice,
    ) -> Result<Self, SensitivityError> {
        let base = CaseSet::new(text, path, fix, cases)?;
        let fixed = apply_overrides(text, fix)?;
        let measure = match cases {
            Cases::Suite { measure, .. } => Some(measure),
            Cases::ModelRuns => None,
        };
        let inputs = inputs(&fixed, measure, choice)?;
        let quantities = quantities(choice)?;
        let n = base.len();
        let runs = n.saturating_mul(1 + 2 * inputs.len());
        if runs > MAX_RUNS {
            let (cases, inputs, cap) = (n, inputs.len(), MAX_RUNS);
            return Err(SensitivityError::TooLarge {
                runs,
                cases,
                inputs,
                cap,
            });
        }
        let sides: Vec<usize> = (1..1 + 2 * inputs.len()).collect();
        let compiled: Vec<Result<CaseSet, SensitivityError>> = (sides.par_iter())
            .map(|&v| compile_variant(text, path, fix, cases, (&fixed, &inputs), v))
            .collect();
        let labels = (0..n).map(|k| base.label(k)).collect();
        let mut variants = vec![base];
        for c in compiled {
            variants.push(c?);
        }
        Ok(Self {
            inputs,
            quantities,
            variants,
            labels,
        })
    }

    pub fn inputs(&self) -> &[Input] {
        &self.inputs
    }

    /// The quantities asked for (the CSV's columns).
    pub fn quantities(&self) -> &[String] {
        &self.quantities
    }

    /// The number of cases.
    pub fn cases(&self) -> usize {
        self.labels.len()
    }

    /// The number of runs: cases × (1 + 2 × inputs).
    pub fn runs(&self) -> usize {
        self.cases() * self.variants.len()
    }

    /// Run `i`, or its row refused as `reason` without running it.
    fn row(&self, i: usize, refuse: Option<&str>) -> RunRow {
        let n = self.cases().max(1);
        let (v, k) = (i / n, i % n);
        let (input, side) = match variant(&self.inputs, v) {
            Some((input, side, _)) => (Some(input.info()), side),
            None => (None, Side::Base),
        };
        let m = match (refuse, self.variants.get(v)) {
            (None, Some(set)) => set.measure(k, &[]),
            (Some(r), _) => super::cases::Measured::refused(r.into()),
            (None, None) => super::cases::Measured::refused(format!("no run {i}")),
        };
        RunRow {
            input,
            side,
            case: self.labels.get(k).cloned().unwrap_or_default(),
            values: self.quantities.iter().map(|q| m.get(q)).collect(),
            status: m.status,
            steps: m.steps,
            events: m.events,
            cpu: Some(m.cpu),
        }
    }

    /// The runs `indices` (those below [`Study::runs`]) in parallel, in their order, `each`
    /// handed every row as soon as it is final; once [`Progress::go_on`] says no, the runs
    /// not started are refused as [`CANCELLED`].
    pub fn run_listed(
        &self,
        indices: &[usize],
        progress: &dyn Progress,
        each: &(dyn Fn(usize, &RunRow) + Sync),
    ) -> Vec<RunRow> {
        let indices: Vec<usize> = (indices.iter().copied())
            .filter(|&i| i < self.runs())
            .collect();
        progress.plan(indices.len());
        (indices.into_par_iter())
            .map(|i| {
                let refuse = (!progress.go_on()).then_some(CANCELLED);
                let row = self.row(i, refuse);
                progress.done(1);
                each(i, &row);
                row
            })
            .collect()
    }

    /// Every run, then the swings: the whole study (cancelled runs count as failed).
    pub fn run(&self, progress: &dyn Progress) -> Sensitivity {
        let all: Vec<usize> = (0..self.runs()).collect();
        let rows = self.run_listed(&all, progress, &|_, _| {});
        summarize(&self.quantities, rows)
    }
}

/// Variant `v` (≥ 1) compiled: its input's overrides after `fix` (resolved in `fixed`, the
/// model with `fix`), or a suite's levels scaled.
fn compile_variant(
    text: &str,
    path: &Path,
    fix: &[String],
    cases: &Cases,
    (fixed, inputs): (&str, &[Input]),
    v: usize,
) -> Result<CaseSet, SensitivityError> {
    let Some((input, side, value)) = variant(inputs, v) else {
        unreachable!("variant {v} of {} inputs", inputs.len())
    };
    let what = describe(input, text, path, side);
    let refuse = |reason: String| SensitivityError::Input {
        what: what.clone(),
        reason,
    };
    let mut set = fix.to_vec();
    let mut cases = cases.clone();
    match (&input.target, &mut cases) {
        (Target::Levels, Cases::Suite { levels, .. }) => {
            levels.iter_mut().for_each(|l| *l *= value);
        }
        (Target::Levels, Cases::ModelRuns) => {
            return Err(refuse(
                "a suite's levels, but the cases are the model's runs".into(),
            ));
        }
        (Target::Keys(keys), _) => {
            if matches!(cases, Cases::Suite { .. })
                && let Some(r) = keys.iter().find_map(|k| reserved(k))
            {
                let why = format!(
                    "a record suite sets {r} itself for each run: leave this input out (--inputs)"
                );
                return Err(refuse(why));
            }
            set.extend(side_overrides(fixed, keys, value, input.relative).map_err(refuse)?);
        }
    }
    CaseSet::new(text, path, &set, &cases).map_err(|e| SensitivityError::Side {
        what,
        side: side.text(),
        value: if input.relative {
            format!("×{value}")
        } else {
            value.to_string()
        },
        source: Box::new(e),
    })
}

/// An input for an error: its file, line and field (`uncertain.N.low`), its default, or its
/// argument.
fn describe(input: &Input, text: &str, path: &Path, side: Side) -> String {
    match &input.origin {
        Origin::Model { entry } => {
            let field = format!("uncertain.{entry}.{}", side.text());
            let line = locate(text, &field).map_or(0, |l| l.0);
            format!("{}:{line}: {field} ('{}')", path.display(), input.name)
        }
        Origin::Default { .. } => format!("the default input '{}' ({})", input.name, input.key()),
        Origin::Added { argument } => format!("--add '{argument}'"),
    }
}

/// The fingerprint text of a study's job (`shard::JobId`'s arguments): its inputs, cases and
/// quantities.
pub fn job_arguments(study: &Study, cases: &Cases, fix: &[String]) -> String {
    let inputs: Vec<String> = (study.inputs.iter())
        .map(|i| format!("{}={}:{}:{}:{}", i.name, i.key(), i.relative, i.low, i.high))
        .collect();
    let cases = match cases {
        Cases::ModelRuns => "model runs".to_string(),
        Cases::Suite {
            pairs,
            measure,
            levels,
            tail,
        } => {
            let names: Vec<&str> = pairs.iter().map(|p| p.name.as_str()).collect();
            format!("suite {names:?} {measure:?} {levels:?} {tail}")
        }
    };
    format!(
        "inputs={inputs:?} cases={cases} quantities={:?} fix={fix:?}",
        study.quantities
    )
}
