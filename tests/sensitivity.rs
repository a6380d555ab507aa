//! `deckspin sensitivity`: the swing of a linear model is proportional to the PGA range; an
//! input the model does not read swings by exactly 0; the tornado is ordered by |swing|;
//! `[[uncertain]]` tables are checked with file, line and field; a sharded study merges into
//! the outputs of the whole one byte for byte; the specimen's default study runs to its end.

use deckspin::design::cases::Cases;
use deckspin::design::sensitivity::{Choice, Origin, SensitivityError, Study};
use deckspin::design::swings::{InputInfo, RunRow, Side, summarize};
use deckspin::design::tornado::tornado;
use deckspin::progress::Unwatched;
use deckspin::suite::row::Status;
use std::path::PathBuf;
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn specimen() -> PathBuf {
    root().join("models/four-span.toml")
}

fn strings(s: &[&str]) -> Vec<String> {
    s.iter().map(|x| x.to_string()).collect()
}

fn dir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("sensitivity")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn deckspin(args: &[&str]) -> (bool, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_deckspin"))
        .args(args)
        .output()
        .expect("deckspin runs");
    let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    (o.status.success(), text(&o.stdout), text(&o.stderr))
}

/// The swing of `input` in `quantity` (value at high, base, at low).
fn swing(s: &deckspin::design::swings::Sensitivity, input: &str, quantity: &str) -> [f64; 3] {
    let i = s.inputs.iter().find(|i| i.input.name == input).unwrap();
    let q = s.quantities.iter().position(|q| q == quantity).unwrap();
    let w = &i.swings[q];
    assert_eq!((w.cases, w.failed), (7, 0), "{input} {quantity}");
    [w.high.unwrap(), w.base.unwrap(), w.low.unwrap()]
}

#[test]
fn a_linear_model_swings_in_proportion_to_the_pga() {
    // Linear columns, no contact, and all three bents of one height: the deck translates
    // without turning (the specimen's unequal bents make it turn, and a turning deck's exact
    // kinematics are nonlinear at order θ). The fixed-step Moreau–Jean method takes the same
    // steps whatever the PGA (an adaptive method's step choice depends on the response), so
    // the response is linear in the record's scale to round-off: the peak of |x| at ×1.2
    // minus that at ×0.8 is 0.4 × the peak at ×1.
    let fix = strings(&[
        "contacts.enabled=false",
        "column.law={ law = \"linear\", stiffness = 9320.0 }",
        "bent.*.height=1.83",
        "solver.method=\"moreau\"",
        "solver.t_end=3",
    ]);
    let choice = Choice {
        inputs: Some(strings(&["pga"])),
        add: Vec::new(),
        quantities: Some(strings(&["peak_x", "peak_y"])),
    };
    let study = Study::open(&specimen(), &fix, &Cases::ModelRuns, &choice).unwrap();
    assert_eq!((study.cases(), study.runs()), (7, 21));
    let s = study.run(&Unwatched);
    for q in ["peak_x", "peak_y"] {
        let [high, base, low] = swing(&s, "pga", q);
        assert!(base > 1e-3, "{q} = {base}: the record has not started");
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
        assert!(
            rel(high - low, 0.4 * base) < 1e-12,
            "{q}: {high} − {low} vs 0.4 × {base}"
        );
        assert!(rel(low, 0.8 * base) < 1e-12 && rel(high, 1.2 * base) < 1e-12);
    }
}

#[test]
fn an_input_the_model_does_not_read_swings_by_exactly_zero() {
    // μ of a bridge without contacts is read by nothing
    let fix = strings(&["contacts.enabled=false", "solver.t_end=2"]);
    let choice = Choice {
        inputs: Some(strings(&["column_stiffness"])),
        add: strings(&["contacts.mu=0.3:0.7"]),
        quantities: Some(strings(&["peak_rotation", "peak_x"])),
    };
    let study = Study::open(&specimen(), &fix, &Cases::ModelRuns, &choice).unwrap();
    let s = study.run(&Unwatched);
    for q in ["peak_rotation", "peak_x"] {
        let [high, base, low] = swing(&s, "contacts.mu", q);
        assert_eq!(
            (high.to_bits(), low.to_bits()),
            (base.to_bits(), base.to_bits())
        );
        let stiffness = swing(&s, "column_stiffness", q);
        assert!(stiffness[0] != stiffness[2], "{q}: the stiffness is read");
    }
    // the tornado puts the input that swings above the one that does not
    assert_eq!(s.inputs[0].input.name, "column_stiffness");
    assert_eq!(s.inputs[1].swings[0].swing(), Some(0.0));
}

fn info(name: &str) -> InputInfo {
    InputInfo {
        name: name.into(),
        key: format!("k.{name}"),
        relative: false,
        low: 0.0,
        high: 1.0,
    }
}

fn row(input: Option<&str>, side: Side, case: &str, v: f64) -> RunRow {
    RunRow {
        input: input.map(info),
        side,
        case: case.into(),
        status: Status::Finished,
        values: vec![Some(v), Some(-v)],
        steps: 1,
        events: 0,
        cpu: None,
    }
}

#[test]
fn the_tornado_is_ordered_by_the_size_of_the_swing() {
    // base 10 on two cases; a: 9 → 12 (+3), b: 14 → 6 (−8), c: 10 → 10.5 (+0.5), and d whose
    // high run failed on the second case
    let mut rows = vec![
        row(None, Side::Base, "one", 10.0),
        row(None, Side::Base, "two", 10.0),
    ];
    for (name, lo, hi) in [("a", 9.0, 12.0), ("b", 14.0, 6.0), ("c", 10.0, 10.5)] {
        for side in [Side::Low, Side::High] {
            let v = if side == Side::Low { lo } else { hi };
            rows.extend(["one", "two"].map(|c| row(Some(name), side, c, v)));
        }
    }
    rows.extend(["one", "two"].map(|c| row(Some("d"), Side::Low, c, 1.0)));
    rows.push(row(Some("d"), Side::High, "one", 100.0));
    let mut failed = row(Some("d"), Side::High, "two", 0.0);
    failed.status = Status::Failed {
        kind: "Unstable".into(),
        reason: "x".into(),
    };
    rows.push(failed);
    let s = summarize(&strings(&["q", "minus_q"]), rows);
    let order: Vec<&str> = s.inputs.iter().map(|i| i.input.name.as_str()).collect();
    // d: only case one counts, 1 → 100
    assert_eq!(order, ["d", "b", "a", "c"]);
    let d = &s.inputs[0].swings[0];
    assert_eq!((d.swing(), d.cases, d.failed), (Some(99.0), 1, 1));
    assert_eq!(s.inputs[1].swings[0].swing(), Some(-8.0));
    assert_eq!(s.inputs[1].swings[0].relative(), Some(-0.8));
    // the chart of the first quantity: a row per input, widest on top, bars from the base
    let c = tornado(&s, 0).unwrap();
    assert!(
        c.rows[0].starts_with("d ") && c.rows[3].starts_with("c "),
        "{:?}",
        c.rows
    );
    assert_eq!(c.bars[0].bars[1], (1, 10.0, 14.0));
    assert_eq!(c.bars[1].bars[1], (1, 10.0, 6.0));
    assert_eq!(c.lines[0].at, 10.0);
    // the CSV: one row per input and quantity, in that order
    let csv = s.csv();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 1 + 4 * 2);
    assert!(
        lines[3].starts_with("b,k.b,false,0.0,1.0,q,14.0,10.0,6.0,-8.0,-0.8,2,0"),
        "{csv}"
    );
}

/// The specimen's text, its records named by absolute paths (so that a copy runs anywhere).
fn specimen_text() -> String {
    let text = std::fs::read_to_string(specimen()).unwrap();
    let records = root().join("excitations").display().to_string();
    text.replace("\"../excitations/", &format!("\"{records}/"))
}

/// `text` written as model `name` in the tests' folder.
fn write_model(name: &str, text: &str) -> PathBuf {
    let path = dir(name).join("model.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn uncertain_tables_are_checked_with_file_line_and_field() {
    let text = std::fs::read_to_string(specimen()).unwrap();
    let line0 = text.lines().count() + 2;
    let cases = [
        (
            "key = \"contacts.mew\"\nlow = 0.3\nhigh = 0.7",
            "uncertain.0.key",
            1,
            "contacts.mew",
        ),
        (
            "key = \"contacts.mu\"\nlow = 0.7\nhigh = 0.3",
            "uncertain.0.high",
            3,
            "above low",
        ),
        (
            "key = \"contacts.gaps\"\nlow = 0.01\nhigh = 0.02",
            "uncertain.0.key",
            1,
            "relative",
        ),
        (
            "key = \"title\"\nlow = 1\nhigh = 2",
            "uncertain.0.key",
            1,
            "not a number",
        ),
        (
            "key = \"contacts.mu\"\nlow = 0.3\nhigh = inf",
            "uncertain.0.high",
            3,
            "finite",
        ),
    ];
    for (table, field, at, why) in cases {
        let full = format!("{text}\n[[uncertain]]\n{table}\n");
        let e = deckspin::model::load_str(&full, &specimen(), &[]).unwrap_err();
        let want = format!("{}:{}: {field}: ", specimen().display(), line0 + at);
        let e = e.to_string();
        assert!(
            e.starts_with(&want) && e.contains(why),
            "{e} (want {want} … {why})"
        );
    }
    // a good table is no part of a run, and replaces the defaults in a study
    let good = "[[uncertain]]\nname = \"friction\"\nkey = \"contacts.mu\"\nlow = 0.2\nhigh = 0.6\n\
        [[uncertain]]\nkey = [\"run.*.pga_x\", \"run.*.pga_y\"]\nrelative = true\nlow = 0.9\nhigh = 1.1\n\
        [[uncertain]]\nkey = \"contacts.restitution\"\nlow = 0.0\nhigh = 2.0\n";
    let full = format!("{text}\n{good}");
    assert!(deckspin::model::load_str(&full, &specimen(), &[]).is_ok());
    let path = write_model("uncertain", &format!("{}\n{good}", specimen_text()));
    let choice = |names: &[&str]| Choice {
        inputs: Some(strings(names)),
        ..Choice::default()
    };
    let fix = strings(&["solver.t_end=1"]);
    let study = Study::open(
        &path,
        &fix,
        &Cases::ModelRuns,
        &choice(&["friction", "run.*.pga_x+run.*.pga_y"]),
    );
    let study = study.unwrap();
    let names: Vec<&str> = study.inputs().iter().map(|i| i.name.as_str()).collect();
    assert_eq!(names, ["friction", "run.*.pga_x+run.*.pga_y"]);
    assert_eq!(study.inputs()[0].origin, Origin::Model { entry: 0 });
    // a value the model refuses stops the study before any run, naming its line and field
    let e = Study::open(&path, &fix, &Cases::ModelRuns, &Choice::default());
    let e = e.err().expect("restitution 2 is refused");
    assert!(matches!(e, SensitivityError::Side { .. }), "{e}");
    let want = format!(
        "{}:{}: uncertain.2.high ('contacts.restitution'): high = 2 ",
        path.display(),
        line0 + 13
    );
    assert!(e.to_string().starts_with(&want), "{e}\nwant {want}");
    assert!(e.to_string().contains("contacts.restitution"), "{e}");
}

#[test]
fn a_sharded_study_merges_into_the_whole_byte_for_byte() {
    // one case: the specimen's run 4 alone
    let text = specimen_text();
    let cut = text.find("\n[[run]]\n").unwrap() + 1;
    let end = text.find("[solver]").unwrap();
    let one = format!(
        "{}[[run]]\nname = \"run4\"\npga_x = 0.60\npga_y = 0.50\n\n{}",
        &text[..cut],
        &text[end..]
    )
    .replace("run = 4 ", "run = 1 ");
    let path = write_model("one-run", &one);
    let m = path.display().to_string();
    let args = [
        "sensitivity",
        &m,
        "--fix",
        "solver.t_end=2.5",
        "--inputs",
        "gaps,mu",
        "--quantities",
        "peak_rotation,peak_x",
    ];
    let whole = dir("whole");
    let w = whole.display().to_string();
    let (ok, out, err) = deckspin(&[&args[..], &["--out", &w]].concat());
    assert!(ok, "{out}{err}");
    assert!(out.contains("5 runs (0 did not finish)"), "{out}");
    let parts = dir("parts");
    let p = parts.display().to_string();
    for k in ["2/2", "1/2"] {
        let (ok, out, err) = deckspin(&[&args[..], &["--out", &p, "--shard", k]].concat());
        assert!(ok, "{out}{err}");
    }
    let merged = dir("merged");
    let part = |k| {
        parts
            .join(format!("sensitivity-part-{k}-of-2.csv"))
            .display()
            .to_string()
    };
    let (ok, out, err) = deckspin(&["merge", &merged.display().to_string(), &part(1), &part(2)]);
    assert!(ok, "{out}{err}");
    for f in [
        "sensitivity.csv",
        "sensitivity-runs.csv",
        "tornado.svg",
        "tornado-peak_rotation.svg",
        "tornado-peak_x.svg",
    ] {
        let a = std::fs::read(whole.join(f)).unwrap();
        let b = std::fs::read(merged.join(f)).unwrap();
        assert!(a == b, "{f} differs");
    }
    let runs = std::fs::read_to_string(whole.join("sensitivity-runs.csv")).unwrap();
    assert_eq!(runs.lines().count(), 1 + 5);
    // a part of another job (other inputs) is refused
    let other = dir("other");
    let o = other.display().to_string();
    let (ok, _, _) = deckspin(&[
        "sensitivity",
        &m,
        "--fix",
        "solver.t_end=2.5",
        "--inputs",
        "gaps,restitution",
        "--quantities",
        "peak_rotation,peak_x",
        "--out",
        &o,
        "--shard",
        "2/2",
    ]);
    assert!(ok);
    let alien = other
        .join("sensitivity-part-2-of-2.csv")
        .display()
        .to_string();
    let (ok, _, err) = deckspin(&["merge", &merged.display().to_string(), &part(1), &alien]);
    assert!(!ok && err.contains("parts of different jobs"), "{err}");
}

#[test]
fn the_specimens_default_tornado_runs_to_its_end() {
    let out = dir("specimen");
    let o = out.display().to_string();
    let m = specimen().display().to_string();
    let (ok, stdout, err) = deckspin(&["sensitivity", &m, "--fix", "solver.t_end=2", "--out", &o]);
    assert!(ok, "{stdout}{err}");
    // 8 defaults (gaps, μ, restitution, column stiffness and yield, damping, actuators, PGA)
    // on 7 runs: 7 × (1 + 2 × 8) runs
    let runs = std::fs::read_to_string(out.join("sensitivity-runs.csv")).unwrap();
    assert_eq!(runs.lines().count(), 1 + 7 * 17);
    assert!(!runs.contains(",failed: ") && !runs.contains(",refused: "));
    // 6 of the 7 default quantities apply (the specimen has no seats)
    let csv = std::fs::read_to_string(out.join("sensitivity.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 8 * 6);
    let peak: Vec<f64> = (csv.lines().skip(1))
        .filter(|l| l.contains(",peak_rotation,"))
        .map(|l| l.split(',').nth(9).unwrap().parse::<f64>().unwrap().abs())
        .collect();
    assert_eq!(peak.len(), 8);
    assert!(peak.windows(2).all(|w| w[0] >= w[1]), "{peak:?}");
    assert!(out.join("tornado.svg").exists() && out.join("tornado-impacts.svg").exists());
}
