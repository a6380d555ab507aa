//! The workbench's run list: every run kept as `#N`, a pinned baseline, the model diff of each
//! run against it, runs overlaid and compared, the list stored beside the model and reopened,
//! bounded; drawn at 80×24 and 120×40 (insta snapshots in tests/snapshots/).

#![cfg(feature = "workbench")]

mod common;

use common::root;
use common::tui::*;

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use deckspin::tui::app::{Mode, StatusKind, View};
use deckspin::tui::keymap::Action;
use deckspin::tui::runs::data::{RunData, RunStatus};
use deckspin::tui::runs::list::{self as run_list, Ended, Entry, KEEP, MAX_SAMPLES, Runs};
use deckspin::tui::{self, App, Effect, Msg, Options, form, runs::store as run_store, update};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

// ---------------------------------------------------------------------------------------------
// fixtures

/// #1 (6 mm gaps), #2 (4 mm), #3 (5 mm) of the short bridge, computed once.
fn bridge_runs() -> &'static [(RunData, String); 3] {
    static R: OnceLock<[(RunData, String); 3]> = OnceLock::new();
    R.get_or_init(|| {
        [("0.006", 1), ("0.004", 2), ("0.005", 3)].map(|(g, n)| {
            let text = short_bridge(g);
            (run_of(&text, &bridge_path(), n), text)
        })
    })
}

/// The short bridge with #1 the baseline, #2 shown, #3 overlaid; the path relative so that
/// snapshots do not hold the checkout's location.
fn runs_app(opts: Options) -> App {
    let path = Path::new("models/four-span.toml");
    let mut app = App::with_options(&short_bridge("0.004"), path, opts);
    let saved = app.text.clone();
    for (r, text) in bridge_runs() {
        app.runs.add(Entry::of_run(r, text.clone()), &saved);
        if r.id == 1 {
            app.runs.pin(1);
        }
    }
    app.current = Some(bridge_runs()[1].0.clone());
    app.runs.toggle_overlay(3).unwrap();
    app.runs.selected = 2;
    app.next_run = 4;
    app.view = View::Runs;
    app.set_status(StatusKind::Ok, "#3 overlaid on the charts and compared");
    app
}

/// Edits a field of the form: select it, Enter, clear, type, Enter.
fn edit(app: &mut App, path: &str, value: &str) {
    app.view = View::Form;
    app.form.selected = app
        .form
        .index_of(path)
        .unwrap_or_else(|| panic!("no {path}"));
    update(app, code(KeyCode::Enter));
    update(
        app,
        Msg::Key(KeyEvent::new(KeyCode::Char('u'), KeyModifiers::CONTROL)),
    );
    for c in value.chars() {
        update(app, key(c));
    }
    update(app, code(KeyCode::Enter));
    assert_eq!(app.mode, Mode::Normal, "{path}={value}: {}", app.status);
}

fn run(app: &mut App, fx: Vec<Effect>) {
    tui::execute_blocking(app, fx);
    let cur = app.current.as_ref().expect("a run");
    assert_eq!(cur.status, RunStatus::Finished, "{}", app.status);
}

/// A scratch folder with models/ (the short bridge) and excitations/; the model's path.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("deckspin-runs-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(d.join("models")).unwrap();
    std::fs::create_dir_all(d.join("excitations")).unwrap();
    for e in std::fs::read_dir(root().join("excitations")).unwrap() {
        let e = e.unwrap();
        if e.path().is_file() {
            std::fs::copy(e.path(), d.join("excitations").join(e.file_name())).unwrap();
        }
    }
    let model = d.join("models/four-span.toml");
    std::fs::write(&model, short_bridge("0.004")).unwrap();
    model
}

/// The cells of the comparison's row `label` (the text between the table's borders).
fn compare_row(s: &str, label: &str) -> Vec<String> {
    let line = s
        .lines()
        .find(|l| l.contains(&format!("│{label} ")))
        .unwrap_or_else(|| panic!("no row {label}:\n{s}"));
    let inner = line.rsplit('│').nth(1).unwrap();
    inner[label.len()..]
        .split_whitespace()
        .map(str::to_string)
        .collect()
}

/// The run numbers heading the comparison (the baseline's `base` left out).
fn compare_head(s: &str) -> Vec<String> {
    let line = s
        .lines()
        .find(|l| l.contains(" base "))
        .unwrap_or_else(|| panic!("no comparison:\n{s}"));
    line.rsplit('│')
        .nth(1)
        .unwrap()
        .split_whitespace()
        .filter(|w| *w != "base")
        .map(str::to_string)
        .collect()
}

// ---------------------------------------------------------------------------------------------
// the session

#[test]
fn edit_run_pin_edit_run_compare_save_and_reopen() {
    let model = scratch("session");
    let dir = model.parent().unwrap().join("four-span.runs");
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    assert!(app.runs.list.is_empty());
    assert_eq!(app.runs.dir.as_deref(), Some(dir.as_path()));
    let fx = app.start();
    run(&mut app, fx);
    assert_eq!(app.runs.baseline, Some(1), "the first finished run");
    assert_eq!(app.runs.get(1).unwrap().name, "as saved");
    // edit a gap, run: #2
    edit(&mut app, "contacts.gaps.2", "0.006");
    let fx = act(&mut app, Action::Rerun);
    run(&mut app, fx);
    assert_eq!(
        app.runs.get(2).unwrap().name,
        "contacts gap 3 (right_top)=0.006"
    );
    // pin #2 in the run list
    update(&mut app, key('#'));
    assert_eq!(app.view, View::Runs);
    assert_eq!(app.runs.selected_entry().unwrap().number, 2);
    let fx = update(&mut app, key('b'));
    assert!(
        matches!(fx.as_slice(), [Effect::StoreRuns { .. }]),
        "{fx:?}"
    );
    tui::execute_blocking(&mut app, fx);
    assert_eq!(app.runs.baseline, Some(2));
    let one = app.runs.get(1).unwrap();
    assert_eq!(one.changes.len(), 1);
    assert_eq!(
        one.changes[0].line(),
        "contacts gap 3 (right_top): 0.006 → 0.004"
    );
    // edit μ, run: #3, compared with #2 (the baseline), never implicitly with the run before
    edit(&mut app, "contacts.mu", "0.2");
    let fx = act(&mut app, Action::Rerun);
    run(&mut app, fx);
    let three = app.runs.get(3).unwrap().clone();
    assert_eq!(three.name, "contacts.mu=0.2");
    let lines: Vec<String> = three.changes.iter().map(|c| c.line()).collect();
    assert_eq!(lines, ["contacts.mu: 0.5 → 0.2"]);
    // overlay #1 too: the table has the baseline, the shown run and #1
    app.view = View::Runs;
    app.runs.selected = 0;
    update(&mut app, key(' '));
    assert!(app.runs.get(1).unwrap().overlay);
    app.runs.selected = 2;
    let s = screen(&render(&mut app, 120, 40));
    assert!(s.contains("#3 against #2: 1 changed"), "{s}");
    assert!(s.contains("contacts.mu: 0.5 → 0.2"), "{s}");
    assert_eq!(compare_head(&s), ["#2", "#3", "#1"], "{s}");
    let want: Vec<String> = [2, 3, 1]
        .iter()
        .map(|&n| app.runs.get(n).unwrap().results.impacts.to_string())
        .collect();
    assert_eq!(compare_row(&s, "impacts"), want, "{s}");
    let peaks: Vec<String> = [2, 3, 1]
        .iter()
        .map(|&n| run_list::cell(app.runs.get(n).unwrap().results.peak_rot))
        .collect();
    assert_eq!(compare_row(&s, "peak |θ|"), peaks, "{s}");
    assert_ne!(peaks[0], peaks[1], "μ changes the peak rotation");
    // every overlaid run on the charts, with its number in the legend
    app.view = View::Charts;
    let s = screen(&render(&mut app, 120, 40));
    let head = s.lines().find(|l| l.starts_with("deck.theta [")).unwrap();
    let (a, b) = (head.find("┈#2 ").unwrap(), head.find("┈#1 ").unwrap());
    assert!(a < b, "{s}");
    // save: the list and the baseline stay; the saved text is #3's: #3 reused, not run again
    let fx = act(&mut app, Action::Save);
    run(&mut app, fx);
    assert!(
        app.status
            .ends_with("#3 reused: same model text (r reruns it)"),
        "{}",
        app.status
    );
    let numbers: Vec<u64> = app.runs.list.iter().map(|e| e.number).collect();
    assert_eq!(numbers, [1, 2, 3]);
    assert_eq!(app.runs.baseline, Some(2));
    assert_eq!(app.runs.get(3).unwrap().name, "contacts.mu=0.2");
    // a later session on the same file: the list, the names, the baseline, the overlay
    let before = app.runs.clone();
    let mut again = App::new_from_path(&model, Options::default()).unwrap();
    assert!(
        again
            .status
            .contains("3 runs reopened from four-span.runs/, baseline #2"),
        "{}",
        again.status
    );
    assert_eq!(again.runs.baseline, Some(2));
    assert_eq!(again.next_run, 4);
    for (a, b) in before.list.iter().zip(&again.runs.list) {
        assert_eq!((a.number, &a.name, &a.model), (b.number, &b.name, &b.model));
        assert_eq!(a.results, b.results, "#{}", a.number);
        assert_eq!(a.changes, b.changes, "#{}", a.number);
    }
    // the saved text is #3's: shown, its series and the baseline's read back
    let fx = again.start();
    run(&mut again, fx);
    assert_eq!(again.current.as_ref().unwrap().id, 3);
    for (a, b) in before.list.iter().zip(&again.runs.list) {
        if b.series != run_list::Series::InMemory {
            continue;
        }
        assert_eq!(a.data.t, b.data.t, "#{}: times exact", a.number);
        let (qa, qb) = (&a.data.q[0], &b.data.q[0]);
        assert_eq!(qa.len(), qb.len());
        for (x, y) in qa.iter().zip(qb) {
            assert!((x - y).abs() <= 1e-6 * x.abs().max(1e-12), "{x} {y}");
        }
    }
    let loaded: Vec<u64> = (again.runs.list.iter())
        .filter(|e| e.series == run_list::Series::InMemory)
        .map(|e| e.number)
        .collect();
    assert_eq!(loaded, [2, 3], "the baseline and the shown run");
    let s = screen(&render(&mut again, 120, 40));
    assert!(s.contains(" ┈#2 "), "the baseline overlaid: {s}");
    assert!(s.contains("#2 base"), "{s}");
    let _ = std::fs::remove_dir_all(model.parent().unwrap().parent().unwrap());
}

#[test]
fn a_run_is_named_by_key_and_the_name_is_stored() {
    let model = scratch("name");
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    let fx = app.start();
    run(&mut app, fx);
    update(&mut app, key('#'));
    update(&mut app, key('n'));
    assert!(matches!(app.mode, Mode::Naming { number: 1, .. }));
    update(
        &mut app,
        Msg::Key(KeyEvent::new(KeyCode::Char('u'), KeyModifiers::CONTROL)),
    );
    for c in "design gap".chars() {
        update(&mut app, key(c));
    }
    // the keys of the list are letters of the name while naming
    update(&mut app, key('b'));
    update(&mut app, code(KeyCode::Backspace));
    let fx = update(&mut app, code(KeyCode::Enter));
    tui::execute_blocking(&mut app, fx);
    assert_eq!(app.mode, Mode::Normal);
    assert_eq!(app.runs.get(1).unwrap().name, "design gap");
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("design gap"), "{s}");
    let again = App::new_from_path(&model, Options::default()).unwrap();
    assert_eq!(again.runs.get(1).unwrap().name, "design gap");
    assert!(again.runs.get(1).unwrap().named);
    // an empty name gives the derived one back
    update(&mut app, key('n'));
    update(
        &mut app,
        Msg::Key(KeyEvent::new(KeyCode::Char('u'), KeyModifiers::CONTROL)),
    );
    update(&mut app, code(KeyCode::Enter));
    assert_eq!(app.runs.get(1).unwrap().name, "as saved");
    let _ = std::fs::remove_dir_all(model.parent().unwrap().parent().unwrap());
}

#[test]
fn corrupt_and_foreign_files_are_reported_and_skipped() {
    let model = scratch("corrupt");
    let dir = model.parent().unwrap().join("four-span.runs");
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    let fx = app.start();
    run(&mut app, fx);
    std::fs::write(dir.join("notes.txt"), "mine").unwrap();
    std::fs::write(dir.join("0007.json"), "{ not json").unwrap();
    std::fs::write(dir.join("0008.csv"), "t\n0\n").unwrap();
    // a run whose series file is broken
    for ext in ["json", "toml"] {
        std::fs::copy(
            dir.join(format!("0001.{ext}")),
            dir.join(format!("0009.{ext}")),
        )
        .unwrap();
    }
    std::fs::write(dir.join("0009.csv"), "t,q:deck.theta\n0,abc\n").unwrap();
    let again = App::new_from_path(&model, Options::default()).unwrap();
    assert_eq!(again.status_kind, StatusKind::Warn);
    let s = &again.status;
    assert!(s.contains("1 run reopened"), "{s}");
    assert!(s.contains("notes.txt: not a run's file"), "{s}");
    assert!(s.contains("0007.json: "), "{s}");
    assert!(s.contains("0008.csv: no 0008.json"), "{s}");
    assert!(s.contains("0009.json: not the metadata of run #9"), "{s}");
    let numbers: Vec<u64> = again.runs.list.iter().map(|e| e.number).collect();
    assert_eq!(numbers, [1]);
    // nothing of them is touched
    assert_eq!(read(&dir.join("notes.txt")), "mine");
    let _ = std::fs::remove_dir_all(model.parent().unwrap().parent().unwrap());
}

#[test]
fn the_list_keeps_the_newest_runs_and_the_baseline() {
    let mut runs = Runs::default();
    let blank = |n: u64| {
        let mut r = RunData::new(
            n,
            format!("#{n}"),
            vec!["deck.theta".into()],
            vec![],
            vec![],
            1.0,
        );
        r.status = RunStatus::Finished;
        Entry::of_run(&r, format!("# run {n}\n"))
    };
    runs.add(blank(1), "");
    runs.pin(1);
    let mut dropped = Vec::new();
    for n in 2..=(KEEP as u64 + 11) {
        dropped.extend(runs.add(blank(n), ""));
    }
    assert_eq!(runs.list.len(), KEEP + 1);
    assert_eq!(runs.list[0].number, 1, "the baseline stays");
    assert_eq!(runs.list[1].number, 12);
    assert_eq!(dropped, (2..=11).collect::<Vec<u64>>());
    // the files of dropped runs are removed, the others kept
    let dir = std::env::temp_dir().join(format!("deckspin-runs-{}-bound", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let job = |n: u64| run_store::Job {
        entry: Box::new(blank(n)),
        baseline: false,
        full: true,
    };
    run_store::store(&dir, &[job(2), job(3)], &[]).unwrap();
    run_store::store(&dir, &[], &[2]).unwrap();
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["0003.csv", "0003.json", "0003.toml"]);
    let _ = std::fs::remove_dir_all(&dir);
    // at most four runs overlaid besides the baseline
    for n in 12..16 {
        assert_eq!(runs.toggle_overlay(n), Ok(true));
    }
    assert!(runs.toggle_overlay(16).is_err());
    assert!(
        runs.toggle_overlay(1).is_err(),
        "the baseline is always overlaid"
    );
    assert_eq!(runs.overlays().len(), 5);
}

#[test]
fn the_model_diff_goes_by_dotted_path_into_arrays_and_shows_elements_from_1() {
    let a = short_bridge("0.004");
    let b = set(&set(&a, "contacts.gaps.2", "0.006"), "contacts.mu", "0.3");
    let lines: Vec<String> = run_list::model_diff(&a, &b)
        .iter()
        .map(|c| c.line())
        .collect();
    assert_eq!(
        lines,
        [
            "contacts.mu: 0.5 → 0.3",
            "contacts gap 3 (right_top): 0.004 → 0.006"
        ]
    );
    assert!(run_list::model_diff(&a, &a).is_empty());
    // a value only on one side
    let c = form::remove_value(&b, "contacts.restitution").unwrap();
    let d = run_list::model_diff(&b, &c);
    assert_eq!(d.len(), 1);
    assert_eq!(d[0].line(), "contacts.restitution: 0.0 → (none)");
    assert_eq!(
        run_list::derived_name(&run_list::model_diff(&a, &b), Some(1)),
        "contacts.mu=0.3 +1"
    );
}

#[test]
fn a_kept_run_holds_at_most_max_samples_and_its_extremes() {
    let n = 100_000;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-4).collect();
    let mut y: Vec<f64> = t.iter().map(|t| (7.0 * t).sin() * 1e-3).collect();
    y[54_321] = 0.05;
    y[7_777] = -0.04;
    let mut r = RunData::new(
        9,
        "#9".into(),
        vec!["deck.theta".into()],
        vec![],
        vec![],
        10.0,
    );
    r.push(&[], &[], 0.0);
    r.t = t.clone();
    r.q[0] = y.clone();
    let thin = run_list::thin(&r);
    assert!(thin.t.len() <= MAX_SAMPLES, "{}", thin.t.len());
    assert!(thin.t.len() > MAX_SAMPLES - 10);
    assert_eq!(thin.t[0], 0.0);
    assert_eq!(*thin.t.last().unwrap(), t[n - 1]);
    assert!(thin.t.windows(2).all(|w| w[0] < w[1]), "in order");
    assert!(thin.q[0].contains(&0.05) && thin.q[0].contains(&-0.04));
    let text = run_store::series_text(&thin);
    assert!(text.len() < 60_000, "{} bytes", text.len());
}

#[test]
fn while_running_the_last_value_is_not_called_residual() {
    let mut app = App::new_from_text(
        &short_bridge("0.004"),
        &root().join("models/four-span.toml"),
    );
    let fx = app.start();
    run(&mut app, fx);
    let fx = act(&mut app, Action::Rerun);
    let msgs = messages_of_started_run(fx);
    let n = msgs.len();
    for m in msgs.into_iter().take(n / 2) {
        update(&mut app, m);
    }
    assert!(app.running());
    app.view = View::Runs;
    let s = screen(&render(&mut app, 120, 40));
    let cells = compare_row(&s, "residual θ");
    assert_eq!(cells.len(), 2, "{s}");
    assert_eq!(cells[1], "…", "{s}");
    assert_eq!(compare_row(&s, "status"), ["done", "running"], "{s}");
    assert_eq!(app.runs.list.len(), 1, "a run going is not kept yet");
    assert_eq!(app.runs.list[0].ended, Ended::Finished);
}

// ---------------------------------------------------------------------------------------------
// snapshots

#[test]
fn snapshot_runs_80x24() {
    let mut app = runs_app(Options::default());
    let t = render(&mut app, 80, 24);
    snapshot_settings().bind(|| insta::assert_snapshot!("runs_80x24", t.backend()));
}

#[test]
fn snapshot_runs_120x40() {
    let mut app = runs_app(Options::default());
    let t = render(&mut app, 120, 40);
    snapshot_settings().bind(|| insta::assert_snapshot!("runs_120x40", t.backend()));
}

#[test]
fn snapshot_runs_80x24_ascii_no_color() {
    let mut app = runs_app(Options {
        color: false,
        ascii: true,
    });
    let t = render(&mut app, 80, 24);
    let buf = t.backend().buffer();
    for c in buf.content() {
        assert_eq!(c.fg, ratatui::style::Color::Reset);
    }
    // the runs view's own lines (the header and the hint bar are drawn for every view)
    for y in 1..22 {
        for x in 0..80 {
            let sym = buf[(x, y)].symbol();
            assert!(sym.bytes().all(|b| b <= 0x7e), "{sym:?} at {x},{y}");
        }
    }
    snapshot_settings().bind(|| insta::assert_snapshot!("runs_80x24_ascii", t.backend()));
}

#[test]
fn snapshot_charts_with_two_runs_overlaid_120x40() {
    let mut app = runs_app(Options::default());
    app.view = View::Charts;
    let t = render(&mut app, 120, 40);
    let s = screen(&t);
    let head = s.lines().find(|l| l.starts_with("deck.theta [")).unwrap();
    let (a, b) = (head.find("┈#1 ").unwrap(), head.find("┈#3 ").unwrap());
    assert!(a < b, "{s}");
    assert_eq!(compare_row(&s, "impacts").len(), 3, "{s}");
    snapshot_settings().bind(|| insta::assert_snapshot!("charts_overlay_120x40", t.backend()));
}

/// A bridge of several frames: the runs compared give the frame that turns most and its peak,
/// as the sweeps and suites report it (`output::deck::DeckPeaks`), beside the charted frame's.
#[test]
fn the_runs_compared_give_the_frame_that_turns_most() {
    let path = root().join("models/three-frame.toml");
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("t_end = 31.0", "t_end = 6.0");
    let run = run_of(&text, &path, 1);
    // the engine's answer for the same scene, without the workbench
    let scene = deckspin::model::load_str(&text, &path, &[]).unwrap();
    let out = deckspin::simulate::integrate(&scene, &mut deckspin::Silent).output;
    let want = deckspin::output::deck::DeckPeaks::of(&out).rotation;
    let k = deckspin::output::deck::largest_rotation_dof(&out);
    let (peak, frame) = run.peak_rot_of_frames().expect("three frames");
    assert_eq!(peak, want);
    assert_eq!(format!("{frame}.theta"), out.dof_names[k]);
    // the charted rotation is frame 1's, and here another frame turns more
    assert_eq!(run.rot_name(), "frame1.theta");
    assert!(peak > run.peak_rot().0, "{peak} {:?}", run.peak_rot());
    // on screen (120×40)
    let mut app = App::new_from_text(&text, &path);
    app.runs.add(Entry::of_run(&run, text.clone()), &text);
    app.current = Some(run.clone());
    let s = screen(&render(&mut app, 120, 40));
    let row = (s.lines())
        .find(|l| l.contains("peak |θ| any frame"))
        .unwrap_or_else(|| panic!("{s}"));
    assert!(row.contains(&run_list::cell(Some(want))), "{row}");
    let row = s.lines().find(|l| l.contains("│  frame ")).expect(&s);
    assert!(row.contains(&frame), "{row}");
    // the specimen has one deck: no such rows
    let (one, _) = &bridge_runs()[0];
    assert!(one.peak_rot_of_frames().is_none());
}

/// A run that failed on its energy closure ran to its end: the comparison gives the closure it
/// reached, marked over its bound, and its residual; `—` only where there is no value.
#[test]
fn the_closure_of_a_run_failed_on_it_is_compared_over_its_bound() {
    let text = short_bridge("0.004").replace("[solver]", "[solver]\nmax_closure = 1e-12");
    let mut app = App::new_from_text(&text, &root().join("models/four-span.toml"));
    let fx = app.start();
    tui::execute_blocking(&mut app, fx);
    let cur = app.current.as_ref().expect("a run");
    assert!(
        matches!(&cur.status, RunStatus::Failed(e) if run_list::is_inaccurate(e)),
        "{}",
        app.status
    );
    assert!(app.status.contains("energy closure"), "{}", app.status);
    let closure = cur
        .summary
        .as_ref()
        .expect("its summary")
        .energy_closure_rel;
    assert!(closure > 1e-12, "{closure}");
    assert_eq!(app.runs.list.len(), 1);
    assert!(matches!(app.runs.list[0].ended, Ended::Inaccurate(_)));
    assert_eq!(app.runs.list[0].results.closure, Some(closure));
    assert_eq!(app.runs.list[0].results.closure_over, Some(1e-12));
    app.view = View::Runs;
    let s = screen(&render(&mut app, 120, 40));
    let sig = |v: f64| deckspin::tui::chart::fmt_sig(v * 100.0, 2);
    let want = format!("{} % >{} %", sig(closure), sig(1e-12));
    assert_eq!(sig(1e-12), "1.0e-10");
    assert_eq!(compare_row(&s, "closure").join(" "), want, "{s}");
    assert_ne!(compare_row(&s, "residual θ"), ["—"], "{s}");
    assert_eq!(compare_row(&s, "status"), ["inexact"], "{s}");
}

/// A message about the overlay stays with no new event, in every view that shows runs, and
/// goes when the overlay changes or in the studies view; it stays in the log.
#[test]
fn an_overlay_message_stays_until_the_overlay_changes_or_the_view_has_no_runs() {
    let mut app = runs_app(Options::default());
    app.runs.selected = 1;
    update(&mut app, key(' '));
    let said = "#2 overlaid on the charts and compared";
    assert_eq!(app.status, said);
    // no timer: frames and resizes without input leave it
    for i in 0..50 {
        update(&mut app, Msg::Resize(100 + i % 3, 30));
        let s = screen(&render(&mut app, 100, 30));
        assert!(s.contains(said), "frame {i}:\n{s}");
    }
    // the charts show the overlay: it stays
    update(&mut app, code(KeyCode::Enter));
    assert_eq!(app.view, View::Charts);
    assert_eq!(app.status, said);
    // the studies view has no runs: it goes
    update(&mut app, code(KeyCode::Tab));
    update(&mut app, code(KeyCode::Tab));
    assert_eq!(app.view, View::Studies);
    assert_eq!(app.status, "");
    assert!(!screen(&render(&mut app, 100, 30)).contains(said));
    assert!(app.messages.iter().any(|m| m.text == said), "in the log");
    // said again, then the overlay changes (the run taken off): it goes
    update(&mut app, key('#'));
    app.runs.selected = 1;
    update(&mut app, key(' '));
    update(&mut app, key(' '));
    assert_eq!(app.status, said);
    app.runs.toggle_overlay(2).unwrap();
    update(&mut app, Msg::Resize(100, 30));
    assert_eq!(app.status, "");
}

/// "N runs reopened" is not wiped by the run that starts with the workbench: its start and
/// its end are said after it.
#[test]
fn the_runs_reopened_are_still_said_when_the_first_run_ends() {
    let model = scratch("reopened-said");
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    let fx = app.start();
    run(&mut app, fx);
    // the same text is reused, not run, and said after the runs reopened
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    let _ = app.start();
    assert!(
        (app.status.contains("1 run reopened")
            && app
                .status
                .ends_with("#1 reused: same model text (r reruns it)")),
        "{}",
        app.status
    );
    // a new text runs
    let text = std::fs::read_to_string(&model).unwrap() + "# another text\n";
    std::fs::write(&model, text).unwrap();
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    assert!(app.status.contains("1 run reopened"), "{}", app.status);
    let fx = app.start();
    assert!(
        app.status.contains("1 run reopened") && app.status.ends_with("#2 started"),
        "{}",
        app.status
    );
    run(&mut app, fx);
    assert!(
        app.status
            .starts_with("loaded four-span.toml · 1 run reopened")
            && app.status.contains(" · #2 finished at t = 2.000 s"),
        "{}",
        app.status
    );
    // on screen whole at 80×24 (the status area takes two rows), and after any number of frames
    for _ in 0..20 {
        update(&mut app, Msg::Resize(80, 24));
    }
    let s = screen(&render(&mut app, 80, 24));
    let flat: String = s.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(flat.contains("1 run reopened"), "{s}");
    assert!(flat.contains("#2 finished at t = 2.000 s"), "{s}");
    // the log has each message once, without the ones before it
    let texts: Vec<&str> = app.messages.iter().map(|m| m.text.as_str()).collect();
    assert!(texts.contains(&"#2 started"), "{texts:?}");
    assert!(
        texts.iter().any(|t| t.starts_with("#2 finished")),
        "{texts:?}"
    );
    // the next run is the user's: it is said alone (the same text: it replaces #2)
    let fx = act(&mut app, Action::Rerun);
    assert_eq!(
        app.status,
        "#2 started again: same model text, it replaces the kept #2 when it ends"
    );
    run(&mut app, fx);
    assert!(app.status.starts_with("#2 finished"), "{}", app.status);
    let _ = std::fs::remove_dir_all(model.parent().unwrap().parent().unwrap());
}
