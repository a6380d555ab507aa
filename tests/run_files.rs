//! A run streamed to files ([`RunFiles`]): the same bytes as the in-memory writers, files
//! written however the run ends, the output holding only what was not handed over, and the
//! limits checked before a run.
mod common;

use deckspin::Stop;
use deckspin::run::{LimitError, OutputBudget, OutputEstimate, RunFiles, check_output};
use deckspin::scene::Scene;
use std::path::PathBuf;

fn scene(rel: &str, set: &[&str]) -> Scene {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    deckspin::load(&common::model(rel), &set).unwrap_or_else(|e| panic!("{e}"))
}

fn dir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("run_files")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn read(d: &std::path::Path, f: &str) -> String {
    std::fs::read_to_string(d.join(f)).unwrap_or_else(|e| panic!("{}: {e}", d.join(f).display()))
}

/// The run streamed into `d`, and the same scene run in memory with its files written by
/// `RunOutput`'s writers into `d/memory`.
fn streamed_and_in_memory(scene: &Scene, d: &std::path::Path) -> (deckspin::Run, deckspin::Run) {
    let mut files = RunFiles::create(d, scene, None).unwrap();
    let streamed = deckspin::simulate::integrate(scene, &mut files);
    files.finish(&streamed).unwrap();
    let memory = deckspin::simulate::integrate(scene, &mut deckspin::Silent);
    memory.output.write_all(&d.join("memory")).unwrap();
    (streamed, memory)
}

#[test]
fn a_streamed_history_has_the_bytes_of_the_in_memory_writer() {
    let cases: [(&str, &[&str]); 5] = [
        ("models/four-span.toml", &[]),
        ("models/validation/elastic-rattle.toml", &[]),
        ("models/validation/bouncing-ball.toml", &[]),
        // fixed-step methods record their last sample after their last batch
        (
            "models/validation/double-impact.toml",
            &["solver.method=\"moreau\""],
        ),
        (
            "models/validation/corner-impact.toml",
            &["solver.method=\"penalty\""],
        ),
    ];
    for (i, (model, set)) in cases.iter().enumerate() {
        let s = scene(model, set);
        let d = dir(&format!("same-bytes-{i}"));
        let (streamed, memory) = streamed_and_in_memory(&s, &d);
        assert!(streamed.finished() && memory.finished(), "{model}");
        let history = read(&d, "history.csv");
        assert_eq!(history, read(&d.join("memory"), "history.csv"), "{model}");
        assert_eq!(
            read(&d, "events.csv"),
            read(&d.join("memory"), "events.csv"),
            "{model}"
        );
        // the header and one row per sample the in-memory run kept
        assert_eq!(history.lines().count(), memory.output.samples.len() + 1);
        assert!(memory.output.samples.len() > 50, "{model}");
        // the streamed output kept only the samples after its last batch: none
        assert!(
            streamed.output.samples.is_empty(),
            "{model}: {} samples kept",
            streamed.output.samples.len()
        );
    }
}

#[test]
fn the_summary_of_a_finished_run_gains_only_its_status_line() {
    let s = scene("models/validation/oscillator-stop.toml", &[]);
    let run = deckspin::simulate::integrate(&s, &mut deckspin::Silent);
    assert!(run.finished());
    let old = serde_json::to_string_pretty(&run.output.summary).unwrap();
    let new = run.summary_json().unwrap();
    assert_eq!(
        new,
        old.replacen("{\n", "{\n  \"status\": \"finished\",\n", 1)
    );
    let d = dir("summary");
    run.write_all(&d).unwrap();
    assert_eq!(read(&d, "summary.json"), new);
}

/// The failed run streamed into `d`: its error, the summary's failure, the history's times.
fn failed_streamed(
    s: &Scene,
    d: &std::path::Path,
) -> (deckspin::SolverError, serde_json::Value, Vec<f64>) {
    let mut files = RunFiles::create(d, s, None).unwrap();
    let run = deckspin::simulate::integrate(s, &mut files);
    files.finish(&run).unwrap();
    let Stop::Failed(e) = run.stop else {
        panic!("expected a failure, got {:?}", run.stop)
    };
    let json: serde_json::Value = serde_json::from_str(&read(d, "summary.json")).unwrap();
    let times = (read(d, "history.csv").lines().skip(1))
        .map(|l| l.split(',').next().unwrap().parse::<f64>().unwrap())
        .collect();
    (e, json, times)
}

#[test]
fn a_failed_run_writes_its_files_up_to_the_failure() {
    // event-driven: the step limit; penalty-explicit: unstable (its last rows come after its
    // last batch)
    let cases: [(&[&str], &str, f64); 2] = [
        (&["solver.max_steps=2000"], "TooManySteps", f64::NAN),
        (
            &["solver.method=\"penalty-explicit\"", "solver.step=1e-3"],
            "Unstable",
            2.628,
        ),
    ];
    for (i, (set, kind, t_fail)) in cases.iter().enumerate() {
        let s = scene("models/four-span.toml", set);
        let d = dir(&format!("failed-{i}"));
        let (e, json, times) = failed_streamed(&s, &d);
        // the step limit's instant is the engine's; the explicit penalty's is the step grid's
        assert!(
            t_fail.is_nan() && e.time() > 2.0 || (e.time() - t_fail).abs() < 1e-9,
            "{kind}: t = {}",
            e.time()
        );
        assert_eq!(json["status"], "failed");
        assert_eq!(json["failure"]["kind"], *kind);
        assert_eq!(json["failure"]["reason"], e.to_string());
        let t = json["failure"]["t"].as_f64().unwrap();
        assert!(
            (t - e.time()).abs() <= 1e-12 * e.time(),
            "{t} vs {}",
            e.time()
        );
        let last = *times.last().unwrap();
        assert!(
            last > 0.0 && last <= e.time(),
            "last row at {last}, failure at {t}"
        );
        assert!(last > e.time() - 0.01, "last row at {last}, failure at {t}");
        // the rows are the in-memory run's, byte for byte
        let memory = deckspin::simulate::integrate(&s, &mut deckspin::Silent);
        memory.output.write_all(&d.join("memory")).unwrap();
        assert_eq!(
            read(&d, "history.csv"),
            read(&d.join("memory"), "history.csv")
        );
        assert_eq!(times.len(), memory.output.samples.len());
        assert_eq!(
            read(&d, "events.csv"),
            read(&d.join("memory"), "events.csv")
        );
    }
}

#[test]
fn the_estimate_bounds_the_history_written() {
    let s = scene("models/four-span.toml", &[]);
    let est = check_output(&s, &OutputBudget::default()).unwrap();
    // t_end 16 s / output_dt 0.005 s, and a pre- and post-event row per event at most
    assert_eq!(est.grid_rows, 3202.0);
    assert_eq!(est.event_rows, 1_600_000.0); // max_events absent: 5e4 per second of t_end
    assert_eq!(est.steps, None);
    let d = dir("estimate");
    let mut files = RunFiles::create(&d, &s, None).unwrap();
    let run = deckspin::simulate::integrate(&s, &mut files);
    let written = files.finish(&run).unwrap();
    let bytes = std::fs::metadata(d.join("history.csv")).unwrap().len() as f64;
    assert!(written.rows as f64 <= est.rows() && written.rows > 3202);
    let per_row = bytes / (written.rows + 1) as f64;
    // each number is its shortest round-trip text: 24 bytes at most, about 18 on average
    assert!(
        per_row <= est.row_bytes && per_row > 0.7 * est.row_bytes,
        "{per_row} bytes per row, estimated {}",
        est.row_bytes
    );
    // a fixed-step method: one row per step at most
    let m = scene(
        "models/four-span.toml",
        &[
            "solver.method=\"moreau\"",
            "solver.step=1e-3",
            "solver.output_dt=1e-4",
        ],
    );
    let est = OutputEstimate::of(&m);
    assert_eq!(
        (est.steps, est.grid_rows, est.event_rows),
        (Some(16_000.0), 16_002.0, 0.0)
    );
}

#[test]
fn runs_above_the_budget_are_refused_with_their_estimate() {
    let s = scene(
        "models/validation/block-on-plane.toml",
        &["solver.t_end=1e5", "solver.output_dt=1e-3"],
    );
    match check_output(&s, &OutputBudget::default()) {
        Err(LimitError::History {
            rows,
            grid_rows,
            max_rows,
            max_bytes,
            ..
        }) => {
            assert_eq!(grid_rows, 1e8 + 2.0);
            assert_eq!(rows, grid_rows + 1e7); // max_events absent: at most 5e6
            assert_eq!((max_rows, max_bytes), (5e7, 2e10));
        }
        r => panic!("{r:?}"),
    }
    // the bytes alone: 4e7 rows of the four-span bridge are about 5.9e10 bytes
    let s = scene("models/four-span.toml", &["solver.output_dt=4e-7"]);
    let Err(LimitError::History { rows, bytes, .. }) = check_output(&s, &OutputBudget::default())
    else {
        panic!("not refused")
    };
    assert!(rows < 5e7 && bytes > 2e10, "{rows} rows, {bytes} bytes");
    let m = scene(
        "models/validation/block-on-plane.toml",
        &[
            "solver.method=\"moreau\"",
            "solver.step=1e-3",
            "solver.t_end=1e6",
            "solver.output_dt=100",
        ],
    );
    match check_output(&m, &OutputBudget::default()) {
        Err(LimitError::Steps {
            steps, max_steps, ..
        }) => {
            // max_steps absent: 2e5 per second of t_end, at most 5e7
            assert_eq!((steps, max_steps), (1e9, 50_000_000));
        }
        r => panic!("{r:?}"),
    }
}

#[test]
fn a_run_failing_at_its_start_writes_a_summary_of_its_scene() {
    let s = scene("models/validation/painleve.toml", &[]);
    let d = dir("start");
    let (e, json, times) = failed_streamed(&s, &d);
    assert_eq!((e.time(), e.kind()), (0.0, "Painleve"));
    assert_eq!(json["failure"]["t"], 0.0);
    assert_eq!(json["title"], "Painleve rod");
    assert_eq!(json["peaks"].as_array().unwrap().len(), 3);
    assert!(times.is_empty());
    assert_eq!(read(&d, "history.csv").lines().count(), 1);
}

/// The numbers of a sample in the order of history.csv's columns (t first), and the text
/// columns (kind, contact states) in theirs.
fn sample_columns(
    r: &deckspin::RunOutput,
    s: &deckspin::output::Sample,
) -> (Vec<f64>, Vec<&'static str>) {
    let mut nums = vec![s.t];
    let kind = match s.kind {
        deckspin::output::SampleKind::Grid => "grid",
        deckspin::output::SampleKind::PreEvent => "pre-event",
        deckspin::output::SampleKind::PostEvent => "post-event",
    };
    let mut text = vec![kind];
    nums.extend(s.q.iter().chain(&s.v));
    for c in &s.contacts {
        nums.extend([
            c.gap,
            c.gap_rate,
            c.slip_rate,
            c.normal_force,
            c.tangential_force,
        ]);
        text.push(c.state.label());
    }
    nums.extend(s.elements.iter().flat_map(|&(e, f)| [e, f]));
    let en = &s.energy;
    nums.extend([
        en.kinetic,
        en.elastic,
        en.hysteretic,
        en.damping,
        en.friction,
        en.impact_normal,
        en.impact_tangential,
        en.loads,
        en.supports,
        en.closure,
    ]);
    nums.extend((r.seats.iter()).map(|seat| seat.edge - s.contacts[seat.contact].gap));
    (nums, text)
}

#[test]
fn every_number_of_history_csv_reads_back_as_its_sample_bit_for_bit() {
    // the default bridge, and a bridge with seats (their margins are the last columns)
    let cases: [(&str, &[&str]); 2] = [
        ("models/four-span.toml", &["solver.t_end=6"]),
        ("models/three-frame.toml", &["solver.t_end=3"]),
    ];
    for (i, (model, set)) in cases.iter().enumerate() {
        let s = scene(model, set);
        let r = deckspin::run(&s, &mut deckspin::Silent).unwrap();
        let d = dir(&format!("round-trip-{i}"));
        r.write_all(&d).unwrap();
        let history = read(&d, "history.csv");
        let mut lines = history.lines();
        let columns = lines.next().unwrap().split(',').count();
        let mut numbers = 0;
        let mut rows = 0;
        for (line, sample) in lines.zip(&r.samples) {
            let (want, want_text) = sample_columns(&r, sample);
            let fields: Vec<&str> = line.split(',').collect();
            assert_eq!(fields.len(), columns, "{model}: {line}");
            let (mut got, mut got_text) = (Vec::new(), Vec::new());
            for f in &fields {
                match f.parse::<f64>() {
                    Ok(x) => got.push(x),
                    Err(_) => got_text.push(*f),
                }
            }
            assert_eq!(got_text, want_text, "{model}: {line}");
            assert_eq!(got.len(), want.len(), "{model}: {line}");
            for (k, (g, w)) in got.iter().zip(&want).enumerate() {
                assert!(
                    g.to_bits() == w.to_bits() || (g.is_nan() && w.is_nan()),
                    "{model} row {rows} number {k}: {g:e} read back, {w:e} in memory"
                );
            }
            numbers += got.len();
            rows += 1;
        }
        assert_eq!(rows, r.samples.len(), "{model}");
        assert!(rows > 250 && numbers > 20 * rows, "{model}: {rows} rows");
        if i == 1 {
            assert!(!r.seats.is_empty(), "three-frame has seats");
        }
    }
}
