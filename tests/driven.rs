//! Rigid bodies driven by the ground (`drive_x`, `drive_y`): a block against a moving wall,
//! checked against Newton's law in the wall's frame, the energy balance with the wall's work,
//! penetration, and the force of a wall that pushes a resting block.
mod common;
use common::*;
use deckspin::output::{EventKind, RunOutput, SampleKind};
use std::f64::consts::PI;
use std::path::Path;

/// A block of mass `m` (x only) at x = 1 m moving at `v` toward a wall driven along x by
/// u_g = A sin(ω t) (A = 0.2 m, f = 0.5 Hz), its face `gap` away.
fn block_and_wall(v: f64, gap: f64, eps: f64) -> String {
    format!(
        r#"
[solver]
t_end = 0.6
rtol = 1e-12
atol = 1e-14
[[support]]
name = "ground"
kind = "harmonic"
amplitude = 0.2
frequency = 0.5
[[body]]
name = "wall"
mass = 0.0
drive_x = "ground"
[[body]]
name = "block"
mass = 2.0
dofs = ["x"]
position = [1.0, 0.0]
initial_velocity = [{v}, 0.0, 0.0]
[[contact]]
name = "face"
body = "block"
face_body = "wall"
normal = [1.0, 0.0]
gap = {gap}
restitution = {eps}
"#
    )
}

fn scene(text: &str) -> deckspin::scene::Scene {
    deckspin::model::load_str(text, Path::new("driven.toml"), &[]).unwrap_or_else(|e| panic!("{e}"))
}

/// The root of g(t) = gap + v t − A sin ω t by Newton from 0.
fn impact_time(v: f64, gap: f64, a: f64, w: f64) -> f64 {
    let mut t = 0.0;
    for _ in 0..60 {
        let g = gap + v * t - a * (w * t).sin();
        let gd = v - a * w * (w * t).cos();
        t -= g / gd;
    }
    t
}

#[test]
fn block_hits_moving_wall_with_newton_restitution_in_the_walls_frame() {
    let (v, gap, a, w) = (-1.0, 0.3, 0.2, PI);
    let t_star = impact_time(v, gap, a, w);
    for eps in [0.0, 0.5, 1.0] {
        let r = run_text(&block_and_wall(v, gap, eps), "driven.toml").unwrap();
        let imp = impacts(&r);
        assert_eq!(imp.len(), 1, "ε = {eps}");
        let e = imp[0];
        assert!(
            (e.t - t_star).abs() < 1e-12,
            "ε = {eps}: impact at {} vs {t_star}",
            e.t
        );
        // the wall's velocity at the impact, and Newton's law in its frame
        let big_v = a * w * (w * e.t).cos();
        assert!(big_v > 0.4, "the wall moves toward the block ({big_v})");
        let v_after = big_v - eps * (v - big_v);
        let post = post_event(&r, e.t);
        eprintln!(
            "ε = {eps}: impact time off by {:.1e} s, v⁺ by {:.1e} m/s",
            (e.t - t_star).abs(),
            (post.v[0] - v_after).abs()
        );
        assert!(
            (post.v[0] - v_after).abs() < 1e-12,
            "ε = {eps}: v⁺ = {}, expected {v_after}",
            post.v[0]
        );
        assert!((e.gap_rate_before - (v - big_v)).abs() < 1e-12);
        assert!((e.gap_rate_after + eps * (v - big_v)).abs() < 1e-12);
        // the impulse m (v⁺ − v⁻) came from the wall
        assert!((e.normal - 2.0 * (v_after - v)).abs() < 1e-11);
    }
}

/// A block (x, y) on an incline (normal 30° from y) driven along x by
/// u_g = 0.05 sin(4π t + φ), with friction μ and ε = 0.5; its corner `gap` above the face at
/// the reference configuration.
struct Incline {
    method: &'static str,
    step: f64,
    t_end: f64,
    gap: f64,
    phase: f64,
    mu: f64,
}

impl Incline {
    fn text(&self) -> String {
        let (s, c) = (30f64.to_radians().sin(), 30f64.to_radians().cos());
        format!(
            r#"
gravity = [0.0, -9.81]
[solver]
method = "{method}"
t_end = {t_end}
output_dt = 0.002
rtol = 1e-12
atol = 1e-14
step = {step:e}
contact_stiffness = 1e7
max_closure = 1.0
max_penetration = 1.0
[[support]]
name = "shake"
kind = "harmonic"
amplitude = 0.05
frequency = 2.0
phase = {phase:.17e}
[[body]]
name = "incline"
mass = 0.0
drive_x = "shake"
[[body]]
name = "block"
mass = 1.5
dofs = ["x", "y"]
position = [0.0, 0.2]
[[contact]]
name = "corner"
body = "block"
point = [0.05, -0.1]
face_body = "incline"
normal = [{nx:.17e}, {ny:.17e}]
gap = {gap:e}
mu = {mu}
restitution = 0.5
"#,
            method = self.method,
            t_end = self.t_end,
            step = self.step,
            phase = self.phase,
            gap = self.gap,
            mu = self.mu,
            nx = -s,
            ny = c
        )
    }
}

/// |closure| / scale at the worst sample, and the largest |W_supports| / scale.
fn closure(r: &RunOutput) -> (f64, f64) {
    let scale = r
        .samples
        .iter()
        .map(|s| s.energy.scale())
        .fold(0.0, f64::max);
    let worst = (r.samples.iter())
        .map(|s| s.energy.closure.abs())
        .fold(0.0, f64::max);
    let wall = (r.samples.iter())
        .map(|s| s.energy.supports.abs())
        .fold(0.0, f64::max);
    (worst / scale, wall / scale)
}

#[test]
fn energy_balance_closes_with_the_work_of_a_moving_face() {
    // dropped 5 cm onto the shaking face: impacts that accumulate, then stick and slip
    let drop = Incline {
        method: "event",
        step: 1e-3,
        t_end: 2.0,
        gap: 0.05,
        phase: 0.0,
        mu: 0.7,
    };
    let r = run_text(&drop.text(), "incline.toml").unwrap();
    let kinds = |k: EventKind| r.events.iter().filter(|e| e.kind == k).count();
    assert!(
        kinds(EventKind::Impact) >= 3,
        "{} impacts",
        kinds(EventKind::Impact)
    );
    assert!(
        kinds(EventKind::Stick) >= 2 && kinds(EventKind::Slip) >= 2,
        "no stick–slip"
    );
    let last = r.samples.last().unwrap();
    assert!(
        last.energy.friction > 1.0,
        "friction works: {}",
        last.energy.friction
    );
    assert!(
        last.energy.impact_tangential > 0.1,
        "{}",
        last.energy.impact_tangential
    );
    let (worst, wall) = closure(&r);
    assert!(worst <= 1e-8, "closure {worst:e} of the input scale");
    // the wall's work is a large part of the balance: leaving it out would not close
    assert!(wall > 0.05, "wall work {wall:e} of the scale");
    // (c) no corner went through the moving face
    let deepest = (r.samples.iter())
        .map(|s| s.contacts[0].gap)
        .fold(f64::INFINITY, f64::min);
    eprintln!("incline: closure {worst:.1e}, wall work {wall:.3}, deepest gap {deepest:.1e} m");
    assert!(deepest >= -1e-9, "penetration {deepest:e} m");
    assert!(r.summary.max_penetration <= 1e-9);
}

#[test]
fn fixed_step_methods_close_the_balance_to_their_order() {
    // the block resting on the face as the shaking starts from rest (φ = −π/2: the face starts
    // 0.05 m to the left, A·sin 30° below the reference): it slides on the moving face for the
    // whole run. Moreau–Jean's balance closes to O(h), the penalty method's (Newmark) to
    // O(h²); without the wall's work neither would close
    for (method, h, order) in [("moreau", 4e-4, 1), ("penalty", 4e-4, 2)] {
        let err = |step: f64| {
            let rest = Incline {
                method,
                step,
                t_end: 1.0,
                gap: 0.05 * 0.5 - 1e-13,
                phase: -PI / 2.0,
                mu: 0.3,
            };
            let sc = scene(&rest.text());
            let r =
                deckspin::simulate(&sc, &mut deckspin::Silent).unwrap_or_else(|e| panic!("{e}"));
            let (worst, wall) = closure(&r);
            assert!(wall > 0.01, "{method}: wall work {wall:e}");
            assert!(r.samples.last().unwrap().energy.friction > 0.1);
            worst
        };
        let e: Vec<f64> = (0..4).map(|k| err(h / f64::powi(2.0, k))).collect();
        let shown: Vec<String> = e.iter().map(|x| format!("{x:.2e}")).collect();
        eprintln!(
            "{method}: closure {} at h = {h:e} / 1, 2, 4, 8",
            shown.join(" ")
        );
        let ratio = 0.5f64.powi(order);
        for k in 1..4 {
            let r = e[k] / e[k - 1];
            assert!(
                (r - ratio).abs() < 0.1 * ratio,
                "{method}: closure {:e} → {:e} at half the step (ratio {r}, expected {ratio})",
                e[k - 1],
                e[k]
            );
        }
        assert!(e[0] < 2e-3, "{method}: {:e}", e[0]);
    }
}

#[test]
fn resting_block_is_pushed_by_an_accelerating_wall() {
    // u_g = A sin(ω t − π/2): the wall starts at rest at −A and accelerates at A ω² cos ω t
    // into the block until t = π/(2ω), where the block leaves it at A ω
    let (m, a, f) = (3.0, 0.05, 2.0);
    let w = 2.0 * PI * f;
    let text = format!(
        r#"
[solver]
t_end = 0.3
output_dt = 0.005
rtol = 1e-12
atol = 1e-14
[[support]]
name = "ground"
kind = "harmonic"
amplitude = {a}
frequency = {f}
phase = {phase:.17e}
[[body]]
name = "wall"
mass = 0.0
drive_x = "ground"
[[body]]
name = "block"
mass = {m}
dofs = ["x"]
position = [1.0, 0.0]
initial_displacement = [{d}, 0.0, 0.0]
[[contact]]
name = "face"
body = "block"
face_body = "wall"
normal = [1.0, 0.0]
gap = 0.0
"#,
        phase = -PI / 2.0,
        d = -a
    );
    let r = run_text(&text, "push.toml").unwrap();
    let t_r = PI / (2.0 * w);
    let (mut checked, mut worst) = (0, 0.0f64);
    // (after the contact closed at t = 0: the pre-event sample has no force yet)
    let pushed = |s: &&deckspin::output::Sample| s.kind != SampleKind::PreEvent && s.t < t_r - 1e-9;
    for s in r.samples.iter().filter(pushed) {
        let lam = m * a * w * w * (w * s.t).cos();
        assert!(
            (s.contacts[0].normal_force - lam).abs() <= 1e-9 * m * a * w * w,
            "t = {}: λ_N = {}, m a_wall = {lam}",
            s.t,
            s.contacts[0].normal_force
        );
        assert!(
            (s.q[0] + a * (w * s.t).cos()).abs() < 1e-11,
            "moves with the wall"
        );
        worst = worst.max((s.contacts[0].normal_force - lam).abs() / (m * a * w * w));
        checked += 1;
    }
    assert!(checked >= 10);
    let release: Vec<_> = (r.events.iter())
        .filter(|e| e.kind == EventKind::Release)
        .collect();
    assert_eq!(release.len(), 1);
    eprintln!(
        "pushed block: λ_N off by {worst:.1e} of m A ω², release by {:.1e} s",
        (release[0].t - t_r).abs()
    );
    assert!(
        (release[0].t - t_r).abs() < 1e-9,
        "release at {}",
        release[0].t
    );
    let last = r.samples.last().unwrap();
    assert!((last.v[0] - a * w).abs() < 1e-9, "leaves at {}", last.v[0]);
    assert_eq!(last.kind, SampleKind::Grid);
}

#[test]
fn bad_drives_and_two_body_elements_name_file_line_and_field() {
    let base = block_and_wall(-1.0, 0.3, 0.5);
    let cases = [
        // a driven body with DOFs
        (
            base.replace(
                "drive_x = \"ground\"",
                "drive_x = \"ground\"\ndofs = [\"x\"]",
            ),
            ":15: body.0.dofs",
            "has no DOFs",
        ),
        (
            base.replace("drive_x = \"ground\"", "drive_y = \"quake\""),
            ":14: body.0.drive_y",
            "no support named 'quake'",
        ),
        (
            base.replace("mass = 0.0\ndrive_x = \"ground\"", "mass = 1.0"),
            ": body.0.dofs",
            "drive_x / drive_y",
        ),
        // a contact between a driven body and the ground
        (
            base.replace(
                "body = \"block\"\nface_body = \"wall\"",
                "body = \"wall\"\nface_body = \"ground\"",
            ),
            ":24: contact.0.face_body",
            "neither body has DOFs",
        ),
        // a two-body spring with a support, or on itself, or acting on nothing
        (
            format!(
                "{base}[[spring]]\nname = \"k\"\nbody = \"block\"\nother = \"wall\"\n\
                 direction = [1.0, 0.0]\nstiffness = 1.0\nsupport = \"ground\"\n"
            ),
            ":34: spring.0.support",
            "has no support",
        ),
        (
            format!(
                "{base}[[spring]]\nname = \"k\"\nbody = \"block\"\nother = \"block\"\n\
                 direction = [1.0, 0.0]\nstiffness = 1.0\n"
            ),
            ":31: spring.0.other",
            "to itself",
        ),
        (
            format!(
                "{base}[[spring]]\nname = \"k\"\nbody = \"wall\"\ndirection = [1.0, 0.0]\n\
                 stiffness = 1.0\nsupport = \"ground\"\n"
            ),
            ":30: spring.0.body",
            "act on nothing",
        ),
        (
            format!(
                "{base}[[spring]]\nname = \"k\"\nbody = \"block\"\nother_point = [1.0, 0.0]\n\
                 direction = [1.0, 0.0]\nstiffness = 1.0\n"
            ),
            ":31: spring.0.other_point",
            "without `other`",
        ),
    ];
    for (text, at, why) in cases {
        let e = deckspin::model::load_str(&text, Path::new("bad.toml"), &[]).expect_err(at);
        let msg = e.to_string();
        assert!(
            msg.starts_with("bad.toml") && msg.contains(at) && msg.contains(why),
            "{msg}"
        );
    }
}
