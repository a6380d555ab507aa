//! Light bodies stepped around their free linear flow (`solver.free_flow`): a DP5 step taken
//! around an exact reference, a driven block against its closed form, the energy ledger of
//! a record-driven abutment, and the bridge against a converged run.
mod common;
use common::*;
use deckspin::dopri::{self, Reference};
use nalgebra::DVector;
use std::sync::Arc;

/// y = (x, ẋ) of ẍ = −ω²x from (1, 0): x = cos ωt.
#[derive(Debug)]
struct Cosine {
    omega: f64,
    comps: Vec<usize>,
}

impl Reference for Cosine {
    fn components(&self) -> &[usize] {
        &self.comps
    }
    fn eval(&self, t: f64, _upto: usize, val: &mut [f64], rate: Option<&mut [f64]>) {
        let (w, (s, c)) = (self.omega, (self.omega * t).sin_cos());
        val[0] = c;
        val[1] = -w * s;
        if let Some(r) = rate {
            r[0] = -w * s;
            r[1] = -w * w * c;
        }
    }
}

#[test]
fn a_step_around_the_exact_flow_is_exact_over_many_periods() {
    let omega = 40.0;
    let mut rhs = |_t: f64, y: &DVector<f64>, f: &mut DVector<f64>| -> Result<(), ()> {
        f[0] = y[1];
        f[1] = -omega * omega * y[0];
        Ok(())
    };
    let y0 = DVector::from_vec(vec![1.0, 0.0]);
    let f0 = DVector::from_vec(vec![0.0, -omega * omega]);
    let h = 10.0 * 2.0 * std::f64::consts::PI / omega + 0.1; // ten periods and more
    let flow: Arc<dyn Reference> = Arc::new(Cosine {
        omega,
        comps: vec![0, 1],
    });
    let mut ws = dopri::Workspace::default();
    dopri::step_into(
        &mut ws,
        &mut rhs,
        0.0,
        &y0,
        &f0,
        h,
        1e-6,
        1e-9,
        2,
        Some(flow),
    )
    .unwrap();
    let s = &ws.step;
    assert!(s.error < 1e-6, "error estimate {:e}", s.error);
    assert!((s.y1[0] - (omega * h).cos()).abs() < 1e-12, "{}", s.y1[0]);
    assert!((s.y1[1] + omega * (omega * h).sin()).abs() < 1e-10);
    // the dense output is the flow's, FSAL the true f(t1, y1)
    for k in 0..=20 {
        let t = h * k as f64 / 20.0;
        let mut y = DVector::zeros(2);
        s.dense_at_into(t, &mut y);
        assert!((y[0] - (omega * t).cos()).abs() < 1e-12, "t {t}: {}", y[0]);
        assert!((s.dense_component(k as f64 / 20.0, 0) - y[0]).abs() < 1e-12);
    }
    assert!((s.f1[1] + omega * omega * s.y1[0]).abs() < 1e-9);
    // without the reference the same step is rejected
    dopri::step_into(&mut ws, &mut rhs, 0.0, &y0, &f0, h, 1e-6, 1e-9, 2, None).unwrap();
    assert!(ws.step.error > 1e3, "error estimate {:e}", ws.step.error);
}

/// A 0.65 t block on two actuators (x, θ) driven by u_g = A sin Ωt, turning at `spin`.
fn block(extra: &str, spin: f64) -> String {
    format!(
        r#"
title = "block on actuators"
{extra}
[[support]]
name = "ground"
kind = "harmonic"
amplitude = 0.05
frequency = 1.5

[[body]]
name = "block"
mass = 0.65
inertia = 0.31
dofs = ["x", "theta"]
initial_velocity = [0.2, 0.0, {spin}]

[[spring]]
name = "a1"
body = "block"
point = [0.0, 0.9]
direction = [1.0, 0.0]
stiffness = 1.0e4
damping = 5.7
support = "ground"

[[spring]]
name = "a2"
body = "block"
point = [0.0, -0.9]
direction = [1.0, 0.0]
stiffness = 1.0e4
damping = 5.7
support = "ground"
"#
    )
}

/// x(t) of m ẍ + C ẋ + K x = K u + C u̇, u = A sin Ωt, from x = 0, ẋ = v0.
fn driven_block(t: f64) -> f64 {
    let (m, k, c, a, v0) = (0.65, 2.0e4, 11.4, 0.05, 0.2);
    let om = 2.0 * std::f64::consts::PI * 1.5;
    // x_p = p sin Ωt + q cos Ωt
    let (d, e) = (k - m * om * om, c * om);
    let det = d * d + e * e;
    let (p, q) = ((d * k * a + e * e * a) / det, (d * e * a - e * k * a) / det);
    let w0 = (k / m).sqrt();
    let zeta = c / (2.0 * m * w0);
    let wd = w0 * (1.0 - zeta * zeta).sqrt();
    let (b1, xd0) = (-q, v0 - p * om);
    let b2 = (xd0 + zeta * w0 * b1) / wd;
    p * (om * t).sin()
        + q * (om * t).cos()
        + (-zeta * w0 * t).exp() * (b1 * (wd * t).cos() + b2 * (wd * t).sin())
}

#[test]
fn a_driven_block_on_its_free_flow_follows_the_closed_form_in_fewer_steps() {
    let solver = |ff: bool, rtol: f64| {
        format!(
            "[solver]\nt_end = 2.0\noutput_dt = 0.01\nrtol = {rtol:e}\natol = 1e-14\nfree_flow = {ff}"
        )
    };
    let ff = run_text(&block(&solver(true, 1e-9), 0.0), "block.toml").unwrap();
    let plain = run_text(&block(&solver(false, 1e-9), 0.0), "block.toml").unwrap();
    let mut worst: f64 = 0.0;
    for s in &ff.samples {
        worst = worst.max((s.q[0] - driven_block(s.t)).abs());
        assert_eq!(s.q[1], 0.0);
    }
    assert!(worst < 1e-10, "largest |x − closed form| {worst:e}");
    let (a, b) = (ff.stats.steps_accepted, plain.stats.steps_accepted);
    assert!(a * 5 < b, "steps: {a} on the free flow, {b} without");
    assert!(
        ff.summary.energy_closure_rel < 1e-8,
        "{:e}",
        ff.summary.energy_closure_rel
    );
}

#[test]
fn a_turning_block_whose_actuators_are_not_linear_enough_keeps_its_own_steps() {
    // θ ≈ 1.5e-4: sin θ departs from θ by 6e-13, |p| θ²/2 = 1e-8 m, far above rtol 1e-9 of
    // |x| ≈ 0.05 m / 100: the block is integrated as it is, step for step
    let solver = |ff: bool| {
        format!(
            "[solver]\nt_end = 0.1\noutput_dt = 0.01\nrtol = 1e-9\natol = 1e-14\nfree_flow = {ff}"
        )
    };
    let ff = run_text(&block(&solver(true), 0.05), "block.toml").unwrap();
    let plain = run_text(&block(&solver(false), 0.05), "block.toml").unwrap();
    let (a, b) = (ff.stats.steps_accepted, plain.stats.steps_accepted);
    assert_eq!(a, b);
    for (s, p) in ff.samples.iter().zip(&plain.samples) {
        assert_eq!((s.q[0], s.q[1]), (p.q[0], p.q[1]), "t {}", s.t);
    }
}

#[test]
fn an_abutment_driven_by_a_record_closes_its_ledger_on_the_free_flow() {
    let text = |ff: bool| {
        format!(
            r#"
title = "abutment alone"
[solver]
t_end = 16.0
output_dt = 0.005
free_flow = {ff}
[[support]]
name = "ground"
kind = "record"
file = "../excitations/NORTHR_MUL009.AT2"
[[body]]
name = "ab"
mass = 0.65
inertia = 0.31
dofs = ["x", "theta"]
initial_velocity = [0.0, 0.0, 0.3]
[[spring]]
name = "a1"
body = "ab"
point = [0.0, 0.9]
direction = [1.0, 0.0]
stiffness = 1e4
damping = 5.7
support = "ground"
[[spring]]
name = "a2"
body = "ab"
point = [0.0, -0.9]
direction = [1.0, 0.0]
stiffness = 1e4
damping = 5.7
support = "ground"
"#
        )
    };
    let name = model("models/abutment.toml");
    let name = name.to_str().unwrap();
    let ff = run_text(&text(true), name).unwrap();
    let plain = run_text(&text(false), name).unwrap();
    let (a, b) = (ff.stats.steps_accepted, plain.stats.steps_accepted);
    assert!(a * 5 < b, "steps: {a} on the free flow, {b} without");
    let (ca, cb) = (
        ff.summary.energy_closure_rel,
        plain.summary.energy_closure_rel,
    );
    assert!(
        ca < 2e-4 && ca < cb,
        "closure {ca:e} on the free flow, {cb:e} without"
    );
    for (s, p) in ff.samples.iter().zip(&plain.samples) {
        assert!(
            (s.q[0] - p.q[0]).abs() < 2e-6,
            "t {}: x {} {}",
            s.t,
            s.q[0],
            p.q[0]
        );
    }
}

#[test]
fn the_bridge_on_free_flows_agrees_with_a_converged_run() {
    let base = ["solver.t_end=8.0"];
    let conv = run(
        "models/four-span.toml",
        &[
            base[0],
            "solver.rtol=1e-10",
            "solver.atol=1e-12",
            "solver.branch_window=0",
        ],
    );
    let ff = run(
        "models/four-span.toml",
        &[base[0], "solver.free_flow=true", "solver.rtol=1e-5"],
    );
    let plain = run("models/four-span.toml", &base);
    for (p, c) in ff.summary.peaks.iter().zip(&conv.summary.peaks) {
        let e = rel(p.max_abs, c.max_abs);
        // the plain run at its default rtol 1e-4 is within 4.5e-5 here
        assert!(
            e < 5e-5,
            "{}: {} against {} ({e:.2e})",
            p.name,
            p.max_abs,
            c.max_abs
        );
    }
    assert!(ff.summary.energy_closure_rel < 1e-5);
    assert!(ff.summary.max_penetration < 1e-12);
    let (a, b) = (ff.stats.steps_accepted, plain.stats.steps_accepted);
    assert!(a * 4 < b * 3, "steps: {a} on the free flow, {b} without");
}
