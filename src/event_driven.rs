//! Event-driven nonsmooth integration (paper §3): DP5 between events, events located by root
//! finding on the dense output, impacts by the velocity LCP (eq. 5), contact state changes by the
//! acceleration LCP (eq. 8), closed constraints held at position and velocity level.

use crate::contact::{Decision, solve_contact, solve_impact};
use crate::dopri::{self, Controller};
use crate::hysteresis::Hysteretic;
use crate::lemke::LcpError;
use crate::output::{
    ContactSample, ContactState, EnergySample, EventKind, EventRecord, RunOutput, Sample,
    SampleKind, SampleView,
};
use crate::scene::{ContactKinematics, ForceModel, LEDGER_TERMS, PowerTerms, Scene, smooth_forces};
use nalgebra::{DMatrix, DVector};
use std::time::Instant;

/// Why a run stopped early. Every variant names the time.
#[derive(Debug, thiserror::Error)]
pub enum SolverError {
    #[error("t = {t:.9} s: {what} LCP failed: {source}")]
    Lcp {
        t: f64,
        what: &'static str,
        #[source]
        source: LcpError,
    },
    #[error(
        "t = {t:.9} s: Painlevé configuration at contact(s) {contacts}: {detail} (the contact LCP has no or several solutions)"
    )]
    Painleve {
        t: f64,
        contacts: String,
        detail: String,
    },
    #[error(
        "t = {t:.9} s: step collapse: {events} events of contact '{contact}' within {window:.3e} s (impact accumulation; enable solver.accumulation_rule)"
    )]
    StepCollapse {
        t: f64,
        contact: String,
        events: usize,
        window: f64,
    },
    #[error("t = {t:.9} s: step size {h:.3e} s fell below the minimum")]
    StepTooSmall { t: f64, h: f64 },
    #[error("t = {t:.9} s: more than {limit} events")]
    TooManyEvents { t: f64, limit: usize },
    #[error("t = {t:.9} s: more than {limit} steps")]
    TooManySteps { t: f64, limit: usize },
    #[error("initial penetration at contact '{contact}': g_N = {gap:.6e} m")]
    InitialPenetration { contact: String, gap: f64 },
    #[error("t = {t:.9} s: state became non-finite")]
    NonFinite { t: f64 },
    #[error("t = {t:.9} s: {method} with step {step:.3e} s is unstable: {detail}")]
    Unstable {
        t: f64,
        method: &'static str,
        step: f64,
        detail: String,
    },
    #[error("t = {t:.9} s: {method} iterations did not converge: {detail}")]
    NoConvergence {
        t: f64,
        method: &'static str,
        detail: String,
    },
    #[error("t = {t:.9} s: cancelled")]
    Cancelled { t: f64 },
}

/// Receives results while a run goes on (for live charts); return false to cancel.
pub trait Observer {
    fn batch(&mut self, samples: &[Sample], events: &[EventRecord], t: f64) -> bool;
}

/// An observer that only lets the run go on.
pub struct Silent;
impl Observer for Silent {
    fn batch(&mut self, _: &[Sample], _: &[EventRecord], _: f64) -> bool {
        true
    }
}

/// Streams what a run adds to an [`Observer`]: every 256 samples or 40 ms, and at the end.
pub(crate) struct Batcher {
    samples: usize,
    events: usize,
    at: Instant,
}

impl Batcher {
    pub(crate) fn new() -> Self {
        Self {
            samples: 0,
            events: 0,
            at: Instant::now(),
        }
    }

    /// Hand over the new results when due; `Cancelled` when the observer says stop.
    pub(crate) fn maybe(
        &mut self,
        out: &RunOutput,
        t: f64,
        observer: &mut dyn Observer,
    ) -> Result<(), SolverError> {
        if out.samples.len() - self.samples >= 256 || self.at.elapsed().as_millis() >= 40 {
            let go = self.flush(out, t, observer);
            if !go {
                return Err(SolverError::Cancelled { t });
            }
        }
        Ok(())
    }

    pub(crate) fn flush(&mut self, out: &RunOutput, t: f64, observer: &mut dyn Observer) -> bool {
        let go = observer.batch(&out.samples[self.samples..], &out.events[self.events..], t);
        *self = Self {
            samples: out.samples.len(),
            events: out.events.len(),
            at: Instant::now(),
        };
        go
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum EventFn {
    Gap(usize),
    Release(usize),
    StickSlip(usize),
    SlideStop(usize),
    Lower(usize),
    Upper(usize),
    Reversal(usize),
}

struct Engine<'a> {
    scene: &'a Scene,
    laws: Vec<Hysteretic>,
    state: Vec<ContactState>,
    minv: DVector<f64>,
    n: usize,
    t: f64,
    y: DVector<f64>,
    /// Impact energy changes (normal, tangential) accumulated: ΔT = Λᵀ(ġ⁺ + ġ⁻)/2.
    impact_normal: f64,
    impact_tangential: f64,
    /// Work-free state corrections (projections) are part of the closure error.
    e0: f64,
    energy_scale: f64,
    out: RunOutput,
    last_impacts: Vec<Vec<f64>>,
    burst: Vec<(f64, usize)>,
    force_scale: f64,
    jac: DVector<f64>,
    /// Event function values at the end of the last step (reused at the next step's start).
    last_event_values: Option<(f64, Vec<f64>)>,
    /// Reused storage of the right-hand side (q, q̇, h, poses, contact kinematics).
    scratch: Scratch,
    /// Reused storage of the event functions.
    event_frame: crate::scene::Frame,
    /// Event function values computed by the last `arm` (for `due_now` at the same instant).
    arm_values: Vec<f64>,
    event_qv: (DVector<f64>, DVector<f64>),
    /// (e, ė) of each hysteretic element at the instant of `event_values` (NaN: not yet).
    defo: Vec<(f64, f64)>,
    locate: LocateScratch,
    forces: ForceModel,
    /// The events of the instant [`locate_event`] returned.
    cluster: Vec<EventFn>,
    proj: ProjectScratch,
    /// Counts the event-function lists made (a list's identity for cached per-list data).
    fns_generation: u64,
    /// Contact rows and element (deformation, force) of the sample being recorded.
    sample_rows: (Vec<ContactSample>, Vec<(f64, f64)>),
}

/// Reused storage of [`Engine::project`].
#[derive(Default)]
struct ProjectScratch {
    q: DVector<f64>,
    v: DVector<f64>,
    fr: crate::scene::Frame,
    kin: Vec<ContactKinematics>,
    held: Vec<usize>,
    res: Vec<f64>,
    /// The position and velocity constraints of the current contact mode are redundant
    /// (cleared on mode changes, like `Scratch::mode_singular`).
    pos_singular: bool,
    vel_singular: bool,
}

#[derive(Default)]
struct Scratch {
    q: DVector<f64>,
    v: DVector<f64>,
    h: DVector<f64>,
    fr: crate::scene::Frame,
    kin: Vec<ContactKinematics>,
    qdd: DVector<f64>,
    lam_n: Vec<f64>,
    lam_t: Vec<f64>,
    power: PowerTerms,
    /// Closed-contact constraint slots (contact, tangential) and their force directions.
    slots: Vec<(usize, bool)>,
    forces: DMatrix<f64>,
    a: DMatrix<f64>,
    b: DVector<f64>,
    lam: DVector<f64>,
    /// (e, ė) of each hysteretic element.
    elements: Vec<(f64, f64)>,
    /// The (t, y, all) of the values held, while no law or contact state has changed since.
    at: Option<(f64, bool)>,
    at_y: DVector<f64>,
    /// The constraints of the current contact mode are redundant (cleared on mode changes).
    mode_singular: bool,
}

impl Scratch {
    /// Buffers for n DOFs.
    fn size(&mut self, n: usize) {
        for b in [&mut self.q, &mut self.v, &mut self.h, &mut self.qdd] {
            if b.len() != n {
                *b = DVector::zeros(n);
            }
        }
    }

    fn hold(&mut self, t: f64, y: &DVector<f64>, all: bool) {
        if self.at_y.len() != y.len() {
            self.at_y = DVector::zeros(y.len());
        }
        self.at_y.as_mut_slice().copy_from_slice(y.as_slice());
        self.at = Some((t, all));
    }

    /// The held evaluation is of (t, y) (with all contacts' kinematics if `all`).
    fn holds(&self, t: f64, y: &DVector<f64>, all: bool) -> bool {
        matches!(self.at, Some((ta, alla)) if ta == t && (alla || !all))
            && self.at_y.as_slice() == y.as_slice()
    }
}

fn sgn(x: f64) -> f64 {
    if x >= 0.0 { 1.0 } else { -1.0 }
}

impl<'a> Engine<'a> {
    fn q(&self) -> DVector<f64> {
        self.y.rows(0, self.n).into_owned()
    }
    fn v(&self) -> DVector<f64> {
        self.y.rows(self.n, self.n).into_owned()
    }

    /// (e, ė) of hysteretic element j at the current state (its body's pose and support only).
    fn element_deformation(&self, j: usize) -> (f64, f64) {
        self.element_deformation_in(j, self.t, &self.y)
    }

    /// The body a hysteretic element is attached to.
    fn element_body(&self, j: usize) -> usize {
        match self.scene.hysteretic[j].attachment {
            crate::scene::Attachment::Point { body, .. }
            | crate::scene::Attachment::Rotation { body } => body,
        }
    }

    /// (e, ė) of hysteretic element j at (t, y): only its body's entries of y are read.
    fn element_deformation_in(&self, j: usize, t: f64, y: &DVector<f64>) -> (f64, f64) {
        let scene = self.scene;
        let el = &scene.hysteretic[j];
        let pose = scene.body_state_from(self.element_body(j), y, self.n);
        let sup = el
            .support
            .map_or((0.0, 0.0, 0.0), |s| scene.supports[s].at(t));
        let (e, ed, ..) = scene.deformation_at(&el.attachment, &pose, sup);
        (e, ed)
    }

    /// Kinematics of contact i at the current state.
    fn contact_kinematics_now(&self, i: usize) -> ContactKinematics {
        let (q, v) = (self.q(), self.v());
        self.scene
            .contact_kinematics(&self.scene.contacts[i], &q, &v)
    }

    /// Kinematics of every contact at the current state.
    fn all_kinematics(&self) -> Vec<ContactKinematics> {
        let (q, v) = (self.q(), self.v());
        let fr = self.scene.frame(self.t, &q, &v);
        self.scene
            .contacts
            .iter()
            .map(|c| self.scene.contact_kinematics_in(&fr, c))
            .collect()
    }

    /// Constrained dynamics in the current mode, M q̈ = h + Σ W λ with g̈_N = 0 (closed),
    /// g̈_T = 0 (stick), λ_T = −μ s λ_N (slide), into `self.scratch` (qdd, lam_n, lam_t, kin,
    /// power), without allocation once the buffers have their sizes. `all`: kinematics of
    /// every contact (for output); otherwise only the closed ones are computed (open contacts
    /// get a placeholder and carry no force).
    fn dynamics_into(&mut self, t: f64, y: &DVector<f64>, all: bool) -> Result<(), SolverError> {
        let n = self.n;
        let scene = self.scene;
        let nc = scene.contacts.len();
        let sc = &mut self.scratch;
        if sc.holds(t, y, all) {
            return Ok(());
        }
        sc.at = None;
        sc.size(n);
        sc.q.as_mut_slice().copy_from_slice(&y.as_slice()[..n]);
        sc.v.as_mut_slice().copy_from_slice(&y.as_slice()[n..2 * n]);
        scene.frame_into(&mut sc.fr, t, &sc.q, &sc.v);
        sc.elements.resize(scene.hysteretic.len(), (0.0, 0.0));
        sc.power = self.forces.eval(
            scene,
            &self.laws,
            &sc.fr,
            &sc.v,
            &mut sc.h,
            &mut sc.elements,
        );
        sc.kin.resize_with(nc, ContactKinematics::placeholder);
        for ((c, st), k) in scene
            .contacts
            .iter()
            .zip(&self.state)
            .zip(sc.kin.iter_mut())
        {
            if all || *st != ContactState::Open {
                scene.contact_kinematics_into(&sc.fr, c, k);
            } else {
                k.gap = f64::INFINITY;
                k.gap_rate = 0.0;
                k.slip_rate = 0.0;
            }
        }
        for lam in [&mut sc.lam_n, &mut sc.lam_t] {
            lam.clear();
            lam.resize(nc, 0.0);
        }
        let minv = self.minv.as_slice();
        for ((a, h), m) in sc
            .qdd
            .as_mut_slice()
            .iter_mut()
            .zip(sc.h.as_slice())
            .zip(minv)
        {
            *a = h * m;
        }
        // constraint rows C (W_N or W_T of a closed contact) and force directions F
        sc.slots.clear();
        for (i, st) in self.state.iter().enumerate() {
            match *st {
                ContactState::Open => {}
                ContactState::Slide(_) => sc.slots.push((i, false)),
                ContactState::Stick => {
                    sc.slots.push((i, false));
                    sc.slots.push((i, true));
                }
            }
        }
        let k = sc.slots.len();
        if k == 0 {
            sc.hold(t, y, all);
            return Ok(());
        }
        if sc.forces.nrows() != n || sc.forces.ncols() < k {
            sc.forces = DMatrix::zeros(n, k.max(2 * nc));
        }
        for (r, &(i, tangential)) in sc.slots.iter().enumerate() {
            let kin = &sc.kin[i];
            let col = &mut sc.forces.as_mut_slice()[r * n..(r + 1) * n];
            match self.state[i] {
                ContactState::Slide(s) if scene.contacts[i].mu > 0.0 && s != 0.0 => {
                    let mu_s = scene.contacts[i].mu * s;
                    let (wn, wt) = (kin.w_n.as_slice(), kin.w_t.as_slice());
                    for ((c, wn), wt) in col.iter_mut().zip(wn).zip(wt) {
                        *c = wn - mu_s * wt;
                    }
                }
                _ => col.copy_from_slice(if tangential { &kin.w_t } else { &kin.w_n }.as_slice()),
            }
        }
        fn row(kin: &[ContactKinematics], (i, tangential): (usize, bool)) -> (&DVector<f64>, f64) {
            let c = &kin[i];
            if tangential {
                (&c.w_t, c.bias_t)
            } else {
                (&c.w_n, c.bias_n)
            }
        }
        if sc.a.nrows() != k {
            sc.a = DMatrix::zeros(k, k);
            sc.b = DVector::zeros(k);
        }
        let forces = &sc.forces.as_slice()[..k * n];
        for r in 0..k {
            let (w, bias) = row(&sc.kin, sc.slots[r]);
            sc.b[r] = -(w.dot(&sc.qdd) + bias);
            let w = &w.as_slice()[..n];
            for (c, f) in forces.chunks_exact(n).enumerate() {
                let mut acc = 0.0;
                for ((wj, mj), fj) in w.iter().zip(minv).zip(f) {
                    acc += wj * mj * fj;
                }
                sc.a[(r, c)] = acc;
            }
        }
        // Painlevé: a sliding contact whose normal Delassus entry is not positive.
        for (r, &(i, tangential)) in sc.slots.iter().enumerate() {
            if !tangential
                && matches!(self.state[i], ContactState::Slide(s) if s != 0.0)
                && scene.contacts[i].mu > 0.0
            {
                let w = &sc.kin[i].w_n;
                let g = w
                    .as_slice()
                    .iter()
                    .zip(minv)
                    .map(|(x, m)| x * m * x)
                    .sum::<f64>();
                if sc.a[(r, r)] <= 1e-12 * g {
                    return Err(SolverError::Painleve {
                        t,
                        contacts: scene.contacts[i].name.clone(),
                        detail: format!(
                            "W_Nᵀ M⁻¹ (W_N − μ s W_T) = {:.4e} ≤ 0 while sliding",
                            sc.a[(r, r)]
                        ),
                    });
                }
            }
        }
        solve_small_into(&sc.a, &sc.b, &mut sc.lam, &mut sc.mode_singular);
        for (r, &(i, tangential)) in sc.slots.iter().enumerate() {
            let lr = sc.lam[r];
            let f = &sc.forces.as_slice()[r * n..(r + 1) * n];
            for ((a, fj), mj) in sc.qdd.as_mut_slice().iter_mut().zip(f).zip(minv) {
                *a += lr * fj * mj;
            }
            if tangential {
                sc.lam_t[i] = lr;
            } else {
                sc.lam_n[i] = lr;
                if let ContactState::Slide(s) = self.state[i] {
                    sc.lam_t[i] = -scene.contacts[i].mu * s * lr;
                }
            }
        }
        sc.hold(t, y, all);
        Ok(())
    }

    fn rhs(&mut self, t: f64, y: &DVector<f64>, out: &mut DVector<f64>) -> Result<(), SolverError> {
        let n = self.n;
        self.dynamics_into(t, y, false)?;
        let d = &self.scratch;
        let o = out.as_mut_slice();
        o[..n].copy_from_slice(&y.as_slice()[n..2 * n]);
        o[n..2 * n].copy_from_slice(&d.qdd.as_slice()[..n]);
        let mut contact_loss = 0.0;
        for i in 0..d.kin.len() {
            contact_loss -= d.lam_n[i] * d.kin[i].gap_rate + d.lam_t[i] * d.kin[i].slip_rate;
        }
        o[2 * n..2 * n + 5].copy_from_slice(&[
            d.power.loads,
            d.power.supports,
            d.power.damping,
            d.power.hysteretic,
            contact_loss,
        ]);
        Ok(())
    }

    fn event_fns(&mut self) -> Vec<EventFn> {
        let mut f = Vec::new();
        self.event_fns_into(&mut f);
        f
    }

    /// [`Engine::event_fns`] into `f` (cleared first).
    fn event_fns_into(&mut self, f: &mut Vec<EventFn>) {
        self.fns_generation += 1;
        f.clear();
        for (i, st) in self.state.iter().enumerate() {
            match st {
                ContactState::Open => f.push(EventFn::Gap(i)),
                ContactState::Stick => {
                    f.push(EventFn::Release(i));
                    f.push(EventFn::StickSlip(i));
                }
                ContactState::Slide(s) => {
                    f.push(EventFn::Release(i));
                    if *s != 0.0 && self.scene.contacts[i].mu > 0.0 {
                        f.push(EventFn::SlideStop(i));
                    }
                }
            }
        }
        for (j, law) in self.laws.iter().enumerate() {
            let b = law.branch();
            if b.lower.is_finite() {
                f.push(EventFn::Lower(j));
            }
            if b.upper.is_finite() {
                f.push(EventFn::Upper(j));
            }
            if b.ends_on_reversal {
                f.push(EventFn::Reversal(j));
            }
        }
    }

    /// Values of the event functions (an event is a crossing from > 0 to ≤ 0) and their
    /// "zero" thresholds.
    fn event_values(
        &mut self,
        t: f64,
        y: &DVector<f64>,
        fns: &[EventFn],
    ) -> Result<Vec<f64>, SolverError> {
        let mut vals = Vec::with_capacity(fns.len());
        self.event_values_into(t, y, fns, &mut vals)?;
        Ok(vals)
    }

    /// [`Engine::event_values`] into `vals` (cleared first).
    fn event_values_into(
        &mut self,
        t: f64,
        y: &DVector<f64>,
        fns: &[EventFn],
        vals: &mut Vec<f64>,
    ) -> Result<(), SolverError> {
        let needs_forces = fns
            .iter()
            .any(|f| matches!(f, EventFn::Release(_) | EventFn::StickSlip(_)));
        let n = self.n;
        let scene = self.scene;
        let mut fr = std::mem::take(&mut self.event_frame);
        let held = needs_forces || self.scratch.holds(t, y, false);
        let mut defo = std::mem::take(&mut self.defo);
        if held {
            // the dynamics leave the frame and the element deformations of (t, y) in the scratch
            self.dynamics_into(t, y, false)?;
            std::mem::swap(&mut fr, &mut self.scratch.fr);
            defo.clear();
            defo.extend_from_slice(&self.scratch.elements);
        } else {
            if self.event_qv.0.len() != n {
                self.event_qv = (DVector::zeros(n), DVector::zeros(n));
            }
            self.event_qv
                .0
                .as_mut_slice()
                .copy_from_slice(&y.as_slice()[..n]);
            self.event_qv
                .1
                .as_mut_slice()
                .copy_from_slice(&y.as_slice()[n..2 * n]);
            let branch = fns.iter().any(|f| {
                matches!(
                    f,
                    EventFn::Lower(_) | EventFn::Upper(_) | EventFn::Reversal(_)
                )
            });
            if branch {
                scene.frame_into(&mut fr, t, &self.event_qv.0, &self.event_qv.1);
            } else {
                // contact functions need the poses only
                scene.poses_into(&mut fr, &self.event_qv.0, &self.event_qv.1);
            }
            defo.clear();
            defo.resize(scene.hysteretic.len(), (f64::NAN, f64::NAN));
        }
        vals.clear();
        let d = &self.scratch;
        for f in fns {
            let val = match *f {
                EventFn::Gap(i) => scene.contact_rates_in(&fr, &scene.contacts[i]).0,
                EventFn::Release(i) => d.lam_n[i],
                EventFn::StickSlip(i) => scene.contacts[i].mu * d.lam_n[i] - d.lam_t[i].abs(),
                EventFn::SlideStop(i) => {
                    let s = match self.state[i] {
                        ContactState::Slide(s) => s,
                        _ => 1.0,
                    };
                    s * scene.contact_rates_in(&fr, &scene.contacts[i]).2
                }
                EventFn::Lower(j) | EventFn::Upper(j) | EventFn::Reversal(j) => {
                    if defo[j].0.is_nan() {
                        let el = &scene.hysteretic[j];
                        let (e, ed, ..) = scene.deformation_sparse(&fr, &el.attachment, el.support);
                        defo[j] = (e, ed);
                    }
                    let (e, ed) = defo[j];
                    let b = self.laws[j].branch();
                    match *f {
                        EventFn::Lower(_) => e - b.lower,
                        EventFn::Upper(_) => b.upper - e,
                        _ => b.direction * ed,
                    }
                }
            };
            vals.push(val);
        }
        if held {
            std::mem::swap(&mut fr, &mut self.scratch.fr);
        }
        self.event_frame = fr;
        self.defo = defo;
        Ok(())
    }

    fn threshold(&self, f: EventFn) -> f64 {
        let s = &self.scene.settings;
        match f {
            EventFn::Gap(_) => 1e-3 * s.gap_tol,
            EventFn::Release(_) | EventFn::StickSlip(_) => 1e-10 * self.force_scale,
            EventFn::SlideStop(_) | EventFn::Reversal(_) => 1e-3 * s.velocity_tol,
            EventFn::Lower(_) | EventFn::Upper(_) => 1e-13,
        }
    }

    fn record_sample(&mut self, kind: SampleKind) -> Result<(), SolverError> {
        let n = self.n;
        let scene = self.scene;
        if self.state.iter().all(|s| *s == ContactState::Open) {
            // no contact force to solve for: kinematics and element deformations only
            let sc = &mut self.scratch;
            sc.at = None;
            sc.size(n);
            sc.q.as_mut_slice().copy_from_slice(&self.y.as_slice()[..n]);
            sc.v.as_mut_slice()
                .copy_from_slice(&self.y.as_slice()[n..2 * n]);
            scene.frame_into(&mut sc.fr, self.t, &sc.q, &sc.v);
            sc.kin
                .resize_with(scene.contacts.len(), ContactKinematics::placeholder);
            for (c, k) in scene.contacts.iter().zip(sc.kin.iter_mut()) {
                // gap and rates only: no Jacobians needed without forces
                (k.gap, k.gap_rate, k.slip_rate) = scene.contact_rates_in(&sc.fr, c);
            }
            sc.lam_n.clear();
            sc.lam_n.resize(scene.contacts.len(), 0.0);
            sc.lam_t.clear();
            sc.lam_t.resize(scene.contacts.len(), 0.0);
            sc.elements.resize(scene.hysteretic.len(), (0.0, 0.0));
            if self.out.keep_history {
                // (the running summary does not use them)
                self.forces.deformations(&sc.fr, &mut sc.elements);
            }
        } else {
            let y = std::mem::take(&mut self.y);
            let r = self.dynamics_into(self.t, &y, true);
            self.y = y;
            r?;
        }
        let d = &self.scratch;
        let (contacts, elements) = &mut self.sample_rows;
        contacts.clear();
        contacts.extend((0..scene.contacts.len()).map(|i| ContactSample {
            gap: d.kin[i].gap,
            gap_rate: d.kin[i].gap_rate,
            slip_rate: d.kin[i].slip_rate,
            normal_force: d.lam_n[i],
            tangential_force: d.lam_t[i],
            state: self.state[i],
        }));
        elements.clear();
        if self.out.keep_history {
            elements.extend(
                d.elements
                    .iter()
                    .zip(&self.laws)
                    .map(|(&(e, _), law)| (e, law.force(e))),
            );
        }
        let q = &self.y.as_slice()[..n];
        let v = &self.y.as_slice()[n..2 * n];
        let kinetic = 0.5
            * v.iter()
                .zip(scene.mass.as_slice())
                .map(|(a, m)| m * a * a)
                .sum::<f64>();
        let mut energy = self.energy_terms(kinetic, self.forces.spring_energy(&d.fr));
        self.energy_scale = self.energy_scale.max(energy.scale());
        energy.closure = energy.balance();
        let (contacts, elements) = &self.sample_rows;
        self.out.record(SampleView {
            t: self.t,
            kind,
            q,
            v,
            contacts,
            elements,
            energy,
        });
        Ok(())
    }

    fn energy_terms(&self, kinetic: f64, elastic: f64) -> EnergySample {
        let n = self.n;
        EnergySample {
            kinetic,
            elastic,
            loads: self.y[2 * n],
            supports: self.y[2 * n + 1],
            damping: self.y[2 * n + 2],
            hysteretic: self.y[2 * n + 3],
            friction: self.y[2 * n + 4],
            impact_normal: -self.impact_normal,
            impact_tangential: -self.impact_tangential,
            initial: self.e0,
            closure: 0.0,
        }
    }

    fn log(&mut self, rec: EventRecord) -> Result<(), SolverError> {
        if self.out.events.len() >= self.scene.settings.max_events {
            return Err(SolverError::TooManyEvents {
                t: self.t,
                limit: self.scene.settings.max_events,
            });
        }
        self.out.stats.count(rec.kind);
        self.out.events.push(rec);
        Ok(())
    }

    /// Minimum-M-norm projection of q onto g_N = 0 for closed contacts, and of q̇ onto
    /// ġ_N = 0 (closed) and ġ_T = 0 (stick). Returns the largest correction made.
    fn project(&mut self) -> f64 {
        let n = self.n;
        let scene = self.scene;
        let mut ps = std::mem::take(&mut self.proj);
        if ps.q.len() != n {
            ps.q = DVector::zeros(n);
            ps.v = DVector::zeros(n);
        }
        ps.kin
            .resize_with(scene.contacts.len(), ContactKinematics::placeholder);
        let load = |ps: &mut ProjectScratch, y: &DVector<f64>, t: f64| {
            ps.q.as_mut_slice().copy_from_slice(&y.as_slice()[..n]);
            ps.v.as_mut_slice().copy_from_slice(&y.as_slice()[n..2 * n]);
            scene.frame_into(&mut ps.fr, t, &ps.q, &ps.v);
        };
        // closed contacts, and open ones that penetrate (after an event located past g_N = 0)
        load(&mut ps, &self.y, self.t);
        ps.held.clear();
        for i in 0..self.state.len() {
            if self.state[i] != ContactState::Open
                || scene.contact_rates_in(&ps.fr, &scene.contacts[i]).0 < 0.0
            {
                ps.held.push(i);
            }
        }
        let mut moved = 0.0f64;
        if !ps.held.is_empty() {
            for _ in 0..3 {
                load(&mut ps, &self.y, self.t);
                let ProjectScratch {
                    fr,
                    kin,
                    held,
                    res,
                    pos_singular,
                    ..
                } = &mut ps;
                res.clear();
                for &i in held.iter() {
                    scene.contact_kinematics_into(fr, &scene.contacts[i], &mut kin[i]);
                    res.push(kin[i].gap);
                }
                if res.iter().all(|r| r.abs() < 1e-15) {
                    break;
                }
                let rows: Vec<&DVector<f64>> = held.iter().map(|&i| &kin[i].w_n).collect();
                let dq = min_norm_correction(&rows, res, &self.minv, pos_singular);
                moved = moved.max(dq.amax());
                for i in 0..n {
                    self.y[i] -= dq[i];
                }
            }
        }
        let closed = self.state.iter().any(|s| *s != ContactState::Open);
        if closed {
            load(&mut ps, &self.y, self.t);
            let ProjectScratch {
                fr,
                kin,
                res,
                vel_singular,
                ..
            } = &mut ps;
            res.clear();
            for (i, st) in self.state.iter().enumerate() {
                if *st != ContactState::Open {
                    scene.contact_kinematics_into(fr, &scene.contacts[i], &mut kin[i]);
                }
            }
            let mut rows: Vec<&DVector<f64>> = Vec::with_capacity(8);
            for (i, st) in self.state.iter().enumerate() {
                if *st != ContactState::Open {
                    rows.push(&kin[i].w_n);
                    res.push(kin[i].gap_rate);
                    if *st == ContactState::Stick {
                        rows.push(&kin[i].w_t);
                        res.push(kin[i].slip_rate);
                    }
                }
            }
            let dv = min_norm_correction(&rows, res, &self.minv, vel_singular);
            moved = moved.max(dv.amax());
            for i in 0..n {
                self.y[n + i] -= dv[i];
            }
        }
        self.proj = ps;
        moved
    }

    /// Decide the contact states at the current instant: impacts (eq. 5) until no closed
    /// contact approaches, then the acceleration LCP (eq. 8) for the closed ones.
    fn resolve(&mut self) -> Result<(), SolverError> {
        self.scratch.at = None;
        self.scratch.mode_singular = false;
        (self.proj.pos_singular, self.proj.vel_singular) = (false, false);
        let scene = self.scene;
        let st = &scene.settings;
        let nc = scene.contacts.len();
        let before = self.state.clone();
        let mut impacted = vec![false; nc];
        for _pass in 0..8 {
            let kin = self.all_kinematics();
            let set: Vec<usize> = (0..nc).filter(|&i| kin[i].gap <= st.gap_tol).collect();
            let approaching: Vec<usize> = set
                .iter()
                .copied()
                .filter(|&i| kin[i].gap_rate < -st.velocity_tol)
                .collect();
            if approaching.is_empty() {
                break;
            }
            let mut eps: Vec<f64> = set.iter().map(|&i| scene.contacts[i].restitution).collect();
            let mu: Vec<f64> = set.iter().map(|&i| scene.contacts[i].mu).collect();
            let mut accumulated = vec![None; set.len()];
            for (a, &i) in set.iter().enumerate() {
                if !approaching.contains(&i) {
                    continue;
                }
                let speed = -kin[i].gap_rate;
                let shrinking = {
                    let h = &self.last_impacts[i];
                    h.len() < 2 || {
                        let (t1, t0) = (h[h.len() - 1], h[h.len() - 2]);
                        (self.t - t1) < 0.999 * (t1 - t0)
                    }
                };
                let flight = self.last_impacts[i]
                    .last()
                    .map_or(f64::INFINITY, |t| self.t - t);
                let slow = speed < st.zeno_velocity || flight < st.min_event_spacing;
                if st.accumulation_rule && eps[a] > 0.0 && slow && shrinking {
                    eps[a] = 0.0;
                    let h = &self.last_impacts[i];
                    let est = if h.len() >= 2 {
                        let t1 = h[h.len() - 1];
                        let t0 = h[h.len() - 2];
                        let f_now = self.t - t1;
                        let f_prev = t1 - t0;
                        let r = if f_prev > 0.0 { f_now / f_prev } else { 0.0 };
                        if r > 0.0 && r < 1.0 {
                            self.t + f_now * r / (1.0 - r)
                        } else {
                            self.t
                        }
                    } else {
                        self.t
                    };
                    accumulated[a] = Some(est);
                }
            }
            let kin_set: Vec<&ContactKinematics> = set.iter().map(|&i| &kin[i]).collect();
            let imp = solve_impact(&kin_set, &eps, &mu, &self.minv, &st.lemke).map_err(|e| {
                SolverError::Lcp {
                    t: self.t,
                    what: "impact",
                    source: e,
                }
            })?;
            self.out.stats.lcp_solves += 1;
            self.out.stats.lemke_pivots += imp.pivots;
            for k in 0..self.n {
                self.y[self.n + k] += imp.velocity_jump[k];
            }
            for (a, &i) in set.iter().enumerate() {
                let de_n = imp.normal_impulse[a] * (kin[i].gap_rate + imp.gap_rate_after[a]) / 2.0;
                let de_t =
                    imp.tangential_impulse[a] * (kin[i].slip_rate + imp.slip_rate_after[a]) / 2.0;
                self.impact_normal += de_n;
                self.impact_tangential += de_t;
                if approaching.contains(&i) || imp.normal_impulse[a] > 0.0 {
                    impacted[i] = true;
                    self.check_burst(i)?;
                    let hist = &mut self.last_impacts[i];
                    hist.push(self.t);
                    if hist.len() > 3 {
                        hist.remove(0);
                    }
                    let sticks = imp.slip_rate_after[a].abs() <= st.velocity_tol.max(1e-12);
                    let record = EventRecord {
                        t: self.t,
                        contact: i,
                        kind: EventKind::Impact,
                        normal: imp.normal_impulse[a],
                        tangential: imp.tangential_impulse[a],
                        gap_rate_before: kin[i].gap_rate,
                        gap_rate_after: imp.gap_rate_after[a],
                        slip_rate_after: imp.slip_rate_after[a],
                        sticks: (scene.contacts[i].mu > 0.0).then_some(sticks),
                        info: f64::NAN,
                    };
                    self.log(record.clone())?;
                    if let Some(est) = accumulated[a] {
                        self.out.accumulation_times.push((i, est));
                        self.log(EventRecord {
                            kind: EventKind::Accumulation,
                            info: est,
                            ..record
                        })?;
                    }
                }
            }
        }
        // acceleration level
        let (q, v) = (self.q(), self.v());
        let kin = self.all_kinematics();
        let closed: Vec<usize> = (0..nc)
            .filter(|&i| kin[i].gap <= st.gap_tol && kin[i].gap_rate.abs() <= st.velocity_tol)
            .collect();
        for i in 0..nc {
            if !closed.contains(&i) {
                self.state[i] = ContactState::Open;
            }
        }
        if !closed.is_empty() {
            let mut h = DVector::zeros(self.n);
            smooth_forces_laws(scene, &self.laws, self.t, &q, &v, &mut h, &mut self.jac);
            self.force_scale = self.force_scale.max(h.amax());
            let mu: Vec<f64> = closed.iter().map(|&i| scene.contacts[i].mu).collect();
            let slide: Vec<Option<f64>> = closed
                .iter()
                .map(|&i| {
                    let s = kin[i].slip_rate;
                    if scene.contacts[i].mu > 0.0 && s.abs() > st.velocity_tol {
                        Some(sgn(s))
                    } else {
                        None
                    }
                })
                .collect();
            let kin_set: Vec<&ContactKinematics> = closed.iter().map(|&i| &kin[i]).collect();
            let outcome = solve_contact(&kin_set, &mu, &slide, &self.minv, &h, &st.lemke).map_err(
                |e| match e {
                    LcpError::Ray { .. } if slide.iter().any(|s| s.is_some()) => {
                        SolverError::Painleve {
                            t: self.t,
                            contacts: closed
                                .iter()
                                .map(|&i| scene.contacts[i].name.as_str())
                                .collect::<Vec<_>>()
                                .join(", "),
                            detail: "the acceleration LCP ends on a ray".into(),
                        }
                    }
                    e => SolverError::Lcp {
                        t: self.t,
                        what: "contact",
                        source: e,
                    },
                },
            )?;
            self.out.stats.lcp_solves += 1;
            self.out.stats.lemke_pivots += outcome.pivots;
            for (a, &i) in closed.iter().enumerate() {
                self.force_scale = self.force_scale.max(outcome.normal_force[a].abs());
                self.state[i] = match outcome.decision[a] {
                    Decision::Detach => ContactState::Open,
                    Decision::Stick => ContactState::Stick,
                    Decision::Slide(s) => ContactState::Slide(s),
                };
            }
            // Painlevé check for sliding contacts (non-uniqueness when the Delassus term is ≤ 0)
            for (a, &i) in closed.iter().enumerate() {
                if let ContactState::Slide(s) = self.state[i] {
                    let c = &scene.contacts[i];
                    if c.mu > 0.0 && s != 0.0 {
                        let k = kin_set[a];
                        let wq = &k.w_n - &k.w_t * (c.mu * s);
                        let g: f64 = k
                            .w_n
                            .iter()
                            .zip(self.minv.iter())
                            .zip(wq.iter())
                            .map(|((x, m), y)| x * m * y)
                            .sum();
                        let g0: f64 = k
                            .w_n
                            .iter()
                            .zip(self.minv.iter())
                            .map(|(x, m)| x * m * x)
                            .sum();
                        if g <= 1e-12 * g0 {
                            return Err(SolverError::Painleve {
                                t: self.t,
                                contacts: c.name.clone(),
                                detail: format!(
                                    "W_Nᵀ M⁻¹ (W_N − μ s W_T) = {g:.4e} ≤ 0 while sliding"
                                ),
                            });
                        }
                    }
                }
            }
        }
        self.project();
        // log transitions
        for i in 0..nc {
            let (b, a) = (before[i], self.state[i]);
            let kind = match (b, a) {
                (ContactState::Stick, ContactState::Slide(_)) => Some(EventKind::Slip),
                (ContactState::Slide(s0), ContactState::Slide(s1)) if s0 != s1 => {
                    Some(EventKind::Slip)
                }
                (ContactState::Slide(_), ContactState::Stick) => Some(EventKind::Stick),
                (ContactState::Open, ContactState::Stick) if !impacted[i] => Some(EventKind::Stick),
                (ContactState::Open, ContactState::Slide(_)) if !impacted[i] => {
                    Some(EventKind::Slip)
                }
                (ContactState::Stick | ContactState::Slide(_), ContactState::Open) => {
                    Some(EventKind::Release)
                }
                _ => None,
            };
            if let Some(kind) = kind {
                let q = self.q();
                let v = self.v();
                let k = scene.contact_kinematics(&scene.contacts[i], &q, &v);
                self.log(EventRecord {
                    t: self.t,
                    contact: i,
                    kind,
                    normal: 0.0,
                    tangential: 0.0,
                    gap_rate_before: k.gap_rate,
                    gap_rate_after: k.gap_rate,
                    slip_rate_after: k.slip_rate,
                    sticks: Some(a == ContactState::Stick),
                    info: f64::NAN,
                })?;
            }
        }
        Ok(())
    }

    /// Guard against impact accumulation without the accumulation rule (Zeno).
    fn check_burst(&mut self, i: usize) -> Result<(), SolverError> {
        let st = &self.scene.settings;
        let (last, count) = self.burst[i];
        let count = if self.t - last < st.min_event_spacing {
            count + 1
        } else {
            0
        };
        self.burst[i] = (self.t, count);
        if count >= 16 {
            return Err(SolverError::StepCollapse {
                t: self.t,
                contact: self.scene.contacts[i].name.clone(),
                events: count,
                window: st.min_event_spacing,
            });
        }
        Ok(())
    }
}

/// smooth_forces with the run's own hysteretic states.
fn smooth_forces_laws(
    scene: &Scene,
    laws: &[Hysteretic],
    t: f64,
    q: &DVector<f64>,
    v: &DVector<f64>,
    h: &mut DVector<f64>,
    jac: &mut DVector<f64>,
) -> PowerTerms {
    smooth_forces(scene, Some(laws), t, q, v, h, jac)
}

/// Minimum-norm solution of a rank-deficient (redundant constraints), consistent system:
/// λ = Aᵀ(AAᵀ + δI)⁻¹ b (→ A⁺b as δ → 0), δ = 1e-12 max diag(AAᵀ), by Cholesky; the SVD
/// solution if that does not reproduce b. It splits forces equally between redundant rows.
fn min_norm_solve(a: &DMatrix<f64>, b: &DVector<f64>) -> DVector<f64> {
    let aat = a * a.transpose();
    let delta = 1e-12 * aat.diagonal().amax().max(1e-300);
    let mut reg = aat;
    for i in 0..reg.nrows() {
        reg[(i, i)] += delta;
    }
    if let Some(ch) = reg.cholesky() {
        let x = a.transpose() * ch.solve(b);
        if x.iter().all(|v| v.is_finite()) && (a * &x - b).amax() <= 1e-9 * (1.0 + b.amax()) {
            return x;
        }
    }
    let scale = a.amax().max(1e-300);
    let svd = a.clone().svd(true, true);
    svd.solve(b, 1e-9 * scale)
        .unwrap_or_else(|_| DVector::zeros(b.len()))
}

/// Solves A x = b (A square, small): complete-pivoting elimination when A is regular, else
/// the minimum-norm solution of [`min_norm_solve`] (on the stack for n ≤ 12); into `x`.
/// `singular`: the system is known to be rank-deficient (skip the direct attempt); set when
/// the direct elimination fails.
fn solve_small_into(a: &DMatrix<f64>, b: &DVector<f64>, x: &mut DVector<f64>, singular: &mut bool) {
    let k = b.len();
    if x.len() != k {
        *x = DVector::zeros(k);
    }
    if !*singular {
        if eliminate_into(a, b, 1e-9, x.as_mut_slice()) {
            return;
        }
        *singular = true;
    }
    let done = match k {
        0..=4 => min_norm_on::<4>(a, b, x),
        5..=8 => min_norm_on::<8>(a, b, x),
        9..=ELIM_N => min_norm_on::<ELIM_N>(a, b, x),
        _ => false,
    };
    if done {
        return;
    }
    x.copy_from(&min_norm_solve(a, b));
}

/// The regularized minimum-norm solution of [`min_norm_solve`] on stack arrays of order N ≥ k;
/// false if it fails (then the SVD decides).
fn min_norm_on<const N: usize>(a: &DMatrix<f64>, b: &DVector<f64>, x: &mut DVector<f64>) -> bool {
    let k = b.len();
    // the regularized minimum-norm solution of min_norm_solve, on the stack
    let mut m = [[0.0f64; N]; N];
    let mut dmax = 0.0f64;
    for r in 0..k {
        for c in 0..k {
            let mut acc = 0.0;
            for j in 0..k {
                acc += a[(r, j)] * a[(c, j)];
            }
            m[r][c] = acc;
        }
        dmax = dmax.max(m[r][r].abs());
    }
    let delta = 1e-12 * dmax.max(1e-300);
    for (r, row) in m.iter_mut().enumerate().take(k) {
        row[r] += delta;
    }
    let mut yv = [0.0f64; N];
    yv[..k].copy_from_slice(b.as_slice());
    if cholesky_solve_stack(&mut m, k, &mut yv[..k]) {
        let mut ok = true;
        for j in 0..k {
            let mut acc = 0.0;
            for r in 0..k {
                acc += a[(r, j)] * yv[r];
            }
            x[j] = acc;
        }
        let bmax = b.amax();
        for r in 0..k {
            let mut acc = 0.0;
            for j in 0..k {
                acc += a[(r, j)] * x[j];
            }
            ok &= (acc - b[r]).abs() <= 1e-9 * (1.0 + bmax);
        }
        if ok {
            return true;
        }
    }
    false
}

/// Solves S x = r in place (`x` holds r on entry) for symmetric positive definite S (its
/// lower triangle is overwritten by the Cholesky factor L, S = L Lᵀ); false if a pivot is not
/// positive or the solution not finite.
fn cholesky_solve_stack<const N: usize>(s: &mut [[f64; N]; N], n: usize, x: &mut [f64]) -> bool {
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(p, q)| p * q).sum::<f64>();
    for j in 0..n {
        let d = s[j][j] - dot(&s[j][..j], &s[j][..j]);
        if d.is_nan() || d <= 0.0 {
            return false;
        }
        let l = d.sqrt();
        s[j][j] = l;
        for i in j + 1..n {
            s[i][j] = (s[i][j] - dot(&s[i][..j], &s[j][..j])) / l;
        }
    }
    // L y = r, then Lᵀ x = y
    for i in 0..n {
        x[i] = (x[i] - dot(&s[i][..i], &x[..i])) / s[i][i];
    }
    for i in (0..n).rev() {
        let v: f64 = s[i + 1..n]
            .iter()
            .zip(&x[i + 1..n])
            .map(|(row, xk)| row[i] * xk)
            .sum();
        x[i] = (x[i] - v) / s[i][i];
    }
    x[..n].iter().all(|v| v.is_finite())
}

/// Largest system solved on the stack.
const ELIM_N: usize = 12;

/// Gaussian elimination with complete pivoting (on the stack for n ≤ 12) into `out`; false
/// when a pivot falls below `tol` of the largest (rank-deficient) or the result is not finite.
fn eliminate_into(a: &DMatrix<f64>, b: &DVector<f64>, tol: f64, out: &mut [f64]) -> bool {
    // the smallest stack array that holds the system (the elimination is the same)
    match a.nrows() {
        0..=4 => eliminate_on::<4>(a, b, tol, out),
        5..=8 => eliminate_on::<8>(a, b, tol, out),
        9..=ELIM_N => eliminate_on::<ELIM_N>(a, b, tol, out),
        _ => match a.clone().full_piv_lu().solve(b) {
            Some(x) => {
                out.copy_from_slice(x.as_slice());
                true
            }
            None => false,
        },
    }
}

fn eliminate_on<const N: usize>(
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    tol: f64,
    out: &mut [f64],
) -> bool {
    let n = a.nrows();
    let mut m = [[0.0f64; N]; N];
    let mut r = [0.0f64; N];
    for i in 0..n {
        for j in 0..n {
            m[i][j] = a[(i, j)];
        }
        r[i] = b[i];
    }
    eliminate_stack(&mut m, &mut r, n, tol, out)
}

/// Complete-pivoting elimination of the leading n × n block of `m` with right side `r`.
fn eliminate_stack<const N: usize>(
    m: &mut [[f64; N]; N],
    r: &mut [f64; N],
    n: usize,
    tol: f64,
    out: &mut [f64],
) -> bool {
    let mut perm = [0usize; N];
    for (i, p) in perm.iter_mut().enumerate() {
        *p = i;
    }
    let mut hi = 0.0f64;
    for k in 0..n {
        let (mut pi, mut pj, mut best) = (k, k, 0.0f64);
        for (i, row) in m.iter().enumerate().take(n).skip(k) {
            for (j, x) in row.iter().enumerate().take(n).skip(k) {
                if x.abs() > best {
                    (pi, pj, best) = (i, j, x.abs());
                }
            }
        }
        hi = hi.max(best);
        if best == 0.0 || best <= tol * hi {
            return false;
        }
        m.swap(k, pi);
        r.swap(k, pi);
        if pj != k {
            for row in m.iter_mut().take(n) {
                row.swap(k, pj);
            }
            perm.swap(k, pj);
        }
        let pivot_row = m[k];
        let inv = 1.0 / pivot_row[k];
        for i in k + 1..n {
            let f = m[i][k] * inv;
            if f != 0.0 {
                for (x, p) in m[i][k..n].iter_mut().zip(&pivot_row[k..n]) {
                    *x -= f * p;
                }
                r[i] -= f * r[k];
            }
        }
    }
    let mut x = [0.0f64; N];
    for k in (0..n).rev() {
        let mut acc = r[k];
        for j in k + 1..n {
            acc -= m[k][j] * x[j];
        }
        x[k] = acc / m[k][k];
    }
    for k in 0..n {
        out[perm[k]] = x[k];
    }
    out.iter().all(|v| v.is_finite())
}

/// δ = M⁻¹Jᵀ (J M⁻¹ Jᵀ)⁺ r: the minimum-M-norm correction with J δ = r.
/// `singular` as in [`solve_small_into`].
fn min_norm_correction(
    rows: &[&DVector<f64>],
    res: &[f64],
    minv: &DVector<f64>,
    singular: &mut bool,
) -> DVector<f64> {
    let k = rows.len();
    let mut a = DMatrix::zeros(k, k);
    for r in 0..k {
        for c in 0..k {
            a[(r, c)] = rows[r]
                .as_slice()
                .iter()
                .zip(minv.as_slice())
                .zip(rows[c].as_slice())
                .map(|((x, m), y)| x * m * y)
                .sum();
        }
    }
    let mut lam = DVector::zeros(k);
    solve_small_into(&a, &DVector::from_column_slice(res), &mut lam, singular);
    let mut d = DVector::zeros(minv.len());
    for r in 0..k {
        d.axpy(lam[r], rows[r], 1.0);
    }
    d.component_mul(minv)
}

/// Run the event-driven integration of a scene.
pub fn run(scene: &Scene, observer: &mut dyn Observer) -> Result<RunOutput, SolverError> {
    let mut it = Integration::start(scene)?;
    it.advance(observer, false)?;
    Ok(it.finish(observer))
}

/// Runs of scenes that differ only in their contacts' friction coefficients are the same motion
/// until the first contact event (μ enters nowhere else): that part is integrated once, and
/// each variant continues from there. The outputs are those of separate runs.
pub struct FrictionFork<'a> {
    shared: Integration<'a>,
    /// A contact event was reached (else the shared run is already the whole run).
    paused: bool,
}

impl<'a> FrictionFork<'a> {
    /// Integrate `scene` up to its first contact event. An error here is each variant's own
    /// error: run them separately then.
    pub fn new(scene: &'a Scene) -> Result<Self, SolverError> {
        let mut shared = Integration::start(scene)?;
        let paused = shared.advance(&mut Silent, true)?;
        Ok(Self { shared, paused })
    }

    /// The run of `scene` from the shared part; None if `scene` differs from the shared one in
    /// more than contact friction, or is integrated by another method. The shared part counts
    /// in its wall time.
    pub fn run(&self, scene: &Scene) -> Option<Result<RunOutput, SolverError>> {
        if scene.settings.method != crate::scene::Method::Event
            || !differs_only_in_friction(self.shared.eng.scene, scene)
        {
            return None;
        }
        let mut it = self.shared.fork(scene);
        if self.paused
            && let Err(e) = it.advance(&mut Silent, false)
        {
            return Some(Err(e));
        }
        Some(Ok(it.finish(&mut Silent)))
    }
}

/// `b` is `a` with other contact friction coefficients (nothing else differs).
fn differs_only_in_friction(a: &Scene, b: &Scene) -> bool {
    let contacts = |s: &Scene| {
        let mut c = s.contacts.clone();
        for x in &mut c {
            x.mu = 0.0;
        }
        format!("{c:?}")
    };
    let records_equal = a.supports.len() == b.supports.len()
        && a.supports.iter().zip(&b.supports).all(|(x, y)| {
            x.name == y.name
                && x.factor == y.factor
                && match (&x.motion, &y.motion) {
                    (crate::scene::Motion::Record(g), crate::scene::Motion::Record(h)) => {
                        std::sync::Arc::ptr_eq(g, h) || **g == **h
                    }
                    (m1, m2) => format!("{m1:?}") == format!("{m2:?}"),
                }
        });
    records_equal
        && contacts(a) == contacts(b)
        && format!("{:?}", a.bodies) == format!("{:?}", b.bodies)
        && format!("{:?}", a.springs) == format!("{:?}", b.springs)
        && format!("{:?}", a.hysteretic) == format!("{:?}", b.hysteretic)
        && format!("{:?}", a.mass_damping) == format!("{:?}", b.mass_damping)
        && format!("{:?}", a.settings) == format!("{:?}", b.settings)
        && a.mass == b.mass
        && a.loads == b.loads
        && a.q0 == b.q0
        && a.v0 == b.v0
}

/// A run in progress: the engine and the integrator's state between steps.
struct Integration<'a> {
    eng: Engine<'a>,
    breakpoints: Vec<f64>,
    bp: usize,
    next_out: usize,
    ctrl: Controller,
    f0: DVector<f64>,
    h: f64,
    h_min: f64,
    batcher: Batcher,
    ws: dopri::Workspace,
    y0: DVector<f64>,
    fns: Vec<EventFn>,
    armed: Vec<bool>,
    rhs_evals: usize,
    /// Seconds spent so far.
    wall: f64,
    /// Events located at `eng.t` (in `eng.cluster`) and not applied yet: the run paused there.
    pending: bool,
}

impl<'a> Integration<'a> {
    /// The initial state, its contact resolution and the first step's data.
    fn start(scene: &'a Scene) -> Result<Self, SolverError> {
        let wall = Instant::now();
        let n = scene.ndof();
        let st = &scene.settings;
        let mut y = DVector::zeros(2 * n + LEDGER_TERMS);
        y.rows_mut(0, n).copy_from(&scene.q0);
        y.rows_mut(n, n).copy_from(&scene.v0);
        let mut laws: Vec<Hysteretic> = scene.hysteretic.iter().map(|h| h.law.clone()).collect();
        let mut eng = Engine {
            scene,
            laws: Vec::new(),
            state: vec![ContactState::Open; scene.contacts.len()],
            minv: scene.mass.map(|m| 1.0 / m),
            n,
            t: 0.0,
            y,
            impact_normal: 0.0,
            impact_tangential: 0.0,
            e0: 0.0,
            energy_scale: 0.0,
            out: RunOutput::new(scene),
            last_impacts: vec![Vec::new(); scene.contacts.len()],
            burst: vec![(f64::NEG_INFINITY, 0); scene.contacts.len()],
            force_scale: 0.0,
            jac: DVector::zeros(n),
            last_event_values: None,
            scratch: Scratch::default(),
            event_frame: Default::default(),
            arm_values: Vec::new(),
            event_qv: (DVector::zeros(0), DVector::zeros(0)),
            defo: Vec::new(),
            locate: LocateScratch::default(),
            forces: ForceModel::new(scene),
            cluster: Vec::new(),
            proj: ProjectScratch::default(),
            fns_generation: 0,
            sample_rows: Default::default(),
        };
        // initial hysteretic directions from the initial deformation rates
        {
            let q = eng.q();
            let v = eng.v();
            for (j, el) in scene.hysteretic.iter().enumerate() {
                let (e, ed, _) =
                    scene.deformation(&el.attachment, el.support, 0.0, &q, &v, &mut eng.jac);
                laws[j].set_direction(e, if ed < 0.0 { -1.0 } else { 1.0 });
            }
        }
        eng.laws = laws;
        {
            let q = eng.q();
            let v = eng.v();
            for c in &scene.contacts {
                let k = scene.contact_kinematics(c, &q, &v);
                if k.gap < -st.gap_tol {
                    return Err(SolverError::InitialPenetration {
                        contact: c.name.clone(),
                        gap: k.gap,
                    });
                }
            }
            eng.e0 = scene.kinetic_energy(&v) + scene.spring_energy(0.0, &q, &v);
            let mut h = DVector::zeros(n);
            smooth_forces_laws(scene, &eng.laws, 0.0, &q, &v, &mut h, &mut eng.jac);
            eng.force_scale = h.amax().max(scene.mass.amax() * 1e-6);
        }
        eng.out.stats.step_control = vec![0; 2 * n];
        // the output grid, and room for the rows around events
        eng.out.keep_history = st.keep_history;
        if st.keep_history {
            let grid = (st.t_end / st.output_dt).ceil().min(1e7) as usize;
            eng.out.samples.reserve(grid + grid / 8 + 16);
        }
        // the initial instant is a pre-event sample if resolving it makes events, else a grid one
        let n_events = eng.out.events.len();
        let initial = {
            let mut silent = RunOutput::new(scene);
            std::mem::swap(&mut eng.out, &mut silent);
            let r = eng.record_sample(SampleKind::PreEvent);
            std::mem::swap(&mut eng.out, &mut silent);
            r?;
            silent.samples.pop()
        };
        eng.resolve()?;
        eng.scratch.mode_singular = false;
        (eng.proj.pos_singular, eng.proj.vel_singular) = (false, false);
        if eng.out.events.len() > n_events {
            if let Some(pre) = initial {
                eng.out.record(pre.view());
            }
            eng.record_sample(SampleKind::PostEvent)?;
        } else {
            eng.record_sample(SampleKind::Grid)?;
        }
        let mut f0 = DVector::zeros(y_len(n));
        {
            let y0 = eng.y.clone();
            eng.rhs(0.0, &y0, &mut f0)?;
        }
        let mut h = dopri::initial_h(&eng.y, &f0, st.rtol, st.atol, 2 * n).min(st.t_end / 10.0);
        if st.h_max > 0.0 {
            h = h.min(st.h_max);
        }
        let fns = eng.event_fns();
        let armed = arm(&mut eng, &fns)?;
        Ok(Self {
            eng,
            breakpoints: scene.breakpoints(),
            bp: 0,
            next_out: 1,
            ctrl: Controller::default(),
            f0,
            h,
            h_min: 1e-14 * st.t_end.max(1.0),
            batcher: Batcher::new(),
            ws: dopri::Workspace::default(),
            y0: DVector::zeros(y_len(n)),
            fns,
            armed,
            rhs_evals: 1,
            wall: wall.elapsed().as_secs_f64(),
            pending: false,
        })
    }

    /// The same state continued with `scene`, which differs from this run's only in contact
    /// friction ([`differs_only_in_friction`]); caches are left behind.
    fn fork<'b>(&self, scene: &'b Scene) -> Integration<'b> {
        let e = &self.eng;
        let eng = Engine {
            scene,
            laws: e.laws.clone(),
            state: e.state.clone(),
            minv: e.minv.clone(),
            n: e.n,
            t: e.t,
            y: e.y.clone(),
            impact_normal: e.impact_normal,
            impact_tangential: e.impact_tangential,
            e0: e.e0,
            energy_scale: e.energy_scale,
            out: e.out.clone(),
            last_impacts: e.last_impacts.clone(),
            burst: e.burst.clone(),
            force_scale: e.force_scale,
            jac: e.jac.clone(),
            last_event_values: e.last_event_values.clone(),
            scratch: Scratch::default(),
            event_frame: Default::default(),
            arm_values: e.arm_values.clone(),
            event_qv: (DVector::zeros(0), DVector::zeros(0)),
            defo: Vec::new(),
            locate: LocateScratch::default(),
            forces: ForceModel::new(scene),
            cluster: e.cluster.clone(),
            proj: ProjectScratch::default(),
            fns_generation: e.fns_generation,
            sample_rows: Default::default(),
        };
        Integration {
            eng,
            breakpoints: self.breakpoints.clone(),
            bp: self.bp,
            next_out: self.next_out,
            ctrl: self.ctrl.clone(),
            f0: self.f0.clone(),
            h: self.h,
            h_min: self.h_min,
            batcher: Batcher::new(),
            ws: dopri::Workspace::default(),
            y0: self.y0.clone(),
            fns: self.fns.clone(),
            armed: self.armed.clone(),
            rhs_evals: self.rhs_evals,
            wall: self.wall,
            pending: self.pending,
        }
    }

    /// Integrate to the end, or, with `pause_at_contact`, until a contact event is located
    /// (returns true, the event not yet applied).
    fn advance(
        &mut self,
        observer: &mut dyn Observer,
        pause_at_contact: bool,
    ) -> Result<bool, SolverError> {
        let wall = Instant::now();
        let r = self.advance_in(observer, pause_at_contact);
        self.wall += wall.elapsed().as_secs_f64();
        r
    }

    fn advance_in(
        &mut self,
        observer: &mut dyn Observer,
        pause_at_contact: bool,
    ) -> Result<bool, SolverError> {
        let Integration {
            eng,
            breakpoints,
            bp,
            next_out,
            ctrl,
            f0,
            h,
            h_min,
            batcher,
            ws,
            y0,
            fns,
            armed,
            rhs_evals,
            pending,
            ..
        } = self;
        let scene = eng.scene;
        let st = &scene.settings;
        let n = eng.n;
        macro_rules! rhs_of {
            ($eng:expr) => {
                |t: f64, y: &DVector<f64>, out: &mut DVector<f64>| {
                    *rhs_evals += 1;
                    $eng.rhs(t, y, out)
                }
            };
        }
        loop {
            let found;
            if *pending {
                *pending = false;
                found = Some(eng.t);
            } else {
                if eng.t >= st.t_end {
                    return Ok(false);
                }
                if eng.out.stats.steps_accepted + eng.out.stats.steps_rejected >= st.max_steps {
                    return Err(SolverError::TooManySteps {
                        t: eng.t,
                        limit: st.max_steps,
                    });
                }
                while *bp < breakpoints.len() && breakpoints[*bp] <= eng.t * (1.0 + 1e-15) {
                    *bp += 1;
                }
                let t_stop = if *bp < breakpoints.len() {
                    breakpoints[*bp].min(st.t_end)
                } else {
                    st.t_end
                };
                let mut hh = h.min(t_stop - eng.t);
                if st.h_max > 0.0 {
                    hh = hh.min(st.h_max);
                }
                if t_stop - eng.t - hh < 1e-12 * hh {
                    hh = t_stop - eng.t;
                }
                y0.as_mut_slice().copy_from_slice(eng.y.as_slice());
                let t0 = eng.t;
                dopri::step_into(
                    ws,
                    &mut rhs_of!(eng),
                    t0,
                    y0,
                    f0,
                    hh,
                    st.rtol,
                    st.atol,
                    2 * n,
                )?;
                let step = &ws.step;
                let finite = step.y1.as_slice().iter().all(|x| x.is_finite());
                if !finite || step.error > 1.0 {
                    eng.out.stats.steps_rejected += 1;
                    *h = if finite {
                        ctrl.next_h(hh, step.error, false)
                    } else {
                        hh * 0.25
                    };
                    if *h < *h_min {
                        return Err(if finite {
                            SolverError::StepTooSmall { t: eng.t, h: *h }
                        } else {
                            SolverError::NonFinite { t: eng.t }
                        });
                    }
                    continue;
                }
                eng.out.stats.steps_accepted += 1;
                if let Some(c) = eng.out.stats.step_control.get_mut(step.worst) {
                    *c += 1;
                }
                *h = ctrl.next_h(hh, step.error, true);
                // event search on the dense output
                found = locate_event(eng, step, fns, armed)?;
                let t1 = found.unwrap_or(step.t1());
                track_peaks(&mut eng.out, step, t1, n, y0);
                // grid output inside (t0, t1]
                while (*next_out as f64) * st.output_dt <= t1 * (1.0 + 1e-14) && eng.t < st.t_end {
                    let tg = (*next_out as f64) * st.output_dt;
                    if tg > t1 {
                        break;
                    }
                    eng.t = tg.min(st.t_end);
                    step.dense_at_into(eng.t, &mut eng.y);
                    eng.record_sample(SampleKind::Grid)?;
                    *next_out += 1;
                }
                eng.t = t1;
                if found.is_some() {
                    step.dense_at_into(t1, &mut eng.y);
                } else {
                    eng.y.as_mut_slice().copy_from_slice(step.y1.as_slice());
                }
                let contact = eng.cluster.iter().any(|f| {
                    !matches!(
                        f,
                        EventFn::Lower(_) | EventFn::Upper(_) | EventFn::Reversal(_)
                    )
                });
                if found.is_some() && pause_at_contact && contact {
                    *pending = true;
                    return Ok(true);
                }
            }
            let mut restart = false;
            if found.is_some() {
                let cluster = std::mem::take(&mut eng.cluster);
                for &f in &cluster {
                    eng.out.stats.events_located += 1;
                    process_event(eng, f)?;
                }
                eng.cluster = cluster;
                restart = true;
            } else if eng.state.iter().any(|s| *s != ContactState::Open) {
                restart = eng.project() > 0.0;
            }
            if restart {
                let y1 = eng.y.clone();
                let t = eng.t;
                (rhs_of!(eng))(t, &y1, f0)?;
                eng.event_fns_into(fns);
                arm_into(eng, fns, armed)?;
                // events already due at this instant (simultaneous crossings, e.g. symmetric
                // columns reversing together): process them now, before any step
                let mut done: Vec<EventFn> = Vec::new();
                while let Some(f) = due_now(eng, fns, &done)? {
                    done.push(f);
                    process_event(eng, f)?;
                    let y1 = eng.y.clone();
                    let t = eng.t;
                    (rhs_of!(eng))(t, &y1, f0)?;
                    eng.event_fns_into(fns);
                    arm_into(eng, fns, armed)?;
                }
            } else {
                f0.as_mut_slice().copy_from_slice(ws.step.f1.as_slice());
            }
            batcher.maybe(&eng.out, eng.t, observer)?;
        }
    }

    /// The output, with the final sample, statistics and summary.
    fn finish(mut self, observer: &mut dyn Observer) -> RunOutput {
        let wall = Instant::now();
        let eng = &mut self.eng;
        let st = &eng.scene.settings;
        if eng.out.last_sample_time().is_none_or(|t| t < st.t_end) {
            // a failure here leaves the last sample where it was
            let _ = eng.record_sample(SampleKind::Grid);
        }
        self.batcher.flush(&eng.out, eng.t, observer);
        eng.out.stats.rhs_evals = self.rhs_evals;
        eng.out.final_laws = eng.laws.clone();
        eng.out.stats.wall_time = self.wall + wall.elapsed().as_secs_f64();
        eng.out.finish(eng.energy_scale);
        std::mem::replace(&mut eng.out, RunOutput::new(eng.scene))
    }
}

/// Apply one located event at the current instant: a branch change of a hysteretic element,
/// or a contact event (the LCPs decide the new state).
fn process_event(eng: &mut Engine, f: EventFn) -> Result<(), SolverError> {
    eng.scratch.at = None;
    match f {
        EventFn::Lower(j) | EventFn::Upper(j) | EventFn::Reversal(j) => {
            let b = *eng.laws[j].branch();
            let e = eng.element_deformation(j).0;
            let (e_at, dir) = match f {
                EventFn::Lower(_) => (b.lower, -1.0),
                EventFn::Upper(_) => (b.upper, 1.0),
                _ => (e, -b.direction),
            };
            eng.laws[j].on_branch_end(e_at, dir);
            eng.out.stats.branch_events += 1;
        }
        _ => {
            eng.record_sample(SampleKind::PreEvent)?;
            eng.resolve()?;
            // a new contact mode: its constraints may or may not be redundant
            eng.scratch.mode_singular = false;
            (eng.proj.pos_singular, eng.proj.vel_singular) = (false, false);
            eng.record_sample(SampleKind::PostEvent)?;
        }
    }
    Ok(())
}

/// A function already past its threshold at the current instant (it crossed together with
/// the event just processed). Gaps count only while closing.
/// Uses the values [`arm`] has just computed at this instant.
fn due_now(
    eng: &mut Engine,
    fns: &[EventFn],
    done: &[EventFn],
) -> Result<Option<EventFn>, SolverError> {
    if eng.arm_values.len() != fns.len() {
        let y = std::mem::take(&mut eng.y);
        let mut vals = std::mem::take(&mut eng.arm_values);
        let r = eng.event_values_into(eng.t, &y, fns, &mut vals);
        eng.y = y;
        eng.arm_values = vals;
        r?;
    }
    for (k, f) in fns.iter().enumerate() {
        if eng.arm_values[k] < -eng.threshold(*f) && !done.contains(f) {
            if let EventFn::Gap(i) = *f {
                let gap_rate = eng.contact_kinematics_now(i).gap_rate;
                if gap_rate >= -eng.scene.settings.velocity_tol {
                    continue;
                }
            }
            eng.arm_values.clear();
            return Ok(Some(*f));
        }
    }
    eng.arm_values.clear();
    Ok(None)
}

/// Peaks of |q| over the step [t0, t1] from the dense output: the ends, and any interior
/// extremum (a sign change of q̇, located by Illinois), so peaks do not depend on the output
/// step.
fn track_peaks(out: &mut RunOutput, step: &dopri::Step, t1: f64, n: usize, y1: &mut DVector<f64>) {
    if out.step_peaks.len() != n {
        out.step_peaks = vec![(0.0, 0.0); n];
    }
    if t1 >= step.t1() {
        y1.as_mut_slice().copy_from_slice(step.y1.as_slice());
    } else {
        step.dense_at_into(t1, y1);
    }
    for k in 0..n {
        let mut consider = |t: f64, q: f64| {
            if q.abs() > out.step_peaks[k].0 {
                out.step_peaks[k] = (q.abs(), t);
            }
        };
        consider(step.t0, step.y0[k]);
        consider(t1, y1[k]);
        let (v0, v1) = (step.y0[n + k], y1[n + k]);
        if v0 * v1 < 0.0 {
            // the extremum: q̇ = 0 by Illinois on the dense output, to 1e-9 of the step (q is
            // flat there: its error is of order q̈ (1e-9 h)²)
            let sign = v0.signum();
            let Ok::<_, std::convert::Infallible>((a, b)) = bracket_root(
                0.0,
                (t1 - step.t0) / step.h,
                v0 * sign,
                v1 * sign,
                1e-9,
                |m| Ok(step.dense_component(m, n + k) * sign),
            );
            let th = 0.5 * (a + b);
            consider(step.t0 + th * step.h, step.dense_component(th, k));
        }
    }
}

fn y_len(n: usize) -> usize {
    2 * n + LEDGER_TERMS
}

/// Armed flags: a function is armed when it is known to be positive just after the start of a
/// phase — clearly positive, or zero and moving up (a separating gap, a slide or branch just
/// begun). Unarmed ones trigger only below −threshold (an inconsistent state the LCP repairs).
fn arm(eng: &mut Engine, fns: &[EventFn]) -> Result<Vec<bool>, SolverError> {
    let mut armed = Vec::new();
    arm_into(eng, fns, &mut armed)?;
    Ok(armed)
}

/// [`arm`] into `armed`.
fn arm_into(eng: &mut Engine, fns: &[EventFn], armed: &mut Vec<bool>) -> Result<(), SolverError> {
    eng.last_event_values = None;
    let y = std::mem::take(&mut eng.y);
    let mut vals = std::mem::take(&mut eng.arm_values);
    let r = eng.event_values_into(eng.t, &y, fns, &mut vals);
    eng.y = y;
    r?;
    let scene = eng.scene;
    let st = &scene.settings;
    armed.clear();
    armed.extend(fns.iter().zip(&vals).map(|(f, &val)| {
        let thr = eng.threshold(*f);
        match *f {
            // a gap at zero counts as positive if it opens
            EventFn::Gap(i) => {
                val > thr
                    || (val > -st.gap_tol
                        && eng.contact_kinematics_now(i).gap_rate > st.velocity_tol)
            }
            EventFn::SlideStop(_)
            | EventFn::Reversal(_)
            | EventFn::Lower(_)
            | EventFn::Upper(_) => val > -thr,
            EventFn::Release(_) | EventFn::StickSlip(_) => val > thr,
        }
    }));
    // they are also the start values of the next step's event search
    eng.last_event_values = Some((eng.t, vals.clone()));
    eng.arm_values = vals;
    Ok(())
}

/// First event in the step: sample the dense output at θ = ¼, ½, ¾, 1, then Illinois on the
/// bracketing interval down to `event_time_tol`. Returns t_event, the bracket end where the
/// function has crossed, with the events to apply there in `eng.cluster` ([`coalesce`]).
/// Updates the armed flags.
fn locate_event(
    eng: &mut Engine,
    step: &dopri::Step,
    fns: &[EventFn],
    armed: &mut [bool],
) -> Result<Option<f64>, SolverError> {
    if fns.is_empty() {
        return Ok(None);
    }
    let mut ls = std::mem::take(&mut eng.locate);
    let r = locate_event_in(eng, step, fns, armed, &mut ls);
    eng.locate = ls;
    r
}

/// Reused storage of [`locate_event`].
#[derive(Default)]
struct LocateScratch {
    thr: Vec<f64>,
    v_prev: Vec<f64>,
    t_prev: Vec<f64>,
    gaps: Vec<usize>,
    gap_fns: Vec<EventFn>,
    vals: Vec<f64>,
    v_end: Vec<f64>,
    y: DVector<f64>,
    roots: Vec<(f64, EventFn)>,
    /// `Engine::fns_generation` of the list `thr` and `gaps` were made for.
    listed: u64,
}

fn locate_event_in(
    eng: &mut Engine,
    step: &dopri::Step,
    fns: &[EventFn],
    armed: &mut [bool],
    ls: &mut LocateScratch,
) -> Result<Option<f64>, SolverError> {
    let LocateScratch {
        thr,
        v_prev,
        t_prev,
        gaps,
        gap_fns,
        vals,
        v_end,
        y,
        roots,
        listed,
    } = ls;
    // thresholds and the gap subset change only with the list of functions
    let fresh = *listed != eng.fns_generation || thr.len() != fns.len();
    if fresh {
        *listed = eng.fns_generation;
        thr.clear();
        thr.extend(fns.iter().map(|f| eng.threshold(*f)));
        gaps.clear();
        gaps.extend((0..fns.len()).filter(|&k| matches!(fns[k], EventFn::Gap(_))));
        gap_fns.clear();
        gap_fns.extend(gaps.iter().map(|&k| fns[k]));
    }
    let shifted = |v: f64, k: usize, armed: &[bool]| if armed[k] { v } else { v + thr[k] };
    // the end values first: the last stage evaluated the dynamics there (FSAL), which any
    // other evaluation would overwrite
    eng.event_values_into(step.t1(), &step.y1, fns, v_end)?;
    match eng.last_event_values.take() {
        Some((t, v)) if t == step.t0 && v.len() == fns.len() => *v_prev = v,
        _ => eng.event_values_into(step.t0, &step.y0, fns, v_prev)?,
    };
    t_prev.clear();
    t_prev.resize(fns.len(), step.t0);
    for (k, v) in v_prev.iter_mut().enumerate() {
        if armed[k] && *v <= 0.0 {
            // positive just after t0 by construction
            *v = f64::MIN_POSITIVE;
        }
    }
    // gaps (cheap, and a corner may graze through in part of a step) at θ = ¼, ½, ¾, 1;
    // everything else at ½ and 1
    if y.len() != step.y0.len() {
        *y = DVector::zeros(step.y0.len());
    }
    for theta in [0.25, 0.5, 0.75, 1.0] {
        let full = theta == 0.5 || theta == 1.0;
        if !full && gaps.is_empty() {
            continue;
        }
        let t = step.t0 + theta * step.h;
        if theta == 1.0 {
            std::mem::swap(vals, v_end);
        } else {
            step.dense_at_into(t, y);
            if full {
                eng.event_values_into(t, y, fns, vals)?;
            } else {
                eng.event_values_into(t, y, gap_fns, vals)?;
            }
        }
        let index = |m: usize| if full { m } else { gaps[m] };
        roots.clear();
        for (m, &val) in vals.iter().enumerate() {
            let k = index(m);
            let a = shifted(v_prev[k], k, armed);
            let b = shifted(val, k, armed);
            if a > 0.0 && b <= 0.0 {
                let root = illinois(eng, step, fns, k, t_prev[k], t, a, b, armed[k], thr[k])?;
                roots.push((root, fns[k]));
            }
        }
        if !roots.is_empty() {
            roots.sort_by(|a, b| a.0.total_cmp(&b.0));
            let window = eng.scene.settings.branch_window;
            return Ok(Some(coalesce(roots, window, &mut eng.cluster)));
        }
        for (m, &val) in vals.iter().enumerate() {
            let k = index(m);
            if !armed[k] && val > thr[k] {
                armed[k] = true;
            }
            v_prev[k] = val;
            t_prev[k] = t;
        }
    }
    eng.last_event_values = Some((step.t1(), std::mem::take(v_prev)));
    Ok(None)
}

/// The events applied at once from the roots found in one sub-interval (sorted by time):
/// the first, and the branch events of other elements that follow it by at most `window` with
/// no contact event between (all at the time of the last of them, so that each element's
/// branch end has been reached when it changes branch). Returns that time; the events go into
/// `cluster`.
fn coalesce(roots: &[(f64, EventFn)], window: f64, cluster: &mut Vec<EventFn>) -> f64 {
    let element = |f: EventFn| match f {
        EventFn::Lower(j) | EventFn::Upper(j) | EventFn::Reversal(j) => Some(j),
        _ => None,
    };
    cluster.clear();
    let (t0, f0) = roots[0];
    cluster.push(f0);
    let mut t = t0;
    if element(f0).is_none() || window <= 0.0 {
        return t;
    }
    for &(tr, f) in &roots[1..] {
        let Some(j) = element(f) else { break };
        if tr - t0 > window {
            break;
        }
        if cluster.iter().any(|&g| element(g) == Some(j)) {
            continue;
        }
        cluster.push(f);
        t = tr;
    }
    t
}

#[allow(clippy::too_many_arguments)]
fn illinois(
    eng: &mut Engine,
    step: &dopri::Step,
    fns: &[EventFn],
    k: usize,
    ta: f64,
    tb: f64,
    fa: f64,
    fb: f64,
    armed: bool,
    thr: f64,
) -> Result<f64, SolverError> {
    let st = &eng.scene.settings;
    // a branch change applied up to `branch_window` late needs its instant no closer than that
    let tol = match fns[k] {
        EventFn::Lower(_) | EventFn::Upper(_) | EventFn::Reversal(_) => {
            st.event_time_tol.max(1e-6 * st.branch_window)
        }
        _ => st.event_time_tol,
    };
    let one = [fns[k]];
    let mut y = step.y0.clone();
    let n = eng.n;
    let (_, tb) = bracket_root(ta, tb, fa, fb, tol, |tm| {
        let theta = (tm - step.t0) / step.h;
        let mut fm = match fns[k] {
            // a branch function needs only its element: one body pose, one support
            EventFn::Lower(j) | EventFn::Upper(j) | EventFn::Reversal(j) => {
                for d in eng.scene.bodies[eng.element_body(j)]
                    .dofs
                    .into_iter()
                    .flatten()
                {
                    y[d] = step.dense_component(theta, d);
                    y[n + d] = step.dense_component(theta, n + d);
                }
                let (e, ed) = eng.element_deformation_in(j, tm, &y);
                let b = eng.laws[j].branch();
                match fns[k] {
                    EventFn::Lower(_) => e - b.lower,
                    EventFn::Upper(_) => b.upper - e,
                    _ => b.direction * ed,
                }
            }
            _ => {
                step.dense_into(theta, &mut y);
                eng.event_values(tm, &y, &one)?[0]
            }
        };
        if !armed {
            fm += thr;
        }
        Ok(fm)
    })?;
    Ok(tb)
}

/// Illinois (modified regula falsi) on [a, b] with f(a) = fa > 0 ≥ fb = f(b), until the
/// bracket is narrower than `tol` (or 4 ulp of b): the final bracket, b on the far side.
fn bracket_root<E>(
    mut a: f64,
    mut b: f64,
    mut fa: f64,
    mut fb: f64,
    tol: f64,
    mut f: impl FnMut(f64) -> Result<f64, E>,
) -> Result<(f64, f64), E> {
    let mut side = 0i32;
    for _ in 0..200 {
        if b - a <= tol.max(4.0 * f64::EPSILON * b.abs()) {
            break;
        }
        let mut m = (a * fb - b * fa) / (fb - fa);
        if !(m > a && m < b) {
            m = 0.5 * (a + b);
        }
        let fm = f(m)?;
        if fm > 0.0 {
            a = m;
            fa = fm;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            b = m;
            fb = fm;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
        if fm == 0.0 {
            break;
        }
    }
    Ok((a, b))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn solve(a: &DMatrix<f64>, b: &DVector<f64>) -> (DVector<f64>, bool) {
        let mut x = DVector::zeros(0);
        let mut singular = false;
        solve_small_into(a, b, &mut x, &mut singular);
        (x, singular)
    }

    #[test]
    fn regular_systems_are_solved_exactly() {
        let a = DMatrix::from_row_slice(3, 3, &[4.0, 1.0, 0.5, 1.0, 3.0, -1.0, 0.0, 2.0, 5.0]);
        let x0 = DVector::from_vec(vec![1.0, -2.0, 0.25]);
        let (x, singular) = solve(&a, &(&a * &x0));
        assert!(!singular);
        assert!((x - x0).amax() < 1e-14);
    }

    #[test]
    fn redundant_rows_get_the_minimum_norm_solution() {
        // two corners sticking on one face: rows 3 and 4 repeat 1 and 2 (rank 2 of 4), b
        // consistent; the minimum-norm solution is A⁺b, forces split equally
        for k in [4usize, 6, 10, 16] {
            let mut a = DMatrix::zeros(k, k);
            let base = DMatrix::from_row_slice(2, 2, &[2.0, 0.5, 0.5, 1.0]);
            for bi in 0..k / 2 {
                for bj in 0..k / 2 {
                    a.view_mut((2 * bi, 2 * bj), (2, 2)).copy_from(&base);
                }
            }
            let b = DVector::from_fn(k, |i, _| if i % 2 == 0 { 3.0 } else { -1.0 });
            let (x, singular) = solve(&a, &b);
            assert!(singular, "k = {k}");
            let pinv = a.clone().pseudo_inverse(1e-12).unwrap() * &b;
            assert!(
                (&x - &pinv).amax() < 1e-9 * pinv.amax(),
                "k = {k}: {x} vs {pinv}"
            );
            assert!((&a * &x - &b).amax() < 1e-9, "k = {k}");
            // equal split between the redundant copies
            assert!((x[0] - x[2]).abs() < 1e-9 && (x[1] - x[3]).abs() < 1e-9);
        }
    }

    #[test]
    fn cholesky_refuses_an_indefinite_matrix() {
        let mut s = [[0.0; ELIM_N]; ELIM_N];
        s[0][0] = 1.0;
        (s[1][0], s[0][1], s[1][1]) = (2.0, 2.0, 1.0);
        let mut x = [1.0, 1.0];
        assert!(!cholesky_solve_stack(&mut s, 2, &mut x));
        let mut s = [[0.0; ELIM_N]; ELIM_N];
        (s[0][0], s[1][0], s[0][1], s[1][1]) = (4.0, 2.0, 2.0, 3.0);
        let mut x = [2.0, 1.0];
        assert!(cholesky_solve_stack(&mut s, 2, &mut x));
        // [4 2; 2 3] x = [2 1] → x = [0.5, 0]
        assert!((x[0] - 0.5).abs() < 1e-15 && x[1].abs() < 1e-15);
    }
}
