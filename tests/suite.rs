//! Record suites (incremental dynamic analysis) and scale-out: each pair scaled by one factor
//! to its level (checked on the records processed here as the model file says), the run's
//! metrics against a run that keeps its whole history, statistics against the rows, shards of
//! `suite` and `sweep` merged byte for byte into the unsharded output, bad arguments named.
mod common;

use deckspin::excitation::{Baseline, G, GroundMotion, Processing, read_any};
use deckspin::progress::Unwatched;
use deckspin::suite::intensity::{Measure, MeasureSpec, Period};
use deckspin::suite::records::{SuitePair, list_pairs};
use deckspin::suite::row::{METRICS, Status, read_csv};
use deckspin::suite::{Suite, SuiteSpec};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn deckspin(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_deckspin"))
        .args(args)
        .output()
        .expect("deckspin runs")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn dir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("suite")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A list of two short pairs (10 s and 14 s once time-scaled), with absolute paths.
fn short_list(d: &Path) -> PathBuf {
    let r = |f: &str| common::root().join("excitations/far-field").join(f);
    let list = d.join("pairs.txt");
    let body = format!(
        "# two short pairs\n{} {}\n{} {} pel\n",
        r("NORTHR_LOS000.AT2").display(),
        r("NORTHR_LOS270.AT2").display(),
        r("SFERN_PEL090.AT2").display(),
        r("SFERN_PEL180.AT2").display()
    );
    std::fs::write(&list, body).unwrap();
    list
}

fn pairs() -> Vec<SuitePair> {
    let list = common::root().join("excitations/pairs.txt");
    let body = "far-field/NORTHR_LOS000.AT2 far-field/NORTHR_LOS270.AT2\n\
                far-field/SFERN_PEL090.AT2 far-field/SFERN_PEL180.AT2 pel\n";
    list_pairs(&list, body).unwrap()
}

fn suite(measure: MeasureSpec, levels: &[f64], axes: &[&str]) -> Suite {
    let axes = (axes.iter())
        .map(|a| deckspin::studies::parse_axis(a).unwrap())
        .collect();
    let spec = SuiteSpec {
        measure,
        levels: levels.to_vec(),
        axes,
        tail: 1.5,
    };
    Suite::open(&common::model("models/four-span.toml"), &[], pairs(), spec)
        .unwrap_or_else(|e| panic!("{e}"))
}

/// A record processed as the four-span model file says (time scale 0.5, cubic baseline,
/// the default taper), unscaled.
fn processed(file: &str) -> GroundMotion {
    let rec = read_any(&common::root().join("excitations/far-field").join(file)).unwrap();
    let p = Processing {
        time_scale: 0.5,
        baseline: Baseline::Polynomial { order: 3 },
        ..Processing::default()
    };
    GroundMotion::from_record(&rec, &p).unwrap()
}

/// The motions of a scene's first `.x` and `.y` supports.
fn components(scene: &deckspin::scene::Scene) -> (GroundMotion, GroundMotion) {
    let m = |axis: &str| {
        (scene.supports.iter())
            .filter(|s| s.name.ends_with(axis))
            .find_map(|s| match &s.motion {
                deckspin::scene::Motion::Record(m) => Some((**m).clone()),
                _ => None,
            })
            .unwrap()
    };
    (m(".x"), m(".y"))
}

#[test]
fn both_components_are_scaled_by_one_factor_to_the_pair_intensity() {
    let sa = MeasureSpec::Sa {
        period: Period::Seconds(0.3),
        damping: 0.05,
    };
    for (measure, levels) in [(MeasureSpec::Pga, [0.25, 0.8]), (sa, [0.4, 1.1])] {
        let s = suite(measure, &levels, &[]);
        assert_eq!(s.runs(), 4);
        for (i, files) in [
            ("NORTHR_LOS000.AT2", "NORTHR_LOS270.AT2"),
            ("NORTHR_LOS000.AT2", "NORTHR_LOS270.AT2"),
            ("SFERN_PEL090.AT2", "SFERN_PEL180.AT2"),
            ("SFERN_PEL090.AT2", "SFERN_PEL180.AT2"),
        ]
        .iter()
        .enumerate()
        {
            let (scene, scale) = s.scene(i).unwrap();
            let (x, y) = components(&scene);
            // the applied motions are the processed records times one factor
            for (applied, file) in [(&x, files.0), (&y, files.1)] {
                let raw = processed(file);
                assert_eq!(applied.acc.len(), raw.acc.len());
                let k = (0..raw.acc.len())
                    .max_by(|&a, &b| raw.acc[a].abs().total_cmp(&raw.acc[b].abs()))
                    .unwrap();
                for j in [k, raw.acc.len() / 3, raw.acc.len() / 2] {
                    let r = applied.acc[j] / raw.acc[j];
                    assert!(
                        (r - scale).abs() <= 1e-13 * scale,
                        "run {i} {file}: {r} vs {scale}"
                    );
                }
            }
            // the pair's intensity is the level: geometric mean of PGA, or of Sa(0.3 s, 5 %)
            let of = |m: &GroundMotion| match measure {
                MeasureSpec::Pga => m.acc.iter().fold(0.0f64, |a, b| a.max(b.abs())) / G,
                _ => {
                    let sa = Measure::Sa {
                        period: 0.3,
                        damping: 0.05,
                    };
                    sa.of_component(&m.acc, m.dt)
                }
            };
            let level = levels[i % 2];
            let got = (of(&x) * of(&y)).sqrt();
            assert!(
                (got - level).abs() <= 1e-12 * level,
                "run {i}: {got} vs {level}"
            );
            // to the end of the longer record plus the tail
            let end = x.end_time().max(y.end_time());
            assert_eq!(scene.settings.t_end, end + 1.5);
        }
    }
}

#[test]
fn a_run_records_what_its_whole_history_shows() {
    let s = suite(MeasureSpec::Pga, &[0.7], &[]);
    let rows = s.run(0..2, &Unwatched);
    assert_eq!(rows.len(), 2);
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row.status, Status::Finished, "{row:?}");
        let (scene, scale) = s.scene(i).unwrap();
        assert_eq!(row.scale, Some(scale));
        let full = deckspin::run(&scene, &mut deckspin::Silent).unwrap();
        // the columns of four-span.toml: bents 1–3, 1.83, 2.44 and 1.52 m high
        let mut drift = 0.0f64;
        for (bent, h) in [("bent1", 1.83), ("bent2", 2.44), ("bent3", 1.52)] {
            for side in ["top", "bottom"] {
                let at = |a: &str| {
                    let name = format!("{bent}_{side}.{a}");
                    full.element_names.iter().position(|n| *n == name).unwrap()
                };
                let (x, y) = (at("x"), at("y"));
                for smp in &full.samples {
                    drift = drift.max(smp.elements[x].0.hypot(smp.elements[y].0) / h);
                }
            }
        }
        let m = |name: &str| row.metrics[METRICS.iter().position(|x| *x == name).unwrap()];
        assert_eq!(m("max_drift_ratio"), Some(drift));
        assert!(drift > 1e-3, "{drift}");
        let theta = full.dof("deck.theta").unwrap();
        let p = &full.summary.peaks[theta];
        assert_eq!(m("peak_rotation"), Some(p.max_abs));
        assert_eq!(m("residual_rotation"), Some(p.residual.abs()));
        let e = full.samples.last().unwrap().energy;
        assert_eq!(
            m("energy_impacts"),
            Some(e.impact_normal + e.impact_tangential)
        );
        assert_eq!(m("energy_columns"), Some(e.hysteretic));
        assert_eq!(m("impacts"), Some(common::impacts(&full).len() as f64));
        assert!(m("impacts").unwrap() > 0.0);
        // no seats, no keys in this model: empty
        assert_eq!((m("min_seat_margin"), m("key_failures")), (None, None));
    }
}

#[test]
fn sa_at_t1_is_at_the_first_mode_period() {
    let t1 = MeasureSpec::Sa {
        period: Period::FirstMode,
        damping: 0.02,
    };
    let s = suite(t1, &[0.5], &[]);
    let scene = deckspin::load(&common::model("models/four-span.toml"), &[]).unwrap();
    let period = (deckspin::modal::modes(&scene).iter())
        .map(|m| m.period)
        .fold(0.0, f64::max);
    assert!((period - 0.38924).abs() < 1e-5, "{period}");
    let want = Measure::Sa {
        period,
        damping: 0.02,
    };
    assert_eq!(s.measure, want);
    assert!(want.label().starts_with("sa(0.3892") && want.label().ends_with("s,2%)"));
}

#[test]
fn keys_the_suite_sets_itself_are_refused_by_argument() {
    let spec = |axes: &[&str]| SuiteSpec {
        measure: MeasureSpec::Pga,
        levels: vec![0.5],
        axes: axes
            .iter()
            .map(|a| deckspin::studies::parse_axis(a).unwrap())
            .collect(),
        tail: 2.0,
    };
    let model = common::model("models/four-span.toml");
    let open = |fix: &[String], axes: &[&str]| {
        Suite::open(&model, fix, pairs(), spec(axes))
            .err()
            .unwrap()
            .to_string()
    };
    let e = open(&[], &["excitation.run=1,2"]);
    assert!(
        e.starts_with("'excitation.run': the suite sets excitation.run itself"),
        "{e}"
    );
    let e = open(&["solver.t_end=3".into()], &[]);
    assert!(
        e.starts_with("'solver.t_end=3': the suite sets solver.t_end"),
        "{e}"
    );
    let e = open(&["run.0.pga_x=3".into()], &[]);
    assert!(e.contains("the suite sets run itself"), "{e}");
    // a harmonic model has no records to scale
    let e = Suite::open(
        &common::model("models/validation/bouncing-ball.toml"),
        &[],
        pairs(),
        spec(&[]),
    )
    .err()
    .unwrap()
    .to_string();
    assert!(
        e.contains("needs a bridge file whose [excitation] table has kind = \"record\""),
        "{e}"
    );
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn a_sharded_suite_merges_into_the_unsharded_output_byte_for_byte() {
    let d = dir("shards");
    let list = short_list(&d);
    let args = |out: &Path, shard: Option<&str>| {
        let mut a: Vec<String> = [
            "suite",
            &common::model("models/four-span.toml").display().to_string(),
            "--records",
            &list.display().to_string(),
            "--measure",
            "sa:0.3",
            "--levels",
            "0.3:0.6:0.3",
            "--set",
            "contacts.mu=0.2,0.6",
            "--tail",
            "1",
            "--out",
            &out.display().to_string(),
        ]
        .map(String::from)
        .to_vec();
        if let Some(s) = shard {
            a.extend(["--shard".to_string(), s.to_string()]);
        }
        a
    };
    let run = |a: Vec<String>| {
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        let r = deckspin(&a);
        assert!(r.status.success(), "{}", text(&r.stderr));
        r
    };
    let whole = d.join("whole.csv");
    let r = run(args(&whole, None));
    // no progress bar where stderr is not a terminal: only the timing line
    let err = text(&r.stderr);
    assert!(
        err.lines().count() == 1 && err.starts_with("8 runs in "),
        "{err:?}"
    );
    let parts: Vec<PathBuf> = (1..=3).map(|k| d.join(format!("part{k}.csv"))).collect();
    for (k, p) in parts.iter().enumerate() {
        run(args(p, Some(&format!("{}/3", k + 1))));
    }
    let first = read(&parts[0]);
    assert!(first.starts_with("#deckspin-part kind=suite shard=1/3 runs=8 version="));
    assert!(first.lines().nth(1).unwrap().starts_with("run,pair,"));
    assert!(first.ends_with(&format!(
        "#deckspin-end rows={}\n",
        first.lines().count() - 3
    )));
    let merged = d.join("merged.csv");
    let m = |ps: &[&PathBuf]| {
        let mut a = vec!["merge".to_string(), merged.display().to_string()];
        a.extend(ps.iter().map(|p| p.display().to_string()));
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        deckspin(&a)
    };
    let r = m(&[&parts[2], &parts[0], &parts[1]]);
    assert!(r.status.success(), "{}", text(&r.stderr));
    for (a, b) in [
        ("whole.csv", "merged.csv"),
        ("whole-stats.csv", "merged-stats.csv"),
        ("whole-stats.json", "merged-stats.json"),
    ] {
        assert_eq!(read(&d.join(a)), read(&d.join(b)), "{a} vs {b}");
    }
    // the rows: 2 pairs × 2 levels × 2 μ, the swept key's column between scale and status
    let csv = read(&whole);
    assert!(csv.starts_with(
        "pair,longitudinal,transverse,measure,level,scale,contacts.mu,status,peak_rotation,"
    ));
    let (keys, rows) = read_csv(&csv).unwrap();
    assert_eq!(keys, vec!["contacts.mu"]);
    let labels: Vec<(&str, f64, &str)> = (rows.iter())
        .map(|r| (r.pair.as_str(), r.level, r.settings[0].1.as_str()))
        .collect();
    assert_eq!(
        labels[..3],
        [
            ("NORTHR_LOS", 0.3, "0.2"),
            ("NORTHR_LOS", 0.3, "0.6"),
            ("NORTHR_LOS", 0.6, "0.2")
        ]
    );
    assert_eq!(labels[7], ("pel", 0.6, "0.6"));
    assert!(
        rows.iter()
            .all(|r| r.measure == "sa(0.3s,5%)" && r.status == Status::Finished)
    );
    // a pair's scale is proportional to the level
    let ratio = rows[2].scale.unwrap() / rows[0].scale.unwrap();
    assert!((ratio - 2.0).abs() < 1e-14, "{ratio}");
    // the statistics: median of the two pairs' peak rotations at each level and μ
    let stats = read(&d.join("whole-stats.csv"));
    let lines: Vec<&str> = stats.lines().collect();
    assert_eq!(lines.len(), 5);
    let mut n = deckspin::output::number::Numbers::new();
    let median = 0.5 * (rows[1].metrics[0].unwrap() + rows[5].metrics[0].unwrap());
    let head = format!("\"sa(0.3s,5%)\",0.3,0.6,2,2,0,0,,{},", n.format(median));
    assert!(lines[2].starts_with(&head), "{} vs {head}", lines[2]);
    // missing and doubled parts are refused
    let r = m(&[&parts[0], &parts[2]]);
    assert!(!r.status.success());
    assert!(
        text(&r.stderr).contains("shards missing: 2 of 3"),
        "{}",
        text(&r.stderr)
    );
    let r = m(&[&parts[0], &parts[1], &parts[1], &parts[2]]);
    assert!(
        text(&r.stderr).contains("shard 2/3 is given twice"),
        "{}",
        text(&r.stderr)
    );
    // a part of another job (another measure, other levels) is refused, naming what differs
    for (flag, value) in [("--measure", "pga"), ("--levels", "0.4:0.7:0.3")] {
        let other = d.join("other.csv");
        let mut a = args(&other, Some("2/3"));
        let at = a.iter().position(|x| x == flag).unwrap();
        a[at + 1] = value.into();
        run(a);
        let r = m(&[&parts[0], &other, &parts[2]]);
        assert_eq!(r.status.code(), Some(1), "{flag}");
        let e = text(&r.stderr);
        assert!(
            e.contains("the arguments' fingerprint") && e.contains("parts of different jobs"),
            "{flag}: {e}"
        );
    }
}

#[test]
fn bad_arguments_are_named() {
    let d = dir("bad");
    let list = short_list(&d);
    let l = list.display().to_string();
    let model = common::model("models/four-span.toml").display().to_string();
    let run = |extra: &[&str]| {
        let mut a = vec!["suite", &model, "--records", &l, "--measure", "pga"];
        a.extend(extra);
        let r = deckspin(&a);
        assert_eq!(r.status.code(), Some(1), "{extra:?}");
        text(&r.stderr)
    };
    let e = run(&["--levels", "0.5", "--shard", "4/3"]);
    assert!(
        e.contains("--shard '4/3': K = 4 is not within 1..=3"),
        "{e}"
    );
    let e = run(&["--levels", "0.5:0.1:0.1"]);
    assert!(e.contains("--levels '0.5:0.1:0.1'"), "{e}");
    let e = run(&["--levels", "0.5", "--damping", "0.05"]);
    assert!(
        e.contains("--damping '0.05': applies to --measure sa:T only"),
        "{e}"
    );
    let e = run(&["--levels", "0.5", "--set", "excitation.transverse=a,b"]);
    assert!(e.contains("'excitation.transverse': the suite sets"), "{e}");
    std::fs::write(&list, "# x\nNORTHR_LOS000.AT2\n").unwrap();
    let e = run(&["--levels", "0.5"]);
    assert!(e.contains("pairs.txt:2: 1 fields"), "{e}");
    let o = d.join("s.csv").display().to_string();
    let r = deckspin(&[
        "sweep",
        &model,
        "--set",
        "contacts.mu=0.1",
        "--shard",
        "1/x",
        "--out",
        &o,
    ]);
    assert!(text(&r.stderr).contains("--shard '1/x': N 'x' is not a whole number"));
    let r = deckspin(&["merge", &o, &l]);
    assert!(
        text(&r.stderr).contains("pairs.txt:1: not a part file"),
        "{}",
        text(&r.stderr)
    );
    // too many runs: refused before it starts, exit 2
    let r = deckspin(&[
        "suite",
        &model,
        "--records",
        &common::root()
            .join("excitations/far-field")
            .display()
            .to_string(),
        "--measure",
        "pga",
        "--levels",
        "0.01:100:0.01",
        "--set",
        "contacts.mu=0:1:0.1",
        "--out",
        &o,
    ]);
    assert_eq!(r.status.code(), Some(2));
    assert!(
        text(&r.stderr).contains("limit of 100000"),
        "{}",
        text(&r.stderr)
    );
}
