#![allow(dead_code)]
use deckspin::output::{EventKind, RunOutput, SampleKind};
use std::path::{Path, PathBuf};

#[cfg(feature = "workbench")]
pub mod tui;

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
