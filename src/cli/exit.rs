//! The process's exit code of an error.

use std::process::ExitCode;

/// 2 for a job refused before it starts (its output or its number of runs above a limit),
/// else 1.
pub fn exit_code(e: &(dyn std::error::Error + 'static)) -> ExitCode {
    use deckspin::suite::SuiteError;
    if let Some(i) = e.downcast_ref::<crate::cli::signals::Interrupted>() {
        return ExitCode::from((128 + i.signal).clamp(0, 255) as u8);
    }
    if let Some(i) = e.downcast_ref::<crate::cli::jobs::JobInterrupted>() {
        return ExitCode::from((128 + i.signal).clamp(0, 255) as u8);
    }
    // a run that finished outside its accuracy bounds is told apart from a failure
    if let Some(deckspin::run::SolverError::Inaccurate { .. }) =
        e.downcast_ref::<deckspin::run::SolverError>()
    {
        return ExitCode::from(3);
    }
    let suite_too_large =
        (e.downcast_ref::<SuiteError>()).is_some_and(|s| matches!(s, SuiteError::TooLarge(_)));
    if e.is::<deckspin::run::LimitError>()
        || e.is::<deckspin::studies::SweepTooLarge>()
        || suite_too_large
    {
        ExitCode::from(2)
    } else {
        ExitCode::FAILURE
    }
}
