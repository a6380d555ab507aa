//! The `[solver]` table of every model file and its settings.

use super::check::{Check, ModelError};
use crate::methods::Method;
use crate::scene::Settings;
use serde::Deserialize;

/// Solver settings as written in a model file (`[solver]`); absent keys take defaults.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// `solver.method`.
    pub method: Option<String>,
    /// `solver.t_end`.
    pub t_end: Option<f64>,
    /// `solver.output_dt`.
    pub output_dt: Option<f64>,
    /// `solver.rtol`.
    pub rtol: Option<f64>,
    /// `solver.atol`.
    pub atol: Option<f64>,
    /// `solver.h_max`.
    pub h_max: Option<f64>,
    /// `solver.event_time_tol`.
    pub event_time_tol: Option<f64>,
    /// `solver.gap_tol`.
    pub gap_tol: Option<f64>,
    /// `solver.velocity_tol`.
    pub velocity_tol: Option<f64>,
    /// `solver.accumulation_rule`.
    pub accumulation_rule: Option<bool>,
    /// `solver.zeno_velocity`.
    pub zeno_velocity: Option<f64>,
    /// `solver.min_event_spacing`.
    pub min_event_spacing: Option<f64>,
    /// `solver.max_events`.
    pub max_events: Option<usize>,
    /// `solver.max_steps`.
    pub max_steps: Option<usize>,
    /// `solver.stop_at_samples`.
    pub stop_at_samples: Option<bool>,
    /// Islands on their own steps while every contact is open.
    pub islands: Option<bool>,
    /// Window (s) within which hysteretic branch events are applied together.
    pub branch_window: Option<f64>,
    /// `solver.lemke_max_pivots`.
    pub lemke_max_pivots: Option<usize>,
    /// Fixed step of time-stepping / penalty methods.
    pub step: Option<f64>,
    /// Contact stiffness of the penalty method, N/m.
    pub contact_stiffness: Option<f64>,
    /// θ of the Moreau–Jean scheme (0.5–1).
    pub theta: Option<f64>,
    /// `solver.max_closure`.
    pub max_closure: Option<f64>,
    /// `solver.max_penetration`.
    pub max_penetration: Option<f64>,
}

/// Settings from `[solver]`.
pub fn settings(s: &SolverSpec, ck: &Check) -> Result<Settings, ModelError> {
    let mut out = Settings::default();
    // the defaults with a length in them are SI-kN's, in the model's units
    let (m, kn) = (ck.units.per_metre(), ck.units.per_kilonewton());
    out.gap_tol *= m;
    out.velocity_tol *= m;
    out.zeno_velocity *= m;
    out.max_penetration *= m;
    out.contact_stiffness *= kn / m;
    macro_rules! pos {
        ($f:ident) => {
            if let Some(x) = s.$f {
                out.$f = ck.positive(concat!("solver.", stringify!($f)), x)?;
            }
        };
    }
    pos!(t_end);
    pos!(output_dt);
    pos!(rtol);
    pos!(atol);
    pos!(event_time_tol);
    pos!(gap_tol);
    pos!(velocity_tol);
    pos!(zeno_velocity);
    pos!(min_event_spacing);
    pos!(max_closure);
    pos!(max_penetration);
    if let Some(x) = s.h_max {
        out.h_max = ck.nonneg("solver.h_max", x)?;
    }
    if let Some(x) = s.branch_window {
        out.branch_window = ck.nonneg("solver.branch_window", x)?;
    }
    if let Some(b) = s.accumulation_rule {
        out.accumulation_rule = b;
    }
    if let Some(b) = s.stop_at_samples {
        out.stop_at_samples = b;
    }
    if let Some(b) = s.islands {
        out.islands = b;
    }
    if let Some(n) = s.max_events {
        out.max_events = n;
    }
    if let Some(n) = s.max_steps {
        out.max_steps = n;
    }
    if let Some(n) = s.lemke_max_pivots {
        out.lemke.max_pivots = n;
    }
    if let Some(x) = s.step {
        out.step = ck.positive("solver.step", x)?;
    }
    if let Some(x) = s.contact_stiffness {
        out.contact_stiffness = ck.positive("solver.contact_stiffness", x)?;
    }
    if let Some(x) = s.theta {
        ck.finite("solver.theta", x)?;
        if !(0.5..=1.0).contains(&x) {
            return Err(ck.err("solver.theta", format!("must be in [0.5, 1], got {x}")));
        }
        out.theta = x;
    }
    if let Some(m) = &s.method {
        out.method = Method::parse(m).ok_or_else(|| {
            ck.err(
                "solver.method",
                format!("unknown method '{m}' ({})", Method::names(", ")),
            )
        })?;
    }
    Ok(out)
}
