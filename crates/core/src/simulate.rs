//! Dispatch of a scene to the method its settings name.

use crate::methods::Method;
use crate::output::RunOutput;
use crate::run::{Observer, Run, SolverError, Stop};
use crate::scene::Scene;
use crate::timestepping::{integrate_moreau, integrate_penalty};

/// Run a scene with the method its settings name: the output of a finished run, else the
/// reason it stopped.
pub fn simulate(scene: &Scene, observer: &mut dyn Observer) -> Result<RunOutput, SolverError> {
    integrate(scene, observer).into_result()
}

/// Run a scene with the method its settings name, keeping what was computed before a cancel
/// or a failure; a run that finishes outside its accuracy bounds fails ([`judge`]).
pub fn integrate(scene: &Scene, observer: &mut dyn Observer) -> Run {
    judge(scene, integrate_unjudged(scene, observer))
}

/// [`integrate`] without the accuracy bounds: for studies that measure the error themselves
/// (work–precision, stability maps), where an inaccurate run is a data point.
pub fn integrate_unjudged(scene: &Scene, observer: &mut dyn Observer) -> Run {
    match scene.settings.method {
        Method::Event => crate::event_driven::integrate(scene, observer),
        Method::Moreau => integrate_moreau(scene, observer),
        Method::Penalty => integrate_penalty(scene, false, observer),
        Method::PenaltyExplicit => integrate_penalty(scene, true, observer),
    }
}

/// The order in h of a method's energy closure: Moreau–Jean and the explicit penalty scheme 1
/// (an impact's work at the step's velocities, a gap element switching inside a step), Newmark 2
/// (the event-driven closure follows its tolerance: order 1 in rtol).
fn closure_order(m: Method) -> f64 {
    match m {
        Method::Penalty => 2.0,
        Method::Event | Method::Moreau | Method::PenaltyExplicit => 1.0,
    }
}

/// A setting that would bring `value` under `limit` for an error of order `order` in the
/// method's knob, and its estimated cost from this run's `wall` time; or raising the bound.
fn remedy(st: &crate::scene::Settings, value: f64, limit: f64, order: f64, wall: f64) -> String {
    if !(value.is_finite() && value > 0.0 && limit > 0.0) {
        return format!("raise solver.{} or check the model", "max_closure");
    }
    // a margin of 2 on the error
    let factor = (value / limit * 2.0).powf(1.0 / order);
    match st.method {
        Method::Event => {
            let rtol = st.rtol / (value / limit * 2.0);
            // DP5: steps grow as rtol^(−1/5)
            let cost = wall * (st.rtol / rtol).powf(0.2);
            format!("solver.rtol = {rtol:.1e} would meet it, ≈ {cost:.2} s; or raise the bound")
        }
        m => {
            let h = st.step / factor;
            let cost = wall * factor;
            format!(
                "{} at solver.step = {:.3e} s: solver.step = {h:.2e} s would meet it, ≈ {cost:.1} s; or raise the bound",
                m.name(),
                st.step
            )
        }
    }
}

/// The penetration a finished run may show: `solver.max_penetration`, or for Moreau–Jean
/// without a positive gap the fraction `max_penetration_of_peak` of the run's largest
/// translation (`model::limits::method_bounds`).
pub fn penetration_limit(st: &crate::scene::Settings, s: &crate::output::Summary) -> f64 {
    match st.max_penetration_of_peak {
        Some(f) => {
            let largest = (s.peaks.iter())
                .filter(|p| p.name.ends_with(".x") || p.name.ends_with(".y"))
                .map(|p| p.max_abs)
                .fold(0.0, f64::max);
            (f * largest).max(st.max_penetration)
        }
        None => st.max_penetration,
    }
}

/// A finished run whose energy balance closes worse than `solver.max_closure` (relative to the
/// energy scale), or whose corners went deeper than `solver.max_penetration` into their faces,
/// is a failure [`SolverError::Inaccurate`] (its output kept). The penalty methods are not
/// judged on penetration: the gap elements' compression is their contact law. A finished run
/// whose energies or peaks overflowed is [`SolverError::NonFinite`].
pub fn judge(scene: &Scene, mut run: Run) -> Run {
    if !matches!(run.stop, Stop::Finished) {
        return run;
    }
    let st = &scene.settings;
    let s = &run.output.summary;
    let t = run
        .output
        .samples
        .last()
        .map_or(st.t_end, |x| x.t)
        .max(s.t_end);
    // an energy or a peak that overflowed (a scheme blown up under a record of 1e300 g)
    let mut peaks = (s.peaks.iter()).flat_map(|p| [p.max_abs, p.residual, p.max_abs_velocity]);
    let finite = s.energy_final.is_finite()
        && peaks.all(f64::is_finite)
        && s.max_penetration.is_finite()
        && s.energy_closure_abs.is_finite();
    if !finite {
        run.stop = Stop::Failed(SolverError::NonFinite { t });
        return run;
    }
    let compliant = st.method.compliant_contact();
    let wall = run.output.stats.wall_time;
    let closure = s.energy_closure_rel;
    let mut bounds = Vec::new();
    if closure.is_nan() || closure > st.max_closure {
        let remedy = remedy(st, closure, st.max_closure, closure_order(st.method), wall);
        bounds.push(crate::run::Bound {
            what: "energy closure",
            value: closure,
            setting: "max_closure",
            limit: st.max_closure,
            remedy,
        });
    }
    let max_penetration = penetration_limit(st, s);
    if !compliant && s.max_penetration > max_penetration {
        let p = s.max_penetration;
        // Moreau–Jean's penetration is O(h ġ_N); the event-driven one is the gap tolerance's
        let remedy = remedy(st, p, max_penetration, 1.0, wall);
        bounds.push(crate::run::Bound {
            what: "penetration",
            value: p,
            setting: "max_penetration",
            limit: max_penetration,
            remedy,
        });
    }
    if !bounds.is_empty() {
        run.stop = Stop::Failed(SolverError::Inaccurate { t, bounds });
    }
    run
}

/// Refinements of a step the method chose itself ([`refined`]) before a run is reported
/// outside its bounds.
pub const MAX_REFINEMENTS: usize = 3;

/// A fixed-step run whose step the method chose (no `solver.step` in the model) and that
/// finished outside its accuracy bounds: the scene with the step the judge's estimate says
/// would meet them all (the smallest asked for, by the method's order), to run again; None
/// otherwise.
pub fn refined(scene: &Scene, run: &Run) -> Option<Scene> {
    let st = &scene.settings;
    let chosen = st.step_chosen.as_ref()?;
    let Stop::Failed(SolverError::Inaccurate { bounds, .. }) = &run.stop else {
        return None;
    };
    let factor = (bounds.iter())
        .map(|b| {
            let order = if b.what == "penetration" {
                1.0
            } else {
                closure_order(st.method)
            };
            (b.value / b.limit * 2.0).powf(1.0 / order)
        })
        .filter(|f| f.is_finite() && *f > 1.0)
        .fold(1.0, f64::max);
    if factor <= 1.0 {
        return None;
    }
    let n = (st.t_end / (st.step / factor)).ceil();
    if n > st.max_steps as f64 {
        return None;
    }
    let mut next = scene.clone();
    let h = st.t_end / n;
    next.settings.step = h;
    let first = chosen.split(" (refined").next().unwrap_or(chosen);
    next.settings.step_chosen = Some(format!(
        "{first} (refined to {h:.4e} s: {})",
        crate::run::Bound::list(bounds)
            .split(" (")
            .next()
            .unwrap_or_default()
    ));
    Some(next)
}
