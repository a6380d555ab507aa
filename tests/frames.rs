//! Bridges of several frames: the one-frame file is the specimen, layout of skewed and curved
//! frames, joints that never pound and joints that pound as the impact law says, and the flush
//! impact of a skewed deck against its closed-form rotation condition.
mod common;
use common::*;
use deckspin::output::{EventKind, RunOutput, SampleKind};
use deckspin::scene::Scene;
use std::path::Path;

fn four_span() -> String {
    std::fs::read_to_string(model("models/four-span.toml")).unwrap()
}

/// The specimen file with its `[deck]` and `[[bent]]` rewritten as one `[[frame]]`.
fn as_one_frame(text: &str) -> String {
    let mut doc: toml_edit::DocumentMut = text.parse().unwrap();
    let deck = doc.remove("deck").unwrap();
    let bents = doc.remove("bent").unwrap();
    let mut frame = deck.into_table().unwrap();
    frame.insert("name", toml_edit::value("deck"));
    frame.insert("bent", bents);
    let mut frames = toml_edit::ArrayOfTables::new();
    frames.push(frame);
    doc.insert("frame", toml_edit::Item::ArrayOfTables(frames));
    doc.to_string()
}

fn load_text(text: &str, set: &[&str]) -> Scene {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    let models = model("models");
    deckspin::model::load_str(text, &models.join("t.toml"), &set).unwrap_or_else(|e| panic!("{e}"))
}

fn simulate(scene: &Scene) -> RunOutput {
    deckspin::run(scene, &mut deckspin::Silent).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn the_one_frame_file_is_the_specimen_bit_for_bit() {
    let deck = load_text(&four_span(), &[]);
    let frame = load_text(&as_one_frame(&four_span()), &[]);
    assert_eq!(deck.dof_names, frame.dof_names);
    let (a, b) = (simulate(&deck), simulate(&frame));
    assert!(
        a.stats.impacts > 20,
        "the specimen pounds: {}",
        a.stats.impacts
    );
    assert_eq!(a.samples.len(), b.samples.len());
    for (x, y) in a.samples.iter().zip(&b.samples) {
        assert_eq!(x.t.to_bits(), y.t.to_bits());
        for (p, q) in x.q.iter().zip(&y.q).chain(x.v.iter().zip(&y.v)) {
            assert_eq!(p.to_bits(), q.to_bits(), "t = {}", x.t);
        }
    }
    assert_eq!(a.events.len(), b.events.len());
}

/// Two frames of the specimen's deck in series, joint between them; `extra` appended.
fn two_frames(heights: [f64; 2], joint: &str, extra: &str) -> String {
    let frame = |name: &str, h: f64| {
        format!(
            "[[frame]]\nname = \"{name}\"\nmass = 70.0\ninertia = 3000.0\nlength = 16.0\n\
             width = 2.4\n\n[[frame.bent]]\nname = \"{name}_bent\"\nx = 0.0\nheight = {h}\n\n"
        )
    };
    format!(
        "title = \"two frames\"\n{}{}[[joint]]\n{joint}\n\n[abutment]\nmass = 0.65\n\
         inertia = 0.31\nactuator_stiffness = 1.0e4\nactuator_offset = 0.9\n\n[contacts]\n\
         enabled = false\nmu = 0.5\nrestitution = 0.0\ngaps = [0.01, 0.01, 0.01, 0.01]\n\n\
         [column]\nlaw = {{ law = \"linear\", stiffness = 4000.0 }}\nreference_height = 2.0\n\
         offset = 0.75\ntorsion_stiffness = 1000.0\n\n[damping]\nratio = 0.02\nmodes = [1, 3]\n\n\
         [excitation]\nkind = \"harmonic\"\namplitude_x = 0.03\namplitude_y = 0.02\n\
         frequency = 1.5\n\n[solver]\nt_end = 4.0\noutput_dt = 0.01\n{extra}",
        frame("west", heights[0]),
        frame("east", heights[1])
    )
}

#[test]
fn identical_frames_driven_identically_never_pound() {
    let text = two_frames([2.0, 2.0], "gaps = [0.002, 0.002]", "");
    let r = simulate(&load_text(&text, &[]));
    assert!(
        r.events.is_empty(),
        "{:?}",
        &r.events[..r.events.len().min(3)]
    );
    let (wx, ex) = (r.dof("west.x").unwrap(), r.dof("east.x").unwrap());
    let peak = r.samples.iter().map(|s| s.q[wx].abs()).fold(0.0, f64::max);
    assert!(peak > 0.02, "the frames move: {peak}");
    // the same motion up to the rounding of positions 16 m apart
    for s in &r.samples {
        assert!((s.q[wx] - s.q[ex]).abs() < 1e-13, "t = {}", s.t);
        for c in &s.contacts {
            assert!((c.gap - 0.002).abs() < 1e-13, "t = {}: {}", s.t, c.gap);
        }
    }
}

/// M⁻¹-weighted products of two generalized directions over the DOFs of two bodies.
fn delassus(a: &[f64; 6], b: &[f64; 6], minv: &[f64; 6]) -> f64 {
    (0..6).map(|i| a[i] * minv[i] * b[i]).sum()
}

fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

fn rot(t: f64, r: [f64; 2]) -> [f64; 2] {
    let (s, c) = t.sin_cos();
    [c * r[0] - s * r[1], s * r[0] + c * r[1]]
}

/// One corner of frame A hits the face of frame B: Newton's law ġ_N⁺ = −ε ġ_N⁻ and Coulomb on
/// impulses, solved in closed form (stick if |Λ_T| ≤ μ Λ_N, else slide against ġ_T).
fn joint_impact(
    w_n: &[f64; 6],
    w_t: &[f64; 6],
    minv: &[f64; 6],
    g: [f64; 2],
    mu: f64,
    eps: f64,
) -> (f64, f64) {
    let (nn, nt, tt) = (
        delassus(w_n, w_n, minv),
        delassus(w_n, w_t, minv),
        delassus(w_t, w_t, minv),
    );
    let (bn, bt) = (-(1.0 + eps) * g[0], -g[1]);
    let det = nn * tt - nt * nt;
    let (pn, pt) = ((bn * tt - nt * bt) / det, (nn * bt - nt * bn) / det);
    if pn >= 0.0 && pt.abs() <= mu * pn {
        return (pn, pt);
    }
    let s = g[1].signum();
    let pn = bn / (nn - mu * s * nt);
    (pn, -mu * s * pn)
}

#[test]
fn frames_of_different_periods_pound_and_exchange_momentum_as_the_impact_law_says() {
    let (mut worst_impulse, mut worst_dv, mut worst_momentum) = (0.0f64, 0.0f64, 0.0f64);
    for (mu, eps) in [(0.5, 0.0), (0.2, 0.6), (0.0, 1.0)] {
        let joint = format!("gaps = [0.004, 0.006]\nmu = {mu}\nrestitution = {eps}\nskew = 12.0");
        let text = two_frames([1.5, 2.8], &joint, "");
        let scene = load_text(&text, &[]);
        let r = simulate(&scene);
        let first = r
            .events
            .iter()
            .find(|e| e.kind == EventKind::Impact)
            .expect("the frames pound");
        assert!(
            !r.events
                .iter()
                .any(|e| e.t == first.t && e.contact != first.contact),
            "a single-corner impact"
        );
        let at = |k: SampleKind| {
            r.samples
                .iter()
                .find(|s| s.kind == k && s.t == first.t)
                .unwrap()
        };
        let (pre, post) = (at(SampleKind::PreEvent), at(SampleKind::PostEvent));
        let c = &scene.contacts[first.contact];
        // frames are bodies 1 and 2, DOFs 2..5 and 5..8
        let (a, b) = (&scene.bodies[1], &scene.bodies[2]);
        let (qa, qb) = (&pre.q[2..5], &pre.q[5..8]);
        let xa = [a.reference.x + qa[0], a.reference.y + qa[1]];
        let xb = [b.reference.x + qb[0], b.reference.y + qb[1]];
        let rho_a = rot(qa[2], [c.point.x, c.point.y]);
        let p = [xa[0] + rho_a[0], xa[1] + rho_a[1]];
        let n = rot(qb[2], [c.face_normal.x, c.face_normal.y]);
        let t = [n[1], -n[0]];
        let rho_b = [p[0] - xb[0], p[1] - xb[1]];
        let w = |d: [f64; 2]| [d[0], d[1], cross(rho_a, d), -d[0], -d[1], -cross(rho_b, d)];
        let (w_n, w_t) = (w(n), w(t));
        let v: Vec<f64> = pre.v[2..8].to_vec();
        let rate = |w: &[f64; 6]| (0..6).map(|i| w[i] * v[i]).sum::<f64>();
        let g = [rate(&w_n), rate(&w_t)];
        assert!(g[0] < 0.0, "approaching: {g:?}");
        let minv = [
            1.0 / a.mass,
            1.0 / a.mass,
            1.0 / a.inertia,
            1.0 / b.mass,
            1.0 / b.mass,
            1.0 / b.inertia,
        ];
        let (pn, pt) = joint_impact(&w_n, &w_t, &minv, g, mu, eps);
        assert_rel(first.normal, pn, 1e-12, "normal impulse");
        worst_impulse = worst_impulse.max(rel(first.normal, pn));
        assert!(
            (first.tangential - pt).abs() <= 1e-12 * pn,
            "{} vs {pt}",
            first.tangential
        );
        for i in 0..6 {
            let dv = minv[i] * (w_n[i] * pn + w_t[i] * pt);
            let got = post.v[2 + i] - pre.v[2 + i];
            assert!(
                (got - dv).abs() <= 1e-12 * dv.abs().max(1e-6),
                "dof {i}: {got} vs {dv}"
            );
            worst_dv = worst_dv.max((got - dv).abs() / dv.abs().max(1e-6));
        }
        // the two frames' linear momentum is unchanged by their impact
        for k in 0..2 {
            let p = |s: &[f64]| a.mass * s[2 + k] + b.mass * s[5 + k];
            let drift = (p(&post.v) - p(&pre.v)).abs() / (a.mass * pre.v[2 + k].abs().max(1e-3));
            assert!(drift < 1e-10, "momentum {k}: {drift:e}");
            worst_momentum = worst_momentum.max(drift);
        }
    }
    eprintln!(
        "joint impacts: normal impulse {worst_impulse:.1e}, Δv {worst_dv:.1e}, momentum \
         {worst_momentum:.1e} (relative, worst of three)"
    );
}

/// Three frames, skewed supports, a curved alignment: at q = 0 every corner's gap is the one
/// given, each end lies flush on its support line, and the joint line bisects the frames.
#[test]
fn skewed_and_curved_frames_start_at_their_gaps_with_flush_ends() {
    let text = std::fs::read_to_string(model("models/three-frame.toml")).unwrap();
    for set in [
        vec![],
        vec![
            "frame.1.heading=8",
            "frame.2.heading=16",
            "joint.1.skew=-5",
            "abutment.right_skew=0",
        ],
    ] {
        let scene = load_text(&text, &set);
        let fr = scene.frame(0.0, &scene.q0, &scene.v0);
        let gaps = [0.05, 0.05, 0.05, 0.05, 0.025, 0.025, 0.025, 0.025];
        let mut points = Vec::new();
        for (c, g) in scene.contacts.iter().zip(gaps) {
            let k = scene.contact_kinematics(&fr, c);
            assert!((k.gap - g).abs() < 1e-14, "{}: {} vs {g}", c.name, k.gap);
            points.push((k.point, k.normal));
        }
        for pair in points.chunks(2) {
            let ((p, n), (q, _)) = (pair[0], pair[1]);
            assert!(n.dot(&(p - q)).abs() < 1e-12, "flush end");
        }
        if !set.is_empty() {
            // joint 1: between headings 0 and 8°, skew 30°: m at 4° − 30°
            let n = points[4].1;
            let want = (4.0f64 - 30.0).to_radians();
            assert!((n.x + want.cos()).abs() < 1e-15 && (n.y + want.sin()).abs() < 1e-15);
        }
    }
}

/// The closed form (`design::screen::flush_impact`): whether the deck rotates after a flush
/// impact, and how far from the boundary.
fn rotates(l_over_b: f64, phi: f64, mu: f64, eps: f64) -> (bool, f64) {
    use deckspin::design::screen::{Flush, flush_impact};
    let (f, margin) = flush_impact(l_over_b, phi, mu, eps);
    (f != Flush::Straight, margin)
}

#[test]
fn a_skewed_deck_hitting_a_parallel_face_flush_rotates_as_the_closed_form_says() {
    let (mut tried, mut rotating) = (0, 0);
    let (mut still_max, mut spin_min) = (0.0f64, f64::INFINITY);
    for l_over_b in [1.5, 3.0, 13.4] {
        for phi_deg in [10.0f64, 25.0, 40.0, 55.0] {
            for mu in [0.0, 0.2, 0.5, 1.0] {
                for eps in [0.0, 0.5, 1.0] {
                    let phi = phi_deg.to_radians();
                    let (expect, margin) = rotates(l_over_b, phi, mu, eps);
                    if margin < 0.05 {
                        continue;
                    }
                    let (l, b) = (10.0, 10.0 / l_over_b);
                    let (hl, hw, tan) = (l / 2.0, b / 2.0, phi.tan());
                    let n = [phi.cos(), -phi.sin()];
                    let corner = |name: &str, x: f64, y: f64| {
                        format!(
                            "[[contact]]\nname = \"{name}\"\nbody = \"deck\"\npoint = [{x:e}, {y:e}]\n\
                             normal = [{:e}, {:e}]\ngap = 0.01\nmu = {mu}\nrestitution = {eps}\n\n",
                            n[0], n[1]
                        )
                    };
                    let text = format!(
                        "[solver]\nt_end = 0.2\noutput_dt = 0.1\n\n[[body]]\nname = \"deck\"\n\
                         mass = 1.0\ninertia = {:e}\ndofs = [\"x\", \"y\", \"theta\"]\n\
                         initial_velocity = [-1.0, 0.0, 0.0]\n\n{}{}",
                        (l * l + b * b) / 12.0,
                        corner("top", -hl + hw * tan, hw),
                        corner("bottom", -hl - hw * tan, -hw),
                    );
                    let scene =
                        deckspin::model::load_str(&text, Path::new("skew.toml"), &[]).unwrap();
                    let r = simulate(&scene);
                    let hit = r
                        .events
                        .iter()
                        .find(|e| e.kind == EventKind::Impact)
                        .unwrap();
                    let post = post_event(&r, hit.t);
                    let spin = post.v[2].abs() * l;
                    let what =
                        format!("L/B {l_over_b}, φ {phi_deg}°, μ {mu}, ε {eps}: θ̇ L = {spin:e}");
                    if expect {
                        assert!(spin > 1e-4, "should rotate: {what}");
                        rotating += 1;
                        spin_min = spin_min.min(spin);
                    } else {
                        assert!(spin < 1e-12, "should not rotate: {what}");
                        still_max = still_max.max(spin);
                    }
                    tried += 1;
                }
            }
        }
    }
    assert!(
        tried > 100 && rotating > 20 && tried - rotating > 20,
        "{tried} cases, {rotating} rotate"
    );
    eprintln!(
        "flush skew impacts: {tried} cases, {rotating} rotate (smallest θ̇L {spin_min:.2e} m/s), \
         the others at most {still_max:.2e} m/s"
    );
}

fn three_frame() -> String {
    std::fs::read_to_string(model("models/three-frame.toml")).unwrap()
}

/// The error of loading `text` (named three-frame.toml in models/).
fn refusal(text: &str, set: &[&str]) -> String {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    let path = model("models/three-frame.toml");
    match deckspin::model::load_str(text, &path, &set) {
        Ok(_) => panic!("accepted: {set:?}"),
        Err(e) => e.to_string(),
    }
}

fn line_of(text: &str, needle: &str, nth: usize) -> usize {
    text.lines()
        .enumerate()
        .filter(|(_, l)| l.starts_with(needle))
        .nth(nth)
        .unwrap_or_else(|| panic!("{needle}"))
        .0
        + 1
}

#[test]
fn every_bad_value_of_the_frame_and_joint_tables_is_refused_with_its_line() {
    let t = three_frame();
    let at = |needle: &str, nth: usize, field: &str| {
        format!("three-frame.toml:{}: {field}: ", line_of(&t, needle, nth))
    };
    // values in the file: each error names the line of the value
    let cases: Vec<(String, String)> = vec![
        (
            t.replacen("mass = 840.0", "mass = -840.0", 1),
            at("mass = 840.0", 0, "frame.1.mass"),
        ),
        (
            t.replacen("width = 12.0", "width = 1.0", 1),
            at("offset = 3.0", 0, "column.offset"),
        ),
        (
            t.replacen("x = 17.5", "x = 36.0", 1),
            at("x = 17.5", 0, "frame.1.bent.1.x"),
        ),
        (
            t.replacen("height = 9.0", "height = 0.0", 1),
            at("height = 9.0", 0, "frame.1.bent.1.height"),
        ),
        (
            t.replacen("gaps = [0.025, 0.025]", "gaps = [0.025, -0.01]", 1),
            at("gaps = [0.025", 0, "joint.0.gaps.1"),
        ),
        (
            t.replacen("seat_width = 0.60", "seat_width = 0.0", 1),
            at("seat_width = 0.60", 0, "joint.0.seat_width"),
        ),
        (
            t.replacen("skew = 30.0", "skew = 75.0", 1),
            at("skew = 30.0", 0, "frame.0.skew"),
        ),
        (
            t.replacen("name = \"frame2\"", "name = \"frame1\"", 1),
            at("name = \"frame2\"", 0, "frame.1.name"),
        ),
    ];
    for (text, want) in &cases {
        let e = refusal(text, &[]);
        assert!(e.contains(&format!("/{want}")), "{e}\nwanted {want}");
    }
    // --set: the argument is named
    for (set, field) in [
        ("joint.1.mu=-0.1", "joint.1.mu"),
        ("joint.0.restitution=1.5", "joint.0.restitution"),
        ("joint.0.skew=61", "joint.0.skew"),
        ("abutment.left_skew=-70", "abutment.left_skew"),
        ("frame.2.heading=50", "frame.2.heading"),
        ("frame.0.inertia=0", "frame.0.inertia"),
    ] {
        let e = refusal(&t, &[set]);
        assert!(e.starts_with(&format!("--set {set}: {field}: ")), "{e}");
    }
    // tables: one joint too few, three gaps, frames beside a [deck], bents outside frames
    let mut doc: toml_edit::DocumentMut = t.parse().unwrap();
    doc["joint"].as_array_of_tables_mut().unwrap().remove(1);
    let fewer = doc.to_string();
    let e = refusal(&fewer, &[]);
    assert!(
        e.contains(": joint: 1 [[joint]] tables for 3 frames"),
        "{e}"
    );
    let e = refusal(
        &t.replacen("gaps = [0.025, 0.025]", "gaps = [0.025, 0.025, 0.02]", 1),
        &[],
    );
    assert!(
        e.contains("expected 2 joint gaps")
            && e.contains(&format!(":{}:", line_of(&t, "gaps = [0.025", 0))),
        "{e}"
    );
    let e = refusal(
        &format!("{t}\n[deck]\nmass = 1.0\ninertia = 1.0\nlength = 1.0\nwidth = 1.0\n"),
        &[],
    );
    assert!(
        e.contains(": frame: give either [deck] (one frame) or [[frame]] tables, not both"),
        "{e}"
    );
    let e = refusal(
        &format!("{t}\n[[bent]]\nname = \"b\"\nx = 0.0\nheight = 1.0\n"),
        &[],
    );
    assert!(
        e.contains(": bent: with [[frame]] tables each frame lists its own bents"),
        "{e}"
    );
}

#[test]
fn history_has_each_seats_margin_over_time() {
    let scene = load_text(&three_frame(), &["solver.t_end=6"]);
    let r = simulate(&scene);
    let dir = std::env::temp_dir().join(format!("deckspin-seat-margin-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("history.csv");
    r.write_history(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| head.iter().position(|h| *h == n).unwrap();
    let (gap, margin) = (col("joint1_top.gap"), col("joint1_top.seat_margin"));
    let (agap, amargin) = (col("left_bottom.gap"), col("left_bottom.seat_margin"));
    let mut rows = 0;
    let mut smallest = f64::INFINITY;
    for l in lines {
        let v: Vec<&str> = l.split(',').collect();
        let x = |i: usize| v[i].parse::<f64>().unwrap();
        // margin = seat width − (g_N − g_N(0)), rotation included in g_N
        assert!((x(margin) - (0.60 - (x(gap) - 0.025))).abs() < 1e-12);
        assert!((x(amargin) - (0.75 - (x(agap) - 0.05))).abs() < 1e-12);
        smallest = smallest.min(x(margin));
        rows += 1;
    }
    assert!(
        rows > 600 && smallest < 0.6 - 1e-3,
        "{rows} rows, smallest {smallest}"
    );
    let listed = r
        .summary
        .seats
        .iter()
        .find(|s| s.contact == "joint1_top")
        .unwrap();
    assert!(
        (listed.min_margin - smallest).abs() < 1e-12,
        "{} vs {smallest}",
        listed.min_margin
    );
}

/// A joint given no gap between skewed frames is closed, not a gap of rounding size to be
/// resolved: its initial gap (3.1e-15 m, the pose arithmetic's rounding at 30° skew) is left
/// out of the check that tolerances resolve the smallest gap, which refused the file asking
/// for atol ≤ 3e-18. A joint's gap of 1 µm is still a gap, and refused at atol 1e-7.
#[test]
fn a_joint_without_a_gap_between_skewed_frames_is_closed_not_refused() {
    let path = model("models/three-frame.toml");
    let load = |set: &[&str]| {
        let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
        deckspin::load(&path, &set)
    };
    let scene = load(&["joint.0.gaps=[0,0]", "solver.t_end=6"]).unwrap_or_else(|e| panic!("{e}"));
    let fr = scene.frame(0.0, &scene.q0, &scene.v0);
    let gap = |name: &str| {
        let c = scene.contacts.iter().find(|c| c.name == name).unwrap();
        scene.contact_kinematics(&fr, c).gap
    };
    let g = gap("joint1_bottom");
    assert!(g != 0.0 && g.abs() < 1e-13, "{g:e}");
    let r = deckspin::run(&scene, &mut deckspin::Silent).unwrap();
    // within the gap's event threshold (1e-3 gap_tol): an impact's located state is no deeper
    assert!(
        r.summary.max_penetration <= 1e-3 * scene.settings.gap_tol,
        "{:e}",
        r.summary.max_penetration
    );
    assert!(r.summary.stats.impacts > 0);
    let msg = load(&["joint.0.gaps=[1e-6,1e-6]"]).unwrap_err().to_string();
    assert!(
        msg.contains(
            "solver.atol: 0.0000001 is above 1e-3 × the smallest initial gap (1.0000e-6 m"
        ),
        "{msg}"
    );
}
