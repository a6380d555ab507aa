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

// ---- the kink of a compression-only law, crossed again and again ----

/// Block on the spring K to a support moving as u_g = −A cos ωt (f = 2 Hz): x₀ = −A puts
/// e = x − u_g at 0 with ė = 0, so the block starts at rest at the kink of the element of gap 0
/// to the same support (stiffness K2, capacity far above any force reached); ë(0) = −ü_g < 0.
const K2: f64 = 1600.0;
const KINK_T_END: f64 = 4.0;
const KINK_DT: f64 = 1e-4;

fn kink_scene(law: &str, amplitude: f64) -> String {
    format!(
        r#"
title = "block at the kink of a compression-only element"
[solver]
method = "event"
t_end = {KINK_T_END}
rtol = 1e-10
atol = 1e-12
output_dt = {KINK_DT}
[[support]]
name = "ground"
kind = "harmonic"
amplitude = {amplitude}
frequency = 2.0
phase = -1.5707963267948966
[[body]]
name = "block"
mass = {M}
dofs = ["x"]
initial_displacement = [{x0}, 0.0, 0.0]
[[spring]]
name = "k1"
body = "block"
direction = [1.0, 0.0]
stiffness = {K}
support = "ground"
[[hysteretic]]
name = "element"
body = "block"
direction = [1.0, 0.0]
support = "ground"
law = {{ {law} }}
"#,
        x0 = -amplitude
    )
}

const BACKFILL_AT_KINK: &str =
    r#"law = "backfill", gap = 0.0, stiffness = 1600.0, capacity = 1.0e6"#;
const KEY_AT_KINK: &str =
    r#"law = "key", gap = 0.0, stiffness = 1600.0, capacity = 1.0e6, failure_displacement = 1.0e3"#;

/// What the kink tests measure of a run: the largest |f − max(0, K2 e)| over the peak force,
/// the largest step of e beyond its branch's bound (f = 0: open, e ≤ 0; f > 0: elastic, e ≥ 0),
/// the sign changes of e on the output grid, and the largest |ė| (from the block's and the
/// support's velocities).
struct KinkReading {
    force_error: f64,
    beyond: f64,
    sign_changes: usize,
    max_rate: f64,
}

fn read_kink(r: &deckspin::RunOutput, amplitude: f64) -> KinkReading {
    let w = 4.0 * std::f64::consts::PI;
    let peak = (r.samples.iter())
        .map(|s| s.elements[0].1.abs())
        .fold(0.0, f64::max);
    let (mut force_error, mut beyond, mut max_rate) = (0.0f64, 0.0f64, 0.0f64);
    let (mut sign_changes, mut last) = (0, 0.0);
    for s in &r.samples {
        let (e, f) = s.elements[0];
        force_error = force_error.max((f - (K2 * e).max(0.0)).abs() / peak);
        beyond = beyond.max(if f == 0.0 { e } else { -e });
        let rate = s.v[0] - amplitude * w * (w * s.t).sin();
        max_rate = max_rate.max(rate.abs());
        if e != 0.0 {
            if last != 0.0 && e.signum() != last {
                sign_changes += 1;
            }
            last = e.signum();
        }
    }
    KinkReading {
        force_error,
        beyond,
        sign_changes,
        max_rate,
    }
}

/// The checks of a run through the kink: every sample on the law's formula, never beyond its
/// branch by more than the event tolerance (ε = 1e-13 on e, and ė over the time tolerance),
/// one branch event per crossing, the energy ledger closed.
fn check_kink(r: &deckspin::RunOutput, amplitude: f64, what: &str) {
    let k = read_kink(r, amplitude);
    let st = &r.summary.stats;
    let tol_e = 1e-13 + k.max_rate * 1e-13;
    if std::env::var("ORACLE_REPORT").is_ok() {
        eprintln!(
            "ORACLE {what}: force {:.2e}, beyond {:.2e} m (tol {tol_e:.1e}), {} branch events, \
             {} sign changes, closure {:.2e}, {} steps",
            k.force_error,
            k.beyond,
            st.branch_events,
            k.sign_changes,
            r.summary.energy_closure_rel,
            st.steps_accepted
        );
    }
    assert!(
        k.force_error <= 1e-12,
        "{what}: force error {:e}",
        k.force_error
    );
    assert!(
        k.beyond <= tol_e,
        "{what}: e beyond its bound by {:e}",
        k.beyond
    );
    assert!(k.sign_changes > 20, "{what}: {} crossings", k.sign_changes);
    assert!(
        st.branch_events.abs_diff(k.sign_changes) <= 2,
        "{what}: {} branch events for {} sign changes of e",
        st.branch_events,
        k.sign_changes
    );
    assert!(
        r.summary.energy_closure_rel <= 1e-8,
        "{what}: closure {:e}",
        r.summary.energy_closure_rel
    );
    assert_eq!(last(r).t, KINK_T_END, "{what}");
}

fn kink_run(law: &str, amplitude: f64, driven_in_y: bool) -> deckspin::RunOutput {
    let text = kink_scene(law, amplitude);
    let mut scene = deckspin::model::load_str(&text, Path::new("kink.toml"), &[])
        .unwrap_or_else(|e| panic!("{e}"));
    if driven_in_y {
        // carried in y by the ground, as a bridge file's backfill backwall (x stays a DOF)
        scene.bodies[0].drive = [None, Some(0)];
    }
    deckspin::simulate(&scene, &mut deckspin::Silent).unwrap_or_else(|e| panic!("{law}: {e}"))
}

#[test]
fn a_block_starting_at_rest_at_the_kink_crosses_it_once_per_sign_change() {
    check_kink(&kink_run(BACKFILL_AT_KINK, 0.01, false), 0.01, "backfill");
    // a deck resting against its key: the same kink
    check_kink(&kink_run(KEY_AT_KINK, 0.01, false), 0.01, "key");
}

#[test]
fn a_block_carried_in_y_by_the_ground_crosses_the_kink_as_one_that_is_not() {
    // y has no DOF and does not enter e: the run is the one without the drive
    let free = kink_run(BACKFILL_AT_KINK, 0.01, false);
    let carried = kink_run(BACKFILL_AT_KINK, 0.01, true);
    check_kink(&carried, 0.01, "backfill, block carried in y");
    assert_eq!(
        carried.summary.stats.branch_events,
        free.summary.stats.branch_events
    );
    let dx = (free.samples.iter().zip(&carried.samples))
        .map(|(a, b)| (a.t - b.t).abs().max((a.q[0] - b.q[0]).abs()))
        .fold(0.0, f64::max);
    if std::env::var("ORACLE_REPORT").is_ok() {
        eprintln!("ORACLE carried in y against free: {dx:.2e}");
    }
    assert!(dx <= 1e-12, "largest difference {dx:e}");
}

#[test]
fn a_block_at_rest_at_the_kink_on_still_ground_makes_no_branch_event() {
    let r = kink_run(BACKFILL_AT_KINK, 0.0, false);
    assert_eq!(r.summary.stats.branch_events, 0);
    assert!(
        r.samples
            .iter()
            .all(|s| s.elements[0] == (0.0, 0.0) && s.q[0] == 0.0)
    );
    assert_eq!(last(&r).t, KINK_T_END);
}

#[test]
fn a_swing_that_grazes_the_backfill_finds_every_entry() {
    // released at rest δ = 1e-9 m inside the gap: the free swing (ω = √(K/M), T = 2π/ω) comes
    // back to GAP + δ once per period (energy), in the elastic branch for ~2√(2δ/a) = 4.5e-5 s
    // (a = K·GAP/M): one event to leave at the start, then an entry and an exit per period
    let delta = 1e-9;
    let text = format!(
        r#"
[solver]
t_end = 3.0
rtol = 1e-10
atol = 1e-13
output_dt = 0.01
[[body]]
name = "block"
mass = {M}
dofs = ["x"]
initial_displacement = [{x0}, 0.0, 0.0]
[[spring]]
name = "k1"
body = "block"
direction = [1.0, 0.0]
stiffness = {K}
[[hysteretic]]
name = "fill"
body = "block"
direction = [1.0, 0.0]
law = {{ law = "backfill", gap = {GAP}, stiffness = {K2}, capacity = 1.0e6 }}
"#,
        x0 = GAP + delta
    );
    let r = run_text(&text, "graze.toml").unwrap_or_else(|e| panic!("{e}"));
    let period = 2.0 * std::f64::consts::PI / (K / M).sqrt();
    let returns = (3.0 / period).floor() as usize;
    assert_eq!(returns, 9);
    assert_eq!(r.summary.stats.branch_events, 1 + 2 * returns);
    let state = r.final_laws[0].gap_state().unwrap();
    assert_eq!((state.permanent_set, state.failed), (0.0, false));
}

#[test]
fn the_specimen_with_backfill_abutments_finishes_its_sixteen_seconds() {
    let set = ["abutment.kind=backfill", "abutment.backwall_height=0.6"].map(String::from);
    let scene = deckspin::load(&model("models/four-span.toml"), &set).unwrap();
    let r = deckspin::simulate(&scene, &mut deckspin::Silent).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(last(&r).t, 16.0);
    let st = &r.summary.stats;
    if std::env::var("ORACLE_REPORT").is_ok() {
        eprintln!(
            "ORACLE specimen with backfill: {} branch events, {} + {} steps, closure {:.2e}",
            st.branch_events, st.steps_accepted, st.steps_rejected, r.summary.energy_closure_rel
        );
    }
    // the backwalls reach their capacity: the soil is pushed back
    let pushed = (r.final_laws.iter())
        .filter_map(|l| l.gap_state())
        .filter(|g| g.permanent_set > 0.0)
        .count();
    assert!(pushed > 0);
}

#[test]
fn a_key_closing_before_an_impact_in_the_same_step_acts_from_its_own_instant() {
    // the key closes at t_k = g_k/v₀ and the block meets a wall δ further on, inside one long
    // free-flight step (the wall's crossing found at an output instant, before the step's
    // middle): from t_k the key's force k (x − g_k) acts, so x − g_k = (v₀/ω) sin ω(t − t_k)
    // and the impact comes at sin ω τ = ω δ/v₀ with ġ = −v₀ cos ω τ
    let (g_k, delta) = (0.03, 0.015);
    let w = (K / M).sqrt();
    let tau = (w * delta / V0).asin() / w;
    let (t_impact, v_impact) = (g_k / V0 + tau, V0 * (w * tau).cos());
    let law = format!(
        r#"law = "key", gap = {g_k}, stiffness = {K}, capacity = 100.0, failure_displacement = 0.5"#
    );
    let text = scene(&law, "event")
        + &format!(
            r#"
[[contact]]
name = "wall"
body = "block"
normal = [-1.0, 0.0]
gap = {}
restitution = 1.0
"#,
            g_k + delta
        );
    let scene = deckspin::model::load_str(&text, Path::new("key-and-wall.toml"), &[]).unwrap();
    let r = deckspin::simulate(&scene, &mut deckspin::Silent).unwrap();
    let impact = &r.events[0];
    assert_eq!(impact.kind, EventKind::Impact);
    assert_rel(impact.t, t_impact, 1e-9, "impact instant");
    assert_rel(-impact.gap_rate_before, v_impact, 1e-9, "impact speed");
    // the key's force just before the impact: k δ, on its elastic branch
    let pre = (r.samples.iter())
        .find(|s| s.kind == SampleKind::PreEvent && s.t == impact.t)
        .unwrap();
    assert_rel(
        pre.elements[0].1,
        K * delta,
        1e-9,
        "key force at the impact",
    );
}

#[test]
fn a_key_grazed_between_two_samples_of_a_long_step_still_closes() {
    // a block on a spring (ω = 1 rad/s, amplitude v₀/ω = 1 m) against a stiff key at
    // g = 1 − 1e-6 m: on the step's dense output (no key) it is beyond the closing point for
    // 2√(2·1e-6)/ω ≈ 2.8 ms, between two samples of the step (without the key it would pass
    // unseen: no branch event, x(3 s) = sin 3 = 0.14112 instead of 0.14021). Closed form: the key
    // closes at sin ω t₁ = ω g/v₀ with v₁ = v₀ cos ω t₁; the block then oscillates about
    // x_eq = K g/(k_s + K) at Ω = √((k_s + K)/m) and is back at g after τ = 2φ/Ω,
    // φ = atan2(v₁/Ω, g − x_eq), at −v₁; then x = g cos ω s − (v₁/ω) sin ω s, s = t − t₁ − τ
    let (k_s, k_key, g, t_end) = (M, 2e6, 1.0 - 1e-6, 3.0);
    let w = (k_s / M).sqrt();
    let t1 = (w * g / V0).asin() / w;
    let v1 = V0 * (w * t1).cos();
    let (x_eq, big_w) = (k_key * g / (k_s + k_key), ((k_s + k_key) / M).sqrt());
    let tau = 2.0 * (v1 / big_w).atan2(g - x_eq) / big_w;
    let s = t_end - t1 - tau;
    let x = g * (w * s).cos() - v1 / w * (w * s).sin();
    let v = -g * w * (w * s).sin() - v1 * (w * s).cos();
    let text = format!(
        r#"
title = "block on a spring grazing a key"
[solver]
method = "event"
t_end = {t_end}
rtol = 1e-10
atol = 1e-12
output_dt = 0.5
[[body]]
name = "block"
mass = {M}
dofs = ["x"]
initial_velocity = [{V0}, 0.0, 0.0]
[[spring]]
name = "k"
body = "block"
direction = [1.0, 0.0]
stiffness = {k_s}
[[hysteretic]]
name = "key"
body = "block"
direction = [1.0, 0.0]
law = {{ law = "key", gap = {g}, stiffness = {k_key}, capacity = 1e3, failure_displacement = 0.5 }}
"#
    );
    let scene = deckspin::model::load_str(&text, Path::new("graze.toml"), &[]).unwrap();
    let r = deckspin::simulate(&scene, &mut deckspin::Silent).unwrap();
    // closed (open → elastic) and open again (elastic → open)
    assert_eq!(r.summary.stats.branch_events, 2);
    let end = last(&r);
    assert_rel(end.q[0], x, 1e-6, "final position");
    assert_rel(end.v[0], v, 1e-7, "final velocity");
}
