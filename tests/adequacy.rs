//! The model ladder (`deckspin adequacy`): exact invariants — a simplification that cannot
//! change the answer changes it by exactly 0 — the error's definition against a closed form,
//! the specimen's ladder over its seven runs, and `--write` (a reduced model that loads, runs
//! to the variant's numbers bit for bit, keeps the comments and says why each key changed).
mod common;

use deckspin::design::adequacy::{Adequacy, Options, Outcome, Variant, adequacy, error};
use deckspin::design::cases::{Cases, Measured};
use deckspin::design::ladder::Simplification;
use deckspin::progress::Unwatched;
use deckspin::suite::row::Status;
use std::path::PathBuf;
use std::process::Command;

fn specimen() -> (String, PathBuf) {
    let path = common::model("models/four-span.toml");
    (std::fs::read_to_string(&path).unwrap(), path)
}

/// The specimen with its first run only, at `pga` g in both directions.
fn one_run(pga: f64) -> (String, PathBuf) {
    let (text, path) = specimen();
    let mut doc: toml_edit::DocumentMut = text.parse().unwrap();
    let runs = doc["run"].as_array_of_tables_mut().unwrap();
    while runs.len() > 1 {
        runs.remove(1);
    }
    let run = runs.get_mut(0).unwrap();
    run["pga_x"] = toml_edit::value(pga);
    run["pga_y"] = toml_edit::value(pga);
    doc["excitation"]["run"] = toml_edit::value(1);
    (doc.to_string(), path)
}

fn ladder(text: &str, path: &std::path::Path, fix: &[&str], only: &[Simplification]) -> Adequacy {
    let fix: Vec<String> = fix.iter().map(|s| s.to_string()).collect();
    let opts = Options {
        quantities: Vec::new(),
        tolerance: 0.05,
        only: Some(only.to_vec()),
        combine: false,
    };
    adequacy(text, path, &fix, &Cases::ModelRuns, &opts, &Unwatched).unwrap()
}

/// Every quantity of every variant: exactly 0.
fn assert_exact(s: &Adequacy, quantities: &[&str]) {
    for (v, o) in s.variants.iter().enumerate() {
        assert!(o.refused.is_none(), "{}: {:?}", o.variant.name, o.refused);
        for q in quantities {
            assert_eq!(
                s.error(v, q),
                Some(0.0),
                "{} in {q}: {:?} against {:?}",
                o.variant.name,
                o.runs[0].get(q),
                s.full.runs[0].get(q)
            );
        }
    }
}

const DECK: [&str; 5] = [
    "peak_rotation",
    "residual_rotation",
    "peak_x",
    "peak_y",
    "max_drift_ratio",
];

#[test]
fn elastic_columns_are_the_same_as_linear_or_bilinear_ones() {
    // 0.02 g: no column leaves its elastic branch (no branch event in the full model)
    let (text, path) = one_run(0.02);
    let s = ladder(
        &text,
        &path,
        &[],
        &[
            Simplification::BilinearColumns,
            Simplification::LinearColumns,
        ],
    );
    assert_eq!(s.full.runs[0].events, 0, "premise: no branch event");
    assert_eq!(s.variants.len(), 2);
    let all: Vec<&str> = s.quantities.iter().map(String::as_str).collect();
    assert_exact(&s, &all);
}

#[test]
fn contacts_that_never_close_change_nothing_when_removed_or_simplified() {
    let (text, path) = one_run(0.09);
    let gaps = "contacts.gaps=[0.5, 0.5, 0.5, 0.5]";
    let s = ladder(
        &text,
        &path,
        &[gaps],
        &[Simplification::NoContacts, Simplification::Frictionless],
    );
    assert_eq!(
        s.full.runs[0].get("impacts"),
        Some(0.0),
        "premise: no impact"
    );
    let all: Vec<&str> = s.quantities.iter().map(String::as_str).collect();
    assert_exact(&s, &all);
}

#[test]
fn rigid_abutments_leave_the_deck_alone_while_its_contacts_stay_open() {
    // by islands, the deck is integrated on its own steps whatever its abutments are (and its
    // damping comes from its own modes, solved apart from the abutments' block)
    let (text, path) = one_run(0.09);
    let fix = ["contacts.gaps=[0.5, 0.5, 0.5, 0.5]", "solver.islands=true"];
    let s = ladder(&text, &path, &fix, &[Simplification::RigidAbutments]);
    assert_eq!(
        s.full.runs[0].get("impacts"),
        Some(0.0),
        "premise: no impact"
    );
    assert_exact(&s, &DECK);
    // cheaper by the abutments' steps
    assert!(s.variants[0].cost().steps < s.full.cost().steps / 2);
}

fn outcome(values: &[Option<f64>], status: Status) -> Outcome {
    Outcome {
        variant: Variant {
            name: "v".into(),
            simplifications: Vec::new(),
            changes: Vec::new(),
        },
        refused: None,
        runs: values
            .iter()
            .map(|&x| {
                let mut m = Measured::refused(String::new());
                m.status = status.clone();
                m.metrics[0] = x;
                m
            })
            .collect(),
    }
}

#[test]
fn the_error_is_the_largest_relative_difference_with_a_floor() {
    let full = outcome(&[Some(1.0), Some(-4.0), Some(0.1)], Status::Finished);
    // run 2: |−3 − (−4)| / 4 = 0.25; run 3: |0.2 − 0.1| / max(0.1, 0.05·4 = 0.2) = 0.5
    let v = outcome(&[Some(1.0), Some(-3.0), Some(0.2)], Status::Finished);
    assert_eq!(error(&full, &v, "peak_rotation"), Some(0.5));
    // a value the variant does not have counts as 0: |0 − 1| / 1
    let v = outcome(&[None, Some(-4.0), Some(0.1)], Status::Finished);
    assert_eq!(error(&full, &v, "peak_rotation"), Some(1.0));
    // a failed run: infinite; a quantity the full model does not have: none
    let failed = Status::Failed {
        kind: "k".into(),
        reason: "r".into(),
    };
    let v = outcome(&[Some(1.0), Some(-4.0), Some(0.1)], failed);
    assert_eq!(error(&full, &v, "peak_rotation"), Some(f64::INFINITY));
    assert_eq!(error(&full, &full, "peak_x"), None);
}

#[test]
fn the_specimens_ladder_over_its_seven_runs() {
    let (text, path) = specimen();
    let opts = Options {
        quantities: vec!["peak_rotation".into(), "peak_x".into()],
        tolerance: 0.05,
        only: None,
        combine: true,
    };
    let s = adequacy(&text, &path, &[], &Cases::ModelRuns, &opts, &Unwatched).unwrap();
    assert_eq!(s.cases.len(), 7);
    assert_eq!(s.cases[3], "run4");
    let names: Vec<&str> = s.variants.iter().map(|o| o.variant.name.as_str()).collect();
    for single in [
        "rigid-abutments",
        "bilinear-columns",
        "linear-columns",
        "frictionless",
        "no-contacts",
        "translating-deck",
        "strong-motion",
    ] {
        assert!(names.contains(&single), "{single} in {names:?}");
    }
    // not applicable to the specimen: ε is 0 already, no keys, bearings or backfill
    for moot in ["plastic-impacts", "no-keys", "no-bearings", "no-backfill"] {
        assert!(!names.contains(&moot), "{moot}");
    }
    let at = |n: &str| names.iter().position(|x| *x == n).unwrap();
    // a deck that cannot turn: its peak rotation is off by 100 %
    assert_eq!(s.error(at("translating-deck"), "peak_rotation"), Some(1.0));
    // every variant ran all seven runs to the end, each cheaper in steps but one
    for o in &s.variants {
        assert_eq!(o.runs.len(), 7, "{}", o.variant.name);
        assert!(
            o.runs.iter().all(|r| r.status == Status::Finished),
            "{}",
            o.variant.name
        );
    }
    // rigid abutments take away the steps the abutments' periods (0.03 s) set
    assert!(s.variants[at("rigid-abutments")].cost().steps * 2 < s.full.cost().steps);
    // the cheapest within 5 % in peak_x is within 5 % in it
    if let Some(v) = s.cheapest(Some("peak_x")) {
        assert!(s.error(v, "peak_x").unwrap() <= 0.05);
    }
}

#[test]
fn write_gives_a_model_that_runs_to_the_variants_numbers_and_says_why() {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("adequacy-write");
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    let (text, path) = one_run(0.6);
    let model = d.join("model.toml");
    let records = common::root().join("excitations").display().to_string();
    std::fs::write(&model, text.replace("../excitations", &records)).unwrap();
    let reduced = d.join("elsewhere").join("reduced.toml");
    let r = Command::new(env!("CARGO_BIN_EXE_deckspin"))
        .args(["adequacy", &model.display().to_string()])
        .args(["--quantities", "peak_x", "--tolerance", "0.5"])
        .args(["--only", "frictionless,rigid-abutments", "--no-combine"])
        .args(["--out", &d.join("out").display().to_string()])
        .args(["--write", &reduced.display().to_string()])
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&r.stdout);
    assert!(
        r.status.success(),
        "{out}{}",
        String::from_utf8_lossy(&r.stderr)
    );
    let written = std::fs::read_to_string(&reduced).unwrap();
    assert!(written.starts_with("# Reduced by `deckspin adequacy`"));
    // the comments of the model kept, the change said
    assert!(written.contains("# paper §4.3"), "{written}");
    let chosen = out.lines().last().unwrap();
    assert!(
        chosen.starts_with("wrote ") && chosen.contains(".toml ("),
        "{out}"
    );
    assert!(written.contains("# simplified ("), "{written}");
    // its records found from its own folder, and its run the variant's, bit for bit
    let scene = deckspin::model::load(&reduced, &[]).unwrap();
    let heights = deckspin::suite::metrics::bent_heights(&written);
    let m = deckspin::design::cases::measure_scene(&scene, &heights);
    let csv = std::fs::read_to_string(d.join("out/adequacy-runs.csv")).unwrap();
    let name = chosen.rsplit_once('(').unwrap().1.trim_end_matches(')');
    let row = csv
        .lines()
        .find(|l| l.starts_with(&format!("{name},")))
        .unwrap();
    let peak_x: f64 = row.split(',').nth(6 + 2).unwrap().parse().unwrap();
    assert_eq!(m.get("peak_x"), Some(peak_x), "{row}");
    // the model itself is never overwritten
    let r = Command::new(env!("CARGO_BIN_EXE_deckspin"))
        .args(["adequacy", &path.display().to_string()])
        .args(["--write", &path.display().to_string()])
        .output()
        .unwrap();
    assert_eq!(r.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&r.stderr).contains("that is the model itself"));
}

#[test]
fn bad_arguments_and_models_are_named() {
    let (_, path) = specimen();
    let p = path.display().to_string();
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("adequacy-bad");
    let o = out.display().to_string();
    let run = |args: &[&str]| {
        let r = Command::new(env!("CARGO_BIN_EXE_deckspin"))
            .arg("adequacy")
            .args(args)
            .args(["--out", &o])
            .output()
            .unwrap();
        assert_eq!(r.status.code(), Some(1), "{args:?}");
        String::from_utf8_lossy(&r.stderr).into_owned()
    };
    let e = run(&[&p, "--tolerance", "0"]);
    assert!(e.contains("--tolerance 0: a relative error above 0"), "{e}");
    let e = run(&[&p, "--quantities", "peak_z"]);
    assert!(
        e.contains("--quantities: 'peak_z' is not one of peak_rotation"),
        "{e}"
    );
    let e = run(&[&p, "--only", "rigid"]);
    assert!(
        e.contains("--only 'rigid': not a simplification (rigid-abutments"),
        "{e}"
    );
    // the specimen's ε is 0 already: nothing to try
    let e = run(&[&p, "--only", "plastic-impacts"]);
    assert!(e.contains("no simplification of the ladder applies"), "{e}");
    let e = run(&["/nonexistent/model.toml"]);
    assert!(e.contains("/nonexistent/model.toml: No such file"), "{e}");
    let e = run(&[&p, "--set", "contacts.mu=abc"]);
    assert!(e.contains("contacts.mu"), "{e}");
    let scene = common::model("models/validation/bouncing-ball.toml");
    let e = run(&[&scene.display().to_string()]);
    assert!(e.contains("it is not a bridge file"), "{e}");
}

#[test]
fn the_longitudinal_component_alone_moves_no_support_in_y() {
    use deckspin::scene::Motion;
    let path = common::model("models/four-span.toml");
    let set = ["excitation.components=\"longitudinal\"".to_string()];
    let scene = deckspin::model::load(&path, &set).unwrap();
    let ys: Vec<&str> = (scene.supports.iter())
        .filter(|s| s.name.ends_with(".y"))
        .map(|s| match &s.motion {
            Motion::Harmonic { amplitude, .. } if *amplitude == 0.0 => "rest",
            _ => "moving",
        })
        .collect();
    assert!(!ys.is_empty() && ys.iter().all(|y| *y == "rest"), "{ys:?}");
    let xs = (scene.supports.iter()).filter(|s| s.name.ends_with(".x"));
    assert!(
        xs.clone().count() > 0
            && xs
                .into_iter()
                .all(|s| matches!(s.motion, Motion::Record(_)))
    );
    // a harmonic input: the same as no y amplitude, bit for bit
    let text = |extra: &str| {
        std::fs::read_to_string(&path).unwrap().replace(
            "kind = \"record\"",
            &format!("kind = \"harmonic\"\nfrequency = 2.0\namplitude_x = 0.01\n{extra}"),
        )
    };
    let run = |t: String| {
        let set = ["solver.t_end=1.0".to_string()];
        let scene = deckspin::model::load_str(&t, &path, &set).unwrap();
        deckspin::run(&scene, &mut deckspin::Silent).unwrap()
    };
    let a = run(text("amplitude_y = 0.02\ncomponents = \"longitudinal\""));
    let b = run(text("amplitude_y = 0.0"));
    let peaks = |r: &deckspin::output::RunOutput| -> Vec<(String, f64)> {
        r.summary
            .peaks
            .iter()
            .map(|p| (p.name.clone(), p.max_abs))
            .collect()
    };
    assert_eq!(peaks(&a), peaks(&b));
    let e = deckspin::model::load(&path, &["excitation.components=\"transverse\"".to_string()])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("excitation.components") && e.contains("\"both\" or \"longitudinal\""),
        "{e}"
    );
}
