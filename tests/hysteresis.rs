//! Hysteretic laws: hand-computed scripted paths, invariants, validation.

use deckspin::hysteresis::{Branch, HysteresisError, Hysteretic, Law};
use proptest::prelude::*;

const TOL: f64 = 1e-9;

fn takeda(alpha: f64) -> Law {
    Law::Takeda {
        stiffness: 1000.0,
        yield_force: 10.0,
        post_yield_ratio: 0.05,
        crack_force: None,
        yield_displacement: None,
        unloading_exponent: alpha,
    }
}

fn trilinear() -> Law {
    // Crack (0.004, 4), yield (0.02, 10): cracked slope (10 − 4)/(0.02 − 0.004) = 375;
    // post-yield slope 0.05·1000 = 50; k_y = 10/0.02 = 500.
    Law::Takeda {
        stiffness: 1000.0,
        yield_force: 10.0,
        post_yield_ratio: 0.05,
        crack_force: Some(4.0),
        yield_displacement: Some(0.02),
        unloading_exponent: 0.4,
    }
}

fn bilinear() -> Law {
    Law::Bilinear {
        stiffness: 1000.0,
        yield_force: 10.0,
        post_yield_ratio: 0.05,
    }
}

fn drive(law: Law, path: &[f64]) -> Vec<(f64, f64)> {
    Hysteretic::new(law).unwrap().drive(path)
}

#[track_caller]
fn assert_points(got: &[(f64, f64)], want: &[(f64, f64)]) {
    assert_eq!(
        got.len(),
        want.len(),
        "point count\n got: {got:?}\nwant: {want:?}"
    );
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            (g.0 - w.0).abs() <= TOL && (g.1 - w.1).abs() <= TOL,
            "point {i}: got {g:?}, want {w:?}\n got: {got:?}"
        );
    }
}

#[test]
fn takeda_bilinear_scripted_path() {
    // k = 1000, f_y = 10, r = 0.05 (post-yield slope 50), α = 0.4, d_y = 0.01, k_y = 1000.
    let got = drive(takeda(0.4), &[0.0, 0.02, -0.005, 0.03, -0.03, 0.0]);
    // Reversal at 0.02: d_max = 0.02, k_u1 = 1000·(0.01/0.02)^0.4 = 757.858283…;
    // chord to the − yield point (−0.01, −10): 20.5/0.03 = 683.33 < k_u1, so k_u1 stands.
    let ku1 = 1000.0 * 0.5f64.powf(0.4);
    assert!(20.5 / 0.03 < ku1);
    // Zero force at z1 = 0.02 − 10.5/k_u1 = 0.00614517.
    let z1 = 0.02 - 10.5 / ku1;
    // Reload − toward (−0.01, −10): slope 10/(z1 + 0.01) = 619.380;
    // at −0.005: f1 = −619.380·(z1 + 0.005) = −6.903098.
    let f1 = -10.0 / (z1 + 0.01) * (z1 + 0.005);
    // Reversal on the reloading line at (−0.005, f1): local peak; chord to (0.02, 10.5):
    // (10.5 + 6.9031)/0.025 = 696.12 < k_u1; zero force at z2 = −0.005 + 6.9031/k_u1 = 0.00410869.
    assert!((10.5 - f1) / 0.025 < ku1);
    let z2 = -0.005 - f1 / ku1;
    // Reload + toward the peak (0.02, 10.5), then backbone: 10 + 50·0.02 = 11 at 0.03.
    // Reversal at 0.03: d_max = 0.03, k_u2 = 1000·(1/3)^0.4 = 644.394015;
    // chord to the local peak (−0.005, f1): (11 + 6.9031)/0.035 = 511.52 < k_u2.
    let ku2 = 1000.0 * (1.0f64 / 3.0).powf(0.4);
    assert!((11.0 - f1) / 0.035 < ku2);
    // Zero force at z3 = 0.03 − 11/k_u2 = 0.0129297; reload − to the local peak (−0.005, f1),
    // then on toward the − yield point (−0.01, −10), then backbone: −10 − 50·0.02 = −11 at −0.03.
    let z3 = 0.03 - 11.0 / ku2;
    // Reversal at −0.03: k_u2 again (d_max = 0.03); chord to (0.03, 11): 22/0.06 = 366.67 < k_u2.
    assert!(22.0 / 0.06 < ku2);
    // Zero force at z4 = −0.03 + 11/k_u2 = −0.0129297; reload + toward (0.03, 11):
    // at 0: 11·(0 − z4)/(0.03 − z4) = 3.313014.
    let z4 = -0.03 + 11.0 / ku2;
    let f_end = 11.0 * (0.0 - z4) / (0.03 - z4);
    assert!((f_end - 3.313014).abs() < 1e-6);
    assert_points(
        &got,
        &[
            (0.0, 0.0),
            (0.01, 10.0),
            (0.02, 10.5),
            (z1, 0.0),
            (-0.005, f1),
            (z2, 0.0),
            (0.02, 10.5),
            (0.03, 11.0),
            (z3, 0.0),
            (-0.005, f1),
            (-0.01, -10.0),
            (-0.03, -11.0),
            (z4, 0.0),
            (0.0, f_end),
        ],
    );
}

#[test]
fn bilinear_kinematic_scripted_path() {
    // k = 1000, f_y = 10, r = 0.05: yield lines f = ±9.5 + 50·u, elastic band width 0.02.
    let got = drive(bilinear(), &[0.0, 0.02, -0.005, 0.03, -0.03, 0.0]);
    assert_points(
        &got,
        &[
            (0.0, 0.0),
            (0.01, 10.0),    // yield: 1000·0.01
            (0.02, 10.5),    // 10 + 50·0.01
            (0.0, -9.5),     // 10.5 + 1000·(u − 0.02) = −9.5 + 50u → u = 0
            (-0.005, -9.75), // −9.5 + 50·(−0.005)
            (0.015, 10.25),  // −9.75 + 1000·(u + 0.005) = 9.5 + 50u → 950u = 14.25
            (0.03, 11.0),    // 10.25 + 50·0.015
            (0.01, -9.0),    // 11 − 1000·0.02 = −9 = −9.5 + 50·0.01
            (-0.03, -11.0),  // −9 − 50·0.04
            (-0.01, 9.0),    // −11 + 1000·0.02 = 9 = 9.5 + 50·(−0.01)
            (0.0, 9.5),      // 9 + 50·0.01
        ],
    );
}

#[test]
fn takeda_trilinear_scripted_path() {
    let got = drive(
        trilinear(),
        &[0.0, 0.01, -0.006, 0.005, 0.03, -0.01, 0.0, -0.015],
    );
    // Cracked slope 375 to 0.01: 4 + 375·0.006 = 6.25.
    // Reversal before yield (T2): line to the − crack point (−0.004, −4), then − backbone:
    // −4 − 375·0.002 = −4.75 at −0.006.
    // Reversal: peak-to-peak line (−0.006, −4.75)–(0.01, 6.25), slope 11/0.016 = 687.5:
    // at 0.005: −4.75 + 687.5·0.011 = 2.8125; on to the peak, backbone to yield (0.02, 10),
    // then 10 + 50·0.01 = 10.5 at 0.03.
    // Reversal at 0.03 (yielded): k_u = 500·(0.02/0.03)^0.4 = 425.141500; chord to the − yield
    // point (−0.02, −10): 20.5/0.05 = 410 < k_u. Zero force at z1 = 0.03 − 10.5/k_u = 0.00530234.
    let ku = 500.0 * (0.02f64 / 0.03).powf(0.4);
    assert!(20.5 / 0.05 < ku);
    let z1 = 0.03 - 10.5 / ku;
    // Reload − toward (−0.02, −10) (the − side has not yielded): slope kr = 10/(z1 + 0.02)
    // = 395.220; at −0.01: f1 = −kr·(z1 + 0.01) = −6.047796.
    let kr = 10.0 / (z1 + 0.02);
    let f1 = -kr * (z1 + 0.01);
    // Reversal at −0.01 (local peak): chord to (0.03, 10.5): (10.5 + 6.0478)/0.04 = 413.69 < k_u;
    // unloading line slope k_u: at 0, f1 + 0.01·k_u = −1.796381 (zero force not reached).
    assert!((10.5 - f1) / 0.04 < ku);
    let f2 = f1 + 0.01 * ku;
    // Back down: retrace to (−0.01, f1) (T6), then the same reloading line toward (−0.02, −10):
    // at −0.015, f1 − kr·0.005 = −8.023898.
    let f3 = f1 - kr * 0.005;
    assert!((f3 + 8.023898).abs() < 1e-6);
    assert_points(
        &got,
        &[
            (0.0, 0.0),
            (0.004, 4.0),
            (0.01, 6.25),
            (-0.004, -4.0),
            (-0.006, -4.75),
            (0.005, 2.8125),
            (0.01, 6.25),
            (0.02, 10.0),
            (0.03, 10.5),
            (z1, 0.0),
            (-0.01, f1),
            (0.0, f2),
            (-0.01, f1),
            (-0.015, f3),
        ],
    );
}

#[test]
fn takeda_unloading_stiffness_raised_to_chord() {
    // α = 1: at d_max = 0.03 the formula gives 1000·(0.01/0.03) = 333.33, softer than the chord
    // from (0.03, 11) to the − yield point (−0.01, −10): 21/0.04 = 525. So k_u = 525, zero force at
    // 0.03 − 11/525 = 0.0090476, and the reloading line 10/(0.0090476 + 0.01) = 525 continues it.
    let got = drive(takeda(1.0), &[0.0, 0.03, -0.015]);
    let z: f64 = 0.03 - 11.0 / 525.0;
    assert!((10.0 / (z + 0.01) - 525.0).abs() < 1e-9);
    assert_points(
        &got,
        &[
            (0.0, 0.0),
            (0.01, 10.0),
            (0.03, 11.0),
            (z, 0.0),
            (-0.01, -10.0),
            (-0.015, -10.25), // −10 − 50·0.005
        ],
    );
}

#[test]
fn takeda_retraces_unloading_line() {
    let ku2 = 1000.0 * (1.0f64 / 3.0).powf(0.4);
    // Unload from (0.03, 11) to 0.02 and back: same line both ways, then the backbone again.
    let got = drive(takeda(0.4), &[0.0, 0.03, 0.02, 0.03, 0.04]);
    assert_points(
        &got,
        &[
            (0.0, 0.0),
            (0.01, 10.0),
            (0.03, 11.0),
            (0.02, 11.0 - 0.01 * ku2),
            (0.03, 11.0),
            (0.04, 11.5),
        ],
    );
    // From a reloading line: a small excursion back along the unloading line leaves no trace.
    let direct = drive(takeda(0.4), &[0.0, 0.03, -0.02, 0.0, 0.01]);
    let detour = drive(takeda(0.4), &[0.0, 0.03, -0.02, 0.0, -0.001, 0.0, 0.01]);
    let at = |pts: &[(f64, f64)], u: f64| {
        pts.iter()
            .rev()
            .find(|p| (p.0 - u).abs() < 1e-15)
            .unwrap()
            .1
    };
    assert!((at(&direct, 0.0) - at(&detour, 0.0)).abs() < TOL);
    assert!((at(&direct, 0.01) - at(&detour, 0.01)).abs() < TOL);
    // The excursion went down the unloading line and back to the same force.
    let i = detour.iter().position(|p| p.0 == -0.001).unwrap();
    assert!((detour[i + 1].1 - detour[i - 1].1).abs() < TOL);
    assert!(detour[i].1 < detour[i - 1].1);
}

#[test]
fn bilinear_retraces_elastic_line() {
    let got = drive(bilinear(), &[0.0, 0.02, 0.01, 0.02, 0.03]);
    assert_points(
        &got,
        &[
            (0.0, 0.0),
            (0.01, 10.0),
            (0.02, 10.5),
            (0.01, 0.5),
            (0.02, 10.5),
            (0.03, 11.0),
        ],
    );
}

#[test]
fn takeda_reversal_exactly_at_reload_target() {
    // Reloading from −0.03 reaches the peak (0.03, 11) exactly and reverses there: the unloading
    // is the backbone unloading of the first cycle, zero force at z3 = 0.03 − 11/k_u2, then the
    // reload toward (−0.03, −11): at 0, −11·z3/(z3 + 0.03) = −3.313014.
    let ku2 = 1000.0 * (1.0f64 / 3.0).powf(0.4);
    let z3 = 0.03 - 11.0 / ku2;
    // (With k_u2 = 1000·(1/3)^0.4 = 644.394015, z3 = 0.0129297, z4 = −z3.)
    let got = drive(takeda(0.4), &[0.0, 0.03, -0.03, 0.03, 0.0]);
    assert_points(
        &got,
        &[
            (0.0, 0.0),
            (0.01, 10.0),
            (0.03, 11.0),
            (z3, 0.0),
            (-0.01, -10.0),
            (-0.03, -11.0),
            (-z3, 0.0),
            (0.03, 11.0),
            (z3, 0.0),
            (0.0, -11.0 * z3 / (z3 + 0.03)),
        ],
    );
}

#[test]
fn set_direction_changes_branch_only_when_needed() {
    let mut h = Hysteretic::new(takeda(0.4)).unwrap();
    let virgin = *h.branch();
    h.set_direction(0.0, -1.0);
    assert_eq!(h.branch().stiffness, virgin.stiffness);
    assert_eq!((h.branch().lower, h.branch().upper), (-0.01, 0.01));
    h.drive(&[0.02]);
    assert!(h.branch().ends_on_reversal);
    assert_eq!(h.branch().stiffness, 50.0);
    h.set_direction(0.02, 1.0);
    assert_eq!(h.branch().stiffness, 50.0);
    h.set_direction(0.02, -1.0);
    let ku1 = 1000.0 * 0.5f64.powf(0.4);
    assert!((h.branch().stiffness - ku1).abs() < TOL);
    assert!(!h.branch().ends_on_reversal);
    assert!((h.force(0.02) - 10.5).abs() < TOL);
}

#[test]
fn linear_never_ends() {
    let mut h = Hysteretic::new(Law::Linear { stiffness: 3.0 }).unwrap();
    let b = *h.branch();
    assert_eq!(
        (b.lower, b.upper, b.ends_on_reversal),
        (f64::NEG_INFINITY, f64::INFINITY, false)
    );
    assert_points(
        &h.drive(&[0.0, 2.0, -1.0]),
        &[(0.0, 0.0), (2.0, 6.0), (-1.0, -3.0)],
    );
}

#[test]
fn backbone_values() {
    assert!((takeda(0.4).backbone(-0.03) + 11.0).abs() < TOL);
    assert!((trilinear().backbone(0.01) - 6.25).abs() < TOL);
    assert!((trilinear().backbone(0.002) - 2.0).abs() < TOL);
    assert!((bilinear().backbone(0.005) - 5.0).abs() < TOL);
    assert_eq!(trilinear().initial_stiffness(), 1000.0);
}

fn field_of(law: Law) -> &'static str {
    match law.validate() {
        Err(HysteresisError::Invalid { field, .. }) => {
            assert!(Hysteretic::new(law).is_err());
            field
        }
        Ok(()) => panic!("accepted {law:?}"),
    }
}

#[test]
fn invalid_parameters_name_the_field() {
    assert_eq!(field_of(Law::Linear { stiffness: 0.0 }), "stiffness");
    assert_eq!(
        field_of(Law::Linear {
            stiffness: f64::NAN
        }),
        "stiffness"
    );
    let bil = |k: f64, fy: f64, r: f64| Law::Bilinear {
        stiffness: k,
        yield_force: fy,
        post_yield_ratio: r,
    };
    assert_eq!(field_of(bil(-1.0, 10.0, 0.1)), "stiffness");
    assert_eq!(field_of(bil(1.0, f64::INFINITY, 0.1)), "yield_force");
    assert_eq!(field_of(bil(1.0, 10.0, 1.0)), "post_yield_ratio");
    assert_eq!(field_of(bil(1.0, 10.0, -0.1)), "post_yield_ratio");
    let tak = |fc: Option<f64>, uy: Option<f64>, r: f64, a: f64| Law::Takeda {
        stiffness: 1000.0,
        yield_force: 10.0,
        post_yield_ratio: r,
        crack_force: fc,
        yield_displacement: uy,
        unloading_exponent: a,
    };
    assert_eq!(field_of(tak(None, None, 0.05, 1.5)), "unloading_exponent");
    assert_eq!(field_of(tak(None, None, 0.05, -0.1)), "unloading_exponent");
    assert_eq!(
        field_of(tak(None, None, 0.05, f64::NAN)),
        "unloading_exponent"
    );
    assert_eq!(field_of(tak(None, None, f64::NAN, 0.4)), "post_yield_ratio");
    assert_eq!(
        field_of(tak(Some(12.0), Some(0.02), 0.05, 0.4)),
        "crack_force"
    );
    assert_eq!(
        field_of(tak(Some(-1.0), Some(0.02), 0.05, 0.4)),
        "crack_force"
    );
    assert_eq!(
        field_of(tak(Some(4.0), None, 0.05, 0.4)),
        "yield_displacement"
    );
    assert_eq!(
        field_of(tak(None, Some(0.02), 0.05, 0.4)),
        "yield_displacement"
    );
    // d_y must exceed f_y/k = 0.01, or the second slope would be stiffer than the first.
    assert_eq!(
        field_of(tak(Some(4.0), Some(0.01), 0.05, 0.4)),
        "yield_displacement"
    );
    // Post-yield slope 0.5·1000 = 500 > cracked slope 375.
    assert_eq!(
        field_of(tak(Some(4.0), Some(0.02), 0.5, 0.4)),
        "post_yield_ratio"
    );
    let msg = tak(None, None, 0.05, 2.0)
        .validate()
        .unwrap_err()
        .to_string();
    assert!(msg.starts_with("unloading_exponent: "), "{msg}");
    assert!(tak(Some(4.0), Some(0.02), 0.05, 0.4).validate().is_ok());
}

#[test]
fn serde_defaults_and_unknown_fields() {
    let law: Law = serde_json::from_str(
        r#"{"law": "takeda", "stiffness": 1000.0, "yield_force": 10.0, "post_yield_ratio": 0.05}"#,
    )
    .unwrap();
    assert_eq!(law, takeda(0.4));
    let back: Law = serde_json::from_str(&serde_json::to_string(&trilinear()).unwrap()).unwrap();
    assert_eq!(back, trilinear());
    assert!(
        serde_json::from_str::<Law>(r#"{"law": "linear", "stiffness": 1.0, "yield_force": 2.0}"#)
            .is_err()
    );
    assert!(serde_json::from_str::<Law>(r#"{"law": "clough", "stiffness": 1.0}"#).is_err());
}

// ---------------------------------------------------------------- properties

/// Steps a path as an event-driven integrator would, using only `set_direction`,
/// `on_branch_end` and `branch`, and checks every branch change.
fn integrate(h: &mut Hysteretic, path: &[f64]) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::new();
    let push = |out: &mut Vec<(f64, f64)>, p: (f64, f64)| {
        if out.last() != Some(&p) {
            out.push(p);
        }
    };
    let mut u = h.displacement();
    for &p in path {
        loop {
            if p == u {
                push(&mut out, (u, h.force(u)));
                break;
            }
            let d = if p > u { 1.0 } else { -1.0 };
            let before = *h.branch();
            h.set_direction(u, d);
            check_change(&before, h.branch(), u, d);
            let b = *h.branch();
            let end = b.end(d);
            if d * (end - p) >= 0.0 {
                u = p;
                push(&mut out, (u, h.force(u)));
                break;
            }
            u = end;
            push(&mut out, (u, b.force(u)));
            h.on_branch_end(u, d);
            check_change(&b, h.branch(), u, d);
        }
    }
    out
}

fn check_change(old: &Branch, new: &Branch, u: f64, d: f64) {
    let (f0, f1) = (old.force(u), new.force(u));
    assert!(
        (f0 - f1).abs() <= TOL * (1.0 + f0.abs()),
        "force jump {f0} → {f1} at u = {u}: {old:?} → {new:?}"
    );
    assert!(new.stiffness.is_finite() && new.stiffness >= 0.0, "{new:?}");
    assert!(new.lower <= u && u <= new.upper, "u = {u} outside {new:?}");
    assert!(
        d * (new.end(d) - u) > 0.0,
        "no room at u = {u} moving {d}: {new:?}"
    );
    if new.ends_on_reversal {
        assert_eq!(new.direction, d, "{new:?}");
    }
}

/// Work ∫ f du along points joined by straight branches.
fn work(pts: &[(f64, f64)]) -> f64 {
    pts.windows(2)
        .map(|w| 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0))
        .sum()
}

fn laws() -> Vec<(Law, f64)> {
    // (law, amplitude limit), the limit keeping Takeda inside |u| ≤ d_y·(1 − r)/r where its
    // loops stay between the extended post-yield lines.
    vec![
        (takeda(0.4), 0.05),
        (takeda(0.0), 0.05),
        (takeda(1.0), 0.05),
        (trilinear(), 0.1),
        (bilinear(), 0.2),
    ]
}

fn path(limit: f64) -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(-1.0f64..1.0, 1..20)
        .prop_map(move |v| v.into_iter().map(|x| x * limit).collect())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 256,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn branch_changes_are_continuous(which in 0usize..5, p in path(1.0)) {
        let (law, limit) = laws()[which].clone();
        let p: Vec<f64> = p.iter().map(|x| x * limit).collect();
        let mut h = Hysteretic::new(law.clone()).unwrap();
        let stepped = integrate(&mut h, &p);
        let driven = Hysteretic::new(law).unwrap().drive(&p);
        prop_assert_eq!(stepped, driven);
    }

    #[test]
    fn force_stays_in_envelope(which in 0usize..5, p in path(1.0)) {
        let (law, limit) = laws()[which].clone();
        let (fy, kp, uy) = match law {
            Law::Takeda { yield_force, post_yield_ratio, stiffness, yield_displacement, .. } =>
                (yield_force, post_yield_ratio * stiffness,
                 yield_displacement.unwrap_or(yield_force / stiffness)),
            Law::Bilinear { yield_force, post_yield_ratio, stiffness } =>
                (yield_force, post_yield_ratio * stiffness, yield_force / stiffness),
            _ => unreachable!(),
        };
        let p: Vec<f64> = p.iter().map(|x| x * limit).collect();
        let pts = drive(law.clone(), &p);
        let mut reach = 0.0f64;
        for &(u, f) in &pts {
            reach = reach.max(u.abs());
            // Never beyond the largest backbone force reached so far.
            prop_assert!(f.abs() <= law.backbone(reach) + TOL, "{u} {f} {pts:?}");
            // Between the extended post-yield lines ±(f_y + k_p·(±u − d_y)).
            prop_assert!(f <= fy + kp * (u - uy) + TOL, "{u} {f} {pts:?}");
            prop_assert!(f >= -fy + kp * (u + uy) - TOL, "{u} {f} {pts:?}");
        }
    }

    #[test]
    fn work_from_virgin_state_is_never_negative(which in 0usize..5, p in path(1.0)) {
        let (law, limit) = laws()[which].clone();
        let p: Vec<f64> = std::iter::once(0.0).chain(p.iter().map(|x| x * limit)).collect();
        let pts = drive(law, &p);
        prop_assert_eq!(pts[0], (0.0, 0.0));
        for n in 2..=pts.len() {
            prop_assert!(work(&pts[..n]) >= -1e-12, "{pts:?}");
        }
    }

    #[test]
    fn repeated_cycles_close_and_dissipate(
        which in 0usize..5, p in path(1.0), a in -1.0f64..1.0,
    ) {
        let (law, limit) = laws()[which].clone();
        let p: Vec<f64> = p.iter().map(|x| x * limit * 0.5).collect();
        let mut h = Hysteretic::new(law).unwrap();
        h.drive(&p);
        let u0 = h.displacement();
        let u1 = u0 + a * limit * 0.5;
        h.drive(&[u1, u0]);
        let start = *h.drive(&[u0]).last().unwrap();
        for _ in 0..2 {
            let mut cycle = vec![start];
            cycle.extend(h.drive(&[u1, u0]));
            let end = *cycle.last().unwrap();
            prop_assert!((end.1 - start.1).abs() < TOL, "not closed: {cycle:?}");
            prop_assert!(work(&cycle) >= -1e-12, "negative loop area: {cycle:?}");
        }
    }

    #[test]
    fn retraced_excursion_leaves_no_trace(
        which in 0usize..5, p in path(1.0), rest in path(1.0), back in 0.0f64..1.0,
    ) {
        let (law, limit) = laws()[which].clone();
        let p: Vec<f64> = p.iter().map(|x| x * limit).collect();
        let rest: Vec<f64> = rest.iter().map(|x| x * limit).collect();
        let mut h = Hysteretic::new(law).unwrap();
        h.drive(&p);
        let u0 = h.displacement();
        // Direction of the last move, and the branch a reversal would start.
        let last = p.iter().rev().find(|&&x| x != u0).copied().unwrap_or(0.0);
        prop_assume!(last != u0);
        let s = (u0 - last).signum();
        let mut probe = h.clone();
        probe.set_direction(u0, -s);
        let b = *probe.branch();
        prop_assume!(!b.ends_on_reversal);
        let excursion = u0 - s * back * (u0 - b.end(-s)).abs();
        let mut with = h.clone();
        with.drive(&[excursion, u0]);
        // Same force at every later path point.
        for &u in &rest {
            let x = *h.drive(&[u]).last().unwrap();
            let y = *with.drive(&[u]).last().unwrap();
            prop_assert!((x.1 - y.1).abs() < TOL, "at {u}: {x:?} vs {y:?}");
        }
    }

    #[test]
    fn linear_law_is_exact(k in 0.1f64..1e6, p in path(10.0)) {
        let pts = drive(Law::Linear { stiffness: k }, &p);
        prop_assert_eq!(pts.len(), {
            let mut q = p.clone();
            q.dedup();
            q.len()
        });
        for (u, f) in pts {
            prop_assert_eq!(f, k * u);
        }
    }

    #[test]
    fn elastic_cycles_dissipate_nothing(which in 0usize..5, p in path(1.0)) {
        let (law, _) = laws()[which].clone();
        // Elastic limit: crack point of the trilinear Takeda, yield point otherwise.
        let (k, ue) = match law {
            Law::Takeda { stiffness, crack_force: Some(fc), .. } => (stiffness, fc / stiffness),
            Law::Takeda { stiffness, yield_force, .. }
            | Law::Bilinear { stiffness, yield_force, .. } => (stiffness, yield_force / stiffness),
            _ => unreachable!(),
        };
        let mut closed: Vec<f64> = p.iter().map(|x| x * ue * 0.999).collect();
        closed.insert(0, 0.0);
        closed.push(0.0);
        let mut h = Hysteretic::new(law).unwrap();
        let virgin = *h.branch();
        let pts = h.drive(&closed);
        for &(u, f) in &pts {
            prop_assert!((f - k * u).abs() < TOL);
        }
        prop_assert!(work(&pts).abs() < 1e-12);
        prop_assert_eq!(h.branch().stiffness, virgin.stiffness);
        prop_assert_eq!((h.branch().lower, h.branch().upper), (virgin.lower, virgin.upper));
    }
}

// ---------------------------------------------------------------- gap laws (backfill, key)

const GAP: f64 = 0.01;
const K: f64 = 1000.0;
const FC: f64 = 10.0;

fn backfill() -> Law {
    Law::Backfill {
        gap: GAP,
        stiffness: K,
        capacity: FC,
    }
}

/// Fails at e = gap + 0.03 = 0.04.
fn key() -> Law {
    Law::Key {
        gap: GAP,
        stiffness: K,
        capacity: FC,
        failure_displacement: 0.03,
    }
}

/// The gap laws by their definition, from the largest deformation reached, `e_max`, and
/// whether the motion has left it (`past`): closing point c = max(gap, e_max − f_c/k),
/// f = max(0, k (e − c)); a key whose `e_max − gap` exceeded its failure displacement (or
/// reached it and moved on) carries nothing.
fn gap_formula(law: &Law, e: f64, e_max: f64, past: bool) -> f64 {
    let (gap, k, fc, fail) = match *law {
        Law::Backfill {
            gap,
            stiffness,
            capacity,
        } => (gap, stiffness, capacity, f64::INFINITY),
        Law::Key {
            gap,
            stiffness,
            capacity,
            failure_displacement,
        } => (gap, stiffness, capacity, failure_displacement),
        _ => unreachable!(),
    };
    if e_max - gap > fail || (e_max - gap == fail && past) {
        return 0.0;
    }
    let c = gap.max(e_max - fc / k);
    (k * (e - c)).max(0.0)
}

/// Drives `law` target by target along `path` and checks every point it reports (targets and
/// branch ends) against [`gap_formula`] to 1e-12, and that the force is never negative.
/// Returns the largest error.
fn check_against_formula(law: &Law, path: &[f64]) -> f64 {
    let mut h = Hysteretic::new(law.clone()).unwrap();
    let mut e_max = 0.0f64;
    let mut worst = 0.0f64;
    for &target in path {
        for (e, f) in h.drive(&[target]) {
            // each move is straight: the largest e so far is at one of the points
            let past = e < e_max;
            e_max = e_max.max(e);
            let want = gap_formula(law, e, e_max, past);
            assert!(f >= 0.0, "tension {f} at e = {e} ({law:?})");
            assert!(
                (f - want).abs() <= 1e-12,
                "at e = {e} (largest {e_max}): force {f}, formula {want} ({law:?})"
            );
            worst = worst.max((f - want).abs());
        }
    }
    worst
}

#[test]
fn backfill_scripted_path() {
    // gap 0.01, k = 1000, f_c = 10: f_c/k = 0.01.
    let got = drive(
        backfill(),
        &[0.0, 0.015, 0.0, 0.03, 0.02, 0.035, -0.01, 0.05],
    );
    assert_points(
        &got,
        &[
            (0.0, 0.0),
            (0.01, 0.0),   // the gap closes
            (0.015, 5.0),  // 1000·0.005
            (0.01, 0.0),   // elastic back to the closing point: no set yet
            (0.0, 0.0),    // open, no tension
            (0.01, 0.0),   // closes again at the gap
            (0.02, 10.0),  // capacity
            (0.03, 10.0),  // plastic: soil pushed back
            (0.02, 0.0),   // reversal at 0.03: c = 0.03 − 0.01 = 0.02 (e_p = 0.01)
            (0.03, 10.0),  // reloading along k up to the reversal point
            (0.035, 10.0), // plastic again
            (0.025, 0.0),  // c = 0.035 − 0.01 (e_p = 0.015)
            (-0.01, 0.0),  // open
            (0.025, 0.0),  // closes at the new closing point
            (0.035, 10.0),
            (0.05, 10.0),
        ],
    );
    let mut h = Hysteretic::new(backfill()).unwrap();
    h.drive(&[0.0, 0.03, 0.0, 0.035, 0.0]);
    let s = h.gap_state().unwrap();
    assert!((s.closing - 0.025).abs() < 1e-15 && (s.permanent_set - 0.015).abs() < 1e-15);
    assert_eq!((s.peak_force, s.failed), (10.0, false));
    assert!(Hysteretic::new(bilinear()).unwrap().gap_state().is_none());
}

#[test]
fn key_scripted_path() {
    // Fails at e = 0.01 + 0.03 = 0.04.
    let got = drive(key(), &[0.0, 0.03, 0.0, 0.045, 0.0, 0.05]);
    assert_points(
        &got,
        &[
            (0.0, 0.0),
            (0.01, 0.0),
            (0.02, 10.0),
            (0.03, 10.0),
            (0.02, 0.0), // c = 0.02
            (0.0, 0.0),
            (0.02, 0.0),
            (0.03, 10.0),
            (0.04, 10.0), // the failure point: the force drops to 0 here
            (0.045, 0.0),
            (0.0, 0.0),
            (0.05, 0.0),
        ],
    );
}

#[test]
fn key_under_monotonic_push_fails_exactly_at_gap_plus_failure_displacement() {
    let law = Law::Key {
        gap: 0.0127,
        stiffness: 3.7e5,
        capacity: 1234.5,
        failure_displacement: 0.0417,
    };
    let u_f = 0.0127 + 0.0417;
    let mut h = Hysteretic::new(law).unwrap();
    let pts = h.drive(&[0.0, 1.0]);
    // open to the gap, elastic to f_c, plastic to the failure point, then nothing
    let yield_at = 0.0127 + 1234.5 / 3.7e5;
    assert_eq!(pts.len(), 5, "{pts:?}");
    assert_eq!(pts[1], (0.0127, 0.0));
    assert!((pts[2].0 - yield_at).abs() < 1e-15 && (pts[2].1 - 1234.5).abs() < 1e-9);
    assert_eq!(pts[3], (u_f, 1234.5));
    assert_eq!(pts[4], (1.0, 0.0));
    let s = h.gap_state().unwrap();
    assert!(s.failed && h.failed());
    assert_eq!(s.peak_force, 1234.5);
    // force 0 for ever after, whatever the motion
    for (u, f) in h.drive(&[0.0, 0.02, -1.0, 2.0]) {
        assert_eq!(f, 0.0, "at {u}");
    }
    // the failure is announced by `fails_at` on the plastic branch only at its end
    let mut h = Hysteretic::new(key()).unwrap();
    h.drive(&[0.0, 0.035]);
    assert!(h.branch().ends_on_reversal && h.branch().upper == 0.04);
    assert!(h.fails_at(0.04, 1.0) && !h.fails_at(0.035, -1.0) && !h.failed());
    // stopping exactly at the failure point and coming back: it failed there
    h.drive(&[0.04]);
    assert!(!h.failed());
    h.drive(&[0.03]);
    assert!(h.failed());
    assert_eq!(h.force(0.03), 0.0);
}

/// Cycles of growing amplitude around 0 (tension side included): through the gap, into the
/// plastic range, unloading, reopening, reloading; a key fails on the way.
fn growing_cycles(amplitude: f64) -> Vec<f64> {
    (0..=480)
        .map(|i| {
            let s = i as f64 / 40.0;
            amplitude * (s / 12.0) * (2.0 * std::f64::consts::PI * s).sin()
        })
        .collect()
}

#[test]
fn gap_laws_follow_their_formula_along_growing_cycles() {
    let path = growing_cycles(0.06);
    for law in [backfill(), key()] {
        let worst = check_against_formula(&law, &path);
        assert!(worst <= 1e-12, "{worst}");
        let mut h = Hysteretic::new(law.clone()).unwrap();
        h.drive(&path);
        let s = h.gap_state().unwrap();
        // the backfill's closing point: the path's largest e (a reversal) less f_c/k
        let e_max = path.iter().fold(0.0f64, |m, &e| m.max(e));
        assert!(e_max > 0.05);
        match law {
            Law::Key { .. } => assert!(s.failed),
            _ => assert!(!s.failed && (s.closing - (e_max - FC / K)).abs() < 1e-15),
        }
    }
    // the same checks through the step-by-step integrator (set_direction, on_branch_end), whose
    // branch changes are continuous in force for backfill
    let mut h = Hysteretic::new(backfill()).unwrap();
    assert_eq!(
        integrate(&mut h, &path),
        Hysteretic::new(backfill()).unwrap().drive(&path)
    );
}

#[test]
fn gap_law_backbones() {
    assert_eq!(backfill().backbone(0.005), 0.0);
    assert!((backfill().backbone(0.015) - 5.0).abs() < 1e-12);
    assert_eq!(backfill().backbone(0.5), 10.0);
    assert_eq!(backfill().backbone(-0.5), 0.0);
    assert_eq!(key().backbone(0.039), 10.0);
    assert_eq!(key().backbone(0.04), 0.0);
    // open at rest: left out of K₀ like a contact
    assert_eq!(key().initial_stiffness(), 0.0);
    assert!(key().is_gap_law() && !bilinear().is_gap_law());
}

#[test]
fn gap_law_parameters_are_checked() {
    let bf = |gap: f64, k: f64, fc: f64| Law::Backfill {
        gap,
        stiffness: k,
        capacity: fc,
    };
    assert_eq!(field_of(bf(-0.01, K, FC)), "gap");
    assert_eq!(field_of(bf(f64::INFINITY, K, FC)), "gap");
    assert_eq!(field_of(bf(GAP, 0.0, FC)), "stiffness");
    assert_eq!(field_of(bf(GAP, K, -1.0)), "capacity");
    assert_eq!(field_of(bf(GAP, K, f64::NAN)), "capacity");
    assert!(bf(0.0, K, FC).validate().is_ok());
    let ky = |fd: f64| Law::Key {
        gap: GAP,
        stiffness: K,
        capacity: FC,
        failure_displacement: fd,
    };
    // must exceed f_c/k = 0.01
    assert_eq!(field_of(ky(0.01)), "failure_displacement");
    assert_eq!(field_of(ky(f64::INFINITY)), "failure_displacement");
    assert_eq!(field_of(ky(f64::NAN)), "failure_displacement");
    assert!(ky(0.0101).validate().is_ok());
    let msg = ky(0.005).validate().unwrap_err().to_string();
    assert!(msg.starts_with("failure_displacement: "), "{msg}");
    let law: Law = serde_json::from_str(
        r#"{"law": "key", "gap": 0.01, "stiffness": 1000.0, "capacity": 10.0, "failure_displacement": 0.03}"#,
    )
    .unwrap();
    assert_eq!(law, key());
    assert!(
        serde_json::from_str::<Law>(r#"{"law": "backfill", "gap": 0.0, "stiffness": 1.0}"#)
            .is_err()
    );
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 256,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn gap_laws_follow_their_formula_on_any_path(which in 0usize..2, p in path(0.06)) {
        let law = [backfill(), key()][which].clone();
        prop_assert!(check_against_formula(&law, &p) <= 1e-12);
    }
}

/// A law's state copied over another's (`clone_from`, which reuses the target's storage)
/// continues exactly as the source and as a fresh clone: every field of the state is copied,
/// whatever law the target held before.
#[test]
fn a_law_copied_over_another_continues_as_its_source() {
    let (history, ahead) = (
        [0.004, -0.03, 0.025, -0.012, 0.018],
        [-0.02, 0.03, -0.001, 0.009],
    );
    let laws = [takeda(0.4), trilinear(), bilinear(), backfill(), key()];
    for source_law in &laws {
        let mut source = Hysteretic::new(source_law.clone()).unwrap();
        source.drive(&history);
        let expected = source.clone().drive(&ahead);
        for target_law in &laws {
            // the target is on another path, and possibly another law
            let mut target = Hysteretic::new(target_law.clone()).unwrap();
            target.drive(&[-0.05, 0.05, 0.0]);
            target.clone_from(&source);
            assert_eq!(
                target.branch(),
                source.branch(),
                "{source_law:?} over {target_law:?}"
            );
            assert_eq!(target.displacement(), source.displacement());
            assert_eq!(
                target.drive(&ahead),
                expected,
                "{source_law:?} over {target_law:?}"
            );
        }
        assert!(
            expected.len() > ahead.len(),
            "the path ahead crosses branches"
        );
    }
}
