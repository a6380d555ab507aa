//! The constrained dynamics between events: M q̈ = h + Σ W λ with g̈_N = 0 for closed
//! contacts, g̈_T = 0 for sticking ones and λ_T = −μ s λ_N for sliding ones (paper eq. 1–4).

use super::engine::Engine;
use super::resolve::check_painleve;
use super::workspace::Scratch;
use crate::hysteresis::Hysteretic;
use crate::linalg::solve_small_into;
use crate::output::ContactState;
use crate::run::SolverError;
use crate::scene::{ContactKinematics, ForceModel, Scene};
use nalgebra::{DMatrix, DVector};

impl Engine<'_> {
    /// Constrained dynamics in the current mode, M q̈ = h + Σ W λ with g̈_N = 0 (closed),
    /// g̈_T = 0 (stick), λ_T = −μ s λ_N (slide), into `self.ws.dynamics` (qdd, lam_n, lam_t, kin,
    /// power), without allocation once the buffers have their sizes. `all`: kinematics of
    /// every contact (for output); otherwise only the closed ones are computed (open contacts
    /// get a placeholder and carry no force).
    pub(super) fn dynamics_into(
        &mut self,
        t: f64,
        y: &DVector<f64>,
        all: bool,
    ) -> Result<(), SolverError> {
        let scene = self.scene;
        let contacts = &self.state.contacts;
        let minv = self.minv.as_slice();
        let sc = &mut self.ws.dynamics;
        if sc.holds(t, y, all) {
            return Ok(());
        }
        sc.at = None;
        sc.free_motion(
            scene,
            &self.forces,
            &self.state.laws,
            contacts,
            minv,
            t,
            y,
            all,
        );
        sc.constraint_slots(contacts);
        if !sc.slots.is_empty() {
            sc.assemble(scene, contacts, minv);
            // Painlevé: a sliding contact whose normal Delassus entry is not positive
            for (r, &(i, tangential)) in sc.slots.iter().enumerate() {
                if !tangential
                    && matches!(contacts[i], ContactState::Slide(s) if s != 0.0)
                    && !scene.contacts[i].law.frictionless()
                {
                    let w = &sc.kin[i].w_n;
                    let g = w
                        .as_slice()
                        .iter()
                        .zip(minv)
                        .map(|(x, m)| x * m * x)
                        .sum::<f64>();
                    check_painleve(t, &scene.contacts[i].name, sc.a[(r, r)], g)?;
                }
            }
            solve_small_into(&sc.a, &sc.b, &mut sc.lam, &mut sc.mode_singular);
            sc.apply_constraint_forces(scene, contacts, minv);
        }
        sc.hold(t, y, all);
        Ok(())
    }

    /// y' = (q̇, q̈, ledger rates) in the current contact mode.
    pub(super) fn rhs(
        &mut self,
        t: f64,
        y: &DVector<f64>,
        out: &mut DVector<f64>,
    ) -> Result<(), SolverError> {
        let n = self.n;
        self.dynamics_into(t, y, false)?;
        let d = &self.ws.dynamics;
        let o = out.as_mut_slice();
        o[..n].copy_from_slice(&y.as_slice()[n..2 * n]);
        o[n..2 * n].copy_from_slice(&d.qdd.as_slice()[..n]);
        // −λ·ġ (relative rates) is dissipated; −λ·∂g/∂t is the work of faces moved by the ground
        let (mut contact_loss, mut driven) = (0.0, 0.0);
        // λ = 0 outside the constraint rows, whose contacts come in order (a stuck one twice)
        let mut last = usize::MAX;
        for &(i, _) in &d.slots {
            if i != last {
                let k = &d.kin[i];
                contact_loss -= d.lam_n[i] * k.gap_rate + d.lam_t[i] * k.slip_rate;
                last = i;
            }
        }
        if self.forces.driven_bodies() {
            for i in 0..d.kin.len() {
                let k = &d.kin[i];
                driven -= d.lam_n[i] * k.driven_n + d.lam_t[i] * k.driven_t;
            }
        }
        o[2 * n..2 * n + 5].copy_from_slice(&[
            d.power.loads,
            d.power.supports + driven,
            d.power.damping,
            d.power.hysteretic,
            contact_loss,
        ]);
        Ok(())
    }
}

impl Scratch {
    /// Poses, smooth forces h and their powers, contact kinematics (closed contacts only
    /// unless `all`), λ = 0 and the unconstrained q̈ = M⁻¹ h at (t, y).
    #[allow(clippy::too_many_arguments)]
    fn free_motion(
        &mut self,
        scene: &Scene,
        forces: &ForceModel,
        laws: &[Hysteretic],
        contacts: &[ContactState],
        minv: &[f64],
        t: f64,
        y: &DVector<f64>,
        all: bool,
    ) {
        let n = minv.len();
        let nc = scene.contacts.len();
        if self.h.len() != n || self.qdd.len() != n {
            self.size(n);
        }
        let (q, v) = y.as_slice()[..2 * n].split_at(n);
        scene.frame_of(&mut self.fr, t, q, v);
        if self.elements.len() != scene.hysteretic.len() {
            self.elements.resize(scene.hysteretic.len(), (0.0, 0.0));
        }
        self.power = forces.eval_in(
            scene,
            laws,
            &self.fr,
            v,
            self.h.as_mut_slice(),
            &mut self.elements,
        );
        if self.kin.len() != nc {
            self.kin.resize_with(nc, ContactKinematics::placeholder);
        }
        for ((c, st), k) in scene.contacts.iter().zip(contacts).zip(self.kin.iter_mut()) {
            if all || *st != ContactState::Open {
                scene.contact_kinematics_into(&self.fr, c, k);
            } else {
                k.gap = f64::INFINITY;
                k.gap_rate = 0.0;
                k.slip_rate = 0.0;
            }
        }
        if self.lam_n.len() == nc && self.lam_t.len() == nc {
            // λ is nonzero only in the rows of the last evaluation's slots
            for &(i, _) in &self.slots {
                (self.lam_n[i], self.lam_t[i]) = (0.0, 0.0);
            }
        } else {
            for lam in [&mut self.lam_n, &mut self.lam_t] {
                lam.clear();
                lam.resize(nc, 0.0);
            }
        }
        for ((a, h), m) in self
            .qdd
            .as_mut_slice()
            .iter_mut()
            .zip(self.h.as_slice())
            .zip(minv)
        {
            *a = h * m;
        }
    }

    /// The constraint rows of the mode: (contact, tangential) for W_N of a closed contact and
    /// W_T of a sticking one.
    fn constraint_slots(&mut self, contacts: &[ContactState]) {
        self.slots.clear();
        for (i, st) in contacts.iter().enumerate() {
            match *st {
                ContactState::Open => {}
                ContactState::Slide(_) => self.slots.push((i, false)),
                ContactState::Stick => {
                    self.slots.push((i, false));
                    self.slots.push((i, true));
                }
            }
        }
    }

    /// Force directions F (W_N − μ s W_T for a sliding contact, else the row itself) and the
    /// system A λ = b with A = C M⁻¹ F, b = −(C q̈_free + bias) for the constraint rows C.
    fn assemble(&mut self, scene: &Scene, contacts: &[ContactState], minv: &[f64]) {
        let n = minv.len();
        let nc = scene.contacts.len();
        let k = self.slots.len();
        if self.forces.nrows() != n || self.forces.ncols() < k {
            self.forces = DMatrix::zeros(n, k.max(2 * nc));
        }
        for (r, &(i, tangential)) in self.slots.iter().enumerate() {
            let kin = &self.kin[i];
            let col = &mut self.forces.as_mut_slice()[r * n..(r + 1) * n];
            match contacts[i] {
                ContactState::Slide(s) if !scene.contacts[i].law.frictionless() && s != 0.0 => {
                    let mu_s = scene.contacts[i].law.mu * s;
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
        if self.a.nrows() != k {
            self.a = DMatrix::zeros(k, k);
            self.b = DVector::zeros(k);
        }
        let forces = &self.forces.as_slice()[..k * n];
        let (a, b) = (self.a.as_mut_slice(), self.b.as_mut_slice());
        for (r, (&slot, br)) in self.slots.iter().zip(b.iter_mut()).enumerate() {
            let (w, bias) = row(&self.kin, slot);
            *br = -(w.dot(&self.qdd) + bias);
            let w = &w.as_slice()[..n];
            // A is column-major: A[r, c] at c k + r
            for (f, arc) in forces.chunks_exact(n).zip(a[r..].iter_mut().step_by(k)) {
                let mut acc = 0.0;
                for ((wj, mj), fj) in w.iter().zip(minv).zip(f) {
                    acc += wj * mj * fj;
                }
                *arc = acc;
            }
        }
    }

    /// q̈ += M⁻¹ F λ; λ_N, λ_T per contact (λ_T = −μ s λ_N while sliding).
    fn apply_constraint_forces(&mut self, scene: &Scene, contacts: &[ContactState], minv: &[f64]) {
        let n = minv.len();
        for (r, &(i, tangential)) in self.slots.iter().enumerate() {
            let lr = self.lam[r];
            let f = &self.forces.as_slice()[r * n..(r + 1) * n];
            for ((a, fj), mj) in self.qdd.as_mut_slice().iter_mut().zip(f).zip(minv) {
                *a += lr * fj * mj;
            }
            if tangential {
                self.lam_t[i] = lr;
            } else {
                self.lam_n[i] = lr;
                if let ContactState::Slide(s) = contacts[i] {
                    self.lam_t[i] = scene.contacts[i].law.sliding_force(s, lr);
                }
            }
        }
    }
}
