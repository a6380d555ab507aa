//! A free block sliding into a compression-only gap element (shear key, backfill) fixed to the
//! ground: contact time, key failure instant, exit and rebound velocities and permanent set
//! against their closed forms, through the full engine.
mod common;
use common::*;
use deckspin::output::{EventKind, KeyFailure, SampleKind, events_csv};
use std::path::Path;

/// Block mass, approach speed, gap, stiffness (ω = √(k/m) = 20 rad/s, √(k m) = 40).
const M: f64 = 2.0;
const V0: f64 = 1.0;
const GAP: f64 = 0.05;
const K: f64 = 800.0;
const T_END: f64 = 0.5;

/// Fixed step of Moreau–Jean and the penalty methods, s.
const H: f64 = 1e-4;

fn scene(law: &str, method: &str) -> String {
    format!(
        r#"
title = "block into a gap element"
[solver]
method = "{method}"
t_end = {T_END}
rtol = 1e-12
atol = 1e-14
step = {H}
output_dt = 0.01
[[body]]
name = "block"
mass = {M}
dofs = ["x"]
initial_velocity = [{V0}, 0.0, 0.0]
[[hysteretic]]
name = "key"
body = "block"
direction = [1.0, 0.0]
law = {{ {law} }}
"#
    )
}

fn key_law(capacity: f64, failure_displacement: f64) -> String {
    format!(
        r#"law = "key", gap = {GAP}, stiffness = {K}, capacity = {capacity}, failure_displacement = {failure_displacement}"#
    )
}

/// The run of the method the scene names, judged (energy closure, penetration).
fn run_scene(law: &str, method: &str) -> deckspin::RunOutput {
    let text = scene(law, method);
    let scene = deckspin::model::load_str(&text, Path::new("gap-element.toml"), &[])
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.settings.method.name(), method);
    deckspin::simulate(&scene, &mut deckspin::Silent).unwrap_or_else(|e| panic!("{method}: {e}"))
}

/// ω, and the elastic stretch: the capacity is reached at sin(ω τ₁) = f_c/(v₀√(km)), with
/// v₁² = v₀² − f_c²/(k m) left; then the block decelerates at f_c/m.
fn elastic_then_plastic(fc: f64) -> (f64, f64, f64) {
    let w = (K / M).sqrt();
    let tau1 = (fc / (V0 * (K * M).sqrt())).asin() / w;
    let v1 = (V0 * V0 - fc * fc / (K * M)).sqrt();
    (w, tau1, v1)
}

fn last(r: &deckspin::RunOutput) -> &deckspin::output::Sample {
    r.samples.last().unwrap()
}

#[test]
fn block_rebounds_elastically_from_a_strong_key_after_half_a_period() {
    // f_c = 100 > v₀√(km) = 40: elastic throughout; contact from GAP/v₀ for π√(m/k), out at −v₀
    let r = run_scene(&key_law(100.0, 0.5), "event");
    let w = (K / M).sqrt();
    let t_out = GAP / V0 + std::f64::consts::PI / w;
    let s = last(&r);
    assert_rel(s.v[0], -V0, 1e-10, "rebound velocity");
    // after t_out the block moves freely from the gap at −v₀: x(T) = GAP − v₀ (T − t_out)
    let t_out_seen = T_END - (GAP - s.q[0]) / V0;
    assert_rel(t_out_seen, t_out, 1e-10, "end of contact");
    // peak force v₀√(km) = 40 at the middle of the contact, never tension
    let peak = r
        .samples
        .iter()
        .map(|s| s.elements[0].1)
        .fold(0.0, f64::max);
    assert!(peak <= 40.0 * (1.0 + 1e-12) && peak > 30.0, "{peak}");
    assert!(r.samples.iter().all(|s| s.elements[0].1 >= -1e-9));
    assert!(r.events.is_empty());
    assert_eq!(r.summary.key_failures, Some(Vec::new()));
    let json = serde_json::to_string(&r.summary).unwrap();
    assert!(json.contains(r#""key_failures":[]"#), "{json}");
    // the count of failures is left out of the stats while 0
    assert!(!json.contains(r#""key_failures":0"#), "{json}");
}

#[test]
fn key_fails_at_the_closed_form_instant_and_the_block_leaves_at_the_closed_form_speed() {
    let (fc, df) = (20.0, 0.04);
    let (_, tau1, v1) = elastic_then_plastic(fc);
    // plateau: from GAP + f_c/k to GAP + δ_f at deceleration a = f_c/m
    let a = fc / M;
    let s_plateau = df - fc / K;
    let v_exit = (v1 * v1 - 2.0 * a * s_plateau).sqrt();
    let t_fail = GAP / V0 + tau1 + (v1 - v_exit) / a;
    // v² = v₀² − (k part + plateau work)·2/m
    let work = fc * fc / (2.0 * K) + fc * s_plateau;
    assert!((v_exit * v_exit - (V0 * V0 - 2.0 * work / M)).abs() < 1e-14);
    let r = run_scene(&key_law(fc, df), "event");
    let failures: Vec<_> = (r.events.iter())
        .filter(|e| e.kind == EventKind::KeyFailure)
        .collect();
    assert_eq!(failures.len(), 1);
    assert_rel(failures[0].t, t_fail, 1e-9, "failure instant");
    assert_eq!(r.summary.stats.key_failures, 1);
    let listed = r.summary.key_failures.as_ref().unwrap();
    assert_eq!(listed.len(), 1);
    let KeyFailure {
        element,
        t,
        peak_force,
    } = &listed[0];
    assert_eq!(
        (element.as_str(), *t, *peak_force),
        ("key", failures[0].t, fc)
    );
    // the force drops from f_c to 0 at that instant: pre- and post-event rows
    let at = |kind| {
        (r.samples.iter())
            .find(|s| s.kind == kind && s.t == failures[0].t)
            .unwrap()
    };
    let (pre, post) = (at(SampleKind::PreEvent), at(SampleKind::PostEvent));
    assert_rel(pre.elements[0].0, GAP + df, 1e-9, "deformation at failure");
    assert_eq!((pre.elements[0].1, post.elements[0].1), (fc, 0.0));
    assert_rel(post.v[0], v_exit, 1e-9, "exit velocity");
    // then free flight at v_exit
    let s = last(&r);
    assert_rel(s.v[0], v_exit, 1e-9, "final velocity");
    assert_rel(
        s.q[0],
        GAP + df + v_exit * (T_END - t_fail),
        1e-9,
        "final position",
    );
    // the energy ledger: the work absorbed is the k part plus the plateau, and closes
    assert_rel(s.energy.hysteretic, work, 1e-9, "hysteretic work");
    assert_rel(s.energy.kinetic, 0.5 * M * v_exit * v_exit, 1e-9, "kinetic");
    for s in &r.samples {
        assert!(
            s.energy.closure.abs() <= 1e-10,
            "closure {:e} at {}",
            s.energy.closure,
            s.t
        );
    }
    // events.csv: the kind and the element's name
    let names = r.element_names.clone();
    let csv = events_csv(&r.events, &r.contact_names, &names);
    let row = csv.lines().nth(1).unwrap();
    assert!(row.contains(",key,key failure,"), "{row}");
}

#[test]
fn fixed_step_methods_log_the_key_failure_in_the_step_where_it_happens() {
    let (fc, df) = (20.0, 0.04);
    let (_, tau1, v1) = elastic_then_plastic(fc);
    let a = fc / M;
    let v_exit = (v1 * v1 - 2.0 * a * (df - fc / K)).sqrt();
    let t_fail = GAP / V0 + tau1 + (v1 - v_exit) / a;
    for method in ["moreau", "penalty", "penalty-explicit"] {
        let r = run_scene(&key_law(fc, df), method);
        let failures: Vec<_> = (r.events.iter())
            .filter(|e| e.kind == EventKind::KeyFailure)
            .collect();
        assert_eq!(failures.len(), 1, "{method}");
        let t = failures[0].t;
        // at the end of the step that holds the failure instant
        assert!(
            t >= t_fail && t - H < t_fail,
            "{method}: logged at {t}, fails at {t_fail}"
        );
        assert_eq!(r.summary.stats.key_failures, 1);
        let listed = r.summary.key_failures.as_ref().unwrap();
        assert_eq!((listed[0].t, listed[0].peak_force), (failures[0].t, fc));
        let s = last(&r);
        // the capacity acts until the end of the failure's step: at most f_c/m · h too long
        let dv = (s.v[0] - v_exit).abs();
        assert!(
            dv <= 1.5 * a * H,
            "{method}: exit velocity {} vs {v_exit}",
            s.v[0]
        );
        assert_eq!(s.elements[0].1, 0.0);
        // the ledger follows the method's own forces: closed to its error before the failure
        // (a Moreau–Jean key acts to the end of its step, and the ledger counts that work)
        let closure = r
            .samples
            .iter()
            .map(|s| s.energy.closure.abs())
            .fold(0.0, f64::max);
        assert!(closure <= 1e-5, "{method}: closure {closure:e}");
        let work = fc * fc / (2.0 * K) + fc * (df - fc / K);
        let dw = (s.energy.hysteretic - work).abs();
        assert!(
            dw <= 1.5 * fc * V0 * H,
            "{method}: hysteretic {}",
            s.energy.hysteretic
        );
    }
}

#[test]
fn block_pushes_the_backfill_back_and_rebounds_at_the_closed_form_speed() {
    let fc = 20.0;
    let law = format!(r#"law = "backfill", gap = {GAP}, stiffness = {K}, capacity = {fc}"#);
    let r = run_scene(&law, "event");
    let (w, tau1, v1) = elastic_then_plastic(fc);
    // plastic until the block stops: e_p = m v₁²/(2 f_c); then it unloads the stored
    // f_c²/(2k) and leaves at −f_c/√(km)
    let a = fc / M;
    let e_p = M * v1 * v1 / (2.0 * fc);
    let v_r = -fc / (K * M).sqrt();
    let t_release = GAP / V0 + tau1 + v1 / a + std::f64::consts::FRAC_PI_2 / w;
    let state = r.final_laws[0].gap_state().unwrap();
    assert_rel(state.permanent_set, e_p, 1e-9, "permanent set");
    assert_rel(state.closing, GAP + e_p, 1e-9, "closing point");
    assert_eq!((state.peak_force, state.failed), (fc, false));
    let s = last(&r);
    assert_rel(s.v[0], v_r, 1e-9, "rebound velocity");
    assert_rel(
        s.q[0],
        GAP + e_p + v_r * (T_END - t_release),
        1e-9,
        "final position",
    );
    // absorbed: ½ m (v₀² − v_r²) = f_c e_p (the elastic part is given back), and it closes
    assert!((0.5 * M * (V0 * V0 - v_r * v_r) - fc * e_p).abs() < 1e-14);
    assert_rel(s.energy.hysteretic, fc * e_p, 1e-9, "hysteretic work");
    assert!(r.samples.iter().all(|s| s.energy.closure.abs() <= 1e-10));
    assert!(r.samples.iter().all(|s| s.elements[0].1 >= -1e-9));
    // no key: nothing about keys in summary.json
    assert!(r.summary.key_failures.is_none());
    let json = serde_json::to_string(&r.summary).unwrap();
    assert!(!json.contains("key_failures"), "{json}");
}

#[test]
fn a_key_failure_is_not_postponed_by_the_branch_window() {
    // a backfill on the same block closes 1.5e-5 s after the key fails, inside a 1e-4 s
    // branch window: the failure is still applied at its own instant
    let (fc, df) = (20.0, 0.04);
    let (_, tau1, v1) = elastic_then_plastic(fc);
    let a = fc / M;
    let v_exit = (v1 * v1 - 2.0 * a * (df - fc / K)).sqrt();
    let t_fail = GAP / V0 + tau1 + (v1 - v_exit) / a;
    let stop_gap = GAP + df + 1.5e-5 * v_exit;
    let text = scene(&key_law(fc, df), "event")
        .replace("output_dt = 0.01", "output_dt = 0.01\nbranch_window = 1e-4")
        + &format!(
            r#"
[[hysteretic]]
name = "stop"
body = "block"
direction = [1.0, 0.0]
law = {{ law = "backfill", gap = {stop_gap}, stiffness = 10.0, capacity = 1.0 }}
"#
        );
    let scene = deckspin::model::load_str(&text, Path::new("window.toml"), &[]).unwrap();
    assert_eq!(scene.settings.branch_window, 1e-4);
    let r = deckspin::simulate(&scene, &mut deckspin::Silent).unwrap();
    let failure = r.summary.key_failures.as_ref().unwrap()[0].clone();
    assert_rel(failure.t, t_fail, 1e-9, "failure instant");
}
