//! The run API: a cancelled or failed run keeps what it computed up to its stop.
mod common;

use deckspin::output::{EventRecord, Sample};
use deckspin::{Observer, Stop};

/// Cancels at the first batch after `t_stop`.
struct CancelAfter {
    t_stop: f64,
    seen: usize,
}

impl Observer for CancelAfter {
    fn batch(&mut self, samples: &[Sample], _: &[EventRecord], t: f64) -> bool {
        self.seen += samples.len();
        t < self.t_stop
    }
}

#[test]
fn a_cancelled_run_keeps_its_output() {
    let scene = deckspin::load(&common::model("models/four-span.toml"), &[]).unwrap();
    let mut obs = CancelAfter {
        t_stop: 5.0,
        seen: 0,
    };
    let run = deckspin::event_driven::integrate(&scene, &mut obs);
    let Stop::Cancelled { t } = run.stop else {
        panic!("{:?}", run.stop)
    };
    assert!((5.0..16.0).contains(&t), "cancelled at {t}");
    let last = run.output.samples.last().unwrap().t;
    assert!(
        last <= t && last > 4.9,
        "last sample at {last}, cancel at {t}"
    );
    // the impacts before the cancel are in the output, the same as in the whole run
    let whole = common::run("models/four-span.toml", &[]);
    let before = |r: &deckspin::RunOutput| r.events.iter().filter(|e| e.t <= last).count();
    assert!(before(&whole) > 0);
    assert_eq!(before(&run.output), before(&whole));
    assert_eq!(run.output.events.len(), before(&whole));
    // the observer saw every sample kept
    assert_eq!(obs.seen, run.output.samples.len());
}

#[test]
fn a_failed_run_keeps_its_output_and_reason() {
    let set = ["solver.max_steps=2000".to_string()];
    let scene = deckspin::load(&common::model("models/four-span.toml"), &set).unwrap();
    let run = deckspin::event_driven::integrate(&scene, &mut deckspin::Silent);
    let Stop::Failed(deckspin::SolverError::TooManySteps { t, limit }) = run.stop else {
        panic!("{:?}", run.stop)
    };
    assert_eq!(limit, 2000);
    assert_eq!(
        run.output.stats.steps_accepted + run.output.stats.steps_rejected,
        2000
    );
    let last = run.output.samples.last().unwrap().t;
    assert!(
        last > 0.0 && last <= t,
        "last sample {last}, failure at {t}"
    );
    // the same result through the Result API
    let e = deckspin::run(&scene, &mut deckspin::Silent).unwrap_err();
    assert!(matches!(e, deckspin::SolverError::TooManySteps { .. }));
}

#[test]
fn a_fixed_step_run_that_fails_keeps_its_output() {
    // central differences with k = 1e6 kN/m and h = 1 ms exceed 2/ω of the stiffest contact
    let set = [
        "solver.method=\"penalty-explicit\"".to_string(),
        "solver.step=1e-3".to_string(),
    ];
    let scene = deckspin::load(&common::model("models/four-span.toml"), &set).unwrap();
    let run = deckspin::simulate::integrate(&scene, &mut deckspin::Silent);
    let Stop::Failed(deckspin::SolverError::Unstable { t, .. }) = run.stop else {
        panic!("{:?}", run.stop)
    };
    assert!(t > 1.0 && t < 16.0, "{t}");
    let last = run.output.samples.last().unwrap().t;
    assert!(
        last <= t && last > t - 0.01,
        "last sample {last}, failure at {t}"
    );
    assert!(run.output.stats.steps_accepted > 1000);
}

#[test]
fn time_that_stops_advancing_is_reported_with_the_contacts() {
    // a velocity tolerance of 0.1 m/s treats an approach at 0.06 m/s as resting: the corner
    // is found crossing again and again at one instant (set on the scene: model files refuse it)
    let mut scene = deckspin::load(&common::model("models/four-span.toml"), &[]).unwrap();
    scene.settings.velocity_tol = 0.1;
    let run = deckspin::simulate::integrate(&scene, &mut deckspin::Silent);
    let Stop::Failed(deckspin::SolverError::Stalled {
        t,
        since,
        events,
        contacts,
    }) = &run.stop
    else {
        panic!("{:?}", run.stop)
    };
    assert_eq!(*events, 10_000);
    assert!(t - since <= 16e-6 && *t > 2.0, "{since} → {t}");
    assert!(
        contacts.contains("right_bottom") && contacts.contains("ġ"),
        "{contacts}"
    );
    // bounded: the steps taken before the report
    let st = &run.output.stats;
    assert!(st.steps_accepted + st.steps_rejected < 40_000, "{st:?}");
    assert!(run.output.samples.last().unwrap().t <= *t);
}

#[test]
fn a_scene_too_stiff_for_the_step_budget_is_refused_before_it_runs() {
    // actuators of 1e12 kN/m on the 0.65 t abutments: ω ≈ 2.3e6 rad/s
    let set = ["abutment.actuator_stiffness=1e12".to_string()];
    let scene = deckspin::load(&common::model("models/four-span.toml"), &set).unwrap();
    let run = deckspin::simulate::integrate(&scene, &mut deckspin::Silent);
    let Stop::Failed(deckspin::SolverError::TooStiff {
        omega,
        steps,
        limit,
    }) = run.stop
    else {
        panic!("{:?}", run.stop)
    };
    // at least the abutment's rotation: ω² = 2 k (0.9 m)² / 0.31 t·m² (the Rayleigh dashpots
    // of such springs, c = a₁k, decay faster still)
    let expected = (2.0 * 1e12 * 0.81 / 0.31f64).sqrt();
    assert!(omega >= 0.99 * expected, "{omega:e} vs {expected:e}");
    assert!((steps - 16.0 * omega / 3.5).abs() < 1e-6 * steps);
    // max_steps absent: 2e5 per simulated second of the 16 s run
    assert_eq!(limit, 3_200_000);
    assert_eq!(run.output.stats.steps_accepted, 0);
    // the same scene with room for its steps is not refused up front
    let mut roomy = scene.clone();
    roomy.settings.max_steps = 20_000_000;
    roomy.settings.t_end = 1e-4;
    let run = deckspin::simulate::integrate_unjudged(&roomy, &mut deckspin::Silent);
    assert!(run.finished(), "{:?}", run.stop);
    assert!(run.output.stats.steps_accepted > 1000);
}

/// A slice of the stress test (`deckspin stress`): two real record pairs of different lengths
/// at the strongest run, ε = 0 and 0.5, μ = 0 and 0.5, Takeda and bilinear columns. Every run
/// finishes with no penetration above 1e-9 m, its energy closed within rtol/10 and no contact
/// pulling beyond 1e-9 of the largest normal force.
#[test]
fn a_slice_of_the_record_stress_test_passes() {
    use deckspin::stress::{StressGrid, record_pairs, stress};
    let (pairs, single) = record_pairs(&common::model("excitations/far-field")).unwrap();
    assert_eq!((pairs.len(), single.len()), (19, 0));
    let pick: Vec<_> = pairs
        .into_iter()
        .filter(|p| p.name == "MANJIL_ABB" || p.name == "NORTHR_LOS")
        .collect();
    assert_eq!(pick.len(), 2);
    let grid = StressGrid {
        runs: vec![7],
        restitution: vec![0.0, 0.5],
        mu: vec![0.0, 0.5],
        ..StressGrid::default()
    };
    let rows = stress(&common::model("models/four-span.toml"), &pick, &grid).unwrap();
    assert_eq!(rows.len(), 16);
    for r in &rows {
        assert!(r.passes(), "{r:?}");
        assert!(r.pull_rel <= 1e-9, "{r:?}");
        // to the end of the longer component (time scale 0.5) and the 2 s tail
        assert!(r.t_end > 2.0 && r.t_end < 40.0, "{r:?}");
    }
}

/// The three-frame example (keys that fail while corners slide) under the two pairs that put
/// corners inside backwalls before a key's failure was projected (up to 1.9e-7 m), at every
/// run of its table: no corner deeper than 1e-9 m, no contact left approaching; its ledger
/// closes within rtol (0.43 rtol at worst over the whole grid, `docs/robustness.md`).
#[test]
fn the_three_frame_example_under_far_field_records_stays_out_of_its_faces() {
    use deckspin::stress::{StressGrid, record_pairs, stress};
    let (pairs, _) = record_pairs(&common::model("excitations/far-field")).unwrap();
    let pick: Vec<_> = (pairs.into_iter())
        .filter(|p| p.name == "HECTOR_HEC" || p.name == "LOMAP_CAP")
        .collect();
    let grid = StressGrid {
        restitution: vec![0.0],
        mu: vec![0.1, 0.2],
        ..StressGrid::default()
    };
    let rows = stress(&common::model("models/three-frame.toml"), &pick, &grid).unwrap();
    assert_eq!(rows.len(), 2 * 2 * 2, "every run of the table is run 1");
    for r in &rows {
        assert_eq!((r.status.as_str(), r.run), ("finished", 1), "{r:?}");
        assert!(r.max_penetration <= 1e-9, "{r:?}");
        assert_eq!(r.approaching, 0, "{r:?}");
        assert!(r.pull_rel <= 1e-9, "{r:?}");
        assert!(r.closure_rel <= r.rtol, "{r:?}");
    }
}

/// A run the model's `[[run]]` table does not have is refused before any run, by its argument.
#[test]
fn a_stress_run_beyond_the_models_table_is_refused_by_argument() {
    use deckspin::stress::{StressError, StressGrid, record_pairs, stress};
    let (pairs, _) = record_pairs(&common::model("excitations/far-field")).unwrap();
    let grid = StressGrid {
        runs: vec![1, 2],
        ..StressGrid::default()
    };
    let err = stress(&common::model("models/three-frame.toml"), &pairs, &grid).unwrap_err();
    assert!(
        matches!(
            err,
            StressError::NoRun {
                run: 2,
                count: 1,
                ..
            }
        ),
        "{err:?}"
    );
    let text = err.to_string();
    assert!(
        text.starts_with("--runs: ") && text.ends_with("no run 2 (its [[run]] table has 1..=1)"),
        "{text}"
    );
    let ball = common::model("models/validation/bouncing-ball.toml");
    let err = stress(&ball, &pairs, &StressGrid::default()).unwrap_err();
    assert!(
        err.to_string()
            .ends_with("no run 1 (the model has no [[run]] table)"),
        "{err}"
    );
}

#[test]
fn stiff_dashpots_and_infinite_energy_are_refused_before_the_run() {
    // actuator dashpots of 5.7e6 kN·s/m on the 0.65 t abutments decay at ~1.8e7 1/s: DP5
    // would need ~2e7 steps for 4 s
    let set = [
        "abutment.actuator_damping=5.7e6".to_string(),
        "solver.t_end=4".to_string(),
    ];
    let scene = deckspin::load(&common::model("models/four-span.toml"), &set).unwrap();
    let run = deckspin::simulate::integrate(&scene, &mut deckspin::Silent);
    let Stop::Failed(deckspin::SolverError::TooStiff { omega, .. }) = run.stop else {
        panic!("{:?}", run.stop)
    };
    // c (Jᵀ M⁻¹ J) of one actuator on the abutment's x: 5.7e6 / 0.65
    assert!(omega >= 5.7e6 / 0.65 * 0.999, "{omega:e}");
    // an initial kinetic energy that overflows: a typed failure at t = 0, for every method
    for method in ["event", "moreau", "penalty", "penalty-explicit"] {
        let mut scene =
            deckspin::load(&common::model("models/validation/block-on-plane.toml"), &[]).unwrap();
        scene.settings.method = deckspin::methods::Method::parse(method).unwrap();
        scene.v0[0] = 1e308;
        let run = deckspin::simulate::integrate(&scene, &mut deckspin::Silent);
        assert!(
            matches!(run.stop, Stop::Failed(deckspin::SolverError::NonFinite { t }) if t == 0.0),
            "{method}: {:?}",
            run.stop
        );
    }
}

/// An event-driven `solver.h_max` whose steps alone exceed `solver.max_steps` is refused
/// before the run, with the estimate (it ran 42 s before failing on max_steps).
#[test]
fn an_event_driven_h_max_beyond_the_step_budget_is_refused_up_front() {
    let set = ["solver.h_max=1e-9".to_string()];
    let scene = deckspin::load(&common::model("models/four-span.toml"), &set).unwrap();
    let e = deckspin::run::check_output(&scene, &deckspin::run::OutputBudget::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("solver.h_max = 0.000000001 s") || e.contains("solver.h_max = 1e-9"),
        "{e}"
    );
    assert!(e.contains("1.600e10 event-driven steps"), "{e}");
    let ok = ["solver.h_max=1e-3".to_string()];
    let scene = deckspin::load(&common::model("models/four-span.toml"), &ok).unwrap();
    assert!(deckspin::run::check_output(&scene, &deckspin::run::OutputBudget::default()).is_ok());
}
