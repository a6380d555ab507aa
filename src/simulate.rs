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
    let hint = match st.method {
        Method::Event => "tighten solver.rtol and solver.atol".to_string(),
        m => format!(
            "{} at solver.step = {:e} s: a smaller step",
            m.name(),
            st.step
        ),
    };
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
    let compliant = matches!(st.method, Method::Penalty | Method::PenaltyExplicit);
    let closure = s.energy_closure_rel;
    let error = if closure.is_nan() || closure > st.max_closure {
        Some(("energy closure", closure, "max_closure", st.max_closure))
    } else if !compliant && s.max_penetration > st.max_penetration {
        let p = s.max_penetration;
        Some(("penetration", p, "max_penetration", st.max_penetration))
    } else {
        None
    };
    if let Some((what, value, setting, limit)) = error {
        run.stop = Stop::Failed(SolverError::Inaccurate {
            t,
            what,
            value,
            setting,
            limit,
            hint: format!("{hint}, or raise solver.{setting}"),
        });
    }
    run
}
