//! Workbench tests without a terminal: `update(app, msg)` for every user action, drawing on
//! ratatui's TestBackend with insta snapshots, chart decimation, file saving and watching.

#![cfg(feature = "workbench")]

mod common;

use common::root;
use common::tui::*;

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use deckspin::output::ContactState;
use deckspin::tui::app::{Confirm, Mode, StatusKind, View};
use deckspin::tui::keymap::{Action, Ctx, KEYMAP};
use deckspin::tui::msg::RunOutcome;
use deckspin::tui::runs::data::{RunData, RunStatus};
use deckspin::tui::runs::list::{Ended, Entry};
use deckspin::tui::{self, App, Effect, Msg, Options, chart, form, update};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::sync::mpsc;
use std::time::{Duration, Instant};

// ---------------------------------------------------------------------------------------------
// fixtures

fn corner_path() -> PathBuf {
    root().join("models/validation/corner-impact.toml")
}

/// Run 2 of the short bridge (4 mm gaps), computed once per test binary.
fn bridge_run() -> &'static RunData {
    static R: OnceLock<RunData> = OnceLock::new();
    R.get_or_init(|| run_of(&short_bridge("0.004"), &bridge_path(), 2))
}

/// Run 1: the same bridge with 6 mm gaps (the baseline of the compare snapshots).
fn bridge_prev_run() -> &'static RunData {
    static R: OnceLock<RunData> = OnceLock::new();
    R.get_or_init(|| run_of(&short_bridge("0.006"), &bridge_path(), 1))
}

/// Keeps `#1` (6 mm gaps, the baseline) and `#2` (4 mm gaps) in the run list of `app`, as
/// if they had been run in it.
fn keep_bridge_runs(app: &mut App) {
    let saved = app.text.clone();
    app.runs.add(
        Entry::of_run(bridge_prev_run(), short_bridge("0.006")),
        &saved,
    );
    app.runs.pin(1);
    app.runs
        .add(Entry::of_run(bridge_run(), short_bridge("0.004")), &saved);
    app.runs.selected = 1;
}

/// A deterministic app: the short bridge with #2 current and #1 the baseline, overlaid. The
/// model path is relative (tests run in the package root) so that snapshots do not contain
/// the checkout's location.
fn bridge_app() -> App {
    let mut app = App::new_from_text(&short_bridge("0.004"), Path::new("models/four-span.toml"));
    app.current = Some(bridge_run().clone());
    keep_bridge_runs(&mut app);
    app.next_run = 3;
    app.set_status(StatusKind::Ok, "#2 finished");
    app
}

/// A fresh app on the corner-impact scene (1 ms runs), first run done.
fn corner_app() -> App {
    let mut app = App::new_from_text(&read(&corner_path()), &corner_path());
    let fx = app.start();
    tui::execute_blocking(&mut app, fx);
    app
}

fn type_str(app: &mut App, s: &str) {
    for c in s.chars() {
        assert!(update(app, key(c)).is_empty());
    }
}

fn select_field(app: &mut App, path: &str) {
    app.view = View::Form;
    app.form.selected = app
        .form
        .index_of(path)
        .unwrap_or_else(|| panic!("no field {path}"));
}

/// Edits the selected field: Enter, clear, type, Enter.
fn edit(app: &mut App, path: &str, value: &str) -> Vec<Effect> {
    select_field(app, path);
    assert!(update(app, code(KeyCode::Enter)).is_empty());
    assert!(matches!(app.mode, Mode::Editing { .. }));
    update(
        app,
        Msg::Key(KeyEvent::new(KeyCode::Char('u'), KeyModifiers::CONTROL)),
    );
    type_str(app, value);
    update(app, code(KeyCode::Enter))
}

fn start_ids(fx: &[Effect]) -> Vec<u64> {
    fx.iter()
        .filter_map(|e| match e {
            Effect::StartRun { id, .. } => Some(*id),
            _ => None,
        })
        .collect()
}

thread_local! {
    /// The drawing cache of this test (each test runs on its own thread), kept across frames
    /// as the runtime keeps its own.
    static CACHE: std::cell::RefCell<tui::ui::Cache> = Default::default();
}

/// Draws one frame of `app` on `t` with the test's drawing cache.
fn draw(t: &mut Terminal<TestBackend>, app: &App) {
    CACHE
        .with(|c| {
            t.draw(|f| tui::ui::draw(f, app, &mut c.borrow_mut()))
                .map(|_| ())
        })
        .unwrap();
}

fn render(app: &mut App, w: u16, h: u16) -> Terminal<TestBackend> {
    update(app, Msg::Resize(w, h));
    let mut t = Terminal::new(TestBackend::new(w, h)).unwrap();
    draw(&mut t, app);
    t
}

/// A scratch directory mirroring the repository layout: models/ + excitations/.
fn scratch(name: &str) -> PathBuf {
    static N: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = N.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
    let d = std::env::temp_dir().join(format!("deckspin-tui-{}-{name}-{n}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(d.join("models")).unwrap();
    std::fs::create_dir_all(d.join("excitations")).unwrap();
    for e in std::fs::read_dir(root().join("excitations")).unwrap() {
        let e = e.unwrap();
        if e.path().is_file() {
            std::fs::copy(e.path(), d.join("excitations").join(e.file_name())).unwrap();
        }
    }
    d
}

// ---------------------------------------------------------------------------------------------
// chart decimation

#[test]
fn downsample_keeps_a_single_sample_spike() {
    let n = 100_000;
    let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-4).collect();
    let mut y = vec![0.0; n];
    y[54_321] = 7.0; // one-sample impact spike
    y[77_777] = -3.0;
    for cols in [10, 57, 200, 1000] {
        let d = chart::downsample_minmax(&t, &y, 0.0, t[n - 1], cols);
        assert!(d.len() <= 2 * cols, "{} points for {cols} columns", d.len());
        assert!(
            d.contains(&(t[54_321], 7.0)),
            "spike lost at {cols} columns"
        );
        assert!(
            d.contains(&(t[77_777], -3.0)),
            "negative spike lost at {cols} columns"
        );
        assert!(d.windows(2).all(|w| w[0].0 <= w[1].0), "not in time order");
    }
    // zoomed window around the spike, and one that excludes it
    let d = chart::downsample_minmax(&t, &y, 5.0, 6.0, 40);
    assert!(d.contains(&(t[54_321], 7.0)));
    assert!(d.iter().all(|p| p.0 >= 5.0 && p.0 <= 6.0));
    let d = chart::downsample_minmax(&t, &y, 0.0, 5.0, 40);
    assert!(d.iter().all(|p| p.1 == 0.0));
}

#[test]
fn downsample_small_input_is_unchanged_and_skips_nan() {
    let t = [0.0, 1.0, 1.0, 2.0];
    let y = [1.0, 2.0, f64::NAN, 3.0];
    assert_eq!(
        chart::downsample_minmax(&t, &y, 0.0, 2.0, 10),
        vec![(0.0, 1.0), (1.0, 2.0), (2.0, 3.0)]
    );
    assert!(chart::downsample_minmax(&t, &y, 3.0, 4.0, 10).is_empty());
    assert!(chart::downsample_minmax(&[], &[], 0.0, 1.0, 10).is_empty());
}

#[test]
fn pixel_dedup_keeps_shape_and_last_point() {
    let pts: Vec<(f64, f64)> = (0..10_000).map(|i| (i as f64 / 10_000.0, 0.0)).collect();
    let d = chart::dedup_pixels(pts.iter().copied(), [0.0, 1.0], [-1.0, 1.0], 20, 10);
    assert!(d.len() <= 21, "{}", d.len());
    assert_eq!(d.last(), pts.last());
    assert_eq!(chart::fmt_num(0.0127, 9), "0.0127");
    assert!(chart::fmt_num(-1.234e-7, 9).len() <= 9);
}

#[test]
fn time_to_column_matches_canvas_rounding() {
    assert_eq!(chart::column_of(0.0, 0.0, 10.0, 50, 2), Some(0));
    assert_eq!(chart::column_of(10.0, 0.0, 10.0, 50, 2), Some(49));
    assert_eq!(chart::column_of(10.1, 0.0, 10.0, 50, 2), None);
}

// ---------------------------------------------------------------------------------------------
// keymap

#[test]
fn every_binding_is_handled_in_its_context() {
    for bd in KEYMAP {
        for k in bd.keys {
            let mut app = corner_app();
            match bd.ctx {
                Ctx::Edit => {
                    app.view = View::Form;
                    act(&mut app, Action::FieldEdit);
                }
                Ctx::Confirm => {
                    app.mode = Mode::Confirm(Confirm::SaveConflict {
                        text: app.text.clone(),
                    })
                }
                Ctx::Quit => app.mode = Mode::Confirm(Confirm::Quit),
                Ctx::Search => {
                    app.view = View::Form;
                    act(&mut app, Action::SearchStart);
                }
                Ctx::OpenModel => {
                    app.mode = Mode::OpenModel {
                        files: vec![corner_path()],
                        selected: 0,
                    }
                }
                Ctx::Merge => {
                    app.mode = Mode::Confirm(Confirm::Merge {
                        conflicts: vec![tui::form::merge::Conflict {
                            path: "contact.0.mu".into(),
                            mine: Some("0.3".into()),
                            theirs: Some("0.5".into()),
                        }],
                        resume: None,
                    })
                }
                Ctx::Recover => {
                    // a recovery file (k) goes beside the model: a scratch folder's
                    app.path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("keymap/x.toml");
                    let mut text = app.text.clone();
                    text.push_str("\n# an edit\n");
                    app.mode = Mode::Confirm(Confirm::Recover {
                        found: tui::form::swap::Found {
                            path: PathBuf::from("/nonexistent/.x.toml.swp"),
                            pid: 1,
                            text,
                            typing: None,
                            older_than_model: false,
                        },
                        differences: vec![],
                    })
                }
                Ctx::Help => app.mode = Mode::Help,
                Ctx::Messages => app.mode = Mode::Messages,
                Ctx::Form => app.view = View::Form,
                Ctx::Studies => app.view = View::Studies,
                Ctx::Pick => {
                    app.view = View::Studies;
                    app.mode = Mode::Pick {
                        files: vec![PathBuf::from("models/x.studies/pga-1.csv")],
                        selected: 0,
                    }
                }
                Ctx::Runs => app.view = View::Runs,
                Ctx::Naming => {
                    app.view = View::Runs;
                    act(&mut app, Action::RunRename);
                }
                Ctx::Events => app.events_open = true,
                Ctx::ChartPick => {
                    app.mode = Mode::ChartPick {
                        chart: 0,
                        query: String::new(),
                        selected: 0,
                    }
                }
                Ctx::RunInfo => {
                    app.mode = Mode::RunInfo(Box::new(tui::runs::info::Info {
                        number: 1,
                        title: "#1".into(),
                        rows: vec![("status".into(), "finished".into())],
                    }))
                }
                Ctx::Charts | Ctx::Global => {}
            }
            let ev = match *k {
                tui::keymap::K::Ch(c) => KeyEvent::new(KeyCode::Char(c), KeyModifiers::NONE),
                tui::keymap::K::Ctrl(c) => KeyEvent::new(KeyCode::Char(c), KeyModifiers::CONTROL),
                tui::keymap::K::Code(c) => KeyEvent::new(c, KeyModifiers::NONE),
                tui::keymap::K::Shift(c) => KeyEvent::new(c, KeyModifiers::SHIFT),
            };
            let found = tui::keymap::lookup(&app.contexts(), &ev);
            assert_eq!(found, Some(bd.action), "{} in {:?}", bd.label, bd.ctx);
            update(&mut app, Msg::Key(ev));
            let _ = render(&mut app, 80, 24);
        }
    }
}

#[test]
fn help_and_hint_bar_come_from_the_keymap() {
    let help = tui::keymap::help();
    for bd in KEYMAP {
        assert!(
            help.iter()
                .any(|(_, rows)| rows.contains(&(bd.label, bd.desc))),
            "{} missing from help",
            bd.label
        );
    }
    let mut app = bridge_app();
    let t = render(&mut app, 200, 40);
    let s = screen(&t);
    let bar = s.lines().last().unwrap();
    for (k, h) in tui::keymap::hints(&[Ctx::Charts, Ctx::Global]) {
        assert!(
            bar.contains(&format!("{k} {h}")),
            "hint {k} {h} missing: {bar}"
        );
    }
    act(&mut app, Action::Help);
    let s = screen(&render(&mut app, 120, 40));
    assert!(s.contains("help — keys"));
    assert!(s.contains("cancel the simulation"));
    act(&mut app, Action::CloseHelp);
    assert_eq!(app.mode, Mode::Normal);
}

#[test]
fn the_documentation_lists_every_key() {
    let doc = read(&root().join("docs/workbench.md"));
    for bd in KEYMAP {
        assert!(
            doc.contains(&format!("`{}`", bd.label)),
            "docs/workbench.md misses `{}`",
            bd.label
        );
    }
}

// ---------------------------------------------------------------------------------------------
// form editing

#[test]
fn edit_a_gap_valid_value_accepted() {
    let mut app = App::new_from_text(&read(&bridge_path()), &bridge_path());
    assert!(!app.dirty());
    let fx = edit(&mut app, "contacts.gaps.1", "0.02");
    assert!(fx.is_empty());
    assert_eq!(app.mode, Mode::Normal);
    assert!(app.dirty());
    assert!(
        app.draft.contains("gaps = [0.0127, 0.02, 0.0127, 0.0127]"),
        "{}",
        app.draft
    );
    // the trailing comment of that line is kept in its column (two characters fewer before it)
    assert!(
        app.draft
            .contains("0.0127]     # m, corners left_top, left_bottom, right_top, right_bottom")
    );
    let f = &app.form.fields[app.form.index_of("contacts.gaps.1").unwrap()];
    assert!(f.edited());
    assert_eq!(f.value.as_deref(), Some("0.02"));
    assert_eq!(f.saved.as_deref(), Some("0.0127"));
    assert!(
        app.status.contains("contacts gap 2 (left_bottom) = 0.02 m"),
        "{}",
        app.status
    );
    // a value typed with its unit, and an integer for a float field
    edit(&mut app, "deck.mass", "150 t");
    assert!(
        app.draft
            .contains("mass = 150.0          # t, incl. added mass"),
        "comment column kept"
    );
    // the edited model is what a rerun uses
    let fx = act(&mut app, Action::Rerun);
    let Some(Effect::StartRun { scene, .. }) =
        fx.iter().find(|e| matches!(e, Effect::StartRun { .. }))
    else {
        panic!("no StartRun")
    };
    assert_eq!(scene.bodies[1].mass, 150.0);
    assert!(app.current.as_ref().unwrap().label.contains("unsaved"));
}

#[test]
fn edit_invalid_values_refused_with_the_reason() {
    let mut app = App::new_from_text(&read(&bridge_path()), &bridge_path());
    let before = app.draft.clone();
    edit(&mut app, "contacts.gaps.0", "-0.01");
    let Mode::Editing {
        check: Err(reason), ..
    } = &app.mode
    else {
        panic!("not refused: {:?}", app.mode)
    };
    assert!(
        reason.contains("contacts gap 1 (left_top): must be ≥ 0, got -0.01"),
        "numbered from 1 as the form's labels: {reason}"
    );
    assert!(
        reason.contains("four-span.toml:24:9:"),
        "line and column: {reason}"
    );
    assert_eq!(app.status_kind, StatusKind::Error);
    assert!(app.status.starts_with("refused: "));
    assert_eq!(app.draft, before);
    // the reason is on screen
    let s = screen(&render(&mut app, 120, 40));
    assert!(s.contains("✗"), "{s}");
    assert!(s.contains("must be ≥ 0"), "{s}");
    update(&mut app, code(KeyCode::Esc));
    assert_eq!(app.mode, Mode::Normal);
    // not a number
    edit(&mut app, "contacts.mu", "abc");
    assert!(
        matches!(&app.mode, Mode::Editing { check: Err(r), .. } if r.contains("'abc' is not a number"))
    );
    update(&mut app, code(KeyCode::Esc));
    // restitution above 1 (engine rule), live check while typing
    select_field(&mut app, "contacts.restitution");
    update(&mut app, code(KeyCode::Enter));
    update(
        &mut app,
        Msg::Key(KeyEvent::new(KeyCode::Char('u'), KeyModifiers::CONTROL)),
    );
    type_str(&mut app, "1.5");
    assert!(matches!(&app.mode, Mode::Editing { check: Err(r), .. } if r.contains("[0, 1]")));
    update(&mut app, code(KeyCode::Backspace));
    update(&mut app, code(KeyCode::Backspace));
    assert!(
        matches!(&app.mode, Mode::Editing { check: Ok(()), .. }),
        "1 is valid"
    );
    assert!(!app.dirty());
}

#[test]
fn revert_and_law_switch() {
    let mut app = App::new_from_text(&read(&bridge_path()), &bridge_path());
    edit(&mut app, "contacts.mu", "0.3");
    assert!(app.dirty());
    act(&mut app, Action::FieldRevert);
    assert!(!app.dirty(), "reverted");
    edit(&mut app, "column.law.law", "bilinear");
    assert_eq!(app.mode, Mode::Normal, "{}", app.status);
    assert!(app.draft.contains("law = { law = \"bilinear\", stiffness = 9320.0, yield_force = 98.0, post_yield_ratio = 0.05 }"), "{}", app.draft);
    assert!(app.form.index_of("column.law.unloading_exponent").is_none());
    edit(&mut app, "column.law.law", "elastic");
    assert!(matches!(&app.mode, Mode::Editing { check: Err(r), .. } if r.contains("unknown law")));
}

#[test]
fn generic_models_list_their_scalar_leaves() {
    let app = App::new_from_text(&read(&corner_path()), &corner_path());
    let paths: Vec<&str> = app.form.fields.iter().map(|f| f.path.as_str()).collect();
    for p in [
        "title",
        "solver.t_end",
        "body.0.mass",
        "body.0.initial_velocity.0",
        "contact.0.point.1",
        "contact.0.mu",
    ] {
        assert!(paths.contains(&p), "{p} not in {paths:?}");
    }
    // the solver settings are offered first (absent ones too), then every leaf by its path
    let curated: Vec<&str> = app
        .form
        .fields
        .iter()
        .filter(|f| f.curated)
        .map(|f| f.path.as_str())
        .collect();
    assert_eq!(
        curated,
        [
            "solver.method",
            "solver.t_end",
            "solver.rtol",
            "solver.output_dt"
        ]
    );
}

// ---------------------------------------------------------------------------------------------
// saving

#[test]
fn save_keeps_every_comment_and_writes_atomically() {
    let d = scratch("save");
    let model = d.join("models/four-span.toml");
    let original = read(&bridge_path());
    std::fs::write(&model, &original).unwrap();
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    assert!(app.load_error.is_none(), "{:?}", app.load_error);
    edit(&mut app, "contacts.gaps.2", "0.01");
    edit(&mut app, "contacts.mu", "0.35");
    let fx = act(&mut app, Action::Save);
    let [Effect::Save { path, text, .. }] = fx.as_slice() else {
        panic!("{fx:?}")
    };
    assert_eq!(path, &model);
    #[cfg(unix)]
    let inode = {
        use std::os::unix::fs::MetadataExt;
        std::fs::metadata(&model).unwrap().ino()
    };
    tui::save_atomic(path, text).unwrap();
    let saved = read(&model);
    assert_eq!(&saved, text);
    // every comment of the original is still there, and only two lines changed
    for line in original.lines() {
        if let Some(i) = line.find('#') {
            assert!(saved.contains(&line[i..]), "comment lost: {}", &line[i..]);
        }
    }
    let changed: Vec<(&str, &str)> = original
        .lines()
        .zip(saved.lines())
        .filter(|(a, b)| a != b)
        .collect();
    assert_eq!(changed.len(), 2, "{changed:?}");
    assert_eq!(original.lines().count(), saved.lines().count());
    assert!(
        saved.contains("mu = 0.35             # paper §4.3"),
        "comment column kept:\n{saved}"
    );
    // temp + rename: a new inode, no temporary file left behind
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        assert_ne!(
            std::fs::metadata(&model).unwrap().ino(),
            inode,
            "not replaced by rename"
        );
    }
    let leftovers: Vec<_> = std::fs::read_dir(d.join("models"))
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(leftovers.len(), 1, "{leftovers:?}");
    // the Saved message clears the edits and reruns
    let fx = update(
        &mut app,
        Msg::Saved {
            text: text.clone(),
            result: Ok(model.clone()),
        },
    );
    assert_eq!(start_ids(&fx), vec![1]);
    assert!(!app.dirty());
    assert!(app.status.contains("saved"));
    // the watcher's event for our own save is not a foreign change
    assert!(update(&mut app, Msg::FileChanged(saved)).is_empty());
    assert_eq!(app.mode, Mode::Normal);
    let _ = std::fs::remove_dir_all(&d);
}

#[cfg(unix)]
#[test]
fn save_through_a_symlink_keeps_the_link() {
    let d = scratch("symlink");
    let real = d.join("models/real.toml");
    let link = d.join("models/link.toml");
    std::fs::write(&real, "a = 1\n").unwrap();
    std::os::unix::fs::symlink(&real, &link).unwrap();
    tui::save_atomic(&link, "a = 2\n").unwrap();
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert_eq!(read(&real), "a = 2\n");
    let _ = std::fs::remove_dir_all(&d);
}

#[cfg(unix)]
#[test]
fn save_of_a_hard_linked_model_keeps_the_link() {
    use std::os::unix::fs::MetadataExt;
    let d = scratch("hardlink");
    let a = d.join("models/a.toml");
    let b = d.join("models/b.toml");
    std::fs::write(&a, "a = 1\nlonger = \"than the new text\"\n").unwrap();
    std::fs::hard_link(&a, &b).unwrap();
    let inode = std::fs::metadata(&a).unwrap().ino();
    tui::save_atomic(&a, "a = 2\n").unwrap();
    // one file, two names, the new text (cut to its length), no backup left
    assert_eq!(std::fs::metadata(&a).unwrap().ino(), inode);
    assert_eq!(std::fs::metadata(&a).unwrap().nlink(), 2);
    assert_eq!(read(&b), "a = 2\n");
    let left: Vec<String> = std::fs::read_dir(d.join("models"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains("backup"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn the_swap_file_holds_the_edits_and_the_value_being_typed() {
    use deckspin::tui::form::swap;
    let mut app = App::new_from_text(&read(&corner_path()), &corner_path());
    assert_eq!(
        deckspin::tui::signals::swap_content(&app),
        None,
        "nothing unsaved, no swap"
    );
    edit(&mut app, "contact.0.mu", "0.2");
    let c = deckspin::tui::signals::swap_content(&app).unwrap();
    let (pid, text, typing) = swap::parse(&c).unwrap();
    assert_eq!(pid, std::process::id());
    assert_eq!(text, app.draft);
    assert_eq!(typing, None);
    // the swap is TOML: its header lines are comments
    assert!(deckspin::tui::form::validate(&c, &corner_path()).is_ok());
    // a value being typed, not valid yet: the draft kept, the typed text named
    app.mode = Mode::Editing {
        buffer: "0.3x".into(),
        check: Err("not a number".into()),
    };
    let (_, text, typing) =
        swap::parse(&deckspin::tui::signals::swap_content(&app).unwrap()).unwrap();
    assert_eq!(text, app.draft);
    let typing = typing.unwrap();
    assert!(typing.ends_with("= 0.3x"), "{typing}");
    // the differences shown at recovery name the field and both values
    let diff = deckspin::tui::form::merge::differences(&app.text, &app.draft);
    assert_eq!(diff.len(), 1, "{diff:?}");
    assert!(diff[0].contains("0.2"), "{diff:?}");
}

#[test]
fn the_swap_writer_writes_within_a_second_and_a_recovery_file_falls_back() {
    use deckspin::tui::form::swap;
    let d = scratch("swap-writer");
    let model = d.join("models/m.toml");
    std::fs::write(&model, read(&corner_path())).unwrap();
    let mut app = App::new_from_text(&read(&model), &model);
    let mut w = swap::Swapper::spawn(&model).unwrap();
    edit(&mut app, "contact.0.mu", "0.2");
    w.update(deckspin::tui::signals::swap_content(&app));
    // the writer waits SETTLE (0.25 s) for more changes; a hang is no file after many of them
    let at = swap::beside(&model);
    let mut waited = 0;
    while !at.exists() {
        std::thread::sleep(std::time::Duration::from_millis(50));
        waited += 1;
        assert!(waited < 2400, "no swap file after 120 s");
    }
    let found = swap::find(&model).unwrap();
    assert_eq!(found.text, app.draft);
    assert_eq!(found.pid, std::process::id());
    assert!(
        !swap::alive(found.pid),
        "this process is not another workbench"
    );
    // a clean quit removes it
    w.finish(false);
    assert!(!at.exists());
    // the model's folder cannot take the recovery file: the state directory does
    let state = d.join("state");
    let blocked = d.join("blocked");
    std::fs::write(&blocked, "a file, not a folder").unwrap();
    let inside = blocked.join("m.toml");
    // SAFETY: this test alone reads XDG_STATE_HOME in this process's tests of the swap
    unsafe { std::env::set_var("XDG_STATE_HOME", &state) };
    let p = deckspin::tui::signals::write_recovery(&inside, "a = 1\n").unwrap();
    assert!(
        p.starts_with(state.join("deckspin/recovered")),
        "{}",
        p.display()
    );
    assert_eq!(read(&p), "a = 1\n");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn save_without_edits_does_nothing_and_failures_are_reported() {
    let mut app = App::new_from_text(&read(&corner_path()), &corner_path());
    assert!(act(&mut app, Action::Save).is_empty());
    assert!(app.status.contains("no unsaved edits"));
    edit(&mut app, "contact.0.mu", "0.2");
    let fx = act(&mut app, Action::Save);
    assert_eq!(fx.len(), 1);
    let text = app.draft.clone();
    let fx = update(
        &mut app,
        Msg::Saved {
            text,
            result: Err("disk full".into()),
        },
    );
    assert!(fx.is_empty());
    assert!(app.dirty(), "edits kept after a failed save");
    assert_eq!(app.status, "save failed: disk full");
    assert!(tui::save_atomic(Path::new("/nonexistent-dir/x.toml"), "x").is_err());
}

// ---------------------------------------------------------------------------------------------
// running

#[test]
fn run_starts_a_worker_and_batches_stream_in() {
    let mut app = App::new_from_text(&read(&corner_path()), &corner_path());
    let fx = app.start();
    assert_eq!(start_ids(&fx), vec![1]);
    assert!(app.running());
    let Effect::StartRun { id, scene } = fx.into_iter().next().unwrap() else {
        unreachable!()
    };
    let msgs = tui::workers::run::run_blocking(id, &scene);
    let mut n = 0;
    for m in msgs {
        let done = matches!(m, Msg::RunDone { .. });
        if let Msg::Batch { samples, .. } = &m {
            n += samples.len();
        }
        assert!(update(&mut app, m).is_empty());
        let cur = app.current.as_ref().unwrap();
        if !done {
            assert_eq!(cur.t.len(), n, "batch appended");
            assert_eq!(cur.status, RunStatus::Running);
        }
    }
    let cur = app.current.as_ref().unwrap();
    assert_eq!(cur.status, RunStatus::Finished);
    assert_eq!(cur.total_impacts(), 1);
    assert!(app.status.contains("finished"), "{}", app.status);
    // progress on screen
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("#1 done"), "{s}");
}

/// A step the method chose that leaves the run outside its bounds is refined in the workbench
/// as in `deckspin run`: the worker says so and streams the run again from t = 0, and the run
/// shown is the refined one, finished (the bouncing ball with the explicit penalty scheme is
/// refined once on the command line too).
#[test]
fn the_workbench_refines_a_chosen_step_like_the_command_line() {
    let path = root().join("models/validation/bouncing-ball.toml");
    let mut app = App::new_from_text(&read(&path), &path);
    edit(&mut app, "solver.method", "penalty-explicit");
    assert_eq!(app.mode, Mode::Normal, "{}", app.status);
    let fx = act(&mut app, Action::Rerun);
    let Some(Effect::StartRun { id, scene }) = fx
        .into_iter()
        .find(|f| matches!(f, Effect::StartRun { .. }))
    else {
        panic!("no run started")
    };
    let first_step = scene.settings.step;
    let msgs = tui::workers::run::run_blocking(id, &scene);
    let refined: Vec<&String> = (msgs.iter())
        .filter_map(|m| match m {
            Msg::Refined { why, .. } => Some(why),
            _ => None,
        })
        .collect();
    assert_eq!(refined.len(), 1, "{refined:?}");
    assert!(refined[0].contains("refined to"), "{}", refined[0]);
    for m in msgs {
        update(&mut app, m);
    }
    let cur = app.current.as_ref().unwrap();
    assert_eq!(cur.status, RunStatus::Finished, "{}", app.status);
    assert_eq!(cur.t.first().copied(), Some(0.0));
    assert!(
        cur.t.windows(2).all(|w| w[1] > w[0]),
        "one run's samples, not two"
    );
    let said: Vec<&str> = app.messages.iter().map(|m| m.text.as_str()).collect();
    assert!(
        said.iter()
            .any(|m| m.contains("runs again") && m.contains("refined to")),
        "{said:?}"
    );
    assert!(first_step > 0.0);
}

#[test]
fn the_models_solver_method_is_used() {
    // a step the model sets (without one, Moreau–Jean chooses a finer one and passes)
    let text = read(&corner_path()).replace("[solver]", "[solver]\nstep = 1e-3");
    let mut app = App::new_from_text(&text, &corner_path());
    edit(&mut app, "solver.method", "moreau");
    assert_eq!(app.mode, Mode::Normal, "{}", app.status);
    assert!(app.draft.contains("method = \"moreau\""), "{}", app.draft);
    let fx = act(&mut app, Action::Rerun);
    tui::execute_blocking(&mut app, fx);
    let cur = app.current.as_ref().unwrap();
    // Moreau–Jean at its 1 ms step sinks the corner 0.25 mm: the run is kept and judged
    // inaccurate, by the method the model names
    assert!(
        app.status.contains("penetration 2.500e-4") && app.status.contains("moreau at solver.step"),
        "{}",
        app.status
    );
    assert!(cur.t.len() > 10);
}

#[test]
fn a_runs_batches_are_drawn_together_at_most_every_data_frame() {
    use deckspin::tui::runtime::{DATA_FRAME, pace};
    let batch = |run| Msg::Batch {
        run,
        samples: Vec::new(),
        events: Vec::new(),
        t: 0.0,
    };
    let (tx, rx) = mpsc::channel();
    // nothing comes: the wait lasts until the frame's time
    let t0 = Instant::now();
    assert!(pace(&rx, t0 + Duration::from_millis(50)).is_empty());
    assert!(t0.elapsed() >= Duration::from_millis(50));
    // batches are taken with it; a key ends the wait at once, and is taken last
    for m in [batch(1), batch(1), key('q'), batch(1)] {
        tx.send(m).unwrap();
    }
    // the key ends the wait long before its deadline (a minute: no load makes it a minute)
    let t0 = Instant::now();
    let got = pace(&rx, t0 + Duration::from_secs(60));
    assert!(t0.elapsed() < Duration::from_secs(60), "{:?}", t0.elapsed());
    assert_eq!(got.len(), 3);
    assert!(matches!(got[..2], [Msg::Batch { .. }, Msg::Batch { .. }]));
    assert!(matches!(got[2], Msg::Key(_)));
    // the batch after the key waits for the next frame
    assert!(matches!(rx.try_recv(), Ok(Msg::Batch { .. })));
    // batches arriving while it waits are taken, up to the frame's time
    let keep = tx.clone();
    let sender = std::thread::spawn(move || {
        for _ in 0..3 {
            std::thread::sleep(Duration::from_millis(10));
            tx.send(batch(2)).unwrap();
        }
    });
    let t0 = Instant::now();
    let got = pace(&rx, t0 + Duration::from_millis(200));
    assert!(t0.elapsed() >= Duration::from_millis(200));
    assert_eq!(got.len(), 3);
    sender.join().unwrap();
    drop(keep);
    // past the frame's time: nothing is waited for
    assert!(pace(&rx, Instant::now()).is_empty());
    assert_eq!(DATA_FRAME, Duration::from_millis(80));
}

#[test]
fn batches_of_a_stale_run_are_ignored() {
    let mut app = corner_app();
    let fx = act(&mut app, Action::Rerun);
    assert_eq!(start_ids(&fx), vec![2]);
    let stale = tui::workers::run::run_blocking(1, app.scene.as_ref().unwrap());
    for m in stale {
        update(&mut app, m);
    }
    // the rerun of the same text is #1 again (it replaces #1 when it ends), its worker's
    // token 2: the messages of the first run's worker (token 1) are not its own
    let cur = app.current.as_ref().unwrap();
    assert_eq!((cur.id, cur.token), (1, 2));
    assert!(cur.t.is_empty());
    assert!(cur.running());
}

#[test]
fn cancel_a_run() {
    let mut app = App::new_from_text(&read(&corner_path()), &corner_path());
    let fx = app.start();
    assert_eq!(start_ids(&fx), vec![1]);
    let fx = update(&mut app, code(KeyCode::Esc));
    assert!(
        matches!(fx.as_slice(), [Effect::CancelRun { id: 1 }]),
        "{fx:?}"
    );
    assert_eq!(app.current.as_ref().unwrap().status, RunStatus::Cancelling);
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("cancelling"), "{s}");
    update(
        &mut app,
        Msg::RunDone {
            run: 1,
            outcome: RunOutcome::Cancelled { t: 0.25 },
        },
    );
    assert_eq!(app.current.as_ref().unwrap().status, RunStatus::Cancelled);
    // said after what the run started after
    assert_eq!(
        app.status,
        "loaded corner-impact.toml · #1 cancelled at t = 0.250 s"
    );
    // kept in the run list as cancelled, not made the baseline
    assert_eq!(app.runs.list.len(), 1);
    assert_eq!(app.runs.list[0].ended, Ended::Cancelled);
    assert_eq!(app.runs.baseline, None);
    // nothing left to cancel; rerun starts again with nothing overlaid
    assert!(update(&mut app, key('c')).is_empty());
    let fx = act(&mut app, Action::Rerun);
    assert_eq!(start_ids(&fx), vec![2]);
    assert!(app.runs.overlays().is_empty());
}

#[test]
fn the_worker_streams_and_cancel_stops_the_engine() {
    // a short run in the worker thread: batches, then the finished output
    let scene = deckspin::load(&corner_path(), &[]).unwrap();
    let (tx, rx) = mpsc::channel();
    let _h = tui::workers::run::spawn(3, scene, tx);
    let mut batches = 0;
    loop {
        match rx
            .recv_timeout(Duration::from_secs(600))
            .expect("the run ends")
        {
            Msg::Batch { run: 3, .. } => batches += 1,
            Msg::RunDone {
                run: 3,
                outcome: RunOutcome::Finished(out),
            } => {
                assert!(batches >= 1);
                assert_eq!(out.events.len(), 1);
                break;
            }
            m => panic!("unexpected {m:?}"),
        }
    }
    // the full 16 s bridge, cancelled: the engine stops at its next batch
    let scene = deckspin::load(&bridge_path(), &[]).unwrap();
    let (tx, rx) = mpsc::channel();
    let h = tui::workers::run::spawn(7, scene, tx);
    h.cancel();
    // a batch may have left before the flag was set (the thread runs while we cancel)
    loop {
        match rx
            .recv_timeout(Duration::from_secs(600))
            .expect("the run ends")
        {
            Msg::Batch { run: 7, .. } => continue,
            Msg::RunDone {
                run: 7,
                outcome: RunOutcome::Cancelled { t },
            } => {
                assert!(t < 16.0);
                break;
            }
            m => panic!("unexpected {m:?}"),
        }
    }
}

#[test]
fn every_run_is_kept_and_compared_with_the_baseline_not_the_run_before() {
    let mut app = corner_app();
    // the first finished run is pinned as the baseline
    assert_eq!(app.runs.baseline, Some(1));
    assert!(app.status.contains("#1 is the baseline"), "{}", app.status);
    // each run of another model text (a comment added: the same values) is a new run
    let edited = |app: &App, k: u32| format!("{}# edit {k}\n", app.text);
    app.draft = edited(&app, 1);
    let fx = update(&mut app, key('r'));
    assert_eq!(start_ids(&fx), vec![2]);
    assert_eq!(app.current.as_ref().unwrap().id, 2);
    let over: Vec<u64> = app.runs.overlays().iter().map(|e| e.number).collect();
    assert_eq!(over, [1]);
    tui::execute_blocking(&mut app, fx);
    assert_eq!(app.current.as_ref().unwrap().status, RunStatus::Finished);
    app.draft = edited(&app, 2);
    let fx = act(&mut app, Action::Rerun);
    tui::execute_blocking(&mut app, fx);
    // #3 is compared with #1, never with #2 (the run before)
    let kept: Vec<u64> = app.runs.list.iter().map(|e| e.number).collect();
    assert_eq!(kept, [1, 2, 3]);
    let over: Vec<u64> = app.runs.overlays().iter().map(|e| e.number).collect();
    assert_eq!(over, [1]);
    assert_eq!(app.runs.get(3).unwrap().name, "same as #1");
    // rerun while running: the running one is cancelled (kept only with samples); the
    // new run of its text keeps its number, #4, its worker a token of its own
    app.draft = edited(&app, 3);
    let fx = act(&mut app, Action::Rerun);
    assert_eq!(start_ids(&fx), vec![4]);
    let fx = act(&mut app, Action::Rerun);
    assert!(
        matches!(
            fx.as_slice(),
            [Effect::CancelRun { id: 4 }, Effect::StartRun { id: 5, .. }]
        ),
        "{fx:?}"
    );
    assert_eq!(app.current.as_ref().unwrap().id, 4);
    assert_eq!(app.runs.list.len(), 3, "#4 had no sample yet");
    assert_eq!(app.runs.baseline, Some(1));
    // the overlay can be hidden
    act(&mut app, Action::ToggleOverlay);
    assert!(!app.overlay);
}

#[test]
fn compare_table_shows_the_baseline_and_the_shown_run() {
    let mut app = bridge_app();
    let s = screen(&render(&mut app, 120, 40));
    assert!(s.contains("#2 done"), "{s}");
    assert!(s.contains("runs compared"), "{s}");
    let cur = bridge_run();
    let base = bridge_prev_run();
    assert_ne!(cur.total_impacts(), base.total_impacts());
    let head = s.lines().find(|l| l.contains("#1 base")).expect("header");
    assert!(head.find("#1 base") < head.find("#2 "), "{head}");
    let row = s
        .lines()
        .find(|l| l.contains("│impacts"))
        .expect("impacts row");
    let cells: Vec<&str> = row.split('│').nth(2).unwrap().split_whitespace().collect();
    assert_eq!(
        cells,
        [
            "impacts",
            &base.total_impacts().to_string(),
            &cur.total_impacts().to_string()
        ],
        "{row}"
    );
}

#[test]
fn run_tally_matches_the_engine_summary() {
    let r = bridge_run();
    let s = r.summary.as_ref().unwrap();
    let rot = s.peaks.iter().find(|p| p.name == "deck.theta").unwrap();
    assert_eq!(r.rot_name(), "deck.theta");
    assert_eq!(r.peak_rot().0, rot.max_abs);
    assert_eq!(r.peak_rot().1, rot.at);
    assert_eq!(r.residual_rot(), rot.residual);
    assert!(r.total_impacts() > 0);
    for (i, c) in s.contacts.iter().enumerate() {
        assert_eq!(r.impacts[i], c.impacts, "{}", c.name);
        assert!(
            (r.stick_time(i) - c.stick_time).abs() <= 1e-12,
            "{}",
            c.name
        );
        assert_eq!(r.min_gap_of(i), c.min_gap);
    }
    assert!(r.total_stick_time() > 0.0);
}

// ---------------------------------------------------------------------------------------------
// hot reload

#[test]
fn reload_with_unchanged_content_is_ignored() {
    let mut app = corner_app();
    let status = app.status.clone();
    let text = app.text.clone();
    assert!(update(&mut app, Msg::FileChanged(text)).is_empty());
    assert_eq!(app.status, status);
    assert_eq!(app.current.as_ref().unwrap().id, 1);
}

#[test]
fn reload_with_changed_content_reruns() {
    let mut app = corner_app();
    let changed = app.text.replace("mu = 0.5", "mu = 0.1") + "# a comment\n";
    let fx = update(&mut app, Msg::FileChanged(changed.clone()));
    assert_eq!(start_ids(&fx), vec![2]);
    assert!(app.status.contains("reloaded"), "{}", app.status);
    assert_eq!(app.text, changed);
    assert_eq!(app.scene.as_ref().unwrap().contacts[0].law.mu, 0.1);
    assert_eq!(
        app.runs.overlays().first().map(|e| e.number),
        Some(1),
        "the first run is the baseline, overlaid"
    );
    tui::execute_blocking(&mut app, fx);
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("reloaded") || s.contains("#2"), "{s}");
}

#[test]
fn reload_with_a_parse_error_keeps_the_last_good_model() {
    let mut app = corner_app();
    let good = app.text.clone();
    let bad = good.replace("mu = 0.5", "mu = 0.5.1");
    let line = bad.lines().position(|l| l.contains("0.5.1")).unwrap() + 1;
    assert!(update(&mut app, Msg::FileChanged(bad)).is_empty());
    let le = app.load_error.clone().expect("error shown");
    assert_eq!(le.line, Some(line));
    assert_eq!(le.column, Some(9));
    assert!(
        le.message
            .contains(&format!("corner-impact.toml:{line}:9:")),
        "{}",
        le.message
    );
    assert!(
        app.status.contains("keeping the last good model"),
        "{}",
        app.status
    );
    assert_eq!(app.status_kind, StatusKind::Error);
    assert_eq!(app.text, good);
    assert!(app.scene.is_some());
    assert_eq!(
        app.current.as_ref().unwrap().status,
        RunStatus::Finished,
        "charts stay"
    );
    let s = screen(&render(&mut app, 80, 24));
    assert!(
        s.contains(&format!("model error at line {line}, column 9")),
        "{s}"
    );
    assert!(s.contains("mu = 0.5.1"), "source line shown: {s}");
    // an invalid value (not a syntax error) is located too
    let invalid = good.replace("mu = 0.5", "mu = -0.5");
    update(&mut app, Msg::FileChanged(invalid));
    let le = app.load_error.clone().unwrap();
    assert_eq!((le.line, le.column), (Some(line), Some(1)));
    assert!(
        le.message.contains("contact 1 mu: must be ≥ 0"),
        "{}",
        le.message
    );
    // fixing the file clears the error and reruns
    let fx = update(
        &mut app,
        Msg::FileChanged(good.replace("mu = 0.5", "mu = 0.4")),
    );
    assert_eq!(start_ids(&fx), vec![2]);
    assert!(app.load_error.is_none());
}

#[test]
fn reload_with_unsaved_edits_merges_and_a_broken_version_is_not_merged() {
    let mut app = corner_app();
    edit(&mut app, "contact.0.restitution", "0.5");
    assert!(app.dirty());
    let disk = app.text.replace("t_end = 0.5", "t_end = 0.4");
    let fx = update(&mut app, Msg::FileChanged(disk.clone()));
    assert_eq!(start_ids(&fx), vec![2]);
    assert_eq!(app.mode, Mode::Normal);
    assert_eq!(
        app.draft,
        disk.replace("restitution = 0.0", "restitution = 0.5")
    );
    // the same content again is ignored
    assert!(update(&mut app, Msg::FileChanged(disk.clone())).is_empty());
    // a version that does not load is not merged: the edits and the last good model stay
    let bad = disk.replace("mu = 0.5", "mu = 0.5.1");
    assert!(update(&mut app, Msg::FileChanged(bad.clone())).is_empty());
    assert!(app.load_error.is_some());
    assert!(app.status.contains("not merged"), "{}", app.status);
    assert_eq!(app.text, disk);
    assert!(app.draft.contains("restitution = 0.5"));
    // s overwrites the broken version (it was seen)
    let fx = act(&mut app, Action::Save);
    let [Effect::Save { base, .. }] = fx.as_slice() else {
        panic!("{fx:?}")
    };
    assert_eq!(*base, Some(tui::app::hash_text(&bad)));
    // the next good version is merged and clears the error
    let good = disk.replace("t_end = 0.4", "t_end = 0.3");
    let fx = update(&mut app, Msg::FileChanged(good.clone()));
    assert_eq!(start_ids(&fx).len(), 1);
    assert!(app.load_error.is_none());
    assert_eq!(
        app.draft,
        good.replace("restitution = 0.0", "restitution = 0.5")
    );
}

#[test]
fn a_file_that_never_loaded_can_be_repaired() {
    let bad = read(&corner_path()).replace("mu = 0.5", "mu = -0.5");
    let mut app = App::new_from_text(&bad, &corner_path());
    assert!(app.scene.is_none());
    let le = app.load_error.clone().unwrap();
    assert!(le.message.contains("contact 1 mu"), "{}", le.message);
    assert!(app.start().is_empty(), "nothing to run");
    assert!(act(&mut app, Action::Rerun).is_empty());
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("model error at line"), "{s}");
    // repair it in the form: an edit elsewhere is taken, the fix makes it run
    edit(&mut app, "contact.0.restitution", "0.1");
    assert_eq!(app.mode, Mode::Normal);
    assert!(app.scene.is_none());
    edit(&mut app, "contact.0.mu", "0.4");
    assert!(app.scene.is_some());
    assert_eq!(start_ids(&act(&mut app, Action::Rerun)), vec![1]);
    // or on disk: a good version loads and runs
    let mut app = App::new_from_text(&bad, &corner_path());
    let fx = update(&mut app, Msg::FileChanged(read(&corner_path())));
    assert_eq!(start_ids(&fx), vec![1]);
    assert!(app.load_error.is_none());
}

#[test]
fn quit_asks_when_there_are_unsaved_edits() {
    let mut app = corner_app();
    let fx = update(&mut app, key('q'));
    assert!(matches!(fx.as_slice(), [Effect::Quit]));
    assert!(app.quit);
    let mut app = corner_app();
    edit(&mut app, "contact.0.mu", "0.2");
    assert!(update(&mut app, key('q')).is_empty());
    assert!(matches!(app.mode, Mode::Confirm(Confirm::Quit)));
    update(&mut app, key('n'));
    assert!(!app.quit);
    // Ctrl-C while typing a value asks too
    select_field(&mut app, "contact.0.gap");
    update(&mut app, code(KeyCode::Enter));
    update(
        &mut app,
        Msg::Key(KeyEvent::new(KeyCode::Char('c'), KeyModifiers::CONTROL)),
    );
    assert!(matches!(app.mode, Mode::Confirm(Confirm::Quit)));
    update(&mut app, key('n'));
    update(
        &mut app,
        Msg::Key(KeyEvent::new(KeyCode::Char('c'), KeyModifiers::CONTROL)),
    );
    let fx = update(&mut app, key('y'));
    assert!(matches!(fx.as_slice(), [Effect::Quit]));
}

// ---------------------------------------------------------------------------------------------
// export

#[test]
fn export_writes_chart_history_and_event_csv_into_the_output_folder_never_over_a_file() {
    let d = scratch("export");
    let model = d.join("models/corner.toml");
    std::fs::write(&model, read(&corner_path())).unwrap();
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    let fx = app.start();
    tui::execute_blocking(&mut app, fx);
    let fx = update(&mut app, key('e'));
    assert!(matches!(fx.as_slice(), [Effect::Export { .. }]));
    tui::execute_blocking(&mut app, fx);
    let out = d.join("models/corner.out");
    let chart = out.join("export-1-chart.csv");
    let history = out.join("export-1-history.csv");
    let events = out.join("export-1-events.csv");
    for p in [&chart, &history, &events] {
        assert!(
            app.status.contains(&p.display().to_string()),
            "{}",
            app.status
        );
    }
    assert!(
        !d.join("models/corner-chart.csv").exists(),
        "not beside the model"
    );
    let c = read(&chart);
    let mut lines = c.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t,deck.theta,corner.gap,deck.x,deck.y"
    );
    let samples = app.current.as_ref().unwrap().t.len();
    assert_eq!(lines.count(), samples);
    let e = read(&events);
    assert!(e.starts_with("t,contact,kind,normal_impulse"));
    assert_eq!(
        e.lines().filter(|l| l.contains(",corner,impact,")).count(),
        1
    );
    // zoomed: the chart holds the visible window, the history the whole run
    act(&mut app, Action::CursorHome);
    act(&mut app, Action::ZoomIn);
    let (a, b) = app.window();
    assert!(b - a < 0.3);
    let fx = update(&mut app, key('e'));
    tui::execute_blocking(&mut app, fx);
    let chart2 = out.join("export-2-chart.csv");
    let history2 = out.join("export-2-history.csv");
    assert!(
        app.status.contains(&chart2.display().to_string()) && app.status.contains("export-1 kept"),
        "{}",
        app.status
    );
    // the first export is untouched
    assert_eq!(read(&chart), c);
    let windowed = read(&chart2).lines().count() - 1;
    assert!(windowed < samples, "{windowed} of {samples}");
    let run = app.current.as_ref().unwrap();
    let w = tui::chart::window(&run.t, a, b).count();
    assert_eq!(windowed, w);
    let h = read(&history2);
    let mut hl = h.lines();
    let header = hl.next().unwrap();
    assert!(header.starts_with("t,"), "{header}");
    assert_eq!(
        header.split(',').count(),
        1 + run.dof_names.len() + run.contact_names.len() + 2 * run.element_names.len()
    );
    assert_eq!(
        hl.count(),
        samples,
        "every sample of the run, not the window"
    );
    // the last sample's time, as the run holds it
    let last = h.lines().last().unwrap();
    let t_last: f64 = last.split(',').next().unwrap().parse().unwrap();
    assert_eq!(t_last.to_bits(), run.t[samples - 1].to_bits());
    // a file planted at the next number's name is not overwritten: the number after it
    std::fs::write(out.join("export-3-events.csv"), "mine\n").unwrap();
    let fx = update(&mut app, key('e'));
    tui::execute_blocking(&mut app, fx);
    assert_eq!(read(&out.join("export-3-events.csv")), "mine\n");
    assert!(out.join("export-4-chart.csv").is_file(), "{}", app.status);
    assert!(!out.join("export-3-chart.csv").exists());
    let _ = std::fs::remove_dir_all(&d);
}

// ---------------------------------------------------------------------------------------------
// time cursor, zoom, element, markers, colours

#[test]
fn cursor_zoom_and_element_cycling() {
    let mut app = bridge_app();
    assert!(app.follow);
    assert_eq!(app.cursor_time(), 2.0);
    update(&mut app, code(KeyCode::Home));
    assert_eq!(app.cursor_time(), 0.0);
    update(&mut app, code(KeyCode::Right));
    assert!((app.cursor_time() - 0.02).abs() < 1e-12);
    update(
        &mut app,
        Msg::Key(KeyEvent::new(KeyCode::Right, KeyModifiers::SHIFT)),
    );
    assert!((app.cursor_time() - 0.22).abs() < 1e-12);
    update(&mut app, key('+'));
    let (a, b) = app.window();
    assert!((b - a - 1.0).abs() < 1e-12 && a <= 0.22 && 0.22 <= b);
    update(&mut app, key('+'));
    update(&mut app, key('-'));
    assert!((app.window().1 - app.window().0 - 1.0).abs() < 1e-12);
    update(&mut app, key('0'));
    assert_eq!(app.window(), (0.0, 2.0));
    update(&mut app, code(KeyCode::End));
    assert!(app.follow);
    let n = bridge_run().element_names.len();
    assert_eq!(n, 12);
    update(&mut app, key('n'));
    assert_eq!(app.element, 1);
    update(&mut app, key('N'));
    update(&mut app, key('N'));
    assert_eq!(app.element, n - 1);
    let s = screen(&render(&mut app, 120, 40));
    assert!(s.contains(&bridge_run().element_names[n - 1]), "{s}");
}

#[test]
fn ascii_markers_and_no_color() {
    let mut app = bridge_app();
    let braille = |s: &str| s.chars().any(|c| ('\u{2800}'..='\u{28ff}').contains(&c));
    assert!(braille(&screen(&render(&mut app, 120, 40))));
    update(&mut app, key('m'));
    assert!(app.ascii);
    let s = screen(&render(&mut app, 120, 40));
    assert!(!braille(&s), "{s}");
    // NO_COLOR: no colour anywhere on screen
    let mut mono = App::with_options(
        &short_bridge("0.004"),
        &bridge_path(),
        Options {
            color: false,
            ascii: true,
        },
    );
    mono.current = Some(bridge_run().clone());
    keep_bridge_runs(&mut mono);
    let t = render(&mut mono, 120, 40);
    let buf = t.backend().buffer();
    for c in buf.content() {
        assert_eq!(c.fg, ratatui::style::Color::Reset, "coloured cell {c:?}");
        assert_eq!(c.bg, ratatui::style::Color::Reset, "coloured cell {c:?}");
    }
    assert!(!braille(&screen(&t)), "DECKSPIN_ASCII-style start");
    // default theme: only the 16 named colours
    let mut app = bridge_app();
    let t = render(&mut app, 120, 40);
    for c in t.backend().buffer().content() {
        for col in [c.fg, c.bg] {
            assert!(
                !matches!(
                    col,
                    ratatui::style::Color::Rgb(..) | ratatui::style::Color::Indexed(_)
                ),
                "{col:?}"
            );
        }
    }
}

#[test]
fn event_strip_marks_impacts_and_stick() {
    let r = bridge_run();
    let w = 100;
    let strips: Vec<String> = (0..4)
        .map(|i| {
            tui::ui::event_strip(r, i, 0.0, 2.0, w, 2, false)
                .into_iter()
                .collect()
        })
        .collect();
    let impact_mark = |c: char| c == '*' || c == '+' || ('2'..='9').contains(&c);
    for (i, s) in strips.iter().enumerate() {
        assert_eq!(s.chars().count(), w);
        assert_eq!(s.chars().any(impact_mark), r.impacts[i] > 0, "{s}");
    }
    let stuck = (0..4).any(|i| r.state[i].contains(&ContactState::Stick));
    assert!(stuck);
    assert!(strips.iter().any(|s| s.contains('█') || s.contains('S')));
}

// ---------------------------------------------------------------------------------------------
// any terminal: ASCII mode, colour depth, NO_COLOR marks, Esc, Ctrl-Z, help scrolling, whole
// items only

fn alt(c: char) -> Msg {
    Msg::Key(KeyEvent::new(KeyCode::Char(c), KeyModifiers::ALT))
}

/// The bridge app in ASCII mode (as `DECKSPIN_ASCII=1` starts it), with or without colour.
fn ascii_app(color: bool) -> App {
    let opts = Options { color, ascii: true };
    let mut app = App::with_options(
        &short_bridge("0.004"),
        Path::new("models/four-span.toml"),
        opts,
    );
    app.current = Some(bridge_run().clone());
    keep_bridge_runs(&mut app);
    app.next_run = 3;
    app.set_status(StatusKind::Ok, "run 2 finished");
    app
}

/// The cells of a screen holding a byte above 0x7E, with their positions.
fn non_ascii(t: &Terminal<TestBackend>) -> Vec<(u16, u16, String)> {
    let b = t.backend().buffer();
    let mut bad = Vec::new();
    for y in 0..b.area.height {
        for x in 0..b.area.width {
            let s = b[(x, y)].symbol();
            if s.bytes().any(|c| c > 0x7e) {
                bad.push((x, y, s.to_string()));
            }
        }
    }
    bad
}

/// Puts an app in the state a test draws.
type Setup = Box<dyn Fn(&mut App)>;

#[test]
fn ascii_mode_draws_nothing_above_0x7e_in_any_view_or_mode() {
    let running = {
        let mut r = bridge_run().clone();
        r.status = RunStatus::Running;
        r.t_sim = 1.2;
        r
    };
    let bad_text = short_bridge("0.004").replace("mu = 0.5", "mu = 0.5.1");
    let states: Vec<(&str, Setup)> = vec![
        ("charts", Box::new(|_| {})),
        ("form", Box::new(|a| a.view = View::Form)),
        ("studies", Box::new(|a| a.view = View::Studies)),
        (
            "editing",
            Box::new(|a| {
                select_field(a, "contacts.mu");
                update(a, code(KeyCode::Enter));
                type_str(a, "x");
            }),
        ),
        (
            "running",
            Box::new(move |a| a.current = Some(running.clone())),
        ),
        (
            "error banner",
            Box::new(move |a| {
                update(a, Msg::FileChanged(bad_text.clone()));
            }),
        ),
        ("help", Box::new(|a| a.mode = Mode::Help)),
        (
            "help at the end",
            Box::new(|a| {
                act(a, Action::Help);
                act(a, Action::HelpBottom);
            }),
        ),
        (
            "quit question",
            Box::new(|a| a.mode = Mode::Confirm(Confirm::Quit)),
        ),
        (
            "picker",
            Box::new(|a| {
                a.view = View::Studies;
                a.mode = Mode::Pick {
                    files: vec![PathBuf::from("models/four-span.studies/pga-1.csv")],
                    selected: 0,
                };
            }),
        ),
    ];
    for color in [true, false] {
        for (name, set) in &states {
            for (w, h) in [(80, 24), (120, 40), (60, 18), (40, 10)] {
                let mut app = ascii_app(color);
                update(&mut app, Msg::Resize(w, h));
                set(&mut app);
                let t = render(&mut app, w, h);
                let bad = non_ascii(&t);
                assert!(bad.is_empty(), "{name} at {w}x{h}: {bad:?}\n{}", screen(&t));
            }
        }
    }
    // the panels spell their symbols out (θ, ×, ·, │) rather than leave them to the last pass
    let mut app = ascii_app(true);
    let s = screen(&render(&mut app, 120, 40));
    assert!(s.contains("deck.theta [urad]"), "{s}");
    assert!(s.contains("deckspin | four-span.toml |"), "{s}");
    assert!(s.contains("peak |theta|"), "{s}");
    assert!(s.contains(" plan x"), "{s}");
    assert!(!s.contains('?') || !s.contains("|?|"), "{s}");
    act(&mut app, Action::Help);
    let s = screen(&render(&mut app, 120, 40));
    assert!(s.contains("<-/h") && s.contains("help - keys"), "{s}");
    // `m` turns ASCII mode on and off at run time
    let mut app = bridge_app();
    assert!(!non_ascii(&render(&mut app, 80, 24)).is_empty());
    update(&mut app, key('m'));
    assert!(non_ascii(&render(&mut app, 80, 24)).is_empty());
}

#[test]
fn the_last_ascii_pass_gives_every_symbol_an_ascii_stand_in() {
    use tui::ui::ascii_symbol;
    for (sym, want) in [
        ("│", '|'),
        ("┃", '|'),
        ("─", '-'),
        ("━", '-'),
        ("└", '+'),
        ("┌", '+'),
        ("┼", '+'),
        ("╳", 'X'),
        ("⣿", '.'),
        ("⠁", '.'),
        ("\u{2800}", ' '),
        ("█", '#'),
        ("▒", '#'),
        ("▄", '#'),
        ("•", '*'),
        ("…", '.'),
        ("θ", '?'),
        ("", ' '),
        ("a", 'a'),
        ("~", '~'),
    ] {
        assert_eq!(ascii_symbol(sym), want, "{sym:?}");
    }
}

#[test]
fn snapshot_charts_ascii_80x24_and_120x40() {
    let mut app = ascii_app(true);
    let t = render(&mut app, 80, 24);
    snapshot_settings().bind(|| insta::assert_snapshot!("charts_80x24_ascii", t.backend()));
    let t = render(&mut app, 120, 40);
    snapshot_settings().bind(|| insta::assert_snapshot!("charts_120x40_ascii", t.backend()));
}

/// The rows of the chart whose header line starts with `title`, down to the next header.
fn chart_rows(s: &str, title: &str, width: usize) -> Vec<String> {
    let lines: Vec<String> = s.lines().map(|l| l.chars().take(width).collect()).collect();
    let i = lines
        .iter()
        .position(|l| l.starts_with(title))
        .unwrap_or_else(|| panic!("no chart {title}:\n{s}"));
    lines[i..]
        .iter()
        .take_while(|l| !l.starts_with("events"))
        .cloned()
        .collect()
}

#[test]
fn without_colour_each_series_has_its_own_mark_and_legend() {
    let mut app = bridge_app();
    app.opts.color = false;
    for (w, h) in [(80, 24), (120, 40)] {
        let t = render(&mut app, w, h);
        let s = screen(&t);
        // the time charts are the left panel
        let right = if w >= 100 {
            (w * 36 / 100).clamp(30, 60)
        } else {
            (w * 35 / 100).max(24)
        };
        let left = (w - right) as usize;
        let gaps = chart_rows(&s, "gaps g_N [", left);
        let legend = &gaps[0];
        let body: String = gaps[1..].concat();
        // four gap series, each drawn with its mark and named with it; the previous run too
        for (k, m) in ['.', '+', 'o', 'x'].iter().enumerate() {
            let tag = format!("[{m}]");
            assert!(legend.contains(&tag), "{tag} not in the legend: {legend}");
            let name = &bridge_run().contact_names[k];
            let short: String = name.split('_').filter_map(|p| p.chars().next()).collect();
            let named = legend.contains(&format!("{tag}{name}"))
                || legend.contains(&format!("{tag}{short} "))
                || legend.contains(&format!("{tag}{short}"));
            assert!(named, "{tag} names neither {name} nor {short}: {legend}");
        }
        // (right_top's gap and right_bottom's nearly coincide: the one drawn last shows)
        let drawn = ['.', '+', 'o', 'x']
            .iter()
            .filter(|m| body.contains(**m))
            .count();
        assert!(drawn >= 3, "{drawn} marks drawn in the gap chart:\n{s}");
        // the overlaid baseline #1 by its mark, named where its values fit (the θ chart)
        assert!(s.contains("[:]#1") && body.contains(':'), "{legend}\n{s}");
        let xy = chart_rows(&s, "deck.x / deck.y [", left);
        assert!(
            xy[0].contains("[.]deck.x") && xy[0].contains("[+]deck.y"),
            "{}",
            xy[0]
        );
        let xy_body: String = xy[1..].concat();
        assert!(xy_body.contains('.') && xy_body.contains('+'), "{s}");
        // and no colour at all
        for c in t.backend().buffer().content() {
            assert_eq!(c.fg, ratatui::style::Color::Reset, "coloured cell {c:?}");
        }
    }
    let t = render(&mut app, 80, 24);
    snapshot_settings().bind(|| insta::assert_snapshot!("charts_80x24_no_color", t.backend()));
}

/// One frame of `app` drawn through crossterm into bytes, with the colours rewritten for
/// `depth`.
fn frame_bytes(app: &App, depth: tui::term::ColorDepth) -> String {
    use ratatui::backend::CrosstermBackend;
    use ratatui::layout::Rect;
    use ratatui::{TerminalOptions, Viewport};
    let mut bytes: Vec<u8> = Vec::new();
    {
        let out = tui::term::SgrFilter::new(&mut bytes, depth);
        let mut t = Terminal::with_options(
            CrosstermBackend::new(out),
            TerminalOptions {
                viewport: Viewport::Fixed(Rect::new(0, 0, 80, 24)),
            },
        )
        .unwrap();
        let mut cache = tui::ui::Cache::default();
        t.draw(|f| tui::ui::draw(f, app, &mut cache)).unwrap();
    }
    String::from_utf8_lossy(&bytes).into_owned()
}

/// The SGR parameter lists (`1;38;5;9`) of `bytes`.
fn sgr_params(bytes: &str) -> Vec<String> {
    bytes
        .split('\u{1b}')
        .filter_map(|s| s.strip_prefix('['))
        .filter_map(|s| {
            let end = s.find(|c: char| ('@'..='~').contains(&c))?;
            (s.as_bytes()[end] == b'm').then(|| s[..end].to_string())
        })
        .collect()
}

#[test]
fn colours_are_written_as_the_terminal_shows_them() {
    use tui::term::ColorDepth;
    let env = |vars: &'static [(&'static str, &'static str)]| {
        move |k: &str| {
            vars.iter()
                .find(|(n, _)| *n == k)
                .map(|(_, v)| v.to_string())
        }
    };
    let depth = |vars| ColorDepth::from_vars(&env(vars));
    let mut app = bridge_app();
    update(&mut app, Msg::Resize(80, 24));
    // vt100 (and linux, xterm …): the 16 colours' own codes, never 38;5 or 48;5
    let vt100 = frame_bytes(&app, depth(&[("TERM", "vt100")]));
    assert!(
        !vt100.contains("38;5") && !vt100.contains("48;5"),
        "{vt100:?}"
    );
    let params = sgr_params(&vt100).join(";");
    let codes: Vec<u16> = params.split(';').filter_map(|p| p.parse().ok()).collect();
    assert!(
        codes
            .iter()
            .any(|c| (30..=37).contains(c) || (90..=97).contains(c)),
        "{params}"
    );
    // the same frame as crossterm writes it, for a 256-colour terminal
    let xterm = frame_bytes(&app, depth(&[("TERM", "xterm-256color")]));
    assert!(xterm.contains("38;5;"), "{xterm:?}");
    // dumb: no colour at all, and the app draws without colours itself
    let dumb_vars: &[(&str, &str)] = &[("TERM", "dumb")];
    assert_eq!(depth(dumb_vars), ColorDepth::None);
    let opts = Options::from_vars(&env(dumb_vars)).unwrap();
    // and ASCII drawing: a dumb terminal shows no Braille or box drawing either
    assert!(!opts.color && opts.ascii);
    let dumb = frame_bytes(&app, ColorDepth::None);
    for p in sgr_params(&dumb) {
        for c in p.split(';').filter_map(|c| c.parse::<u16>().ok()) {
            let colour = matches!(c, 30..=39 | 40..=49 | 58 | 59 | 90..=97 | 100..=107);
            assert!(!colour, "colour {c} in ESC[{p}m");
        }
    }
    let ascii = Options::from_vars(&env(&[("TERM", "xterm"), ("DECKSPIN_ASCII", "1")])).unwrap();
    assert!(ascii.color && ascii.ascii);
    // ASCII mode: every byte written is ASCII
    let mut app = ascii_app(true);
    update(&mut app, Msg::Resize(80, 24));
    let bytes = frame_bytes(&app, ColorDepth::Ansi16);
    assert!(bytes.bytes().all(|b| b <= 0x7e), "{bytes:?}");
}

#[test]
fn esc_and_a_key_in_one_read_are_both_taken() {
    // Esc then y, read as Alt+y, during the quit question: Esc answers no, y does nothing
    let mut app = corner_app();
    app.mode = Mode::Confirm(Confirm::Quit);
    update(&mut app, alt('y'));
    assert_eq!(app.mode, Mode::Normal);
    assert!(!app.quit);
    // Esc then j while typing a value: the edit is abandoned, j selects the next field
    let mut app = bridge_app();
    select_field(&mut app, "contacts.mu");
    let sel = app.form.selected;
    update(&mut app, code(KeyCode::Enter));
    type_str(&mut app, "9");
    update(&mut app, alt('j'));
    assert_eq!(app.mode, Mode::Normal);
    assert_eq!(app.form.selected, sel + 1);
    assert!(!app.dirty());
    // Esc then q over the help: the help closed, then q quits
    let mut app = corner_app();
    act(&mut app, Action::Help);
    act(&mut app, Action::HelpDown);
    update(&mut app, alt('q'));
    assert!(app.quit, "Esc closed the help, q quit");
}

#[test]
fn ctrl_z_suspends_from_any_mode() {
    let mut app = bridge_app();
    for setup in [
        Mode::Normal,
        Mode::Help,
        Mode::Confirm(Confirm::Quit),
        Mode::Editing {
            buffer: "0.3".into(),
            check: Ok(()),
        },
    ] {
        app.mode = setup.clone();
        let fx = update(&mut app, ctrl('z'));
        assert!(matches!(fx[..], [Effect::Suspend]), "{setup:?}: {fx:?}");
        assert_eq!(app.mode, setup, "the mode is kept across the suspension");
    }
    let bd = KEYMAP.iter().find(|b| b.action == Action::Suspend).unwrap();
    assert_eq!(bd.label, "^Z");
    // without a terminal the effect does nothing
    tui::execute_blocking(&mut app, vec![Effect::Suspend]);
    assert!(!app.quit);
}

#[test]
fn the_help_scrolls_when_taller_than_the_screen() {
    let mut app = bridge_app();
    update(&mut app, Msg::Resize(80, 24));
    act(&mut app, Action::Help);
    let max = tui::help::max_scroll(Ctx::Charts, 24);
    assert!(max > 0, "the help is taller than 24 rows");
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("more below"), "{s}");
    update(&mut app, key('j'));
    assert_eq!(app.help_scroll, 1);
    update(&mut app, code(KeyCode::Up));
    update(&mut app, code(KeyCode::Up));
    assert_eq!(app.help_scroll, 0);
    update(&mut app, code(KeyCode::PageDown));
    assert_eq!(app.help_scroll, 21.min(max));
    update(&mut app, code(KeyCode::End));
    assert_eq!(app.help_scroll, max);
    update(&mut app, key('j'));
    assert_eq!(app.help_scroll, max, "not past the end");
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("the end") && !s.contains("more below"), "{s}");
    update(&mut app, code(KeyCode::Home));
    assert_eq!(app.help_scroll, 0);
    // every key's line is on screen at one scroll position or another
    let mut seen = String::new();
    for _ in 0..=max {
        seen.push_str(&screen(&render(&mut app, 80, 24)));
        act(&mut app, Action::HelpDown);
    }
    for bd in KEYMAP {
        assert!(seen.contains(bd.desc), "{} never shown\n{seen}", bd.desc);
    }
    // opening the help again starts at the top; a tall screen needs no scrolling
    act(&mut app, Action::CloseHelp);
    act(&mut app, Action::Help);
    assert_eq!(app.help_scroll, 0);
    assert_eq!(tui::help::max_scroll(Ctx::Charts, 100), 0);
    update(&mut app, code(KeyCode::PageDown));
    let t = render(&mut app, 80, 24);
    snapshot_settings().bind(|| insta::assert_snapshot!("help_80x24_scrolled", t.backend()));
}

#[test]
fn nothing_is_cut_into_a_wrong_meaning_at_any_width() {
    let run = bridge_run();
    let names = &run.contact_names;
    let initials: Vec<String> = names
        .iter()
        .map(|n| n.split('_').filter_map(|p| p.chars().next()).collect())
        .collect();
    let hint_texts: Vec<String> = tui::keymap::hints(&[Ctx::Charts, Ctx::Global])
        .iter()
        .map(|(k, h)| format!("{k} {h}"))
        .collect();
    for (w, h) in [(60, 18), (80, 24), (100, 30), (120, 40)] {
        let mut app = bridge_app();
        // a cursor on a small negative rotation (the readout that read "-0.0")
        act(&mut app, Action::CursorHome);
        for _ in 0..6 {
            act(&mut app, Action::CursorRightFast);
        }
        let s = screen(&render(&mut app, w, h));
        let lines: Vec<&str> = s.lines().collect();
        // hint bar: whole hints only, in the keymap's order, ? first
        let bar = lines[lines.len() - 1].trim_end();
        let mut rest = bar;
        for (i, ht) in hint_texts.iter().enumerate() {
            let ht = if i == 0 && rest.starts_with("? all keys") {
                "? all keys".to_string()
            } else {
                ht.clone()
            };
            if let Some(r) = rest.strip_prefix(ht.as_str()) {
                rest = r.trim_start();
            }
        }
        assert!(
            rest.is_empty(),
            "{w}x{h}: '{rest}' is not a whole hint: {bar}"
        );
        assert!(bar.starts_with("? "), "{bar}");
        if w <= 80 {
            assert!(bar.starts_with("? all keys"), "{bar}");
        }
        // header: the title whole or cut after a word, with …
        let title = app.title();
        let head = lines[0];
        let parts: Vec<&str> = head.split(" │ ").collect();
        let file = parts.iter().position(|p| *p == "four-span.toml");
        assert!(file.is_some(), "{w}x{h}: {head}");
        let shown = parts[file.unwrap() + 1];
        assert!(
            shown == title
                || shown.starts_with("charts")
                || (shown.ends_with('…')
                    && title.starts_with(shown.trim_end_matches('…'))
                    && title[shown.trim_end_matches('…').len()..].starts_with(' ')),
            "{w}x{h}: title '{shown}' of '{title}'\n{s}"
        );
        // the value at the cursor, whole
        let tc = app.cursor_time();
        let k = run.rot.unwrap();
        let i = chart::at_or_before(&run.t, tc).unwrap();
        let want = format!("@cursor {}", chart::fmt_num(run.q[k][i], 9));
        if let Some(l) = lines.iter().find(|l| l.contains("@cursor")) {
            let at = l.find(&want);
            let after = at.and_then(|j| l[j + want.len()..].chars().next());
            let whole = after.is_none_or(|c| !c.is_ascii_alphanumeric() && c != '.');
            assert!(at.is_some() && whole, "{w}x{h}: {l} (want {want})");
        }
        // the cursor time, whole, and the events legend not run into it
        let tnow = format!(" t = {} s", chart::fmt_num(tc, 9));
        let ev = lines.iter().find(|l| l.starts_with("events")).unwrap();
        let at = lines.iter().find(|l| l.starts_with("t = ")).unwrap();
        assert!(
            at.starts_with(tnow.trim_start()),
            "{w}x{h}: {at} (want {tnow})"
        );
        assert!(!ev.contains("slides") && !ev.contains("slidin "), "{ev}");
        // gap legend: whole contact names or their initials
        let gl = lines.iter().find(|l| l.starts_with("gaps g_N")).unwrap();
        for part in gl.split('━').skip(1) {
            let word = part.split_whitespace().next().unwrap_or("");
            let word = word.split('│').next().unwrap();
            let value = word.parse::<f64>().is_ok();
            assert!(
                names.iter().any(|n| n == word) || initials.iter().any(|n| n == word) || value,
                "{w}x{h}: legend word '{word}': {gl}"
            );
        }
        // the loop's force unit whole on its labels, or in its title
        assert!(s.contains("kN"), "{w}x{h}:\n{s}");
        for l in &lines {
            let cut = l.match_indices(" k").any(|(j, _)| {
                l[..j].ends_with(|c: char| c.is_ascii_digit()) && !l[j + 2..].starts_with('N')
            });
            assert!(!cut, "{w}x{h}: a cut unit in {l}");
        }
        // the loop's title is whole: an element name then force-deformation, or the name alone
        let el = &run.element_names[0];
        assert!(s.contains(&format!(" {el} ")), "{w}x{h}: loop title:\n{s}");
    }
}

// ---------------------------------------------------------------------------------------------
// terminal sizes and snapshots

#[test]
fn resize_and_too_small() {
    let mut app = bridge_app();
    update(&mut app, Msg::Resize(40, 10));
    assert!(app.too_small());
    let s = screen(&render(&mut app, 40, 10));
    assert!(s.contains("terminal too small"));
    assert!(s.contains("needs 60×18"));
    update(&mut app, Msg::Resize(60, 18));
    assert!(!app.too_small());
    let s = screen(&render(&mut app, 60, 18));
    assert!(!s.contains("too small"));
    // every size from tiny to large draws without panicking, in both views and with help
    for (w, h) in [
        (1, 1),
        (59, 17),
        (60, 18),
        (61, 19),
        (80, 24),
        (100, 30),
        (200, 60),
        (300, 12),
    ] {
        for view in [View::Charts, View::Form, View::Studies] {
            app.view = view;
            render(&mut app, w, h);
            act(&mut app, Action::Help);
            render(&mut app, w, h);
            act(&mut app, Action::CloseHelp);
        }
    }
}

#[test]
fn snapshot_charts_80x24() {
    let mut app = bridge_app();
    let t = render(&mut app, 80, 24);
    snapshot_settings().bind(|| insta::assert_snapshot!("charts_80x24", t.backend()));
}

#[test]
fn snapshot_charts_120x40_with_cursor() {
    let mut app = bridge_app();
    act(&mut app, Action::CursorHome);
    for _ in 0..4 {
        act(&mut app, Action::CursorRightFast);
    }
    for _ in 0..8 {
        act(&mut app, Action::CursorRight);
    }
    let t = render(&mut app, 120, 40);
    snapshot_settings().bind(|| insta::assert_snapshot!("charts_120x40", t.backend()));
}

#[test]
fn snapshot_too_small_40x10() {
    let mut app = bridge_app();
    let t = render(&mut app, 40, 10);
    snapshot_settings().bind(|| insta::assert_snapshot!("too_small_40x10", t.backend()));
}

#[test]
fn snapshot_resize_120x40_to_80x24() {
    let mut app = bridge_app();
    let mut t = render(&mut app, 120, 40);
    t.backend_mut().resize(80, 24);
    update(&mut app, Msg::Resize(80, 24));
    draw(&mut t, &app);
    let direct = render(&mut app, 80, 24);
    assert_eq!(
        screen(&t),
        screen(&direct),
        "a resized frame equals a fresh one"
    );
    snapshot_settings().bind(|| insta::assert_snapshot!("resize_120x40_to_80x24", t.backend()));
}

#[test]
fn snapshot_form_80x24_editing() {
    let mut app = bridge_app();
    select_field(&mut app, "contacts.gaps.0");
    update(&mut app, code(KeyCode::Enter));
    update(
        &mut app,
        Msg::Key(KeyEvent::new(KeyCode::Char('u'), KeyModifiers::CONTROL)),
    );
    type_str(&mut app, "-1");
    let t = render(&mut app, 80, 24);
    snapshot_settings().bind(|| insta::assert_snapshot!("form_80x24_editing", t.backend()));
}

#[test]
fn snapshot_help_80x24() {
    let mut app = bridge_app();
    act(&mut app, Action::Help);
    let t = render(&mut app, 80, 24);
    snapshot_settings().bind(|| insta::assert_snapshot!("help_80x24", t.backend()));
}

#[test]
fn snapshot_reload_error_80x24() {
    let mut app = bridge_app();
    let bad = app.text.replace("mu = 0.5", "mu = 0.5.1");
    update(&mut app, Msg::FileChanged(bad));
    let t = render(&mut app, 80, 24);
    snapshot_settings().bind(|| insta::assert_snapshot!("reload_error_80x24", t.backend()));
}

// ---------------------------------------------------------------------------------------------
// file watching

fn wait_for_change(rx: &mpsc::Receiver<Msg>, want: &str) -> bool {
    let end = Instant::now() + Duration::from_secs(5);
    while Instant::now() < end {
        if let Ok(Msg::FileChanged(t)) = rx.recv_timeout(Duration::from_millis(100))
            && t.contains(want)
        {
            return true;
        }
    }
    false
}

#[test]
fn notify_watcher_sees_writes_and_rename_saves() {
    let d = scratch("notify");
    let model = d.join("models/m.toml");
    std::fs::write(&model, "a = 1\n").unwrap();
    let (tx, rx) = mpsc::channel();
    let _w = match tui::workers::watch::notify_watch(&model, tx) {
        Ok(w) => w,
        Err(e) => {
            // the workbench falls back to polling (tested below)
            println!("no notify watcher here ({e}): skipping");
            return;
        }
    };
    std::thread::sleep(Duration::from_millis(50));
    // an editor that saves by writing a temporary file and renaming it over the model
    tui::save_atomic(&model, "a = 2\n").unwrap();
    assert!(wait_for_change(&rx, "a = 2"), "rename-save not seen");
    // in-place write
    std::fs::write(&model, "a = 3\n").unwrap();
    assert!(wait_for_change(&rx, "a = 3"), "write not seen");
    // other files in the directory are not reported
    std::fs::write(d.join("models/other.toml"), "b = 1\n").unwrap();
    std::thread::sleep(Duration::from_millis(400));
    assert!(
        rx.try_iter()
            .all(|m| !matches!(m, Msg::FileChanged(t) if t.contains("b = 1")))
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn polling_fallback_sees_changes_by_content() {
    let d = scratch("poll");
    let model = d.join("models/m.toml");
    std::fs::write(&model, "a = 1\n").unwrap();
    let (tx, rx) = mpsc::channel();
    tui::workers::watch::spawn_poll(model.clone(), tx, Duration::from_millis(50));
    std::thread::sleep(Duration::from_millis(120));
    std::fs::write(&model, "a = 22\n").unwrap();
    assert!(wait_for_change(&rx, "a = 22"));
    // touching without a content change sends nothing
    std::fs::write(&model, "a = 22\n").unwrap();
    std::thread::sleep(Duration::from_millis(300));
    assert!(rx.try_iter().next().is_none());
    let _ = std::fs::remove_dir_all(&d);
}

// ---------------------------------------------------------------------------------------------
// outside changes merged with the unsaved edits

fn ctrl(c: char) -> Msg {
    Msg::Key(KeyEvent::new(KeyCode::Char(c), KeyModifiers::CONTROL))
}

/// The corner-impact model in a scratch directory, opened from its path.
fn corner_on_disk(name: &str) -> (PathBuf, PathBuf, App) {
    let d = scratch(name);
    let model = d.join("models/corner.toml");
    std::fs::write(&model, read(&corner_path())).unwrap();
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    let fx = app.start();
    tui::execute_blocking(&mut app, fx);
    (d, model, app)
}

#[test]
fn a_value_being_typed_survives_an_outside_change_to_another_field() {
    let mut app = corner_app();
    select_field(&mut app, "contact.0.mu");
    update(&mut app, code(KeyCode::Enter));
    update(&mut app, ctrl('u'));
    type_str(&mut app, "0.3");
    let disk = app.text.replace("restitution = 0.0", "restitution = 0.2");
    let fx = update(&mut app, Msg::FileChanged(disk.clone()));
    let Mode::Editing { buffer, check } = &app.mode else {
        panic!(
            "the value being typed was lost: {:?} ({})",
            app.mode, app.status
        )
    };
    assert_eq!(buffer, "0.3");
    assert_eq!(check, &Ok(()));
    assert_eq!(app.form.selected().unwrap().path, "contact.0.mu");
    assert_eq!(app.text, disk, "the change on disk is the new base");
    assert_eq!(app.draft, disk, "and is in the model");
    assert_eq!(app.scene.as_ref().unwrap().contacts[0].law.restitution, 0.2);
    assert_eq!(start_ids(&fx), vec![2], "the merged model reruns");
    assert!(
        app.status.contains("contact 1 restitution"),
        "{}",
        app.status
    );
    // Enter accepts the typed value on top of the outside change
    update(&mut app, code(KeyCode::Enter));
    assert_eq!(app.mode, Mode::Normal);
    assert_eq!(app.draft, disk.replace("mu = 0.5", "mu = 0.3"));
    assert!(app.dirty());
}

#[test]
fn an_outside_change_to_the_field_being_typed_keeps_the_typed_value() {
    let mut app = corner_app();
    select_field(&mut app, "contact.0.mu");
    update(&mut app, code(KeyCode::Enter));
    update(&mut app, ctrl('u'));
    type_str(&mut app, "0.3");
    let disk = app.text.replace("mu = 0.5", "mu = 0.4");
    update(&mut app, Msg::FileChanged(disk.clone()));
    let Mode::Editing { buffer, .. } = &app.mode else {
        panic!("the value being typed was lost: {:?}", app.mode)
    };
    assert_eq!(buffer, "0.3");
    assert!(
        app.status.contains("contact 1 mu") && app.status.contains("0.4"),
        "{}",
        app.status
    );
    // Esc abandons the typed value: the outside one stays
    update(&mut app, code(KeyCode::Esc));
    assert_eq!(app.draft, disk);
    assert!(!app.dirty());
}

#[test]
fn an_unsaved_edit_and_an_outside_change_to_another_field_are_merged() {
    let (d, model, mut app) = corner_on_disk("merge");
    edit(&mut app, "contact.0.mu", "0.3");
    let disk = app.text.replace("restitution = 0.0", "restitution = 0.2");
    std::fs::write(&model, &disk).unwrap();
    let fx = update(&mut app, Msg::FileChanged(disk.clone()));
    assert_eq!(app.mode, Mode::Normal, "no question: {}", app.status);
    assert!(app.status.contains("merged"), "{}", app.status);
    let merged = disk.replace("mu = 0.5", "mu = 0.3");
    assert_eq!(app.text, disk);
    assert_eq!(app.draft, merged);
    assert_eq!(start_ids(&fx), vec![2]);
    tui::execute_blocking(&mut app, fx);
    // the form: mu is still an unsaved edit, restitution is the value on disk
    let mu = &app.form.fields[app.form.index_of("contact.0.mu").unwrap()];
    assert!(mu.edited());
    let e = &app.form.fields[app.form.index_of("contact.0.restitution").unwrap()];
    assert!(!e.edited());
    assert_eq!(e.value.as_deref(), Some("0.2"));
    // s writes both
    let fx = act(&mut app, Action::Save);
    tui::execute_blocking(&mut app, fx);
    assert_eq!(read(&model), merged);
    assert!(!app.dirty(), "{}", app.status);
    let _ = std::fs::remove_dir_all(&d);
}

/// An unsaved edit of μ and a change of μ on disk: a conflict, asked about, and the status
/// line says just that (not that the change "needed no merge").
#[test]
fn a_conflict_alone_is_asked_about_and_not_called_a_change_needing_no_merge() {
    let mut app = corner_app();
    edit(&mut app, "contact.0.mu", "0.3");
    let disk = app.text.replace("mu = 0.5", "mu = 0.4");
    let fx = update(&mut app, Msg::FileChanged(disk.clone()));
    assert!(start_ids(&fx).is_empty(), "no run before the answer");
    assert!(
        matches!(app.mode, Mode::Confirm(Confirm::Merge { .. })),
        "{:?}",
        app.mode
    );
    assert_eq!(
        app.status,
        "contact 1 mu changed on disk and here: yours 0.3, on disk 0.4 — m keeps mine, \
         t takes theirs, M/T for all"
    );
    // the answer says what was done
    let fx = update(&mut app, key('t'));
    assert_eq!(app.draft, disk);
    assert_eq!(start_ids(&fx), vec![2]);
    assert_eq!(
        app.status,
        "took the value on disk; merge done — rerunning (s saves)"
    );
    // the run's end does not wipe it: it is said after it
    tui::execute_blocking(&mut app, fx);
    assert!(
        app.status
            .starts_with("took the value on disk; merge done — rerunning (s saves) · #2 finished"),
        "{}",
        app.status
    );
}

/// The text inside the question's box on screen, its rows joined by spaces.
fn question_text(s: &str) -> String {
    let rows: Vec<&str> = s.lines().collect();
    let top = rows
        .iter()
        .position(|l| l.contains(" question "))
        .unwrap_or_else(|| panic!("no question:\n{s}"));
    let top_row: Vec<char> = rows[top].chars().collect();
    let left = top_row.iter().position(|&c| c == '┌').unwrap();
    let right = top_row.iter().rposition(|&c| c == '┐').unwrap();
    let mut out = Vec::new();
    for l in &rows[top + 1..] {
        let row: Vec<char> = l.chars().collect();
        if row[left] == '└' {
            break;
        }
        let inner: String = row[left + 1..right].iter().collect();
        out.push(inner.trim().to_string());
    }
    out.join(" ")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}

/// A merge question with long values is whole at 80×24 (wrapped in its box, its keys too), and
/// at 140 columns.
#[test]
fn a_long_merge_question_is_whole_at_80x24() {
    let mut app = corner_app();
    let mine = "the corner impact of a long deck against its abutment wall, as edited here";
    let theirs = "the corner impact of a long deck against its abutment wall, as changed on disk";
    edit(&mut app, "title", mine);
    assert_eq!(app.mode, Mode::Normal, "{}", app.status);
    let disk = app
        .text
        .replace("corner impact of a long deck\"", &format!("{theirs}\""));
    update(&mut app, Msg::FileChanged(disk));
    assert!(matches!(app.mode, Mode::Confirm(Confirm::Merge { .. })));
    let want = format!(
        "corner-impact.toml changed on disk, and so did this value here: title: yours {mine}, \
         on disk {theirs} m keep mine t take theirs M mine for all T theirs for all"
    );
    for (w, h) in [(80, 24), (140, 40)] {
        let s = screen(&render(&mut app, w, h));
        assert_eq!(question_text(&s), want, "{w}×{h}:\n{s}");
    }
}

/// mu and restitution edited here and on disk (differently), t_end changed on disk only.
fn conflict_app() -> (App, String) {
    let mut app = corner_app();
    edit(&mut app, "contact.0.mu", "0.3");
    edit(&mut app, "contact.0.restitution", "0.1");
    let disk = app
        .text
        .replace("mu = 0.5", "mu = 0.4")
        .replace("restitution = 0.0", "restitution = 0.2")
        .replace("t_end = 0.5", "t_end = 0.4");
    let fx = update(&mut app, Msg::FileChanged(disk.clone()));
    assert!(start_ids(&fx).is_empty(), "no run before the answers");
    assert!(
        matches!(app.mode, Mode::Confirm(_)),
        "a question: {:?} {}",
        app.mode,
        app.status
    );
    assert!(app.draft.contains("t_end = 0.4"), "outside-only merged");
    assert_eq!(app.text, disk);
    (app, disk)
}

#[test]
fn a_field_changed_outside_and_by_the_user_is_asked_about() {
    // per field: keep mine for mu, take theirs for restitution
    let (mut app, disk) = conflict_app();
    // the field in the user's words, numbered from 1
    assert!(app.status.contains("contact 1 mu"), "{}", app.status);
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("contact 1 mu"), "{s}");
    assert!(s.contains("yours 0.3") && s.contains("on disk 0.4"), "{s}");
    assert!(s.contains("keep mine") && s.contains("take theirs"), "{s}");
    assert!(update(&mut app, key('m')).is_empty());
    assert!(matches!(app.mode, Mode::Confirm(_)), "second question");
    assert!(
        app.status.contains("contact 1 restitution"),
        "{}",
        app.status
    );
    let fx = update(&mut app, key('t'));
    assert_eq!(app.mode, Mode::Normal);
    assert_eq!(app.draft, disk.replace("mu = 0.4", "mu = 0.3"));
    assert_eq!(start_ids(&fx), vec![2], "the merged model reruns");
    // take theirs for all
    let (mut app, disk) = conflict_app();
    update(&mut app, key('T'));
    assert_eq!(app.mode, Mode::Normal);
    assert_eq!(app.draft, disk);
    assert!(!app.dirty());
    // keep mine for all
    let (mut app, disk) = conflict_app();
    update(&mut app, key('M'));
    assert_eq!(app.mode, Mode::Normal);
    assert_eq!(
        app.draft,
        disk.replace("mu = 0.4", "mu = 0.3")
            .replace("restitution = 0.2", "restitution = 0.1")
    );
}

#[test]
fn a_question_while_typing_keeps_the_typed_value() {
    let (mut app, disk) = conflict_app();
    update(&mut app, key('T'));
    // type t_end, then a conflicting outside change to mu arrives
    edit(&mut app, "contact.0.mu", "0.25");
    select_field(&mut app, "solver.t_end");
    update(&mut app, code(KeyCode::Enter));
    update(&mut app, ctrl('u'));
    type_str(&mut app, "0.3");
    update(
        &mut app,
        Msg::FileChanged(disk.replace("mu = 0.4", "mu = 0.45")),
    );
    assert!(matches!(app.mode, Mode::Confirm(_)));
    update(&mut app, key('m'));
    let Mode::Editing { buffer, .. } = &app.mode else {
        panic!("the value being typed was lost: {:?}", app.mode)
    };
    assert_eq!(buffer, "0.3");
    assert_eq!(app.form.selected().unwrap().path, "solver.t_end");
    assert!(app.draft.contains("mu = 0.25"));
}

#[test]
fn save_asks_when_the_file_changed_on_disk_and_was_not_merged() {
    let (d, model, mut app) = corner_on_disk("save-check");
    edit(&mut app, "contact.0.mu", "0.3");
    // changed on disk; the watcher has not reported it yet
    let disk = app.text.replace("restitution = 0.0", "restitution = 0.2");
    std::fs::write(&model, &disk).unwrap();
    let fx = act(&mut app, Action::Save);
    tui::execute_blocking(&mut app, fx);
    assert_eq!(read(&model), disk, "the outside change was overwritten");
    assert!(
        matches!(app.mode, Mode::Confirm(_)),
        "asks: {:?} {}",
        app.mode,
        app.status
    );
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("changed on disk"), "{s}");
    // n: nothing is written, the edits stay
    update(&mut app, key('n'));
    assert_eq!(app.mode, Mode::Normal);
    assert_eq!(read(&model), disk);
    assert!(app.draft.contains("mu = 0.3"));
    assert!(app.status.contains("not saved"), "{}", app.status);
    // s again asks again; y merges the change into the edits, then s saves both
    let fx = act(&mut app, Action::Save);
    tui::execute_blocking(&mut app, fx);
    assert!(matches!(app.mode, Mode::Confirm(_)));
    let fx = update(&mut app, key('y'));
    tui::execute_blocking(&mut app, fx);
    let merged = disk.replace("mu = 0.5", "mu = 0.3");
    assert_eq!(app.draft, merged);
    assert_eq!(read(&model), disk, "merging does not save");
    let fx = act(&mut app, Action::Save);
    tui::execute_blocking(&mut app, fx);
    assert_eq!(read(&model), merged);
    assert!(!app.dirty());
    let _ = std::fs::remove_dir_all(&d);
}

// ---------------------------------------------------------------------------------------------
// signals: the unsaved work and the recovery file

#[test]
fn the_recovery_file_holds_the_unsaved_work_next_to_the_model() {
    use tui::signals;
    let (d, model, mut app) = corner_on_disk("recovery");
    assert_eq!(signals::unsaved(&app), signals::Unsaved::default());
    edit(&mut app, "contact.0.mu", "0.3");
    // a valid value being typed is included
    select_field(&mut app, "contact.0.restitution");
    update(&mut app, code(KeyCode::Enter));
    update(&mut app, ctrl('u'));
    type_str(&mut app, "0.1");
    let u = signals::unsaved(&app);
    let want = app
        .text
        .replace("mu = 0.5", "mu = 0.3")
        .replace("restitution = 0.0", "restitution = 0.1");
    assert_eq!(u.text.as_deref(), Some(want.as_str()));
    assert_eq!(u.note, None);
    // one that is not valid is named, the rest kept
    update(&mut app, ctrl('u'));
    type_str(&mut app, "-1");
    let u = signals::unsaved(&app);
    assert_eq!(u.text, Some(app.draft.clone()));
    assert!(u.note.unwrap().contains("contact.0.restitution, '-1'"));
    // the first free name next to the model; the model itself untouched
    let p = signals::write_recovery(&model, &want).unwrap();
    assert_eq!(p, d.join("models/corner.toml.recovered"));
    assert_eq!(read(&p), want);
    let p1 = signals::write_recovery(&model, "x").unwrap();
    assert_eq!(p1, d.join("models/corner.toml.recovered.1"));
    assert_eq!(read(&p), want, "an earlier recovery file is kept");
    assert_eq!(read(&model), read(&corner_path()));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_run_whose_output_grid_exceeds_the_memory_limit_is_refused_before_it_starts() {
    // 0.5 s at 1e-9 s: 5e8 rows, above the 1e6 the workbench keeps in memory
    let scene = deckspin::load(&corner_path(), &["solver.output_dt=1e-9".into()]).unwrap();
    let msgs = tui::workers::run::run_blocking(5, &scene);
    let [
        Msg::RunDone {
            run: 5,
            outcome: RunOutcome::Failed(f),
        },
    ] = msgs.as_slice()
    else {
        panic!("{msgs:?}")
    };
    let text = f.to_string();
    assert!(
        text.contains("5.000e8 rows") && text.contains("1e6") && text.contains("solver.output_dt"),
        "{text}"
    );
    // 1e-6 s: 5e5 rows, within the limit
    let scene = deckspin::load(&corner_path(), &["solver.output_dt=1e-6".into()]).unwrap();
    let msgs = tui::workers::run::run_blocking(6, &scene);
    assert!(
        matches!(
            msgs.last(),
            Some(Msg::RunDone {
                outcome: RunOutcome::Finished(_),
                ..
            })
        ),
        "{:?}",
        msgs.last()
    );
}

#[test]
fn a_multi_frame_bridge_lists_its_frames_joints_and_bents_in_bridge_words() {
    let text = std::fs::read_to_string(root().join("models/three-frame.toml")).unwrap();
    assert!(form::is_bridge(&text));
    let f = form::build(&text, &text);
    let field = |p: &str| f.fields.iter().find(|x| x.path == p);
    let h = field("frame.1.bent.0.height").expect("frame 2's first bent");
    assert_eq!(
        (h.label.as_str(), h.unit.as_str()),
        ("frame 2 bent 1 height", "m")
    );
    let g = field("joint.1.gaps.0").expect("joint 2's top gap");
    assert_eq!(
        (g.label.as_str(), g.unit.as_str()),
        ("joint 2 gap 1 (top)", "m")
    );
    let m = field("frame.2.mass").unwrap();
    assert_eq!((m.label.as_str(), m.unit.as_str()), ("frame 3 mass", "t"));
    // the one-frame fields are not offered to a file of frames
    assert!(f.fields.iter().all(|x| !x.path.starts_with("deck.")));
    // an edit of a list field is a valid model
    let edited =
        form::set_leaf(&text, "frame.1.bent.0.height", toml_edit::Value::from(11.0)).unwrap();
    let scene =
        deckspin::model::load_str(&edited, &root().join("models/three-frame.toml"), &[]).unwrap();
    assert_eq!(scene.bodies.len(), 5);
}

/// A block sliding at 1 m/s into a shear key that fails at t ≈ 0.0957 s, with a wall it never
/// reaches (a contact row).
const KEY_SCENE: &str = r#"
title = "block through a shear key"
[solver]
t_end = 0.5
[[body]]
name = "block"
mass = 2.0
dofs = ["x"]
initial_velocity = [1.0, 0.0, 0.0]
[[contact]]
name = "wall"
body = "block"
normal = [-1.0, 0.0]
gap = 1.0
[[hysteretic]]
name = "key"
body = "block"
direction = [1.0, 0.0]
law = { law = "key", gap = 0.05, stiffness = 800.0, capacity = 20.0, failure_displacement = 0.04 }
"#;

#[test]
fn key_failures_have_their_own_row_and_mark_in_the_event_strip() {
    let path = root().join("key-scene.toml");
    let run = run_of(KEY_SCENE, &path, 1);
    let failures: Vec<f64> = (run.events.iter())
        .filter(|e| e.kind == deckspin::output::EventKind::KeyFailure)
        .map(|e| e.t)
        .collect();
    assert_eq!(failures.len(), 1);
    assert!((failures[0] - 0.0957).abs() < 1e-4, "{failures:?}");
    // the key row: one mark, in the column of the failure (0.0957 of 0.5 s over 50 cells)
    let (w, per_cell) = (50, 1);
    for (ascii, mark) in [(false, '╳'), (true, 'X')] {
        assert_eq!(tui::ui::key_failure_mark(ascii), mark);
        let keys = tui::ui::key_strip(&run, 0.0, 0.5, w, per_cell, ascii);
        let at: Vec<usize> = (0..w).filter(|&c| keys[c] == mark).collect();
        assert_eq!(
            at,
            vec![chart::column_of(failures[0], 0.0, 0.5, w, per_cell).unwrap()]
        );
        assert!(keys.iter().all(|&c| c == mark || c == ' '));
        // element 0's failure is not an event of contact 0
        let wall = tui::ui::event_strip(&run, 0, 0.0, 0.5, w, per_cell, ascii);
        assert!(wall.iter().all(|&c| c == ' '), "{wall:?}");
    }
    let mut app = App::new_from_text(KEY_SCENE, &path);
    app.current = Some(run.clone());
    let s = screen(&render(&mut app, 120, 40));
    let row = s
        .lines()
        .find(|l| l.trim_start().starts_with("keys"))
        .expect(&s);
    assert_eq!(row.matches('╳').count(), 1, "{row}");
    let legend = s.lines().find(|l| l.starts_with("events ")).expect(&s);
    assert!(legend.contains("╳key"), "{legend}");
    let s = screen(&render(&mut app, 200, 40));
    let legend = s.lines().find(|l| l.starts_with("events ")).expect(&s);
    assert!(
        legend.contains("^ release  █ stuck  ▒ sliding  ╳ key failure"),
        "{legend}"
    );
    update(&mut app, key('m'));
    let s = screen(&render(&mut app, 120, 40));
    let row = s
        .lines()
        .find(|l| l.trim_start().starts_with("keys"))
        .expect(&s);
    assert_eq!(row.matches('X').count(), 1, "{row}");
    // a run without key failures has no such row
    let s = screen(&render(&mut bridge_app(), 120, 40));
    assert!(!s.contains("key failure") && !s.lines().any(|l| l.trim_start().starts_with("keys")));
}

#[test]
fn frames_bents_and_keys_are_added_and_removed_as_lists() {
    use deckspin::tui::form::list_edit::{duplicate, remove};
    let path = root().join("models/three-frame.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let load = |t: &str| deckspin::model::load_str(t, &path, &[]).unwrap_or_else(|e| panic!("{e}"));
    let base = load(&text);
    // a frame copied brings a joint: four frames, three joints, every other line kept
    let (four, what) = duplicate(&text, "frame.1.mass").unwrap();
    assert_eq!(what, "frame 2 copied, with joint 2");
    let s = load(&four);
    assert_eq!(s.bodies.len(), base.bodies.len() + 1);
    assert_eq!(s.bodies[3].name, "frame2_copy");
    assert!(
        s.hysteretic
            .iter()
            .any(|h| h.name.starts_with("bent2_copy_top"))
    );
    assert_eq!(
        s.contacts
            .iter()
            .filter(|c| c.name.starts_with("joint"))
            .count(),
        6
    );
    for l in text.lines() {
        assert!(four.contains(l), "line lost: {l}");
    }
    // and removed again: the model of three frames (frame and joint gone)
    let (three, what) = remove(&four, "frame.2.length").unwrap();
    assert_eq!(what, "frame 3 removed, with joint 2");
    let back = load(&three);
    assert_eq!(back.dof_names, base.dof_names);
    // a bent of a frame, a key
    let (more, _) = duplicate(&text, "frame.1.bent.0.height").unwrap();
    assert_eq!(load(&more).hysteretic.len(), base.hysteretic.len() + 4);
    let (keyless, what) = remove(&text, "joint.0.key.gap").unwrap();
    assert_eq!(what, "joint key removed");
    assert_eq!(load(&keyless).hysteretic.len(), base.hysteretic.len() - 2);
    // a key added to a joint without one: a copy of the file's first key line
    let (keyed, what) = duplicate(&keyless, "joint.0.gaps.0").unwrap();
    assert_eq!(what, "joint 1 keyed (a copy of the file's first key)");
    assert_eq!(load(&keyed).hysteretic.len(), base.hysteretic.len());
    // what cannot be done is said
    let e = duplicate(&text, "joint.0.gaps.0").unwrap_err();
    assert!(e.contains("has its key"), "{e}");
    let one = std::fs::read_to_string(root().join("models/four-span.toml")).unwrap();
    assert!(remove(&one, "deck.mass").is_err());
    // the keys of the form view: `+` on a frame's field, `-` on the copy's
    let mut app = App::new_from_text(&text, &path);
    app.view = View::Form;
    select_field(&mut app, "frame.1.mass");
    update(&mut app, key('+'));
    assert!(
        app.dirty() && app.draft.contains("frame2_copy"),
        "{}",
        app.status
    );
    select_field(&mut app, "frame.2.mass");
    update(&mut app, key('-'));
    assert!(!app.draft.contains("frame2_copy"), "{}", app.status);
    // the bridge's only frame stays, said in the status line
    let mut one_app = App::new_from_text(&one, &root().join("models/four-span.toml"));
    one_app.view = View::Form;
    select_field(&mut one_app, "bent.0.height");
    update(&mut one_app, key('-'));
    update(&mut one_app, key('-'));
    update(&mut one_app, key('-'));
    assert!(one_app.status.contains("invalid"), "{}", one_app.status);
}

// ---------------------------------------------------------------------------------------------
// the studies view

use deckspin::study_csv::to_csv;
use deckspin::study_table::{PointStatus, StudyKind, StudyTable};
use deckspin::tui::msg::StudyOutcome;
use deckspin::tui::runs::out_folder::out_dirs;
use deckspin::tui::studies::{Phase, Source};

fn study_index(kind: StudyKind) -> usize {
    StudyKind::ALL.iter().position(|k| *k == kind).unwrap()
}

/// `Enter` on `kind` in the studies view: the study's id and its worker's spec.
fn start_study(app: &mut App, kind: StudyKind) -> (u64, Box<tui::studies::StudySpec>) {
    app.view = View::Studies;
    app.studies.selected = study_index(kind);
    let mut fx = act(app, Action::StudyRun);
    assert_eq!(fx.len(), 1, "{}", app.status);
    match fx.remove(0) {
        Effect::StartStudy { id, spec } => (id, spec),
        e => panic!("{e:?}"),
    }
}

/// The table a study ends with (the messages of its worker, run here).
fn final_table(msgs: Vec<Msg>) -> StudyTable {
    match msgs.into_iter().last() {
        Some(Msg::StudyDone {
            outcome: StudyOutcome::Finished(t),
            ..
        }) => *t,
        m => panic!("{m:?}"),
    }
}

/// The PGA, μ (μ 0, 0.3, 0.6), screening, suite (2 pairs at 0.2 and 0.4 g), work-precision,
/// ladder and swings studies of the short bridge, computed once.
fn study_tables() -> &'static [StudyTable; 7] {
    static T: OnceLock<[StudyTable; 7]> = OnceLock::new();
    T.get_or_init(|| {
        StudyKind::ALL.map(|k| {
            let mut app = bridge_app();
            app.studies.mus = vec![0.0, 0.3, 0.6];
            let mut sub = app.studies.suite_for(&app.path);
            (sub.pairs, sub.levels) = (2, vec![0.2, 0.4]);
            app.studies.suite = Some(sub);
            let (id, spec) = start_study(&mut app, k);
            final_table(tui::workers::study::run_blocking(id, &spec))
        })
    })
}

/// The bridge app in the studies view with `kind` finished (as if its CSV were written to
/// `models/four-span.out/<kind>-1.csv`).
fn studies_app(kind: StudyKind) -> App {
    let mut app = bridge_app();
    let (id, _) = start_study(&mut app, kind);
    let table = study_tables()[study_index(kind)].clone();
    let outcome = StudyOutcome::Finished(Box::new(table));
    let fx = update(&mut app, Msg::StudyDone { id, outcome });
    assert!(
        matches!(fx.as_slice(), [Effect::WriteStudy { .. }]),
        "{fx:?}"
    );
    let csv = PathBuf::from(format!("models/four-span.out/{}-1.csv", kind.key()));
    update(
        &mut app,
        Msg::StudyWritten {
            id,
            result: Ok(csv),
        },
    );
    app
}

/// The rows of the run table of `kind`.
fn runs_of(app: &App, kind: StudyKind) -> Vec<deckspin::study_table::StudyRun> {
    match &app.studies.entry(kind).expect("an entry").table {
        Some(StudyTable::Runs(t)) => t.runs.clone(),
        t => panic!("{t:?}"),
    }
}

#[test]
fn the_studies_view_is_the_third_view() {
    let mut app = bridge_app();
    let views: Vec<View> = (0..3)
        .map(|_| {
            update(&mut app, code(KeyCode::Tab));
            app.view
        })
        .collect();
    assert_eq!(views, vec![View::Form, View::Studies, View::Charts]);
    update(&mut app, code(KeyCode::BackTab));
    assert_eq!(app.view, View::Studies);
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.lines().next().unwrap().contains("│ studies"), "{s}");
    assert!(s.contains(">PGA (Fig. 7): not run"), "{s}");
    assert!(
        s.contains("Fig. 7: peak |θ| vs PGA · model: four-span.toml as saved"),
        "{s}"
    );
    // h/l move through the list of studies, then on to the results pages and round
    for (k, want) in [('l', 1), ('l', 2), ('l', 3), ('l', 4), ('h', 3), ('h', 2)] {
        update(&mut app, key(k));
        assert_eq!(app.studies.selected, want);
        assert_eq!(app.results.page, None);
    }
    assert_eq!(app.studies.kind(), StudyKind::Screen);
    app.studies.selected = 0;
    update(&mut app, key('h'));
    assert_eq!(app.results.page, Some(tui::results::Page::Records));
    update(&mut app, key('l'));
    assert_eq!((app.results.page, app.studies.selected), (None, 0));
    update(&mut app, key('l'));
    update(&mut app, key('l'));
    // the help puts the studies keys after those of everywhere
    act(&mut app, Action::Help);
    let s = screen(&render(&mut app, 80, 24));
    let (everywhere, studies) = (
        s.find("everywhere").unwrap(),
        s.find("studies view").unwrap(),
    );
    assert!(
        everywhere < studies && s.contains("reopen a study from its CSV"),
        "{s}"
    );
}

#[test]
fn a_study_starts_in_a_worker_on_the_form_model() {
    let mut app = bridge_app();
    assert!(edit(&mut app, "contacts.mu", "0.3").is_empty());
    assert!(app.dirty());
    let (id, spec) = start_study(&mut app, StudyKind::Pga);
    // the form's model, edits included, as the worker's
    assert_eq!(spec.kind, StudyKind::Pga);
    assert_eq!(spec.text, app.draft);
    assert!(spec.text.contains("mu = 0.3"));
    assert_eq!(spec.path, app.path);
    let e = app.studies.entry(StudyKind::Pga).unwrap();
    assert_eq!((e.id, &e.phase), (id, &Phase::Running));
    assert_eq!(
        e.source,
        Source::Form {
            file: "four-span.toml".into(),
            edited: true
        }
    );
    // seven [[run]] tables, each without and with contact
    assert_eq!(e.progress(), (0, 14));
    assert_eq!(
        app.status,
        "PGA (Fig. 7) study started on the form's model (four-span.toml with unsaved edits)"
    );
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("0/14 runs"), "{s}");
    assert!(s.contains("form draft (unsaved edits)"), "{s}");
    // one study at a time; the run of the charts is not touched
    app.studies.selected = study_index(StudyKind::Mu);
    assert!(act(&mut app, Action::StudyRun).is_empty());
    assert_eq!(
        app.status,
        "the PGA (Fig. 7) study is running: Esc cancels it first"
    );
    // a model without [[run]] tables has no PGA study
    let mut corner = corner_app();
    corner.view = View::Studies;
    assert!(act(&mut corner, Action::StudyRun).is_empty());
    assert!(
        corner.status.contains("needs [[run]] tables"),
        "{}",
        corner.status
    );
    // the screening runs on any model
    corner.studies.selected = study_index(StudyKind::Screen);
    let fx = act(&mut corner, Action::StudyRun);
    assert!(
        matches!(fx.as_slice(), [Effect::StartStudy { .. }]),
        "{fx:?}"
    );
}

#[test]
fn study_rows_arrive_as_progress_and_the_end_writes_its_csv() {
    let mut app = bridge_app();
    let (id, spec) = start_study(&mut app, StudyKind::Pga);
    let msgs = tui::workers::study::run_blocking(id, &spec);
    assert_eq!(msgs.len(), 15, "14 rows and the end");
    let mut done = 0;
    for m in msgs {
        let row = matches!(m, Msg::StudyRow { .. });
        let fx = update(&mut app, m);
        if row {
            done += 1;
            assert!(fx.is_empty());
            let e = app.studies.entry(StudyKind::Pga).unwrap();
            assert_eq!(e.progress(), (done, 14));
            if done == 5 {
                let s = screen(&render(&mut app, 80, 24));
                assert!(s.contains("5/14 runs") && s.contains("Esc cancels"), "{s}");
                assert!(
                    s.lines().next().unwrap().contains("PGA 5/14 · #2 done"),
                    "{s}"
                );
            }
            continue;
        }
        // the end: the whole table, then its CSV written beside the model
        let [Effect::WriteStudy { id: w, dirs, table }] = fx.as_slice() else {
            panic!("{fx:?}")
        };
        assert_eq!(*w, id);
        assert_eq!(*dirs, out_dirs(Path::new("models/four-span.toml")));
        assert_eq!(dirs[0], PathBuf::from("models/four-span.out"));
        assert_eq!(to_csv(table), to_csv(&study_tables()[0]));
    }
    let e = app.studies.entry(StudyKind::Pga).unwrap();
    assert_eq!(e.phase, Phase::Finished);
    assert_eq!(
        app.status,
        "PGA (Fig. 7) finished: 14 of 14 runs — writing its CSV…"
    );
    // the rows as they came are those of the table the worker ended with
    let runs = runs_of(&app, StudyKind::Pga);
    let StudyTable::Runs(t) = &study_tables()[0] else {
        unreachable!()
    };
    for (a, b) in runs.iter().zip(&t.runs) {
        assert_eq!(a.peak_rotation.to_bits(), b.peak_rotation.to_bits());
        assert_eq!(a.status, PointStatus::Ok);
    }
    // the runs without impacts peak as without contact, those that pound do not; runs 6 and 7
    // (the same scene) the same
    let [without, with] = t.fig7();
    for (k, (n, w)) in without.iter().zip(&with).enumerate() {
        let pounds = t.runs[2 * k + 1].impacts > 0;
        assert_eq!(pounds, n.1 != w.1, "run {}: {n:?} {w:?}", k + 1);
    }
    assert_eq!(t.runs[1].impacts, 0, "run 1 does not reach the abutments");
    assert!(t.runs[13].impacts > 0);
    assert_eq!(with[5].1.to_bits(), with[6].1.to_bits());
}

#[test]
fn a_cancelled_study_keeps_its_finished_rows() {
    use std::sync::Mutex;
    use std::sync::atomic::{AtomicBool, Ordering};
    let mut app = bridge_app();
    let (id, spec) = start_study(&mut app, StudyKind::Pga);
    // the worker, its cancel flag raised by the third row as Esc would
    let cancel = AtomicBool::new(false);
    let sent = Mutex::new(Vec::new());
    let send = |m: Msg| {
        let mut s = sent.lock().unwrap();
        s.push(m);
        if s.len() == 3 {
            cancel.store(true, Ordering::SeqCst);
        }
    };
    let done = tui::workers::study::run(id, &spec, &cancel, &send);
    let rows = sent.into_inner().unwrap();
    let n = rows.len();
    assert!((3..14).contains(&n), "{n} rows before the runs stopped");
    for m in rows.into_iter().take(3) {
        update(&mut app, m);
    }
    let fx = update(&mut app, code(KeyCode::Esc));
    assert!(
        matches!(fx.as_slice(), [Effect::CancelStudy { id: i }] if *i == id),
        "{fx:?}"
    );
    assert_eq!(
        app.studies.entry(StudyKind::Pga).unwrap().phase,
        Phase::Cancelling
    );
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("cancelling after 3/14 runs"), "{s}");
    let before = runs_of(&app, StudyKind::Pga);
    let Msg::StudyDone {
        outcome: StudyOutcome::Cancelled(_),
        ..
    } = &done
    else {
        panic!("{done:?}")
    };
    let fx = update(&mut app, done);
    // its CSV is written all the same, the runs not run marked so
    assert!(
        matches!(fx.as_slice(), [Effect::WriteStudy { .. }]),
        "{fx:?}"
    );
    let e = app.studies.entry(StudyKind::Pga).unwrap();
    assert_eq!(e.phase, Phase::Cancelled);
    assert_eq!(e.progress(), (n, 14));
    let after = runs_of(&app, StudyKind::Pga);
    for (a, b) in before.iter().zip(&after) {
        if a.status == PointStatus::Ok {
            assert_eq!(a.peak_rotation.to_bits(), b.peak_rotation.to_bits());
        }
    }
    let not_run = after
        .iter()
        .filter(|r| r.status == PointStatus::NotRun)
        .count();
    assert_eq!(not_run, 14 - n);
    assert!(
        app.status
            .starts_with(&format!("PGA (Fig. 7) cancelled: {n} of 14 runs")),
        "{}",
        app.status
    );
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains(">PGA (Fig. 7): cancelled"), "{s}");
    assert!(
        s.contains(&format!("cancelled: {n} of 14 runs done, drawn")),
        "{s}"
    );
    assert!(
        s.contains("Fig. 7: peak |θ| vs PGA · cancelled · model: four-span.toml"),
        "{s}"
    );
    // nothing left to cancel
    assert!(update(&mut app, code(KeyCode::Esc)).is_empty());
    assert_eq!(app.status, "no study in progress (c cancels the run)");
}

/// The bridge (2 s, 4 mm gaps) written into a scratch folder, its app opened there.
fn scratch_bridge(name: &str) -> (PathBuf, App) {
    let d = scratch(name);
    let model = d.join("models/four-span.toml");
    std::fs::write(&model, short_bridge("0.004")).unwrap();
    let app = App::new_from_text(&read(&model), &model);
    (d, app)
}

#[test]
fn a_finished_study_is_written_and_reopened_from_its_csv_exactly() {
    let (d, mut app) = scratch_bridge("study-csv");
    app.studies.mus = vec![0.1 + 0.2, 0.6];
    app.view = View::Studies;
    app.studies.selected = study_index(StudyKind::Mu);
    for n in 1..=2 {
        let fx = act(&mut app, Action::StudyRun);
        tui::execute_blocking(&mut app, fx);
        let csv = d.join(format!("models/four-span.out/mu-{n}.csv"));
        assert!(csv.is_file(), "{}", app.status);
        assert!(
            app.status.ends_with(&format!("; CSV {}", csv.display())),
            "{}",
            app.status
        );
    }
    let written = app
        .studies
        .entry(StudyKind::Mu)
        .unwrap()
        .table
        .clone()
        .unwrap();
    assert_eq!(written.progress(), (7 + 7 * 2, 21));
    // f lists the CSVs (newest first), Enter opens one
    let fx = update(&mut app, key('f'));
    tui::execute_blocking(&mut app, fx);
    let Mode::Pick { files, .. } = &app.mode else {
        panic!("{:?} {}", app.mode, app.status)
    };
    assert_eq!(files.len(), 2);
    assert!(
        files
            .iter()
            .all(|f| f.starts_with(d.join("models/four-span.out")))
    );
    let s = screen(&render(&mut app, 80, 24));
    assert!(
        s.contains("reopen a study") && s.contains("mu-1.csv"),
        "{s}"
    );
    update(&mut app, key('j'));
    let Mode::Pick { files, selected } = &app.mode else {
        unreachable!()
    };
    let chosen = files[*selected].clone();
    let fx = update(&mut app, code(KeyCode::Enter));
    assert_eq!(app.mode, Mode::Normal);
    tui::execute_blocking(&mut app, fx);
    let e = app.studies.entry(StudyKind::Mu).unwrap();
    assert_eq!(e.source, Source::Csv(chosen.clone()));
    assert_eq!(e.phase, Phase::Finished);
    assert!(
        app.status
            .starts_with(&format!("opened {}", chosen.display())),
        "{}",
        app.status
    );
    // the numbers read back are the numbers run, bit for bit
    let read = e.table.clone().unwrap();
    assert_eq!(to_csv(&read), to_csv(&written));
    let (StudyTable::Runs(a), StudyTable::Runs(b)) = (&read, &written) else {
        panic!()
    };
    for (x, y) in a.runs.iter().zip(&b.runs) {
        assert_eq!(x.peak_rotation.to_bits(), y.peak_rotation.to_bits());
        assert_eq!(x.residual_rotation.to_bits(), y.residual_rotation.to_bits());
        assert_eq!(x.mu.map(f64::to_bits), y.mu.map(f64::to_bits));
    }
    assert_eq!(a.fig8(), b.fig8());
    let s = screen(&render(&mut app, 80, 24));
    assert!(
        s.contains(&format!(
            "from {}",
            chosen.file_name().unwrap().to_string_lossy()
        )),
        "{s}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_malformed_study_csv_is_reported_with_its_file_and_line() {
    let (d, mut app) = scratch_bridge("study-bad-csv");
    let dir = d.join("models/four-span.studies");
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("pga-1.csv");
    std::fs::write(
        &bad,
        "study,run,pga_x,pga_y,contact,mu,peak_rotation,residual_rotation,impacts,status\n\
         pga,1,0.09,0.075,false,,1e-4,0,0,ok\n\
         pga,1,0.09,0.075,true,,abc,0,2,ok\n",
    )
    .unwrap();
    app.view = View::Studies;
    let fx = update(&mut app, key('f'));
    tui::execute_blocking(&mut app, fx);
    let fx = update(&mut app, code(KeyCode::Enter));
    tui::execute_blocking(&mut app, fx);
    assert_eq!(
        app.status,
        format!(
            "cannot open the study: {}:3: peak_rotation: `abc` is not a number",
            bad.display()
        )
    );
    assert_eq!(app.status_kind, StatusKind::Error);
    assert!(app.studies.entry(StudyKind::Pga).is_none());
    // no CSVs at all: said so
    std::fs::remove_file(&bad).unwrap();
    let fx = update(&mut app, key('f'));
    tui::execute_blocking(&mut app, fx);
    assert_eq!(app.mode, Mode::Normal);
    assert!(app.status.starts_with("no study CSVs in"), "{}", app.status);
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_study_that_cannot_run_says_why() {
    let mut app = bridge_app();
    app.studies.overrides = vec!["solver.t_end=-1".into()];
    let (id, spec) = start_study(&mut app, StudyKind::Mu);
    let msgs = tui::workers::study::run_blocking(id, &spec);
    assert_eq!(msgs.len(), 1, "no row, the end");
    for m in msgs {
        assert!(update(&mut app, m).is_empty(), "no CSV");
    }
    let e = app.studies.entry(StudyKind::Mu).unwrap();
    let Phase::Failed(why) = &e.phase else {
        panic!("{:?}", e.phase)
    };
    assert!(why.contains("solver.t_end"), "{why}");
    assert_eq!(app.status, format!("μ (Fig. 8) failed: {why}"));
    let s = screen(&render(&mut app, 80, 24));
    assert!(
        s.contains(">μ (Fig. 8): failed") && s.contains("failed: the reason below"),
        "{s}"
    );
    // the hint bar of the studies view (wide enough for every hint): Esc cancels the study,
    // not the run
    let s = screen(&render(&mut app, 200, 24));
    let bar = s.lines().last().unwrap();
    assert!(bar.contains("Esc cancel study"), "{bar}");
    assert_eq!(bar.matches("Esc cancel").count(), 1, "{bar}");
}

#[test]
fn quitting_cancels_a_running_study() {
    let mut app = bridge_app();
    let (id, _) = start_study(&mut app, StudyKind::Screen);
    let fx = act(&mut app, Action::Quit);
    assert!(
        fx.iter()
            .any(|e| matches!(e, Effect::CancelStudy { id: i } if *i == id)),
        "{fx:?}"
    );
}

#[test]
fn studies_in_ascii_mode_and_without_colour() {
    for kind in StudyKind::ALL {
        let mut app = studies_app(kind);
        app.ascii = true;
        for (w, h) in [(80, 24), (120, 40), (60, 18)] {
            let s = screen(&render(&mut app, w, h));
            // below the header line (shared with the other views), ASCII only
            for (y, line) in s.lines().enumerate().skip(1) {
                let wide: Vec<char> = line.chars().filter(|c| *c as u32 > 0x7e).collect();
                assert!(wide.is_empty(), "{kind:?} {w}x{h} line {y}: {wide:?}\n{s}");
            }
        }
    }
    // without colour the series differ by their marks: o without contact, # with (as the CLI)
    let mut app = studies_app(StudyKind::Pga);
    app.opts.color = false;
    let t = render(&mut app, 80, 24);
    for c in t.backend().buffer().content() {
        assert_eq!(c.fg, ratatui::style::Color::Reset, "coloured cell {c:?}");
    }
    let s = screen(&t);
    let plot: String = s.lines().skip(5).take(14).collect();
    assert!(plot.contains('o') && plot.contains('#'), "{s}");
    assert!(
        s.contains("o without contact") && s.contains("# with contact"),
        "{s}"
    );
}

#[test]
fn snapshot_studies_pga_80x24() {
    let mut app = studies_app(StudyKind::Pga);
    let t = render(&mut app, 80, 24);
    snapshot_settings().bind(|| insta::assert_snapshot!("studies_pga_80x24", t.backend()));
}

#[test]
fn snapshot_studies_suite_80x24() {
    // 2 far-field pairs at 0.2 and 0.4 g: each pair's peak |θ| joined across the levels, the
    // median marked #; + and - change the number of pairs
    let mut app = studies_app(StudyKind::Suite);
    let t = render(&mut app, 80, 24);
    let s = screen(&t);
    assert!(s.contains("record suite: peak |θ| vs PGA"), "{s}");
    assert!(s.contains("4 runs"), "{s}");
    act(&mut app, Action::StudyMore);
    assert_eq!(app.studies.suite.as_ref().map(|s| s.pairs), Some(5)); // 4 by default
    assert!(
        app.status.contains("suite: 5 record pairs × 6 levels"),
        "{}",
        app.status
    );
    snapshot_settings().bind(|| insta::assert_snapshot!("studies_suite_80x24", t.backend()));
}

#[test]
fn snapshot_studies_mu_120x40() {
    let mut app = studies_app(StudyKind::Mu);
    let t = render(&mut app, 120, 40);
    snapshot_settings().bind(|| insta::assert_snapshot!("studies_mu_120x40", t.backend()));
}

#[test]
fn snapshot_studies_screen_80x24() {
    let mut app = studies_app(StudyKind::Screen);
    let t = render(&mut app, 80, 24);
    snapshot_settings().bind(|| insta::assert_snapshot!("studies_screen_80x24", t.backend()));
}

#[test]
fn snapshot_studies_screen_120x40_ascii() {
    let mut app = studies_app(StudyKind::Screen);
    app.ascii = true;
    let t = render(&mut app, 120, 40);
    snapshot_settings()
        .bind(|| insta::assert_snapshot!("studies_screen_120x40_ascii", t.backend()));
}

/// Ctrl-C while typing a value: a valid value is kept (accepted into the draft) and the quit
/// question asked; one not valid yet is given back on "stay", and named in the question.
#[test]
fn ctrl_c_while_typing_asks_and_keeps_the_typed_value() {
    let mut app = corner_app();
    let start_typing = |app: &mut App, value: &str| {
        select_field(app, "contact.0.mu");
        update(app, code(KeyCode::Enter));
        update(
            app,
            Msg::Key(KeyEvent::new(KeyCode::Char('u'), KeyModifiers::CONTROL)),
        );
        type_str(app, value);
    };
    start_typing(&mut app, "0.25");
    assert!(!app.dirty(), "typed, not accepted yet");
    let fx = update(&mut app, ctrl('c'));
    assert!(fx.is_empty() && !app.quit, "it asks");
    assert_eq!(app.mode, Mode::Confirm(Confirm::Quit));
    assert!(
        app.draft.contains("0.25"),
        "the typed value is in the draft"
    );
    update(&mut app, key('n'));
    assert_eq!(app.mode, Mode::Normal);
    assert!(app.dirty() && app.draft.contains("0.25"));
    // not valid yet: the question names it, "n" gives the typing back
    start_typing(&mut app, "0.3x");
    update(&mut app, ctrl('c'));
    assert_eq!(app.mode, Mode::Confirm(Confirm::Quit));
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("0.3x"), "{s}");
    update(&mut app, key('n'));
    match &app.mode {
        Mode::Editing { buffer, .. } => assert_eq!(buffer, "0.3x"),
        m => panic!("{m:?}"),
    }
    // and "y" quits without it
    update(&mut app, ctrl('c'));
    let fx = update(&mut app, key('y'));
    assert!(app.quit, "{fx:?}");
}

/// Every status message goes to the log (`M`), whole and with its time, however long.
#[test]
fn the_message_log_keeps_every_message_whole() {
    let mut app = corner_app();
    let before = app.messages.len();
    let long = format!(
        "#14 (unsaved edits) failed: t = 16.000000000 s: finished outside the accuracy asked for: {} the end",
        "energy closure 2.713e-1 above solver.max_closure = 1e-1; ".repeat(3)
    );
    app.set_status(StatusKind::Error, long.clone());
    app.set_status(StatusKind::Info, "merged from disk");
    app.set_status(StatusKind::Info, "merged from disk");
    assert_eq!(app.messages.len(), before + 2, "a repeat is one message");
    update(&mut app, key('M'));
    assert_eq!(app.mode, Mode::Messages);
    let s = screen(&render(&mut app, 80, 24));
    // the long message, wrapped, every word on screen
    let shown: String = s.split_whitespace().collect::<Vec<_>>().join(" ");
    for word in [
        "#14",
        "failed:",
        "16.000000000",
        "the",
        "end",
        "merged",
        "disk",
    ] {
        assert!(shown.contains(word), "{word} not in\n{s}");
    }
    assert_eq!(shown.matches("2.713e-1").count(), 3, "{s}");
    // a time before each message
    assert!(
        s.lines()
            .any(|l| l.contains("merged from disk") && l.contains(':')),
        "{s}"
    );
    update(&mut app, code(KeyCode::Esc));
    assert_eq!(app.mode, Mode::Normal);
    // scrolling stays within the log
    for _ in 0..1100 {
        app.set_status(StatusKind::Info, format!("m{}", app.messages.len()));
    }
    assert_eq!(app.messages.len(), deckspin::tui::messages::KEEP);
    update(&mut app, key('M'));
    update(&mut app, code(KeyCode::Home));
    assert_eq!(app.log_scroll, 0);
    update(&mut app, code(KeyCode::End));
    let s = screen(&render(&mut app, 80, 24));
    assert!(
        s.contains(&format!("m{}", deckspin::tui::messages::KEEP - 1)),
        "{s}"
    );
}
