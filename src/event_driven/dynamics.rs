//! The constrained dynamics between events: M q̈ = h + Σ W λ with g̈_N = 0 for closed
//! contacts, g̈_T = 0 for sticking ones and λ_T = −μ s λ_N for sliding ones (paper eq. 1–4).

use super::engine::Engine;
use crate::linalg::solve_small_into;
use crate::output::ContactState;
use crate::run::SolverError;
use crate::scene::ContactKinematics;
use nalgebra::{DMatrix, DVector};

impl<'a> Engine<'a> {
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
        let n = self.n;
        let scene = self.scene;
        let nc = scene.contacts.len();
        let sc = &mut self.ws.dynamics;
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
            &self.state.laws,
            &sc.fr,
            &sc.v,
            &mut sc.h,
            &mut sc.elements,
        );
        sc.kin.resize_with(nc, ContactKinematics::placeholder);
        for ((c, st), k) in scene
            .contacts
            .iter()
            .zip(&self.state.contacts)
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
        for (i, st) in self.state.contacts.iter().enumerate() {
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
            match self.state.contacts[i] {
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
                && matches!(self.state.contacts[i], ContactState::Slide(s) if s != 0.0)
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
                if let ContactState::Slide(s) = self.state.contacts[i] {
                    sc.lam_t[i] = -scene.contacts[i].mu * s * lr;
                }
            }
        }
        sc.hold(t, y, all);
        Ok(())
    }

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
}
