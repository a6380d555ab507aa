//! Friction sweeps: runs that differ only in μ share their motion up to the first contact event.

use super::driver::Integration;
use super::engine::Engine;
use super::workspace::Workspace;
use crate::dopri;
use crate::output::RunOutput;
use crate::run::{Batcher, Silent, SolverError};
use crate::scene::{ForceModel, Method, Scene, SceneKey};

/// Runs of scenes that differ only in their contacts' friction coefficients are the same motion
/// until the first contact event (μ enters nowhere else): that part is integrated once, and
/// each variant continues from there. The outputs are those of separate runs.
pub struct FrictionFork<'a> {
    shared: Integration<'a>,
    /// A contact event was reached (else the shared run is already the whole run).
    paused: bool,
    /// The shared scene's identity up to friction.
    key: SceneKey,
}

impl<'a> FrictionFork<'a> {
    /// Integrate `scene` up to its first contact event. An error here is each variant's own
    /// error: run them separately then.
    pub fn new(scene: &'a Scene) -> Result<Self, SolverError> {
        let mut shared = Integration::start(scene)?;
        let paused = shared.advance(&mut Silent, true)?;
        let key = SceneKey::without_friction(scene);
        Ok(Self {
            shared,
            paused,
            key,
        })
    }

    /// The run of `scene` from the shared part; None if `scene` differs from the shared one in
    /// more than contact friction, or is integrated by another method. The shared part counts
    /// in its wall time.
    pub fn run(&self, scene: &Scene) -> Option<Result<RunOutput, SolverError>> {
        if scene.settings.method != Method::Event
            || !self.key.same(&SceneKey::without_friction(scene))
        {
            return None;
        }
        let mut it = self.shared.fork(scene);
        if self.paused
            && let Err(e) = it.advance(&mut Silent, false)
        {
            return Some(Err(e));
        }
        Some(Ok(it.finish(&mut Silent, true)))
    }
}

impl<'a> Integration<'a> {
    /// The same run continued with `scene`, which differs from this run's only in contact
    /// friction (equal [`SceneKey::without_friction`]): a clone of the state, fresh reused storage.
    fn fork<'b>(&self, scene: &'b Scene) -> Integration<'b> {
        Integration {
            eng: self.eng.fork(scene),
            clock: self.clock.clone(),
            batcher: Batcher::new(),
            ws: dopri::Workspace::default(),
            ws_event: dopri::Workspace::default(),
        }
    }
}

impl Engine<'_> {
    /// This engine's state on `scene` (same DOFs and masses), with fresh reused storage.
    fn fork<'b>(&self, scene: &'b Scene) -> Engine<'b> {
        Engine {
            scene,
            minv: self.minv.clone(),
            n: self.n,
            forces: ForceModel::new(scene),
            state: self.state.clone(),
            ws: Workspace::new(self.n),
        }
    }
}
