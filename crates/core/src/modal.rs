//! Modal analysis of any model at its initial state: K₀, modes (K₀ φ = ω² M φ) and Rayleigh
//! damping. The `modes` command and the bridge's `[damping]` both use it.

use crate::scene::{Attachment, MassDamping, Scene, spread};
use nalgebra::{DMatrix, DVector};

/// Initial stiffness K₀ = Σ k J Jᵀ of springs and hysteretic elements at q = 0 (contacts open).
pub fn initial_stiffness(scene: &Scene) -> DMatrix<f64> {
    let n = scene.ndof();
    let z = DVector::zeros(n);
    let mut jac = DVector::zeros(n);
    let mut k = DMatrix::zeros(n, n);
    let fr = scene.frame(0.0, &z, &z);
    let mut add = |att: &Attachment, stiff: f64, jac: &mut DVector<f64>| {
        let (.., sparse, nj) = scene.deformation(&fr, att, None);
        spread(&sparse[..nj], jac);
        k += &*jac * jac.transpose() * stiff;
    };
    for s in &scene.springs {
        add(&s.attachment, s.stiffness, &mut jac);
    }
    for h in &scene.hysteretic {
        add(&h.attachment, h.law.law().initial_stiffness(), &mut jac);
    }
    k
}

/// Largest ω of M⁻¹K for the stiffness `k` (√ of the largest eigenvalue of M^-½ K M^-½).
fn omega_max_of(scene: &Scene, k: &DMatrix<f64>) -> f64 {
    let s: DVector<f64> = scene.mass.map(|m| 1.0 / m.sqrt());
    let a = DMatrix::from_fn(k.nrows(), k.ncols(), |i, j| k[(i, j)] * s[i] * s[j]);
    let top = nalgebra::SymmetricEigen::new(a)
        .eigenvalues
        .iter()
        .fold(0.0f64, |m, x| m.max(*x));
    top.sqrt()
}

/// ω_max of the initial system: the fastest mode of K₀ (contacts open).
pub(crate) fn omega_max(scene: &Scene) -> f64 {
    omega_max_of(scene, &initial_stiffness(scene))
}

/// ω_max of the stiffest linearised system a penalty method meets: K₀ plus, for every
/// contact, `contact_stiffness` along its normal and (sticking) its tangent, W_N W_Nᵀ and
/// W_T W_Tᵀ at the initial state, as if every contact were closed. For each contact alone this
/// contains ω_c = √(k / m_eff), m_eff = 1/(W_Nᵀ M⁻¹ W_N); together it bounds them all.
pub(crate) fn omega_max_closed(scene: &Scene, contact_stiffness: f64) -> f64 {
    let mut k = initial_stiffness(scene);
    let fr = scene.frame(0.0, &scene.q0, &scene.v0);
    for c in &scene.contacts {
        let ck = scene.contact_kinematics(&fr, c);
        k += (&ck.w_n * ck.w_n.transpose() + &ck.w_t * ck.w_t.transpose()) * contact_stiffness;
    }
    omega_max_of(scene, &k)
}

/// A mode of the initial system (K₀ φ = ω² M φ, φᵀMφ = 1).
#[derive(Clone, Debug)]
pub struct Mode {
    /// Circular frequency ω, rad/s.
    pub omega: f64,
    /// Period 2π/ω, s.
    pub period: f64,
    /// φ, mass-normalised, per DOF of the scene.
    pub shape: DVector<f64>,
}

/// Eigen-analysis of (K₀, M), modes sorted by frequency. The DOFs that K₀ does not couple
/// (e.g. an abutment on its actuators and the deck while their contacts are open) are solved
/// as separate blocks, so that a part's modes do not depend, not even by round-off, on the
/// parts it is not joined to.
pub fn modes(scene: &Scene) -> Vec<Mode> {
    let k = initial_stiffness(scene);
    let s: DVector<f64> = scene.mass.map(|m| 1.0 / m.sqrt());
    let n = scene.ndof();
    let mut out = Vec::with_capacity(n);
    for block in coupled_blocks(&k) {
        let m = block.len();
        let a = DMatrix::from_fn(m, m, |i, j| {
            let (bi, bj) = (block[i], block[j]);
            k[(bi, bj)] * s[bi] * s[bj]
        });
        let eig = nalgebra::SymmetricEigen::new(a);
        for i in 0..m {
            let w2 = eig.eigenvalues[i].max(0.0);
            let omega = w2.sqrt();
            let mut shape = DVector::zeros(n);
            for (r, &d) in block.iter().enumerate() {
                shape[d] = eig.eigenvectors[(r, i)] * s[d];
            }
            let big = shape
                .iter()
                .cloned()
                .fold(0.0f64, |m, x| if x.abs() > m.abs() { x } else { m });
            if big < 0.0 {
                shape = -shape;
            }
            out.push(Mode {
                omega,
                period: if omega > 0.0 {
                    2.0 * std::f64::consts::PI / omega
                } else {
                    f64::INFINITY
                },
                shape,
            });
        }
    }
    out.sort_by(|a, b| a.omega.total_cmp(&b.omega));
    out
}

/// The DOFs in groups that `k` couples (connected through non-zero entries), each in
/// ascending order, the groups by their first DOF.
fn coupled_blocks(k: &DMatrix<f64>) -> Vec<Vec<usize>> {
    let n = k.nrows();
    let mut group: Vec<Option<usize>> = vec![None; n];
    let mut blocks: Vec<Vec<usize>> = Vec::new();
    for start in 0..n {
        if group[start].is_some() {
            continue;
        }
        let g = blocks.len();
        let mut members = vec![start];
        group[start] = Some(g);
        let mut next = 0;
        while next < members.len() {
            let i = members[next];
            next += 1;
            for j in 0..n {
                if group[j].is_none() && (k[(i, j)] != 0.0 || k[(j, i)] != 0.0) {
                    group[j] = Some(g);
                    members.push(j);
                }
            }
        }
        members.sort_unstable();
        blocks.push(members);
    }
    blocks
}

/// The DOF name endings of the three directions of [`participation`].
pub(crate) const DIRECTIONS: [&str; 3] = [".x", ".y", ".theta"];

/// Participating mass ratios of each mode along x, y and θ: (φᵀMr)² / (φᵀMφ · rᵀMr), with r
/// 1 on every DOF whose name ends as [`DIRECTIONS`] says (all bodies translating together;
/// for θ each body turning about its own centre) and 0 elsewhere. Over all modes each
/// direction sums to 1; 0 for a direction without DOFs.
pub fn participation(scene: &Scene, modes: &[Mode]) -> Vec<[f64; 3]> {
    let r: Vec<Vec<bool>> = (DIRECTIONS.iter())
        .map(|d| scene.dof_names.iter().map(|n| n.ends_with(d)).collect())
        .collect();
    modes
        .iter()
        .map(|m| {
            let mut out = [0.0; 3];
            for (k, rk) in r.iter().enumerate() {
                let (mut l, mut mr, mut mm) = (0.0, 0.0, 0.0);
                for (i, &on) in rk.iter().enumerate() {
                    let (mi, phi) = (scene.mass[i], m.shape[i]);
                    mm += mi * phi * phi;
                    if on {
                        l += mi * phi;
                        mr += mi;
                    }
                }
                out[k] = if mr > 0.0 && mm > 0.0 {
                    l * l / (mm * mr)
                } else {
                    0.0
                };
            }
            out
        })
        .collect()
}

/// Rayleigh damping C = a₀M + a₁K₀ with ζ at modes i, j (Chopra, *Dynamics of Structures*
/// §11.4): a₀ = 2ζωᵢωⱼ/(ωᵢ+ωⱼ), a₁ = 2ζ/(ωᵢ+ωⱼ). The a₁K₀ part acts on element deformation
/// rates, the a₀M part on velocities relative to the quasi-static motion of the supports, so
/// damping forces vanish for rigid-body support motion.
pub fn apply_rayleigh(
    scene: &mut Scene,
    zeta: f64,
    modes_ij: [usize; 2],
) -> Result<(f64, f64), String> {
    let (a0, a1) = rayleigh_coefficients(scene, zeta, modes_ij)?;
    apply_rayleigh_coefficients(scene, a0, a1);
    Ok((a0, a1))
}

/// (a₀, a₁) of [`apply_rayleigh`] from the modes of `scene` (numbered from 1 by frequency).
pub(crate) fn rayleigh_coefficients(
    scene: &Scene,
    zeta: f64,
    modes_ij: [usize; 2],
) -> Result<(f64, f64), String> {
    let m = modes(scene);
    let [i, j] = modes_ij;
    if i == 0 || j == 0 || i > m.len() || j > m.len() || i == j {
        return Err(format!(
            "modes must be two different numbers in 1..={}",
            m.len()
        ));
    }
    let (wi, wj) = (m[i - 1].omega, m[j - 1].omega);
    if wi <= 0.0 || wj <= 0.0 {
        return Err("a chosen mode has zero frequency".into());
    }
    let a0 = 2.0 * zeta * wi * wj / (wi + wj);
    let a1 = 2.0 * zeta / (wi + wj);
    Ok((a0, a1))
}

/// Rayleigh damping C = a₀M + a₁K₀ of given coefficients ([`apply_rayleigh`]).
pub(crate) fn apply_rayleigh_coefficients(scene: &mut Scene, a0: f64, a1: f64) {
    for s in &mut scene.springs {
        s.damping += a1 * s.stiffness;
    }
    for h in &mut scene.hysteretic {
        h.damping += a1 * h.law.law().initial_stiffness();
    }
    let reference = support_influence(scene);
    scene.mass_damping = MassDamping {
        alpha: a0,
        reference,
    };
}

/// Quasi-static influence of each support, r_s = K₀⁻¹ Σ −k c J for the elements whose
/// deformation e = J q + c u_s a unit support displacement changes (c = −1 for an element to
/// the support; ±d_x, ±d_y for a two-body element on a body the support drives), as (DOF,
/// support, r) entries above 1e-14. One pass over the elements (grouped by support, in file
/// order: springs, then hysteretic elements), so the cost is linear in their number.
pub fn support_influence(scene: &Scene) -> Vec<(usize, usize, f64)> {
    let k0 = initial_stiffness(scene);
    let n = scene.ndof();
    let lu = k0.lu();
    let z = DVector::zeros(n);
    let mut jac = DVector::zeros(n);
    let fr = scene.frame(0.0, &z, &z);
    let ns = scene.supports.len();
    let mut driven: Vec<Vec<(&Attachment, f64)>> = vec![Vec::new(); ns];
    let springs = scene
        .springs
        .iter()
        .map(|x| (x.support, &x.attachment, x.stiffness));
    let hyst = (scene.hysteretic.iter())
        .map(|x| (x.support, &x.attachment, x.law.law().initial_stiffness()));
    for (s, att, k) in springs.chain(hyst) {
        if let Some(list) = s.and_then(|s| driven.get_mut(s)) {
            list.push((att, k));
        }
        if let Attachment::Relative {
            body,
            other,
            direction,
            ..
        } = *att
        {
            // e ∋ d·u_a − d·u_b of the bodies moved by the ground
            for (b, sign) in [(body, -1.0), (other, 1.0)] {
                for (a, s) in scene.bodies[b].drive.into_iter().enumerate() {
                    if let Some(list) = s.and_then(|s| driven.get_mut(s)) {
                        list.push((att, sign * direction[a] * k));
                    }
                }
            }
        }
    }
    let mut reference = Vec::new();
    for (s, list) in driven.iter().enumerate() {
        let mut f = DVector::zeros(n);
        for (att, k) in list {
            let (.., sparse, nj) = scene.deformation(&fr, att, None);
            spread(&sparse[..nj], &mut jac);
            f.axpy(*k, &jac, 1.0);
        }
        if let Some(r) = lu.solve(&f) {
            for k in 0..n {
                if r[k].abs() > 1e-14 {
                    reference.push((k, s, r[k]));
                }
            }
        }
    }
    reference
}
