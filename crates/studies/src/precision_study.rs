//! Work–precision and stability as a study the workbench fills point by point: the quick
//! knobs of every method ([`crate::precision::knobs`]) against the converged event-driven
//! reference, each point told to its caller as it is final, the points not started skipped
//! on a cancel. Its CSV rows (`study_csv`):
//! `study,method,knob,cpu_s,peak_error,rms_error,impact_time_error,steps,status` — `study` is
//! `precision`, `status` is `ok`, `not run` or the run's failure (`unstable: …`, `failed: …`).

use crate::methods::Method;
use crate::precision::{Bench, Point, knobs};
use crate::progress::Progress;
use crate::run::SolverError;
use crate::studies::{RunFailure, Study};
use std::sync::Arc;

/// The reference's relative tolerance (as `deckspin precision`).
pub(crate) const REFERENCE_RTOL: f64 = 1e-10;

/// The CSV header of a work–precision study.
pub const HEADER: [&str; 9] = [
    "study",
    "method",
    "knob",
    "cpu_s",
    "peak_error",
    "rms_error",
    "impact_time_error",
    "steps",
    "status",
];

/// The points of a work–precision study, planned and done.
#[derive(Clone, Debug)]
pub struct PrecisionTable {
    /// (method, knob label) of each point, in the order they run (method by method, coarse to
    /// fine).
    pub planned: Vec<(Method, String)>,
    /// The point of each planned knob once it ran (None: not run, or cancelled before).
    pub points: Vec<Option<Point>>,
}

impl PartialEq for PrecisionTable {
    /// Same plan, and point by point the same numbers and the same kind of status (finished,
    /// unstable, failed otherwise): an instability read back keeps its words as its detail.
    fn eq(&self, other: &Self) -> bool {
        let key = |p: &Option<Point>| {
            p.as_ref().map(|p| {
                let kind = match p.failure.as_deref() {
                    None => 0,
                    Some(RunFailure::Unstable(_)) => 1,
                    Some(_) => 2,
                };
                (
                    [p.cpu_s, p.peak_error, p.rms_error, p.impact_time_error].map(f64::to_bits),
                    p.steps,
                    kind,
                )
            })
        };
        self.planned == other.planned
            && self.points.len() == other.points.len()
            && (self.points.iter().zip(&other.points)).all(|(a, b)| key(a) == key(b))
    }
}

/// A point's status as written: `ok` or its failure's text.
pub(crate) fn status_text(p: &Point) -> String {
    p.failure.as_ref().map_or("ok".into(), |e| e.to_string())
}

/// A failure read back from its text: `unstable: …` stays an instability (the stability
/// grid's verdict; its text becomes the detail), anything else keeps its words.
pub(crate) fn failure_of(text: &str) -> Arc<RunFailure> {
    Arc::new(match text.strip_prefix("unstable: ") {
        Some(detail) => RunFailure::Unstable(SolverError::Unstable {
            t: f64::NAN,
            method: "read back",
            step: f64::NAN,
            detail: detail.to_string(),
        }),
        None => RunFailure::Suite(text.to_string()),
    })
}

impl PrecisionTable {
    /// Every method's quick knobs for a run of `t_end` s with contact stiffness `k`.
    pub fn plan(t_end: f64, k: f64) -> Self {
        let planned: Vec<(Method, String)> = (Method::ALL.iter())
            .flat_map(|&m| {
                knobs(m, t_end, k, true)
                    .into_iter()
                    .map(move |(l, _)| (m, l))
            })
            .collect();
        Self {
            points: vec![None; planned.len()],
            planned,
        }
    }

    /// The points that ran, in plan order.
    pub fn done_points(&self) -> Vec<Point> {
        self.points.iter().flatten().cloned().collect()
    }

    /// (points done, points in all).
    pub fn progress(&self) -> (usize, usize) {
        (self.points.iter().flatten().count(), self.planned.len())
    }

    /// Point `index` is final; false when there is no such point.
    pub fn record(&mut self, index: usize, p: Point) -> bool {
        match self.points.get_mut(index) {
            Some(slot) => {
                *slot = Some(p);
                true
            }
            None => false,
        }
    }

    pub fn failed(&self) -> usize {
        (self.points.iter().flatten())
            .filter(|p| p.failure.is_some())
            .count()
    }
}

/// Runs the study on `study`'s model: the reference, then each planned point in turn, each
/// told to `point` by its index as it is final; a cancel (`progress`'s
/// [`Progress::go_on`]) leaves the points not started out.
pub fn run_precision(
    study: &Study,
    progress: &dyn Progress,
    point: &dyn Fn(usize, &Point),
) -> Result<PrecisionTable, String> {
    let fresh =
        Study::from_text(&study.text, &study.path, &study.base).map_err(|e| e.to_string())?;
    let bench = Bench { study: fresh };
    let scene = bench.study.scene(&[]).map_err(|e| e.to_string())?;
    crate::run::check_memory(&scene).map_err(|e| e.to_string())?;
    let (t_end, k) = (scene.settings.t_end, scene.settings.contact_stiffness);
    let mut table = PrecisionTable::plan(t_end, k);
    let reference = bench
        .reference(REFERENCE_RTOL)
        .map_err(|e| format!("the event-driven reference: {e}"))?;
    let overrides: Vec<(Method, Vec<String>)> = (Method::ALL.iter())
        .flat_map(|&m| {
            knobs(m, t_end, k, true)
                .into_iter()
                .map(move |(_, o)| (m, o))
        })
        .collect();
    for (i, (m, ov)) in overrides.iter().enumerate() {
        if !progress.go_on() {
            break;
        }
        let p = bench.measure(&reference, *m, &table.planned[i].1, ov);
        point(i, &p);
        table.record(i, p);
    }
    Ok(table)
}

/// Writes the table's rows (the header first), `num` formatting the numbers.
pub(crate) fn write_rows(
    w: &mut csv::Writer<Vec<u8>>,
    t: &PrecisionTable,
    num: &mut dyn FnMut(f64) -> String,
) -> Result<(), csv::Error> {
    w.write_record(HEADER)?;
    for ((m, knob), p) in t.planned.iter().zip(&t.points) {
        let nums = p.as_ref().map_or([f64::NAN; 4], |p| {
            [p.cpu_s, p.peak_error, p.rms_error, p.impact_time_error]
        });
        let mut rec = vec!["precision".to_string(), m.name().into(), knob.clone()];
        rec.extend(nums.map(&mut *num));
        rec.push(p.as_ref().map_or(0, |p| p.steps).to_string());
        rec.push(p.as_ref().map_or("not run".into(), status_text));
        w.write_record(rec)?;
    }
    Ok(())
}

/// The table of the rows after the header ((line, record) pairs); Err: (line, reason).
pub(crate) fn read_rows(
    body: &[(u64, csv::StringRecord)],
) -> Result<PrecisionTable, (u64, String)> {
    let mut t = PrecisionTable {
        planned: Vec::new(),
        points: Vec::new(),
    };
    for (line, rec) in body {
        let bad = |why: String| (*line, why);
        if &rec[0] != "precision" {
            return Err(bad(format!("study: `{}` is not precision", &rec[0])));
        }
        let method = Method::parse(&rec[1])
            .ok_or_else(|| bad(format!("method: `{}` is not a method", &rec[1])))?;
        let num = |i: usize| {
            (rec[i].parse::<f64>())
                .map_err(|_| bad(format!("{}: `{}` is not a number", HEADER[i], &rec[i])))
        };
        let steps: usize =
            (rec[7].parse()).map_err(|_| bad(format!("steps: `{}` is not a count", &rec[7])))?;
        let point = match &rec[8] {
            "not run" => None,
            status => Some(Point {
                method,
                knob: rec[2].to_string(),
                cpu_s: num(3)?,
                peak_error: num(4)?,
                rms_error: num(5)?,
                impact_time_error: num(6)?,
                steps,
                failure: (status != "ok").then(|| failure_of(status)),
            }),
        };
        t.planned.push((method, rec[2].to_string()));
        t.points.push(point);
    }
    Ok(t)
}
