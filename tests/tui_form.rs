//! The workbench's form: search, first/last field, folding groups, units from the model's unit
//! system on every field, list elements numbered from 1, trailing comments kept in place,
//! "save and quit", another model opened in the same session; snapshots of the form.

#![cfg(feature = "workbench")]

mod common;

use common::root;
use common::tui::*;

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use deckspin::tui::app::{Confirm, Mode, View};
use deckspin::tui::keymap::Action;
use deckspin::tui::{self, App, Effect, Msg, Options, form, update};
use std::path::{Path, PathBuf};

/// The four-span bridge in the form view (relative path: snapshots hold no checkout path).
fn bridge_app() -> App {
    let text = read(&root().join("models/four-span.toml"));
    let mut app = App::new_from_text(&text, Path::new("models/four-span.toml"));
    app.view = View::Form;
    app
}

fn keys(app: &mut App, s: &str) {
    for c in s.chars() {
        update(app, key(c));
    }
}

fn selected_path(app: &App) -> String {
    app.form
        .selected()
        .map(|f| f.path.clone())
        .unwrap_or_default()
}

/// A file in a fresh folder of the test's scratch space.
fn scratch_copy(name: &str, from: &Path) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("tui_form-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(from.file_name().unwrap());
    std::fs::copy(from, &p).unwrap();
    p
}

// ---------------------------------------------------------------------------------------------
// search, first and last, folds

#[test]
fn search_jumps_live_enter_keeps_esc_goes_back() {
    let mut app = bridge_app();
    update(&mut app, code(KeyCode::Down));
    let start = selected_path(&app);
    update(&mut app, key('/'));
    assert!(matches!(app.mode, Mode::Search { .. }));
    keys(&mut app, "rest");
    assert_eq!(selected_path(&app), "contacts.restitution");
    // live: one more letter that matches nothing leaves the selection where it started
    keys(&mut app, "q");
    assert_eq!(selected_path(&app), start);
    assert!(app.status.contains("no field matches"), "{}", app.status);
    update(&mut app, code(KeyCode::Backspace));
    assert_eq!(selected_path(&app), "contacts.restitution");
    update(&mut app, code(KeyCode::Esc));
    assert_eq!(app.mode, Mode::Normal);
    assert_eq!(selected_path(&app), start);

    // case-insensitive, on labels (1-based words) and paths; Enter keeps; n/N again
    update(&mut app, key('/'));
    keys(&mut app, "PGA X");
    assert_eq!(selected_path(&app), "run.0.pga_x");
    update(&mut app, code(KeyCode::Enter));
    assert_eq!(app.mode, Mode::Normal);
    assert_eq!(selected_path(&app), "run.0.pga_x");
    update(&mut app, key('n'));
    assert_eq!(selected_path(&app), "run.1.pga_x");
    update(&mut app, key('N'));
    update(&mut app, key('N'));
    // from the first match back: the last one (7 test runs)
    assert_eq!(selected_path(&app), "run.6.pga_x");
    assert!(app.status.contains("other end"), "{}", app.status);
    update(&mut app, key('/'));
    keys(&mut app, "test run 4 pga y");
    assert_eq!(selected_path(&app), "run.3.pga_y");
    update(&mut app, code(KeyCode::Enter));
    update(&mut app, key('/'));
    keys(&mut app, "contacts.gaps");
    update(&mut app, code(KeyCode::Down));
    assert_eq!(selected_path(&app), "contacts.gaps.1");
}

#[test]
fn home_end_and_g_go_to_the_first_and_last_rows() {
    let mut app = bridge_app();
    update(&mut app, code(KeyCode::End));
    let last = app.form.fields.last().unwrap().path.clone();
    assert!(last.starts_with("solver."), "{last}");
    assert_eq!(selected_path(&app), last);
    update(&mut app, code(KeyCode::Home));
    // the first row is the first group's header
    assert!(app.form.on_header);
    assert_eq!(app.form.selected, 0);
    assert_eq!(app.form.group(), Some(""));
    update(&mut app, key('G'));
    assert_eq!(selected_path(&app), last);
    update(&mut app, key('g'));
    assert!(app.form.on_header);
    update(&mut app, code(KeyCode::Down));
    assert_eq!(selected_path(&app), "title");
}

#[test]
fn groups_fold_stay_folded_across_edits_and_search_unfolds() {
    let mut app = bridge_app();
    let rows_all = app.form.rows().len();
    let groups: Vec<String> =
        app.form
            .fields
            .iter()
            .map(|f| f.group.clone())
            .fold(Vec::new(), |mut v, g| {
                if !v.contains(&g) {
                    v.push(g)
                }
                v
            });
    assert_eq!(rows_all, app.form.fields.len() + groups.len());
    // the groups in the bridge's order, the solver last
    assert_eq!(
        groups,
        [
            "",
            "deck",
            "abutment",
            "contacts",
            "bent",
            "column",
            "damping",
            "excitation",
            "run",
            "solver"
        ]
    );
    // z on a field of the test runs folds them: the selection goes to the header
    let i = app.form.index_of("run.2.pga_x").unwrap();
    app.form.select(i);
    update(&mut app, key('z'));
    assert!(app.form.on_header && app.form.folded.contains("run"));
    let runs = app.form.fields.iter().filter(|f| f.group == "run").count();
    assert_eq!(runs, 21);
    assert_eq!(app.form.rows().len(), rows_all - runs);
    let s = screen(&render(&mut app, 120, 40));
    assert!(s.contains("▸ test runs (21)"), "{s}");
    assert!(!s.contains("test run 3 pga x"), "{s}");
    // an edit elsewhere rebuilds the form: the fold stays
    let m = app.form.index_of("deck.mass").unwrap();
    app.form.select(m);
    update(&mut app, code(KeyCode::Enter));
    update(
        &mut app,
        Msg::Key(KeyEvent::new(KeyCode::Char('u'), KeyModifiers::CONTROL)),
    );
    keys(&mut app, "150");
    update(&mut app, code(KeyCode::Enter));
    assert!(app.dirty());
    assert!(app.form.folded.contains("run"));
    assert_eq!(selected_path(&app), "deck.mass");
    // Enter on a header unfolds it; search into a folded group unfolds it
    // Z with one folded unfolds all; again, folds all
    update(&mut app, key('Z'));
    assert!(app.form.folded.is_empty());
    update(&mut app, key('Z'));
    assert_eq!(app.form.folded.len(), groups.len());
    update(&mut app, key('/'));
    keys(&mut app, "time scale");
    assert_eq!(selected_path(&app), "excitation.time_scale");
    assert!(!app.form.folded.contains("excitation"));
    assert!(app.form.folded.contains("run"));
    update(&mut app, code(KeyCode::Esc));
    assert!(app.form.folded.contains("excitation"), "Esc folds it back");
    assert!(app.form.on_header);
    // back on the deck's header (Z took the selection there): Enter unfolds the deck
    assert_eq!(app.form.group(), Some("deck"));
    update(&mut app, code(KeyCode::Enter));
    assert!(!app.form.folded.contains("deck"));
    assert!(app.form.folded.contains("excitation"));
    // Z with some folded unfolds them all
    update(&mut app, key('Z'));
    assert!(app.form.folded.is_empty());
}

// ---------------------------------------------------------------------------------------------
// units and words

#[test]
fn every_number_has_a_unit_in_the_models_system() {
    for model in ["models/four-span.toml", "models/three-frame.toml"] {
        let text = read(&root().join(model));
        let f = form::build(&text, &text);
        for x in f.fields.iter().filter(|x| x.kind == form::Kind::Float) {
            assert!(!x.unit.is_empty(), "{model}: {} has no unit", x.path);
        }
    }
    let text = read(&root().join("models/four-span.toml"));
    let kip = text.replacen("title = ", "units = \"kip-in\"\ntitle = ", 1);
    let f = form::build(&kip, &kip);
    let unit = |p: &str| f.fields[f.index_of(p).unwrap()].unit.clone();
    assert_eq!(unit("deck.mass"), "kip·s²/in");
    assert_eq!(unit("abutment.actuator_stiffness"), "kip/in");
    assert_eq!(unit("contacts.gaps.0"), "in");
    assert_eq!(unit("column.law.yield_force"), "kip");
    assert_eq!(unit("column.torsion_stiffness"), "kip·in/rad");
    assert_eq!(unit("bent.0.height"), "in");
    assert_eq!(unit("run.3.pga_x"), "g");
    assert_eq!(unit("excitation.lag_bents.0"), "s");
    assert_eq!(unit("contacts.mu"), "–");
    assert_eq!(unit("units"), "SI-kN|SI|kip-in");
    // typed in mm into a kip-in model: written in in
    let t = form::set_value(
        &kip,
        "contacts.gaps.0",
        form::Kind::Float,
        "12.7 mm",
        form::Dim::Q(deckspin::units::Quantity::Length),
    )
    .unwrap();
    assert!(t.contains("gaps = [0.5, 0.0127"), "{t}");
    let si = form::build(&text, &text);
    let unit = |p: &str| si.fields[si.index_of(p).unwrap()].unit.clone();
    assert_eq!(unit("deck.mass"), "t");
    assert_eq!(unit("abutment.actuator_damping"), "kN·s/m");
    assert_eq!(unit("solver.t_end"), "s");
}

/// The form's row (the left pane of the screen `s`) that holds `what`.
fn row_with(s: &str, what: &str) -> String {
    s.lines()
        .map(|l| l.split('│').nth(1).unwrap_or_default().to_string())
        .find(|l| l.contains(what))
        .unwrap_or_else(|| panic!("no {what}:\n{s}"))
}

/// While typing, a value with its own unit is not followed by the field's (`20 mm_`), one
/// without is (`20_ m`); atol's unit says it is mixed and the right pane names the units.
#[test]
fn a_value_typed_with_its_unit_shows_no_second_unit_and_atol_reads_mixed() {
    let mut app = bridge_app();
    app.form.selected = app.form.index_of("contacts.gaps.0").unwrap();
    update(&mut app, code(KeyCode::Enter));
    update(
        &mut app,
        Msg::Key(KeyEvent::new(KeyCode::Char('u'), KeyModifiers::CONTROL)),
    );
    keys(&mut app, "20");
    let s = screen(&render(&mut app, 120, 40));
    let row = row_with(&s, "20_");
    assert!(row.contains("20_ m "), "{row}");
    keys(&mut app, " mm");
    let s = screen(&render(&mut app, 120, 40));
    let row = row_with(&s, "20 mm_");
    assert!(!row.contains("mm_ m"), "{row}");
    assert!(row.contains("20 mm_ "), "{row}");
    update(&mut app, code(KeyCode::Enter));
    assert_eq!(app.mode, Mode::Normal, "{}", app.status);
    assert!(app.draft.contains("gaps = [0.02"), "{}", app.draft);
    // atol
    app.form.selected = app.form.index_of("solver.atol").unwrap();
    assert_eq!(app.form.selected().unwrap().unit, "mixed");
    let s = screen(&render(&mut app, 120, 40));
    let row = row_with(&s, "1e-7");
    assert!(row.contains("1e-7 mixed"), "{row}");
    for part in [
        "state component",
        "(displacements)",
        "(rotations)",
        "(velocities)",
    ] {
        assert!(s.contains(part), "{part}:\n{s}");
    }
}

#[test]
fn list_elements_are_numbered_from_one_in_every_label() {
    for model in ["models/four-span.toml", "models/three-frame.toml"] {
        let text = read(&root().join(model));
        let f = form::build(&text, &text);
        for x in &f.fields {
            let nums: Vec<usize> = x
                .path
                .split('.')
                .filter_map(|s| s.parse::<usize>().ok())
                .collect();
            let words: Vec<&str> = x.label.split([' ', '(', ')']).collect();
            for n in &nums {
                assert!(
                    words.contains(&(n + 1).to_string().as_str()),
                    "{model}: {} is labelled '{}'",
                    x.path,
                    x.label
                );
            }
            assert!(
                !x.label.contains('.') || x.label.contains("ref."),
                "{}",
                x.label
            );
        }
        let label = |p: &str| {
            f.fields
                .iter()
                .find(|x| x.path == p)
                .map(|x| x.label.clone())
        };
        if model.contains("four-span") {
            assert_eq!(label("run.3.pga_x").unwrap(), "test run 4 pga x");
            assert_eq!(
                label("contacts.gaps.0").unwrap(),
                "contacts gap 1 (left_top)"
            );
            assert_eq!(label("excitation.run").unwrap(), "test run");
            assert_eq!(
                label("excitation.lag_bents.2").unwrap(),
                "excitation lag bent 3"
            );
            assert_eq!(label("bent.2.height").unwrap(), "bent 3 height");
        }
    }
    // the detail pane says where the field is in the file, 1-based too
    let mut app = bridge_app();
    let i = app.form.index_of("run.3.pga_x").unwrap();
    app.form.select(i);
    let s = screen(&render(&mut app, 120, 40));
    assert!(s.contains("in the file: run.pga_x (run 4)"), "{s}");
    assert!(!s.contains("run.3"), "{s}");
}

// ---------------------------------------------------------------------------------------------
// trailing comments

/// The line of `text` that starts with `start` (after blanks).
fn line<'a>(text: &'a str, start: &str) -> &'a str {
    text.lines()
        .find(|l| l.trim_start().starts_with(start))
        .unwrap_or_else(|| panic!("no line {start}"))
}

#[test]
fn saved_values_keep_the_text_around_them_and_the_comment_column() {
    let text = read(&root().join("models/four-span.toml"));
    let gaps = line(&text, "gaps =");
    assert_eq!(
        gaps,
        "gaps = [0.0127, 0.0127, 0.0127, 0.0127]   # m, corners left_top, left_bottom, right_top, right_bottom (design gap 0.0127 m, paper §4.1)"
    );
    let set = |t: &str, p: &str, v: &str| {
        form::set_value(t, p, form::Kind::Float, v, form::Dim::Plain).unwrap()
    };
    let comment = gaps.find('#').unwrap();
    // the same width: the whole line the same but the value
    let same = set(&text, "contacts.gaps.1", "0.0254");
    assert_eq!(
        line(&same, "gaps ="),
        gaps.replacen("0.0127, 0.0127", "0.0127, 0.0254", 1)
    );
    // narrower and wider: the comment in its column; one space at least
    let narrow = set(&text, "contacts.gaps.1", "0.02");
    let l = line(&narrow, "gaps =");
    assert_eq!(
        l,
        "gaps = [0.0127, 0.02, 0.0127, 0.0127]     # m, corners left_top, left_bottom, right_top, right_bottom (design gap 0.0127 m, paper §4.1)"
    );
    assert_eq!(l.find('#'), Some(comment));
    let wide = set(&text, "contacts.gaps.1", "0.012345");
    assert_eq!(line(&wide, "gaps =").find('#'), Some(comment));
    let wider = set(&text, "contacts.gaps.3", "0.0123456789");
    assert_eq!(
        line(&wider, "gaps ="),
        "gaps = [0.0127, 0.0127, 0.0127, 0.0123456789] # m, corners left_top, left_bottom, right_top, right_bottom (design gap 0.0127 m, paper §4.1)"
    );
    // every other line untouched
    let others = |t: &str| -> Vec<String> {
        t.lines()
            .filter(|l| !l.starts_with("gaps ="))
            .map(str::to_string)
            .collect()
    };
    assert_eq!(others(&narrow), others(&text));
    // scalars: in a table, and in an array of tables
    let mass = line(&text, "mass = 140.5");
    let m = set(&text, "deck.mass", "150");
    assert_eq!(line(&m, "mass = 150"), mass.replacen("140.5", "150.0", 1));
    let mu = set(&text, "contacts.mu", "0.25");
    let was = line(&text, "mu = 0.5");
    let now = line(&mu, "mu = 0.25");
    assert_eq!(now.find('#'), was.find('#'));
    assert_eq!(now, "mu = 0.25             # paper §4.3");
    // an array over several lines: the comment after an element keeps its column
    let multi = "[damping]\nratio = 0.02\nmodes = [\n  1,   # first\n  3,   # third\n]\n";
    let t = form::set_value(
        multi,
        "damping.modes.0",
        form::Kind::Int,
        "12",
        form::Dim::Plain,
    )
    .unwrap();
    assert_eq!(
        t,
        "[damping]\nratio = 0.02\nmodes = [\n  12,  # first\n  3,   # third\n]\n"
    );
    let t = form::set_value(
        multi,
        "damping.modes.1",
        form::Kind::Int,
        "30",
        form::Dim::Plain,
    )
    .unwrap();
    assert_eq!(
        t,
        "[damping]\nratio = 0.02\nmodes = [\n  1,   # first\n  30,  # third\n]\n"
    );
}

// ---------------------------------------------------------------------------------------------
// the quit question

fn corner_copy(name: &str) -> (App, PathBuf) {
    let p = scratch_copy(name, &root().join("models/validation/corner-impact.toml"));
    let mut app = App::new_from_path(&p, Options::default()).unwrap();
    app.view = View::Form;
    (app, p)
}

fn edit_mu(app: &mut App, v: &str) {
    let i = app.form.index_of("contact.0.mu").unwrap();
    app.form.select(i);
    update(app, code(KeyCode::Enter));
    update(
        app,
        Msg::Key(KeyEvent::new(KeyCode::Char('u'), KeyModifiers::CONTROL)),
    );
    keys(app, v);
    update(app, code(KeyCode::Enter));
    assert!(app.dirty(), "{}", app.status);
}

#[test]
fn the_quit_question_offers_save_and_quit() {
    let (mut app, p) = corner_copy("save-quit");
    let before = read(&p);
    edit_mu(&mut app, "0.35");
    update(&mut app, key('q'));
    assert_eq!(app.mode, Mode::Confirm(Confirm::Quit));
    let s = screen(&render(&mut app, 80, 24));
    assert!(
        s.contains("save and quit") && s.contains("quit without saving"),
        "{s}"
    );
    // n and Esc stay
    update(&mut app, key('n'));
    assert_eq!(app.mode, Mode::Normal);
    assert!(!app.quit);
    update(&mut app, key('q'));
    update(&mut app, code(KeyCode::Esc));
    assert!(!app.quit && app.dirty());
    // s saves, then quits (no rerun)
    update(&mut app, key('q'));
    let fx = update(&mut app, key('s'));
    assert!(matches!(fx.as_slice(), [Effect::Save { .. }]), "{fx:?}");
    assert!(!app.quit);
    tui::execute_blocking(&mut app, fx);
    assert!(app.quit, "{}", app.status);
    let after = read(&p);
    assert_ne!(after, before);
    assert!(after.contains("mu = 0.35"), "{after}");
    assert!(!app.dirty());

    // y quits without saving
    let (mut app, p) = corner_copy("quit-no-save");
    let before = read(&p);
    edit_mu(&mut app, "0.35");
    update(&mut app, key('q'));
    let fx = update(&mut app, key('y'));
    assert!(fx.iter().any(|e| matches!(e, Effect::Quit)), "{fx:?}");
    assert!(app.quit);
    assert_eq!(read(&p), before);

    // a save that fails does not quit
    let (mut app, p) = corner_copy("save-fails");
    edit_mu(&mut app, "0.35");
    update(&mut app, key('q'));
    let fx = update(&mut app, key('s'));
    assert!(!fx.is_empty());
    let text = app.draft.clone();
    update(
        &mut app,
        Msg::Saved {
            text,
            result: Err("disk full".into()),
        },
    );
    assert!(!app.quit);
    assert!(app.status.contains("not quitting"), "{}", app.status);
    let _ = p;
}

// ---------------------------------------------------------------------------------------------
// another model

#[test]
fn another_model_opens_without_restart() {
    let mut app = bridge_app();
    app.next_run = 5;
    let fx = update(&mut app, key('O'));
    let [Effect::ListModels { dir }] = fx.as_slice() else {
        panic!("{fx:?}")
    };
    assert_eq!(dir, Path::new("models"));
    let files = tui::form::model_files::list(dir).unwrap();
    assert!(
        files.contains(&PathBuf::from("models/validation/corner-impact.toml")),
        "{files:?}"
    );
    assert!(files.iter().all(|p| p.extension().unwrap() == "toml"));
    update(&mut app, Msg::ModelFiles(Ok(files.clone())));
    let Mode::OpenModel { selected, .. } = app.mode.clone() else {
        panic!("{:?}", app.mode)
    };
    // the open model is selected first
    assert_eq!(files[selected], PathBuf::from("models/four-span.toml"));
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("validation/corner-impact.toml"), "{s}");
    let target = files
        .iter()
        .position(|p| p.ends_with("corner-impact.toml"))
        .unwrap();
    while !matches!(app.mode, Mode::OpenModel { selected, .. } if selected == target) {
        update(&mut app, key('j'));
    }
    let fx = update(&mut app, code(KeyCode::Enter));
    let [Effect::ReadModel { path }] = fx.as_slice() else {
        panic!("{fx:?}")
    };
    let path = path.clone();
    let text = read(&root().join(&path));
    let fx = update(
        &mut app,
        Msg::ModelRead {
            path: path.clone(),
            result: Ok(text.clone()),
        },
    );
    // the watcher moves to the new file and the new model runs: its first run is #1, its
    // worker's token goes on from the session's (5)
    assert!(
        fx.iter()
            .any(|e| matches!(e, Effect::Watch { path: p } if *p == path)),
        "{fx:?}"
    );
    assert!(
        fx.iter()
            .any(|e| matches!(e, Effect::StartRun { id: 5, .. })),
        "{fx:?}"
    );
    assert_eq!(app.path, path);
    assert_eq!(app.text, text);
    assert!(!app.dirty());
    assert!(app.runs.list.is_empty(), "the old model's runs are cleared");
    assert_eq!(app.current.as_ref().map(|r| (r.id, r.token)), Some((1, 5)));
    assert_eq!(app.view, View::Form);
    assert!(app.form.index_of("contact.0.mu").is_some());
    assert!(app.form.index_of("deck.mass").is_none());
    let title = app.title();
    assert!(app.status.contains(&title), "{}", app.status);
    let s = screen(&render(&mut app, 120, 40));
    assert!(s.contains(&title), "{s}");
}

#[test]
fn opening_another_model_asks_first_with_unsaved_edits() {
    let (mut app, _) = corner_copy("open-dirty");
    edit_mu(&mut app, "0.35");
    let other = root().join("models/validation/bouncing-ball.toml");
    let files = vec![app.path.clone(), other.clone()];
    update(&mut app, Msg::ModelFiles(Ok(files)));
    update(&mut app, key('j'));
    let fx = update(&mut app, code(KeyCode::Enter));
    assert!(fx.is_empty());
    assert_eq!(
        app.mode,
        Mode::Confirm(Confirm::OpenModel {
            path: other.clone()
        })
    );
    // n stays with the edits
    update(&mut app, key('n'));
    assert!(app.dirty());
    assert_eq!(app.mode, Mode::Normal);
    // y reads it; an unreadable file leaves everything as it was
    app.mode = Mode::Confirm(Confirm::OpenModel {
        path: other.clone(),
    });
    let fx = update(&mut app, key('y'));
    assert!(matches!(fx.as_slice(), [Effect::ReadModel { path }] if *path == other));
    update(
        &mut app,
        Msg::ModelRead {
            path: other.clone(),
            result: Err("gone".into()),
        },
    );
    assert!(app.dirty());
    assert!(app.status.contains("not opened"), "{}", app.status);
    tui::execute_blocking(&mut app, fx);
    assert_eq!(app.path, other);
    assert!(!app.dirty());
    assert_eq!(app.mode, Mode::Normal);
}

// ---------------------------------------------------------------------------------------------
// snapshots

fn snap(app: &mut App, name: &str, w: u16, h: u16) {
    let t = render(app, w, h);
    snapshot_settings().bind(|| insta::assert_snapshot!(name, t.backend()));
}

#[test]
fn snapshots_of_the_form() {
    for (w, h) in [(80, 24), (120, 40)] {
        let mut app = bridge_app();
        let i = app.form.index_of("contacts.gaps.1").unwrap();
        app.form.select(i);
        snap(&mut app, &format!("form_{w}x{h}"), w, h);

        let mut app = bridge_app();
        update(&mut app, key('/'));
        keys(&mut app, "pga");
        snap(&mut app, &format!("form_{w}x{h}_searching"), w, h);

        let mut app = bridge_app();
        let i = app.form.index_of("abutment.mass").unwrap();
        app.form.select(i);
        update(&mut app, key('z'));
        snap(&mut app, &format!("form_{w}x{h}_folded"), w, h);
    }
    let mut app = App::with_options(
        &read(&root().join("models/four-span.toml")),
        Path::new("models/four-span.toml"),
        Options {
            color: false,
            ascii: true,
        },
    );
    app.view = View::Form;
    let i = app.form.index_of("bent.0.x").unwrap();
    app.form.select(i);
    update(&mut app, key('z'));
    snap(&mut app, "form_80x24_folded_ascii", 80, 24);
}

#[test]
fn the_form_draws_at_any_size_in_any_state() {
    let mut app = bridge_app();
    for (w, h) in [(60, 18), (61, 19), (80, 24), (200, 60)] {
        for a in [Action::FieldLast, Action::FoldAll, Action::SearchStart] {
            update(&mut app, Msg::Action(a));
            keys(&mut app, "ab");
            let _ = render(&mut app, w, h);
            update(&mut app, code(KeyCode::Esc));
            let _ = render(&mut app, w, h);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// the engine's messages, numbered from 1

/// Types `value` into the field at `path` (not accepted) and returns the live verdict.
fn verdict(app: &mut App, path: &str, value: &str) -> Result<(), String> {
    app.view = View::Form;
    app.form.selected = app.form.index_of(path).expect(path);
    update(app, code(KeyCode::Enter));
    update(
        app,
        Msg::Key(KeyEvent::new(KeyCode::Char('u'), KeyModifiers::CONTROL)),
    );
    keys(app, value);
    let Mode::Editing { check, .. } = &app.mode else {
        panic!("not editing: {:?}", app.mode)
    };
    check.clone()
}

#[test]
fn engine_errors_name_list_elements_from_1_as_the_labels_do() {
    // an edit refused: the reason names the field by its label
    let mut app = bridge_app();
    let r = verdict(&mut app, "contacts.gaps.0", "-0.01").unwrap_err();
    assert!(
        r.contains("contacts gap 1 (left_top): must be ≥ 0, got -0.01"),
        "{r}"
    );
    assert!(!r.contains("contacts.gaps.0"), "{r}");
    assert!(r.starts_with("models/four-span.toml:24:9: "), "{r}");
    let s = screen(&render(&mut app, 120, 40));
    assert!(
        s.contains("✗") && s.contains("gap 1 (left_top): must be ≥ 0"),
        "{s}"
    );
    assert!(!s.contains("gaps.0"), "{s}");
    update(&mut app, code(KeyCode::Esc));
    let r = verdict(&mut app, "contacts.gaps.3", "-1").unwrap_err();
    assert!(
        r.contains("contacts gap 4 (right_bottom): must be ≥ 0"),
        "{r}"
    );

    // nested lists: frame 2's first bent
    let path = root().join("models/three-frame.toml");
    let mut app = App::new_from_text(&read(&path), Path::new("models/three-frame.toml"));
    let r = verdict(&mut app, "frame.1.bent.0.height", "-2").unwrap_err();
    assert!(r.contains("frame 2 bent 1 height: "), "{r}");
    assert!(!r.contains("frame.1.bent.0"), "{r}");

    // a version on disk that does not load: the banner and the status line, from 1
    let mut app = bridge_app();
    let broken = app
        .text
        .replace("gaps = [0.0127, 0.0127,", "gaps = [0.0127, -0.0127,");
    assert_ne!(broken, app.text);
    update(&mut app, Msg::FileChanged(broken));
    let le = app.load_error.clone().expect("the reload refused");
    assert!(
        le.message
            .contains("contacts gap 2 (left_bottom): must be ≥ 0"),
        "{}",
        le.message
    );
    assert!(
        le.detail.starts_with("contacts gap 2 (left_bottom)"),
        "{}",
        le.detail
    );
    assert!(
        app.status.contains("contacts gap 2 (left_bottom)"),
        "{}",
        app.status
    );
    let s = screen(&render(&mut app, 120, 40));
    assert!(
        s.contains("contacts gap 2 (left_bottom): must be ≥ 0"),
        "{s}"
    );
    assert!(!s.contains("gaps.1"), "{s}");
    // the command line's --set keeps the engine's paths, numbered from 0
    let e = deckspin::model::load_str(
        &read(&root().join("models/four-span.toml")),
        Path::new("four-span.toml"),
        &["contacts.gaps.0=-0.01".to_string()],
    )
    .unwrap_err();
    assert!(
        e.to_string().contains("contacts.gaps.0: must be ≥ 0"),
        "{e}"
    );
}
