//! Fragility curves of a record suite: for each combination of swept parameters and each
//! limit state, the lognormal P(exceed | IM = x) = Φ(ln(x/θ)/β) fitted by maximum likelihood
//! over multiple stripes or IDA capacities (`design::mle`), with a 5–95 % band from the
//! bootstrap over records (`design::bootstrap`).
//!
//! Runs that failed or were refused, and finished runs whose limit-state column is empty
//! (does not apply), are counted per level ([`LevelCount`]) and left out of the likelihood;
//! except a run that stopped because a deck end left its seat (`failed: Unseated: …`): the
//! bridge has collapsed, and such a run exceeds every limit state.
//! In IDA a record's capacity is the lowest level at which a finished run exceeds; a record
//! none of whose finished runs exceeds is censored at the highest level it finished.

use super::bootstrap::{quantile, resample};
use super::mle::{Capacity, Count, Fit, FitError, fit_ida, fit_stripes, probability};
use super::suite::{RunStatus, Suite};
use crate::model::limit_state::LimitState;
use serde::Serialize;
use std::collections::BTreeMap;

/// Replicates of the bootstrap unless told otherwise.
pub const DEFAULT_BOOTSTRAP: usize = 1000;
/// Most replicates of one bootstrap.
pub const MAX_BOOTSTRAP: usize = 100_000;
/// Points of a fitted curve (and its band), from x = 0.
pub const CURVE_POINTS: usize = 101;
/// The band's quantiles.
pub(crate) const BAND: [f64; 2] = [0.05, 0.95];

/// Which likelihood.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Binomial counts per level (multiple stripes).
    Stripes,
    /// Censored lognormal capacities per record (incremental dynamic analysis).
    Ida,
}

impl Method {
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "stripes" => Some(Method::Stripes),
            "ida" => Some(Method::Ida),
            _ => None,
        }
    }
    pub fn title(self) -> &'static str {
        match self {
            Method::Stripes => "multiple stripes",
            Method::Ida => "IDA (censored capacities)",
        }
    }
}

/// How to fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Options {
    pub method: Method,
    /// Bootstrap replicates (0: no band).
    pub bootstrap: usize,
    pub seed: u64,
}

/// What a run says about a limit state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    Exceed,
    Safe,
    Failed,
    Refused,
    /// Finished, with the limit state's column empty.
    NotApplicable,
}

/// A record (pair) and its runs: (level, outcome).
#[derive(Clone, Debug, PartialEq)]
pub struct Record {
    pub pair: String,
    pub runs: Vec<(f64, Outcome)>,
}

/// The runs at one level.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct LevelCount {
    pub level: f64,
    /// Finished runs to which the limit state applies (those in the likelihood).
    pub runs: usize,
    pub exceed: usize,
    pub failed: usize,
    pub refused: usize,
    pub not_applicable: usize,
}

/// The bootstrap's band.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Band {
    pub replicates: usize,
    /// Replicates that could be fitted (the others' resampled data had no maximum).
    pub fitted: usize,
    pub seed: u64,
    /// 5 and 95 % quantiles of θ, of β, and of P at the fitted θ.
    pub theta: [f64; 2],
    pub beta: [f64; 2],
    pub at_theta: [f64; 2],
}

/// A point of the fitted curve, with the band (`None` without bootstrap).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CurvePoint {
    pub x: f64,
    pub p: f64,
    pub lo: Option<f64>,
    pub hi: Option<f64>,
}

/// A fragility curve of one limit state for one combination of swept parameters.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Fragility {
    pub limit: LimitState,
    pub expression: String,
    /// The swept parameters' (key, value).
    pub group: Vec<(String, String)>,
    pub method: Method,
    /// Records with at least one run in the likelihood.
    pub records: usize,
    pub levels: Vec<LevelCount>,
    pub fit: Fit,
    pub band: Option<Band>,
    pub curve: Vec<CurvePoint>,
}

/// Why no fragility curve.
#[derive(Debug, thiserror::Error)]
pub enum FragilityError {
    #[error("limit state '{limit}': no response column '{column}' in the suite ({available})")]
    Column {
        limit: String,
        column: String,
        available: String,
    },
    #[error("{replicates} bootstrap replicates: at most {max}")]
    Bootstrap { replicates: usize, max: usize },
    #[error("limit state '{limit}'{}: {source}", group_suffix(group))]
    Fit {
        limit: String,
        group: Vec<(String, String)>,
        /// The runs per level the fit was given.
        levels: Vec<LevelCount>,
        #[source]
        source: FitError,
    },
}

/// `key=value, …` of a group.
pub fn group_text(group: &[(String, String)]) -> String {
    let parts: Vec<String> = group.iter().map(|(k, v)| format!("{k}={v}")).collect();
    parts.join(", ")
}

fn group_suffix(group: &[(String, String)]) -> String {
    if group.is_empty() {
        String::new()
    } else {
        format!(" at {}", group_text(group))
    }
}

/// The records of `group` with the outcome of each run for `limit`, pairs in order of first
/// appearance.
pub fn records(
    suite: &Suite,
    group: &[(String, String)],
    limit: &LimitState,
) -> Result<Vec<Record>, FragilityError> {
    let column = (suite.responses.iter().position(|c| *c == limit.column)).ok_or_else(|| {
        FragilityError::Column {
            limit: limit.name.clone(),
            column: limit.column.clone(),
            available: suite.responses.join(", "),
        }
    })?;
    let values: Vec<&String> = group.iter().map(|(_, v)| v).collect();
    let mut index: BTreeMap<&str, usize> = BTreeMap::new();
    let mut out: Vec<Record> = Vec::new();
    for r in suite
        .runs
        .iter()
        .filter(|r| r.params.iter().eq(values.iter().copied()))
    {
        let outcome = match (&r.status, r.values[column]) {
            (RunStatus::Failed(reason), _) if is_unseated(reason) => Outcome::Exceed,
            (RunStatus::Failed(_), _) => Outcome::Failed,
            (RunStatus::Refused(_), _) => Outcome::Refused,
            (RunStatus::Finished, None) => Outcome::NotApplicable,
            (RunStatus::Finished, Some(v)) if limit.exceeded(v) => Outcome::Exceed,
            (RunStatus::Finished, Some(_)) => Outcome::Safe,
        };
        let k = *index.entry(r.pair.as_str()).or_insert_with(|| {
            out.push(Record {
                pair: r.pair.clone(),
                runs: Vec::new(),
            });
            out.len() - 1
        });
        out[k].runs.push((r.level, outcome));
    }
    Ok(out)
}

/// The runs per level of `records`, levels in increasing order.
pub(crate) fn level_counts<'a>(records: impl IntoIterator<Item = &'a Record>) -> Vec<LevelCount> {
    let mut by: BTreeMap<u64, LevelCount> = BTreeMap::new();
    for r in records {
        for &(level, o) in &r.runs {
            // positive levels order as their bits
            let c = by.entry(level.to_bits()).or_insert(LevelCount {
                level,
                ..LevelCount::default()
            });
            match o {
                Outcome::Exceed => {
                    c.runs += 1;
                    c.exceed += 1;
                }
                Outcome::Safe => c.runs += 1,
                Outcome::Failed => c.failed += 1,
                Outcome::Refused => c.refused += 1,
                Outcome::NotApplicable => c.not_applicable += 1,
            }
        }
    }
    by.into_values().collect()
}

/// Each record's capacity: the lowest level at which it exceeds, else censored at the highest
/// level it finished; records without a finished run that applies are left out.
pub fn capacities<'a>(records: impl IntoIterator<Item = &'a Record>) -> Vec<Capacity> {
    let mut out = Vec::new();
    for r in records {
        let lowest_exceed = (r.runs.iter())
            .filter(|(_, o)| *o == Outcome::Exceed)
            .map(|(l, _)| *l)
            .min_by(f64::total_cmp);
        let highest_safe = (r.runs.iter())
            .filter(|(_, o)| *o == Outcome::Safe)
            .map(|(l, _)| *l)
            .max_by(f64::total_cmp);
        match (lowest_exceed, highest_safe) {
            (Some(level), _) => out.push(Capacity {
                level,
                censored: false,
            }),
            (None, Some(level)) => out.push(Capacity {
                level,
                censored: true,
            }),
            (None, None) => {}
        }
    }
    out
}

/// The fit of `records` by `method`.
pub fn fit(method: Method, records: &[&Record]) -> Result<Fit, FitError> {
    match method {
        Method::Stripes => {
            let counts: Vec<Count> = (level_counts(records.iter().copied()).iter())
                .map(|c| Count {
                    level: c.level,
                    runs: c.runs,
                    exceed: c.exceed,
                })
                .collect();
            fit_stripes(&counts)
        }
        Method::Ida => fit_ida(&capacities(records.iter().copied())),
    }
}

/// The fragility curve of `limit` for the runs of `group`.
pub fn fragility(
    suite: &Suite,
    group: &[(String, String)],
    limit: &LimitState,
    opts: &Options,
) -> Result<Fragility, FragilityError> {
    if opts.bootstrap > MAX_BOOTSTRAP {
        return Err(FragilityError::Bootstrap {
            replicates: opts.bootstrap,
            max: MAX_BOOTSTRAP,
        });
    }
    let recs = records(suite, group, limit)?;
    let levels = level_counts(&recs);
    let all: Vec<&Record> = recs.iter().collect();
    let f = fit(opts.method, &all).map_err(|source| FragilityError::Fit {
        limit: limit.name.clone(),
        group: group.to_vec(),
        levels: levels.clone(),
        source,
    })?;
    let used = (recs.iter())
        .filter(|r| {
            r.runs
                .iter()
                .any(|(_, o)| matches!(o, Outcome::Exceed | Outcome::Safe))
        })
        .count();
    let top = levels.iter().map(|c| c.level).fold(0.0, f64::max);
    let x_hi = top.max(1.2 * f.theta).min(3.0 * top);
    let xs: Vec<f64> = (0..CURVE_POINTS)
        .map(|i| x_hi * i as f64 / (CURVE_POINTS - 1) as f64)
        .collect();
    let (band, bounds) = if opts.bootstrap > 0 {
        let (b, bounds) = bootstrap(&all, opts, &f, &xs);
        (Some(b), bounds)
    } else {
        (None, vec![None; xs.len()])
    };
    let curve = (xs.iter().zip(bounds))
        .map(|(&x, b)| CurvePoint {
            x,
            p: f.probability(x),
            lo: b.map(|b| b[0]),
            hi: b.map(|b| b[1]),
        })
        .collect();
    Ok(Fragility {
        limit: limit.clone(),
        expression: limit.expression(),
        group: group.to_vec(),
        method: opts.method,
        records: used,
        levels,
        fit: f,
        band,
        curve,
    })
}

/// The band of the bootstrap over records and its bounds at each x (`None` where no
/// replicate could be fitted).
fn bootstrap(
    all: &[&Record],
    opts: &Options,
    f: &Fit,
    xs: &[f64],
) -> (Band, Vec<Option<[f64; 2]>>) {
    let fits: Vec<(f64, f64)> = resample(all.len(), opts.bootstrap, opts.seed, |pick| {
        let sample: Vec<&Record> = pick.iter().map(|&i| all[i]).collect();
        fit(opts.method, &sample).ok().map(|g| (g.theta, g.beta))
    })
    .into_iter()
    .flatten()
    .collect();
    let band_of = |mut v: Vec<f64>| -> [f64; 2] {
        v.sort_by(f64::total_cmp);
        BAND.map(|q| quantile(&v, q))
    };
    let at = |x: f64| -> Vec<f64> { fits.iter().map(|&(t, b)| probability(x, t, b)).collect() };
    let band = Band {
        replicates: opts.bootstrap,
        fitted: fits.len(),
        seed: opts.seed,
        theta: band_of(fits.iter().map(|p| p.0).collect()),
        beta: band_of(fits.iter().map(|p| p.1).collect()),
        at_theta: band_of(at(f.theta)),
    };
    let bounds = (xs.iter())
        .map(|&x| (!fits.is_empty()).then(|| band_of(at(x))))
        .collect();
    (band, bounds)
}

/// A run stopped by the loss of a seat (the solver error's kind `Unseated`).
fn is_unseated(reason: &str) -> bool {
    reason.trim_start().starts_with("Unseated")
}
