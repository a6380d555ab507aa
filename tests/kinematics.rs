//! Exact planar kinematics against finite differences: W_N = ∂g_N/∂q, ġ = Wᵀq̇ and the
//! velocity-product terms ŵ of g̈ = Wᵀq̈ + ŵ, for a corner of one moving body on the face of
//! another moving, rotating body at a skew angle.
use nalgebra::DVector;
use std::path::Path;

const TEXT: &str = r#"
[[body]]
name = "deck"
mass = 10.0
inertia = 40.0
dofs = ["x", "y", "theta"]
position = [0.0, 0.0]
[[body]]
name = "abutment"
mass = 2.0
inertia = 1.0
dofs = ["x", "y", "theta"]
position = [-6.0, 0.5]
[[contact]]
name = "corner"
body = "deck"
point = [-5.0, 1.2]
face_body = "abutment"
normal = [0.9659258262890683, 0.25881904510252074]   # skew 15°
gap = 0.05
mu = 0.4
"#;

fn scene() -> deckspin::scene::Scene {
    deckspin::model::load_str(TEXT, Path::new("kin.toml"), &[]).unwrap()
}

#[test]
fn jacobians_and_bias_match_finite_differences() {
    let s = scene();
    let c = &s.contacts[0];
    let q = DVector::from_vec(vec![0.01, -0.02, 0.03, 0.004, 0.01, -0.05]);
    let v = DVector::from_vec(vec![0.3, -0.1, 0.2, -0.4, 0.25, 0.7]);
    let a = DVector::from_vec(vec![1.0, 0.5, -0.3, 0.2, -0.7, 0.4]);
    let k = s.contact_kinematics(&s.frame(0.0, &q, &v), c);
    // ∂g/∂q by central differences
    let h = 1e-6;
    for j in 0..6 {
        let mut qp = q.clone();
        let mut qm = q.clone();
        qp[j] += h;
        qm[j] -= h;
        let d = (s.contact_kinematics(&s.frame(0.0, &qp, &v), c).gap
            - s.contact_kinematics(&s.frame(0.0, &qm, &v), c).gap)
            / (2.0 * h);
        assert!(
            (d - k.w_n[j]).abs() < 1e-8,
            "W_N[{j}]: fd {d}, exact {}",
            k.w_n[j]
        );
    }
    assert!((k.gap_rate - k.w_n.dot(&v)).abs() < 1e-14);
    assert!((k.slip_rate - k.w_t.dot(&v)).abs() < 1e-14);
    // d/dt of ġ_N, ġ_T along q(t) = q + v t + a t²/2 equals Wᵀa + ŵ
    let at = |t: f64| {
        let qt = &q + &v * t + &a * (0.5 * t * t);
        let vt = &v + &a * t;
        s.contact_kinematics(&s.frame(0.0, &qt, &vt), c)
    };
    let dt = 1e-6;
    let gdd_n = (at(dt).gap_rate - at(-dt).gap_rate) / (2.0 * dt);
    let gdd_t = (at(dt).slip_rate - at(-dt).slip_rate) / (2.0 * dt);
    assert!(
        (gdd_n - (k.w_n.dot(&a) + k.bias_n)).abs() < 1e-7,
        "g̈_N {gdd_n}"
    );
    assert!(
        (gdd_t - (k.w_t.dot(&a) + k.bias_t)).abs() < 1e-7,
        "g̈_T {gdd_t}"
    );
    assert!(k.bias_n.abs() > 1e-3, "the test exercises nonzero ŵ");
}

#[test]
fn gap_at_reference_is_the_declared_gap_and_exact_in_rotation() {
    let s = scene();
    let c = &s.contacts[0];
    let z = DVector::zeros(6);
    let k = s.contact_kinematics(&s.frame(0.0, &z, &z), c);
    assert!((k.gap - 0.05).abs() < 1e-15);
    // rotate the deck by θ about its centre: exact g_N change = n·(R(θ)r − r)
    let th: f64 = 0.01;
    let mut q = DVector::zeros(6);
    q[2] = th;
    let r = nalgebra::Vector2::new(-5.0, 1.2);
    let rr = nalgebra::Vector2::new(
        th.cos() * r.x - th.sin() * r.y,
        th.sin() * r.x + th.cos() * r.y,
    );
    let n = nalgebra::Vector2::new(0.9659258262890683, 0.25881904510252074);
    let exact = 0.05 + n.dot(&(rr - r));
    let g = s.contact_kinematics(&s.frame(0.0, &q, &z), c).gap;
    assert!((g - exact).abs() < 1e-15, "g {g} exact {exact}");
    // the linear form W_Nᵀq misses the second-order term (L/2)θ²/2-type contribution
    let linear = 0.05 + k.w_n.dot(&q);
    assert!((linear - exact).abs() > 1e-5 * 0.5);
}

/// A backwall free in x and θ and carried in y by the ground (a bridge file's `backfill`
/// abutment), with a backfill element at a point off its centre.
const BACKWALL: &str = r#"
[[support]]
name = "ground"
kind = "harmonic"
amplitude = 0.03
frequency = 1.7
[[body]]
name = "wall"
mass = 0.65
inertia = 0.2
dofs = ["x", "theta"]
position = [-20.0, 0.0]
[[hysteretic]]
name = "fill"
body = "wall"
point = [0.0, 0.4]
direction = [1.0, 0.0]
support = "ground"
law = { law = "backfill", gap = 0.0, stiffness = 1.0e4, capacity = 50.0 }
"#;

#[test]
fn a_body_driven_in_y_keeps_its_dofs_in_x_and_theta() {
    // the one-body reading (event location) against the frame (the forces): x, θ from q, y from
    // the ground; e = x − 0.4 sin θ − u_g by hand
    let mut s = deckspin::model::load_str(BACKWALL, Path::new("wall.toml"), &[]).unwrap();
    s.bodies[0].drive = [None, Some(0)];
    let (x, th, vx, om) = (0.012, 0.003, -0.2, 0.05);
    let q = DVector::from_vec(vec![x, th]);
    let v = DVector::from_vec(vec![vx, om]);
    let y = DVector::from_vec(vec![x, th, vx, om]);
    let t = 0.37;
    let (ug, vg, _) = s.supports[0].at(t);
    let fr = s.frame(t, &q, &v);
    let one = s.body_state_at(0, t, &y, 2);
    let framed = &fr.poses[0];
    assert_eq!(one.position, framed.position);
    assert_eq!(one.velocity, framed.velocity);
    assert_eq!((one.angle, one.omega), (framed.angle, framed.omega));
    assert_eq!(one.position.y, ug);
    assert_eq!(one.velocity.y, vg);
    let el = &s.hysteretic[0];
    let (e, ed) = s.deformation_value(&el.attachment, &one, &one, fr.supports[0]);
    let (e_hand, ed_hand) = (x - 0.4 * th.sin() - ug, vx - 0.4 * om * th.cos() - vg);
    assert!((e - e_hand).abs() < 1e-15, "e {e} by hand {e_hand}");
    assert!((ed - ed_hand).abs() < 1e-15, "ė {ed} by hand {ed_hand}");
    assert_eq!(
        (e, ed),
        s.deformation_rates(&fr, &el.attachment, el.support)
    );
}

/// ë of every hysteretic element (`Scene::deformation_acceleration`, the rate of a load
/// reversal's function d·ė) against the central difference of ė along q(t ± δ) = q ± δq̇ +
/// δ²q̈/2, q̇(t ± δ) = q̇ ± δq̈, the supports at t ± δ: elements on a point, a rotation and
/// between two frames (keys), bodies on DOFs, driven by the ground in one axis and in both.
#[test]
fn deformation_accelerations_match_finite_differences() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut scenes: Vec<(String, deckspin::scene::Scene)> = [
        "models/four-span.toml",
        "models/four-span-rigid.toml",
        "models/three-frame.toml",
    ]
    .iter()
    .map(|m| (m.to_string(), deckspin::load(&root.join(m), &[]).unwrap()))
    .collect();
    // the backwall's element along x, and along a skew direction that sees the driven y
    for (what, text) in [
        ("backwall", BACKWALL.to_string()),
        (
            "skew backwall",
            BACKWALL.replace("[1.0, 0.0]", "[0.6, 0.8]"),
        ),
    ] {
        let mut wall = deckspin::model::load_str(&text, Path::new("wall.toml"), &[]).unwrap();
        wall.bodies[0].drive = [None, Some(0)];
        scenes.push((what.into(), wall));
    }
    // a fixed sequence in [−1, 1)
    let mut seed = 0x9e3779b97f4a7c15u64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    };
    let mut checked = 0;
    for (name, s) in &scenes {
        let n = s.ndof();
        assert!(!s.hysteretic.is_empty(), "{name}");
        for _ in 0..5 {
            let t = 2.0 + next().abs() * 8.0;
            let q = DVector::from_fn(n, |k, _| 0.02 * next() * if k % 3 == 2 { 0.1 } else { 1.0 });
            let v = DVector::from_fn(n, |_, _| 0.3 * next());
            let a = DVector::from_fn(n, |_, _| 5.0 * next());
            let fr = s.frame(t, &q, &v);
            let d = 1e-5;
            let at = |h: f64| {
                let qh = &q + &v * h + &a * (0.5 * h * h);
                let vh = &v + &a * h;
                s.frame(t + h, &qh, &vh)
            };
            let (plus, minus) = (at(d), at(-d));
            for el in &s.hysteretic {
                let acc = s.deformation_acceleration(&fr, &el.attachment, el.support, a.as_slice());
                let rate = |f: &deckspin::scene::Frame| {
                    s.deformation_rates(f, &el.attachment, el.support).1
                };
                let fd = (rate(&plus) - rate(&minus)) / (2.0 * d);
                assert!(
                    (acc - fd).abs() < 1e-6 * (1.0 + fd.abs()),
                    "{name}, {}: ë {acc} against {fd} by differences at t = {t}",
                    el.name
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 100, "{checked}");
}
