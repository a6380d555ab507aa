//! `excitation.window`: a record cut to a time window of the run (the target PGA the whole
//! record's, the cut re-corrected so that it starts at rest), and the 5–95 % Arias
//! strong-motion window that chooses it.
mod common;
use common::*;
use deckspin::excitation::{
    Baseline, END_TOLERANCE, G, GroundMotion, Processing, Record, read_any,
};
use deckspin::model::load_str;
use deckspin::output::{HistoryWriter, RunOutput};
use deckspin::scene::{Motion, Scene};
use std::path::PathBuf;

const FOUR_SPAN: &str = "models/four-span.toml";

fn mul009() -> Record {
    read_any(&model("excitations/NORTHR_MUL009.AT2")).unwrap()
}

fn history(r: &RunOutput) -> Vec<u8> {
    let mut w = HistoryWriter::new(Vec::new(), r).unwrap();
    w.write(&r.samples).unwrap();
    w.finish().unwrap()
}

fn load(set: &[&str]) -> Scene {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    deckspin::load(&model(FOUR_SPAN), &set).unwrap_or_else(|e| panic!("{e}"))
}

/// The motion of the support named `name`.
fn motion(scene: &Scene, name: &str) -> GroundMotion {
    let s = scene.supports.iter().find(|s| s.name == name).unwrap();
    match &s.motion {
        Motion::Record(g) => (**g).clone(),
        Motion::Harmonic { .. } => panic!("{name} is harmonic"),
    }
}

#[test]
fn a_window_over_the_whole_record_runs_bit_for_bit_as_no_window() {
    let lags = [
        "excitation.lag_bents=[0.0, 0.05, 0.1]",
        "excitation.lag_abutments=[0.0, 0.15]",
    ];
    for lagged in [false, true] {
        let mut set = vec!["solver.t_end=3.0"];
        if lagged {
            set.extend(lags);
        }
        let plain = load(&set);
        set.push("excitation.window=[0.0, 1000.0]");
        let cut = load(&set);
        for (a, b) in plain.supports.iter().zip(&cut.supports) {
            let (Motion::Record(a), Motion::Record(b)) = (&a.motion, &b.motion) else {
                panic!("record supports")
            };
            assert_eq!(a, b, "{lagged}");
        }
        let a = deckspin::run(&plain, &mut deckspin::Silent).unwrap();
        let b = deckspin::run(&cut, &mut deckspin::Silent).unwrap();
        assert!(a.samples.len() > 100);
        assert!(
            history(&a) == history(&b),
            "lagged {lagged}: histories differ"
        );
    }
}

/// Without baseline correction or taper, the cut is the scaled record itself: each of its
/// samples is the uncut motion's sample at the same absolute time, bit for bit, the factor
/// being the whole record's (the cut is not rescaled to its own peak).
#[test]
fn the_cut_is_the_uncut_scaled_acceleration_at_the_same_times() {
    let rec = mul009();
    let (lag, s, e) = (0.3, 2.0123, 7.5);
    let p = Processing {
        target_pga: Some(0.6),
        time_scale: 0.5,
        lag,
        baseline: Baseline::None,
        taper: 0.0,
        ..Processing::default()
    };
    let whole = GroundMotion::from_record(&rec, &p).unwrap();
    let cut = GroundMotion::from_record(
        &rec,
        &Processing {
            window: Some([s, e]),
            ..p.clone()
        },
    )
    .unwrap();
    assert_eq!(cut.dt, whole.dt);
    let dt = whole.dt;
    // the first sample at or after s, t = 0 being s
    assert!(cut.t0 >= 0.0 && cut.t0 < dt, "t0 {}", cut.t0);
    let first = ((s - lag) / dt).ceil() as usize;
    let last = ((e - lag) / dt).floor() as usize;
    assert_eq!(cut.acc.len(), last - first + 1);
    for (i, a) in cut.acc.iter().enumerate() {
        let t = s + cut.t0 + i as f64 * dt;
        let k = ((t - whole.t0) / dt).round() as usize;
        assert!((whole.t0 + k as f64 * dt - t).abs() < 1e-9 * dt.max(t));
        assert_eq!(a.to_bits(), whole.acc[k].to_bits(), "sample {i} at {t} s");
    }
    // from rest at the window's start
    assert_eq!((cut.vel[0], cut.disp[0]), (0.0, 0.0));
    assert_eq!(cut.at(0.0), (0.0, 0.0, 0.0));
}

/// With the default processing the cut is corrected alone (it starts and ends at rest) and
/// scaled by the factor that brings the whole processed record to the target PGA.
#[test]
fn the_cut_is_corrected_alone_at_the_whole_records_factor() {
    let rec = mul009();
    let p = Processing {
        time_scale: 0.5,
        ..Processing::default()
    };
    let unscaled = GroundMotion::from_record(&rec, &p).unwrap();
    let target = 0.6;
    let factor = target * G / unscaled.stats().pga;
    for (s, e) in [(3.0, 9.0), (10.0, 14.0), (12.0, 100.0)] {
        let cut = GroundMotion::from_record(
            &rec,
            &Processing {
                target_pga: Some(target),
                window: Some([s, e]),
                ..p.clone()
            },
        )
        .unwrap();
        let dt = cut.dt;
        let first = (s / dt).ceil() as usize;
        let last = ((e / dt).floor() as usize).min(rec.accel_g.len() - 1);
        let alone = GroundMotion::from_samples(
            rec.dt,
            (rec.accel_g[first..=last].iter()).map(|x| x * G).collect(),
            &Processing {
                scale: Some(factor),
                ..p.clone()
            },
        )
        .unwrap();
        assert_eq!(cut.acc, alone.acc, "[{s}, {e}]");
        assert_eq!(cut.t0, first as f64 * dt - s);
        let st = cut.stats();
        assert_eq!(cut.acc[0], 0.0);
        assert!(st.final_displacement.abs() <= END_TOLERANCE * st.pgd);
        assert!(st.final_velocity.abs() <= END_TOLERANCE * st.pgv);
        if e > 50.0 {
            // past the record's end: cut at its end
            assert_eq!(last, rec.accel_g.len() - 1);
        }
    }
    // the tail is weaker than the target: not rescaled to its own peak
    let tail = Processing {
        target_pga: Some(target),
        window: Some([10.0, 14.0]),
        ..p.clone()
    };
    let pga = GroundMotion::from_record(&rec, &tail)
        .unwrap()
        .stats()
        .pga_g;
    assert!(pga < 0.5 * target, "tail PGA {pga} g");
}

/// A motion with the given node accelerations (velocity and displacement unused).
fn synthetic(dt: f64, acc: Vec<f64>, t0: f64) -> GroundMotion {
    let n = acc.len();
    GroundMotion {
        dt,
        t0,
        acc,
        vel: vec![0.0; n],
        disp: vec![0.0; n],
        correction_pga_change: 0.0,
    }
}

/// I(t) ∝ ∫₀ᵗ a²: a constant a over [0, T] gives I ∝ t, so t₅ = 0.05 T, t₉₅ = 0.95 T; a ramp
/// a = c·t gives I ∝ t³, so t_p = T p^{1/3}; both shifted by the lag t₀.
#[test]
fn arias_5_and_95_percent_times_match_closed_forms() {
    let (dt, n, t0) = (0.01, 1001, 0.7);
    let t_total = (n - 1) as f64 * dt;
    let flat = synthetic(dt, vec![2.0; n], t0);
    let (a, b) = flat.strong_motion_window().unwrap();
    assert_rel(a, t0 + 0.05 * t_total, 1e-12, "constant t5");
    assert_rel(b, t0 + 0.95 * t_total, 1e-12, "constant t95");
    let ramp = synthetic(dt, (0..n).map(|i| 3.0 * i as f64 * dt).collect(), t0);
    let (a, b) = ramp.strong_motion_window().unwrap();
    assert_rel(a, t0 + t_total * 0.05f64.cbrt(), 1e-12, "ramp t5");
    assert_rel(b, t0 + t_total * 0.95f64.cbrt(), 1e-12, "ramp t95");
    // the significant duration is their difference
    assert_rel(ramp.stats().significant_duration, b - a, 1e-12, "D5-95");
    assert_eq!(synthetic(dt, vec![0.0; n], t0).strong_motion_window(), None);
}

/// A scene's strong-motion window spans its records': the earliest 5 % time, the latest 95 %
/// time, each support's lag included.
#[test]
fn a_scenes_strong_motion_window_spans_its_lagged_records() {
    let plain = load(&[]);
    let (x5, x95) = motion(&plain, "bent1.x").strong_motion_window().unwrap();
    let (y5, y95) = motion(&plain, "bent1.y").strong_motion_window().unwrap();
    assert_eq!(
        plain.strong_motion_window(),
        Some((x5.min(y5), x95.max(y95)))
    );
    let lagged = load(&[
        "excitation.lag_bents=[0.0, 0.05, 0.1]",
        "excitation.lag_abutments=[0.0, 0.15]",
    ]);
    let (a, b) = lagged.strong_motion_window().unwrap();
    assert_eq!(a, x5.min(y5));
    // the right abutment (x, 0.15 s) and bent 3 (y, 0.1 s) lag most
    assert_rel(b, (x95 + 0.15).max(y95 + 0.1), 1e-14, "latest 95 %");
    // a model cut to it: its records start at rest there
    let set = format!("excitation.window=[{a}, {b}]");
    let cut = load(&[&set]);
    let m = motion(&cut, "bent1.x");
    assert!(m.t0 < m.dt && m.end_time() <= b - a + 1e-9);
    assert_eq!(m.acc[0], 0.0);
}

/// The four-span model file with `window = …` in its `[excitation]` (and `kind` replaced), at
/// a path beside it (its records found as from the file), and the line of `window`.
fn windowed(window: &str, kind: &str) -> (String, PathBuf, usize) {
    let text = std::fs::read_to_string(model(FOUR_SPAN)).unwrap();
    let kind_line = "kind = \"record\"\n";
    let text = text.replacen(kind_line, &format!("{kind}\nwindow = {window}   # s\n"), 1);
    let line = 1 + text
        .lines()
        .position(|l| l.starts_with("window ="))
        .unwrap();
    (text, model("models/windowed.toml"), line)
}

#[test]
fn bad_windows_name_the_file_line_and_field() {
    let record = "kind = \"record\"";
    let harmonic = "kind = \"harmonic\"\nfrequency = 1.0\namplitude_x = 0.01";
    let cases = [
        ("[nan, 5.0]", record, "finite"),
        ("[inf, 5.0]", record, "finite"),
        ("[1.0, inf]", record, "finite"),
        ("[-1.0, 5.0]", record, "≥ 0"),
        ("[5.0, 5.0]", record, "after start"),
        ("[6.0, 5.0]", record, "after start"),
        ("[1.0, 2.0, 3.0]", record, "[start, end]"),
        ("[20.0, 30.0]", record, "after the record ends"),
        ("[14.8, 30.0]", record, "taper"),
        ("[2.0, 8.0]", harmonic, "harmonic"),
    ];
    for (window, kind, why) in cases {
        let (text, path, line) = windowed(window, kind);
        let e = load_str(&text, &path, &[]).expect_err(window).to_string();
        let at = format!("windowed.toml:{line}: excitation.window: ");
        assert!(e.contains(&at) && e.contains(why), "{window}: {e}");
    }
    // a good one in the file
    let (text, path, _) = windowed("[2.0, 8.0]", record);
    let s = load_str(&text, &path, &[]).unwrap();
    assert!(motion(&s, "bent1.x").duration() <= 6.0);
}

/// A suite scales each pair by its whole records' intensity: a window (in the model or an
/// argument) is refused, not applied at a wrong level.
#[test]
fn a_suite_refuses_a_window() {
    use deckspin::suite::intensity::MeasureSpec;
    use deckspin::suite::records::list_pairs;
    use deckspin::suite::{Suite, SuiteSpec};
    let list = model("excitations/pairs.txt");
    let pairs = || {
        list_pairs(
            &list,
            "far-field/NORTHR_LOS000.AT2 far-field/NORTHR_LOS270.AT2\n",
        )
        .unwrap()
    };
    let spec = || SuiteSpec {
        measure: MeasureSpec::Pga,
        levels: vec![0.5],
        axes: Vec::new(),
        tail: 2.0,
    };
    let fix = ["excitation.window=[2.0, 8.0]".to_string()];
    let e = Suite::open(&model(FOUR_SPAN), &fix, pairs(), spec())
        .err()
        .unwrap();
    assert!(
        e.to_string()
            .starts_with("'excitation.window=[2.0, 8.0]': excitation.window: "),
        "{e}"
    );
    let (text, path, _) = windowed("[2.0, 8.0]", "kind = \"record\"");
    let e = Suite::from_text(&text, &path, &[], pairs(), spec())
        .err()
        .unwrap();
    assert!(
        e.to_string()
            .contains("windowed.toml: excitation.window: a suite"),
        "{e}"
    );
}
