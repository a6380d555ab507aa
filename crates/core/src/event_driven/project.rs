//! Projection of the state onto the constraints of the contact mode (minimum M-norm).

use super::engine::Engine;
use super::workspace::ProjectScratch;
use crate::output::ContactState;
use crate::scene::ContactKinematics;
use nalgebra::DVector;

/// Position passes at most (Newton on the gaps, which are nearly linear in q over a projection).
const PASSES: usize = 4;

/// Drift of a closed constraint left in place, as a fraction of `gap_tol` (g_N) and
/// `velocity_tol` (ġ_N, ġ_T): below it a projection would move the state by less than the
/// step's own error and restart the step sequence for nothing.
const DRIFT: f64 = 1e-4;

impl Engine<'_> {
    /// Minimum-M-norm projection of q onto g_N = 0 for closed contacts and open ones that
    /// penetrate (also those a correction pushes in), and of q̇ onto ġ_N = 0 (closed) and
    /// ġ_T = 0 (stick). A closed constraint's drift within [`DRIFT`] of the tolerances is left
    /// in place. Returns the largest correction made.
    pub(super) fn project(&mut self) -> f64 {
        let n = self.n;
        let mut ps = std::mem::take(&mut self.ws.project);
        if ps.q.len() != n {
            ps.q = DVector::zeros(n);
            ps.v = DVector::zeros(n);
        }
        ps.kin
            .resize_with(self.scene.contacts.len(), ContactKinematics::placeholder);
        let (mut moved, fresh, kin_fresh) = self.project_positions(&mut ps);
        if self.state.contacts.iter().any(|s| *s != ContactState::Open) {
            moved = moved.max(self.project_velocities(&mut ps, fresh, kin_fresh));
        }
        self.ws.project = ps;
        moved
    }

    /// q, q̇ of the state into the scratch, and the poses of q (contact kinematics need the
    /// poses only).
    fn load_poses(&self, ps: &mut ProjectScratch) {
        let n = self.n;
        let y = self.state.y.as_slice();
        ps.q.as_mut_slice().copy_from_slice(&y[..n]);
        ps.v.as_mut_slice().copy_from_slice(&y[n..2 * n]);
        self.scene
            .poses_into(&mut ps.fr, self.state.t, &ps.q, &ps.v);
    }

    /// The position passes: (largest correction, `fr` holds the poses of the current q, `kin`
    /// of every closed contact is of them).
    fn project_positions(&mut self, ps: &mut ProjectScratch) -> (f64, bool, bool) {
        let n = self.n;
        let scene = self.scene;
        let tol_gap = DRIFT * scene.settings.gap_tol;
        // closed contacts, and open ones that penetrate (after an event located past g_N = 0)
        self.load_poses(ps);
        ps.held.clear();
        for i in 0..self.state.contacts.len() {
            if self.state.contacts[i] != ContactState::Open
                || scene.contact_rates(&ps.fr, &scene.contacts[i]).0 < 0.0
            {
                ps.held.push(i);
            }
        }
        let mut moved = 0.0f64;
        let (mut fresh, mut kin_fresh) = (true, false);
        if ps.held.is_empty() {
            return (moved, fresh, kin_fresh);
        }
        for pass in 0..PASSES {
            if pass > 0 {
                self.load_poses(ps);
                fresh = true;
            }
            let ProjectScratch {
                fr,
                kin,
                held,
                res,
                pos_singular,
                correction,
                dq,
                ..
            } = ps;
            if pass > 0 {
                // a correction that turns a body may push another corner into its face
                for i in 0..scene.contacts.len() {
                    if !held.contains(&i) && scene.contact_rates(fr, &scene.contacts[i]).0 < 0.0 {
                        held.push(i);
                    }
                }
            }
            res.clear();
            for &i in held.iter() {
                scene.contact_kinematics_into(fr, &scene.contacts[i], &mut kin[i]);
                res.push(kin[i].gap);
            }
            // an open contact that penetrates is always moved back onto its face
            let contacts = &self.state.contacts;
            let within = |(r, &i): (&f64, &usize)| match contacts[i] {
                ContactState::Open => r.abs() < 1e-15,
                _ => r.abs() <= tol_gap,
            };
            if res.iter().zip(held.iter()).all(within) {
                kin_fresh = true;
                break;
            }
            let rows = |r: usize| &kin[held[r]].w_n;
            correction.solve(held.len(), rows, res, &self.minv, pos_singular, dq);
            moved = moved.max(dq.amax());
            for i in 0..n {
                self.state.y[i] -= dq[i];
            }
            fresh = false;
        }
        (moved, fresh, kin_fresh)
    }

    /// The velocity pass onto ġ_N = 0 (closed) and ġ_T = 0 (stick), from the position passes'
    /// poses and kinematics where they are still those of q (`fresh`, `kin_fresh`).
    fn project_velocities(&mut self, ps: &mut ProjectScratch, fresh: bool, kin_fresh: bool) -> f64 {
        let n = self.n;
        let scene = self.scene;
        let mut kin_fresh = kin_fresh;
        if !fresh {
            self.load_poses(ps);
            kin_fresh = false;
        }
        let ProjectScratch {
            fr,
            kin,
            res,
            vel_singular,
            correction,
            dq,
            slots,
            ..
        } = ps;
        res.clear();
        for (i, st) in self.state.contacts.iter().enumerate() {
            if *st != ContactState::Open && !kin_fresh {
                scene.contact_kinematics_into(fr, &scene.contacts[i], &mut kin[i]);
            }
        }
        slots.clear();
        for (i, st) in self.state.contacts.iter().enumerate() {
            if *st != ContactState::Open {
                slots.push((i, false));
                res.push(kin[i].gap_rate);
                if *st == ContactState::Stick {
                    slots.push((i, true));
                    res.push(kin[i].slip_rate);
                }
            }
        }
        if res
            .iter()
            .all(|r| r.abs() <= DRIFT * scene.settings.velocity_tol)
        {
            return 0.0;
        }
        let kin = &*kin;
        let rows = |r: usize| match slots[r] {
            (i, false) => &kin[i].w_n,
            (i, true) => &kin[i].w_t,
        };
        correction.solve(slots.len(), rows, res, &self.minv, vel_singular, dq);
        for i in 0..n {
            self.state.y[n + i] -= dq[i];
        }
        dq.amax()
    }
}
