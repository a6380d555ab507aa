//! Lemke's complementary pivoting algorithm for the linear complementarity
//! problem LCP(q, M): find `z ≥ 0` with `w = M z + q ≥ 0` and `wᵀz = 0`.
//!
//! The method augments the problem with an artificial variable `z0` and the
//! covering vector `d = (1, …, 1)`, starts from the almost-complementary basis
//! obtained by bringing `z0` in at its smallest feasible value, and then
//! follows the complementary path until `z0` leaves the basis (a solution) or
//! the entering column has no positive entry (ray termination).
//! Degeneracy is resolved with the lexicographic minimum-ratio test, which
//! rules out cycling.
//!
//! References:
//! - C. E. Lemke, "Bimatrix equilibrium points and mathematical programming",
//!   *Management Science* 11 (1965) 681–689.
//! - R. W. Cottle, J.-S. Pang, R. E. Stone, *The Linear Complementarity
//!   Problem*, Academic Press 1992, §4.4 (Lemke's method, lexicographic
//!   degeneracy resolution).
//! - K. G. Murty, *Linear Complementarity, Linear and Nonlinear Programming*,
//!   Heldermann 1988, ch. 2 (complementary pivot algorithm) and ch. 6
//!   (exponential examples).

use nalgebra::{DMatrix, DVector};

/// Options for [`lemke`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LemkeOptions {
    /// Maximum number of pivots (counted as in [`LcpSolution::pivots`]).
    /// Default 10 000.
    pub max_pivots: usize,
    /// Pivot and ratio-test tolerance, relative to the (internally
    /// power-of-two normalised) data. Also used to clean tiny values of the
    /// returned `z`/`w`. Default 1e-12.
    pub tolerance: f64,
    /// Acceptance threshold for [`lcp_residual`] of the returned point.
    /// Default 1e-9.
    pub check_tolerance: f64,
}

impl Default for LemkeOptions {
    fn default() -> Self {
        Self {
            max_pivots: 10_000,
            tolerance: 1e-12,
            check_tolerance: 1e-9,
        }
    }
}

/// A verified solution of LCP(q, M).
#[derive(Debug, Clone, PartialEq)]
pub struct LcpSolution {
    /// `z ≥ 0`.
    pub z: DVector<f64>,
    /// `w = M z + q ≥ 0`, recomputed from the original data.
    pub w: DVector<f64>,
    /// Number of basis changes: the initial pivot bringing `z0` into the
    /// basis and the final pivot driving `z0` out both count. It is 0 when
    /// `q ≥ 0` (then `z = 0`).
    pub pivots: usize,
}

/// Failure of [`lemke`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LcpError {
    /// Ray termination: no solution reachable (e.g. infeasible, or M not
    /// copositive-plus). Carries the problem.
    #[error("Lemke: ray termination after {pivots} pivots (no solution reachable from this start)")]
    Ray {
        /// Pivots made.
        pivots: usize,
        /// The problem's M.
        m: DMatrix<f64>,
        /// The problem's q.
        q: DVector<f64>,
    },
    /// The pivot budget [`LemkeOptions::max_pivots`] was exhausted.
    #[error("Lemke: pivot cap reached after {pivots} pivots")]
    PivotCap {
        /// Pivots made.
        pivots: usize,
        /// The problem's M.
        m: DMatrix<f64>,
        /// The problem's q.
        q: DVector<f64>,
    },
    /// The returned point fails the check w = Mz+q, w ≥ 0, z ≥ 0, wᵀz ≈ 0.
    #[error("Lemke: solution check failed (residual {residual:e})")]
    CheckFailed {
        /// The largest violation of w = Mz + q, w ≥ 0, z ≥ 0, wᵀz = 0.
        residual: f64,
        /// The problem's M.
        m: DMatrix<f64>,
        /// The problem's q.
        q: DVector<f64>,
    },
    /// NaN or infinity in M or q.
    #[error("Lemke: non-finite entry in M or q")]
    NonFinite,
    /// M is not square or q does not match its size.
    #[error("Lemke: dimension mismatch (M is {rows}x{cols}, q has length {q_len})")]
    DimensionMismatch {
        /// Rows of M.
        rows: usize,
        /// Columns of M.
        cols: usize,
        /// Length of q.
        q_len: usize,
    },
}

/// Tie-breaking rule of the minimum-ratio test.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TieBreak {
    /// Lexicographic rule (Cottle, Pang & Stone 1992, §4.4): ties are broken
    /// with the rows of the inverse basis. Never cycles.
    #[default]
    Lexicographic,
    /// Smallest row index among tied rows. Can cycle on degenerate problems;
    /// provided only for comparison and testing.
    FirstIndex,
}

/// Solves LCP(q, M) with Lemke's method (covering vector `d = e`) and the
/// lexicographic minimum-ratio test.
///
/// The returned point is checked against the original data with
/// [`lcp_residual`]; see [`LcpError`] for the failure modes. Never panics.
pub fn lemke(
    m: &DMatrix<f64>,
    q: &DVector<f64>,
    opts: &LemkeOptions,
) -> Result<LcpSolution, LcpError> {
    lemke_with_tie_break(m, q, opts, TieBreak::Lexicographic)
}

/// [`lemke`] with an explicit tie-breaking rule. Use [`TieBreak::Lexicographic`]
/// (what [`lemke`] does) unless you are studying cycling.
pub fn lemke_with_tie_break(
    m: &DMatrix<f64>,
    q: &DVector<f64>,
    opts: &LemkeOptions,
    rule: TieBreak,
) -> Result<LcpSolution, LcpError> {
    let n = q.len();
    if m.nrows() != m.ncols() || m.nrows() != n {
        return Err(LcpError::DimensionMismatch {
            rows: m.nrows(),
            cols: m.ncols(),
            q_len: n,
        });
    }
    if m.iter().chain(q.iter()).any(|v| !v.is_finite()) {
        return Err(LcpError::NonFinite);
    }
    if q.iter().all(|&v| v >= 0.0) {
        // Covers n = 0 too: z = 0, w = q.
        return Ok(LcpSolution {
            z: DVector::zeros(n),
            w: q.clone(),
            pivots: 0,
        });
    }
    // A NaN tolerance would make every comparison false; fall back to defaults.
    let defaults = LemkeOptions::default();
    let tol = if opts.tolerance.is_finite() && opts.tolerance >= 0.0 {
        opts.tolerance
    } else {
        defaults.tolerance
    };

    // Normalise by powers of two (exact): M/α and q/β have max-abs in [1, 2).
    let m_max = max_abs(m.iter());
    let q_max = max_abs(q.iter());
    let alpha = pow2_floor(m_max);
    let beta = pow2_floor(q_max);

    let mut tab = Tableau::new(m, q, 1.0 / alpha, 1.0 / beta);
    let pivots = match follow_path(&mut tab, opts.max_pivots, tol, rule, |_| {}) {
        Outcome::Solved(p) => p,
        Outcome::Ray(pivots) => {
            return Err(LcpError::Ray {
                pivots,
                m: m.clone(),
                q: q.clone(),
            });
        }
        Outcome::Cap(pivots) => {
            return Err(LcpError::PivotCap {
                pivots,
                m: m.clone(),
                q: q.clone(),
            });
        }
        Outcome::Breakdown => {
            return Err(LcpError::CheckFailed {
                residual: f64::INFINITY,
                m: m.clone(),
                q: q.clone(),
            });
        }
    };

    // Read z from the tableau, undo the scaling, clean and verify against the
    // original data.
    let mut z = DVector::zeros(n);
    let unscale = beta / alpha;
    for (i, &var) in tab.basis.iter().enumerate() {
        if (n..2 * n).contains(&var) {
            z[var - n] = tab.rhs(i).max(0.0) * unscale;
        }
    }
    let z_max = max_abs(z.iter());
    for v in z.iter_mut() {
        if v.abs() <= tol * z_max {
            *v = 0.0;
        }
    }
    let w = clean_w(m, q, &z, tol);
    let residual = lcp_residual(m, q, &z, &w);
    if residual <= opts.check_tolerance {
        Ok(LcpSolution { z, w, pivots })
    } else {
        Err(LcpError::CheckFailed {
            residual,
            m: m.clone(),
            q: q.clone(),
        })
    }
}

/// Regularisations tried by [`lemke_regularized`], relative to max|M|.
pub(crate) const REGULARIZATIONS: [f64; 3] = [1e-12, 1e-10, 1e-8];

/// [`lemke`]; if it fails (degenerate problems: nearly dependent rows, such as the friction rows
/// of two corners on one face of a body that cannot move along it), Lemke again on
/// LCP(q, M + δI) for each δ/max|M| in [`REGULARIZATIONS`], and the first candidate that passes
/// the check on the *original* data ([`lcp_residual`] ≤ `check_tolerance`) is the solution.
/// The regularised problem splits what the original leaves undetermined (e.g. the friction
/// between redundant contacts) equally, and its answer is verified, not assumed. When no
/// candidate passes, the original error is returned. `regularized` in the result is δ (0 when
/// the plain problem was solved).
pub fn lemke_regularized(
    m: &DMatrix<f64>,
    q: &DVector<f64>,
    opts: &LemkeOptions,
) -> Result<(LcpSolution, f64), LcpError> {
    let first = match lemke(m, q, opts) {
        Ok(sol) => {
            // the refined point is checked like any candidate; the verified one stands if not
            let refined = refined(m, q, &sol, opts.tolerance.max(0.0))
                .filter(|r| lcp_residual(m, q, &r.z, &r.w) <= opts.check_tolerance);
            return Ok((refined.unwrap_or(sol), 0.0));
        }
        Err(e @ (LcpError::NonFinite | LcpError::DimensionMismatch { .. })) => return Err(e),
        Err(e) => e,
    };
    let m_max = max_abs(m.iter());
    let mut pivots = 0;
    for rel in REGULARIZATIONS {
        let delta = rel * m_max;
        let mut reg = m.clone();
        for i in 0..reg.nrows() {
            reg[(i, i)] += delta;
        }
        let Ok(mut sol) = lemke(&reg, q, opts) else {
            continue;
        };
        pivots += sol.pivots;
        // the regularised answer leaves w_A = −δ z_A on its active set: solve the original
        // there (minimum norm for dependent rows) when that keeps z ≥ 0 and w ≥ 0
        let tol = opts.tolerance.max(0.0);
        if let Some(z) = polish(m, q, &sol.z, &sol.z.map(|v| v > 0.0), tol) {
            sol.z = z;
        } else {
            // degenerate: also the rows where w vanishes or dips below zero
            if let Some(r) = refined(m, q, &sol, tol) {
                sol = r;
            }
        }
        let w = clean_w(m, q, &sol.z, tol);
        if lcp_residual(m, q, &sol.z, &w) <= opts.check_tolerance {
            return Ok((
                LcpSolution {
                    z: sol.z,
                    w,
                    pivots,
                },
                delta,
            ));
        }
    }
    Err(first)
}

/// A solution whose w = Mz + q dips below zero beyond rounding (nearly dependent rows, where
/// pivoting loses digits) re-solved on the set of rows with z > 0 or w ≤ 0 ([`polish`]); None
/// when it needs no refinement or the re-solve fails.
fn refined(m: &DMatrix<f64>, q: &DVector<f64>, sol: &LcpSolution, tol: f64) -> Option<LcpSolution> {
    let w = m * &sol.z + q;
    let scale = max_abs(q.iter()) + max_abs(m.iter()) * max_abs(sol.z.iter());
    let floor = 1e-12 * scale;
    if w.iter().all(|&v| v >= -floor) {
        return None;
    }
    let act = DVector::from_fn(q.len(), |i, _| sol.z[i] > 0.0 || w[i] <= floor);
    let z = polish(m, q, &sol.z, &act, tol)?;
    let w = clean_w(m, q, &z, tol);
    Some(LcpSolution {
        z,
        w,
        pivots: sol.pivots,
    })
}

/// z with its active set A (`active`: zᵢ > 0, or also the degenerate rows where wᵢ vanishes
/// too) re-solved on the original data, M_AA z_A = −q_A (SVD, minimum norm), zero elsewhere —
/// or None when that would make a zᵢ or a wᵢ outside A negative beyond `tol` of their scales.
fn polish(
    m: &DMatrix<f64>,
    q: &DVector<f64>,
    z: &DVector<f64>,
    active: &DVector<bool>,
    tol: f64,
) -> Option<DVector<f64>> {
    let act: Vec<usize> = (0..z.len()).filter(|&i| active[i]).collect();
    if act.is_empty() {
        return None;
    }
    let k = act.len();
    let a = DMatrix::from_fn(k, k, |r, c| m[(act[r], act[c])]);
    let b = DVector::from_fn(k, |r, _| -q[act[r]]);
    let svd = a.svd(true, true);
    let sv_max = svd.singular_values.iter().copied().fold(0.0, f64::max);
    let x = svd.solve(&b, 1e-12 * sv_max).ok()?;
    let z_scale = x.amax();
    if x.iter().any(|v| !v.is_finite() || *v < -tol * z_scale) {
        return None;
    }
    let mut out = DVector::zeros(z.len());
    for (r, &i) in act.iter().enumerate() {
        out[i] = x[r].max(0.0);
    }
    let w = m * &out + q;
    let w_scale = max_abs(q.iter()) + max_abs(m.iter()) * z_scale;
    let outside = (0..z.len()).filter(|i| !act.contains(i));
    for i in outside {
        if w[i] < -tol * w_scale {
            return None;
        }
    }
    Some(out)
}

/// Residual of a candidate `(z, w)` for LCP(q, M), on a scale that does not grow with the
/// candidate: with v = Mz + q recomputed and rᵢ = γ (|M||z| + |q|)ᵢ, γ = 4(n + 2)u, the
/// rounding of vᵢ in floating point (Higham 2002, §3.1), the largest of
/// `(−vᵢ − rᵢ)⁺` (w ≥ 0), `max|M|·(−zᵢ)⁺` (z ≥ 0), `min((|vᵢ| − rᵢ)⁺, max|M|·zᵢ)`
/// (complementarity: a positive zᵢ beside a positive wᵢ, counted by the smaller of wᵢ and the
/// zᵢ's effect on w) and `(|wᵢ − vᵢ| − rᵢ)⁺` (w is Mz + q), each divided by max|q| (by
/// max|M|·max|z| when q = 0, a homogeneous problem). A huge z cannot make it small: it only
/// widens rᵢ, by u·|M||z|. Returns `+∞` on a size mismatch or non-finite input, 0 for n = 0.
/// [`lemke`] and [`lemke_regularized`] accept a candidate when it is ≤
/// [`LemkeOptions::check_tolerance`].
pub fn lcp_residual(m: &DMatrix<f64>, q: &DVector<f64>, z: &DVector<f64>, w: &DVector<f64>) -> f64 {
    let n = q.len();
    if m.nrows() != n || m.ncols() != n || z.len() != n || w.len() != n {
        return f64::INFINITY;
    }
    if m.iter()
        .chain(q.iter())
        .chain(z.iter())
        .chain(w.iter())
        .any(|v| !v.is_finite())
    {
        return f64::INFINITY;
    }
    if n == 0 {
        return 0.0;
    }
    let m_max = max_abs(m.iter());
    let mut scale = max_abs(q.iter());
    if scale == 0.0 {
        scale = m_max * max_abs(z.iter());
    }
    let gamma = rounding_gamma(n);
    let mut worst = 0.0f64;
    for i in 0..n {
        let (mut v, mut abs) = (q[i], q[i].abs());
        for j in 0..n {
            v += m[(i, j)] * z[j];
            abs += (m[(i, j)] * z[j]).abs();
        }
        let r = gamma * abs;
        let viol = (-v - r)
            .max(-z[i] * m_max)
            .max((v.abs() - r).max(0.0).min(m_max * z[i]));
        // a wᵢ cleaned to 0 beside a positive zᵢ is judged by complementarity, on vᵢ
        let viol = if w[i] == 0.0 && z[i] > 0.0 {
            viol
        } else {
            viol.max((w[i] - v).abs() - r)
        };
        worst = worst.max(viol);
    }
    if worst <= 0.0 {
        return 0.0;
    }
    let res = worst / scale;
    if res.is_finite() { res } else { f64::INFINITY }
}

/// γ = 4(n + 2)u: a bound on the relative rounding of an n-term dot product plus q.
fn rounding_gamma(n: usize) -> f64 {
    4.0 * (n as f64 + 2.0) * f64::EPSILON
}

/// w = Mz + q with the entries within their rounding (γ (|M||z| + |q|)ᵢ) set to 0, and those
/// beside a positive zᵢ within `tol` of max|q| + max|M|·max|z| (complementary pairs: wᵢ is
/// nonbasic there, the pivoting's error is no slack).
fn clean_w(m: &DMatrix<f64>, q: &DVector<f64>, z: &DVector<f64>, tol: f64) -> DVector<f64> {
    let n = q.len();
    let gamma = rounding_gamma(n);
    let pair = tol * (max_abs(q.iter()) + max_abs(m.iter()) * max_abs(z.iter()));
    DVector::from_fn(n, |i, _| {
        let (mut v, mut abs) = (q[i], q[i].abs());
        for j in 0..n {
            v += m[(i, j)] * z[j];
            abs += (m[(i, j)] * z[j]).abs();
        }
        let paired = z[i] > 0.0 && v.abs() <= pair;
        if v.abs() <= gamma * abs || paired {
            0.0
        } else {
            v
        }
    })
}

enum Outcome {
    Solved(usize),
    Ray(usize),
    Cap(usize),
    Breakdown,
}

/// Runs the complementary path from the initial tableau; `observe` sees the
/// tableau after every pivot.
fn follow_path(
    tab: &mut Tableau,
    max_pivots: usize,
    tol: f64,
    rule: TieBreak,
    mut observe: impl FnMut(&Tableau),
) -> Outcome {
    // Initial pivot: z0 enters, the row with the most negative q leaves.
    if max_pivots == 0 {
        return Outcome::Cap(0);
    }
    let r = tab.initial_row(tol, rule);
    let mut leaving = tab.basis[r];
    tab.pivot(r, tab.z0());
    let mut pivots = 1usize;
    observe(tab);
    loop {
        if pivots >= max_pivots {
            return Outcome::Cap(pivots);
        }
        let entering = tab.complement(leaving);
        let r = match tab.ratio_test(entering, tol, rule) {
            Choice::Row(r) => r,
            Choice::Ray => return Outcome::Ray(pivots),
            Choice::Breakdown => return Outcome::Breakdown,
        };
        leaving = tab.basis[r];
        tab.pivot(r, entering);
        pivots += 1;
        observe(tab);
        if leaving == tab.z0() {
            return Outcome::Solved(pivots);
        }
    }
}

fn max_abs<'a>(it: impl Iterator<Item = &'a f64>) -> f64 {
    it.fold(0.0, |acc, v| acc.max(v.abs()))
}

/// Largest power of two ≤ `x` (1 for `x = 0`), clamped to the normal range.
fn pow2_floor(x: f64) -> f64 {
    if x <= 0.0 || !x.is_finite() {
        return 1.0;
    }
    let e = (x.log2().floor() as i64).clamp(-1022, 1023);
    let p = f64::from_bits(((e + 1023) as u64) << 52);
    // Guard against log2 rounding up across a power of two.
    if p > x && e > -1022 { p / 2.0 } else { p }
}

enum Choice {
    Row(usize),
    Ray,
    Breakdown,
}

/// Dense tableau `B⁻¹ [I | −M | −d | q]`; columns `0..n` are `w`, `n..2n`
/// are `z`, `2n` is `z0` and `2n+1` is the right-hand side. The `w` block
/// holds `B⁻¹`, used by the lexicographic test.
struct Tableau {
    n: usize,
    width: usize,
    t: Vec<f64>,
    basis: Vec<usize>,
    prow: Vec<f64>,
}

impl Tableau {
    fn new(m: &DMatrix<f64>, q: &DVector<f64>, m_scale: f64, q_scale: f64) -> Self {
        let n = q.len();
        let width = 2 * n + 2;
        let mut t = vec![0.0; n * width];
        for i in 0..n {
            let row = &mut t[i * width..(i + 1) * width];
            row[i] = 1.0;
            for j in 0..n {
                row[n + j] = -m[(i, j)] * m_scale;
            }
            row[2 * n] = -1.0;
            row[2 * n + 1] = q[i] * q_scale;
        }
        Self {
            n,
            width,
            t,
            basis: (0..n).collect(),
            prow: vec![0.0; width],
        }
    }

    fn z0(&self) -> usize {
        2 * self.n
    }

    fn complement(&self, var: usize) -> usize {
        if var < self.n {
            var + self.n
        } else {
            var - self.n
        }
    }

    fn at(&self, i: usize, j: usize) -> f64 {
        self.t[i * self.width + j]
    }

    fn rhs(&self, i: usize) -> f64 {
        self.at(i, self.width - 1)
    }

    /// Lexicographic comparison of rows `i` and `k` of `B⁻¹`, divided by the
    /// positive divisors `di`, `dk`: true if row `i` is strictly smaller.
    /// Exact ties (only possible through rounding) go to the larger divisor.
    fn lex_less(&self, i: usize, di: f64, k: usize, dk: f64, tol: f64) -> bool {
        for c in 0..self.n {
            let a = self.at(i, c) / di;
            let b = self.at(k, c) / dk;
            if (a - b).abs() <= tol * 1f64.max(a.abs()).max(b.abs()) {
                continue;
            }
            return a < b;
        }
        di > dk
    }

    /// Leaving row for the first pivot (z0 enters): the most negative
    /// right-hand side, ties broken lexicographically (i.e. the largest index,
    /// which keeps every row lexicographically positive afterwards).
    fn initial_row(&self, tol: f64, rule: TieBreak) -> usize {
        let n = self.n;
        let mut q_min = f64::INFINITY;
        let mut b_max = 0.0f64;
        for i in 0..n {
            q_min = q_min.min(self.rhs(i));
            b_max = b_max.max(self.rhs(i).abs());
        }
        let zero_tol = tol * b_max.max(1.0);
        let mut best: Option<usize> = None;
        for i in 0..n {
            if self.rhs(i) > q_min + zero_tol {
                continue;
            }
            best = match (best, rule) {
                (None, _) => Some(i),
                (Some(k), TieBreak::Lexicographic) => {
                    // Divisor d_i = 1 for every row.
                    if self.lex_less(i, 1.0, k, 1.0, tol) {
                        Some(i)
                    } else {
                        Some(k)
                    }
                }
                (Some(k), TieBreak::FirstIndex) => Some(k),
            };
        }
        best.unwrap_or(0)
    }

    /// Minimum-ratio test for entering column `j`. Rows within `tol` of the
    /// minimum ratio are tied; `z0` leaves if it is among them, otherwise the
    /// tie is broken by `rule`.
    fn ratio_test(&self, j: usize, tol: f64, rule: TieBreak) -> Choice {
        let n = self.n;
        let mut col_max = 0.0f64;
        let mut b_max = 0.0f64;
        for i in 0..n {
            let a = self.at(i, j);
            let b = self.rhs(i);
            if !a.is_finite() || !b.is_finite() {
                return Choice::Breakdown;
            }
            col_max = col_max.max(a.abs());
            b_max = b_max.max(b.abs());
        }
        let piv_tol = tol * col_max.max(1.0);
        let zero_tol = tol * b_max.max(1.0);
        let mut theta = f64::INFINITY;
        for i in 0..n {
            let a = self.at(i, j);
            if a > piv_tol {
                theta = theta.min((self.rhs(i).max(0.0) + zero_tol) / a);
            }
        }
        if theta == f64::INFINITY {
            return Choice::Ray;
        }
        let mut best: Option<usize> = None;
        for i in 0..n {
            let a = self.at(i, j);
            if !(a > piv_tol && self.rhs(i).max(0.0) / a <= theta) {
                continue;
            }
            if self.basis[i] == self.z0() {
                return Choice::Row(i);
            }
            best = match (best, rule) {
                (None, _) => Some(i),
                (Some(k), TieBreak::Lexicographic) => {
                    if self.lex_less(i, a, k, self.at(k, j), tol) {
                        Some(i)
                    } else {
                        Some(k)
                    }
                }
                (Some(k), TieBreak::FirstIndex) => Some(k),
            };
        }
        match best {
            Some(r) => Choice::Row(r),
            None => Choice::Breakdown,
        }
    }

    /// Gauss–Jordan pivot on `(r, j)`; `j` becomes basic in row `r`.
    fn pivot(&mut self, r: usize, j: usize) {
        let w = self.width;
        let p = self.t[r * w + j];
        for v in &mut self.t[r * w..(r + 1) * w] {
            *v /= p;
        }
        self.t[r * w + j] = 1.0;
        self.prow.copy_from_slice(&self.t[r * w..(r + 1) * w]);
        for i in 0..self.n {
            if i == r {
                continue;
            }
            let f = self.t[i * w + j];
            if f != 0.0 {
                let row = &mut self.t[i * w..(i + 1) * w];
                for (v, &pv) in row.iter_mut().zip(self.prow.iter()) {
                    *v -= f * pv;
                }
                row[j] = 0.0;
            }
        }
        self.basis[r] = j;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Checks the invariant behind the lexicographic rule (Cottle, Pang &
    /// Stone 1992, §4.4): while z0 is basic, every row of `[b | B⁻¹]` is
    /// lexicographically positive. Returns whether it held, and the outcome.
    fn lex_invariant(m: &DMatrix<f64>, q: &DVector<f64>, rule: TieBreak) -> (bool, Outcome) {
        let mut tab = Tableau::new(m, q, 1.0, 1.0);
        let n = q.len();
        let mut ok = true;
        let outcome = follow_path(&mut tab, 2000, 1e-12, rule, |t| {
            if !t.basis.contains(&t.z0()) {
                return;
            }
            for i in 0..n {
                let first = std::iter::once(t.rhs(i))
                    .chain((0..n).map(|c| t.at(i, c)))
                    .find(|v| v.abs() > 1e-9);
                ok &= first.is_some_and(|v| v > 0.0);
            }
        });
        (ok, outcome)
    }

    /// Small integer problems with many ties (deterministic LCG).
    fn degenerate_problems() -> Vec<(DMatrix<f64>, DVector<f64>)> {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move |k: u64| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 33) % k) as f64
        };
        let mut out = vec![(
            DMatrix::from_row_slice(3, 3, &[1.0, 2.0, 0.0, 0.0, 1.0, 2.0, 2.0, 0.0, 1.0]),
            DVector::from_element(3, -1.0),
        )];
        for _ in 0..400 {
            let n = 2 + next(5) as usize;
            let m = DMatrix::from_fn(n, n, |_, _| next(5) - 2.0);
            let q = DVector::from_fn(n, |_, _| next(3) - 1.0);
            // q ≥ 0 is answered before any pivot.
            if q.iter().any(|&v| v < 0.0) {
                out.push((m, q));
            }
        }
        out
    }

    #[test]
    fn lexicographic_rows_stay_positive_and_never_cap() {
        for (m, q) in degenerate_problems() {
            let (ok, outcome) = lex_invariant(&m, &q, TieBreak::Lexicographic);
            assert!(ok, "lexicographic invariant broken for M = {m}, q = {q}");
            assert!(
                !matches!(outcome, Outcome::Cap(_) | Outcome::Breakdown),
                "no termination for M = {m}, q = {q}"
            );
        }
    }

    #[test]
    fn first_index_rule_breaks_the_invariant() {
        let broken = degenerate_problems()
            .iter()
            .filter(|(m, q)| !lex_invariant(m, q, TieBreak::FirstIndex).0)
            .count();
        assert!(broken > 0);
    }

    #[test]
    fn pow2_floor_is_exact() {
        assert_eq!(pow2_floor(0.0), 1.0);
        assert_eq!(pow2_floor(1.0), 1.0);
        assert_eq!(pow2_floor(3.0), 2.0);
        assert_eq!(pow2_floor(4.0), 4.0);
        assert_eq!(pow2_floor(0.3), 0.25);
        assert_eq!(pow2_floor(f64::MAX), 2f64.powi(1023));
        assert!(pow2_floor(1e-310) > 0.0);
    }
}
