//! The engine of one run: the scene, the physical state carried from instant to instant, and
//! the state's kinematic readings.

use super::event_fn::EventFn;
use super::workspace::Workspace;
use crate::hysteresis::Hysteretic;
use crate::output::{ContactState, RunOutput};
use crate::run::SolverError;
use crate::scene::{ContactKinematics, ForceModel, Frame, LEDGER_TERMS, Scene, smooth_forces};
use nalgebra::DVector;
use std::sync::Arc;

/// The engine of one run: its scene, the physical [`State`] and reused storage.
pub(super) struct Engine<'a> {
    pub(super) scene: &'a Scene,
    /// Diagonal of M⁻¹.
    pub(super) minv: DVector<f64>,
    /// Number of DOFs.
    pub(super) n: usize,
    /// The scene's smooth forces, flattened.
    pub(super) forces: ForceModel,
    pub(super) state: State,
    pub(super) ws: Workspace,
}

/// Everything a run carries from one instant to the next: a fork of the run is a clone.
#[derive(Clone)]
pub(super) struct State {
    pub(super) t: f64,
    /// y = [q; q̇; ledger terms].
    pub(super) y: DVector<f64>,
    /// Hysteretic laws with their current branches.
    pub(super) laws: Vec<Hysteretic>,
    /// Open, stick or slide, per contact.
    pub(super) contacts: Vec<ContactState>,
    /// Impact energy changes (normal, tangential) accumulated: ΔT = Λᵀ(ġ⁺ + ġ⁻)/2.
    pub(super) impact_normal: f64,
    pub(super) impact_tangential: f64,
    /// Initial energy; work-free state corrections (projections) are part of the closure error.
    pub(super) e0: f64,
    pub(super) energy_scale: f64,
    pub(super) out: RunOutput,
    /// The last three impact instants of each contact (accumulation rule).
    pub(super) last_impacts: Vec<Vec<f64>>,
    /// (last impact, impacts in a row closer than `min_event_spacing`) per contact.
    pub(super) burst: Vec<(f64, usize)>,
    /// Largest generalized force seen (scale of the force thresholds).
    pub(super) force_scale: f64,
    /// Event function values at the end of the last step (reused at the next step's start).
    /// (with their rates: ġ_N of the gap functions, ±ė of the branch bounds, NaN for the others).
    pub(super) last_event_values: Option<(f64, Vec<f64>, Vec<f64>)>,
    /// Event function values computed by the last `arm` (for `due_now` at the same instant).
    pub(super) arm_values: Vec<f64>,
    /// The events of the instant `locate_event` returned.
    pub(super) cluster: Vec<EventFn>,
    /// Counts the event-function lists made (a list's identity for cached per-list data).
    pub(super) fns_generation: u64,
}

impl<'a> Engine<'a> {
    /// The initial state of `scene`: laws directed by the initial deformation rates, every
    /// contact open; an initial penetration is refused.
    pub(super) fn new(scene: &'a Scene) -> Result<Self, SolverError> {
        let n = scene.ndof();
        let nc = scene.contacts.len();
        let st = &scene.settings;
        let mut y = DVector::zeros(2 * n + LEDGER_TERMS);
        y.rows_mut(0, n).copy_from(&scene.q0);
        y.rows_mut(n, n).copy_from(&scene.v0);
        let mut eng = Engine {
            scene,
            minv: scene.mass.map(|m| 1.0 / m),
            n,
            forces: ForceModel::new(scene),
            state: State {
                t: 0.0,
                y,
                laws: Vec::new(),
                contacts: vec![ContactState::Open; nc],
                impact_normal: 0.0,
                impact_tangential: 0.0,
                e0: 0.0,
                energy_scale: 0.0,
                out: RunOutput::new(scene),
                last_impacts: vec![Vec::new(); nc],
                burst: vec![(f64::NEG_INFINITY, 0); nc],
                force_scale: 0.0,
                last_event_values: None,
                arm_values: Vec::new(),
                cluster: Vec::new(),
                fns_generation: 0,
            },
            ws: Workspace::new(n),
        };
        let (q, v) = (eng.q(), eng.v());
        let fr = scene.frame(0.0, &q, &v);
        // initial hysteretic directions from the initial deformation rates
        let mut laws: Vec<Hysteretic> = scene.hysteretic.iter().map(|h| h.law.clone()).collect();
        for (j, el) in scene.hysteretic.iter().enumerate() {
            let (e, ed, ..) = scene.deformation(&fr, &el.attachment, el.support);
            laws[j].set_direction(e, if ed < 0.0 { -1.0 } else { 1.0 });
        }
        eng.state.laws = laws;
        for c in &scene.contacts {
            let k = scene.contact_kinematics(&fr, c);
            if k.gap < -st.gap_tol {
                return Err(SolverError::InitialPenetration {
                    contact: c.name.clone(),
                    gap: k.gap,
                });
            }
        }
        eng.state.e0 = scene.kinetic_energy(&v) + scene.spring_energy(0.0, &q, &v);
        if !eng.state.e0.is_finite() {
            return Err(SolverError::NonFinite { t: 0.0 });
        }
        let mut h = DVector::zeros(n);
        smooth_forces(
            scene,
            Some(&eng.state.laws),
            0.0,
            &q,
            &v,
            &mut h,
            &mut eng.ws.jac,
        );
        eng.state.force_scale = h.amax().max(scene.mass.amax() * 1e-6);
        eng.state.out.stats.step_control = vec![0; 2 * n];
        // the output grid, and room for the rows around events
        eng.state.out.keep_history = st.keep_history;
        if st.keep_history {
            let grid = (st.t_end / st.output_dt).ceil().min(1e7) as usize;
            eng.state.out.samples.reserve(grid + grid / 8 + 16);
        }
        Ok(eng)
    }

    pub(super) fn q(&self) -> DVector<f64> {
        self.state.y.rows(0, self.n).into_owned()
    }

    pub(super) fn v(&self) -> DVector<f64> {
        self.state.y.rows(self.n, self.n).into_owned()
    }

    /// (e, ė) of hysteretic element j at the current state (its body's pose and support only).
    pub(super) fn element_deformation(&self, j: usize) -> (f64, f64) {
        self.element_deformation_in(j, self.state.t, &self.state.y)
    }

    /// The bodies a hysteretic element is attached to (the other one of a two-body element).
    pub(super) fn element_bodies(&self, j: usize) -> (usize, Option<usize>) {
        self.scene.hysteretic[j].attachment.bodies()
    }

    /// (e, ė) of hysteretic element j at (t, y): only its bodies' entries of y are read.
    pub(super) fn element_deformation_in(&self, j: usize, t: f64, y: &DVector<f64>) -> (f64, f64) {
        let scene = self.scene;
        let el = &scene.hysteretic[j];
        let (a, b) = self.element_bodies(j);
        let pose = scene.body_state_at(a, t, y, self.n);
        let other = b.map_or(pose, |b| scene.body_state_at(b, t, y, self.n));
        let sup = el
            .support
            .map_or((0.0, 0.0, 0.0), |s| scene.supports[s].at(t));
        scene.deformation_value(&el.attachment, &pose, &other, sup)
    }

    /// Kinematics of contact i at the current state.
    pub(super) fn contact_kinematics_now(&self, i: usize) -> ContactKinematics {
        let (q, v) = (self.q(), self.v());
        let mut fr = Frame::default();
        self.scene.poses_into(&mut fr, self.state.t, &q, &v);
        self.scene.contact_kinematics(&fr, &self.scene.contacts[i])
    }

    /// Each contact's name, state, g_N and ġ_N at the current state (for error reports).
    pub(super) fn describe_contacts(&self) -> String {
        let kin = self.all_kinematics();
        let scene = self.scene;
        (scene.contacts.iter().zip(&kin).zip(&self.state.contacts))
            .map(|((c, k), st)| {
                format!(
                    "{} {st:?} g {:.3e} m ġ {:.3e} m/s",
                    c.name, k.gap, k.gap_rate
                )
            })
            .collect::<Vec<_>>()
            .join("; ")
    }

    /// [`Engine::all_kinematics`], shared while (t, y) stays the same (they depend on t, q, q̇
    /// only): the passes of an event's resolution read them several times unmoved.
    pub(super) fn kinematics_now(&mut self) -> Arc<Vec<ContactKinematics>> {
        if let Some((t, y, kin)) = &self.ws.kin_now
            && *t == self.state.t
            && y.as_slice() == self.state.y.as_slice()
        {
            return Arc::clone(kin);
        }
        let kin = Arc::new(self.all_kinematics());
        let y = self.state.y.clone();
        self.ws.kin_now = Some((self.state.t, y, Arc::clone(&kin)));
        kin
    }

    /// Kinematics of every contact at the current state.
    pub(super) fn all_kinematics(&self) -> Vec<ContactKinematics> {
        let (q, v) = (self.q(), self.v());
        let fr = self.scene.frame(self.state.t, &q, &v);
        self.scene
            .contacts
            .iter()
            .map(|c| self.scene.contact_kinematics(&fr, c))
            .collect()
    }
}
