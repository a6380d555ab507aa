//! The results pages of the workbench's studies view (energy ledger, contact forces and
//! impulses, modes, input records with their spectrum) and the work-precision study: drawn
//! on ratatui's TestBackend with insta snapshots, and their numbers checked against the
//! library's.

#![cfg(feature = "workbench")]

mod common;

use common::root;
use common::tui::*;

use deckspin::excitation::G;
use deckspin::study_table::{StudyKind, StudyTable};
use deckspin::tui::app::{StatusKind, View};
use deckspin::tui::keymap::Action;
use deckspin::tui::msg::StudyOutcome;
use deckspin::tui::results::{JobState, Page};
use deckspin::tui::runs::data::{RunData, RunStatus};
use deckspin::tui::{self, App, Effect, Msg, update};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

// ---------------------------------------------------------------------------------------------
// fixtures

/// The four-span bridge shortened to 2 s with 4 mm gaps (impacts early on).
fn short_bridge() -> String {
    let mut t = set(
        &read(&root().join("models/four-span.toml")),
        "solver.t_end",
        "2.0",
    );
    for i in 0..4 {
        t = set(&t, &format!("contacts.gaps.{i}"), "0.004");
    }
    t
}

/// Run 2 of the short bridge, computed once per test binary.
fn bridge_run() -> &'static RunData {
    static R: OnceLock<RunData> = OnceLock::new();
    R.get_or_init(|| {
        let mut app = App::new_from_text(&short_bridge(), &root().join("models/four-span.toml"));
        app.next_run = 2;
        let fx = app.start();
        tui::execute_blocking(&mut app, fx);
        let run = app.current.expect("a run");
        assert_eq!(run.status, RunStatus::Finished, "{}", app.status);
        run
    })
}

/// The short bridge with run 2 current, in the studies view (relative path: snapshots do not
/// hold the checkout's location).
fn bridge_app() -> App {
    let mut app = App::new_from_text(&short_bridge(), Path::new("models/four-span.toml"));
    app.current = Some(bridge_run().clone());
    app.next_run = 3;
    app.view = View::Studies;
    app.set_status(StatusKind::Ok, "run 2 finished");
    app
}

/// Steps with `l` to `page`, executing what it starts (blocking).
fn show(app: &mut App, page: Page) {
    for _ in 0..20 {
        if app.results.page == Some(page) {
            return;
        }
        let fx = act(app, Action::StudyNext);
        tui::execute_blocking(app, fx);
    }
    panic!("{page:?} not reached");
}

/// Below the header line (shared with the other views), no character above 0x7E.
fn assert_ascii(s: &str, what: &str) {
    for (y, line) in s.lines().enumerate().skip(1) {
        let wide: Vec<char> = line.chars().filter(|c| *c as u32 > 0x7e).collect();
        assert!(wide.is_empty(), "{what} line {y}: {wide:?}\n{s}");
    }
}

fn ready<T: Clone>(s: Option<&JobState<T>>) -> T {
    match s {
        Some(JobState::Ready(d)) => d.clone(),
        s => panic!("not ready: {}", s.is_some()),
    }
}

// ---------------------------------------------------------------------------------------------
// numbers: what the pages show is what the library computes

#[test]
fn the_energy_page_carries_the_ledger_and_its_closure_is_the_summarys() {
    let r = bridge_run();
    let summary = r.summary.as_ref().expect("a finished run");
    let ledger = &r.results.ledger;
    for col in &ledger.terms {
        assert_eq!(col.len(), r.t.len());
    }
    // the largest |closure| of the samples is the summary's energy_closure_abs
    assert!(summary.energy_closure_abs > 0.0);
    assert_eq!(r.results.max_closure(), summary.energy_closure_abs);
    // the last sample's terms are the summary's final ledger
    let e = summary.energy_final;
    let last = |k: usize| *ledger.terms[k].last().unwrap();
    assert_eq!(last(0), e.initial + e.loads + e.supports);
    assert_eq!(last(1), e.kinetic);
    assert_eq!(last(6), e.impact_normal + e.impact_tangential);
    assert!(last(6) > 0.0, "impacts dissipate energy in this run");
    let mut app = bridge_app();
    show(&mut app, Page::Energy);
    let s = screen(&render(&mut app, 120, 40));
    let shown = format!(
        "max |closure| {} kJ",
        tui::chart::fmt_sig(summary.energy_closure_abs, 3)
    );
    assert!(s.contains(&shown), "{shown}\n{s}");
    for term in tui::results::run::TERMS {
        assert!(s.contains(term), "{term}\n{s}");
    }
}

#[test]
fn the_contacts_page_shows_each_corners_forces_and_impulses() {
    let r = bridge_run();
    let summary = r.summary.as_ref().unwrap();
    let f = &r.results.forces;
    for (i, c) in summary.contacts.iter().enumerate() {
        let peak = f.normal[i].iter().fold(0.0f64, |m, x| m.max(*x));
        assert_eq!(peak, c.max_normal_force, "{}", c.name);
        assert_eq!(r.impacts[i], c.impacts, "{}", c.name);
    }
    let mut app = bridge_app();
    show(&mut app, Page::Contacts);
    let busiest = (0..r.impacts.len()).max_by_key(|&i| r.impacts[i]).unwrap();
    for _ in 0..busiest {
        act(&mut app, Action::ResultDown);
    }
    assert_eq!(app.results.contact, busiest);
    let s = screen(&render(&mut app, 120, 40));
    let c = &summary.contacts[busiest];
    assert!(s.contains(&format!("{} impacts", c.impacts)), "{s}");
    let imp = format!(
        "max ΛN {} kN·s",
        tui::chart::fmt_sig(c.max_normal_impulse, 3)
    );
    assert!(s.contains(&imp), "{imp}\n{s}");
    // k wraps round to the last corner
    for _ in 0..=busiest {
        act(&mut app, Action::ResultUp);
    }
    assert_eq!(app.results.contact, r.contact_names.len() - 1);
}

#[test]
fn the_modes_page_gives_modal_rs_periods_and_mass_ratios() {
    let mut app = bridge_app();
    show(&mut app, Page::Modes);
    let m = ready(app.results.modes.as_ref().map(|j| &j.state));
    let scene = app.scene.clone().unwrap();
    let scene = &scene;
    let modes = deckspin::modal::modes(scene);
    let periods: Vec<f64> = modes.iter().map(|m| m.period).collect();
    assert_eq!(m.periods, periods);
    assert_eq!(m.ratios, deckspin::modal::participation(scene, &modes));
    // the effective masses of all modes add up to the mass of each direction
    for k in 0..3 {
        let sum: f64 = m.ratios.iter().map(|r| r[k]).sum();
        assert!((sum - 1.0).abs() < 1e-9, "direction {k}: {sum}");
    }
    let s = screen(&render(&mut app, 80, 24));
    let t1 = format!("{:>9}", tui::chart::fmt_sig(periods[0], 4));
    assert!(s.contains(&format!("   1 {t1}")), "{s}");
    // every DOF by its full name
    for n in &scene.dof_names {
        assert!(s.contains(n.as_str()), "{n}\n{s}");
    }
    act(&mut app, Action::ResultDown);
    let s = screen(&render(&mut app, 80, 24));
    assert!(
        s.contains("shape of mode 2") && s.contains("mode 2 of"),
        "{s}"
    );
}

#[test]
fn the_records_page_spectrum_at_t1_is_intensity_rs_sa() {
    let mut app = bridge_app();
    show(&mut app, Page::Records);
    let d = ready(app.results.records.as_ref().map(|j| &j.state));
    let scene = app.scene.clone().unwrap();
    let scene = &scene;
    let t1 = deckspin::modal::modes(scene)[0].period;
    assert_eq!(d.t1, t1);
    let (recs, _) = tui::results::record_supports(scene);
    assert_eq!(d.components.len(), recs.len());
    assert!(!recs.is_empty());
    for (c, (name, acc, dt, ..)) in d.components.iter().zip(&recs) {
        assert_eq!(&c.name, name);
        let sa = deckspin::suite::intensity::pseudo_acceleration(acc, *dt, t1, 0.05) / G;
        assert_eq!(c.sa_t1, sa, "{name}");
        // each point of the spectrum is intensity.rs's Sa at its period, 0.02 to 5 s
        assert_eq!(c.spectrum.len(), 60);
        for &(t, sa) in c.spectrum.iter().step_by(7) {
            let want = deckspin::suite::intensity::pseudo_acceleration(acc, *dt, t, 0.05) / G;
            assert_eq!(sa, want, "{name} T {t}");
        }
        let ends = (c.spectrum[0].0, c.spectrum[59].0);
        assert!(
            (ends.0 - 0.02).abs() < 1e-12 && (ends.1 - 5.0).abs() < 1e-12,
            "{ends:?}"
        );
    }
    let s = screen(&render(&mut app, 120, 40));
    let c = &d.components[0];
    let shown = format!(
        "T1 {} s: Sa {} g",
        tui::chart::fmt_sig(t1, 3),
        tui::chart::fmt_sig(c.sa_t1, 3)
    );
    assert!(s.contains(&shown), "{shown}\n{s}");
    assert!(s.contains(&format!("{} acceleration [g]", c.name)), "{s}");
    act(&mut app, Action::ResultDown);
    let s = screen(&render(&mut app, 120, 40));
    assert!(
        s.contains(&format!("{} acceleration [g]", d.components[1].name)),
        "{s}"
    );
}

#[test]
fn a_results_computation_runs_in_a_worker_and_esc_cancels_it() {
    let mut app = bridge_app();
    // reaching the page starts its computation (not on the UI thread: an effect)
    for _ in 0..StudyKind::ALL.len() + 2 {
        act(&mut app, Action::StudyNext);
    }
    assert_eq!(app.results.page, Some(Page::Modes));
    let fx = act(&mut app, Action::StudyNext);
    assert_eq!(app.results.page, Some(Page::Records));
    let id = match fx.as_slice() {
        [Effect::StartResult { id, .. }] => *id,
        fx => panic!("{fx:?}"),
    };
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("computing"), "{s}");
    // Esc asks the worker to stop
    let fx = act(&mut app, Action::StudyCancel);
    assert!(
        matches!(fx.as_slice(), [Effect::CancelResult { id: i }] if *i == id),
        "{fx:?}"
    );
    // a worker whose flag is set stops before the end and says so
    let spec = tui::results::ResultSpec::Records(Box::new(app.scene.clone().unwrap()));
    let flag = std::sync::atomic::AtomicBool::new(true);
    let done = tui::workers::results::run(id, &spec, &flag, &|_| {});
    update(&mut app, done);
    assert!(matches!(
        app.results.records.as_ref().unwrap().state,
        JobState::Cancelled
    ));
    assert!(app.status.contains("cancelled"), "{}", app.status);
    // Enter computes it again, to its end, with progress on the way
    let fx = act(&mut app, Action::StudyRun);
    let (id, spec) = match fx.into_iter().next() {
        Some(Effect::StartResult { id, spec }) => (id, spec),
        e => panic!("{e:?}"),
    };
    let msgs = tui::workers::results::run_blocking(id, &spec);
    assert!(msgs.iter().any(|m| matches!(m, Msg::ResultProgress { .. })));
    for m in msgs {
        update(&mut app, m);
    }
    assert!(matches!(
        app.results.records.as_ref().unwrap().state,
        JobState::Ready(_)
    ));
    // an edit makes the page stale: it says so
    app.draft = set(&app.draft, "contacts.gaps.0", "0.005");
    let s = screen(&render(&mut app, 120, 40));
    assert!(
        s.contains("the form changed since: Enter recomputes"),
        "{s}"
    );
}

// ---------------------------------------------------------------------------------------------
// work-precision and stability

/// The work-precision study of the short bridge: its point messages and its table.
fn precision_run() -> &'static (Vec<usize>, StudyTable) {
    static P: OnceLock<(Vec<usize>, StudyTable)> = OnceLock::new();
    P.get_or_init(|| {
        let mut app = bridge_app();
        app.studies.selected = StudyKind::ALL
            .iter()
            .position(|k| *k == StudyKind::Precision)
            .unwrap();
        let fx = act(&mut app, Action::StudyRun);
        let (id, spec) = match fx.into_iter().next() {
            Some(Effect::StartStudy { id, spec }) => (id, spec),
            e => panic!("{e:?} {}", app.status),
        };
        let msgs = tui::workers::study::run_blocking(id, &spec);
        let mut points = Vec::new();
        let mut table = None;
        for m in msgs {
            match m {
                Msg::StudyPoint { index, .. } => points.push(index),
                Msg::StudyDone {
                    outcome: StudyOutcome::Finished(t),
                    ..
                } => table = Some(*t),
                m => panic!("{m:?}"),
            }
        }
        (points, table.expect("finished"))
    })
}

fn precision_app() -> App {
    let mut app = bridge_app();
    app.studies.selected = StudyKind::ALL
        .iter()
        .position(|k| *k == StudyKind::Precision)
        .unwrap();
    let fx = act(&mut app, Action::StudyRun);
    let id = match fx.as_slice() {
        [Effect::StartStudy { id, .. }] => *id,
        fx => panic!("{fx:?}"),
    };
    // its plan is there from the start: progress counts points
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("work-precision: 0/12"), "{s}");
    let outcome = StudyOutcome::Finished(Box::new(precision_run().1.clone()));
    let fx = update(&mut app, Msg::StudyDone { id, outcome });
    assert!(
        matches!(fx.as_slice(), [Effect::WriteStudy { .. }]),
        "{fx:?}"
    );
    let csv = PathBuf::from("models/four-span.out/precision-1.csv");
    update(
        &mut app,
        Msg::StudyWritten {
            id,
            result: Ok(csv),
        },
    );
    app
}

#[test]
fn work_precision_runs_point_by_point_with_stabilitys_verdicts_and_its_csv_reads_back() {
    use deckspin::precision::{INACCURATE_ABOVE, Verdict, verdict};
    let (indices, table) = precision_run();
    let StudyTable::Precision(t) = table else {
        panic!("{table:?}")
    };
    // every planned point, each sent as it was final, in order
    assert_eq!(indices, &(0..t.planned.len()).collect::<Vec<_>>());
    assert_eq!(t.progress(), (12, 12));
    let points = t.done_points();
    // the event-driven points are within 1 % of the reference; some coarse step is not fine
    for p in points
        .iter()
        .filter(|p| p.method == deckspin::methods::Method::Event)
    {
        assert!(
            matches!(verdict(p, INACCURATE_ABOVE), Verdict::Ok { .. }),
            "{p:?}"
        );
        assert!(p.peak_error < 0.01, "{p:?}");
    }
    assert!(
        points
            .iter()
            .any(|p| !matches!(verdict(p, INACCURATE_ABOVE), Verdict::Ok { .. }))
    );
    // the CSV holds the same numbers bit for bit
    let text = deckspin::study_csv::to_csv(table);
    assert!(text.starts_with("study,method,knob,cpu_s,"), "{text}");
    let back = deckspin::study_csv::read_csv(&text, Path::new("precision-1.csv")).unwrap();
    assert_eq!(&back, table);
    // the grid shows the shared legend and threshold, one row per method
    let mut app = precision_app();
    act(&mut app, Action::ResultGrid);
    let s = screen(&render(&mut app, 120, 40));
    assert!(s.contains("error above 5 %"), "{s}");
    for name in ["ok", "inaccurate", "unstable", "failed"] {
        assert!(s.contains(name), "{name}\n{s}");
    }
    let grid = deckspin::figures::stability(&points, INACCURATE_ABOVE);
    for row in &grid.rows {
        assert!(s.contains(&row.label), "{}\n{s}", row.label);
    }
}

#[test]
fn every_results_page_in_ascii_mode_and_without_colour() {
    for page in Page::ALL {
        let mut app = bridge_app();
        show(&mut app, page);
        app.ascii = true;
        for (w, h) in [(80, 24), (120, 40), (60, 18)] {
            assert_ascii(
                &screen(&render(&mut app, w, h)),
                &format!("{page:?} {w}x{h}"),
            );
        }
        app.ascii = false;
        app.opts.color = false;
        let t = render(&mut app, 80, 24);
        for c in t.backend().buffer().content() {
            assert_eq!(
                c.fg,
                ratatui::style::Color::Reset,
                "{page:?}: coloured cell {c:?}"
            );
        }
    }
    let mut app = precision_app();
    app.ascii = true;
    for grid in [false, true] {
        app.results.grid = grid;
        assert_ascii(&screen(&render(&mut app, 80, 24)), "precision");
    }
    // without colour the ledger's terms differ by their marks, named in the legend
    let mut app = bridge_app();
    show(&mut app, Page::Energy);
    app.opts.color = false;
    let s = screen(&render(&mut app, 120, 40));
    assert!(s.contains("I input  K kinetic  E elastic"), "{s}");
}

// ---------------------------------------------------------------------------------------------
// snapshots

fn snap(app: &mut App, w: u16, h: u16, name: &str) {
    let t = render(app, w, h);
    snapshot_settings().bind(|| insta::assert_snapshot!(name, t.backend()));
}

#[test]
fn snapshot_results_pages() {
    for page in Page::ALL {
        let mut app = bridge_app();
        show(&mut app, page);
        let name = page.title();
        snap(&mut app, 80, 24, &format!("results_{name}_80x24"));
        snap(&mut app, 120, 40, &format!("results_{name}_120x40"));
    }
    let mut app = bridge_app();
    show(&mut app, Page::Records);
    app.ascii = true;
    snap(&mut app, 80, 24, "results_records_80x24_ascii");
    let mut app = bridge_app();
    show(&mut app, Page::Modes);
    app.ascii = true;
    let t = render(&mut app, 80, 24);
    assert_ascii(&screen(&t), "modes");
    assert!(
        screen(&t).contains("mode 1 on the plan x1"),
        "{}",
        screen(&t)
    );
    snap(&mut app, 80, 24, "results_modes_80x24_ascii");
}

#[test]
fn snapshot_precision() {
    // CPU times differ from run to run: the chart's shape is not pinned, its frame is
    let mut app = precision_app();
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("work-precision and stability"), "{s}");
    assert!(s.contains("1 %") && s.contains("CPU time [s], log"), "{s}");
    app.results.grid = true;
    let t = render(&mut app, 120, 40);
    let mut s = screen(&t);
    // the grid has no clock values: pinned whole
    s = s
        .lines()
        .filter(|l| !l.contains("cpu"))
        .collect::<Vec<_>>()
        .join("\n");
    snapshot_settings().bind(|| insta::assert_snapshot!("precision_grid_120x40", s));
}

/// The canvas of the modes page's plan (inside its border) and its title line.
fn mode_plan(s: &str) -> (String, Vec<Vec<char>>) {
    let lines: Vec<&str> = s.lines().collect();
    let top = (lines.iter().position(|l| l.contains(" on the plan ×")))
        .unwrap_or_else(|| panic!("no mode plan:\n{s}"));
    let bottom = top
        + lines[top..]
            .iter()
            .position(|l| l.starts_with('└'))
            .unwrap();
    let rows = lines[top + 1..bottom]
        .iter()
        .map(|l| {
            let inner: Vec<char> = l.chars().skip(1).collect();
            let end = inner.iter().position(|&c| c == '│').unwrap();
            inner[..end].to_vec()
        })
        .collect();
    (lines[top].to_string(), rows)
}

#[test]
fn the_modes_page_draws_the_selected_mode_on_the_plan() {
    let mut app = bridge_app();
    show(&mut app, Page::Modes);
    // without colour only the displaced outline is drawn
    app.opts.color = false;
    let mut plans = Vec::new();
    for k in 1..=5 {
        assert_eq!(app.results.mode, k - 1);
        let s = screen(&render(&mut app, 120, 40));
        let (title, rows) = mode_plan(&s);
        assert!(
            title.contains(&format!("┌ mode {k} on the plan ×")),
            "{title}"
        );
        assert!(
            rows.iter().flatten().filter(|c| **c != ' ').count() > 50,
            "an outline is drawn:\n{s}"
        );
        plans.push(rows);
        act(&mut app, Action::ResultDown);
    }
    // modes 1 (deck y and θ), 2 (deck x), 4 (left abutment x) are drawn differently
    assert_ne!(plans[0], plans[1]);
    assert_ne!(plans[1], plans[3]);
    assert_ne!(plans[0], plans[3]);
    // modes 4 and 5 move only the left or the right abutment: they differ at the ends of the
    // bridge, and nowhere in the middle half, where the deck is at rest in both
    let (a, b) = (&plans[3], &plans[4]);
    let w = a[0].len();
    let mut differ = Vec::new();
    for (ra, rb) in a.iter().zip(b) {
        for x in 0..w {
            if ra[x] != rb[x] {
                differ.push(x);
            }
        }
    }
    assert!(differ.iter().any(|&x| x < w / 4), "{differ:?}");
    assert!(differ.iter().any(|&x| x >= 3 * w / 4), "{differ:?}");
    assert!(
        differ.iter().all(|&x| x < w / 4 || x >= 3 * w / 4),
        "{differ:?} of {w}"
    );
    // a terminal too short for it: the table alone
    let s = screen(&render(&mut app, 80, 18));
    assert!(!s.contains("on the plan"), "{s}");
    assert!(s.contains("shape of mode 6"), "{s}");
}

#[test]
fn the_results_worker_runs_in_its_own_named_thread_and_sends_its_end() {
    use deckspin::tui::msg::{ResultData, ResultOutcome};
    use deckspin::tui::results::ResultSpec;
    let app = bridge_app();
    let scene = app.scene.clone().expect("the model loads");
    let (tx, rx) = std::sync::mpsc::channel();
    let h = tui::workers::results::spawn(7, ResultSpec::Modes(Box::new(scene)), tx);
    assert_eq!(h.id, 7);
    let msg = rx
        .recv_timeout(std::time::Duration::from_secs(30))
        .expect("the worker's end");
    let Msg::ResultDone { id, outcome } = msg else {
        panic!("not the end: {msg:?}")
    };
    assert_eq!(id, 7);
    let ResultOutcome::Done(ResultData::Modes(m)) = outcome else {
        panic!("{outcome:?}")
    };
    // the same modes as in this thread
    let blocking = tui::workers::results::run_blocking(
        7,
        &ResultSpec::Modes(Box::new(app.scene.clone().unwrap())),
    );
    let Some(Msg::ResultDone {
        outcome: ResultOutcome::Done(ResultData::Modes(b)),
        ..
    }) = blocking.last()
    else {
        panic!("{blocking:?}")
    };
    assert_eq!(m.periods, b.periods);
    assert_eq!(m.periods.len(), 7);
    assert!((m.periods[0] - 0.3892).abs() < 5e-5, "{}", m.periods[0]);
}
