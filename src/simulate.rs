//! Dispatch of a scene to the method its settings name.

use crate::methods::Method;
use crate::output::RunOutput;
use crate::run::{Observer, Run, SolverError};
use crate::scene::Scene;
use crate::timestepping::{integrate_moreau, integrate_penalty};

/// Run a scene with the method its settings name: the output of a finished run, else the
/// reason it stopped.
pub fn simulate(scene: &Scene, observer: &mut dyn Observer) -> Result<RunOutput, SolverError> {
    integrate(scene, observer).into_result()
}

/// Run a scene with the method its settings name, keeping what was computed before a cancel
/// or a failure.
pub fn integrate(scene: &Scene, observer: &mut dyn Observer) -> Run {
    match scene.settings.method {
        Method::Event => crate::event_driven::integrate(scene, observer),
        Method::Moreau => integrate_moreau(scene, observer),
        Method::Penalty => integrate_penalty(scene, false, observer),
        Method::PenaltyExplicit => integrate_penalty(scene, true, observer),
    }
}
