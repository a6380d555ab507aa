//! Abutments as a scene needs them: rigid walls moving with the ground, backfill from the
//! SDC's formulas, exterior and interior shear keys that fail, bearings; their bad values.
mod common;
use common::*;
use deckspin::hysteresis::Law;
use deckspin::output::{EventKind, SampleKind};
use deckspin::scene::{Attachment, Scene};

const FOUR_SPAN: &str = "models/four-span.toml";

fn load(rel: &str, set: &[&str]) -> Scene {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    deckspin::load(&model(rel), &set).unwrap_or_else(|e| panic!("{e}"))
}

fn refusal(rel: &str, set: &[&str]) -> String {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    match deckspin::load(&model(rel), &set) {
        Ok(_) => panic!("accepted: {set:?}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn rigid_abutments_move_with_the_ground_and_take_their_stiff_modes_away() {
    let (blocks, walls) = (
        load(FOUR_SPAN, &[]),
        load(FOUR_SPAN, &["abutment.kind=rigid"]),
    );
    assert_eq!((blocks.ndof(), walls.ndof()), (7, 3));
    assert_eq!(walls.dof_names, ["deck.x", "deck.y", "deck.theta"]);
    for (i, side) in [(0, "left"), (2, "right")] {
        let b = &walls.bodies[i];
        assert!(b.dofs.iter().all(Option::is_none));
        let [x, y] = b.drive.map(|s| walls.supports[s.unwrap()].name.clone());
        assert_eq!(
            (x, y),
            (format!("{side}_abutment.x"), format!("{side}_abutment.y"))
        );
    }
    // the shortest period is the deck's own now (the 0.65 t blocks on their actuators: 0.027 s)
    let shortest = |s: &Scene| {
        deckspin::modal::modes(s)
            .iter()
            .map(|m| m.period)
            .fold(f64::INFINITY, f64::min)
    };
    assert!(
        shortest(&blocks) < 0.03 && shortest(&walls) > 0.25,
        "{}",
        shortest(&walls)
    );
    let (rb, rw) = (
        deckspin::run(&blocks, &mut deckspin::Silent).unwrap(),
        deckspin::run(&walls, &mut deckspin::Silent).unwrap(),
    );
    assert!(rw.stats.steps_accepted * 2 < rb.stats.steps_accepted);
    let imp = impacts(&rw);
    assert!(imp.len() > 5, "the deck pounds the walls: {}", imp.len());
    // ε = 0 in the wall's frame: every impact ends with the corner at the wall's speed
    for e in &imp {
        assert!(e.gap_rate_after.abs() < 1e-9, "{e:?}");
        assert!(e.gap_rate_before < 0.0);
    }
    let s = &rw.summary;
    assert!(
        s.energy_closure_rel < 1e-4 && s.max_penetration < 1e-9,
        "{s:?}"
    );
}

#[test]
fn backfill_follows_the_sdc_from_the_backwall_height_width_and_skew() {
    // h = 1.7 m (the SDC's reference height): K = 28.7 kN/mm/m × w, P = 239 kPa × h × w
    for (skew, w) in [(0.0f64, 2.4f64), (30.0, 2.4 / 30f64.to_radians().cos())] {
        let (k, p) = deckspin::model::bridge::caltrans_backfill(1.7, w, skew);
        let r = 8.0e-5 * skew * skew - 0.018 * skew + 1.0;
        assert_rel(k, r * 28.7e3 * w, 1e-14, "backfill stiffness");
        assert_rel(p, r * 239.0 * 1.7 * w, 1e-14, "backfill capacity");
        let skew_set = format!("deck.skew={skew}");
        let s = load(
            FOUR_SPAN,
            &[
                "abutment.kind=backfill",
                "abutment.backwall_height=1.7",
                &skew_set,
            ],
        );
        let halves: Vec<_> = s
            .hysteretic
            .iter()
            .filter(|h| h.name.contains("backfill"))
            .collect();
        assert_eq!(halves.len(), 4);
        for h in halves {
            let Law::Backfill {
                gap,
                stiffness,
                capacity,
            } = *h.law.law()
            else {
                panic!("{}", h.name)
            };
            assert_eq!(gap, 0.0);
            assert_rel(stiffness, 0.5 * k, 1e-14, "half the stiffness");
            assert_rel(capacity, 0.5 * p, 1e-14, "half the capacity");
            let Attachment::Point { direction, .. } = h.attachment else {
                panic!()
            };
            // pushed into the soil: −x behind the left wall, +x behind the right one
            let left = h.name.starts_with("left");
            assert_eq!(direction.x, if left { -1.0 } else { 1.0 });
        }
        // the backwall is free in x and θ, carried in y by the ground
        let wall = &s.bodies[0];
        assert!(wall.dofs[0].is_some() && wall.dofs[1].is_none() && wall.dofs[2].is_some());
        assert!(wall.drive[0].is_none() && wall.drive[1].is_some());
    }
    // Rollins & Jessee's curve at 45°: 8e-5·45² − 0.018·45 + 1 = 0.352
    assert!((deckspin::model::bridge::skew_reduction(45.0) - 0.352).abs() < 1e-12);
}

#[test]
fn a_shear_key_fails_at_its_failure_displacement_and_carries_nothing_after() {
    let key = "abutment.key.gap=0.002";
    let set = [
        key,
        "abutment.key.stiffness=2.0e4",
        "abutment.key.capacity=8.0",
        "abutment.key.failure_displacement=0.004",
    ];
    let text = std::fs::read_to_string(model(FOUR_SPAN))
        .unwrap()
        .replace("seat_width", "# seat_width");
    // the key table, then its values by --set
    let text = text.replace(
        "actuator_offset = 0.9",
        "actuator_offset = 0.9\nkey = { gap = 0.01, stiffness = 1.0, capacity = 1.0, failure_displacement = 2.0 }",
    );
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    let scene = deckspin::model::load_str(&text, &model(FOUR_SPAN), &set).unwrap();
    let keys: Vec<usize> = (0..scene.hysteretic.len())
        .filter(|&j| scene.hysteretic[j].name.contains("_key_"))
        .collect();
    assert_eq!(keys.len(), 4);
    let r = deckspin::run(&scene, &mut deckspin::Silent).unwrap();
    let failures: Vec<_> = r
        .events
        .iter()
        .filter(|e| e.kind == EventKind::KeyFailure)
        .collect();
    assert!(!failures.is_empty(), "the keys fail");
    for f in &failures {
        let j = f.contact;
        assert!(keys.contains(&j));
        let at = |k: SampleKind| {
            r.samples
                .iter()
                .find(|s| s.kind == k && s.t == f.t)
                .unwrap()
        };
        let (pre, post) = (at(SampleKind::PreEvent), at(SampleKind::PostEvent));
        assert_rel(
            pre.elements[j].1,
            8.0,
            1e-12,
            "the key's force at failure: its capacity",
        );
        // located to the event tolerance: within 1e-10 m of gap + failure displacement
        let e = pre.elements[j].0;
        assert!(
            (e - 0.006).abs() < 1e-10,
            "failure at gap + failure displacement: {e}"
        );
        assert_eq!(post.elements[j].1, 0.0);
        for s in r.samples.iter().filter(|s| s.t > f.t) {
            assert_eq!(s.elements[j].1, 0.0, "t = {}", s.t);
        }
    }
    // the summary lists them with their times and peak forces
    let listed = r.summary.key_failures.as_ref().unwrap();
    assert_eq!(listed.len(), failures.len());
    assert!(listed.iter().all(|k| (k.peak_force - 8.0).abs() < 1e-9));
}

#[test]
fn joint_keys_act_between_the_two_frames_along_the_joint_line() {
    let text = std::fs::read_to_string(model("models/three-frame.toml")).unwrap();
    let text = text.replacen(
        "seat_percent = 150.0\n\n[[joint]]",
        "seat_percent = 150.0\nkey = { gap = 0.02, stiffness = 2.0e5, capacity = 1500.0, failure_displacement = 0.05 }\n\n[[joint]]",
        1,
    );
    let scene = deckspin::model::load_str(&text, &model("models/three-frame.toml"), &[]).unwrap();
    let keys: Vec<_> = scene
        .hysteretic
        .iter()
        .filter(|h| h.name.starts_with("joint1_key"))
        .collect();
    assert_eq!(keys.len(), 2);
    let m = (-30.0f64).to_radians();
    for (k, sign) in keys.iter().zip([1.0, -1.0]) {
        let Attachment::Relative {
            body,
            other,
            direction,
            point,
            other_point,
        } = k.attachment
        else {
            panic!()
        };
        assert_eq!((body, other), (1, 2));
        // along the joint line t = m turned +90°, m = (cos −30°, sin −30°)
        assert!(
            (direction.x - sign * -m.sin()).abs() < 1e-15
                && (direction.y - sign * m.cos()).abs() < 1e-15
        );
        // the same world point on both frames at the reference configuration
        let (a, b) = (
            scene.bodies[1].reference + point,
            scene.bodies[2].reference + other_point,
        );
        assert!((a - b).norm() < 1e-12);
    }
}

#[test]
fn bad_abutment_kinds_keys_and_bearings_are_refused_with_their_fields() {
    for (set, want) in [
        (
            vec!["abutment.kind=wall"],
            "abutment.kind: unknown abutment kind 'wall'",
        ),
        (
            vec!["abutment.kind=backfill"],
            "abutment.backwall_height: required for abutment kind = \"backfill\"",
        ),
        (
            vec!["abutment.kind=backfill", "abutment.backwall_height=-1"],
            "abutment.backwall_height: must be > 0",
        ),
    ] {
        let e = refusal(FOUR_SPAN, &set);
        assert!(e.contains(want), "{e}");
    }
    let text = std::fs::read_to_string(model(FOUR_SPAN)).unwrap();
    let with = |line: &str| {
        text.replace(
            "actuator_offset = 0.9",
            &format!("actuator_offset = 0.9\n{line}"),
        )
    };
    let line_of =
        |t: &str, needle: &str| t.lines().position(|l| l.starts_with(needle)).unwrap() + 1;
    for (line, field) in [
        (
            "key = { gap = 0.01, stiffness = 1e4, capacity = -5.0, failure_displacement = 0.1 }",
            "abutment.key.capacity",
        ),
        (
            "key = { gap = 0.01, stiffness = 1e4, capacity = 500.0, failure_displacement = 0.01 }",
            "abutment.key.failure_displacement",
        ),
        (
            "bearing = { law = \"key\", gap = 0.0, stiffness = 1.0, capacity = 1.0, failure_displacement = 2.0 }",
            "abutment.bearing",
        ),
        (
            "bearing = { law = \"bilinear\", stiffness = 1e4, yield_force = -1.0, post_yield_ratio = 0.0 }",
            "abutment.bearing",
        ),
    ] {
        let t = with(line);
        let e = deckspin::model::load_str(&t, &model(FOUR_SPAN), &[])
            .unwrap_err()
            .to_string();
        let want = format!(
            "four-span.toml:{}: {field}: ",
            line_of(&t, line.split(' ').next().unwrap())
        );
        assert!(e.contains(&want), "{e}\nwanted {want}");
    }
    // a rigid wall does not read the block's fields: said, not silently ignored
    let l =
        deckspin::model::load_checked(&model(FOUR_SPAN), &["abutment.kind=rigid".into()]).unwrap();
    let said: Vec<String> = l.warnings.iter().map(|w| w.to_string()).collect();
    assert!(
        said.iter()
            .any(|w| w.contains("abutment.mass: not read by abutment kind = \"rigid\"")),
        "{said:?}"
    );
}

/// Every gap element of the three-frame example (backfill, exterior and joint keys) stays on
/// its law at every sample: 0 ≤ f ≤ capacity (a crossing of a branch bound is never missed).
#[test]
fn the_three_frame_examples_keys_and_backfill_never_leave_their_laws() {
    let scene = load("models/three-frame.toml", &[]);
    let r = deckspin::run(&scene, &mut deckspin::Silent).unwrap();
    let mut checked = 0;
    for (j, el) in scene.hysteretic.iter().enumerate() {
        let cap = match *el.law.law() {
            Law::Key { capacity, .. } | Law::Backfill { capacity, .. } => capacity,
            _ => continue,
        };
        let peak = r
            .samples
            .iter()
            .map(|s| s.elements[j].1)
            .fold(0.0, f64::max);
        let low = r
            .samples
            .iter()
            .map(|s| s.elements[j].1)
            .fold(0.0, f64::min);
        // a closing located to the event tolerance leaves at most k·1e-12 m of tension
        let ok = low >= -1e-8 * cap && peak <= cap * (1.0 + 1e-12);
        assert!(ok, "{}: {low} … {peak} (capacity {cap})", el.name);
        checked += 1;
    }
    assert_eq!(
        checked,
        4 + 4 + 4,
        "backfill halves, exterior keys, joint keys"
    );
}

/// A key that fails while a corner slides on its backwall (the three-frame example under
/// Hector Mine, μ = 0.2: the right exterior key at 5.025 s, the left corner `left_bottom` in
/// slide): its pre- and post-event samples are on the closed constraints (|g_N| ≤ 1e-4 gap_tol,
/// ġ_N = 0 to `velocity_tol`), and after the force's jump every closed contact holds λ_N ≥ 0,
/// |λ_T| ≤ μ λ_N (the contact LCP, eq. 8–10, decided anew). Before, the pre-event sample was the
/// dense output's state, 4.95e-8 m inside the backwall.
#[test]
fn a_key_failing_while_a_corner_slides_leaves_the_corner_on_its_face() {
    let rec = |c: &str| {
        let p = model(&format!("excitations/far-field/HECTOR_HEC{c}.AT2"));
        p.to_string_lossy().to_string()
    };
    let (l, t) = (rec("000"), rec("090"));
    let set = [
        format!("excitation.longitudinal={l}"),
        format!("excitation.transverse={t}"),
        "contacts.mu=0.2".to_string(),
        "solver.t_end=5.1".to_string(),
    ];
    let set: Vec<&str> = set.iter().map(|s| s.as_str()).collect();
    let scene = load("models/three-frame.toml", &set);
    let r = deckspin::run(&scene, &mut deckspin::Silent).unwrap();
    let st = &scene.settings;
    let failures: Vec<f64> = (r.events.iter())
        .filter(|e| e.kind == EventKind::KeyFailure)
        .map(|e| e.t)
        .collect();
    assert!(!failures.is_empty(), "no key failed");
    let mut closed_seen = 0;
    for s in r.samples.iter().filter(|s| failures.contains(&s.t)) {
        for (i, c) in s.contacts.iter().enumerate() {
            if c.state == deckspin::output::ContactState::Open {
                continue;
            }
            closed_seen += 1;
            let name = &scene.contacts[i].name;
            assert!(
                c.gap.abs() <= 1e-4 * st.gap_tol,
                "{name} at {}: g_N {:e}",
                s.t,
                c.gap
            );
            assert!(
                c.gap_rate.abs() <= st.velocity_tol,
                "{name}: ġ_N {:e}",
                c.gap_rate
            );
            if s.kind == SampleKind::PostEvent {
                let mu = scene.contacts[i].law.mu;
                assert!(c.normal_force >= 0.0, "{name}: λ_N {}", c.normal_force);
                let excess = c.tangential_force.abs() - mu * c.normal_force;
                assert!(
                    excess <= 1e-9 * c.normal_force,
                    "{name}: |λ_T| − μλ_N = {excess:e}"
                );
            }
        }
    }
    assert!(closed_seen >= 2, "no closed contact at a key failure");
    assert!(
        r.summary.max_penetration <= 1e-4 * st.gap_tol,
        "{:e}",
        r.summary.max_penetration
    );
}

/// An impact located on the dense output just before an output instant and moved along the
/// flow onto the face just after it (rigid abutments, run 6, ε = 0.5, μ = 0.1: the event at
/// 4.2100053 s, the instant 4.21 s): the instant is sampled before the event, on the move.
/// Before, it was sampled after the event, on the next step's dense output taken backwards
/// through the impact: 1.14e-6 m inside the face, out of time order, and the run failed
/// `solver.max_penetration`.
#[test]
fn an_output_instant_that_a_moved_impact_passes_is_sampled_before_the_impact() {
    let set = [
        "excitation.run=6",
        "contacts.restitution=0.5",
        "contacts.mu=0.1",
        "solver.t_end=4.3",
    ];
    let scene = load("models/four-span-rigid.toml", &set);
    let r = deckspin::run(&scene, &mut deckspin::Silent).unwrap();
    let (te, tg) = (4.210005337839962, 4.21);
    assert!(
        (r.events.iter()).any(|e| e.kind == EventKind::Impact && (e.t - te).abs() < 1e-9),
        "the impact moved"
    );
    for w in r.samples.windows(2) {
        assert!(
            w[1].t >= w[0].t,
            "samples out of order: {} then {}",
            w[0].t,
            w[1].t
        );
    }
    let grid = (r.samples.iter())
        .position(|s| s.kind == SampleKind::Grid && (s.t - tg).abs() < 1e-12)
        .unwrap();
    let impact = (r.samples.iter())
        .position(|s| s.kind == SampleKind::PreEvent && (s.t - te).abs() < 1e-9)
        .unwrap();
    assert!(grid < impact, "the instant after the impact");
    assert!(
        r.summary.max_penetration <= 1e-4 * scene.settings.gap_tol,
        "{:e}",
        r.summary.max_penetration
    );
}
