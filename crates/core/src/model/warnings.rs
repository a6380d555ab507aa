//! What a model was compiled with that its file does not say: defaults taken for absent
//! tables and fields, records cut by the end of the run, steps that resolve no contact
//! dynamics. The library never prints: [`super::load_checked`] returns these with the scene
//! and the front ends show them.

use std::path::PathBuf;

/// A warning about a model that was accepted (see `docs/engine.md`, bad input).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ModelWarning {
    /// No `[solver]` table: every setting is its documented default.
    #[error(
        "{}: no [solver] table: the defaults are used (method event, t_end {t_end:.3} s, rtol 1e-8, \
         atol 1e-10, output_dt 0.01 s; docs/engine.md)",
        path.display()
    )]
    NoSolver {
        /// The model file.
        path: PathBuf,
        /// End time, s.
        t_end: f64,
    },
    /// A bridge file without a `[damping]` table: Rayleigh damping at its default.
    #[error(
        "{}: no [damping] table: Rayleigh damping of 2 % at modes 1 and 3 is used (the paper's; \
         docs/bridges.md)",
        path.display()
    )]
    NoDamping {
        /// The model file.
        path: PathBuf,
    },
    /// `solver.t_end` absent: the end of the longest record plus the free-vibration tail.
    #[error(
        "{}: solver.t_end absent: {t_end:.3} s = end of the longest record ({record_end:.3} s, \
         {field}) + {tail} s of free vibration",
        path.display()
    )]
    TEndFromRecords {
        /// The model file.
        path: PathBuf,
        /// End time, s.
        t_end: f64,
        /// The record's end, s.
        record_end: f64,
        /// The free vibration after it, s.
        tail: f64,
        /// The field's dotted path.
        field: String,
    },
    /// `solver.t_end` absent and no record to end with: the default.
    #[error("{}: solver.t_end absent: {t_end} s (the default)", path.display())]
    TEndDefault {
        /// The model file.
        path: PathBuf,
        /// End time, s.
        t_end: f64,
    },
    /// A record runs past `t_end`: its end is not applied.
    #[error(
        "{}:{line}: solver.t_end: {t_end} s ends before the record of {field} ({record_end:.3} \
         s): its last {:.3} s are not applied",
        path.display(),
        record_end - t_end
    )]
    RecordCut {
        /// The model file.
        path: PathBuf,
        /// Line in the file, from 1.
        line: usize,
        /// End time, s.
        t_end: f64,
        /// The record's end, s.
        record_end: f64,
        /// The field's dotted path.
        field: String,
    },
    /// A bridge without `[excitation]`: it starts at rest and nothing moves it.
    #[error(
        "{}: no [excitation]: the bridge starts at rest and nothing moves it (the response is \
         zero; modes and settings are still meaningful)",
        path.display()
    )]
    NoExcitation {
        /// The model file.
        path: PathBuf,
    },
    /// `[[run]]` tables present but no `excitation.run` to pick one: records unscaled.
    #[error(
        "{}: excitation.run absent: the {runs} [[run]] tables are not used, the records keep \
         their own amplitude",
        path.display()
    )]
    RunsUnused {
        /// The model file.
        path: PathBuf,
        /// The `[[run]]` tables.
        runs: usize,
    },
    /// An implicit fixed step longer than 2/ω_max of the stiffest linearised system: the
    /// fastest modes (contact, with the penalty method) are not resolved, only damped.
    #[error(
        "{}:{line}: solver.step: {step} s > 2/ω_max = {limit:.3e} s (ω_max = {omega:.4e} rad/s, \
         {what}): the {method} method stays stable but does not resolve these dynamics",
        path.display()
    )]
    StepUnresolved {
        /// The model file.
        path: PathBuf,
        /// Line in the file, from 1.
        line: usize,
        /// The step, s.
        step: f64,
        /// The limit, s.
        limit: f64,
        /// ω of the stiffest mode, rad/s.
        omega: f64,
        /// What sets it.
        what: String,
        /// The method.
        method: String,
    },
    /// An explicit step above the stability limit of the system with its contacts closed
    /// (unstable while a contact is closed), or above that of K₀ in the studies' entry
    /// ([`super::load_str_with`]), which probes where methods fail (refused elsewhere).
    #[error(
        "{}:{line}: solver.step: {step} s > 2/ω_max = {limit:.3e} s (ω_max = {omega:.4e} rad/s, \
         {what}): the central-difference scheme is unstable there",
        path.display()
    )]
    StepAboveStability {
        /// The model file.
        path: PathBuf,
        /// Line in the file, from 1.
        line: usize,
        /// The step, s.
        step: f64,
        /// The limit, s.
        limit: f64,
        /// ω of the stiffest mode, rad/s.
        omega: f64,
        /// What sets it.
        what: String,
    },
    /// A field the chosen kind of abutment does not read.
    #[error(
        "{}:{line}: {field}: not read by abutment kind = \"{kind}\" (ignored)",
        path.display()
    )]
    AbutmentUnread {
        /// The model file.
        path: PathBuf,
        /// Line in the file, from 1.
        line: usize,
        /// The field's dotted path.
        field: String,
        /// The kind chosen.
        kind: String,
    },
    /// A field the chosen kind of excitation does not read.
    #[error(
        "{}:{line}: {field}: not read by excitation kind = \"{kind}\" (ignored)",
        path.display()
    )]
    Unread {
        /// The model file.
        path: PathBuf,
        /// Line in the file, from 1.
        line: usize,
        /// The field's dotted path.
        field: String,
        /// The kind chosen.
        kind: String,
    },
    /// Tolerances too loose for error control, with `h_max` set: a fixed-step DP5 at h_max.
    #[error(
        "{}: solver.rtol = {rtol}, solver.atol = {atol}: no error control, the event-driven \
         method steps at solver.h_max = {h_max} s (a fixed-step DP5)",
        path.display()
    )]
    ErrorControlOff {
        /// The model file.
        path: PathBuf,
        /// solver.rtol.
        rtol: f64,
        /// solver.atol.
        atol: f64,
        /// solver.h_max, s.
        h_max: f64,
    },
}
