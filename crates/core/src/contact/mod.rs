//! The two LCPs of the paper (§3.2): frictional impact at velocity level (eq. 5–7) and
//! continuous contact / detachment at acceleration level (eq. 8–10), both solved by Lemke.

pub mod law;

pub use law::coulomb;

use crate::lemke::{LcpError, LcpSolution, LemkeOptions, lemke_regularized};
use crate::scene::ContactKinematics;
use nalgebra::{DMatrix, DVector};

/// Post-impact state of the contacts taking part in an impact.
#[derive(Clone, Debug)]
pub struct ImpactOutcome {
    /// Velocity jump Δq̇ = M⁻¹(W_N Λ_N + W_T Λ_T).
    pub velocity_jump: DVector<f64>,
    /// Λ_N per participating contact.
    pub normal_impulse: Vec<f64>,
    /// Λ_T = Λ_TR − μ Λ_N per participating contact.
    pub tangential_impulse: Vec<f64>,
    /// ġ_N⁺ per participating contact.
    pub gap_rate_after: Vec<f64>,
    /// ġ_T⁺ per participating contact.
    pub slip_rate_after: Vec<f64>,
    /// Lemke's pivots.
    pub pivots: usize,
    /// δ of a regularised solve ([`crate::lemke::lemke_regularized`]), 0 if none was needed.
    pub regularization: f64,
}

/// Delassus entry G_XY = W_Xᵀ M⁻¹ W_Y (eq. 7).
fn delassus(a: &DVector<f64>, minv: &DVector<f64>, b: &DVector<f64>) -> f64 {
    a.iter()
        .zip(minv.iter())
        .zip(b.iter())
        .map(|((x, m), y)| x * m * y)
        .sum()
}

/// Impact LCP (eq. 5–6): unknowns (Λ_N, Λ_TR, ġ_TL⁺) ≥ 0 complementary to (v_N, ġ_TR⁺, Λ_TL) ≥ 0,
/// v_N = ġ_N⁺ + ε ġ_N⁻ (eq. 4). Frictionless contacts carry no tangential rows.
/// `kin[i]` are the participating contacts with restitution `eps[i]` and friction `mu[i]`.
pub fn solve_impact(
    kin: &[&ContactKinematics],
    eps: &[f64],
    mu: &[f64],
    minv: &DVector<f64>,
    opts: &LemkeOptions,
) -> Result<ImpactOutcome, LcpError> {
    let w_n: Vec<&DVector<f64>> = kin.iter().map(|k| &k.w_n).collect();
    let w_t: Vec<&DVector<f64>> = kin.iter().map(|k| &k.w_t).collect();
    let q_n: Vec<f64> = (0..kin.len())
        .map(|i| (1.0 + eps[i]) * kin[i].gap_rate)
        .collect();
    let q_t: Vec<f64> = kin.iter().map(|k| k.slip_rate).collect();
    let (lam_n, lam_t, pivots, regularization) = frictional_velocity_lcp(
        &w_n,
        &w_t,
        &|a, b| delassus(a, minv, b),
        &q_n,
        &q_t,
        mu,
        opts,
    )?;
    let nc = kin.len();
    let mut dv = DVector::zeros(minv.len());
    for i in 0..nc {
        dv.axpy(lam_n[i], &kin[i].w_n, 1.0);
        dv.axpy(lam_t[i], &kin[i].w_t, 1.0);
    }
    dv.component_mul_assign(minv);
    let gap_rate_after = (0..nc)
        .map(|i| kin[i].gap_rate + kin[i].w_n.dot(&dv))
        .collect();
    let slip_rate_after = (0..nc)
        .map(|i| kin[i].slip_rate + kin[i].w_t.dot(&dv))
        .collect();
    Ok(ImpactOutcome {
        velocity_jump: dv,
        normal_impulse: lam_n,
        tangential_impulse: lam_t,
        gap_rate_after,
        slip_rate_after,
        pivots,
        regularization,
    })
}

/// The velocity-level frictional LCP shared by impacts (eq. 5) and Moreau–Jean steps:
/// v_N = G_NN Λ_N + G_NT Λ_T + q_N ≥ 0 ⊥ Λ_N ≥ 0, Coulomb on Λ_T with the split of eq. 5,
/// ġ_T⁺ = G_TN Λ_N + G_TT Λ_T + q_T. `g(a, b)` is the Delassus product aᵀ Ŵ⁻¹ b.
/// Returns (Λ_N, Λ_T, pivots, δ of a regularised solve or 0).
pub fn frictional_velocity_lcp(
    w_n: &[&DVector<f64>],
    w_t: &[&DVector<f64>],
    g: &dyn Fn(&DVector<f64>, &DVector<f64>) -> f64,
    q_n: &[f64],
    q_t: &[f64],
    mu: &[f64],
    opts: &LemkeOptions,
) -> Result<(Vec<f64>, Vec<f64>, usize, f64), LcpError> {
    let nc = w_n.len();
    let fr: Vec<usize> = (0..nc).filter(|&i| mu[i] > 0.0).collect();
    let nf = fr.len();
    let n = nc + 2 * nf;
    let mut m = DMatrix::zeros(n, n);
    let mut q = DVector::zeros(n);
    for i in 0..nc {
        for j in 0..nc {
            m[(i, j)] = g(w_n[i], w_n[j]);
        }
        q[i] = q_n[i];
    }
    for (a, &j) in fr.iter().enumerate() {
        // column of Λ_N(j) gets −G_NT μ_j; column Λ_TR(a) gets G_NT
        for i in 0..nc {
            let g_nt = g(w_n[i], w_t[j]);
            m[(i, j)] -= g_nt * mu[j];
            m[(i, nc + a)] = g_nt;
        }
    }
    for (a, &i) in fr.iter().enumerate() {
        let r = nc + a;
        for j in 0..nc {
            m[(r, j)] = g(w_t[i], w_n[j]);
        }
        for (b, &j) in fr.iter().enumerate() {
            let g_tt = g(w_t[i], w_t[j]);
            m[(r, j)] -= g_tt * mu[j];
            m[(r, nc + b)] = g_tt;
        }
        m[(r, nc + nf + a)] = 1.0;
        q[r] = q_t[i];
        let s = nc + nf + a;
        m[(s, i)] = 2.0 * mu[i];
        m[(s, nc + a)] = -1.0;
    }
    let (LcpSolution { z, pivots, .. }, delta) = lemke_regularized(&m, &q, opts)?;
    let mut lam_n = vec![0.0; nc];
    let mut lam_t = vec![0.0; nc];
    lam_n.copy_from_slice(&z.as_slice()[..nc]);
    for (a, &i) in fr.iter().enumerate() {
        lam_t[i] = z[nc + a] - mu[i] * lam_n[i];
    }
    Ok((lam_n, lam_t, pivots, delta))
}

/// What the acceleration LCP decides for a closed contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Decision {
    /// λ_N = 0 and g̈_N ≥ 0: the contact opens.
    Detach,
    /// |λ_T| ≤ μ λ_N and g̈_T = 0.
    Stick,
    /// Slides with ġ_T of this sign.
    Slide(f64),
}

/// The solution of the acceleration LCP (eq. 8–10) for the closed contacts.
#[derive(Clone, Debug)]
pub struct ContactOutcome {
    /// Per closed contact.
    pub decision: Vec<Decision>,
    /// λ_N per closed contact.
    pub normal_force: Vec<f64>,
    /// λ_T per closed contact.
    pub tangential_force: Vec<f64>,
    /// g̈_N per contact (0 where closed).
    pub normal_accel: Vec<f64>,
    /// Lemke's pivots.
    pub pivots: usize,
    /// δ of a regularised solve ([`crate::lemke::lemke_regularized`]), 0 if none was needed.
    pub regularization: f64,
}

/// Acceleration LCP (eq. 8–10) over closed contacts. `slide[i] = Some(s)` for a contact already
/// sliding with sign s (set G: friction −μ s λ_N folded into W_Q), `None` for a stick candidate
/// (set H, ġ_T = 0). `h` are the smooth forces; ŵ (velocity terms of g̈) enter q.
/// (The paper's second q block reads −W_NᵀM⁻¹h; it is −W_HᵀM⁻¹h − ŵ_H.)
pub fn solve_contact(
    kin: &[&ContactKinematics],
    mu: &[f64],
    slide: &[Option<f64>],
    minv: &DVector<f64>,
    h: &DVector<f64>,
    opts: &LemkeOptions,
) -> Result<ContactOutcome, LcpError> {
    let nc = kin.len();
    let hs: Vec<usize> = (0..nc)
        .filter(|&i| slide[i].is_none() && mu[i] > 0.0)
        .collect();
    let nh = hs.len();
    let n = nc + 2 * nh;
    let minv_h = h.component_mul(minv);
    // W_Q column of each contact.
    let wq: Vec<DVector<f64>> = (0..nc)
        .map(|i| {
            let f = match slide[i] {
                Some(s) => -mu[i] * s,
                None => mu[i],
            };
            if f == 0.0 {
                kin[i].w_n.clone()
            } else {
                &kin[i].w_n + &kin[i].w_t * f
            }
        })
        .collect();
    let mut m = DMatrix::zeros(n, n);
    let mut q = DVector::zeros(n);
    for i in 0..nc {
        for j in 0..nc {
            m[(i, j)] = delassus(&kin[i].w_n, minv, &wq[j]);
        }
        for (b, &j) in hs.iter().enumerate() {
            m[(i, nc + b)] = -delassus(&kin[i].w_n, minv, &kin[j].w_t);
        }
        q[i] = kin[i].w_n.dot(&minv_h) + kin[i].bias_n;
    }
    for (a, &i) in hs.iter().enumerate() {
        let r = nc + a;
        for j in 0..nc {
            m[(r, j)] = -delassus(&kin[i].w_t, minv, &wq[j]);
        }
        for (b, &j) in hs.iter().enumerate() {
            m[(r, nc + b)] = delassus(&kin[i].w_t, minv, &kin[j].w_t);
        }
        m[(r, nc + nh + a)] = 1.0;
        q[r] = -(kin[i].w_t.dot(&minv_h) + kin[i].bias_t);
        let s = nc + nh + a;
        m[(s, i)] = 2.0 * mu[i];
        m[(s, nc + a)] = -1.0;
    }
    let (sol, regularization) = lemke_regularized(&m, &q, opts)?;
    let (z, w) = (&sol.z, &sol.w);
    let scale_f = 1.0 + z.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let scale_a = 1.0 + q.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let mut decision = vec![Decision::Stick; nc];
    let mut lam_n = vec![0.0; nc];
    let mut lam_t = vec![0.0; nc];
    let mut acc_n = vec![0.0; nc];
    for i in 0..nc {
        lam_n[i] = z[i];
        acc_n[i] = w[i];
        let closed = z[i] > 1e-12 * scale_f || w[i] <= 1e-12 * scale_a;
        decision[i] = if !closed {
            Decision::Detach
        } else {
            match slide[i] {
                Some(s) => Decision::Slide(s),
                None if mu[i] > 0.0 => Decision::Stick,
                None => Decision::Slide(0.0),
            }
        };
        if let Some(s) = slide[i] {
            lam_t[i] = coulomb::sliding_force(mu[i], s, lam_n[i]);
        }
    }
    for (a, &i) in hs.iter().enumerate() {
        let z_h = z[nc + a];
        lam_t[i] = mu[i] * lam_n[i] - z_h;
        let acc_hr = z[nc + nh + a];
        let acc_hl = w[nc + a];
        if decision[i] != Decision::Detach {
            let tol = 1e-12 * scale_a;
            if acc_hr > tol {
                decision[i] = Decision::Slide(1.0);
            } else if acc_hl > tol {
                decision[i] = Decision::Slide(-1.0);
            }
        }
    }
    Ok(ContactOutcome {
        decision,
        normal_force: lam_n,
        tangential_force: lam_t,
        normal_accel: acc_n,
        pivots: sol.pivots,
        regularization,
    })
}
