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
