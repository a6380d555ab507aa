//! The identity of a compiled scene, for runs that may share their work: sweep rows of the
//! same scene run once (`studies`), and friction variants share their motion up to the first
//! contact event (`event_driven::FrictionFork`).

use super::{Motion, Scene};
use crate::excitation::GroundMotion;
use std::sync::Arc;

/// What a run of a scene depends on: every field but the title as exact text (`{:?}` writes
/// each f64 as its shortest round-trip text: equal text, equal bits), the recorded support
/// motions apart (compared by content, most often the same shared motion).
pub struct SceneKey {
    /// Every field but the title and the recorded motions, as text.
    pub text: String,
    /// The recorded support motions.
    pub motions: Vec<Arc<GroundMotion>>,
}

impl SceneKey {
    /// The key of `scene`.
    pub fn of(scene: &Scene) -> Self {
        Self::with(scene, false)
    }

    /// [`SceneKey::of`] with every contact's friction coefficient left out: scenes with equal
    /// such keys differ at most in μ (the friction fork's runs).
    pub(crate) fn without_friction(scene: &Scene) -> Self {
        Self::with(scene, true)
    }

    fn with(scene: &Scene, no_mu: bool) -> Self {
        // every field named: a field added to `Scene` must be added here
        let Scene {
            title: _,
            units: _,
            bridge: _,
            seats,
            bodies,
            contacts,
            springs,
            hysteretic,
            supports,
            mass_damping,
            loads,
            mass,
            dof_names,
            q0,
            v0,
            settings,
        } = scene;
        let mut motions = Vec::new();
        let supports: Vec<String> = (supports.iter())
            .map(|s| {
                let motion = match &s.motion {
                    Motion::Record(g) => {
                        motions.push(g.clone());
                        format!("record {}", motions.len() - 1)
                    }
                    m => format!("{m:?}"),
                };
                format!("{:?} {:?} {motion}", s.name, s.factor)
            })
            .collect();
        let contacts = if no_mu {
            let mut c = contacts.clone();
            for x in &mut c {
                x.law.mu = 0.0;
            }
            format!("{c:?}")
        } else {
            format!("{contacts:?}")
        };
        let text = format!(
            "{seats:?}\n{bodies:?}\n{contacts}\n{springs:?}\n{hysteretic:?}\n{supports:?}\n\
             {mass_damping:?}\n{loads:?}\n{mass:?}\n{dof_names:?}\n{q0:?}\n{v0:?}\n{settings:?}"
        );
        Self { text, motions }
    }

    /// Keys of the same scene: equal text, and the same recorded motions in order.
    pub fn same(&self, other: &SceneKey) -> bool {
        self.text == other.text && self.same_motions(other)
    }

    /// The same recorded motions, in order (the same shared motion, or equal ones).
    pub(crate) fn same_motions(&self, other: &SceneKey) -> bool {
        self.motions.len() == other.motions.len()
            && (self.motions.iter().zip(&other.motions)).all(|(a, b)| Arc::ptr_eq(a, b) || a == b)
    }
}
