//! Tests for `deckspin::excitation`. Fixtures are found under `$DECKSPIN_ROOT` (default: the
//! crate directory).

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use approx::assert_relative_eq;
use deckspin::excitation::{
    Baseline, END_TOLERANCE, ExcitationError, G, GroundMotion, Processing, Record, parse_at2,
    read_any, read_at2, read_two_column,
};
use proptest::prelude::*;

fn root() -> PathBuf {
    std::env::var("DECKSPIN_ROOT")
        .map(PathBuf::from)
        .unwrap_or_else(|_| PathBuf::from(env!("CARGO_MANIFEST_DIR")))
}

fn fixture(name: &str) -> PathBuf {
    root().join("tests/fixtures/excitation").join(name)
}

const NORTHRIDGE: [(&str, f64); 4] = [
    ("NORTHR_LOS000.AT2", 0.410),
    ("NORTHR_LOS270.AT2", 0.482),
    ("NORTHR_MUL009.AT2", 0.416),
    ("NORTHR_MUL279.AT2", 0.516),
];

fn northridge(name: &str) -> Record {
    read_at2(&root().join("excitations").join(name)).expect("record readable")
}

/// No baseline, no taper, no pad: the samples as given.
fn plain() -> Processing {
    Processing {
        baseline: Baseline::None,
        taper: 0.0,
        ..Processing::default()
    }
}

fn round3(x: f64) -> f64 {
    let mag = 10f64.powi(2 - x.abs().log10().floor() as i32);
    (x * mag).round() / mag
}

// ---------- exact integration ----------

#[test]
fn sine_matches_analytic_integral_and_derivatives_are_consistent() {
    let (amp, w, dt) = (3.0, 2.0 * PI * 2.0, 1e-3);
    let n = 2001; // 2 s
    let acc: Vec<f64> = (0..n).map(|i| amp * (w * i as f64 * dt).sin()).collect();
    let m = GroundMotion::from_samples(dt, acc, &plain()).unwrap();
    assert_eq!(m.duration(), 2000.0 * dt);
    for k in 0..=397 {
        let t = 0.005 * k as f64 + 0.0013; // between breakpoints
        let (d, v, a) = m.at(t);
        let v_exact = amp / w * (1.0 - (w * t).cos());
        let d_exact = amp / w * (t - (w * t).sin() / w);
        // interpolation error of linear a: |Δa| ≤ A ω² dt²/8 ≈ 5.9e-5
        assert!((a - amp * (w * t).sin()).abs() <= amp * w * w * dt * dt / 8.0 + 1e-12);
        // trapezoid error bound: |Δv| ≤ A ω dt²/6, |Δd| ≤ t·A ω dt²/6
        let tol_v = amp * w * dt * dt / 6.0;
        assert!((v - v_exact).abs() <= tol_v, "v at {t}: {v} vs {v_exact}");
        assert!(
            (d - d_exact).abs() <= tol_v * t + 1e-12,
            "d at {t}: {d} vs {d_exact}"
        );
        let h = 1e-6;
        let (dp, vp, _) = m.at(t + h);
        let (dm, vm, _) = m.at(t - h);
        assert!(((dp - dm) / (2.0 * h) - v).abs() <= 1e-8, "d' ≠ v at {t}");
        assert!(((vp - vm) / (2.0 * h) - a).abs() <= 1e-7, "v' ≠ a at {t}");
    }
    let s = m.stats();
    let rel = w * w * dt * dt / 6.0;
    assert_relative_eq!(s.pgv, 2.0 * amp / w, max_relative = rel);
    assert_relative_eq!(s.pgd, amp / w * 2.0, max_relative = rel);
}

#[test]
fn constant_acceleration_gives_exact_quadratic() {
    let (c, dt) = (2.5, 0.01);
    let m = GroundMotion::from_samples(dt, vec![c; 101], &plain()).unwrap();
    for k in 0..=1000 {
        let t = k as f64 * 0.000_999_7;
        let (d, v, a) = m.at(t);
        assert!((a - c).abs() <= 1e-12);
        assert!((v - c * t).abs() <= 1e-12, "v({t}) = {v}");
        assert!((d - 0.5 * c * t * t).abs() <= 1e-12, "d({t}) = {d}");
    }
    // After the end: final displacement held, at rest.
    assert_eq!(m.at(1.5), (m.disp[100], 0.0, 0.0));
    assert!((m.disp[100] - 0.5 * c).abs() <= 1e-12);
    // Before the start: zero.
    assert_eq!(m.at(-0.1), (0.0, 0.0, 0.0));
}

#[test]
fn linear_ramp_gives_exact_cubic() {
    let (j, dt) = (4.0, 0.02);
    let acc: Vec<f64> = (0..51).map(|i| j * i as f64 * dt).collect();
    let m = GroundMotion::from_samples(dt, acc, &plain()).unwrap();
    for k in 0..=300 {
        let t = k as f64 * 0.00333;
        let (d, v, a) = m.at(t);
        assert!((a - j * t).abs() <= 1e-12);
        assert!((v - j * t * t / 2.0).abs() <= 1e-12);
        assert!((d - j * t * t * t / 6.0).abs() <= 1e-12, "d({t}) = {d}");
    }
}

#[test]
fn significant_duration_of_constant_motion_is_ninety_percent() {
    let m = GroundMotion::from_samples(0.01, vec![1.0; 401], &plain()).unwrap();
    let s = m.stats();
    assert_relative_eq!(s.significant_duration, 0.9 * 4.0, max_relative = 1e-9);
    assert_relative_eq!(
        s.arias_intensity,
        PI / (2.0 * G) * 4.0,
        max_relative = 1e-12
    );
    assert_eq!(s.duration, 4.0);
}

// ---------- baseline correction on the real records ----------

#[test]
fn northridge_records_end_at_rest_with_target_pga() {
    let p = Processing {
        target_pga: Some(0.6),
        time_scale: 0.5,
        ..Processing::default()
    };
    for (name, _) in NORTHRIDGE {
        let rec = northridge(name);
        let m = GroundMotion::from_record(&rec, &p).unwrap();
        let s = m.stats();
        assert!((s.pga_g - 0.6).abs() <= 1e-9, "{name}: PGA {}", s.pga_g);
        assert!(
            s.final_displacement.abs() <= END_TOLERANCE * s.pgd,
            "{name}: final d {} (PGD {})",
            s.final_displacement,
            s.pgd
        );
        assert!(
            s.final_velocity.abs() <= END_TOLERANCE * s.pgv,
            "{name}: final v {} (PGV {})",
            s.final_velocity,
            s.pgv
        );
        assert!(s.correction_pga_change.abs() < 1e-3, "{name}: {s:?}");
        assert!(s.pgd > 0.0 && s.pgv > 0.0);
        // taper: record ends start and end at zero acceleration
        assert_eq!(m.acc[0], 0.0);
        assert_eq!(*m.acc.last().unwrap(), 0.0);
        assert_relative_eq!(m.duration(), 0.5 * 0.01 * (rec.accel_g.len() - 1) as f64);
        let (d_end, v_end, a_end) = m.at(m.end_time() + 1.0);
        assert_eq!((d_end, v_end, a_end), (s.final_displacement, 0.0, 0.0));
    }
}

#[test]
fn baseline_with_pad_and_no_taper_ends_at_rest() {
    let p = Processing {
        taper: 0.0,
        pad: 2.0,
        baseline: Baseline::Polynomial { order: 6 },
        ..Processing::default()
    };
    for (name, _) in NORTHRIDGE {
        let rec = northridge(name);
        let m = GroundMotion::from_record(&rec, &p).unwrap();
        let s = m.stats();
        assert_eq!(m.acc.len(), rec.accel_g.len() + 200);
        assert!(m.acc[rec.accel_g.len()..].iter().all(|a| *a == 0.0));
        assert!(
            s.final_displacement.abs() <= END_TOLERANCE * s.pgd,
            "{name}: {s:?}"
        );
        assert!(
            s.final_velocity.abs() <= END_TOLERANCE * s.pgv,
            "{name}: {s:?}"
        );
        let n = rec.accel_g.len();
        assert!(
            m.vel[n].abs() <= END_TOLERANCE * s.pgv,
            "{name}: not at rest in pad"
        );
    }
}

#[test]
fn uncorrected_record_drifts() {
    // The correction matters: without it the raw record ends with a sizeable offset.
    let m = GroundMotion::from_record(&northridge("NORTHR_LOS000.AT2"), &plain()).unwrap();
    let s = m.stats();
    assert!(
        s.final_displacement.abs() > 1e3 * END_TOLERANCE * s.pgd,
        "{s:?}"
    );
}

// ---------- time scaling and lag ----------

#[test]
fn time_scaling_halves_duration_keeps_pga_and_quarters_displacement() {
    let rec = northridge("NORTHR_LOS270.AT2");
    for baseline in [Baseline::None, Baseline::Polynomial { order: 3 }] {
        let full = Processing {
            baseline,
            taper: 0.0,
            ..Processing::default()
        };
        let half = Processing {
            time_scale: 0.5,
            ..full.clone()
        };
        let m1 = GroundMotion::from_record(&rec, &full).unwrap();
        let m2 = GroundMotion::from_record(&rec, &half).unwrap();
        assert_eq!(m2.duration(), 0.5 * m1.duration());
        let (s1, s2) = (m1.stats(), m2.stats());
        assert_relative_eq!(s2.pga, s1.pga, max_relative = 1e-12);
        assert_relative_eq!(s2.pgd, 0.25 * s1.pgd, max_relative = 1e-9);
        assert_relative_eq!(s2.pgv, 0.5 * s1.pgv, max_relative = 1e-9);
        for k in 0..50 {
            let t = 0.397 * k as f64;
            let (d1, v1, a1) = m1.at(t);
            let (d2, v2, a2) = m2.at(0.5 * t);
            assert!((a2 - a1).abs() <= 1e-9 * s1.pga);
            assert!((v2 - 0.5 * v1).abs() <= 1e-9 * s1.pgv);
            assert!((d2 - 0.25 * d1).abs() <= 1e-9 * s1.pgd);
        }
    }
}

#[test]
fn lag_shifts_the_motion() {
    let rec = northridge("NORTHR_MUL009.AT2");
    let p = Processing {
        time_scale: 0.5,
        ..Processing::default()
    };
    let lag = 0.137;
    let m0 = GroundMotion::from_record(&rec, &p).unwrap();
    let ml = GroundMotion::from_record(&rec, &Processing { lag, ..p }).unwrap();
    assert_eq!(ml.t0, lag);
    assert_eq!(ml.end_time(), m0.end_time() + lag);
    for k in 0..4000 {
        let t = -0.5 + 0.004_01 * k as f64;
        assert_eq!(ml.at(t), m0.at(t - lag), "t = {t}");
        if t < lag {
            assert_eq!(ml.at(t), (0.0, 0.0, 0.0));
        }
    }
    let times: Vec<f64> = ml.sample_times().collect();
    assert_eq!(times.len(), ml.acc.len());
    assert_eq!(times[0], lag);
    assert_relative_eq!(times[10], lag + 10.0 * ml.dt);
}

#[test]
fn at_is_continuous_at_breakpoints() {
    let m = GroundMotion::from_record(&northridge("NORTHR_MUL279.AT2"), &Processing::default())
        .unwrap();
    let s = m.stats();
    for (i, t) in m.sample_times().enumerate().skip(1).take(m.acc.len() - 2) {
        let (d, v, a) = m.at(t);
        assert!((d - m.disp[i]).abs() <= 1e-12 * s.pgd);
        assert!((v - m.vel[i]).abs() <= 1e-12 * s.pgv);
        assert!((a - m.acc[i]).abs() <= 1e-12 * s.pga);
        let (dl, vl, _) = m.at(t - 1e-9);
        assert!((d - dl).abs() <= 1e-8 * s.pgd && (v - vl).abs() <= 1e-6 * s.pgv);
    }
}

// ---------- reading ----------

#[test]
fn raw_northridge_pga_matches_readme_table() {
    for (name, pga_g) in NORTHRIDGE {
        let rec = northridge(name);
        assert_eq!(rec.header.len(), 4);
        assert!(
            rec.header[0].contains("FEMA P695"),
            "{name}: {:?}",
            rec.header
        );
        assert_eq!(rec.dt, 0.01);
        let m = GroundMotion::from_record(&rec, &plain()).unwrap();
        let s = m.stats();
        assert_eq!(round3(s.pga_g), pga_g, "{name}: {}", s.pga_g);
        assert!(s.significant_duration > 1.0 && s.significant_duration < s.duration);
    }
    let rec = northridge("NORTHR_LOS000.AT2");
    assert_eq!(rec.accel_g.len(), 1999);
    assert_eq!(rec.accel_g[0], 8.409_08e-4);
    assert_eq!(*rec.accel_g.last().unwrap(), -4.240_85e-4);
}

#[test]
fn tiny_at2_with_header_variants() {
    let rec = read_at2(&fixture("tiny.AT2")).unwrap();
    assert_eq!(rec.dt, 0.02);
    assert_eq!(rec.accel_g, vec![0.0, 0.1, 0.2, -0.15, 0.05, 0.0, 0.0]);
    assert_eq!(rec.header[3], "npts=  7 dt=   .0200 sec");
    for line in [
        "NPTS= 3, DT= 0.0100 SEC",
        "NPTS=  3, DT=   .0100 SEC",
        "npts=3 dt=.01 sec",
        "NPTS:3, DT:0.01",
        "3   0.0100   NPTS, DT",
    ] {
        let text = format!("a\nb\nc\n{line}\n 1.0 2.0\n3.0\n");
        let rec = parse_at2(Path::new("mem"), &text).unwrap_or_else(|e| panic!("{line}: {e}"));
        assert_eq!((rec.accel_g.len(), rec.dt), (3, 0.01), "{line}");
    }
}

#[test]
fn two_column_with_units_and_comments() {
    let rec = read_two_column(&fixture("two_column.txt")).unwrap();
    assert_relative_eq!(rec.dt, 0.01, max_relative = 1e-12);
    let expect = [0.0, 0.1, -0.2, 0.0, 0.05];
    assert_eq!(rec.accel_g.len(), expect.len());
    for (a, e) in rec.accel_g.iter().zip(expect) {
        assert!((a - e).abs() <= 1e-15, "{a} vs {e}");
    }
    assert_eq!(rec.header.len(), 3);
    let any = read_any(&fixture("two_column.txt")).unwrap();
    assert_eq!(any, rec);
    let at2 = read_any(&fixture("tiny.AT2")).unwrap();
    assert_eq!(at2.accel_g.len(), 7);
}

// ---------- bad input ----------

#[test]
fn missing_file_is_io_naming_the_path() {
    let path = fixture("no_such_record.AT2");
    let err = read_at2(&path).unwrap_err();
    match &err {
        ExcitationError::Io { path: p, source } => {
            assert_eq!(p, &path);
            assert_eq!(source.kind(), std::io::ErrorKind::NotFound);
        }
        other => panic!("expected Io, got {other:?}"),
    }
    assert!(err.to_string().contains("no_such_record.AT2"));
    assert!(matches!(
        read_two_column(&fixture("nope.txt")),
        Err(ExcitationError::Io { .. })
    ));
}

#[test]
fn npts_mismatch_is_count() {
    let err = read_at2(&fixture("bad_npts.AT2")).unwrap_err();
    assert!(
        matches!(&err, ExcitationError::Count { expected: 12, found: 10, path } if path.ends_with("bad_npts.AT2")),
        "{err:?}"
    );
    assert!(err.to_string().contains("bad_npts.AT2"));
}

#[test]
fn non_numeric_token_is_value_with_line() {
    let err = read_at2(&fixture("non_numeric.AT2")).unwrap_err();
    match &err {
        ExcitationError::Value { path, line, token } => {
            assert!(path.ends_with("non_numeric.AT2"));
            assert_eq!(*line, 6);
            assert_eq!(token, "8.0x-03");
        }
        other => panic!("expected Value, got {other:?}"),
    }
    assert!(err.to_string().contains("non_numeric.AT2:6"));
    let nan = parse_at2(Path::new("m"), "a\nb\nc\nNPTS= 2, DT= 0.01\n1.0\nNaN\n").unwrap_err();
    assert!(
        matches!(nan, ExcitationError::Value { line: 6, .. }),
        "{nan:?}"
    );
}

#[test]
fn garbled_header_is_header_error() {
    let err = read_at2(&fixture("garbled_header.AT2")).unwrap_err();
    assert!(
        matches!(&err, ExcitationError::Header { line: 4, reason, .. } if reason.contains("NPTS")),
        "{err:?}"
    );
    let err = read_at2(&fixture("short_header.AT2")).unwrap_err();
    assert!(
        matches!(err, ExcitationError::Header { line: 3, .. }),
        "{err:?}"
    );
    for line in [
        "NPTS= 10",
        "DT= 0.01",
        "NPTS= 10, DT= -0.01",
        "NPTS= 10, DT= 0",
        "hello",
    ] {
        let text = format!("a\nb\nc\n{line}\n1.0\n");
        let err = parse_at2(Path::new("m"), &text).unwrap_err();
        assert!(
            matches!(err, ExcitationError::Header { line: 4, .. }),
            "{line}: {err:?}"
        );
    }
}

#[test]
fn two_column_errors() {
    let err = read_two_column(&fixture("nonuniform.txt")).unwrap_err();
    assert!(
        matches!(err, ExcitationError::Sampling { line: 4, .. }),
        "{err:?}"
    );
    let err = read_two_column(&fixture("three_columns.txt")).unwrap_err();
    assert!(
        matches!(
            err,
            ExcitationError::Columns {
                line: 3,
                expected: 2,
                found: 3,
                ..
            }
        ),
        "{err:?}"
    );
}

fn invalid_field(r: Result<GroundMotion, ExcitationError>) -> &'static str {
    match r {
        Err(ExcitationError::Invalid { field, .. }) => field,
        other => panic!("expected Invalid, got {other:?}"),
    }
}

#[test]
fn bad_processing_parameters_are_invalid() {
    let rec = read_at2(&fixture("tiny.AT2")).unwrap();
    let run = |p: Processing| invalid_field(GroundMotion::from_record(&rec, &p));
    let base = Processing {
        taper: 0.0,
        baseline: Baseline::None,
        ..Processing::default()
    };
    let cases = [
        (
            Processing {
                target_pga: Some(0.5),
                scale: Some(2.0),
                ..base.clone()
            },
            "target_pga",
        ),
        (
            Processing {
                target_pga: Some(f64::NAN),
                ..base.clone()
            },
            "target_pga",
        ),
        (
            Processing {
                target_pga: Some(-0.1),
                ..base.clone()
            },
            "target_pga",
        ),
        (
            Processing {
                scale: Some(f64::INFINITY),
                ..base.clone()
            },
            "scale",
        ),
        (
            Processing {
                time_scale: -0.5,
                ..base.clone()
            },
            "time_scale",
        ),
        (
            Processing {
                lag: -1.0,
                ..base.clone()
            },
            "lag",
        ),
        (
            Processing {
                pad: f64::NAN,
                ..base.clone()
            },
            "pad",
        ),
        (
            Processing {
                taper: 1.0,
                ..base.clone()
            },
            "taper",
        ),
        (
            Processing {
                baseline: Baseline::Polynomial { order: 1 },
                ..base.clone()
            },
            "baseline",
        ),
        (
            Processing {
                baseline: Baseline::Polynomial { order: 6 },
                ..base.clone()
            },
            "baseline",
        ),
    ];
    for (p, field) in cases {
        assert_eq!(run(p.clone()), field, "{p:?}");
    }
    assert_eq!(
        invalid_field(GroundMotion::from_samples(-0.01, vec![0.0; 10], &base)),
        "dt"
    );
    assert_eq!(
        invalid_field(GroundMotion::from_samples(0.01, vec![1.0], &base)),
        "acc"
    );
    assert_eq!(
        invalid_field(GroundMotion::from_samples(0.01, vec![0.0, f64::NAN], &base)),
        "acc"
    );
    let zero = Processing {
        target_pga: Some(0.5),
        ..base.clone()
    };
    assert_eq!(
        invalid_field(GroundMotion::from_samples(0.01, vec![0.0; 10], &zero)),
        "acc"
    );
}

#[test]
fn processing_deserializes_with_defaults_and_rejects_unknown_fields() {
    let p: Processing = serde_json::from_str("{}").unwrap();
    assert_eq!(p, Processing::default());
    assert_eq!(p.baseline, Baseline::Polynomial { order: 3 });
    assert_eq!((p.time_scale, p.lag, p.taper, p.pad), (1.0, 0.0, 0.5, 0.0));
    let p: Processing = serde_json::from_str(
        r#"{"target_pga": 0.6, "time_scale": 0.5, "lag": 0.1, "baseline": {"kind": "none"}}"#,
    )
    .unwrap();
    assert_eq!(p.baseline, Baseline::None);
    assert_eq!(p.target_pga, Some(0.6));
    assert!(serde_json::from_str::<Processing>(r#"{"pga": 0.6}"#).is_err());
    assert!(serde_json::from_str::<Processing>(r#"{"baseline": {"kind": "polynomial"}}"#).is_err());
}

// ---------- properties ----------

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn polynomial_baseline_always_ends_at_rest(
        acc in prop::collection::vec(-10.0f64..10.0, 12..400),
        dt in 0.001f64..0.05,
        order in 2usize..=6,
        taper_frac in 0.0f64..0.3,
        pad_steps in 0usize..50,
    ) {
        let n = acc.len();
        let p = Processing {
            baseline: Baseline::Polynomial { order },
            taper: taper_frac * (n - 1) as f64 * dt,
            pad: pad_steps as f64 * dt,
            ..Processing::default()
        };
        let m = GroundMotion::from_samples(dt, acc, &p).unwrap();
        let s = m.stats();
        prop_assert!(s.final_displacement.abs() <= END_TOLERANCE * s.pgd, "{:?}", s);
        prop_assert!(s.final_velocity.abs() <= END_TOLERANCE * s.pgv, "{:?}", s);
        prop_assert_eq!(m.acc.len(), n + pad_steps);
    }

    #[test]
    fn at_agrees_with_nodes_and_is_continuous(
        acc in prop::collection::vec(-10.0f64..10.0, 2..100),
        dt in 0.001f64..0.1,
        lag in 0.0f64..1.0,
    ) {
        let p = Processing { lag, ..plain() };
        let m = GroundMotion::from_samples(dt, acc, &p).unwrap();
        let scale = 1.0 + m.stats().pgd + m.stats().pgv;
        for i in 1..m.acc.len() - 1 {
            let t = lag + i as f64 * dt;
            let (d, v, a) = m.at(t);
            prop_assert!((d - m.disp[i]).abs() <= 1e-12 * scale);
            prop_assert!((v - m.vel[i]).abs() <= 1e-12 * scale);
            prop_assert!((a - m.acc[i]).abs() <= 1e-9);
        }
    }
}
