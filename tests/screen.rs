//! Screening (`design::screen`) against the engine: a skewed deck's corner struck alone, over
//! L/B × skew × μ × ε (post-impact velocities to 1e-11 and stick against slide), the model's
//! corners and ends read from bridge files, and the gap-element equivalence grid.
mod common;
use common::*;
use deckspin::design::equivalence::{answers, default_grid, grid};
use deckspin::design::screen::{Flush, model_screen, rectangle_corner, screening_map};
use deckspin::output::EventKind;

/// One contact at the acute (bottom) or obtuse (top) corner of the left end of a rectangle
/// (width 1, length L/B, unit mass, uniform inertia) moving at 1 m/s along −x into the face
/// parallel to its end, 1 cm away.
fn corner_scene(l_over_b: f64, phi: f64, acute: bool, mu: f64, eps: f64) -> String {
    let (hl, hw, tan) = (0.5 * l_over_b, 0.5, phi.tan());
    let (x, y) = if acute {
        (-hl - hw * tan, -hw)
    } else {
        (-hl + hw * tan, hw)
    };
    format!(
        "[solver]\nt_end = 0.02\noutput_dt = 0.01\n\n[[body]]\nname = \"deck\"\nmass = 1.0\n\
         inertia = {:e}\ndofs = [\"x\", \"y\", \"theta\"]\ninitial_velocity = [-1.0, 0.0, 0.0]\n\n\
         [[contact]]\nname = \"corner\"\nbody = \"deck\"\npoint = [{x:e}, {y:e}]\n\
         normal = [{:e}, {:e}]\ngap = 0.01\nmu = {mu}\nrestitution = {eps}\n",
        (l_over_b * l_over_b + 1.0) / 12.0,
        phi.cos(),
        -phi.sin()
    )
}

#[test]
fn a_corner_struck_alone_leaves_as_the_closed_form_says() {
    let (mut cases, mut sticking, mut worst) = (0, 0, 0.0f64);
    for l_over_b in [1.5, 3.0, 13.4] {
        for phi_deg in [0.0f64, 15.0, 35.0, 50.0] {
            for mu in [0.0, 0.2, 0.5, 1.0] {
                for eps in [0.0, 0.5, 1.0] {
                    for acute in [true, false] {
                        let phi = phi_deg.to_radians();
                        let Ok(c) = rectangle_corner(l_over_b, phi, acute, mu, eps) else {
                            panic!("closed form: no answer at L/B {l_over_b}, φ {phi_deg}");
                        };
                        // close to the stick limit either answer is right to rounding
                        if (c.stick_mu - mu).abs() < 1e-6 {
                            continue;
                        }
                        let text = corner_scene(l_over_b, phi, acute, mu, eps);
                        let r = run_text(&text, "corner.toml").unwrap();
                        let hit = r.events.iter().find(|e| e.kind == EventKind::Impact);
                        let hit = hit.expect("an impact");
                        let what =
                            format!("L/B {l_over_b}, φ {phi_deg}°, μ {mu}, ε {eps}, acute {acute}");
                        if mu > 0.0 {
                            assert_eq!(hit.sticks, Some(c.sticks), "stick: {what}");
                        }
                        let post = post_event(&r, hit.t);
                        for d in 0..3 {
                            let (got, want) = (post.v[d], c.velocity_after[d]);
                            let err = (got - want).abs();
                            worst = worst.max(err);
                            assert!(err <= 1e-11, "{what}: q̇⁺[{d}] {got:e} against {want:e}");
                        }
                        cases += 1;
                        sticking += c.sticks as usize;
                    }
                }
            }
        }
    }
    assert!(
        cases > 250 && sticking > 40 && cases - sticking > 40,
        "{cases} cases, {sticking} stick"
    );
    eprintln!("corner impacts: {cases} cases, {sticking} stick, worst |Δq̇⁺| {worst:.1e}");
}

#[test]
fn the_straight_specimen_never_rotates_flush_and_its_corners_stick() {
    let scene = deckspin::load(&model("models/four-span.toml"), &[]).unwrap();
    let (corners, ends) = model_screen(&scene, true);
    assert_eq!(ends.len(), 2, "{ends:?}");
    for e in &ends {
        assert!((e.l_over_b - 32.2 / 2.4).abs() < 1e-12, "{e:?}");
        assert!(
            e.skew_deg.abs() < 1e-12 && e.flush == Flush::Straight,
            "{e:?}"
        );
    }
    // each corner struck alone against a rigid face sticks, |r_x r_y|/(I/m + r_x²) ≤ μ, and
    // the deck spins at θ̇⁺ = m r_y v/(I + m|r|²): the mechanism of the paper's Fig. 6
    let (m, i, rx, ry) = (140.5, 13090.0, 16.1, 1.2);
    assert_eq!(corners.len(), 4);
    for c in &corners {
        let imp = c.impact.as_ref().unwrap();
        assert!(imp.sticks, "{c:?}");
        assert_rel(
            imp.stick_mu,
            rx * ry / (i / m + rx * rx),
            1e-12,
            "μ to stick",
        );
        let spin = m * ry / (i + m * (rx * rx + ry * ry));
        assert_rel(c.spin.abs(), spin, 1e-12, "θ̇⁺ per m/s");
    }
    // against the 0.65 t abutment blocks the corner does not stick: the block is knocked away
    let (blocks, _) = model_screen(&scene, false);
    for c in &blocks {
        let imp = c.impact.as_ref().unwrap();
        assert!(!imp.sticks && imp.stick_mu > 1.0, "{c:?}");
    }
}

#[test]
fn a_skewed_bridge_file_gives_its_skew_and_aspect() {
    let scene = deckspin::load(&model("models/four-span.toml"), &["deck.skew=30".into()]).unwrap();
    let (_, ends) = model_screen(&scene, true);
    assert_eq!(ends.len(), 2);
    for e in &ends {
        assert!((e.skew_deg - 30.0).abs() < 1e-9, "{e:?}");
        // the frame's length is corner to corner along the axis, its width across it
        assert!((e.l_over_b - 32.2 / 2.4).abs() < 1e-9, "{e:?}");
        assert_eq!(
            e.flush,
            deckspin::design::screen::flush_impact(e.l_over_b, 30f64.to_radians(), 0.5, 0.0).0
        );
    }
}

#[test]
fn the_map_marks_all_three_outcomes_where_the_closed_form_puts_them() {
    let lb: Vec<f64> = (0..20).map(|i| 1.0 + i as f64).collect();
    let skew: Vec<f64> = (0..13).map(|i| 5.0 * i as f64).collect();
    let cells = screening_map(&lb, &skew, 0.2, 0.5);
    assert_eq!(cells.len(), 20 * 13);
    // at φ = 0 nothing rotates flush; tan φ ≤ μ(1+ε) = 0.3 sticks; beyond, slides
    for c in &cells {
        let phi = c.skew_deg.to_radians();
        let lhs = if phi.tan() <= 0.3 {
            0.5 * phi.sin() * phi.cos() / 1.5
        } else {
            (phi.sin() - 0.2 * phi.cos()).abs() * phi.cos()
        };
        let expect = if lhs * c.l_over_b <= 1.0 {
            Flush::Straight
        } else if phi.tan() <= 0.3 {
            Flush::RotatesSticking
        } else {
            Flush::RotatesSliding
        };
        assert_eq!(c.flush, expect, "{c:?}");
    }
    for f in [
        Flush::Straight,
        Flush::RotatesSticking,
        Flush::RotatesSliding,
    ] {
        assert!(cells.iter().any(|c| c.flush == f), "{f:?} missing");
    }
}

#[test]
fn soft_gap_elements_miss_the_rotation_stiff_ones_find_it() {
    // a deck's corner strikes a wall: the spin it leaves with is the peak rotation rate
    let text = corner_scene(3.0, 0.0, true, 0.0, 1.0).replace("t_end = 0.02", "t_end = 0.1");
    let path = std::env::temp_dir().join(format!("screen-eq-{}.toml", std::process::id()));
    std::fs::write(&path, &text).unwrap();
    let bench = deckspin::precision::Bench::open(&path, &[]).unwrap();
    let reference = bench.reference(1e-10).unwrap();
    let ks = [1e3, 1e5, 1e7, 1e9];
    let hs = [1e-4, 1e-5];
    let cells = grid(
        &bench,
        &reference,
        deckspin::methods::Method::Penalty,
        &ks,
        &hs,
        &deckspin::progress::Unwatched,
    );
    std::fs::remove_file(&path).ok();
    assert_eq!(cells.len(), 8);
    let err = |k: f64, h: f64| {
        let c = cells.iter().find(|c| c.k == k && c.h == h).unwrap();
        assert!(c.point.is_ok(), "{c:?}");
        c.point.peak_error
    };
    // elastic, frictionless: the gap element's error falls as k^(−1/2) (contact time π√(m/k))
    // while the step resolves the contact; a step as long as the contact misses it
    assert!(err(1e3, 1e-5) > 0.3, "{}", err(1e3, 1e-5));
    let ratio = err(1e5, 1e-5) / err(1e7, 1e-5);
    assert!((7.0..14.0).contains(&ratio), "k^(-1/2): {ratio}");
    assert!(err(1e7, 1e-5) < 0.01, "{}", err(1e7, 1e-5));
    assert!(
        err(1e9, 1e-4) > 0.3,
        "h = 1e-4 s > π√(m/k) = 1e-4 s: {}",
        err(1e9, 1e-4)
    );
    let a = answers(&cells, &[0.05, 0.01]);
    assert_eq!(a[0].cheapest, Some((1e5, 1e-4)), "{a:?}");
    assert_eq!(a[1].cheapest, Some((1e7, 1e-4)), "{a:?}");
    assert_eq!(a[1].largest_step[0], (1e3, None));
    assert_eq!(default_grid(true).0.len(), 3);
}
