//! Integration tests for `deckspin::lemke`.

use approx::assert_abs_diff_eq;
use deckspin::lemke::{
    LcpError, LcpSolution, LemkeOptions, TieBreak, lcp_residual, lemke, lemke_regularized,
    lemke_with_tie_break,
};
use nalgebra::{DMatrix, DVector};
use proptest::prelude::*;

// ---------------------------------------------------------------- helpers

fn opts() -> LemkeOptions {
    LemkeOptions::default()
}

/// Independent check of a returned solution: w = Mz+q componentwise,
/// w ≥ -tol, z ≥ -tol, |w_i z_i| ≤ tol (all relative to the data scale).
fn assert_verified(m: &DMatrix<f64>, q: &DVector<f64>, sol: &LcpSolution, tol: f64) {
    let n = q.len();
    assert_eq!(sol.z.len(), n);
    assert_eq!(sol.w.len(), n);
    let scale = 1.0 + q.amax() + m.amax() * sol.z.amax();
    let mz_q = m * &sol.z + q;
    for i in 0..n {
        assert!(
            (sol.w[i] - mz_q[i]).abs() <= tol * scale,
            "w[{i}] = {} but (Mz+q)[{i}] = {}",
            sol.w[i],
            mz_q[i]
        );
        assert!(sol.w[i] >= -tol * scale, "w[{i}] = {} < 0", sol.w[i]);
        assert!(sol.z[i] >= -tol * scale, "z[{i}] = {} < 0", sol.z[i]);
        assert!(
            (sol.w[i] * sol.z[i]).abs() <= tol * scale * (1.0 + sol.z.amax()),
            "complementarity fails at {i}: w = {}, z = {}",
            sol.w[i],
            sol.z[i]
        );
    }
    assert!(lcp_residual(m, q, &sol.z, &sol.w) <= 1e-9);
}

/// The cleaning step makes w_i z_i exactly 0 on well-conditioned problems.
fn assert_exactly_complementary(sol: &LcpSolution) {
    for (i, (w, z)) in sol.w.iter().zip(sol.z.iter()).enumerate() {
        assert!(w * z == 0.0, "w[{i}] = {w:e}, z[{i}] = {z:e}");
    }
}

/// All solutions found by enumerating the 2ⁿ complementary bases
/// (z_α = -M_αα⁻¹ q_α, z = 0 elsewhere), kept if z ≥ 0 and w ≥ 0.
fn brute_force(m: &DMatrix<f64>, q: &DVector<f64>, tol: f64) -> Vec<DVector<f64>> {
    let n = q.len();
    let mut out = Vec::new();
    for mask in 0u32..(1u32 << n) {
        let idx: Vec<usize> = (0..n).filter(|i| (mask >> i) & 1 == 1).collect();
        let k = idx.len();
        let mut z = DVector::zeros(n);
        if k > 0 {
            let a = DMatrix::from_fn(k, k, |r, c| m[(idx[r], idx[c])]);
            let b = DVector::from_fn(k, |r, _| -q[idx[r]]);
            let Some(x) = a.lu().solve(&b) else { continue };
            for (r, &i) in idx.iter().enumerate() {
                z[i] = x[r];
            }
        }
        let w = m * &z + q;
        let scale = 1.0 + q.amax() + m.amax() * z.amax();
        if z.iter().chain(w.iter()).all(|&v| v >= -tol * scale) {
            out.push(z);
        }
    }
    out
}

/// For a P-matrix: every complementary basis solution found by enumeration
/// equals Lemke's z (uniqueness), and there is at least one.
fn assert_matches_brute_force(m: &DMatrix<f64>, q: &DVector<f64>, z: &DVector<f64>) {
    let all = brute_force(m, q, 1e-10);
    assert!(!all.is_empty(), "brute force found no solution");
    for zb in &all {
        let tol = 1e-7 * (1.0 + zb.amax());
        assert!(
            (zb - z).amax() <= tol,
            "solution not unique / mismatch: lemke {z:?} vs enumeration {zb:?}"
        );
    }
}

/// Murty's matrix in the orientation of the brief: 1 on the diagonal,
/// 2 above it, 0 below.
fn murty_upper(n: usize) -> DMatrix<f64> {
    DMatrix::from_fn(n, n, |i, j| match j.cmp(&i) {
        std::cmp::Ordering::Equal => 1.0,
        std::cmp::Ordering::Greater => 2.0,
        std::cmp::Ordering::Less => 0.0,
    })
}

/// q_i = -(2^{n+1} - 2^i), i = 1..n (1-based).
fn murty_q_upper(n: usize) -> DVector<f64> {
    DVector::from_fn(n, |i, _| {
        -(2f64.powi(n as i32 + 1) - 2f64.powi(i as i32 + 1))
    })
}

/// Murty (1978; 1988 ch. 6): M̃(n) lower triangular (1 on the diagonal,
/// 2 below), q̂(n) = (-2ⁿ, -2ⁿ-2ⁿ⁻¹, …, -2ⁿ-…-2).
fn murty_lower(n: usize) -> DMatrix<f64> {
    murty_upper(n).transpose()
}

fn murty_q_hat(n: usize) -> DVector<f64> {
    DVector::from_fn(n, |i, _| {
        -(2f64.powi(n as i32 + 1) - 2f64.powi((n - i) as i32))
    })
}

fn unit(n: usize, k: usize, scale: f64) -> DVector<f64> {
    let mut v = DVector::zeros(n);
    v[k] = scale;
    v
}

fn cycling_example() -> (DMatrix<f64>, DVector<f64>) {
    (
        DMatrix::from_row_slice(3, 3, &[1.0, 2.0, 0.0, 0.0, 1.0, 2.0, 2.0, 0.0, 1.0]),
        DVector::from_element(3, -1.0),
    )
}

// ------------------------------------------------------- property tests

fn spd_problem() -> impl Strategy<Value = (DMatrix<f64>, DVector<f64>)> {
    (1usize..=12).prop_flat_map(|n| {
        (
            prop::collection::vec(-1.0f64..1.0, n * n),
            prop::collection::vec(-1.0f64..1.0, n),
            0.01f64..1.0,
            prop::sample::select(vec![1e-3, 1.0, 1e3]),
        )
            .prop_map(move |(a, q, delta, s)| {
                let a = DMatrix::from_row_slice(n, n, &a);
                let m = &a * a.transpose() + DMatrix::identity(n, n) * delta;
                (m, DVector::from_vec(q) * s)
            })
    })
}

/// Strictly row-diagonally-dominant with positive diagonal: a non-symmetric
/// P-matrix.
fn sdd_problem() -> impl Strategy<Value = (DMatrix<f64>, DVector<f64>)> {
    (1usize..=12).prop_flat_map(|n| {
        (
            prop::collection::vec(-1.0f64..1.0, n * n),
            prop::collection::vec(-1.0f64..1.0, n),
            0.05f64..2.0,
        )
            .prop_map(move |(a, q, delta)| {
                let mut m = DMatrix::from_row_slice(n, n, &a);
                for i in 0..n {
                    let off: f64 = (0..n).filter(|&j| j != i).map(|j| m[(i, j)].abs()).sum();
                    m[(i, i)] = off + delta;
                }
                (m, DVector::from_vec(q))
            })
    })
}

/// Singular PSD M = A Aᵀ (A is n×k, k < n) with q built from a known
/// complementary pair, so a solution exists.
fn psd_solvable_problem() -> impl Strategy<Value = (DMatrix<f64>, DVector<f64>)> {
    (2usize..=10).prop_flat_map(|n| {
        (
            1..n,
            prop::collection::vec(-1.0f64..1.0, n * n),
            prop::collection::vec(0.0f64..1.0, n),
            prop::collection::vec(any::<bool>(), n),
        )
            .prop_map(move |(k, a, v, support)| {
                let a = DMatrix::from_row_slice(n, n, &a).columns(0, k).into_owned();
                let m = &a * a.transpose();
                let z = DVector::from_fn(n, |i, _| if support[i] { v[i] } else { 0.0 });
                let w = DVector::from_fn(n, |i, _| if support[i] { 0.0 } else { v[i] });
                let q = w - &m * z;
                (m, q)
            })
    })
}

fn wild_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -10.0f64..10.0,
        1 => Just(0.0),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(-1e300),
        1 => Just(1e-300),
    ]
}

proptest! {
    #[test]
    fn spd_p_matrices_solved_and_unique((m, q) in spd_problem()) {
        let sol = lemke(&m, &q, &opts()).expect("P-matrix LCP must be solved");
        assert_exactly_complementary(&sol);
        assert_verified(&m, &q, &sol, 1e-9);
        if q.len() <= 6 {
            assert_matches_brute_force(&m, &q, &sol.z);
        }
    }

    #[test]
    fn nonsymmetric_p_matrices_solved_and_unique((m, q) in sdd_problem()) {
        let sol = lemke(&m, &q, &opts()).expect("P-matrix LCP must be solved");
        assert_exactly_complementary(&sol);
        assert_verified(&m, &q, &sol, 1e-9);
        if q.len() <= 6 {
            assert_matches_brute_force(&m, &q, &sol.z);
        }
    }

    #[test]
    fn singular_psd_with_solution_is_solved((m, q) in psd_solvable_problem()) {
        let sol = lemke(&m, &q, &opts()).expect("feasible PSD LCP must be solved");
        assert_verified(&m, &q, &sol, 1e-9);
    }

    #[test]
    fn never_panics_and_ok_means_verified(
        (m, q) in (0usize..=5).prop_flat_map(|n| (
            prop::collection::vec(wild_f64(), n * n),
            prop::collection::vec(wild_f64(), n),
        ).prop_map(move |(a, q)| (DMatrix::from_row_slice(n, n, &a), DVector::from_vec(q))))
    ) {
        let finite = m.iter().chain(q.iter()).all(|v| v.is_finite());
        match lemke(&m, &q, &opts()) {
            Ok(sol) => prop_assert!(lcp_residual(&m, &q, &sol.z, &sol.w) <= 1e-9),
            Err(LcpError::NonFinite) => prop_assert!(!finite),
            Err(LcpError::DimensionMismatch { .. }) => prop_assert!(false, "sizes match"),
            Err(_) => prop_assert!(finite),
        }
    }
}

// ------------------------------------------------- Murty's exponential example

/// M = I + 2·(strictly upper ones), q_i = -(2^{n+1} - 2^i): Lemke with d = e
/// takes exactly 2ⁿ pivots (initial z0 pivot and final z0-leaving pivot
/// included) and ends at z = 2ⁿ e_n, the unique solution.
#[test]
fn murty_exponential_upper_orientation() {
    for n in 3..=10 {
        let (m, q) = (murty_upper(n), murty_q_upper(n));
        let sol = lemke(&m, &q, &opts()).unwrap();
        assert_eq!(sol.pivots, 1 << n, "n = {n}");
        let expected = unit(n, n - 1, 2f64.powi(n as i32));
        assert_eq!(sol.z, expected, "n = {n}");
        assert_verified(&m, &q, &sol, 1e-12);
        let all = brute_force(&m, &q, 1e-12);
        assert_eq!(all, vec![expected], "n = {n}");
    }
}

/// Murty's original orientation (M̃(n) lower triangular, q̂(n)): 2ⁿ pivots,
/// z = 2ⁿ e_1.
#[test]
fn murty_exponential_original_orientation() {
    for n in 3..=10 {
        let (m, q) = (murty_lower(n), murty_q_hat(n));
        let sol = lemke(&m, &q, &opts()).unwrap();
        assert_eq!(sol.pivots, 1 << n, "n = {n}");
        let expected = unit(n, 0, 2f64.powi(n as i32));
        assert_eq!(sol.z, expected, "n = {n}");
        let all = brute_force(&m, &q, 1e-12);
        assert_eq!(all, vec![expected], "n = {n}");
    }
}

#[test]
fn pivot_cap_is_reported() {
    let (m, q) = (murty_upper(8), murty_q_upper(8));
    let o = LemkeOptions {
        max_pivots: 100,
        ..opts()
    };
    match lemke(&m, &q, &o) {
        Err(LcpError::PivotCap {
            pivots,
            m: em,
            q: eq,
        }) => {
            assert_eq!(pivots, 100);
            assert_eq!((em, eq), (m.clone(), q.clone()));
        }
        other => panic!("expected PivotCap, got {other:?}"),
    }
    // Exactly enough pivots succeeds.
    let o = LemkeOptions {
        max_pivots: 256,
        ..opts()
    };
    assert_eq!(lemke(&m, &q, &o).unwrap().pivots, 256);
    let o = LemkeOptions {
        max_pivots: 255,
        ..opts()
    };
    assert!(matches!(
        lemke(&m, &q, &o),
        Err(LcpError::PivotCap { pivots: 255, .. })
    ));
}

// ------------------------------------------------------------ degeneracy

#[test]
fn cycling_example_terminates_with_lexicographic_rule() {
    let (m, q) = cycling_example();
    let sol = lemke(&m, &q, &opts()).unwrap();
    assert!(sol.pivots <= 10, "took {} pivots", sol.pivots);
    for i in 0..3 {
        assert_abs_diff_eq!(sol.z[i], 1.0 / 3.0, epsilon = 1e-12);
        assert_abs_diff_eq!(sol.w[i], 0.0, epsilon = 1e-12);
    }
    assert_verified(&m, &q, &sol, 1e-12);
}

/// With smallest-index tie-breaking the same problem cycles: a 3×3 problem
/// has at most C(7,3) = 35 bases, so 200 pivots means a basis repeated.
#[test]
fn cycling_example_cycles_with_first_index_rule() {
    let (m, q) = cycling_example();
    let o = LemkeOptions {
        max_pivots: 200,
        ..opts()
    };
    assert!(matches!(
        lemke_with_tie_break(&m, &q, &o, TieBreak::FirstIndex),
        Err(LcpError::PivotCap { pivots: 200, .. })
    ));
    assert!(lemke_with_tie_break(&m, &q, &o, TieBreak::Lexicographic).is_ok());
}

#[test]
fn q_with_zeros_p_matrix() {
    let m = DMatrix::from_row_slice(
        4,
        4,
        &[
            4.0, 1.0, 0.0, -1.0, //
            1.0, 3.0, 1.0, 0.0, //
            0.0, -1.0, 2.0, 0.5, //
            1.0, 0.0, 0.5, 3.0,
        ],
    );
    for q in [
        DVector::from_vec(vec![0.0, -1.0, 0.0, -1.0]),
        DVector::from_vec(vec![-1.0, 0.0, -1.0, 0.0]),
        DVector::from_vec(vec![0.0, 0.0, 0.0, -1.0]),
        DVector::from_vec(vec![-1.0, -1.0, -1.0, -1.0]),
    ] {
        let sol = lemke(&m, &q, &opts()).unwrap();
        assert_verified(&m, &q, &sol, 1e-12);
        assert_matches_brute_force(&m, &q, &sol.z);
    }
}

/// Degenerate start: all q tied (Murty's lower matrix with q = -e).
#[test]
fn all_ties_in_q() {
    for n in 1..=8 {
        let m = murty_lower(n);
        let q = DVector::from_element(n, -1.0);
        let sol = lemke(&m, &q, &opts()).unwrap();
        assert_verified(&m, &q, &sol, 1e-12);
        assert_eq!(sol.z, unit(n, 0, 1.0));
    }
}

/// Redundant contacts: duplicated rows of the contact Jacobian give
/// duplicated rows and columns of M = J Jᵀ (singular PSD).
#[test]
fn duplicated_rows_redundant_contacts() {
    let j = DMatrix::from_row_slice(
        4,
        2,
        &[
            1.0, 0.0, //
            1.0, 0.0, //
            0.0, 1.0, //
            0.0, 1.0,
        ],
    );
    let m = &j * j.transpose();
    let v = DVector::from_vec(vec![-1.0, -2.0]);
    let q = &j * v;
    let sol = lemke(&m, &q, &opts()).unwrap();
    assert_verified(&m, &q, &sol, 1e-12);
    assert_abs_diff_eq!(sol.z[0] + sol.z[1], 1.0, epsilon = 1e-12);
    assert_abs_diff_eq!(sol.z[2] + sol.z[3], 2.0, epsilon = 1e-12);

    // Mixed: one pair pushing, one pair separating.
    let q = &j * DVector::from_vec(vec![-1.0, 0.5]);
    let sol = lemke(&m, &q, &opts()).unwrap();
    assert_verified(&m, &q, &sol, 1e-12);
    assert_abs_diff_eq!(sol.z[0] + sol.z[1], 1.0, epsilon = 1e-12);
    assert_eq!((sol.z[2], sol.z[3]), (0.0, 0.0));
}

#[test]
fn singular_psd_with_solution() {
    let m = DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 1.0, 1.0]);
    let q = DVector::from_vec(vec![-1.0, -1.0]);
    let sol = lemke(&m, &q, &opts()).unwrap();
    assert_verified(&m, &q, &sol, 1e-12);
    assert_abs_diff_eq!(sol.z[0] + sol.z[1], 1.0, epsilon = 1e-12);

    // Zero row/column with q = 0 there.
    let m = DMatrix::from_row_slice(2, 2, &[2.0, 0.0, 0.0, 0.0]);
    let q = DVector::from_vec(vec![-1.0, 0.0]);
    let sol = lemke(&m, &q, &opts()).unwrap();
    assert_verified(&m, &q, &sol, 1e-12);
    assert_abs_diff_eq!(sol.z[0], 0.5, epsilon = 1e-12);
}

// --------------------------------------------------------- ray termination

/// M = [[1,-1],[-1,1]] is PSD (so copositive-plus); with q = (-1,-1) the
/// rows of Mz+q add up to -2 < 0, so no z ≥ 0 is feasible.
#[test]
fn infeasible_psd_ends_on_ray() {
    let m = DMatrix::from_row_slice(2, 2, &[1.0, -1.0, -1.0, 1.0]);
    let q = DVector::from_vec(vec![-1.0, -1.0]);
    assert!(brute_force(&m, &q, 1e-12).is_empty());
    match lemke(&m, &q, &opts()) {
        Err(LcpError::Ray {
            pivots,
            m: em,
            q: eq,
        }) => {
            assert!(pivots <= 5, "ray after {pivots} pivots");
            assert_eq!((em, eq), (m, q));
        }
        other => panic!("expected Ray, got {other:?}"),
    }
}

#[test]
fn zero_matrix_negative_q_is_ray() {
    let m = DMatrix::zeros(1, 1);
    let q = DVector::from_vec(vec![-1.0]);
    assert!(matches!(
        lemke(&m, &q, &opts()),
        Err(LcpError::Ray { pivots: 1, .. })
    ));
}

// ---------------------------------------------------- trivial and bad input

#[test]
fn nonnegative_q_returns_zero_without_pivots() {
    let m = DMatrix::from_row_slice(2, 2, &[1.0, -3.0, 2.0, 0.0]);
    let q = DVector::from_vec(vec![0.0, 2.5]);
    let sol = lemke(&m, &q, &opts()).unwrap();
    assert_eq!(sol.pivots, 0);
    assert_eq!(sol.z, DVector::zeros(2));
    assert_eq!(sol.w, q);
}

#[test]
fn empty_problem() {
    let sol = lemke(&DMatrix::zeros(0, 0), &DVector::zeros(0), &opts()).unwrap();
    assert_eq!(sol.z.len(), 0);
    assert_eq!(sol.w.len(), 0);
    assert_eq!(sol.pivots, 0);
}

#[test]
fn non_finite_input() {
    let m = DMatrix::identity(2, 2);
    let q = DVector::from_vec(vec![f64::NAN, -1.0]);
    assert!(matches!(lemke(&m, &q, &opts()), Err(LcpError::NonFinite)));
    let mut m_inf = DMatrix::identity(2, 2);
    m_inf[(0, 1)] = f64::INFINITY;
    let q = DVector::from_vec(vec![-1.0, -1.0]);
    assert!(matches!(
        lemke(&m_inf, &q, &opts()),
        Err(LcpError::NonFinite)
    ));
}

#[test]
fn dimension_mismatch() {
    let q = DVector::from_vec(vec![-1.0, -1.0]);
    assert!(matches!(
        lemke(&DMatrix::zeros(2, 3), &q, &opts()),
        Err(LcpError::DimensionMismatch {
            rows: 2,
            cols: 3,
            q_len: 2
        })
    ));
    assert!(matches!(
        lemke(&DMatrix::identity(3, 3), &q, &opts()),
        Err(LcpError::DimensionMismatch {
            rows: 3,
            cols: 3,
            q_len: 2
        })
    ));
}

#[test]
fn residual_detects_bad_candidates() {
    let m = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 2.0]);
    let q = DVector::from_vec(vec![-1.0, -1.0]);
    let z = DVector::from_element(2, 1.0 / 3.0);
    let w = &m * &z + &q;
    assert!(lcp_residual(&m, &q, &z, &w) < 1e-15);
    // w inconsistent with Mz+q.
    assert!(lcp_residual(&m, &q, &z, &DVector::from_element(2, 0.1)) > 1e-3);
    // Negative z.
    let zn = DVector::from_vec(vec![-0.5, 0.0]);
    let wn = &m * &zn + &q;
    assert!(lcp_residual(&m, &q, &zn, &wn) > 1e-3);
    // Not complementary: z = (1,1), w = (2,2).
    let zc = DVector::from_element(2, 1.0);
    let wc = &m * &zc + &q;
    assert!(lcp_residual(&m, &q, &zc, &wc) > 1e-3);
    // Size mismatch and NaN.
    assert_eq!(lcp_residual(&m, &q, &DVector::zeros(3), &w), f64::INFINITY);
    assert_eq!(
        lcp_residual(&m, &q, &DVector::from_element(2, f64::NAN), &w),
        f64::INFINITY
    );
}

#[test]
fn error_messages_render() {
    let m = DMatrix::zeros(1, 1);
    let q = DVector::from_vec(vec![-1.0]);
    let e = lemke(&m, &q, &opts()).unwrap_err();
    assert!(e.to_string().contains("ray"));
    let e = LcpError::DimensionMismatch {
        rows: 1,
        cols: 2,
        q_len: 3,
    };
    assert!(e.to_string().contains("1x2"));
}

/// The impact LCP of the bridge at ε = 1 when both corners of one deck end hit an abutment
/// that cannot move along its face (t = 4.473 s of run 4): the two friction rows are dependent
/// to 1e-9. Plain Lemke's answer fails its check; the regularised retry is verified on the
/// original data.
#[test]
fn degenerate_friction_rows_are_solved_by_the_regularised_retry() {
    let m = DMatrix::from_column_slice(
        6,
        6,
        &[
            6.567765879763651,
            -3.0918247541016317,
            -0.011465723917139098,
            -0.011465841379624484,
            1.0,
            0.0,
            -3.0933007441637543,
            5.828193700844168,
            -0.014417821503869614,
            -0.014417713016776263,
            0.0,
            1.0,
            0.001994151719265691,
            -0.0009579458854138604,
            0.02691975127280958,
            0.026919751236911506,
            -1.0,
            0.0,
            0.001994034238831269,
            -0.0009578374162681722,
            0.026919751236911506,
            0.02691975120101618,
            0.0,
            -1.0,
            0.0,
            0.0,
            1.0,
            0.0,
            0.0,
            0.0,
            0.0,
            0.0,
            0.0,
            1.0,
            0.0,
            0.0,
        ],
    );
    let q = DVector::from_vec(vec![
        -0.002821997802779445,
        -0.002424417659143129,
        -0.09140303599481804,
        -0.09140303599240074,
        0.0,
        0.0,
    ]);
    let opts = LemkeOptions {
        check_tolerance: 1e-7,
        ..LemkeOptions::default()
    };
    assert!(matches!(
        lemke(&m, &q, &opts),
        Err(LcpError::CheckFailed { .. })
    ));
    let (sol, delta) = lemke_regularized(&m, &q, &opts).expect("regularised solve");
    assert!(delta > 0.0 && delta <= 1e-8 * 6.6, "δ = {delta:e}");
    let w = &m * &sol.z + &q;
    assert!(lcp_residual(&m, &q, &sol.z, &w) <= 1e-7);
    // both normal impulses positive (both corners hit), and w ⊥ z to the check's scale
    assert!(sol.z[0] > 0.0 && sol.z[1] > 0.0, "{}", sol.z);
    let s = 1.0 + q.amax() + m.amax() * sol.z.amax();
    for i in 0..6 {
        assert!(
            sol.z[i] >= 0.0 && w[i] >= -1e-7 * s && (sol.z[i] * w[i]).abs() < 1e-7 * s,
            "{i}: z {} w {}",
            sol.z[i],
            w[i]
        );
    }
    // on its active set the answer solves the original problem, not the regularised one:
    // w_A = 0 to rounding relative to q (an impact left no contact approaching by δ z)
    let qs = q.amax();
    for i in (0..6).filter(|&i| sol.z[i] > 0.0) {
        assert!(
            w[i].abs() <= 1e-12 * qs,
            "{i}: w {:e} (q scale {qs:e})",
            w[i]
        );
    }
    // a regular problem is solved by the first attempt, unregularised
    let m2 = DMatrix::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 2.0]);
    let q2 = DVector::from_vec(vec![-1.0, -1.0]);
    let (s2, d2) = lemke_regularized(&m2, &q2, &opts).unwrap();
    assert_eq!(d2, 0.0);
    assert!((s2.z[0] - 1.0 / 3.0).abs() < 1e-15 && (s2.z[1] - 1.0 / 3.0).abs() < 1e-15);
}

// ------------------------------------- an answer is a solution or an error

/// An independent check that z solves LCP(q, M) on a scale that does not grow with z: w = Mz + q
/// ≥ −tol·max|q| and, where z > 0, |w| ≤ tol·max|q| — each beyond the rounding of w,
/// 64 n u (|M||z|)ᵢ.
fn solves(m: &DMatrix<f64>, q: &DVector<f64>, z: &DVector<f64>, tol: f64) -> Result<(), String> {
    let n = q.len();
    let qmax = q.amax();
    for i in 0..n {
        if z[i] < 0.0 {
            return Err(format!("z[{i}] = {:e} < 0", z[i]));
        }
        let (mut w, mut abs) = (q[i], q[i].abs());
        for j in 0..n {
            w += m[(i, j)] * z[j];
            abs += (m[(i, j)] * z[j]).abs();
        }
        let slack = tol * qmax + 64.0 * n as f64 * f64::EPSILON * abs;
        if w < -slack {
            return Err(format!("w[{i}] = {w:e} < 0 (z = {z})"));
        }
        if z[i] > 0.0 && w > slack && m.amax() * z[i] > slack {
            return Err(format!("w[{i}] = {w:e} beside z[{i}] = {:e}", z[i]));
        }
    }
    Ok(())
}

#[test]
fn the_regularised_retry_returns_no_non_solution() {
    let opts = LemkeOptions {
        check_tolerance: 1e-7,
        ..LemkeOptions::default()
    };
    let q2 = DVector::from_vec(vec![-1.0, -1.0]);
    // w₂ ≡ −1: no solution; plain Lemke ends on a ray, the retry at δ = 1e-10 found z = (0, 1e10)
    let m = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]);
    assert!(matches!(lemke(&m, &q2, &opts), Err(LcpError::Ray { .. })));
    let r = lemke_regularized(&m, &q2, &opts);
    assert!(r.is_err(), "{r:?}");
    // copositive-plus, so its ray proves that no solution exists
    let m = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -1.0, 0.0]);
    let r = lemke_regularized(&m, &q2, &opts);
    assert!(r.is_err(), "{r:?}");
    // the residual of the old candidates, on the new scale
    let z = DVector::from_vec(vec![0.0, 1e10]);
    let m = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, 0.0, 0.0]);
    let w = &m * &z + &q2;
    assert!(
        lcp_residual(&m, &q2, &z, &w) >= 0.99,
        "{}",
        lcp_residual(&m, &q2, &z, &w)
    );
}

/// A 4×4 bimatrix game of coordination in costs, A = B = [[1, 2], [2, 1]]: three equilibria
/// (two pure, one mixed). Whatever Lemke's method with d = e does, an answer solves it.
#[test]
fn a_bimatrix_game_gets_a_solution_or_an_error() {
    let opts = LemkeOptions {
        check_tolerance: 1e-7,
        ..LemkeOptions::default()
    };
    let a = [[1.0, 2.0], [2.0, 1.0]];
    for (b, shift) in [(a, 0.0), ([[3.0, 1.0], [1.0, 3.0]], 0.5)] {
        let mut m = DMatrix::zeros(4, 4);
        for i in 0..2 {
            for j in 0..2 {
                m[(i, 2 + j)] = a[i][j] + shift;
                m[(2 + j, i)] = b[i][j];
            }
        }
        let q = DVector::from_element(4, -1.0);
        match lemke_regularized(&m, &q, &opts) {
            Ok((sol, _)) => solves(&m, &q, &sol.z, 1e-7).unwrap(),
            Err(e) => assert!(matches!(
                e,
                LcpError::Ray { .. } | LcpError::CheckFailed { .. }
            )),
        }
    }
}

#[test]
fn murtys_example_through_the_regularised_entry() {
    let n = 8;
    let (m, q) = (murty_upper(n), murty_q_upper(n));
    let (sol, delta) = lemke_regularized(&m, &q, &opts()).unwrap();
    assert_eq!(delta, 0.0);
    assert_eq!(sol.pivots, 1 << n);
    solves(&m, &q, &sol.z, 1e-12).unwrap();
}

/// Copositive-plus M = A Aᵀ + (B − Bᵀ) (PSD plus skew) with q from a known complementary pair.
fn copositive_plus_solvable() -> impl Strategy<Value = (DMatrix<f64>, DVector<f64>)> {
    (1usize..=10).prop_flat_map(|n| {
        (
            1..=n,
            prop::collection::vec(-1.0f64..1.0, n * n),
            prop::collection::vec(-1.0f64..1.0, n * n),
            prop::collection::vec(0.0f64..1.0, n),
            prop::collection::vec(any::<bool>(), n),
        )
            .prop_map(move |(k, a, b, v, support)| {
                let a = DMatrix::from_row_slice(n, n, &a).columns(0, k).into_owned();
                let b = DMatrix::from_row_slice(n, n, &b);
                let m = &a * a.transpose() + &b - b.transpose();
                let z = DVector::from_fn(n, |i, _| if support[i] { v[i] } else { 0.0 });
                let w = DVector::from_fn(n, |i, _| if support[i] { 0.0 } else { v[i] });
                (m.clone(), w - m * z)
            })
    })
}

/// Infeasible LCPs: a rank-one PSD block v vᵀ with q < 0 at a row where v > 0 and one where
/// v < 0 (w = v (vᵀz) + q cannot be ≥ 0 at both), or a row of M ≤ 0 with q < 0; the other
/// entries random. No z ≥ 0 makes w ≥ 0.
fn infeasible() -> impl Strategy<Value = (DMatrix<f64>, DVector<f64>)> {
    (2usize..=8).prop_flat_map(|n| {
        (
            prop::collection::vec(0.1f64..1.0, n),
            prop::collection::vec(-1.0f64..1.0, n * n),
            prop::collection::vec(-1.0f64..1.0, n),
            any::<bool>(),
            prop::sample::select(vec![1e-6, 1.0, 1e6]),
        )
            .prop_map(move |(mag, noise, qr, rank_one, s)| {
                let mut m = DMatrix::from_row_slice(n, n, &noise);
                let mut q = DVector::from_vec(qr) * s;
                if rank_one {
                    // v: + at 0, − at 1, any sign elsewhere; M = v vᵀ everywhere
                    let v = DVector::from_fn(n, |i, _| match i {
                        0 => mag[0],
                        1 => -mag[1],
                        _ => mag[i] * noise[i].signum(),
                    });
                    m = &v * v.transpose();
                    q[0] = -mag[0] * s;
                    q[1] = -mag[1] * s;
                } else {
                    for j in 0..n {
                        m[(0, j)] = -m[(0, j)].abs();
                    }
                    q[0] = -mag[0] * s;
                }
                (m, q)
            })
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn copositive_plus_problems_with_a_solution_are_solved((m, q) in copositive_plus_solvable()) {
        let opts = LemkeOptions { check_tolerance: 1e-7, ..LemkeOptions::default() };
        let (sol, _) = lemke_regularized(&m, &q, &opts).expect("copositive-plus and feasible");
        prop_assert!(solves(&m, &q, &sol.z, 1e-7).is_ok(), "{:?}", solves(&m, &q, &sol.z, 1e-7));
        prop_assert!(lcp_residual(&m, &q, &sol.z, &sol.w) <= 1e-7);
    }

    #[test]
    fn p_matrix_problems_are_solved_by_the_regularised_entry((m, q) in sdd_problem()) {
        let (sol, delta) = lemke_regularized(&m, &q, &opts()).expect("P-matrix");
        prop_assert_eq!(delta, 0.0);
        prop_assert!(solves(&m, &q, &sol.z, 1e-9).is_ok());
    }

    #[test]
    fn infeasible_problems_are_never_solved((m, q) in infeasible()) {
        let opts = LemkeOptions { check_tolerance: 1e-7, ..LemkeOptions::default() };
        let r = lemke_regularized(&m, &q, &opts);
        prop_assert!(r.is_err(), "solved an infeasible LCP: {:?}", r.map(|s| s.0.z));
        prop_assert!(lemke(&m, &q, &opts).is_err());
    }
}
