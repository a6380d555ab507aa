//! Commands of the `deckspin` binary kept apart from `main.rs`.

pub mod adequacy;
pub mod args;
pub mod bench;
pub mod exit;
pub mod fragility;
pub mod inspect;
pub mod jobs;
pub mod merge;
pub mod progress;
pub mod run;
pub mod screen;
pub mod sensitivity;
pub mod sequence;
pub mod show;
pub mod signals;
pub mod stdout;
pub mod stress;
pub mod study;
pub mod suite;
pub mod sweep;
pub mod tables;

/// What a command returns: its errors are printed by `main` with their exit code
/// ([`exit::exit_code`]).
pub type CliResult = Result<(), Box<dyn std::error::Error>>;

/// A time argument: a finite number of seconds, not negative (`--at inf` printed t = 0).
pub fn finite_time(s: &str) -> Result<f64, String> {
    let t: f64 = s
        .trim()
        .parse()
        .map_err(|e| format!("{s:?} is no number of seconds: {e}"))?;
    if t.is_finite() && t >= 0.0 {
        Ok(t)
    } else {
        Err(format!(
            "{s:?}: a time must be a finite number of seconds ≥ 0"
        ))
    }
}
