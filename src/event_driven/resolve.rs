//! At an event: impacts by the velocity LCP (eq. 5–7) with the accumulation rule, then the
//! contact phase by the acceleration LCP (eq. 8–10), the projection onto the constraints and
//! the log of stick/slip/release transitions.

use super::engine::Engine;
use super::workspace::ProjectScratch;
use crate::contact::{Decision, solve_contact, solve_impact};
use crate::lemke::LcpError;
use crate::linalg::min_norm_correction;
use crate::output::{ContactState, EventKind, EventRecord};
use crate::run::SolverError;
use crate::scene::{ContactKinematics, smooth_forces};
use nalgebra::DVector;

impl<'a> Engine<'a> {
    /// Minimum-M-norm projection of q onto g_N = 0 for closed contacts, and of q̇ onto
    /// ġ_N = 0 (closed) and ġ_T = 0 (stick). Returns the largest correction made.
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
            scene.frame_into(&mut ps.fr, t, &ps.q, &ps.v);
        };
        // closed contacts, and open ones that penetrate (after an event located past g_N = 0)
        load(&mut ps, &self.state.y, self.state.t);
        ps.held.clear();
        for i in 0..self.state.contacts.len() {
            if self.state.contacts[i] != ContactState::Open
                || scene.contact_rates_in(&ps.fr, &scene.contacts[i]).0 < 0.0
            {
                ps.held.push(i);
            }
        }
        let mut moved = 0.0f64;
        if !ps.held.is_empty() {
            for _ in 0..3 {
                load(&mut ps, &self.state.y, self.state.t);
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
                    self.state.y[i] -= dq[i];
                }
            }
        }
        let closed = self.state.contacts.iter().any(|s| *s != ContactState::Open);
        if closed {
            load(&mut ps, &self.state.y, self.state.t);
            let ProjectScratch {
                fr,
                kin,
                res,
                vel_singular,
                ..
            } = &mut ps;
            res.clear();
            for (i, st) in self.state.contacts.iter().enumerate() {
                if *st != ContactState::Open {
                    scene.contact_kinematics_into(fr, &scene.contacts[i], &mut kin[i]);
                }
            }
            let mut rows: Vec<&DVector<f64>> = Vec::with_capacity(8);
            for (i, st) in self.state.contacts.iter().enumerate() {
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
                self.state.y[n + i] -= dv[i];
            }
        }
        self.ws.project = ps;
        moved
    }

    /// Decide the contact states at the current instant: impacts (eq. 5) until no closed
    /// contact approaches, then the acceleration LCP (eq. 8) for the closed ones.
    pub(super) fn resolve(&mut self) -> Result<(), SolverError> {
        self.ws.dynamics.at = None;
        self.ws.dynamics.mode_singular = false;
        (self.ws.project.pos_singular, self.ws.project.vel_singular) = (false, false);
        let scene = self.scene;
        let st = &scene.settings;
        let nc = scene.contacts.len();
        let before = self.state.contacts.clone();
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
                    let h = &self.state.last_impacts[i];
                    h.len() < 2 || {
                        let (t1, t0) = (h[h.len() - 1], h[h.len() - 2]);
                        (self.state.t - t1) < 0.999 * (t1 - t0)
                    }
                };
                let flight = self.state.last_impacts[i]
                    .last()
                    .map_or(f64::INFINITY, |t| self.state.t - t);
                let slow = speed < st.zeno_velocity || flight < st.min_event_spacing;
                if st.accumulation_rule && eps[a] > 0.0 && slow && shrinking {
                    eps[a] = 0.0;
                    let h = &self.state.last_impacts[i];
                    let est = if h.len() >= 2 {
                        let t1 = h[h.len() - 1];
                        let t0 = h[h.len() - 2];
                        let f_now = self.state.t - t1;
                        let f_prev = t1 - t0;
                        let r = if f_prev > 0.0 { f_now / f_prev } else { 0.0 };
                        if r > 0.0 && r < 1.0 {
                            self.state.t + f_now * r / (1.0 - r)
                        } else {
                            self.state.t
                        }
                    } else {
                        self.state.t
                    };
                    accumulated[a] = Some(est);
                }
            }
            let kin_set: Vec<&ContactKinematics> = set.iter().map(|&i| &kin[i]).collect();
            let imp = solve_impact(&kin_set, &eps, &mu, &self.minv, &st.lemke).map_err(|e| {
                SolverError::Lcp {
                    t: self.state.t,
                    what: "impact",
                    source: e,
                }
            })?;
            self.state.out.stats.lcp_solves += 1;
            self.state.out.stats.lemke_pivots += imp.pivots;
            for k in 0..self.n {
                self.state.y[self.n + k] += imp.velocity_jump[k];
            }
            for (a, &i) in set.iter().enumerate() {
                let de_n = imp.normal_impulse[a] * (kin[i].gap_rate + imp.gap_rate_after[a]) / 2.0;
                let de_t =
                    imp.tangential_impulse[a] * (kin[i].slip_rate + imp.slip_rate_after[a]) / 2.0;
                self.state.impact_normal += de_n;
                self.state.impact_tangential += de_t;
                if approaching.contains(&i) || imp.normal_impulse[a] > 0.0 {
                    impacted[i] = true;
                    self.check_burst(i)?;
                    let hist = &mut self.state.last_impacts[i];
                    hist.push(self.state.t);
                    if hist.len() > 3 {
                        hist.remove(0);
                    }
                    let sticks = imp.slip_rate_after[a].abs() <= st.velocity_tol.max(1e-12);
                    let record = EventRecord {
                        t: self.state.t,
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
                        self.state.out.accumulation_times.push((i, est));
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
                self.state.contacts[i] = ContactState::Open;
            }
        }
        if !closed.is_empty() {
            let mut h = DVector::zeros(self.n);
            smooth_forces(
                scene,
                Some(&self.state.laws),
                self.state.t,
                &q,
                &v,
                &mut h,
                &mut self.ws.jac,
            );
            self.state.force_scale = self.state.force_scale.max(h.amax());
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
                            t: self.state.t,
                            contacts: closed
                                .iter()
                                .map(|&i| scene.contacts[i].name.as_str())
                                .collect::<Vec<_>>()
                                .join(", "),
                            detail: "the acceleration LCP ends on a ray".into(),
                        }
                    }
                    e => SolverError::Lcp {
                        t: self.state.t,
                        what: "contact",
                        source: e,
                    },
                },
            )?;
            self.state.out.stats.lcp_solves += 1;
            self.state.out.stats.lemke_pivots += outcome.pivots;
            for (a, &i) in closed.iter().enumerate() {
                self.state.force_scale = self.state.force_scale.max(outcome.normal_force[a].abs());
                self.state.contacts[i] = match outcome.decision[a] {
                    Decision::Detach => ContactState::Open,
                    Decision::Stick => ContactState::Stick,
                    Decision::Slide(s) => ContactState::Slide(s),
                };
            }
            // Painlevé check for sliding contacts (non-uniqueness when the Delassus term is ≤ 0)
            for (a, &i) in closed.iter().enumerate() {
                if let ContactState::Slide(s) = self.state.contacts[i] {
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
                                t: self.state.t,
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
            let (b, a) = (before[i], self.state.contacts[i]);
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
                    t: self.state.t,
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
    pub(super) fn check_burst(&mut self, i: usize) -> Result<(), SolverError> {
        let st = &self.scene.settings;
        let (last, count) = self.state.burst[i];
        let count = if self.state.t - last < st.min_event_spacing {
            count + 1
        } else {
            0
        };
        self.state.burst[i] = (self.state.t, count);
        if count >= 16 {
            return Err(SolverError::StepCollapse {
                t: self.state.t,
                contact: self.scene.contacts[i].name.clone(),
                events: count,
                window: st.min_event_spacing,
            });
        }
        Ok(())
    }
}

pub(super) fn sgn(x: f64) -> f64 {
    if x >= 0.0 { 1.0 } else { -1.0 }
}
