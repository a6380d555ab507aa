//! Gap elements (penalty contact, as OpenSees users build them): a compression-only spring k
//! and dashpot per contact, Coulomb friction as an elastic stick–slip spring.

use super::Stepper;
use crate::scene::{Frame, PowerTerms, Scene};
use nalgebra::DVector;

/// Penalty contact forces at (q, v) with trial tangential springs `slip0 + Δs`.
pub(super) struct PenaltyForces {
    pub f: DVector<f64>,
    pub lam_n: Vec<f64>,
    pub lam_t: Vec<f64>,
    pub slip: Vec<f64>,
    pub elastic: f64,
    /// Power absorbed by the contact elements, −Σ(λ_N ġ_N + λ_T ġ_T) (relative rates).
    pub absorbed: f64,
    /// Power of faces moved by the ground, −Σ(λ_N ∂g_N/∂t + λ_T ∂g_T/∂t).
    pub driven: f64,
}

/// The gap elements of a run: stiffness k and (normal, tangential) dashpots per contact.
pub(super) struct GapElements {
    pub k: f64,
    pub dashpots: Vec<(f64, f64)>,
}

impl GapElements {
    pub fn new(scene: &Scene, k: f64) -> Self {
        Self {
            k,
            dashpots: dashpots(scene, k),
        }
    }

    /// M⁻¹ (h(t, q, q̇) + W λ) with the laws and tangential springs on trial: accelerations,
    /// smooth-force powers, contact forces.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn accel(
        &self,
        s: &Stepper,
        t: f64,
        q: &DVector<f64>,
        v: &DVector<f64>,
        slip0: &[f64],
        dslip: &[f64],
        mask: Option<&[bool]>,
    ) -> (DVector<f64>, PowerTerms, PenaltyForces) {
        let mut f = DVector::zeros(s.scene.ndof());
        let p = s.forces_trial(t, q, v, &mut f);
        // the frame at (t, q, q̇) forces_trial left in the scratch
        let fr = &s.scratch.borrow().fr;
        let pf = penalty_forces(s.scene, fr, self.k, &self.dashpots, slip0, dslip, mask);
        ((f + &pf.f).component_mul(&s.minv), p, pf)
    }
}

/// Gap element per contact: λ_N = max(0, −k g_N − c ġ_N) for g_N < 0; c = 2ζ√(k m_eff) with
/// ζ from the target restitution ε = exp(−ζπ/√(1−ζ²)) (ζ = 1 for ε = 0); Coulomb friction as
/// an elastic stick spring k_T = k with return mapping to μλ_N.
fn penalty_forces(
    scene: &Scene,
    fr: &Frame,
    k: f64,
    dashpots: &[(f64, f64)],
    slip0: &[f64],
    dslip: &[f64],
    mask: Option<&[bool]>,
) -> PenaltyForces {
    let nc = scene.contacts.len();
    let mut out = PenaltyForces {
        f: DVector::zeros(scene.ndof()),
        lam_n: vec![0.0; nc],
        lam_t: vec![0.0; nc],
        slip: vec![0.0; nc],
        elastic: 0.0,
        absorbed: 0.0,
        driven: 0.0,
    };
    for (i, c) in scene.contacts.iter().enumerate() {
        if mask.is_some_and(|m| !m[i]) {
            continue;
        }
        let kin = scene.contact_kinematics(fr, c);
        if mask.is_none() && kin.gap >= 0.0 {
            continue;
        }
        let (c_n, c_t) = dashpots[i];
        // with a fixed active set (Newmark iterations) the element is linear
        let ln = if mask.is_some() {
            -k * kin.gap - c_n * kin.gap_rate
        } else {
            (-k * kin.gap - c_n * kin.gap_rate).max(0.0)
        };
        out.elastic += 0.5 * k * kin.gap * kin.gap;
        let mut s = slip0[i] + dslip[i];
        // stick spring with a dashpot of the normal damping ratio (an undamped stick spring
        // would give the tangential motion a restitution of one)
        let mut lt = -k * s - c_t * kin.slip_rate;
        if !c.law.frictionless() {
            let on_cone = c.law.onto_cone(ln, lt);
            if on_cone != lt {
                lt = on_cone;
                s = -lt / k;
            }
            out.elastic += 0.5 * k * s * s;
        } else {
            lt = 0.0;
            s = 0.0;
        }
        out.absorbed -= ln * kin.gap_rate + lt * kin.slip_rate;
        out.driven -= ln * kin.driven_n + lt * kin.driven_t;
        out.lam_n[i] = ln;
        out.lam_t[i] = lt;
        out.slip[i] = s;
        out.f.axpy(ln, &kin.w_n, 1.0);
        out.f.axpy(lt, &kin.w_t, 1.0);
    }
    out
}

/// (normal, tangential) dashpot per contact: c = 2ζ√(k m_eff) with m_eff = 1/(WᵀM⁻¹W).
fn dashpots(scene: &Scene, k: f64) -> Vec<(f64, f64)> {
    let minv = scene.mass.map(|m| 1.0 / m);
    let fr = scene.frame(0.0, &scene.q0, &scene.v0);
    let m_eff = |w: &DVector<f64>| {
        let g: f64 = w.iter().zip(minv.iter()).map(|(w, m)| w * w * m).sum();
        1.0 / g.max(1e-300)
    };
    (scene.contacts.iter())
        .map(|c| {
            let kin = scene.contact_kinematics(&fr, c);
            let e = c.law.restitution;
            let zeta = if e <= 0.0 {
                1.0
            } else {
                let l = e.ln();
                -l / (std::f64::consts::PI.powi(2) + l * l).sqrt()
            };
            (
                2.0 * zeta * (k * m_eff(&kin.w_n)).sqrt(),
                2.0 * zeta * (k * m_eff(&kin.w_t)).sqrt(),
            )
        })
        .collect()
}
