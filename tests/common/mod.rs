#![allow(dead_code)]
use deckspin::output::{EventKind, RunOutput, SampleKind};
use std::path::{Path, PathBuf};

#[cfg(feature = "workbench")]
pub mod tui;

/// The CPU seconds (user + system) a child process has used, from `/proc/PID/stat`; None
/// where that cannot be read. Watchdogs judge a hang by it, never by the wall clock: a child
/// on a busy machine is slow, not stuck.
pub fn child_cpu_seconds(pid: u32) -> Option<f64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    // the fields after the command name, which may hold spaces, in parentheses
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let (utime, stime): (f64, f64) = (f.get(11)?.parse().ok()?, f.get(12)?.parse().ok()?);
    // SAFETY: sysconf reads a constant of the system
    let tick = unsafe { libc::sysconf(libc::_SC_CLK_TCK) } as f64;
    (tick > 0.0).then(|| (utime + stime) / tick)
}

/// Watches a child for a hang: past `cpu_budget` seconds of its CPU, or no CPU gained for
/// `blocked` seconds of wall time (blocked on something, not waiting for a core).
pub struct HangWatch {
    pid: u32,
    cpu_budget: f64,
    blocked: std::time::Duration,
    last: (std::time::Instant, f64),
}

impl HangWatch {
    pub fn new(pid: u32, cpu_budget: f64, blocked_secs: u64) -> Self {
        Self {
            pid,
            cpu_budget,
            blocked: std::time::Duration::from_secs(blocked_secs),
            last: (std::time::Instant::now(), 0.0),
        }
    }

    /// Some(reason) once the child hangs.
    pub fn hangs(&mut self) -> Option<String> {
        let cpu = child_cpu_seconds(self.pid)?;
        if cpu > self.last.1 + 1e-2 {
            self.last = (std::time::Instant::now(), cpu);
        }
        if cpu > self.cpu_budget {
            return Some(format!("past {} s of CPU", self.cpu_budget));
        }
        (self.last.0.elapsed() > self.blocked)
            .then(|| format!("no CPU for {} s", self.blocked.as_secs()))
    }
}

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub fn model(rel: &str) -> PathBuf {
    root().join(rel)
}

pub fn run(rel: &str, set: &[&str]) -> RunOutput {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    let scene = deckspin::load(&model(rel), &set).unwrap_or_else(|e| panic!("{e}"));
    deckspin::run(&scene, &mut deckspin::Silent).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

pub fn run_text(text: &str, name: &str) -> Result<RunOutput, String> {
    let scene = deckspin::model::load_str(text, Path::new(name), &[]).map_err(|e| e.to_string())?;
    deckspin::run(&scene, &mut deckspin::Silent).map_err(|e| e.to_string())
}

pub fn impacts(r: &RunOutput) -> Vec<&deckspin::output::EventRecord> {
    r.events
        .iter()
        .filter(|e| e.kind == EventKind::Impact)
        .collect()
}

/// Post-event sample at time t.
pub fn post_event(r: &RunOutput, t: f64) -> &deckspin::output::Sample {
    r.samples
        .iter()
        .find(|s| s.kind == SampleKind::PostEvent && (s.t - t).abs() <= 1e-12 * t.abs().max(1.0))
        .expect("post-event sample")
}

pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

#[track_caller]
pub fn assert_rel(a: f64, b: f64, tol: f64, what: &str) {
    let e = rel(a, b);
    if std::env::var("ORACLE_REPORT").is_ok() {
        eprintln!("ORACLE {what}: {e:.2e}");
    }
    assert!(
        e <= tol,
        "{what}: got {a:.15e}, expected {b:.15e}, rel err {e:.3e} > {tol:.1e}"
    );
}
