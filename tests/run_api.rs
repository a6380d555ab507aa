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
    assert!(t >= 5.0 && t < 16.0, "cancelled at {t}");
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
    let set = ["solver.max_steps=400".to_string()];
    let scene = deckspin::load(&common::model("models/four-span.toml"), &set).unwrap();
    let run = deckspin::event_driven::integrate(&scene, &mut deckspin::Silent);
    let Stop::Failed(deckspin::SolverError::TooManySteps { t, limit }) = run.stop else {
        panic!("{:?}", run.stop)
    };
    assert_eq!(limit, 400);
    assert_eq!(
        run.output.stats.steps_accepted + run.output.stats.steps_rejected,
        400
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
    let set = ["solver.method=\"penalty-explicit\"".to_string()];
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
