//! Bad input gets a clear error naming the file, the line and the field — never a panic.
mod common;
use common::*;
use deckspin::ModelError;

fn load_err(rel: &str, set: &[&str]) -> (ModelError, String) {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    let e = deckspin::load(&model(rel), &set).expect_err("must fail");
    let msg = e.to_string();
    (e, msg)
}

#[test]
fn malformed_toml_names_file_line_and_column() {
    let (e, msg) = load_err("tests/fixtures/models/malformed.toml", &[]);
    assert!(matches!(e, ModelError::Parse { line: 5, .. }), "{msg}");
    assert!(msg.contains("malformed.toml:5:"), "{msg}");
}

#[test]
fn unknown_key_is_rejected_with_its_line() {
    let (e, msg) = load_err("tests/fixtures/models/unknown-key.toml", &[]);
    assert!(matches!(e, ModelError::Parse { line: 7, .. }), "{msg}");
    assert!(msg.contains("unknown field `mas`"), "{msg}");
}

#[test]
fn negative_mass_names_the_field_and_line() {
    let (e, msg) = load_err("tests/fixtures/models/negative-mass.toml", &[]);
    assert!(matches!(e, ModelError::Invalid { line: 5, .. }), "{msg}");
    assert!(msg.contains("negative-mass.toml:5: body.0.mass"), "{msg}");
}

#[test]
fn nan_is_rejected() {
    let (e, msg) = load_err("tests/fixtures/models/nan-mu.toml", &[]);
    assert!(matches!(e, ModelError::Invalid { line: 13, .. }), "{msg}");
    assert!(
        msg.contains("contact.0.mu") && msg.contains("finite"),
        "{msg}"
    );
}

#[test]
fn missing_file_names_the_path() {
    let (e, msg) = load_err("models/no-such-model.toml", &[]);
    assert!(matches!(e, ModelError::Io { .. }));
    assert!(msg.contains("no-such-model.toml"), "{msg}");
}

#[test]
fn unknown_body_reference_names_the_field() {
    let (_, msg) = load_err("tests/fixtures/models/unknown-body.toml", &[]);
    assert!(
        msg.contains(":11: contact.0.body") && msg.contains("ballx"),
        "{msg}"
    );
}

#[test]
fn overrides_set_scalars_by_path_index_name_and_wildcard() {
    let s = deckspin::load(
        &model("models/validation/elastic-rattle.toml"),
        &[
            "contact.*.mu=0.3".into(),
            "contact.left-top.restitution=0.5".into(),
            "solver.t_end=2".into(),
        ],
    )
    .unwrap();
    assert!(s.contacts.iter().all(|c| c.law.mu == 0.3));
    assert_eq!(s.contacts[2].law.restitution, 0.5);
    assert_eq!(s.contacts[0].law.restitution, 1.0);
    assert_eq!(s.settings.t_end, 2.0);
    // bad overrides
    for bad in [
        "contact.*.mu",
        "nosuch.key=1",
        "contact.9.mu=0.1",
        "body.0.dofs=1",
    ] {
        let r = deckspin::load(
            &model("models/validation/elastic-rattle.toml"),
            &[bad.into()],
        );
        assert!(r.is_err(), "{bad} accepted");
    }
    // an override that makes the model invalid is reported as such
    let e = deckspin::load(
        &model("models/validation/elastic-rattle.toml"),
        &["body.0.mass=-3".into()],
    )
    .unwrap_err();
    assert!(e.to_string().contains("body.0.mass"), "{e}");
    // an override that adds an unknown key is rejected by the schema
    let e = deckspin::load(
        &model("models/validation/elastic-rattle.toml"),
        &["solver.rtoll=1e-3".into()],
    )
    .unwrap_err();
    assert!(e.to_string().contains("rtoll"), "{e}");
}

#[test]
fn invalid_values_in_scene_text_are_rejected_not_panicking() {
    let cases = [
        ("[[body]]\nname='b'\nmass=1.0\ndofs=['q']\n", "unknown DOF"),
        ("[[body]]\nname='b'\nmass=1.0\ndofs=['theta']\n", "inertia"),
        (
            "[[body]]\nname='b'\nmass=1.0\ndofs=['x']\n[[contact]]\nname='c'\nbody='b'\nnormal=[0.0,0.0]\ngap=0.0\n",
            "nonzero",
        ),
        (
            "[[body]]\nname='b'\nmass=1.0\ndofs=['x']\n[[contact]]\nname='c'\nbody='b'\nnormal=[1.0,0.0]\ngap=0.0\nrestitution=1.5\n",
            "[0, 1]",
        ),
        (
            "[[body]]\nname='b'\nmass=1.0\ndofs=['x']\n[solver]\nt_end=-1.0\n",
            "solver.t_end",
        ),
        (
            "[[body]]\nname='b'\nmass=1.0\ndofs=['x']\ninitial_displacement=[0.0,1.0,0.0]\n",
            "no such DOF",
        ),
        ("", "no degrees of freedom"),
    ];
    for (text, want) in cases {
        let e = deckspin::model::load_str(text, std::path::Path::new("t.toml"), &[]).unwrap_err();
        assert!(e.to_string().contains(want), "{text:?}: {e}");
    }
}

#[test]
fn cli_exits_nonzero_with_message_on_bad_input() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_deckspin"))
        .args(["run", "tests/fixtures/models/negative-mass.toml", "--out"])
        .arg(std::env::temp_dir().join("deckspin-bad"))
        .current_dir(root())
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("negative-mass.toml:5: body.0.mass"), "{err}");
}

#[test]
fn cli_run_writes_history_events_and_summary() {
    let dir = std::env::temp_dir().join(format!("deckspin-cli-{}", std::process::id()));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_deckspin"))
        .args([
            "run",
            "models/validation/bouncing-ball.toml",
            "--set",
            "solver.t_end=1.0",
            "--out",
        ])
        .arg(&dir)
        .current_dir(root())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let hist = std::fs::read_to_string(dir.join("history.csv")).unwrap();
    assert!(hist.lines().count() > 100);
    assert!(hist.lines().any(|l| l.contains("pre-event")));
    let ev = std::fs::read_to_string(dir.join("events.csv")).unwrap();
    assert_eq!(ev.lines().filter(|l| l.contains(",impact,")).count(), 1);
    let sum: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert!(sum["energy_closure_rel"].as_f64().unwrap() < 1e-8);
    std::fs::remove_dir_all(&dir).ok();
}

// ---- every bad input refused clearly (docs/engine.md, bad input) ----

use deckspin::model::{Loaded, ModelWarning, Motions, load_str_checked, load_str_with};
use std::path::{Path, PathBuf};

const FOUR_SPAN: &str = "models/four-span.toml";

/// The default model's text with `edit` applied, loaded as if it were the default model file.
fn four_span(edit: &dyn Fn(String) -> String, set: &[&str]) -> Result<Loaded, ModelError> {
    let path = model(FOUR_SPAN);
    let text = edit(std::fs::read_to_string(&path).unwrap());
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    load_str_checked(&text, &path, &set, &Motions::default())
}

fn same(t: String) -> String {
    t
}

/// The error message of the default model with `set`.
fn set_err(set: &[&str]) -> String {
    four_span(&same, set).expect_err("must fail").to_string()
}

/// 1-based line of the first line of the default model containing `needle`.
fn line_of(needle: &str) -> usize {
    let text = std::fs::read_to_string(model(FOUR_SPAN)).unwrap();
    text.lines().position(|l| l.contains(needle)).unwrap() + 1
}

/// A two-column record (g) of `seconds` at dt 0.01 in a fresh directory: a(t) = f(t).
fn record(name: &str, seconds: f64, f: &dyn Fn(f64) -> f64) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("deckspin-bad-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let n = (seconds / 0.01).round() as usize;
    let mut s = String::from("# units: g\n");
    for i in 0..=n {
        let t = i as f64 * 0.01;
        s.push_str(&format!("{t:.2} {:.9e}\n", f(t)));
    }
    let p = dir.join(format!("{name}.txt"));
    std::fs::write(&p, s).unwrap();
    p
}

/// The default model driven by `rec` in both directions.
fn with_record(rec: &Path) -> impl Fn(String) -> String {
    let r = rec.display().to_string();
    move |t: String| {
        t.replace("../excitations/NORTHR_MUL009.AT2", &r)
            .replace("../excitations/NORTHR_MUL279.AT2", &r)
    }
}

fn sine(t: f64) -> f64 {
    0.2 * (2.0 * std::f64::consts::PI * 1.3 * t).sin() * (1.0 - (-t).exp())
}

#[test]
fn record_longer_than_t_end_is_said_and_absent_t_end_follows_the_records() {
    let rec = record("long", 90.0, &sine);
    // t_end = 16 s given, the record (90 s × time_scale 0.5) ends at 45 s: accepted, said
    let l = four_span(&with_record(&rec), &[]).unwrap();
    let w = &l.warnings[0];
    assert!(
        matches!(w, ModelWarning::RecordCut { t_end: 16.0, .. }),
        "{w}"
    );
    let msg = w.to_string();
    let line = line_of("t_end = 16.0");
    assert!(
        msg.contains(&format!(
            "four-span.toml:{line}: solver.t_end: 16 s ends before"
        )) && msg.contains("(45.000 s)")
            && msg.contains("last 29.000 s"),
        "{msg}"
    );
    // t_end absent: end of the longest record + the free-vibration tail
    let no_t_end = |t: String| with_record(&rec)(t).replace("t_end = 16.0", "");
    let l = four_span(&no_t_end, &[]).unwrap();
    let tail = deckspin::model::FREE_VIBRATION_TAIL;
    assert_eq!(l.scene.settings.t_end, 45.0 + tail);
    let msg = l.warnings[0].to_string();
    assert!(
        msg.contains("solver.t_end absent: 50.000 s = end of the longest record (45.000 s")
            && msg.contains("+ 5 s of free vibration"),
        "{msg}"
    );
    // the default model: its record ends before its t_end, nothing to say
    let l = four_span(&same, &[]).unwrap();
    assert!(l.warnings.is_empty(), "{:?}", l.warnings);
}

#[test]
fn constant_record_is_refused_with_its_pgas() {
    let rec = record("constant", 10.0, &|_| 0.1);
    let e = four_span(&with_record(&rec), &[]).unwrap_err();
    assert!(matches!(e, ModelError::Record { .. }), "{e}");
    let msg = e.to_string();
    let line = line_of("longitudinal = ");
    assert!(
        msg.contains(&format!("four-span.toml:{line}: excitation.longitudinal: "))
            && msg.contains("constant.txt")
            && msg.contains("no signal after processing: raw PGA 1.0000e-1 g, processed PGA"),
        "{msg}"
    );
    // all zeros
    let rec = record("zeros", 10.0, &|_| 0.0);
    let msg = four_span(&with_record(&rec), &[]).unwrap_err().to_string();
    assert!(msg.contains("no signal: every sample is zero"), "{msg}");
}

#[test]
fn absurd_scaling_is_refused_with_the_factor() {
    // a real-looking record at 1e-3 of its amplitude: 0.6 g needs a factor ≈ 3000
    let rec = record("weak", 20.0, &|t| 1e-3 * sine(t));
    let msg = four_span(&with_record(&rec), &[]).unwrap_err().to_string();
    let line = line_of("pga_x = 0.60");
    assert!(
        msg.contains(&format!("four-span.toml:{line}: run.3.pga_x: "))
            && msg.contains("target 0.6 g needs a factor")
            && msg.contains("outside [0.01, 100]")
            && msg.contains("raw PGA 2.0"),
        "{msg}"
    );
}

#[test]
fn tiny_time_scale_is_blamed_on_the_time_scale() {
    let edit = |t: String| t.replace("time_scale = 0.5", "time_scale = 1e-9");
    let msg = four_span(&edit, &[]).unwrap_err().to_string();
    let line = line_of("time_scale = 0.5");
    assert!(
        msg.contains(&format!("four-span.toml:{line}: excitation.time_scale: "))
            && msg
                .contains("invalid time_scale: the record lasts 29.98 s × time_scale 0.000000001")
            && msg.contains("taper of 0.5 s"),
        "{msg}"
    );
    let msg = set_err(&["excitation.time_scale=1e-9"]);
    assert!(
        msg.starts_with(
            "--set excitation.time_scale=1e-9: excitation.time_scale: invalid time_scale"
        ),
        "{msg}"
    );
}

#[test]
fn solver_values_out_of_range_are_refused_with_the_numbers() {
    let rtol = line_of("rtol = 1e-4");
    let edit = |t: String| t.replace("rtol = 1e-4", "rtol = 1.5");
    let msg = four_span(&edit, &[]).unwrap_err().to_string();
    assert!(
        msg.contains(&format!(
            "four-span.toml:{rtol}: solver.rtol: must be in (0, 1)"
        )) && msg.contains("got 1.5"),
        "{msg}"
    );
    for (set, want) in [
        (
            "solver.rtol=1",
            "--set solver.rtol=1: solver.rtol: must be in (0, 1)",
        ),
        (
            "solver.atol=0.1",
            "--set solver.atol=0.1: solver.atol: 0.1 is above 1e-3 × the smallest initial gap \
             (1.2700e-2 m, contact left_top) = 1.270e-5",
        ),
        (
            "solver.gap_tol=1e-4",
            "--set solver.gap_tol=1e-4: solver.gap_tol: 0.0001 is above 1e-3",
        ),
        (
            "solver.velocity_tol=0.1",
            "--set solver.velocity_tol=0.1: solver.velocity_tol: 0.1 is above 1e-3 × gap·ω₁ = \
             1e-3 × 1.2700e-2 m × 16.1420 rad/s = 2.050e-4 m/s",
        ),
        (
            "solver.output_dt=20",
            "--set solver.output_dt=20: solver.output_dt: must be ≤ solver.t_end = 16 s, got 20 s",
        ),
        (
            "solver.t_end=0",
            "--set solver.t_end=0: solver.t_end: must be > 0, got 0",
        ),
        (
            "solver.t_end=inf",
            "--set solver.t_end=inf: solver.t_end: must be a finite number",
        ),
    ] {
        let msg = set_err(&[set]);
        assert!(msg.contains(want), "{set}: {msg}");
    }
    // with h_max, loose tolerances are a fixed-step DP5 (order studies): accepted, said
    let l = four_span(
        &same,
        &["solver.rtol=1e3", "solver.atol=1e3", "solver.h_max=0.01"],
    )
    .unwrap();
    let msg = l.warnings[0].to_string();
    assert!(
        msg.contains("solver.rtol = 1000, solver.atol = 1000: no error control")
            && msg.contains("solver.h_max = 0.01 s"),
        "{msg}"
    );
    // in the file: the line of the field
    let atol = line_of("atol = 1e-7");
    let edit = |t: String| t.replace("atol = 1e-7", "atol = 0.1");
    let msg = four_span(&edit, &[]).unwrap_err().to_string();
    assert!(
        msg.contains(&format!("four-span.toml:{atol}: solver.atol: 0.1 is above")),
        "{msg}"
    );
}

#[test]
fn fixed_steps_are_judged_against_the_stability_limit() {
    let explicit = "solver.method=\"penalty-explicit\"";
    // above 2/ω_max of K₀ (contacts open): refused
    let msg = set_err(&[explicit, "solver.step=0.01"]);
    assert!(
        msg.contains("solver.step: 0.01 s is above the stability limit 2/ω_max = 8.749e-3 s")
            && msg.contains("ω_max = 2.2860e2 rad/s"),
        "{msg}"
    );
    // … but accepted by the studies' entry, which probes where methods fail
    let path = model(FOUR_SPAN);
    let text = std::fs::read_to_string(&path).unwrap();
    let set = [explicit.to_string(), "solver.step=0.01".to_string()];
    assert!(load_str_with(&text, &path, &set, &Motions::default()).is_ok());
    // above the limit with the contacts closed: accepted, said (a step the file sets; without
    // one, the method chooses its own)
    let comment = "# step: the fixed-step methods choose it from the model (see docs/engine.md) unless set here";
    let with_step = |t: String| t.replace(comment, "step = 0.001");
    let l = four_span(&with_step, &[explicit]).unwrap();
    let msg = l.warnings[0].to_string();
    let line = line_of(comment);
    assert!(
        matches!(l.warnings[0], ModelWarning::StepAboveStability { .. })
            && msg.contains(&format!(
                "four-span.toml:{line}: solver.step: 0.001 s > 2/ω_max = 6.543e-4 s"
            ))
            && msg.contains("every contact closed and sticking at contact_stiffness 1e6"),
        "{msg}"
    );
    // implicit: stable, the unresolved contact dynamics said
    let l = four_span(&with_step, &["solver.method=\"penalty\""]).unwrap();
    let msg = l.warnings[0].to_string();
    assert!(
        matches!(l.warnings[0], ModelWarning::StepUnresolved { .. })
            && msg.contains("the penalty method stays stable"),
        "{msg}"
    );
    let l = four_span(&with_step, &["solver.method=\"moreau\""]).unwrap();
    assert!(l.warnings.is_empty(), "{:?}", l.warnings);
    // a step the method chooses is within every limit, and said
    for m in ["moreau", "penalty", "penalty-explicit"] {
        let l = four_span(&same, &[&format!("solver.method=\"{m}\"")]).unwrap();
        assert!(l.warnings.is_empty(), "{m}: {:?}", l.warnings);
        let chose = l.scene.settings.step_chosen.unwrap();
        assert!(
            chose.starts_with(&format!("{m} chose solver.step = ")),
            "{chose}"
        );
    }
}

#[test]
fn nothing_in_a_bridge_file_is_silently_ignored() {
    let gaps = line_of("gaps = [");
    let edit = |t: String| t.replace("0.0127, 0.0127]", "0.0127, 0.0127, 0.5]");
    let msg = four_span(&edit, &[]).unwrap_err().to_string();
    assert!(
        msg.contains(&format!("four-span.toml:{gaps}:"))
            && msg.contains(
                "expected 4 contacts.gaps (left_top, left_bottom, right_top, right_bottom), got 5"
            ),
        "{msg}"
    );
    for (set, want) in [
        (
            "excitation.lag_bents=[0.0,0.0,0.0,0.0]",
            "excitation.lag_bents: 4 lags for 3 bents: give one per bent or none (all 0)",
        ),
        (
            "bent.0.x=1000",
            "--set bent.0.x=1000: bent.0.x: bent.0.x = 1000 m is off the deck: a bent must stand \
             under it, |x| ≤ deck.length/2 = 16.1 m",
        ),
        (
            "deck.width=2.4e-6",
            "--set deck.width=2.4e-6: deck.width: columns at ±0.75 m (column.offset) stand outside \
             the deck: offset ≤ deck.width/2 = 0.0000012 m",
        ),
        (
            "run.3.pga_x=0",
            "--set run.3.pga_x=0: run.3.pga_x: must be > 0, got 0",
        ),
    ] {
        let msg = set_err(&[set]);
        assert!(msg.contains(want), "{set}: {msg}");
    }
    // a harmonic kind does not read the records: said
    let l = four_span(
        &same,
        &["excitation.kind=\"harmonic\"", "excitation.frequency=2"],
    )
    .unwrap();
    let msg = l.warnings[0].to_string();
    let line = line_of("longitudinal = ");
    assert!(
        msg.contains(&format!(
            "four-span.toml:{line}: excitation.longitudinal: not read by excitation kind = \"harmonic\""
        )),
        "{msg}"
    );
}

#[test]
fn missing_tables_are_refused_or_said() {
    // no [solver]: the defaults, said; t_end from the records
    let edit = |t: String| t[..t.find("[solver]").unwrap()].to_string();
    let l = four_span(&edit, &[]).unwrap();
    assert!(matches!(l.warnings[0], ModelWarning::NoSolver { .. }));
    let msg = l.warnings[0].to_string();
    assert!(
        msg.contains(
            "four-span.toml: no [solver] table: the defaults are used (method event, t_end 19.990 s"
        ),
        "{msg}"
    );
    assert!(
        l.warnings[1]
            .to_string()
            .contains("19.990 s = end of the longest record (14.990 s")
    );
    // no [excitation]: nothing moves the bridge, said
    let edit = |t: String| {
        let (a, b) = (
            t.find("[excitation]").unwrap(),
            t.find("# The seven test runs").unwrap(),
        );
        format!("{}{}", &t[..a], &t[b..])
    };
    let l = four_span(&edit, &[]).unwrap();
    let msg = l.warnings[0].to_string();
    assert!(
        msg.contains("four-span.toml: no [excitation]: the bridge starts at rest"),
        "{msg}"
    );
    // no [deck] but bridge tables: a bridge file missing its deck
    let text = "[abutment]\nmass = 0.65\ninertia = 0.31\nactuator_stiffness = 1e4\nactuator_offset = 0.9\n";
    let msg = deckspin::model::load_str(text, Path::new("b.toml"), &[])
        .unwrap_err()
        .to_string();
    assert_eq!(
        msg,
        "b.toml:1: deck: missing: [abutment] (line 1) makes this a bridge file, which needs a \
         [deck] table (mass, inertia, length, width) or [[frame]] tables"
    );
}

#[test]
fn bad_set_values_name_the_argument_not_a_line() {
    let msg = set_err(&["deck.mass=abc"]);
    assert_eq!(
        msg,
        "--set deck.mass=abc: deck.mass: invalid type: string \"abc\", expected f64"
    );
    let msg = set_err(&["contacts.mu=-1"]);
    assert_eq!(
        msg,
        "--set contacts.mu=-1: contacts.mu: must be ≥ 0, got -1"
    );
    let msg = set_err(&["bent.*.height=-1"]);
    assert_eq!(
        msg,
        "--set bent.*.height=-1: bent.0.height: must be > 0, got -1"
    );
    // the same value in the file: its line
    let line = line_of("mu = 0.5");
    let msg = four_span(&|t| t.replace("mu = 0.5", "mu = -1.0"), &[])
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains(&format!("four-span.toml:{line}: contacts.mu: must be ≥ 0")),
        "{msg}"
    );
}

/// The double-impact validation scene with one line replaced.
fn double_impact_with(old: &str, new: &str) -> Result<deckspin::scene::Scene, ModelError> {
    let path = model("models/validation/double-impact.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains(old));
    deckspin::model::load_str(&text.replacen(old, new, 1), &path, &[])
}

#[test]
fn contact_point_beyond_the_resolvable_reach_is_refused() {
    // at 1.2e9 m from the centre rounding is ~1.7e-4 m, far above gap_tol = 1e-9 m
    let e = double_impact_with("point = [-16.1, 1.2]", "point = [-16.1, 1.2e9]").unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, ModelError::Invalid { line: 18, .. }), "{msg}");
    assert!(
        msg.contains("contact.0.point") && msg.contains("1.200e9 m"),
        "{msg}"
    );
    // 7 km is the reach at gap_tol = 1e-9 m: 5 km is accepted
    double_impact_with("point = [-16.1, 1.2]", "point = [-16.1, 5000.0]").unwrap();
}

#[test]
fn initial_speed_beyond_event_resolution_is_refused() {
    // 1e8 m/s × event_time_tol 1e-13 s = 1e-5 m of penetration at an event
    let e = double_impact_with(
        "initial_velocity = [-0.3, 0.0, 0.0]",
        "initial_velocity = [-1e8, 0.0, 0.0]",
    )
    .unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, ModelError::Invalid { line: 13, .. }), "{msg}");
    assert!(
        msg.contains("body.0.initial_velocity") && msg.contains("1.000e-5 m"),
        "{msg}"
    );
    // 2000 m/s leaves 2e-10 m: accepted
    double_impact_with(
        "initial_velocity = [-0.3, 0.0, 0.0]",
        "initial_velocity = [-2000.0, 0.0, 0.0]",
    )
    .unwrap();
}

#[test]
fn mass_ratio_beyond_double_precision_is_refused() {
    let scene = |m: f64| {
        format!(
            "[solver]\nt_end = 0.1\n\n[[body]]\nname = \"a\"\nmass = 1.0\ndofs = [\"x\"]\n\n\
             [[body]]\nname = \"b\"\nmass = {m:e}\ndofs = [\"x\"]\n"
        )
    };
    let path = std::path::Path::new("two-bodies.toml");
    let e = deckspin::model::load_str(&scene(1e13), path, &[]).unwrap_err();
    let msg = e.to_string();
    assert!(matches!(e, ModelError::Invalid { line: 6, .. }), "{msg}");
    assert!(
        msg.contains("body.0.mass")
            && msg.contains("body.1.mass")
            && msg.contains("1.000e13 apart"),
        "{msg}"
    );
    deckspin::model::load_str(&scene(1e11), path, &[]).unwrap();
    // the mass a corner impulse meets in rotation, I/r²: 1e-9 t·m² at 16.14 m is 3.8e-12 t
    let e = double_impact_with("inertia = 13090.0", "inertia = 1e-9").unwrap_err();
    let msg = e.to_string();
    assert!(
        matches!(e, ModelError::Invalid { line: 11, .. })
            && msg.contains("body.0.inertia")
            && msg.contains("3.662e13 apart"),
        "{msg}"
    );
    double_impact_with("inertia = 13090.0", "inertia = 1e-3").unwrap();
}

#[test]
fn a_record_sample_above_10_g_is_refused_as_a_unit_mistake() {
    // one corrupt sample of 9e9 g in a real-looking record drove a penalty run 322 km
    let rec = record("spike", 20.0, &|t| {
        if (t - 5.0).abs() < 1e-9 { 9e9 } else { sine(t) }
    });
    let msg = four_span(&with_record(&rec), &[]).unwrap_err().to_string();
    assert!(
        msg.contains("sample 500 is 9e9 g") && msg.contains("above the 10 g"),
        "{msg}"
    );
    // 4 g, the order of the strongest records, is accepted
    let rec = record("strong", 20.0, &|t| 20.0 * sine(t));
    four_span(&with_record(&rec), &[]).unwrap();
}

#[test]
fn a_bad_shear_key_names_its_line_and_field() {
    let text = r#"[[body]]
name = "block"
mass = 2.0
dofs = ["x"]
[[hysteretic]]
name = "key"
body = "block"
direction = [1.0, 0.0]
law = { law = "key", gap = 0.05, stiffness = 800.0, capacity = 20.0, failure_displacement = 0.02 }
"#;
    let e = deckspin::model::load_str(text, std::path::Path::new("key.toml"), &[])
        .expect_err("failure_displacement 0.02 < capacity/stiffness 0.025");
    let msg = e.to_string();
    assert!(matches!(e, ModelError::Invalid { line: 9, .. }), "{msg}");
    assert!(
        msg.contains("key.toml:9: hysteretic.0.law: failure_displacement: must be finite and exceed capacity/stiffness = 0.025, got 0.02"),
        "{msg}"
    );
}

/// `[[limit_state]]` tables appended to the default model.
fn with_limit_states(tables: &'static str) -> impl Fn(String) -> String {
    move |t: String| format!("{t}\n{tables}")
}

#[test]
fn limit_states_in_a_model_file_are_checked_with_file_line_and_field() {
    use deckspin::model::limit_state::{self, Op};
    let good = "[[limit_state]]\nname = \"slight\"\nexpression = \"peak_rotation > 0.005\"\n\n\
                [[limit_state]]\nname = \"unseated\"\nexpression = \"min_seat_margin<0\"\n";
    four_span(&with_limit_states(good), &[]).expect("valid limit states load");
    let text = with_limit_states(good)(std::fs::read_to_string(model(FOUR_SPAN)).unwrap());
    let ls = limit_state::from_text(&text, &model(FOUR_SPAN)).unwrap();
    assert_eq!(ls.len(), 2);
    assert_eq!(
        (
            ls[0].name.as_str(),
            ls[0].column.as_str(),
            ls[0].op,
            ls[0].threshold
        ),
        ("slight", "peak_rotation", Op::Above, 0.005)
    );
    assert_eq!(
        (ls[1].column.as_str(), ls[1].op, ls[1].threshold),
        ("min_seat_margin", Op::Below, 0.0)
    );
    let base_lines = text.lines().count() - good.lines().count();

    // a bad expression: its line and field, and the text
    let bad = "[[limit_state]]\nname = \"a\"\nexpression = \"peak_rotation>0.005\"\n\n\
               [[limit_state]]\nname = \"b\"\nexpression = \"min_seat_margin>=0\"\n";
    for e in [
        four_span(&with_limit_states(bad), &[]).expect_err("must fail"),
        limit_state::from_text(
            &with_limit_states(bad)(std::fs::read_to_string(model(FOUR_SPAN)).unwrap()),
            &model(FOUR_SPAN),
        )
        .expect_err("must fail"),
    ] {
        let msg = e.to_string();
        let want = base_lines + 7;
        assert!(
            matches!(&e, ModelError::Invalid { line, field, .. }
                if *line == want && field == "limit_state.1.expression"),
            "{msg}"
        );
        assert!(
            msg.contains("'min_seat_margin>=0'") && msg.contains("one comparison"),
            "{msg}"
        );
    }
    // the same name twice
    let twice = "[[limit_state]]\nname = \"a\"\nexpression = \"impacts>3\"\n\n\
                 [[limit_state]]\nname = \"a\"\nexpression = \"impacts>5\"\n";
    let msg = (four_span(&with_limit_states(twice), &[]).expect_err("must fail")).to_string();
    assert!(
        msg.contains(&format!(":{}: limit_state.1.name", base_lines + 6)),
        "{msg}"
    );
    // an unknown key of the table
    let unknown = "[[limit_state]]\nname = \"a\"\nexpression = \"impacts>3\"\nthreshold = 1\n";
    let e = four_span(&with_limit_states(unknown), &[]).expect_err("must fail");
    assert!(
        matches!(e, ModelError::Parse { line, .. } if line == base_lines + 4),
        "{e}"
    );
    assert!(e.to_string().contains("threshold"), "{e}");
}

#[test]
fn a_skew_of_60_degrees_or_more_is_refused_by_its_argument() {
    let (e, msg) = load_err("models/three-frame.toml", &["frame.1.skew=60"]);
    assert!(matches!(e, ModelError::OverrideInvalid { .. }), "{msg}");
    assert!(
        msg.ends_with("--set frame.1.skew=60: frame.1.skew: |skew| must be below 60°, got 60"),
        "{msg}"
    );
    let (_, msg) = load_err(FOUR_SPAN, &["deck.skew=-75"]);
    assert!(
        msg.ends_with("deck.skew: |skew| must be below 60°, got -75"),
        "{msg}"
    );
    let set = ["frame.1.skew=59.9".to_string()];
    deckspin::load(&model("models/three-frame.toml"), &set).expect("59.9° loads");
}

#[test]
fn a_missing_damping_table_is_warned_and_absurd_ratios_are_refused() {
    let without = |t: String| t.replace("[damping]\nratio = 0.02", "[damping_gone]\nratio = 0.02");
    let drop_table = |t: String| {
        let a = t.find("[damping]").unwrap();
        let b = t[a..].find("[excitation]").unwrap() + a;
        format!("{}{}", &t[..a], &t[b..])
    };
    assert!(
        four_span(&without, &[]).is_err(),
        "an unknown table is refused"
    );
    let loaded = four_span(&drop_table, &[]).unwrap();
    let w: Vec<String> = loaded.warnings.iter().map(|w| w.to_string()).collect();
    assert!(w.iter().any(|w| w.contains("no [damping] table")), "{w:?}");
    let loaded = four_span(&same, &[]).unwrap();
    assert!(
        !loaded
            .warnings
            .iter()
            .any(|w| w.to_string().contains("[damping]"))
    );
    for ratio in ["100", "1"] {
        let e = set_err(&[&format!("damping.ratio={ratio}")]);
        assert!(
            e.contains("damping.ratio") && e.contains("allowed 0 ≤ ζ < 1"),
            "{e}"
        );
        assert!(
            e.contains(&format!(":{}:", line_of("ratio = 0.02"))) || e.contains("--set"),
            "{e}"
        );
    }
}

#[test]
fn control_characters_in_titles_and_names_are_escaped() {
    let text = std::fs::read_to_string(model("models/validation/bouncing-ball.toml")).unwrap();
    let text = text.replacen("title = \"", "title = \"\\u001b[2J\\u0007", 1);
    assert!(text.contains("\\u001b[2J"));
    let path = model("models/validation/bouncing-ball.toml");
    let loaded = load_str_checked(&text, &path, &[], &Motions::default()).unwrap();
    let title = &loaded.scene.title;
    assert!(!title.chars().any(char::is_control), "{title:?}");
    assert!(title.starts_with("\\u{1b}[2J\\u{7}"), "{title:?}");
}

#[test]
fn an_initial_penetration_names_file_line_and_field() {
    let text = "title = \"through\"\n[solver]\nt_end = 1.0\n[[body]]\nname = \"mass\"\nmass = 1.0\ndofs = [\"x\"]\ninitial_displacement = [0.05, 0.0, 0.0]\n[[spring]]\nname = \"spring\"\nbody = \"mass\"\ndirection = [1.0, 0.0]\nstiffness = 10.0\n[[contact]]\nname = \"stop\"\nbody = \"mass\"\nnormal = [-1.0, 0.0]\ngap = 0.02\n";
    let path = std::path::Path::new("through.toml");
    let e = deckspin::model::load_str(text, path, &[])
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("through.toml:18: contact.0.gap:"), "{e}");
    assert!(
        e.contains("'stop' starts 3.000000e-2 m through its face"),
        "{e}"
    );
}
