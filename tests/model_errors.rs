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
    assert!(s.contacts.iter().all(|c| c.mu == 0.3));
    assert_eq!(s.contacts[2].restitution, 0.5);
    assert_eq!(s.contacts[0].restitution, 1.0);
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
