//! Convergence under refinement: event times and peaks converge as the tolerance tightens and,
//! at fixed step, with the order of DP5.
mod common;
use common::*;

const OMEGA: f64 = 2.0 * std::f64::consts::PI;

/// Error of the 8th impact time of the oscillator against a stop (exact: 8π/ω).
fn impact_error(set: &[&str]) -> f64 {
    let r = run("models/validation/oscillator-stop.toml", set);
    let imp = impacts(&r);
    (imp[7].t - 8.0 * std::f64::consts::PI / OMEGA).abs()
}

#[test]
fn event_times_converge_as_tolerance_tightens() {
    let tols: [f64; 3] = [1e-4, 1e-6, 1e-8];
    let errs: Vec<f64> = tols
        .iter()
        .map(|t| {
            impact_error(&[
                &format!("solver.rtol={t}"),
                &format!("solver.atol={}", t * 1e-2),
            ])
        })
        .collect();
    for w in errs.windows(2) {
        assert!(w[1] < w[0] * 0.2, "errors {errs:?} do not decrease");
    }
    // observed order with respect to the tolerance (DP5 with PI control: ≈ 0.8–1.1)
    let p = (errs[0] / errs[2]).log10() / (tols[0] / tols[2]).log10();
    assert!(p > 0.6 && p < 1.4, "order in tol {p}, errors {errs:?}");
}

#[test]
fn fixed_step_event_times_converge_with_fifth_order() {
    // rtol/atol so loose that every step is accepted: the step is h_max
    let errs: Vec<f64> = [0.05, 0.025, 0.0125]
        .iter()
        .map(|h| {
            impact_error(&[
                "solver.rtol=1e3",
                "solver.atol=1e3",
                &format!("solver.h_max={h}"),
            ])
        })
        .collect();
    let p1 = (errs[0] / errs[1]).log2();
    let p2 = (errs[1] / errs[2]).log2();
    assert!(
        p1 > 4.0 && p2 > 4.0,
        "observed orders {p1:.2}, {p2:.2}, errors {errs:?}"
    );
}

#[test]
fn peak_value_converges_to_closed_form() {
    // bouncing ball with a coarse output step: the peak between the first two impacts
    // comes from the dense output; the apex height of flight k is (ε^k V)²/(2g)
    let r = run(
        "models/validation/bouncing-ball.toml",
        &["solver.output_dt=0.001"],
    );
    let v: f64 = (2.0 * 9.81f64).sqrt();
    let apex = (0.8 * v).powi(2) / (2.0 * 9.81);
    let t1 = v / 9.81;
    let t2 = t1 + 2.0 * 0.8 * v / 9.81;
    let peak = r
        .samples
        .iter()
        .filter(|s| s.t > t1 && s.t < t2)
        .map(|s| s.q[0])
        .fold(0.0, f64::max);
    // grid sampling error ≤ g·(dt/2)²/2
    assert!(
        (peak - apex).abs() <= 9.81 * 0.0005f64.powi(2) / 2.0 + 1e-12,
        "peak {peak}, apex {apex}"
    );
}
