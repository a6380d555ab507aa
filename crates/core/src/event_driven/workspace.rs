//! Reused storage of the event-driven engine: buffers that let an evaluation run without
//! allocation, and caches valid for one contact mode.

use super::event_fn::EventFn;
use crate::output::ContactSample;
use crate::scene::{BodyState, ContactKinematics, Frame, PowerTerms};
use nalgebra::{DMatrix, DVector};
use std::sync::Arc;

/// Reused storage of one run: nothing here outlives an evaluation (a fork starts afresh).
pub(super) struct Workspace {
    /// Of the right-hand side (q, q̇, h, poses, contact kinematics).
    pub(super) dynamics: Scratch,
    /// Of [`Engine::project`].
    pub(super) project: ProjectScratch,
    /// Of `locate_event`.
    pub(super) locate: LocateScratch,
    /// Of [`Engine::probe`]: valid for one step.
    pub(super) probe: ProbeScratch,
    /// Of the event functions.
    pub(super) event_frame: Frame,
    pub(super) event_qv: (DVector<f64>, DVector<f64>),
    /// (e, ė) of each hysteretic element at the instant of `event_values` (NaN: not yet).
    pub(super) defo: Vec<(f64, f64)>,
    /// Contact rows and element (deformation, force) of the sample being recorded.
    pub(super) sample_rows: (Vec<ContactSample>, Vec<(f64, f64)>),
    /// A Jacobian row of n DOFs.
    pub(super) jac: DVector<f64>,
    /// The rates at the instant of the last `event_values`: ġ_N of its gap functions, ė and
    /// −ė of its branch bounds (e − lower, upper − e), NaN for the other functions.
    pub(super) gap_rates: Vec<f64>,
    /// A state on the dense output (one event function's value) and that value.
    pub(super) dense_y: DVector<f64>,
    pub(super) one_value: Vec<f64>,
    /// Every contact's kinematics at (t, y) ([`Engine::kinematics_now`]).
    pub(super) kin_now: Option<(f64, DVector<f64>, Arc<Vec<ContactKinematics>>)>,
}

impl Workspace {
    pub(super) fn new(n: usize) -> Self {
        Self {
            dynamics: Scratch::default(),
            project: ProjectScratch::default(),
            locate: LocateScratch::default(),
            probe: ProbeScratch::default(),
            event_frame: Frame::default(),
            event_qv: (DVector::zeros(0), DVector::zeros(0)),
            defo: Vec::new(),
            sample_rows: Default::default(),
            jac: DVector::zeros(n),
            gap_rates: Vec::new(),
            dense_y: DVector::zeros(0),
            one_value: Vec::new(),
            kin_now: None,
        }
    }

    /// A new contact mode: its constraints may or may not be redundant.
    pub(super) fn new_contact_mode(&mut self) {
        self.dynamics.mode_singular = false;
        (self.project.pos_singular, self.project.vel_singular) = (false, false);
    }
}

/// Reused storage of [`Engine::project`].
#[derive(Default)]
pub(super) struct ProjectScratch {
    pub(super) q: DVector<f64>,
    pub(super) v: DVector<f64>,
    pub(super) fr: crate::scene::Frame,
    pub(super) kin: Vec<ContactKinematics>,
    pub(super) held: Vec<usize>,
    pub(super) res: Vec<f64>,
    /// The position and velocity constraints of the current contact mode are redundant
    /// (cleared on mode changes, like `Scratch::mode_singular`).
    pub(super) pos_singular: bool,
    pub(super) vel_singular: bool,
    pub(super) correction: crate::linalg::Correction,
    /// The correction δq or δq̇.
    pub(super) dq: DVector<f64>,
    /// The velocity constraints' rows: (contact, tangential).
    pub(super) slots: Vec<(usize, bool)>,
}

#[derive(Default)]
pub(super) struct Scratch {
    pub(super) q: DVector<f64>,
    pub(super) v: DVector<f64>,
    pub(super) h: DVector<f64>,
    pub(super) fr: crate::scene::Frame,
    pub(super) kin: Vec<ContactKinematics>,
    pub(super) qdd: DVector<f64>,
    pub(super) lam_n: Vec<f64>,
    pub(super) lam_t: Vec<f64>,
    pub(super) power: PowerTerms,
    /// Closed-contact constraint slots (contact, tangential) and their force directions.
    pub(super) slots: Vec<(usize, bool)>,
    pub(super) forces: DMatrix<f64>,
    pub(super) a: DMatrix<f64>,
    pub(super) b: DVector<f64>,
    pub(super) lam: DVector<f64>,
    /// (e, ė) of each hysteretic element.
    pub(super) elements: Vec<(f64, f64)>,
    /// The (t, y, all) of the values held, while no law or contact state has changed since.
    pub(super) at: Option<(f64, bool)>,
    pub(super) at_y: DVector<f64>,
    /// The constraints of the current contact mode are redundant (cleared on mode changes).
    pub(super) mode_singular: bool,
}

impl Scratch {
    /// Buffers for n DOFs.
    pub(super) fn size(&mut self, n: usize) {
        for b in [&mut self.q, &mut self.v, &mut self.h, &mut self.qdd] {
            if b.len() != n {
                *b = DVector::zeros(n);
            }
        }
    }

    #[inline]
    pub(super) fn hold(&mut self, t: f64, y: &DVector<f64>, all: bool) {
        if self.at_y.len() != y.len() {
            self.at_y = DVector::zeros(y.len());
        }
        self.at_y.as_mut_slice().copy_from_slice(y.as_slice());
        self.at = Some((t, all));
    }

    /// The held evaluation is of (t, y) (with all contacts' kinematics if `all`).
    pub(super) fn holds(&self, t: f64, y: &DVector<f64>, all: bool) -> bool {
        matches!(self.at, Some((ta, alla)) if ta == t && (alla || !all))
            && self.at_y.as_slice() == y.as_slice()
    }
}

/// Reused storage of [`locate_event`].
#[derive(Default)]
pub(super) struct LocateScratch {
    pub(super) thr: Vec<f64>,
    pub(super) v_prev: Vec<f64>,
    pub(super) t_prev: Vec<f64>,
    pub(super) vals: Vec<f64>,
    pub(super) v_end: Vec<f64>,
    /// ġ_N of the gap functions at `t_prev`, at the current sample and at the step's end.
    pub(super) r_prev: Vec<f64>,
    pub(super) r_vals: Vec<f64>,
    pub(super) r_end: Vec<f64>,
    pub(super) y: DVector<f64>,
    pub(super) roots: Vec<(f64, EventFn)>,
    /// The step's sample instants: (θ, every function or the gaps only).
    pub(super) thetas: Vec<(f64, bool)>,
    /// `Engine::fns_generation` of the list `thr` was made for.
    pub(super) listed: u64,
    /// The functions the step's ends do not show far from zero, the gaps among them.
    pub(super) near: Vec<usize>,
    pub(super) near_gaps: Vec<usize>,
    /// The functions of one sample read from the dynamics.
    pub(super) sub: Vec<EventFn>,
}

/// The dense output of one step for the bodies read so far, and their poses at one instant.
#[derive(Default)]
pub(super) struct ProbeScratch {
    /// [`crate::dopri::Step::dense_coefficients`] of q and q̇ (entries of the bodies in `loaded`).
    pub(super) coef: Vec<[f64; 5]>,
    pub(super) loaded: Vec<bool>,
    /// Per body, its pose at the instant `at.0`, θ = `at.1`, if `posed`.
    pub(super) poses: Vec<BodyState>,
    pub(super) posed: Vec<bool>,
    pub(super) at: (f64, f64),
}
