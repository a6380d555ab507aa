//! One fuzz input run and classified: refused at load, refused by the output budget,
//! finished (with its checks), failed with a typed error, cancelled by the watchdog, panicked.

use deckspin::output::{EventRecord, Sample};
use deckspin::run::{OutputBudget, Stop, check_output};
use std::panic::AssertUnwindSafe;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Simulated time each input runs at most (longer `t_end` are cut to it).
pub const T_END_MAX: f64 = 4.0;
/// Rows and bytes of history an input may ask for (the output is streamed, not kept).
pub const BUDGET: OutputBudget = OutputBudget {
    max_rows: 2e6,
    max_bytes: 2e9,
};
/// Finding categories the CI run asserts to be absent.
pub const MUST_BE_ZERO: &[&str] = &[
    "panic",
    "hang",
    "crash",
    "non-finite",
    "closure",
    "penetration",
];

/// How one input ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// The model file (or its record) was refused at load, with the error's kind.
    Refused(String),
    /// Loaded, but its output estimate is above [`BUDGET`] (`check_output`).
    OverBudget,
    /// Reached its end: the method, energy closure, penetration, and whether a value of a
    /// sample or of the summary was NaN or infinite.
    Finished {
        method: String,
        closure: f64,
        penetration: f64,
        non_finite: bool,
        /// The judge's bounds for this scene and run (`solver.max_closure`,
        /// `simulate::penetration_limit`).
        max_closure: f64,
        max_penetration: f64,
    },
    /// Stopped with a typed `SolverError` (its kind).
    Failed(String),
    /// Cancelled by the watchdog: its simulated time stood still for `limit` of CPU time, a
    /// hang (an input that stops making progress, whatever the machine's load).
    Hang(String),
    /// Cancelled by the watchdog past [`SLOW`] × `limit` of CPU time while its simulated time
    /// still advanced: slow, not hung (counted, not asserted; its step count is bounded by
    /// `solver.max_steps`, so it would end).
    Slow(String),
    /// A panic, with its message.
    Panic(String),
}

impl Outcome {
    /// The finding categories this outcome falls in (none for an acceptable one).
    pub fn findings(&self) -> Vec<&'static str> {
        match self {
            Outcome::Hang(_) => vec!["hang"],
            Outcome::Slow(_) => vec!["slow"],
            Outcome::Panic(_) => vec!["panic"],
            Outcome::Finished {
                method,
                closure,
                penetration,
                non_finite,
                max_closure,
                max_penetration,
            } => {
                let mut f = Vec::new();
                if *non_finite || !closure.is_finite() || !penetration.is_finite() {
                    f.push("non-finite");
                }
                // every method's finished run is judged (`simulate::judge`): a closure or a
                // penetration above the scene's bounds is a finding (nothing escapes the judge);
                // the penalty methods' penetration is their gap elements' compression, counted
                // apart
                if *closure > *max_closure {
                    f.push("closure");
                }
                if *penetration > *max_penetration {
                    let penalty = method.starts_with("Penalty");
                    f.push(if penalty {
                        "penetration:penalty"
                    } else {
                        "penetration"
                    });
                }
                f
            }
            _ => Vec::new(),
        }
    }

    /// One word for the tally: `refused:Invalid`, `failed:TooManySteps`, `finished`, …
    pub fn class(&self) -> String {
        match self {
            Outcome::Refused(k) => format!("refused:{k}"),
            Outcome::OverBudget => "refused:budget".into(),
            Outcome::Finished { method, .. } => format!("finished:{method}"),
            Outcome::Failed(k) => format!("failed:{k}"),
            Outcome::Hang(_) => "hang".into(),
            Outcome::Slow(_) => "slow".into(),
            Outcome::Panic(_) => "panic".into(),
        }
    }
}

/// How many times `limit` of CPU time a run whose simulated time advances may take.
pub const SLOW: f64 = 6.0;

/// Cancels the run once its thread has used `limit` of CPU time without its simulated time
/// advancing (a hang), or [`SLOW`] × `limit` in all (slow); time waiting for a core on a busy
/// machine does not count. Notes any non-finite value of the samples it is handed.
struct Watchdog {
    cpu0: f64,
    limit: Duration,
    /// The simulated time last seen and the CPU time when it last advanced.
    progress: (f64, f64),
    /// Cancelled while the simulated time advanced.
    slow: bool,
    non_finite: bool,
}

fn sample_finite(s: &Sample) -> bool {
    s.t.is_finite()
        && s.q.iter().chain(&s.v).all(|x| x.is_finite())
        && s.contacts.iter().all(|c| {
            [
                c.gap,
                c.gap_rate,
                c.slip_rate,
                c.normal_force,
                c.tangential_force,
            ]
            .iter()
            .all(|x| x.is_finite())
        })
        && s.elements
            .iter()
            .all(|(d, f)| d.is_finite() && f.is_finite())
        && s.energy.is_finite()
}

impl deckspin::Observer for Watchdog {
    fn batch(&mut self, samples: &[Sample], _: &[EventRecord], t: f64) -> bool {
        self.non_finite |= !samples.iter().all(sample_finite);
        let now = deckspin::clock::thread_cpu_seconds();
        if t > self.progress.0 {
            self.progress = (t, now);
        }
        let limit = self.limit.as_secs_f64();
        self.slow = now - self.cpu0 >= SLOW * limit;
        !self.slow && now - self.progress.1 < limit
    }

    fn keeps_samples(&self) -> bool {
        true
    }
}

/// The variant name of a `Debug` text (`Invalid { … }` → `Invalid`).
fn variant(debug: &str) -> String {
    debug
        .split(|c: char| !c.is_alphanumeric())
        .next()
        .unwrap_or("?")
        .to_string()
}

/// Where each process writes the record of its inputs.
pub fn scratch() -> PathBuf {
    let d = std::env::temp_dir().join(format!("deckspin-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Loads `model` (as if at `path`, with `at2` written next to it as `rec.AT2`) and runs it.
pub fn run_input(model: &str, path: &Path, at2: Option<&str>, limit: Duration) -> Outcome {
    let path = match at2 {
        Some(a) => {
            let dir = scratch();
            std::fs::write(dir.join("rec.AT2"), a).unwrap();
            dir.join(path)
        }
        None => path.to_path_buf(),
    };
    let caught = std::panic::catch_unwind(AssertUnwindSafe(|| load_and_run(model, &path, limit)));
    caught.unwrap_or_else(|p| {
        let msg = p
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_else(|| "?".into());
        Outcome::Panic(msg)
    })
}

fn load_and_run(model: &str, path: &Path, limit: Duration) -> Outcome {
    let mut scene = match deckspin::model::load_str(model, path, &[]) {
        Ok(s) => s,
        Err(e) => return Outcome::Refused(variant(&format!("{e:?}"))),
    };
    if scene.settings.t_end > T_END_MAX {
        // the limits that scale with t_end scale down with it (a file's own stay if smaller)
        let st = &mut scene.settings;
        st.t_end = T_END_MAX;
        st.max_events = st.max_events.min(deckspin::model::event_limit(T_END_MAX));
        st.max_steps = st.max_steps.min(deckspin::model::step_limit(T_END_MAX));
    }
    if check_output(&scene, &BUDGET).is_err() {
        return Outcome::OverBudget;
    }
    let cpu0 = deckspin::clock::thread_cpu_seconds();
    let mut dog = Watchdog {
        cpu0,
        limit,
        progress: (f64::NEG_INFINITY, cpu0),
        slow: false,
        non_finite: false,
    };
    let run = deckspin::simulate::integrate(&scene, &mut dog);
    let s = &run.output.summary;
    match run.stop {
        Stop::Finished => {
            let peaks = s.peaks.iter().all(|p| {
                p.max_abs.is_finite() && p.residual.is_finite() && p.max_abs_velocity.is_finite()
            });
            let rest = run.output.samples.iter().all(sample_finite);
            Outcome::Finished {
                method: format!("{:?}", scene.settings.method),
                closure: s.energy_closure_rel,
                penetration: s.max_penetration,
                max_closure: scene.settings.max_closure,
                max_penetration: deckspin::simulate::penetration_limit(&scene.settings, s),
                non_finite: dog.non_finite || !rest || !peaks || !s.energy_final.is_finite(),
            }
        }
        Stop::Cancelled { t } => {
            let why = format!(
                "cancelled at t = {t:.6e} s of {} s after {:.1} s of CPU",
                scene.settings.t_end,
                deckspin::clock::thread_cpu_seconds() - dog.cpu0
            );
            if dog.slow { Outcome::Slow(why) } else { Outcome::Hang(why) }
        }
        Stop::Failed(e) => Outcome::Failed(e.kind().to_string()),
    }
}
