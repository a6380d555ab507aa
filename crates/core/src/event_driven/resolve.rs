//! At an event: impacts by the velocity LCP (eq. 5–7) with the accumulation rule, then the
//! contact phase by the acceleration LCP (eq. 8–10), the projection onto the constraints
//! ([`super::project`]) and the log of stick/slip/release transitions.

use super::engine::Engine;
use super::event_fn::EventFn;
use crate::contact::{Decision, ImpactOutcome, solve_contact, solve_impact};
use crate::lemke::LcpError;
use crate::output::{ContactState, EventKind, EventRecord};
use crate::run::SolverError;
use crate::scene::{ContactKinematics, smooth_forces};
use nalgebra::DVector;

impl Engine<'_> {
    /// Decide the contact states at the current instant: impacts (eq. 5–7) until no closed
    /// contact approaches, then the acceleration LCP (eq. 8–10) for the closed ones; project
    /// onto their constraints; log the transitions. `event` is the function whose crossing
    /// brought the run here, if any: it settles the LCP's degenerate answer for its contact
    /// ([`Engine::settle_crossing`]).
    pub(super) fn resolve(&mut self, event: Option<EventFn>) -> Result<(), SolverError> {
        self.ws.dynamics.at = None;
        self.ws.new_contact_mode();
        let before = self.state.contacts.clone();
        let mut impacted = vec![false; self.scene.contacts.len()];
        for _pass in 0..8 {
            if !self.impact_phase(&mut impacted)? {
                break;
            }
        }
        self.hold_slow_separations(&before, &impacted);
        self.contact_phase(event)?;
        self.project();
        self.check_left_approaching(&impacted);
        self.log_transitions(&before, &impacted)
    }

    /// No contact leaves the impacts approaching: after the passes (each LCP's v_N ≥ 0 holds to
    /// its accuracy, and a contact an LCP of a degenerate set left approaching by 1e-9 m/s is
    /// hit again by the next pass), the hold of slow ones and the contact phase, every contact
    /// hit is at rest or separating (`stats.approaching_after_impact` counts the exceptions; a
    /// debug build stops).
    fn check_left_approaching(&mut self, impacted: &[bool]) {
        if !impacted.contains(&true) {
            return;
        }
        let tol = self.scene.settings.velocity_tol;
        let kin = self.kinematics_now();
        for (i, k) in kin.iter().enumerate() {
            let left = impacted[i] && k.gap_rate < -tol;
            debug_assert!(
                !left,
                "contact {i} leaves the impacts approaching: {}",
                k.gap_rate
            );
            self.state.out.stats.approaching_after_impact += usize::from(left);
        }
    }

    /// After impacts: a contact closed before them (stick or slide) that they leave at
    /// g_N ≤ gap_tol separating slower than `zeno_velocity` stays closed, with the contacts the
    /// impacts closed: q̇ is projected (minimum M-norm) onto ġ_N = 0 of all of them, and the
    /// acceleration LCP (eq. 8–10) decides whether one detaches. This ends the Zeno sequence of
    /// two corners of one end that no single contact's accumulation rule ends: each slow
    /// impact of one corner lifting the other, flights shrinking geometrically while the end
    /// slides along its face. A contact the passes leave approaching slower than `zeno_velocity`
    /// is held the same way: the passes' LCPs of a degenerate set (the deck jammed between both
    /// abutments by two diagonal corners, ε = 1, μ = 1) return it at their own accuracy, a few
    /// nm/s, pass after pass, and the contact phase then detached it while it approached. The
    /// velocity change is below `zeno_velocity`.
    fn hold_slow_separations(&mut self, before: &[ContactState], impacted: &[bool]) {
        if !impacted.contains(&true) {
            return;
        }
        let st = &self.scene.settings;
        let kin = self.kinematics_now();
        let near = |i: usize| kin[i].gap <= st.gap_tol;
        let lifted =
            |i: usize| before[i] != ContactState::Open && kin[i].gap_rate > st.velocity_tol;
        let left = |i: usize| impacted[i] && kin[i].gap_rate < -st.velocity_tol;
        let held: Vec<usize> = (0..kin.len())
            .filter(|&i| near(i) && kin[i].gap_rate.abs() <= st.zeno_velocity)
            .filter(|&i| {
                lifted(i) || left(i) || (impacted[i] && kin[i].gap_rate.abs() <= st.velocity_tol)
            })
            .collect();
        if !held.iter().any(|&i| lifted(i) || left(i)) {
            return;
        }
        let rows: Vec<&DVector<f64>> = held.iter().map(|&i| &kin[i].w_n).collect();
        let res: Vec<f64> = held.iter().map(|&i| kin[i].gap_rate).collect();
        let mut singular = false;
        let dv = crate::linalg::min_norm_correction(&rows, &res, &self.minv, &mut singular);
        for k in 0..self.n {
            self.state.y[self.n + k] -= dv[k];
        }
        self.state.out.stats.held_after_impact += 1;
    }

    /// One impact pass (eq. 5–7) over the contacts with g_N ≤ gap_tol, if any of them
    /// approaches (ġ_N < −velocity_tol; else false): the velocity jump, the impact energies
    /// ΔT = Λᵀ(ġ⁺ + ġ⁻)/2 in relative rates (the loss in the frame of the faces) and the work
    /// −Λ·∂g/∂t of faces moved by the ground, the impact (and accumulation) events. `impacted` marks the contacts hit.
    fn impact_phase(&mut self, impacted: &mut [bool]) -> Result<bool, SolverError> {
        let scene = self.scene;
        let st = &scene.settings;
        let nc = scene.contacts.len();
        let kin = self.kinematics_now();
        let set: Vec<usize> = (0..nc).filter(|&i| kin[i].gap <= st.gap_tol).collect();
        let approaching: Vec<usize> = set
            .iter()
            .copied()
            .filter(|&i| kin[i].gap_rate < -st.velocity_tol)
            .collect();
        if approaching.is_empty() {
            return Ok(false);
        }
        // Newton's law ġ⁺ = −ε ġ⁻ for the approaching contacts; the others of the set (resting
        // or separating) only may not approach afterwards (ε = 0: ġ⁺ ≥ 0)
        let mut eps: Vec<f64> = set
            .iter()
            .map(|&i| {
                let closing = approaching.contains(&i);
                if closing {
                    scene.contacts[i].law.restitution
                } else {
                    0.0
                }
            })
            .collect();
        let mu: Vec<f64> = set.iter().map(|&i| scene.contacts[i].law.mu).collect();
        let mut accumulated = vec![None; set.len()];
        for (a, &i) in set.iter().enumerate() {
            if !st.accumulation_rule || eps[a] <= 0.0 || !approaching.contains(&i) {
                continue;
            }
            let rule = accumulation_rule(
                self.state.t,
                -kin[i].gap_rate,
                &self.state.last_impacts[i],
                st.zeno_velocity,
                st.min_event_spacing,
            );
            // a rebound slower than `zeno_velocity` (ε ġ⁻): its flight rises ġ⁺²/(2g̈) —
            // 1.6e-18 m at 3e-9 m/s against 2.8 m/s² (ε = 1e-4) — below the gap's rounding,
            // where no event can end it (the run stalled, locating it at its start again and
            // again); the contact closes now, as it would at its next impact
            let rule =
                rule.or((-kin[i].gap_rate * eps[a] < st.zeno_velocity).then_some(self.state.t));
            // a burst of impacts closer than min_event_spacing closes the contact even when the
            // flights do not shrink geometrically
            let (last, count) = self.state.burst[i];
            let burst = self.state.t - last < st.min_event_spacing && count + 1 >= BURST_CLOSES;
            if let Some(est) = rule.or(burst.then_some(self.state.t)) {
                eps[a] = 0.0;
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
        self.state.out.stats.lcp_regularized += usize::from(imp.regularization > 0.0);
        for k in 0..self.n {
            self.state.y[self.n + k] += imp.velocity_jump[k];
        }
        for (a, &i) in set.iter().enumerate() {
            let (p_n, p_t) = (imp.normal_impulse[a], imp.tangential_impulse[a]);
            let de_n = p_n * (kin[i].gap_rate + imp.gap_rate_after[a]) / 2.0;
            let de_t = p_t * (kin[i].slip_rate + imp.slip_rate_after[a]) / 2.0;
            self.state.impact_normal += de_n;
            self.state.impact_tangential += de_t;
            // ΔT = Λ·Wᵀ(q̇⁺ + q̇⁻)/2 = ΔT_rel − Λ·∂g/∂t: a face moved by the ground works on
            // the bodies
            self.state.y[2 * self.n + 1] -= p_n * kin[i].driven_n + p_t * kin[i].driven_t;
            if approaching.contains(&i) || imp.normal_impulse[a] > 0.0 {
                impacted[i] = true;
                self.log_impact(i, &kin[i], &imp, a, accumulated[a])?;
            }
        }
        Ok(true)
    }

    /// The impact event of contact `i` (row `a` of the impact LCP), and the accumulation event
    /// when the rule closed it; its impact history and Zeno guard.
    fn log_impact(
        &mut self,
        i: usize,
        kin: &ContactKinematics,
        imp: &ImpactOutcome,
        a: usize,
        accumulated: Option<f64>,
    ) -> Result<(), SolverError> {
        let st = &self.scene.settings;
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
            gap_rate_before: kin.gap_rate,
            gap_rate_after: imp.gap_rate_after[a],
            slip_rate_after: imp.slip_rate_after[a],
            sticks: (!self.scene.contacts[i].law.frictionless()).then_some(sticks),
            info: f64::NAN,
        };
        self.log(record.clone())?;
        if let Some(est) = accumulated {
            self.state.out.accumulation_times.push((i, est));
            self.log(EventRecord {
                kind: EventKind::Accumulation,
                info: est,
                ..record
            })?;
        }
        Ok(())
    }

    /// The contact phase (eq. 8–10): contacts closed at position and velocity level get their
    /// stick / slide / detach decision from the acceleration LCP; the others open. At the
    /// crossing of `event` the decision for its contact follows the crossing where the LCP is
    /// degenerate ([`Engine::settle_crossing`]).
    fn contact_phase(&mut self, event: Option<EventFn>) -> Result<(), SolverError> {
        let scene = self.scene;
        let st = &scene.settings;
        let nc = scene.contacts.len();
        let (q, v) = (self.q(), self.v());
        let kin = self.kinematics_now();
        let closed: Vec<usize> = (0..nc)
            .filter(|&i| kin[i].gap <= st.gap_tol && kin[i].gap_rate.abs() <= st.velocity_tol)
            .collect();
        for i in 0..nc {
            if !closed.contains(&i) {
                self.state.contacts[i] = ContactState::Open;
            }
        }
        if closed.is_empty() {
            return Ok(());
        }
        let mut h = DVector::zeros(self.n);
        let laws = Some(self.state.laws.as_slice());
        smooth_forces(scene, laws, self.state.t, &q, &v, &mut h, &mut self.ws.jac);
        self.state.force_scale = self.state.force_scale.max(h.amax());
        let mu: Vec<f64> = closed.iter().map(|&i| scene.contacts[i].law.mu).collect();
        let slide: Vec<Option<f64>> = closed
            .iter()
            .map(|&i| {
                let s = kin[i].slip_rate;
                (!scene.contacts[i].law.frictionless() && s.abs() > st.velocity_tol).then(|| sgn(s))
            })
            .collect();
        let kin_set: Vec<&ContactKinematics> = closed.iter().map(|&i| &kin[i]).collect();
        let outcome = solve_contact(&kin_set, &mu, &slide, &self.minv, &h, &st.lemke)
            .map_err(|e| self.contact_lcp_error(e, &closed, &slide))?;
        self.state.out.stats.lcp_solves += 1;
        self.state.out.stats.lemke_pivots += outcome.pivots;
        self.state.out.stats.lcp_regularized += usize::from(outcome.regularization > 0.0);
        for (a, &i) in closed.iter().enumerate() {
            self.state.force_scale = self.state.force_scale.max(outcome.normal_force[a].abs());
            let decision = self.settle_crossing(event, i, &outcome, a);
            self.state.contacts[i] = match decision {
                Decision::Detach => ContactState::Open,
                Decision::Stick => ContactState::Stick,
                Decision::Slide(s) => ContactState::Slide(s),
            };
        }
        // non-uniqueness of a sliding contact whose Delassus term is ≤ 0
        for (a, &i) in closed.iter().enumerate() {
            if let ContactState::Slide(s) = self.state.contacts[i] {
                let c = &scene.contacts[i];
                if !c.law.frictionless() && s != 0.0 {
                    let k = kin_set[a];
                    let wq = &k.w_n - &k.w_t * (c.law.mu * s);
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
                    check_painleve(self.state.t, &c.name, g, g0)?;
                }
            }
        }
        Ok(())
    }

    /// The decision for contact `i` (row `a` of the contact LCP) at the crossing of `event`.
    /// At the instant λ_N of a closed contact reaches zero ([`EventFn::Release`]) the LCP is
    /// degenerate, λ_N = 0 = g̈_N, and closed or open are both its answers to first order;
    /// the crossing says which follows: λ_N decreasing through 0 would pull, so the contact is
    /// released unless the LCP gives it a force above the event's threshold (a force another
    /// contact's change brought). (A stick on the cone's edge is left to the LCP: the friction
    /// of two corners on one face is split by its regularisation, not by the crossing.)
    fn settle_crossing(
        &self,
        event: Option<EventFn>,
        i: usize,
        outcome: &crate::contact::ContactOutcome,
        a: usize,
    ) -> Decision {
        let decision = outcome.decision[a];
        let Some(f) = event else {
            return decision;
        };
        let lam_n = outcome.normal_force[a];
        match f {
            EventFn::Release(j)
                if j == i && decision != Decision::Detach && lam_n <= self.threshold(f) =>
            {
                Decision::Detach
            }
            _ => decision,
        }
    }

    /// A failed contact LCP: a ray with sliding contacts is a Painlevé configuration.
    fn contact_lcp_error(
        &self,
        e: LcpError,
        closed: &[usize],
        slide: &[Option<f64>],
    ) -> SolverError {
        match e {
            LcpError::Ray { .. } if slide.iter().any(|s| s.is_some()) => SolverError::Painleve {
                t: self.state.t,
                contacts: closed
                    .iter()
                    .map(|&i| self.scene.contacts[i].name.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
                detail: "the acceleration LCP ends on a ray".into(),
            },
            e => SolverError::Lcp {
                t: self.state.t,
                what: "contact",
                source: e,
            },
        }
    }

    /// Stick, slip and release events of the contacts whose state changed (impacts were
    /// logged already).
    fn log_transitions(
        &mut self,
        before: &[ContactState],
        impacted: &[bool],
    ) -> Result<(), SolverError> {
        let scene = self.scene;
        for i in 0..scene.contacts.len() {
            let after = self.state.contacts[i];
            if let Some(kind) = transition(before[i], after, impacted[i]) {
                let k = self.contact_kinematics_now(i);
                self.log(EventRecord {
                    t: self.state.t,
                    contact: i,
                    kind,
                    normal: 0.0,
                    tangential: 0.0,
                    gap_rate_before: k.gap_rate,
                    gap_rate_after: k.gap_rate,
                    slip_rate_after: k.slip_rate,
                    sticks: Some(after == ContactState::Stick),
                    info: f64::NAN,
                })?;
            }
        }
        Ok(())
    }

    /// Guard against impact accumulation (Zeno): impacts in a row of one contact, each within
    /// `min_event_spacing` of the last, stop the run at 16 without the accumulation rule, at
    /// [`BURST_FAILS`] with it (the rule closes such a contact from the [`BURST_CLOSES`]th on).
    pub(super) fn check_burst(&mut self, i: usize) -> Result<(), SolverError> {
        let st = &self.scene.settings;
        let (last, count) = self.state.burst[i];
        let count = if self.state.t - last < st.min_event_spacing {
            count + 1
        } else {
            0
        };
        self.state.burst[i] = (self.state.t, count);
        let limit = if st.accumulation_rule {
            BURST_FAILS
        } else {
            16
        };
        if count >= limit {
            return Err(SolverError::StepCollapse {
                t: self.state.t,
                contact: self.scene.contacts[i].name.clone(),
                events: count,
                window: st.min_event_spacing,
                rule: st.accumulation_rule,
            });
        }
        Ok(())
    }
}

/// With the accumulation rule: the impact of a burst (impacts in a row within
/// `min_event_spacing`) from which the contact is closed, and the one at which the run stops.
const BURST_CLOSES: usize = 3;
const BURST_FAILS: usize = 64;

/// The accumulation rule: an impact at `t` of a contact whose flights shrink (the last one
/// shorter than 0.999 of the one before; or fewer than two impacts in `impacts`, the last
/// impact instants) and that is slow (`speed` < `zeno_velocity`, or within `min_spacing` of
/// the last impact) closes the contact (ε → 0). Returns the estimated accumulation instant,
/// t + f r/(1 − r) for the last flight f and flight ratio r (a geometric series; t if r is not
/// in (0, 1)), or None when the rule does not apply.
pub(super) fn accumulation_rule(
    t: f64,
    speed: f64,
    impacts: &[f64],
    zeno_velocity: f64,
    min_spacing: f64,
) -> Option<f64> {
    let k = impacts.len();
    let shrinking = k < 2 || (t - impacts[k - 1]) < 0.999 * (impacts[k - 1] - impacts[k - 2]);
    let flight = impacts.last().map_or(f64::INFINITY, |t1| t - t1);
    let slow = speed < zeno_velocity || flight < min_spacing;
    if !(slow && shrinking) {
        return None;
    }
    if k < 2 {
        return Some(t);
    }
    let (t1, t0) = (impacts[k - 1], impacts[k - 2]);
    let (f_now, f_prev) = (t - t1, t1 - t0);
    let r = if f_prev > 0.0 { f_now / f_prev } else { 0.0 };
    Some(if r > 0.0 && r < 1.0 {
        t + f_now * r / (1.0 - r)
    } else {
        t
    })
}

/// The event a change of contact state makes (an impact is logged as such, not as a stick or
/// slip from open).
fn transition(before: ContactState, after: ContactState, impacted: bool) -> Option<EventKind> {
    use ContactState::{Open, Slide, Stick};
    match (before, after) {
        (Stick, Slide(_)) => Some(EventKind::Slip),
        (Slide(s0), Slide(s1)) if s0 != s1 => Some(EventKind::Slip),
        (Slide(_), Stick) => Some(EventKind::Stick),
        (Open, Stick) if !impacted => Some(EventKind::Stick),
        (Open, Slide(_)) if !impacted => Some(EventKind::Slip),
        (Stick | Slide(_), Open) => Some(EventKind::Release),
        _ => None,
    }
}

/// A sliding contact whose Delassus term W_Nᵀ M⁻¹ (W_N − μ s W_T) = `delassus` is not positive
/// (relative to `scale` = W_Nᵀ M⁻¹ W_N) makes the contact problem non-unique (Painlevé).
pub(super) fn check_painleve(
    t: f64,
    contact: &str,
    delassus: f64,
    scale: f64,
) -> Result<(), SolverError> {
    if delassus <= 1e-12 * scale {
        return Err(SolverError::Painleve {
            t,
            contacts: contact.to_string(),
            detail: format!("W_Nᵀ M⁻¹ (W_N − μ s W_T) = {delassus:.4e} ≤ 0 while sliding"),
        });
    }
    Ok(())
}

/// sign(x), with sign(0) = 1.
pub(super) fn sgn(x: f64) -> f64 {
    if x >= 0.0 { 1.0 } else { -1.0 }
}

#[cfg(test)]
mod tests {
    use super::{accumulation_rule, transition};
    use crate::output::{ContactState, EventKind};

    #[test]
    fn accumulation_instant_is_the_sum_of_the_geometric_flights() {
        // a ball bouncing with ε = 0.5 on a floor: flights 1, 0.5, 0.25 … from t = 0; the
        // impacts at 1, 1.5, 1.75; the series ends at 2
        let impacts = [1.0, 1.5];
        let t = 1.75;
        let slow = 1e-3;
        assert_eq!(
            accumulation_rule(t, 0.5, &impacts, slow, 1e-6),
            None,
            "fast impact"
        );
        let est = accumulation_rule(t, 1e-4, &impacts, slow, 1e-6).unwrap();
        assert!((est - 2.0).abs() < 1e-15, "{est}");
        // within the spacing counts as slow whatever the speed
        let est = accumulation_rule(t, 0.5, &impacts, slow, 0.3).unwrap();
        assert!((est - 2.0).abs() < 1e-15);
        // flights that do not shrink: no accumulation
        assert_eq!(accumulation_rule(2.1, 1e-4, &impacts, slow, 1e-6), None);
        // too few impacts to estimate: the rule closes the contact now
        assert_eq!(accumulation_rule(0.3, 1e-4, &[], slow, 1e-6), Some(0.3));
        assert_eq!(accumulation_rule(1.2, 1e-4, &[1.0], slow, 1e-6), Some(1.2));
    }

    #[test]
    fn transitions_name_the_event() {
        use ContactState::{Open, Slide, Stick};
        assert_eq!(transition(Stick, Slide(1.0), false), Some(EventKind::Slip));
        assert_eq!(
            transition(Slide(1.0), Slide(-1.0), false),
            Some(EventKind::Slip)
        );
        assert_eq!(transition(Slide(1.0), Slide(1.0), false), None);
        assert_eq!(
            transition(Slide(-1.0), Stick, false),
            Some(EventKind::Stick)
        );
        assert_eq!(transition(Open, Stick, false), Some(EventKind::Stick));
        assert_eq!(transition(Open, Stick, true), None);
        assert_eq!(transition(Open, Slide(1.0), true), None);
        assert_eq!(transition(Stick, Open, false), Some(EventKind::Release));
        assert_eq!(transition(Open, Open, true), None);
    }
}
