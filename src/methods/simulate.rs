//! Dispatch of a scene to the method its settings name.

use super::Method;
use crate::output::RunOutput;
use crate::run::{Observer, SolverError};
use crate::scene::Scene;
use crate::timestepping::{run_moreau, run_penalty};

/// Run a scene with the method its settings name.
pub fn simulate(scene: &Scene, observer: &mut dyn Observer) -> Result<RunOutput, SolverError> {
    match scene.settings.method {
        Method::Event => crate::event_driven::run(scene, observer),
        Method::Moreau => run_moreau(scene, observer),
        Method::Penalty => run_penalty(scene, false, observer),
        Method::PenaltyExplicit => run_penalty(scene, true, observer),
    }
}
