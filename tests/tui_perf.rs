//! Frame cost with a 10⁵-sample history at 120×40 (printed with `--nocapture`; no time is
//! asserted). The run is synthetic: the four-span bridge's names and geometry with made-up
//! samples (a spike per 1000 samples, contact states cycling) streamed through `update`.

#![cfg(feature = "workbench")]

use deckspin::output::{
    ContactSample, ContactState, EventKind, EventRecord, RunOutput, Sample, SampleKind,
};
use deckspin::tui::keymap::Action;
use deckspin::tui::msg::RunOutcome;
use deckspin::tui::{self, App, Msg, update};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use std::path::Path;
use std::time::{Duration, Instant};

const N: usize = 100_000;

fn synthetic(scene: &deckspin::scene::Scene) -> RunOutput {
    let mut out = RunOutput::new(scene);
    let nd = out.dof_names.len();
    let nc = out.contact_names.len();
    let ne = out.element_names.len();
    let dt = scene.settings.t_end / N as f64;
    for i in 0..N {
        let t = i as f64 * dt;
        let spike = if i % 1000 == 500 { 5.0 } else { 1.0 };
        let q: Vec<f64> = (0..nd)
            .map(|k| spike * 1e-3 * (t * (k + 1) as f64).sin())
            .collect();
        let contacts = (0..nc)
            .map(|c| ContactSample {
                gap: (0.01 * (t + c as f64).cos()).max(0.0),
                gap_rate: 0.0,
                slip_rate: 0.0,
                normal_force: 0.0,
                tangential_force: 0.0,
                state: match (i / 700 + c) % 3 {
                    0 => ContactState::Open,
                    1 => ContactState::Stick,
                    _ => ContactState::Slide(1.0),
                },
            })
            .collect();
        let elements = (0..ne)
            .map(|j| ((t + j as f64).sin() * 0.01, (t + j as f64).sin() * 50.0))
            .collect();
        out.samples.push(Sample {
            t,
            kind: SampleKind::Grid,
            q: q.clone(),
            v: q,
            contacts,
            elements,
            energy: Default::default(),
        });
        if i % 1000 == 500 {
            out.events.push(EventRecord {
                t,
                contact: (i / 1000) % nc.max(1),
                kind: EventKind::Impact,
                normal: 1.0,
                tangential: 0.0,
                gap_rate_before: -0.1,
                gap_rate_after: 0.0,
                slip_rate_after: 0.0,
                sticks: Some(false),
                info: f64::NAN,
            });
        }
    }
    out.finish(1.0);
    out
}

fn time_frames(
    term: &mut Terminal<TestBackend>,
    app: &mut App,
    cache: &mut tui::ui::Cache,
    frames: usize,
    mut between: impl FnMut(&mut App),
) -> Duration {
    let t0 = Instant::now();
    for _ in 0..frames {
        between(app);
        term.draw(|f| tui::ui::draw(f, app, cache)).unwrap();
    }
    t0.elapsed() / frames as u32
}

#[test]
fn frame_time_with_1e5_samples_at_120x40() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/four-span.toml");
    let mut app = App::new_from_path(&path, Default::default()).unwrap();
    let scene = app.scene.clone().unwrap();
    let out = synthetic(&scene);
    let fx = app.start();
    let id = match &fx[..] {
        [tui::Effect::StartRun { id, .. }] => *id,
        _ => panic!("{fx:?}"),
    };
    let t0 = Instant::now();
    for chunk in out.samples.chunks(256) {
        let t = chunk.last().unwrap().t;
        let events: Vec<EventRecord> = out
            .events
            .iter()
            .filter(|e| e.t >= chunk[0].t && e.t <= t)
            .cloned()
            .collect();
        update(
            &mut app,
            Msg::Batch {
                run: id,
                samples: chunk.to_vec(),
                events,
                t,
            },
        );
    }
    let ingest = t0.elapsed();
    update(
        &mut app,
        Msg::RunDone {
            run: id,
            outcome: RunOutcome::Finished(Box::new(out)),
        },
    );
    assert_eq!(app.current.as_ref().unwrap().t.len(), N);
    update(&mut app, Msg::Resize(120, 40));
    let mut term = Terminal::new(TestBackend::new(120, 40)).unwrap();
    let mut cache = tui::ui::Cache::default();

    let cold = time_frames(&mut term, &mut app, &mut cache, 1, |_| {});
    let warm = time_frames(&mut term, &mut app, &mut cache, 20, |_| {});
    let mut moved = 0;
    let scrub = time_frames(&mut term, &mut app, &mut cache, 20, |a| {
        moved += 1;
        update(
            a,
            Msg::Action(if moved == 1 {
                Action::CursorHome
            } else {
                Action::CursorRight
            }),
        );
    });
    let zoom = time_frames(&mut term, &mut app, &mut cache, 6, |a| {
        update(a, Msg::Action(Action::ZoomIn));
    });
    // new data every frame (what a streaming run costs): the current run grows by one sample
    update(&mut app, Msg::Action(Action::ZoomReset));
    let streaming = time_frames(&mut term, &mut app, &mut cache, 5, |a| {
        let grow = a.current.as_mut().unwrap();
        grow.t.push(grow.t.last().unwrap() + 1e-9);
        for c in grow.q.iter_mut().chain(grow.gap.iter_mut()) {
            c.push(0.0);
        }
        for s in grow.state.iter_mut() {
            s.push(ContactState::Open);
        }
        for (d, f) in grow.el.iter_mut() {
            d.push(0.0);
            f.push(0.0);
        }
    });
    println!(
        "ingest of 10^5 samples in 256-sample batches: {:.1} ms",
        ingest.as_secs_f64() * 1e3
    );
    println!(
        "draw 120x40, 10^5 samples, first frame (cold caches): {:.2} ms",
        cold.as_secs_f64() * 1e3
    );
    println!(
        "draw 120x40, 10^5 samples, warm caches:              {:.2} ms",
        warm.as_secs_f64() * 1e3
    );
    println!(
        "draw 120x40, 10^5 samples, scrubbing the cursor:     {:.2} ms",
        scrub.as_secs_f64() * 1e3
    );
    println!(
        "draw 120x40, 10^5 samples, zooming in:               {:.2} ms",
        zoom.as_secs_f64() * 1e3
    );
    println!(
        "draw 120x40, 10^5 samples, data changed every frame: {:.2} ms",
        streaming.as_secs_f64() * 1e3
    );
}
