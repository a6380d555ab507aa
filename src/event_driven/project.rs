//! Projection of the state onto the constraints of the contact mode (minimum M-norm).

use super::engine::Engine;
use super::workspace::ProjectScratch;
use crate::output::ContactState;
use crate::scene::ContactKinematics;
use nalgebra::DVector;

/// Position passes at most (Newton on the gaps, which are nearly linear in q over a projection).
const PASSES: usize = 4;

impl Engine<'_> {
    /// Minimum-M-norm projection of q onto g_N = 0 for closed contacts and open ones that
    /// penetrate (also those a correction pushes in), and of q̇ onto ġ_N = 0 (closed) and
    /// ġ_T = 0 (stick). Returns the largest correction made.
    pub(super) fn project(&mut self) -> f64 {
        let n = self.n;
        let scene = self.scene;
        let mut ps = std::mem::take(&mut self.ws.project);
        if ps.q.len() != n {
            ps.q = DVector::zeros(n);
            ps.v = DVector::zeros(n);
        }
        ps.kin
            .resize_with(scene.contacts.len(), ContactKinematics::placeholder);
        let load = |ps: &mut ProjectScratch, y: &DVector<f64>, t: f64| {
            ps.q.as_mut_slice().copy_from_slice(&y.as_slice()[..n]);
            ps.v.as_mut_slice().copy_from_slice(&y.as_slice()[n..2 * n]);
            // contact kinematics need the poses only
            scene.poses_into(&mut ps.fr, t, &ps.q, &ps.v);
        };
        // closed contacts, and open ones that penetrate (after an event located past g_N = 0)
        load(&mut ps, &self.state.y, self.state.t);
        ps.held.clear();
        for i in 0..self.state.contacts.len() {
            if self.state.contacts[i] != ContactState::Open
                || scene.contact_rates(&ps.fr, &scene.contacts[i]).0 < 0.0
            {
                ps.held.push(i);
            }
        }
        let mut moved = 0.0f64;
        // `fr`: the poses of the current q; `kin` of the held (all closed) contacts are of them
        let (mut fresh, mut kin_fresh) = (true, false);
        if !ps.held.is_empty() {
            for pass in 0..PASSES {
                if pass > 0 {
                    load(&mut ps, &self.state.y, self.state.t);
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
                } = &mut ps;
                if pass > 0 {
                    // a correction that turns a body may push another corner into its face
                    for i in 0..scene.contacts.len() {
                        if !held.contains(&i) && scene.contact_rates(fr, &scene.contacts[i]).0 < 0.0
                        {
                            held.push(i);
                        }
                    }
                }
                res.clear();
                for &i in held.iter() {
                    scene.contact_kinematics_into(fr, &scene.contacts[i], &mut kin[i]);
                    res.push(kin[i].gap);
                }
                if res.iter().all(|r| r.abs() < 1e-15) {
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
        }
        let closed = self.state.contacts.iter().any(|s| *s != ContactState::Open);
        if closed {
            if !fresh {
                load(&mut ps, &self.state.y, self.state.t);
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
            } = &mut ps;
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
            let kin = &*kin;
            let rows = |r: usize| match slots[r] {
                (i, false) => &kin[i].w_n,
                (i, true) => &kin[i].w_t,
            };
            correction.solve(slots.len(), rows, res, &self.minv, vel_singular, dq);
            let dv = &*dq;
            moved = moved.max(dv.amax());
            for i in 0..n {
                self.state.y[n + i] -= dv[i];
            }
        }
        self.ws.project = ps;
        moved
    }
}
