//! The command line's robustness: `run` writes its files however the run ends, streams its
//! history (memory independent of `t_end`), refuses runs and sweeps above their limits before
//! they start (exit 2); a sweep with failing runs writes every row; a sweep cut into shards
//! merges into the unsharded CSV byte for byte.
mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// `deckspin args`, killed (and the test failed) after 60 s: a limit that no longer refuses
/// must not leave the test running.
fn deckspin(args: &[&str]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_deckspin"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("deckspin runs");
    let drain = |r: Option<Box<dyn std::io::Read + Send>>| {
        std::thread::spawn(move || {
            let mut buf = Vec::new();
            if let Some(mut r) = r {
                r.read_to_end(&mut buf).unwrap();
            }
            buf
        })
    };
    let stdout = drain(child.stdout.take().map(|r| Box::new(r) as _));
    let stderr = drain(child.stderr.take().map(|r| Box::new(r) as _));
    // a hang by the child's CPU, not the wall clock (a busy machine is no hang)
    let mut watch = common::HangWatch::new(child.id(), 120.0, 300);
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if let Some(why) = watch.hangs() {
            child.kill().unwrap();
            child.wait().unwrap();
            panic!("deckspin {args:?} hangs: {why}");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    Output {
        status,
        stdout: stdout.join().unwrap(),
        stderr: stderr.join().unwrap(),
    }
}

fn model(rel: &str) -> String {
    common::model(rel).display().to_string()
}

fn dir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("cli")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(d.parent().unwrap()).unwrap();
    d
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn a_failed_run_writes_its_files_and_exits_1() {
    let out = dir("failed");
    let o = out.display().to_string();
    let r = deckspin(&[
        "run",
        &model("models/four-span.toml"),
        "--out",
        &o,
        "--set",
        "solver.max_steps=2000",
    ]);
    assert_eq!(r.status.code(), Some(1), "{}", text(&r.stderr));
    let stderr = text(&r.stderr);
    // "deckspin: t = 6.69… s: more than 2000 steps": the instant is the engine's
    let said: f64 = (stderr
        .split("t = ")
        .nth(1)
        .and_then(|x| x.split(' ').next()))
    .and_then(|x| x.parse().ok())
    .unwrap_or_else(|| panic!("{stderr}"));
    assert!(
        stderr.contains(&format!("t = {said:.9} s: more than 2000 steps")) && said > 2.0,
        "{stderr}"
    );
    assert!(text(&r.stdout).contains(&format!("up to t = {said:.9} s")));
    let s = json(&out.join("summary.json"));
    assert_eq!(s["status"], "failed");
    assert_eq!(s["failure"]["kind"], "TooManySteps");
    let t = s["failure"]["t"].as_f64().unwrap();
    assert!((t - said).abs() < 1e-9, "{t}");
    let history = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let last: f64 = (history.lines().last().unwrap().split(',').next().unwrap())
        .parse()
        .unwrap();
    assert!(last > 1.9 && last <= t, "last row at {last}");
    assert!(out.join("events.csv").exists());
    assert_eq!(s["t_end"].as_f64().unwrap(), last);
}

#[test]
fn a_finished_run_reports_its_status() {
    let out = dir("finished");
    let o = out.display().to_string();
    let r = deckspin(&[
        "run",
        &model("models/validation/bouncing-ball.toml"),
        "--out",
        &o,
    ]);
    assert!(r.status.success(), "{}", text(&r.stderr));
    let s = json(&out.join("summary.json"));
    assert_eq!(s["status"], "finished");
    assert!(s.get("failure").is_none());
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.starts_with("{\n  \"status\": \"finished\",\n  \"title\""));
}

/// Exit status and peak resident memory (kB) of `deckspin args`.
#[allow(clippy::zombie_processes)] // reaped by wait4, which reports its peak memory
fn peak_memory(args: &[&str]) -> (i32, i64) {
    let child = Command::new(env!("CARGO_BIN_EXE_deckspin"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut status = 0;
    // SAFETY: rusage is plain data; wait4 fills it for this child, which it reaps
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    let pid = unsafe { libc::wait4(child.id() as libc::pid_t, &mut status, 0, &mut usage) };
    assert_eq!(pid, child.id() as libc::pid_t);
    (libc::WEXITSTATUS(status), usage.ru_maxrss)
}

#[test]
fn a_long_run_streams_its_history_in_bounded_memory() {
    // 1e6 rows of a block at rest after 1 s: it used to hold them all (239 MB)
    let out = dir("long");
    std::fs::create_dir_all(&out).unwrap();
    std::os::unix::fs::symlink("/dev/null", out.join("history.csv")).unwrap();
    let o = out.display().to_string();
    let m = model("models/validation/block-on-plane.toml");
    let run = |t_end: &str| {
        let t = format!("solver.t_end={t_end}");
        peak_memory(&[
            "run",
            &m,
            "--out",
            &o,
            "--set",
            &t,
            "--set",
            "solver.output_dt=1e-3",
        ])
    };
    let (code, long) = run("1000");
    assert_eq!(code, 0);
    let s = json(&out.join("summary.json"));
    assert_eq!(s["t_end"].as_f64(), Some(1000.0));
    let (code, short) = run("10");
    assert_eq!(code, 0);
    assert!(long < 40_000, "peak {long} kB for 1e6 rows");
    assert!(
        long < short + 8_000,
        "peak {long} kB for 1e6 rows, {short} kB for 1e4"
    );
}

#[test]
fn runs_above_the_limits_are_refused_before_they_start() {
    let out = dir("refused");
    let o = out.display().to_string();
    let m = model("models/validation/block-on-plane.toml");
    let r = deckspin(&[
        "run",
        &m,
        "--out",
        &o,
        "--set",
        "solver.t_end=1e5",
        "--set",
        "solver.output_dt=1e-3",
    ]);
    assert_eq!(r.status.code(), Some(2));
    let e = text(&r.stderr);
    for part in [
        "solver.t_end = 100000 s",
        "solver.output_dt = 0.001 s",
        "1.100e8 rows",
        "5e7 rows",
    ] {
        assert!(e.contains(part), "'{part}' not in: {e}");
    }
    assert!(!out.exists(), "a refused run wrote {}", out.display());
    let r = deckspin(&[
        "run",
        &m,
        "--out",
        &o,
        "--method",
        "moreau",
        "--set",
        "solver.step=1e-3",
        "--set",
        "solver.t_end=1e6",
    ]);
    assert_eq!(r.status.code(), Some(2));
    let e = text(&r.stderr);
    // max_steps absent: 2e5 per second of t_end, at most 5e7
    assert!(
        e.contains("1.000e9 steps") && e.contains("solver.max_steps = 50000000"),
        "{e}"
    );
    assert!(!out.exists());
}

#[test]
fn sweeps_are_capped_by_the_product_of_their_axes() {
    let csv = dir("sweep-cap").join("sweep.csv");
    let c = csv.display().to_string();
    let r = deckspin(&[
        "sweep",
        &model("models/four-span.toml"),
        "--set",
        "contacts.mu=0:1:0.0001",
        "--set",
        "excitation.run=1:30000:1",
        "--out",
        &c,
    ]);
    assert_eq!(r.status.code(), Some(2));
    let e = text(&r.stderr);
    assert!(
        e.contains("300030000 runs") && e.contains("limit of 100000"),
        "{e}"
    );
    assert!(!csv.exists());
    // at the cap: every combination is counted, none run
    let axes = [
        deckspin::studies::parse_axis("a=1:1000:1").unwrap(),
        deckspin::studies::parse_axis("b=1:100:1").unwrap(),
    ];
    assert_eq!(
        deckspin::studies::sweep_size(&axes, 100_000).unwrap(),
        100_000
    );
    let e = deckspin::studies::sweep_size(&axes, 99_999).unwrap_err();
    assert_eq!((e.runs, e.cap), (100_000, 99_999));
}

#[test]
fn a_sweep_with_failing_runs_writes_every_row() {
    let csv = dir("sweep-failing").join("sweep.csv");
    let c = csv.display().to_string();
    let r = deckspin(&[
        "sweep",
        &model("models/four-span.toml"),
        "--set",
        "solver.max_steps=2000,1000000",
        "--set",
        "contacts.mu=0,0.3",
        "--out",
        &c,
    ]);
    assert_eq!(r.status.code(), Some(1), "{}", text(&r.stderr));
    let rows = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<&str> = rows.lines().skip(1).collect();
    assert_eq!(rows.len(), 4);
    assert_eq!(
        rows.iter()
            .filter(|l| l.contains("more than 2000 steps"))
            .count(),
        2
    );
    assert!(rows[2].starts_with("1000000,0,") && rows[2].ends_with(","));
}

#[test]
fn a_study_whose_runs_would_not_fit_in_memory_is_refused_before_it_starts() {
    // each work–precision run keeps its history: 16 s at 1e-9 s would be 1.6e10 rows
    let r = deckspin(&[
        "precision",
        &model("models/four-span.toml"),
        "--quick",
        "--set",
        "solver.output_dt=1e-9",
    ]);
    assert_ne!(r.status.code(), Some(0));
    let e = text(&r.stderr);
    assert!(
        e.contains("1.600e10 rows") && e.contains("1e6") && e.contains("solver.output_dt"),
        "{e}"
    );
}

#[test]
fn screen_marks_the_specimen_and_writes_its_corners() {
    let root = common::model("");
    let out = std::env::temp_dir().join(format!("deckspin-screen-{}", std::process::id()));
    let model = root.join("models/four-span.toml");
    let o = deckspin(&[
        "screen",
        model.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(text.matches("stays straight").count(), 3, "{text}"); // two ends and the legend
    assert_eq!(text.matches('@').count(), 3, "{text}"); // both maps and the legend
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("screen.json")).unwrap()).unwrap();
    let corners = json["corners_rigid_face"].as_array().unwrap();
    assert_eq!(corners.len(), 4);
    let mu = corners[0]["impact"]["stick_mu"].as_f64().unwrap();
    assert!(
        (mu - 16.1 * 1.2 / (13090.0 / 140.5 + 16.1 * 16.1)).abs() < 1e-12,
        "{mu}"
    );
    let csv = std::fs::read_to_string(out.join("screen-map.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 31 * 13);
    // both maps as SVG grids: 31 × 13 cells, the specimen's one marked
    for name in ["screen-flush.svg", "screen-corner.svg"] {
        let s = std::fs::read_to_string(out.join(name)).unwrap();
        let doc = roxmltree::Document::parse(&s).unwrap();
        let cells = (doc.descendants())
            .filter(|n| n.attribute("class") == Some("cell"))
            .count();
        assert_eq!(cells, 31 * 13, "{name}");
        let marks = (doc.descendants())
            .filter(|n| n.is_text() && n.text() == Some("@"))
            .count();
        assert_eq!(marks, 1, "{name}");
    }
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn a_sharded_sweep_merges_into_the_unsharded_output_byte_for_byte() {
    let d = dir("sweep-shards");
    std::fs::create_dir_all(&d).unwrap();
    let model = model("models/four-span.toml");
    let sweep = |out: &Path, shard: Option<&str>| {
        let o = out.display().to_string();
        let mut a = vec![
            "sweep",
            &model,
            "--set",
            "contacts.mu=0.1,0.5,0.9",
            "--set",
            "excitation.run=1,4",
            "--fix",
            "solver.t_end=4",
            "--out",
            &o,
        ];
        if let Some(s) = shard {
            a.extend(["--shard", s]);
        }
        let r = deckspin(&a);
        assert!(r.status.success(), "{}", text(&r.stderr));
        assert!(r.stderr.is_empty(), "{}", text(&r.stderr));
    };
    let whole = d.join("whole.csv");
    sweep(&whole, None);
    let parts: Vec<PathBuf> = (1..=4).map(|k| d.join(format!("p{k}.csv"))).collect();
    for (k, p) in parts.iter().enumerate() {
        sweep(p, Some(&format!("{}/4", k + 1)));
    }
    let merged = d.join("merged.csv");
    let merge = |ps: &[&PathBuf]| {
        let mut a = vec!["merge".to_string(), merged.display().to_string()];
        a.extend(ps.iter().map(|p| p.display().to_string()));
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        deckspin(&a)
    };
    let r = merge(&parts.iter().rev().collect::<Vec<_>>());
    assert!(r.status.success(), "{}", text(&r.stderr));
    let w = std::fs::read_to_string(&whole).unwrap();
    assert_eq!(w, std::fs::read_to_string(&merged).unwrap());
    assert_eq!(w.lines().count(), 7);
    assert!(w.starts_with("contacts.mu,excitation.run,peak_rotation,"));
    assert!(!w.contains("wall"));
    // a part of another job (another --fix) is refused, naming what differs
    let other = d.join("other.csv");
    let o = other.display().to_string();
    let r = deckspin(&[
        "sweep",
        &model,
        "--set",
        "contacts.mu=0.1,0.5,0.9",
        "--set",
        "excitation.run=1,4",
        "--fix",
        "solver.t_end=3",
        "--out",
        &o,
        "--shard",
        "2/4",
    ]);
    assert!(r.status.success(), "{}", text(&r.stderr));
    let r = merge(&[&parts[0], &other, &parts[2], &parts[3]]);
    assert_eq!(r.status.code(), Some(1));
    let e = text(&r.stderr);
    assert!(
        e.contains("the arguments' fingerprint") && e.contains("parts of different jobs"),
        "{e}"
    );
    // a part cut inside its last number is refused
    let cut = d.join("cut.csv");
    let p2 = std::fs::read_to_string(&parts[1]).unwrap();
    let body = &p2[..p2.rfind("#deckspin-end").unwrap()];
    std::fs::write(&cut, &body[..body.len() - 3]).unwrap();
    let r = merge(&[&parts[0], &cut, &parts[2], &parts[3]]);
    assert_eq!(r.status.code(), Some(1));
    assert!(text(&r.stderr).contains("cut short"), "{}", text(&r.stderr));
}

/// The SVG at `path`, parsed back: the texts of its legend and its number of polylines.
fn svg_legend(path: &Path) -> (Vec<String>, usize) {
    let s = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let doc = roxmltree::Document::parse(&s).unwrap_or_else(|e| panic!("{e}"));
    let legend: Vec<String> = (doc.descendants())
        .filter(|n| n.attribute("class") == Some("legend"))
        .flat_map(|g| g.descendants().filter(|n| n.tag_name().name() == "text"))
        .filter_map(|n| n.text().map(String::from))
        .collect();
    let lines = (doc.descendants())
        .filter(|n| n.attribute("class") == Some("series"))
        .count();
    (legend, lines)
}

#[test]
fn studies_precision_and_stability_write_their_charts() {
    let out = dir("charts");
    let o = out.display().to_string();
    let r = deckspin(&["study", "pga", &model("models/four-span.toml"), "--out", &o]);
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let (legend, lines) = svg_legend(&out.join("rotation_vs_pga.svg"));
    assert_eq!(legend, ["without contact", "with contact"]);
    assert_eq!(lines, 2);
    // stdout is not a terminal here: the table without the text chart
    assert!(!text(&r.stdout).contains("P(exceed)") && !text(&r.stdout).contains("+---"));
    let r = deckspin(&["study", "mu", &model("models/four-span.toml"), "--out", &o]);
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let (legend, lines) = svg_legend(&out.join("increase_vs_mu.svg"));
    // seven runs, their mean, the no-contact line
    assert_eq!(legend.len(), 9, "{legend:?}");
    assert_eq!(
        (legend[0].as_str(), legend[7].as_str()),
        ("run 1 (0.09 g)", "mean")
    );
    assert_eq!(lines, 8);
    let ball = model("models/validation/bouncing-ball.toml");
    let r = deckspin(&["precision", &ball, "--quick", "--out", &o]);
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let (legend, _) = svg_legend(&out.join("precision-bouncing-ball.svg"));
    assert_eq!(legend.first().map(String::as_str), Some("event-driven"));
    assert_eq!(legend.last().map(String::as_str), Some("1 %"));
    let txt = std::fs::read_to_string(out.join("precision-bouncing-ball.txt")).unwrap();
    assert!(
        txt.contains("Work-precision\nRMS history error (relative)\n"),
        "{txt}"
    );
    // each point with the verdict stability gives it, never a bare "ok" beside a large error
    assert!(
        txt.contains("inaccurate (peak") && txt.contains("ok (peak"),
        "{txt}"
    );
    assert!(!txt.lines().any(|l| l.trim_end().ends_with(" ok")), "{txt}");
    let r = deckspin(&["stability", &ball, "--quick", "--out", &o]);
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let s = std::fs::read_to_string(out.join("stability-bouncing-ball.svg")).unwrap();
    let doc = roxmltree::Document::parse(&s).unwrap();
    let cells = (doc.descendants())
        .filter(|n| n.attribute("class") == Some("cell"))
        .count();
    // three knobs of each of the four methods (--quick)
    assert_eq!(cells, 12);
    // the grid's numbers as CSV: a line per cell, its verdict matching the printed table
    let csv = std::fs::read_to_string(out.join("stability-bouncing-ball.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("method,knob,verdict,peak_error,history_error,steps,cpu_s,reason")
    );
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 12, "{csv}");
    let printed = text(&r.stdout);
    for row in &rows {
        let f: Vec<&str> = row.split(',').collect();
        assert!(
            ["ok", "inaccurate", "unstable", "failed"].contains(&f[2]),
            "{row}"
        );
        let line = (printed.lines())
            .find(|l| l.starts_with(f[0]) && l.contains(f[1]))
            .unwrap_or_else(|| panic!("{row} not printed:\n{printed}"));
        assert!(line.contains(f[2]), "{row} vs {line}");
    }
}

#[test]
fn modes_name_every_dof_in_full_and_print_no_negative_zero() {
    let r = deckspin(&["modes", &model("models/four-span.toml")]);
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let out = text(&r.stdout);
    let header = out.lines().nth(1).unwrap();
    for name in [
        "left_abutment.x",
        "left_abutment.theta",
        "deck.theta",
        "right_abutment.theta",
    ] {
        assert!(header.contains(name), "{header}");
    }
    assert!(!out.contains("-0.0000"), "{out}");
    // mode 1: the deck's transverse sway with its rotation, -0.1814 rad per m
    assert!(out.lines().nth(2).unwrap().contains("-0.1814"), "{out}");
}

/// Methods and studies are named from one list each (clap value enums): an unknown name is
/// refused before any run (exit 2) with the names it could be.
#[test]
fn unknown_methods_and_studies_are_refused_with_the_known_names() {
    let m = model("models/four-span.toml");
    let o = dir("unknown-names").join("out").display().to_string();
    for args in [
        vec!["run", &m, "--out", &o, "--method", "newmark"],
        vec!["precision", &m, "--out", &o, "--methods", "event,newmark"],
        vec!["study", "pgv", &m, "--out", &o],
        vec!["sequence", &m, "--out", &o, "--study", "pgv"],
    ] {
        let r = deckspin(&args);
        assert_eq!(r.status.code(), Some(2), "{args:?}");
        let e = text(&r.stderr);
        let names = if args.contains(&"pgv") {
            "[possible values: pga, mu]"
        } else {
            "[possible values: event, moreau, penalty, penalty-explicit]"
        };
        assert!(e.contains(names), "{args:?}: {e}");
        assert!(!std::path::Path::new(&o).exists(), "{args:?} wrote {o}");
    }
    // a known name goes through to the model: the method is the run's (Moreau–Jean chooses
    // its step from K₀ and says so)
    let r = deckspin(&[
        "run",
        &m,
        "--out",
        &o,
        "--method",
        "moreau",
        "--set",
        "solver.t_end=0.05",
    ]);
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    assert!(
        text(&r.stderr).contains("moreau chose solver.step"),
        "{}",
        text(&r.stderr)
    );
}
