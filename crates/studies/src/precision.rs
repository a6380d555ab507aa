//! Work–precision: each method over its own knob (tolerance, step, contact stiffness), CPU time
//! against the error from a converged event-driven reference (Hairer & Wanner's work–precision
//! diagrams); and where each method fails (stability table).

use crate::methods::{Knob, Method};
use crate::model;
use crate::output::{EventKind, RunOutput, SampleKind};
use crate::studies::{Failure, RunFailure, Study, failure_text, largest_rotation_dof};
use serde::Serialize;
use std::fmt;
use std::path::Path;
use std::sync::Arc;

/// One point of a work–precision diagram.
#[derive(Clone, Debug, Serialize)]
pub struct Point {
    #[serde(serialize_with = "method_name")]
    pub method: Method,
    /// "rtol=1e-6", "h=1e-3", "h=1e-3 k=1e6" …
    pub knob: String,
    /// CPU seconds of the thread that ran the integration (`clock::thread_cpu`).
    pub cpu_s: f64,
    /// |peak − peak_ref| / |peak_ref| of the watched DOF.
    pub peak_error: f64,
    /// RMS of the history difference over RMS of the reference.
    pub rms_error: f64,
    /// |t₁ − t₁,ref| of the first impact, s (NaN without impacts).
    pub impact_time_error: f64,
    pub steps: usize,
    /// Why the run gave no output (None: it finished).
    #[serde(serialize_with = "failure_text")]
    pub failure: Option<Failure>,
}

fn method_name<S: serde::Serializer>(m: &Method, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(m.name())
}

impl Point {
    /// The run finished.
    pub fn is_ok(&self) -> bool {
        self.failure.is_none()
    }

    /// The error named by `metric`: "peak", "rms" or "impact".
    pub fn error(&self, metric: &str) -> f64 {
        match metric {
            "rms" => self.rms_error,
            "impact" => self.impact_time_error,
            _ => self.peak_error,
        }
    }
}

/// The watched quantity: the rotation of the deck's body that turns most in the reference (the
/// specimen's deck; of several frames, the one with the largest peak), else the first θ, else
/// DOF 0.
pub struct Reference {
    pub run: RunOutput,
    pub dof: usize,
    pub peak: f64,
    pub t: Vec<f64>,
    pub y: Vec<f64>,
    pub first_impact: Option<f64>,
}

fn series(r: &RunOutput, dof: usize) -> (Vec<f64>, Vec<f64>) {
    r.samples
        .iter()
        .filter(|s| s.kind != SampleKind::PreEvent)
        .map(|s| (s.t, s.q[dof]))
        .unzip()
}

fn first_impact(r: &RunOutput) -> Option<f64> {
    r.events
        .iter()
        .find(|e| e.kind == EventKind::Impact)
        .map(|e| e.t)
}

fn interp(t: &[f64], y: &[f64], x: f64) -> f64 {
    match t.partition_point(|&ti| ti < x) {
        0 => y[0],
        i if i >= t.len() => y[t.len() - 1],
        i => {
            let (t0, t1) = (t[i - 1], t[i]);
            if t1 <= t0 {
                y[i]
            } else {
                y[i - 1] + (y[i] - y[i - 1]) * (x - t0) / (t1 - t0)
            }
        }
    }
}

/// A model read once and run with knob overrides.
pub struct Bench {
    pub study: Study,
}

impl Bench {
    pub fn open(path: &Path, base: &[String]) -> Result<Self, model::ModelError> {
        Ok(Self {
            study: Study::open(path, base)?,
        })
    }

    pub fn run(&self, set: &[String]) -> Result<(RunOutput, f64), RunFailure> {
        self.study.measure(set)
    }

    /// The converged event-driven reference.
    pub fn reference(&self, rtol: f64) -> Result<Reference, RunFailure> {
        // every event at its own instant: the reference carries no branch window
        let (run, _) = self.run(&[
            format!("solver.method=\"{}\"", Method::Event.name()),
            format!("solver.rtol={rtol:e}"),
            format!("solver.atol={:e}", rtol * 1e-3),
            "solver.branch_window=0".into(),
        ])?;
        let dof = largest_rotation_dof(&run);
        let (t, y) = series(&run, dof);
        Ok(Reference {
            peak: run.summary.peaks[dof].max_abs,
            first_impact: first_impact(&run),
            dof,
            t,
            y,
            run,
        })
    }

    pub fn measure(
        &self,
        reference: &Reference,
        method: Method,
        knob: &str,
        set: &[String],
    ) -> Point {
        let mut ov = vec![format!("solver.method=\"{}\"", method.name())];
        ov.extend(set.iter().cloned());
        match self.run(&ov) {
            Ok((r, cpu)) => {
                let (t, y) = series(&r, reference.dof);
                let (mut num, mut den) = (0.0, 0.0);
                for (tr, yr) in reference.t.iter().zip(&reference.y) {
                    let d = interp(&t, &y, *tr) - yr;
                    num += d * d;
                    den += yr * yr;
                }
                Point {
                    method,
                    knob: knob.into(),
                    cpu_s: cpu,
                    peak_error: (r.summary.peaks[reference.dof].max_abs - reference.peak).abs()
                        / reference.peak.abs().max(1e-300),
                    rms_error: (num / den.max(1e-300)).sqrt(),
                    impact_time_error: match (first_impact(&r), reference.first_impact) {
                        (Some(a), Some(b)) => (a - b).abs(),
                        _ => f64::NAN,
                    },
                    steps: r.summary.stats.steps_accepted,
                    failure: None,
                }
            }
            Err(e) => Point {
                method,
                knob: knob.into(),
                cpu_s: f64::NAN,
                peak_error: f64::NAN,
                rms_error: f64::NAN,
                impact_time_error: f64::NAN,
                steps: 0,
                failure: Some(Arc::new(e)),
            },
        }
    }
}

/// Knob settings of each method for a run of length `t_end` with base contact stiffness `k`.
pub fn knobs(method: Method, t_end: f64, k: f64, quick: bool) -> Vec<(String, Vec<String>)> {
    let steps: Vec<f64> = if quick {
        vec![100.0, 1000.0, 10000.0]
    } else {
        vec![100.0, 300.0, 1000.0, 3000.0, 10000.0, 30000.0, 100000.0]
    };
    match method.knob() {
        Knob::Tolerance => {
            let tols: &[f64] = if quick {
                &[1e-3, 1e-5, 1e-7]
            } else {
                &[1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8]
            };
            tols.iter()
                .map(|r| {
                    (
                        format!("rtol={r:.0e}"),
                        vec![
                            format!("solver.rtol={r:e}"),
                            format!("solver.atol={:e}", r * 1e-3),
                        ],
                    )
                })
                .collect()
        }
        Knob::Step => steps
            .iter()
            .map(|n| {
                let h = t_end / n;
                (format!("h={h:.1e}"), vec![format!("solver.step={h:e}")])
            })
            .collect(),
        Knob::StepStiffness => {
            let ks: &[f64] = if quick { &[1.0] } else { &[0.01, 1.0, 100.0] };
            let mut out = Vec::new();
            for f in ks {
                for n in &steps {
                    let h = t_end / n;
                    let kk = k * f;
                    out.push((
                        format!("h={h:.1e} k={kk:.0e}"),
                        vec![
                            format!("solver.step={h:e}"),
                            format!("solver.contact_stiffness={kk:e}"),
                        ],
                    ));
                }
            }
            out
        }
    }
}

/// The family of a knob: its contact stiffness (`h=1e-3 k=1e6` → `k=1e6`), empty for
/// methods with one knob. Points of one method and family form one curve.
pub(crate) fn knob_family(knob: &str) -> &str {
    knob.split_once(" k=")
        .map_or("", |(_, k)| &knob[knob.len() - k.len() - 2..])
}

/// The knob without its family (`h=1e-3 k=1e6` → `h=1e-3`).
pub(crate) fn knob_step(knob: &str) -> &str {
    knob.split_once(" k=").map_or(knob, |(h, _)| h)
}

/// The cheapest knob of a method from which on every costlier knob also stays within `tol`
/// (so a coarse run that lands near the reference by chance does not count).
/// Penalty points form one family per contact stiffness.
pub fn cheapest_within<'a>(
    points: &'a [Point],
    method: Method,
    metric: &str,
    tol: f64,
) -> Option<&'a Point> {
    let family = |p: &Point| knob_family(&p.knob).to_string();
    let mut families: Vec<String> = points
        .iter()
        .filter(|p| p.method == method)
        .map(family)
        .collect();
    families.sort();
    families.dedup();
    let ok = |p: &Point| p.is_ok() && p.error(metric) <= tol;
    families
        .iter()
        .filter_map(|f| {
            // in the order the knobs were generated: coarse to fine
            let mine: Vec<&Point> = points
                .iter()
                .filter(|p| p.method == method && family(p) == *f)
                .collect();
            (0..mine.len())
                .find(|&i| mine[i..].iter().all(|p| ok(p)))
                .map(|i| mine[i])
        })
        .min_by(|a, b| a.cpu_s.total_cmp(&b.cpu_s))
}

pub fn write_csv(points: &[Point], path: &Path) -> std::io::Result<()> {
    let mut w = csv::Writer::from_path(path)?;
    w.write_record([
        "method",
        "knob",
        "cpu_s",
        "peak_error",
        "rms_error",
        "impact_time_error",
        "steps",
        "status",
    ])?;
    for p in points {
        w.write_record([
            p.method.name().to_string(),
            p.knob.clone(),
            format!("{:.6e}", p.cpu_s),
            format!("{:.6e}", p.peak_error),
            format!("{:.6e}", p.rms_error),
            format!("{:.6e}", p.impact_time_error),
            p.steps.to_string(),
            p.failure.as_ref().map_or("ok".into(), |e| e.to_string()),
        ])?;
    }
    w.flush()
}

/// A point of the stability table.
#[derive(Clone, Debug)]
pub enum Verdict {
    /// max(peak, history error) within the limit.
    Ok { peak: f64, history: f64 },
    /// max(peak, history error) above the limit or not finite.
    Inaccurate { peak: f64, history: f64 },
    /// Stopped by [`crate::SolverError::Unstable`] (energy growth).
    Unstable,
    /// Stopped by any other error.
    Failed(Failure),
}

/// The error above which `stability` calls a run inaccurate unless told otherwise, and
/// `precision` marks its points: one legend for both.
pub const INACCURATE_ABOVE: f64 = 0.05;

/// Classify a point for the stability table: the larger of the peak and the RMS history
/// error against `tol` (a coarse run can hit the peak by chance, not the history).
pub fn verdict(p: &Point, tol: f64) -> Verdict {
    let (peak, history) = (p.peak_error, p.rms_error);
    let e = peak.max(history);
    match &p.failure {
        Some(f) if matches!(**f, RunFailure::Unstable(_)) => Verdict::Unstable,
        Some(f) => Verdict::Failed(f.clone()),
        None if e > tol || !e.is_finite() => Verdict::Inaccurate { peak, history },
        None => Verdict::Ok { peak, history },
    }
}

/// The table's text: errors in percent.
impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let pct = |peak: f64, history: f64| {
            format!(
                "peak {:.2} %, history {:.2} %",
                100.0 * peak,
                100.0 * history
            )
        };
        match self {
            Verdict::Ok { peak, history } => write!(f, "ok ({})", pct(*peak, *history)),
            Verdict::Inaccurate { peak, history } => {
                write!(f, "inaccurate ({})", pct(*peak, *history))
            }
            Verdict::Unstable => f.write_str("unstable (detected: energy growth)"),
            // a solver error's own text starts with "failed: " already
            Verdict::Failed(e) => match &**e {
                RunFailure::Solver(s) => write!(f, "failed: {s}"),
                other => write!(f, "failed: {other}"),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::SolverError;

    #[test]
    fn a_failed_run_says_failed_once() {
        let p = Point {
            method: Method::Event,
            knob: "rtol=1e-3".into(),
            cpu_s: f64::NAN,
            peak_error: f64::NAN,
            rms_error: f64::NAN,
            impact_time_error: f64::NAN,
            steps: 0,
            failure: Some(Arc::new(RunFailure::Solver(SolverError::NonFinite {
                t: 1.5,
            }))),
        };
        let v = verdict(&p, INACCURATE_ABOVE).to_string();
        assert!(
            v.starts_with("failed: ") && !v.contains("failed: failed"),
            "{v}"
        );
        assert!(v.contains("1.5"), "{v}");
    }
}
