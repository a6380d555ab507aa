//! Elements between two bodies (`other`, `other_point`: e = d·[(P_a − P_a0) − (P_b − P_b0)]):
//! a free pair on a spring against its closed form, its modes, a hysteretic pair against the
//! reduced-mass oscillator, a key to a driven wall against a spring to the support, and the
//! Jacobian against finite differences.
mod common;
use common::*;
use deckspin::output::{RunOutput, SampleKind};
use deckspin::scene::Scene;
use nalgebra::DVector;
use std::path::Path;

fn scene(text: &str) -> Scene {
    deckspin::model::load_str(text, Path::new("pair.toml"), &[]).unwrap_or_else(|e| panic!("{e}"))
}

const SOLVER: &str = r#"
[solver]
t_end = 2.0
output_dt = 0.01
rtol = 1e-12
atol = 1e-14
"#;

/// Bodies a (m₁ = 2, at 0, 0.5 m/s) and b (m₂ = 3, at 1 m, −0.2 m/s), x only, joined by
/// `element` (a `[[spring]]` or `[[hysteretic]]` table without its body fields).
fn pair(element: &str) -> String {
    format!(
        r#"{SOLVER}
[[body]]
name = "a"
mass = 2.0
dofs = ["x"]
initial_velocity = [0.5, 0.0, 0.0]
[[body]]
name = "b"
mass = 3.0
dofs = ["x"]
position = [1.0, 0.0]
initial_velocity = [-0.2, 0.0, 0.0]
{element}
body = "a"
other = "b"
direction = [1.0, 0.0]
"#
    )
}

const SPRING: &str = "[[spring]]\nname = \"key\"\nstiffness = 100.0";

/// Largest |m₁v₁ + m₂v₂ − p₀| / |p₀| over the samples.
fn momentum_drift(r: &RunOutput) -> f64 {
    let p0 = 2.0 * 0.5 + 3.0 * -0.2;
    (r.samples.iter())
        .map(|s| ((2.0 * s.v[0] + 3.0 * s.v[1]) - p0).abs() / p0.abs())
        .fold(0.0, f64::max)
}

/// Largest |closure| / scale over the samples.
fn closure(r: &RunOutput) -> f64 {
    let scale = r
        .samples
        .iter()
        .map(|s| s.energy.scale())
        .fold(0.0, f64::max);
    (r.samples.iter())
        .map(|s| s.energy.closure.abs())
        .fold(0.0, f64::max)
        / scale
}

#[test]
fn free_pair_on_a_spring_oscillates_at_the_reduced_mass_frequency() {
    let (m1, m2, k): (f64, f64, f64) = (2.0, 3.0, 100.0);
    let w = (k * (1.0 / m1 + 1.0 / m2)).sqrt();
    let r = run_text(&pair(SPRING), "pair.toml").unwrap();
    // e = x_a − x_b from e(0) = 0, ė(0) = 0.7 m/s: e = 0.7/ω sin ωt, storing ½ k e²
    let amp = 0.7 / w;
    let (mut worst, mut worst_u) = (0.0f64, 0.0f64);
    for s in &r.samples {
        let e = amp * (w * s.t).sin();
        worst = worst.max(((s.q[0] - s.q[1]) - e).abs());
        worst_u = worst_u.max((s.energy.elastic - 0.5 * k * e * e).abs());
    }
    eprintln!("pair: e off by {worst:.2e} m, ½ k e² by {worst_u:.2e} J");
    assert!(worst < 1e-9 * amp, "relative motion off by {worst:e} m");
    assert!(
        worst_u < 1e-9 * 0.5 * k * amp * amp,
        "stored energy off by {worst_u:e} J"
    );
    let drift = momentum_drift(&r);
    let c = closure(&r);
    eprintln!("pair: momentum drift {drift:.2e}, closure {c:.2e}");
    assert!(drift < 1e-12, "momentum drift {drift:e}");
    assert!(c < 1e-10, "closure {c:e}");
}

#[test]
fn modes_of_the_pair_give_the_same_frequency() {
    let sc = scene(&pair(SPRING));
    let modes = deckspin::modal::modes(&sc);
    assert_eq!(modes.len(), 2);
    assert!(modes[0].omega < 1e-6, "rigid-body mode {}", modes[0].omega);
    let w = (100.0f64 * (1.0 / 2.0 + 1.0 / 3.0)).sqrt();
    assert_rel(modes[1].omega, w, 1e-12, "ω of the pair");
    // the mode moves the bodies against each other with zero momentum
    let phi = &modes[1].shape;
    assert!((2.0 * phi[0] + 3.0 * phi[1]).abs() < 1e-12 * phi.amax());
}

#[test]
fn hysteretic_pair_moves_as_the_reduced_mass_oscillator() {
    let law = r#"[[hysteretic]]
name = "key"
law = { law = "bilinear", stiffness = 100.0, yield_force = 5.0, post_yield_ratio = 0.1 }"#;
    let r = run_text(&pair(law), "pair.toml").unwrap();
    assert!(
        r.summary.stats.branch_events >= 4,
        "{} branch changes",
        r.summary.stats.branch_events
    );
    assert!(
        momentum_drift(&r) < 1e-12,
        "momentum drift {:e}",
        momentum_drift(&r)
    );
    let c = closure(&r);
    assert!(c < 1e-9, "closure {c:e}");
    // the same law on one body of the reduced mass m₁m₂/(m₁+m₂) = 1.2 to the ground, started at
    // the relative velocity 0.7 m/s: an independent run of the one-body path
    let single = format!(
        r#"{SOLVER}
[[body]]
name = "r"
mass = 1.2
dofs = ["x"]
initial_velocity = [0.7, 0.0, 0.0]
[[hysteretic]]
name = "key"
law = {{ law = "bilinear", stiffness = 100.0, yield_force = 5.0, post_yield_ratio = 0.1 }}
body = "r"
direction = [1.0, 0.0]
"#
    );
    let one = run_text(&single, "single.toml").unwrap();
    let grid = |r: &RunOutput| -> Vec<(f64, f64, f64)> {
        (r.samples.iter())
            .filter(|s| s.kind == SampleKind::Grid)
            .map(|s| {
                (
                    s.t,
                    s.q[0] - s.q.get(1).copied().unwrap_or(0.0),
                    s.elements[0].1,
                )
            })
            .collect()
    };
    let (a, b) = (grid(&r), grid(&one));
    assert_eq!(a.len(), b.len());
    let de = (a.iter().zip(&b))
        .map(|(x, y)| (x.1 - y.1).abs())
        .fold(0.0, f64::max);
    let df = (a.iter().zip(&b))
        .map(|(x, y)| (x.2 - y.2).abs())
        .fold(0.0, f64::max);
    eprintln!("bilinear pair vs reduced mass: e {de:.1e} m, force {df:.1e}");
    for (x, y) in a.iter().zip(&b) {
        assert!((x.0 - y.0).abs() < 1e-12);
        assert!(
            (x.1 - y.1).abs() < 1e-11,
            "t = {}: e {} vs {}",
            x.0,
            x.1,
            y.1
        );
        assert!(
            (x.2 - y.2).abs() < 1e-9,
            "t = {}: force {} vs {}",
            x.0,
            x.2,
            y.2
        );
    }
}

#[test]
fn key_to_a_driven_wall_acts_as_a_spring_to_its_support() {
    // a block (x, y) on a bearing along y to the ground and a key along x to a wall that moves
    // with the ground, against the same block with the key replaced by a spring to the support
    let block = |element: &str| {
        format!(
            r#"{SOLVER}
[[support]]
name = "ground"
kind = "harmonic"
amplitude = 0.02
frequency = 1.5
[[body]]
name = "wall"
mass = 0.0
drive_x = "ground"
position = [-2.0, 0.0]
[[body]]
name = "block"
mass = 4.0
dofs = ["x", "y"]
initial_velocity = [0.0, 0.1, 0.0]
[[spring]]
name = "bearing"
body = "block"
direction = [0.0, 1.0]
stiffness = 90.0
support = "ground"
[[spring]]
name = "k"
body = "block"
direction = [1.0, 0.0]
stiffness = 250.0
damping = 3.0
{element}
"#
        )
    };
    let key = scene(&block(
        "other = \"wall\"\npoint = [-0.5, 0.0]\nother_point = [1.5, 0.0]",
    ));
    let support = scene(&block("support = \"ground\""));
    let run = |sc: &Scene| deckspin::run(sc, &mut deckspin::Silent).unwrap();
    let compare = |a: &RunOutput, b: &RunOutput| {
        assert_eq!(a.samples.len(), b.samples.len());
        let peak = b.summary.peaks[0].max_abs;
        assert!(peak > 0.01, "the block moves: {peak}");
        for (x, y) in a.samples.iter().zip(&b.samples) {
            assert!((x.q[0] - y.q[0]).abs() <= 1e-12 * peak, "t = {}", x.t);
            // the same work of the ground through the element, the same dashpot loss
            assert!((x.energy.supports - y.energy.supports).abs() < 1e-12);
            assert!((x.energy.damping - y.energy.damping).abs() < 1e-12);
        }
        assert!(a.samples.last().unwrap().energy.supports.abs() > 1e-3);
        assert!(closure(a) < 1e-9, "closure {:e}", closure(a));
    };
    compare(&run(&key), &run(&support));
    // Rayleigh damping: the quasi-static motion of the block is the wall's (r = 1 along x),
    // so a₀M damps the motion relative to the ground alike
    let (mut key, mut support) = (key, support);
    let ab = deckspin::modal::apply_rayleigh(&mut key, 0.05, [1, 2]).unwrap();
    assert_eq!(
        ab,
        deckspin::modal::apply_rayleigh(&mut support, 0.05, [1, 2]).unwrap()
    );
    let mut r = key.mass_damping.reference.clone();
    r.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(
        r,
        vec![(0, 0, 1.0), (1, 0, 1.0)],
        "quasi-static influence of the ground"
    );
    assert_eq!(
        format!("{:?}", support.mass_damping),
        format!("{:?}", key.mass_damping)
    );
    compare(&run(&key), &run(&support));
}

#[test]
fn two_body_jacobian_with_rotation_arms_matches_finite_differences() {
    let text = format!(
        r#"{SOLVER}
[[body]]
name = "deck"
mass = 10.0
inertia = 40.0
dofs = ["x", "y", "theta"]
[[body]]
name = "frame"
mass = 5.0
inertia = 8.0
dofs = ["x", "y", "theta"]
position = [12.0, 0.5]
[[spring]]
name = "key"
body = "deck"
point = [6.0, -1.5]
other = "frame"
other_point = [-5.5, 0.8]
direction = [0.6, 0.8]
stiffness = 1.0
"#
    );
    let sc = scene(&text);
    let att = &sc.springs[0].attachment;
    let q = DVector::from_vec(vec![0.01, -0.02, 0.03, 0.004, 0.01, -0.05]);
    let v = DVector::from_vec(vec![0.3, -0.1, 0.2, -0.4, 0.25, 0.7]);
    let (e, ed, ug, jac, nj) = sc.deformation(&sc.frame(0.0, &q, &v), att, None);
    assert_eq!(nj, 6);
    assert_eq!(ug, 0.0, "no support, no driven body");
    let mut dense = DVector::zeros(6);
    deckspin::scene::spread(&jac[..nj], &mut dense);
    let e_at = |q: &DVector<f64>| sc.deformation(&sc.frame(0.0, q, &v), att, None).0;
    let h = 1e-6;
    let mut worst = 0.0f64;
    for j in 0..6 {
        let (mut qp, mut qm) = (q.clone(), q.clone());
        qp[j] += h;
        qm[j] -= h;
        let fd = (e_at(&qp) - e_at(&qm)) / (2.0 * h);
        let scale = dense.amax();
        worst = worst.max((fd - dense[j]).abs() / scale);
        assert!(
            (fd - dense[j]).abs() <= 1e-7 * scale,
            "J[{j}]: fd {fd}, exact {}",
            dense[j]
        );
    }
    eprintln!("two-body J against central differences: {worst:.1e}");
    assert!(
        dense[2].abs() > 1.0 && dense[5].abs() > 1.0,
        "the arms count: {dense}"
    );
    assert!((ed - dense.dot(&v)).abs() < 1e-14, "ė = J q̇");
    // e from the definition, d·[(P_a − P_a0) − (P_b − P_b0)]
    let d = nalgebra::Vector2::new(0.6, 0.8);
    let rot = |th: f64, p: [f64; 2]| {
        nalgebra::Vector2::new(
            th.cos() * p[0] - th.sin() * p[1],
            th.sin() * p[0] + th.cos() * p[1],
        )
    };
    let pa = nalgebra::Vector2::new(q[0], q[1]) + rot(q[2], [6.0, -1.5]) - rot(0.0, [6.0, -1.5]);
    let pb = nalgebra::Vector2::new(q[3], q[4]) + rot(q[5], [-5.5, 0.8]) - rot(0.0, [-5.5, 0.8]);
    assert!((e - d.dot(&(pa - pb))).abs() < 1e-15, "{e}");
}
