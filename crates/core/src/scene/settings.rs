//! Solver settings of one run.

use crate::lemke::LemkeOptions;
use crate::methods::Method;

/// Solver settings of one run (`[solver]` of a model file). Units are the model's (`units`; the
/// defaults below are SI-kN's: t, kN, m, s, converted by `model::solver::settings`). Each field says which method reads it: E = event-driven, M = Moreau–Jean,
/// P = penalty (Newmark), X = penalty-explicit; the defaults are those of [`Settings::default`].
#[derive(Clone, Debug)]
pub struct Settings {
    /// The integration method (all).
    pub method: Method,
    /// Fixed step h, s (M, P, X; default 1e-3; a model without `solver.step` gets
    /// `model::limits::chosen_step`).
    pub step: f64,
    /// How the step was chosen when the model set none (said by the front ends).
    pub step_chosen: Option<String>,
    /// Moreau–Jean without a positive gap and without `max_penetration`: the penetration is
    /// judged against this fraction of the run's largest translation.
    pub max_penetration_of_peak: Option<f64>,
    /// θ of the Moreau–Jean θ-method for the smooth forces, in [0.5, 1] (M; 0.5).
    pub theta: f64,
    /// Penalty contact stiffness, normal and tangential stick spring, force/length (P, X; 1e6).
    pub contact_stiffness: f64,
    /// End of the run, s (all; 1; a model file with records and no `t_end`: the end of the
    /// longest record + 5 s, `model::FREE_VIBRATION_TAIL`).
    pub t_end: f64,
    /// Output step of the time history, s; event instants are always added (all; 0.01).
    pub output_dt: f64,
    /// A finished run whose energy balance closes worse than this (relative to the energy
    /// scale) fails as inaccurate, its output kept (all; 1e-3; `simulate::judge`).
    pub max_closure: f64,
    /// A finished run with a corner deeper than this in its face fails as inaccurate, length
    /// (E, M; not the penalty methods, whose gap elements compress by design; 1e-6).
    pub max_penetration: f64,
    /// Relative tolerance of the DP5 error control (E; 1e-8).
    pub rtol: f64,
    /// Absolute tolerance of the DP5 error control, in the units of each state component
    /// (E; 1e-10).
    pub atol: f64,
    /// Largest step, s; 0 = none (E; 0).
    pub h_max: f64,
    /// Event location tolerance on time, s (E; 1e-13).
    pub event_time_tol: f64,
    /// |g_N| below this is a closed contact, length (E; 1e-9).
    pub gap_tol: f64,
    /// |ġ| below this is zero: no impact, stick, length/s (E; 1e-9).
    pub velocity_tol: f64,
    /// Accumulation rule: an impact slower than `zeno_velocity` in a sequence of shrinking
    /// flights closes the contact, ε → 0 (E; on).
    pub accumulation_rule: bool,
    /// Impact speed below which the accumulation rule closes a contact, length/s (E; 1e-6).
    pub zeno_velocity: f64,
    /// Zeno guard: 16 impacts in a row of one contact each closer than this to the previous
    /// one stop the run (without the accumulation rule); with the rule, such an impact closes
    /// the contact; s (E; 1e-6).
    pub min_event_spacing: f64,
    /// Largest number of logged events (E; 200 000; a model file without it gets 50 000 per
    /// second of `t_end` within 200 000 … 5·10⁶, `model::limits::event_limit`).
    pub max_events: usize,
    /// Largest number of steps, accepted and rejected (E, M, P, X; 5 000 000; a model file without it gets
    /// 200 000 per second of `t_end` within 10⁶ … 5·10⁷, `model::limits::step_limit`).
    pub max_steps: usize,
    /// Never step over the sample instants of recorded support motions (E; off).
    pub stop_at_samples: bool,
    /// Hysteretic branch events that follow the first event located in a step by at most this
    /// are applied together at the last of them; 0 applies each at its own instant; s (E; 0).
    pub branch_window: f64,
    /// Keep every output sample; off keeps only the running summary (sweeps) (all; on).
    pub keep_history: bool,
    /// While every contact is open, integrate each island (bodies joined by elements) on its
    /// own steps between output instants, the open contacts between islands watched on their
    /// dense outputs; each island is then held to rtol on its own, less closely than the
    /// whole scene holds it (E; off; `event_driven::islands`).
    pub islands: bool,
    /// Lemke's pivoting options of the impact, contact and Moreau–Jean LCPs (E, M).
    pub lemke: LemkeOptions,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            method: Method::Event,
            step: 1e-3,
            step_chosen: None,
            max_penetration_of_peak: None,
            theta: 0.5,
            contact_stiffness: 1e6,
            t_end: 1.0,
            output_dt: 0.01,
            max_closure: 1e-3,
            max_penetration: 1e-6,
            rtol: 1e-8,
            atol: 1e-10,
            h_max: 0.0,
            event_time_tol: 1e-13,
            gap_tol: 1e-9,
            velocity_tol: 1e-9,
            accumulation_rule: true,
            zeno_velocity: 1e-6,
            min_event_spacing: 1e-6,
            max_events: 200_000,
            max_steps: 5_000_000,
            stop_at_samples: false,
            branch_window: 0.0,
            keep_history: true,
            islands: false,
            // the Moreau–Jean Delassus Wᵀ Ŵ⁻¹ W of light abutments on stiff actuators is badly
            // scaled: accept solutions whose relative residual is below 1e-7
            lemke: LemkeOptions {
                check_tolerance: 1e-7,
                ..LemkeOptions::default()
            },
        }
    }
}
