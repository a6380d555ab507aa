//! Small dense linear algebra of the engine: complete-pivoting elimination, minimum-norm
//! solutions of redundant constraint systems (regularized Cholesky, SVD fallback), on the stack
//! for up to 12 unknowns.

use nalgebra::{DMatrix, DVector};

/// Minimum-norm solution of a rank-deficient (redundant constraints), consistent system:
/// λ = Aᵀ(AAᵀ + δI)⁻¹ b (→ A⁺b as δ → 0), δ = 1e-12 max diag(AAᵀ), by Cholesky; the SVD
/// solution if that does not reproduce b. It splits forces equally between redundant rows.
pub(crate) fn min_norm_solve(a: &DMatrix<f64>, b: &DVector<f64>) -> DVector<f64> {
    // a non-finite system has no solution to find (and nalgebra's SVD panics on NaN): NaN goes
    // on, and the integrator reports a non-finite state
    if !a.iter().chain(b.iter()).all(|x| x.is_finite()) {
        return DVector::from_element(b.len(), f64::NAN);
    }
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
pub(crate) fn solve_small_into(
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    x: &mut DVector<f64>,
    singular: &mut bool,
) {
    let k = b.len();
    if x.len() != k {
        *x = DVector::zeros(k);
    }
    let done = match k {
        // the same arithmetic on arrays of the order itself for one and two rows (a closed
        // contact, a sticking one): the loops unrolled, nothing zeroed that is not read
        0..=1 => solve_on::<1>(a, b, x.as_mut_slice(), singular),
        2 => solve_on::<2>(a, b, x.as_mut_slice(), singular),
        3..=4 => solve_on::<4>(a, b, x.as_mut_slice(), singular),
        5..=8 => solve_on::<8>(a, b, x.as_mut_slice(), singular),
        9..=ELIM_N => solve_on::<ELIM_N>(a, b, x.as_mut_slice(), singular),
        _ => {
            if !*singular {
                if eliminate_into(a, b, 1e-9, x.as_mut_slice()) {
                    return;
                }
                *singular = true;
            }
            false
        }
    };
    if !done {
        x.copy_from(&min_norm_solve(a, b));
    }
}

/// [`solve_stack`] of a `DMatrix` copied to the stack (k ≤ N).
fn solve_on<const N: usize>(
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    x: &mut [f64],
    singular: &mut bool,
) -> bool {
    let k = b.len();
    let (m, r) = on_stack::<N>(a, b, k);
    solve_stack(&m, &r, k, x, singular)
}

/// The leading k × k block of `a` and k entries of `b` on the stack (k ≤ N).
#[inline(always)]
fn on_stack<const N: usize>(
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    k: usize,
) -> ([[f64; N]; N], [f64; N]) {
    let mut m = [[0.0f64; N]; N];
    let mut r = [0.0f64; N];
    for i in 0..k {
        for j in 0..k {
            m[i][j] = a[(i, j)];
        }
        r[i] = b[i];
    }
    (m, r)
}

/// [`solve_small_into`] of the leading k × k block of `a` (rows) and `b`, k ≤ N, into
/// `x[..k]`; false when the minimum-norm solution on the stack fails (then [`min_norm_solve`]
/// decides).
pub(crate) fn solve_stack<const N: usize>(
    a: &[[f64; N]; N],
    b: &[f64; N],
    k: usize,
    x: &mut [f64],
    singular: &mut bool,
) -> bool {
    let x = &mut x[..k];
    if !*singular {
        let (mut m, mut r) = (*a, *b);
        if eliminate_stack(&mut m, &mut r, k, 1e-9, x) {
            return true;
        }
        *singular = true;
    }
    min_norm_stack(a, b, k, x)
}

/// The regularized minimum-norm solution of [`min_norm_solve`] on stack arrays of order N ≥ k;
/// false if it fails (then the SVD decides).
fn min_norm_stack<const N: usize>(
    a: &[[f64; N]; N],
    b: &[f64; N],
    k: usize,
    x: &mut [f64],
) -> bool {
    let mut m = [[0.0f64; N]; N];
    let mut dmax = 0.0f64;
    // the lower triangle and diagonal of A Aᵀ: all that the Cholesky factorization reads
    for r in 0..k {
        for c in 0..=r {
            let mut acc = 0.0;
            for (p, q) in a[r][..k].iter().zip(&a[c][..k]) {
                acc += p * q;
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
    yv[..k].copy_from_slice(&b[..k]);
    if !cholesky_solve_stack(&mut m, k, &mut yv[..k]) {
        return false;
    }
    for (j, xj) in x.iter_mut().enumerate() {
        let mut acc = 0.0;
        for (row, y) in a[..k].iter().zip(&yv[..k]) {
            acc += row[j] * y;
        }
        *xj = acc;
    }
    let bmax = b[..k].iter().fold(0.0f64, |m, v| m.max(v.abs()));
    a[..k].iter().zip(&b[..k]).all(|(row, br)| {
        let mut acc = 0.0;
        for (p, xj) in row[..k].iter().zip(&*x) {
            acc += p * xj;
        }
        (acc - br).abs() <= 1e-9 * (1.0 + bmax)
    })
}

/// Solves S x = r in place (`x` holds r on entry) for symmetric positive definite S, read from
/// its lower triangle (which is overwritten by the Cholesky factor L, S = L Lᵀ); false if a pivot is not
/// positive or the solution not finite.
pub(crate) fn cholesky_solve_stack<const N: usize>(
    s: &mut [[f64; N]; N],
    n: usize,
    x: &mut [f64],
) -> bool {
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
pub(crate) fn eliminate_into(
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    tol: f64,
    out: &mut [f64],
) -> bool {
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
    let (mut m, mut r) = on_stack::<N>(a, b, n);
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
pub(crate) fn min_norm_correction(
    rows: &[&DVector<f64>],
    res: &[f64],
    minv: &DVector<f64>,
    singular: &mut bool,
) -> DVector<f64> {
    let mut ws = Correction::default();
    let mut d = DVector::zeros(minv.len());
    ws.solve(rows.len(), |r| rows[r], res, minv, singular, &mut d);
    d
}

/// Reused storage of [`min_norm_correction`]: the Gram matrix, right-hand side and multipliers.
#[derive(Clone, Debug, Default)]
pub(crate) struct Correction {
    a: DMatrix<f64>,
    b: DVector<f64>,
    lam: DVector<f64>,
}

impl Correction {
    /// [`min_norm_correction`] of the `k` rows `row(0..k)` into `d`, without allocation once
    /// the buffers have their sizes.
    pub fn solve<'r>(
        &mut self,
        k: usize,
        row: impl Fn(usize) -> &'r DVector<f64>,
        res: &[f64],
        minv: &DVector<f64>,
        singular: &mut bool,
        d: &mut DVector<f64>,
    ) {
        if self.a.nrows() != k {
            self.a = DMatrix::zeros(k, k);
            self.b = DVector::zeros(k);
        }
        for r in 0..k {
            for c in 0..k {
                self.a[(r, c)] = row(r)
                    .as_slice()
                    .iter()
                    .zip(minv.as_slice())
                    .zip(row(c).as_slice())
                    .map(|((x, m), y)| x * m * y)
                    .sum();
            }
        }
        self.b.as_mut_slice().copy_from_slice(res);
        solve_small_into(&self.a, &self.b, &mut self.lam, singular);
        if d.len() != minv.len() {
            *d = DVector::zeros(minv.len());
        }
        d.fill(0.0);
        for r in 0..k {
            d.axpy(self.lam[r], row(r), 1.0);
        }
        d.component_mul_assign(minv);
    }
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
    fn a_non_finite_system_gives_nan_not_a_panic() {
        let a = DMatrix::from_row_slice(2, 2, &[1.0, f64::NAN, 0.0, 1.0]);
        let b = DVector::from_vec(vec![1.0, 1.0]);
        assert!(min_norm_solve(&a, &b).iter().all(|x| x.is_nan()));
        let (x, _) = solve(&a, &b);
        assert!(x.iter().any(|x| !x.is_finite()));
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
