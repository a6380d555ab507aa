//! Closed-form oracles run through the full engine (model file → events → history).
mod common;
use common::*;
use deckspin::output::{ContactState, EventKind};

const G: f64 = 9.81;

#[test]
fn bouncing_ball_impacts_rebounds_and_accumulation() {
    let r = run("models/validation/bouncing-ball.toml", &[]);
    let (h0, eps) = (1.0, 0.8);
    let v = (2.0 * G * h0).sqrt();
    let t1 = v / G;
    let imp = impacts(&r);
    assert!(imp.len() > 40, "only {} impacts", imp.len());
    let mut t = t1;
    let mut speed = v;
    for (k, e) in imp.iter().take(30).enumerate() {
        assert_rel(e.t, t, 1e-8, &format!("impact {k} time"));
        assert_rel(
            -e.gap_rate_before,
            speed,
            1e-8,
            &format!("impact {k} speed"),
        );
        assert_rel(e.gap_rate_after, eps * speed, 1e-8, &format!("rebound {k}"));
        assert_rel(e.normal, (1.0 + eps) * speed, 1e-8, &format!("impulse {k}"));
        t += 2.0 * eps * speed / G;
        speed *= eps;
    }
    let t_inf = t1 + 2.0 * eps * v / (G * (1.0 - eps));
    assert_eq!(r.accumulation_times.len(), 1);
    assert_rel(r.accumulation_times[0].1, t_inf, 1e-8, "accumulation time");
    // the run goes on past t∞ with the ball at rest on the floor
    let last = r.samples.last().unwrap();
    assert!((last.t - 5.0).abs() < 1e-12);
    assert!(last.q[0].abs() < 1e-12 && last.v[0].abs() < 1e-9);
    assert_eq!(last.contacts[0].state, ContactState::Slide(0.0));
    assert_rel(
        last.contacts[0].normal_force,
        G,
        1e-10,
        "resting contact force m g",
    );
}

#[test]
fn zeno_without_accumulation_rule_is_caught_by_the_guard() {
    let set = ["solver.accumulation_rule=false"];
    let scene = deckspin::load(
        &model("models/validation/bouncing-ball.toml"),
        &set.map(String::from),
    )
    .unwrap();
    match deckspin::run(&scene, &mut deckspin::Silent) {
        Err(deckspin::SolverError::StepCollapse { t, .. }) => {
            let t_inf = (2.0 * G).sqrt() / G * (1.0 + 2.0 * 0.8 / 0.2);
            assert!(
                t < t_inf && t > t_inf - 1e-3,
                "collapse at {t}, t∞ = {t_inf}"
            );
        }
        other => panic!(
            "expected a step collapse, got {:?}",
            other.map(|r| r.summary.stats)
        ),
    }
}

#[test]
fn block_on_rough_plane_stops_at_closed_form_time_and_distance() {
    let r = run("models/validation/block-on-plane.toml", &[]);
    let (v0, mu) = (3.0, 0.3);
    let stick: Vec<_> = r
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Stick)
        .collect();
    assert_eq!(stick.len(), 1);
    assert_rel(stick[0].t, v0 / (mu * G), 1e-10, "stop time");
    let s = post_event(&r, stick[0].t);
    assert_rel(s.q[0], v0 * v0 / (2.0 * mu * G), 1e-10, "stop distance");
    let last = r.samples.last().unwrap();
    assert_rel(last.q[0], v0 * v0 / (2.0 * mu * G), 1e-10, "final position");
    assert_eq!(last.contacts[0].state, ContactState::Stick);
    // sliding friction force μ m g during the slide
    let mid = r.samples.iter().find(|s| s.t > 0.5).unwrap();
    assert_rel(
        mid.contacts[0].tangential_force,
        -mu * 2.0 * G,
        1e-10,
        "friction",
    );
}

fn incline(angle_deg: f64, mu: f64) -> deckspin::RunOutput {
    let a = angle_deg.to_radians();
    let text = format!(
        r#"
gravity = [{gx:.17e}, {gy:.17e}]
[solver]
t_end = 1.0
rtol = 1e-11
atol = 1e-13
[[body]]
name = "block"
mass = 1.0
dofs = ["x", "y"]
[[contact]]
name = "base"
body = "block"
normal = [0.0, 1.0]
gap = 0.0
mu = {mu}
"#,
        gx = G * a.sin(),
        gy = -G * a.cos()
    );
    run_text(&text, "incline.toml").unwrap()
}

#[test]
fn block_on_incline_sticks_iff_tan_theta_le_mu() {
    let mu: f64 = 0.4;
    let crit = mu.atan().to_degrees();
    for angle in [crit - 1.0, crit - 0.01] {
        let r = incline(angle, mu);
        let last = r.samples.last().unwrap();
        assert!(
            last.q[0].abs() < 1e-12,
            "angle {angle}: moved {}",
            last.q[0]
        );
        assert_eq!(last.contacts[0].state, ContactState::Stick);
    }
    for angle in [crit + 0.01, crit + 5.0] {
        let r = incline(angle, mu);
        let a = angle.to_radians();
        let acc = G * (a.sin() - mu * a.cos());
        let last = r.samples.last().unwrap();
        assert_rel(last.q[0], 0.5 * acc * 1.0, 1e-8, "slide distance");
        assert!(matches!(last.contacts[0].state, ContactState::Slide(s) if s > 0.0));
    }
}

#[test]
fn oscillator_against_stop_flights_last_pi_over_omega() {
    let r = run("models/validation/oscillator-stop.toml", &[]);
    let omega = 2.0 * std::f64::consts::PI;
    let imp = impacts(&r);
    assert_eq!(imp.len(), 10);
    let mut speed = 1.0;
    for (k, e) in imp.iter().enumerate() {
        let t = (k as f64 + 1.0) * std::f64::consts::PI / omega;
        assert_rel(e.t, t, 1e-8, &format!("impact {k} time"));
        assert_rel(
            -e.gap_rate_before,
            speed,
            1e-8,
            &format!("impact {k} speed"),
        );
        speed *= 0.5;
    }
    // peak of the first flight: V/ω
    let peak = r.summary.peaks[0].max_abs;
    assert_rel(peak, 1.0 / omega, 1e-6, "first amplitude (grid-sampled)");
}

/// Corner r from the centre of a body (m, I) approaching a wall normal to x at speed v.
struct Corner {
    m: f64,
    i: f64,
    rx: f64,
    ry: f64,
    v: f64,
}

fn corner_run(mu: f64) -> (deckspin::RunOutput, Corner) {
    let c = Corner {
        m: 140.5,
        i: 13090.0,
        rx: -16.1,
        ry: 1.2,
        v: 0.5,
    };
    let set = [format!("contact.0.mu={mu}")];
    let set: Vec<&str> = set.iter().map(|s| s.as_str()).collect();
    (run("models/validation/corner-impact.toml", &set), c)
}

#[test]
fn corner_impact_sticks_with_closed_form_spin() {
    let (r, c) = corner_run(0.5);
    assert!(
        (c.rx * c.ry).abs() <= 0.5 * (c.i / c.m + c.rx * c.rx),
        "oracle: stick case"
    );
    let imp = impacts(&r);
    assert_eq!(imp.len(), 1);
    assert_eq!(imp[0].sticks, Some(true));
    let s = post_event(&r, 0.0);
    let r2 = c.rx * c.rx + c.ry * c.ry;
    let omega = -c.m * c.ry * c.v / (c.i + c.m * r2);
    assert_rel(s.v[2], omega, 1e-10, "θ̇⁺");
    let px = c.m * c.v * (c.i + c.m * c.rx * c.rx) / (c.i + c.m * r2);
    let py = c.m * c.m * c.v * c.rx * c.ry / (c.i + c.m * r2);
    assert_rel(imp[0].normal, px, 1e-10, "Λ_N");
    // the wall's tangent is t = (n_y, −n_x) = (0, −1): Λ_T = −P_y
    assert_rel(imp[0].tangential, -py, 1e-10, "Λ_T");
    assert!(imp[0].slip_rate_after.abs() < 1e-12);
}

#[test]
fn corner_impact_slips_below_the_stick_limit() {
    let mu = 0.05;
    let (r, c) = corner_run(mu);
    assert!(
        (c.rx * c.ry).abs() > mu * (c.i / c.m + c.rx * c.rx),
        "oracle: slip case"
    );
    let imp = impacts(&r);
    assert_eq!(imp[0].sticks, Some(false));
    assert_rel(
        imp[0].tangential.abs(),
        mu * imp[0].normal,
        1e-10,
        "|Λ_T| = μ Λ_N",
    );
    assert!(imp[0].gap_rate_after.abs() < 1e-12, "ε = 0: ġ_N⁺ = 0");
    // closed form with Λ_T = σ μ Λ_N, σ opposite to the post-impact slip
    // Λ_T = −P_y along t = (0, −1); P_y = σ μ P_x with σ = sign(ġ_T⁺)
    let sigma = imp[0].slip_rate_after.signum();
    let px = c.v / (1.0 / c.m + c.ry * (c.ry - sigma * mu * c.rx) / c.i);
    assert_rel(imp[0].normal, px, 1e-10, "Λ_N slip");
    let s = post_event(&r, 0.0);
    assert_rel(
        s.v[2],
        px * (sigma * mu * c.rx - c.ry) / c.i,
        1e-10,
        "θ̇⁺ slip",
    );
}

#[test]
fn corner_impact_frictionless() {
    let (r, c) = corner_run(0.0);
    let s = post_event(&r, 0.0);
    assert_rel(
        s.v[2],
        -c.m * c.ry * c.v / (c.i + c.m * c.ry * c.ry),
        1e-10,
        "θ̇⁺",
    );
    assert!(s.v[1].abs() < 1e-14, "no lateral velocity without friction");
}

#[test]
fn rod_on_floor_stick_impulses() {
    let (m, v, eps) = (3.0, 2.0, 0.5);
    let (s, c) = (0.5f64, 3f64.sqrt() / 2.0);
    let limit = 3.0 * s * c / (1.0 + 3.0 * s * s);
    let r = run("models/validation/rod-on-floor.toml", &[]);
    assert!(0.8 >= limit);
    let imp = impacts(&r);
    assert_eq!(imp[0].sticks, Some(true));
    assert_rel(
        imp[0].normal,
        m * v * (1.0 + eps) * (1.0 + 3.0 * s * s) / 4.0,
        1e-10,
        "P_N",
    );
    assert_rel(
        imp[0].tangential,
        3.0 * m * v * (1.0 + eps) * s * c / 4.0,
        1e-10,
        "P_T",
    );
    assert_rel(imp[0].gap_rate_after, eps * v, 1e-10, "ġ_N⁺ = εV");
    // just below the limit it slips
    let r = run(
        "models/validation/rod-on-floor.toml",
        &[&format!("contact.end.mu={}", limit * 0.99)],
    );
    let imp = impacts(&r);
    assert_eq!(imp[0].sticks, Some(false));
    assert_rel(
        imp[0].tangential.abs(),
        limit * 0.99 * imp[0].normal,
        1e-10,
        "|P_T| = μ P_N",
    );
}

#[test]
fn symmetric_double_impact_produces_no_rotation() {
    let r = run("models/validation/double-impact.toml", &[]);
    let imp = impacts(&r);
    assert_eq!(imp.len(), 2);
    assert_eq!(imp[0].t, imp[1].t, "simultaneous");
    assert_rel(imp[0].t, 0.01 / 0.3, 1e-10, "impact time");
    assert_rel(imp[0].normal, imp[1].normal, 1e-10, "equal impulses");
    let last = r.samples.last().unwrap();
    assert!(
        last.q[2].abs() < 1e-14 && last.v[2].abs() < 1e-14,
        "θ = {}",
        last.q[2]
    );
    assert!(last.q[1].abs() < 1e-14);
    assert_rel(last.v[0], 0.3 * 0.3, 1e-10, "rebound ε v");
}

#[test]
fn painleve_configuration_is_reported() {
    let scene = deckspin::load(&model("models/validation/painleve.toml"), &[]).unwrap();
    let (s, c, mu) = (3f64.sqrt() / 2.0, 0.5, 2.0);
    assert!(
        1.0 + 3.0 * c * c - 3.0 * mu * s * c < 0.0,
        "oracle: Painlevé condition"
    );
    match deckspin::run(&scene, &mut deckspin::Silent) {
        Err(deckspin::SolverError::Painleve { contacts, .. }) => assert_eq!(contacts, "end"),
        other => panic!(
            "expected Painlevé, got {:?}",
            other.map(|r| r.summary.stats)
        ),
    }
    // sliding the other way, friction presses the end down: 1 + 3c² + 3μsc > 0, no Painlevé
    let scene = deckspin::load(
        &model("models/validation/painleve.toml"),
        &["body.0.initial_velocity=[1.0, 0.0, 0.0]".to_string()],
    )
    .unwrap();
    let r = deckspin::run(&scene, &mut deckspin::Silent).unwrap();
    assert!(
        r.summary.stats.sticks == 1,
        "slides to a stop: {:?}",
        r.summary.stats
    );
}

#[test]
fn frictionless_elastic_rattle_conserves_energy() {
    let r = run("models/validation/elastic-rattle.toml", &[]);
    assert!(impacts(&r).len() >= 4);
    let e0 = r.samples[0].energy.kinetic + r.samples[0].energy.elastic;
    for s in &r.samples {
        let e = s.energy.kinetic + s.energy.elastic;
        assert!(rel(e, e0) < 1e-8, "t = {}: E = {e}, E0 = {e0}", s.t);
        assert!(s.energy.impact_normal.abs() < 1e-9 * e0);
    }
}

#[test]
fn energy_ledger_closes_and_nothing_penetrates_on_every_validation_scene() {
    let dir = model("models/validation");
    let mut n = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_none_or(|e| e != "toml") {
            continue;
        }
        let scene = deckspin::load(&p, &[]).unwrap();
        let Ok(r) = deckspin::run(&scene, &mut deckspin::Silent) else {
            assert!(p.ends_with("painleve.toml"), "{} failed", p.display());
            continue;
        };
        n += 1;
        let s = &r.summary;
        assert!(
            s.energy_closure_rel < 1e-8,
            "{}: closure {:.3e}",
            p.display(),
            s.energy_closure_rel
        );
        assert!(
            s.max_penetration < 1e-12,
            "{}: penetration {:.3e}",
            p.display(),
            s.max_penetration
        );
        // frictionless impacts with ε ≤ 1 never create energy
        assert!(s.energy_final.impact_normal > -1e-9 * s.energy_final.initial.max(1.0));
    }
    assert!(n >= 7);
}

/// A grazing impact inside one step: an oscillator (ω = 2π rad/s, amplitude A = 1/ω) whose stop
/// sits 10 nm inside its swing, so the gap would dip 10 nm below zero for 0.1 ms, between the
/// samples of a DP5 step 50 times longer. The crossing must still be found (no penetration beyond the
/// event tolerance), at the closed-form instant x(t) = A sin ωt = −(A − 1 µm).
#[test]
fn a_gap_that_dips_below_zero_inside_one_step_is_found() {
    let omega = 2.0 * std::f64::consts::PI;
    let a = 1.0 / omega;
    let dip = 1e-8;
    let text = format!(
        r#"
title = "grazing stop"
[solver]
t_end = 1.0
output_dt = 1.0
rtol = 1e-11
atol = 1e-13
[[body]]
name = "mass"
mass = 1.0
dofs = ["x"]
initial_velocity = [1.0, 0.0, 0.0]
[[spring]]
name = "spring"
body = "mass"
direction = [1.0, 0.0]
stiffness = {k}
[[contact]]
name = "stop"
body = "mass"
normal = [1.0, 0.0]
gap = {gap}
restitution = 0.5
"#,
        k = omega * omega,
        gap = a - dip
    );
    let r = common::run_text(&text, "grazing.toml").unwrap();
    let impacts = common::impacts(&r);
    assert_eq!(impacts.len(), 1, "{:?}", r.events);
    // first passage of x = −(A − dip) after the turn at the top: ωt = π + asin(1 − dip/A)
    let t_exact = (std::f64::consts::PI + (1.0 - dip / a).asin()) / omega;
    let v_exact = a * omega * (omega * t_exact).cos();
    // a grazing crossing is ill-conditioned: a position error δx moves it by δx/|ġ|; DP5 at
    // rtol 1e-11 keeps δx below 1e-11 m here
    let dt = (impacts[0].t - t_exact).abs();
    assert!(dt < 1e-11 / v_exact.abs(), "{} vs {t_exact}", impacts[0].t);
    // the approach speed, to the same position error: δġ = ω²A δx/|ġ| (plus rounding)
    let dv = (impacts[0].gap_rate_before - v_exact).abs();
    assert!(
        dv < omega * omega * a * 1e-11 / v_exact.abs() + 1e-12,
        "{dv:e} of {v_exact:e}"
    );
    let s = &r.summary;
    assert!(
        s.max_penetration <= 1e-9,
        "penetration {:e}",
        s.max_penetration
    );
}
