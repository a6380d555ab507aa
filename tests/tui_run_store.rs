//! The run list on disk, kept tidy: a run stored once per model text (reused at the start,
//! replaced by `r`), runs deleted with a question that names them, a model opened without
//! running (`--no-run`), run numbers per model after `O`, only the metadata read at the start
//! (the series when shown or overlaid), a failure's whole reason one key away.

#![cfg(feature = "workbench")]

mod common;

use common::root;
use common::tui::*;

use crossterm::event::KeyCode;
use deckspin::tui::app::{Confirm, Mode, View};
use deckspin::tui::keymap::Action;
use deckspin::tui::runs::data::{RunData, RunStatus};
use deckspin::tui::runs::list::{self as run_list, Ended, Entry, Series};
use deckspin::tui::{self, App, Effect, Msg, Options, runs::store as run_store, update};
use std::path::{Path, PathBuf};

/// A scratch folder with models/four-span.toml (the short bridge, 4 mm gaps) and
/// excitations/; the model's path.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("deckspin-store-{}-{name}", std::process::id()));
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

fn cleanup(model: &Path) {
    let _ = std::fs::remove_dir_all(model.parent().unwrap().parent().unwrap());
}

fn runs_dir(model: &Path) -> PathBuf {
    run_store::runs_dir(model)
}

/// The files of the store, sorted.
fn files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|r| {
            r.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

fn start_ids(fx: &[Effect]) -> Vec<u64> {
    fx.iter()
        .filter_map(|e| match e {
            Effect::StartRun { id, .. } => Some(*id),
            _ => None,
        })
        .collect()
}

/// The runs whose series `fx` asks for.
fn series_asked(fx: &[Effect]) -> Vec<u64> {
    fx.iter()
        .flat_map(|e| match e {
            Effect::LoadSeries { runs, .. } => runs.iter().map(|r| r.0).collect(),
            _ => Vec::new(),
        })
        .collect()
}

fn run(app: &mut App, fx: Vec<Effect>) {
    tui::execute_blocking(app, fx);
    let cur = app.current.as_ref().expect("a run");
    assert_eq!(cur.status, RunStatus::Finished, "{}", app.status);
}

fn numbers(app: &App) -> Vec<u64> {
    app.runs.list.iter().map(|e| e.number).collect()
}

/// A gap edited in the draft (as the form does).
fn edit_draft(app: &mut App, gap: &str) {
    app.draft = set(&app.draft, "contacts.gaps.2", gap);
    app.scene = Some(deckspin::tui::form::validate(&app.draft, &app.path).unwrap());
}

// ---------------------------------------------------------------------------------------------
// a run stored once

#[test]
fn the_start_reuses_the_run_of_the_same_model_text_and_stores_nothing_new() {
    let model = scratch("reuse");
    let dir = runs_dir(&model);
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    let fx = app.start();
    assert_eq!(start_ids(&fx), [1]);
    run(&mut app, fx);
    let stored = files(&dir);
    assert_eq!(stored, ["0001.csv", "0001.json", "0001.toml"]);
    let want_t = app.runs.get(1).unwrap().data.t.clone();
    // a second start on the same file: #1 shown, nothing run, nothing written
    let mut again = App::new_from_path(&model, Options::default()).unwrap();
    let fx = again.start();
    assert!(start_ids(&fx).is_empty(), "{fx:?}");
    assert_eq!(
        series_asked(&fx),
        [1],
        "the shown run's series, and only it"
    );
    assert!(
        again.status.contains("#1 reused: same model text"),
        "{}",
        again.status
    );
    tui::execute_blocking(&mut again, fx);
    let cur = again.current.as_ref().unwrap();
    assert_eq!((cur.id, cur.label.as_str()), (1, "#1"));
    assert_eq!(cur.t, want_t, "the kept series on the charts");
    assert_eq!(again.runs.get(1).unwrap().series, Series::InMemory);
    assert_eq!(files(&dir), stored);
    assert_eq!(again.next_run, 2);
    // drawn without a run going
    let s = screen(&render(&mut again, 80, 24));
    assert!(s.contains("deck.theta"), "{s}");
    // `r` on the unchanged model runs, as #1, and replaces it: still one run, three files
    let fx = act(&mut again, Action::Rerun);
    assert_eq!(start_ids(&fx), [1]);
    assert!(
        again
            .status
            .contains("it replaces the kept #1 when it ends"),
        "{}",
        again.status
    );
    run(&mut again, fx);
    assert_eq!(numbers(&again), [1]);
    assert_eq!(again.runs.baseline, Some(1));
    assert_eq!(files(&dir), stored);
    assert_eq!(again.next_run, 2);
    // an edited draft is another text: #2
    edit_draft(&mut again, "0.006");
    let fx = act(&mut again, Action::Rerun);
    assert_eq!(start_ids(&fx), [2]);
    run(&mut again, fx);
    assert_eq!(numbers(&again), [1, 2]);
    cleanup(&model);
}

#[test]
fn a_cancelled_rerun_does_not_replace_the_run_of_the_same_text() {
    let model = scratch("cancel");
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    let fx = app.start();
    run(&mut app, fx);
    let before = app.runs.get(1).unwrap().results.clone();
    let fx = act(&mut app, Action::Rerun);
    let msgs = messages_of_started_run(fx);
    let n = msgs.len();
    for m in msgs.into_iter().take(n / 2) {
        update(&mut app, m);
    }
    assert!(app.running());
    let token = app.current.as_ref().unwrap().token;
    update(&mut app, code(KeyCode::Esc));
    update(
        &mut app,
        Msg::RunDone {
            run: token,
            outcome: deckspin::tui::msg::RunOutcome::Cancelled { t: 0.5 },
        },
    );
    assert!(app.status.contains("the kept #1 stays"), "{}", app.status);
    assert_eq!(app.runs.get(1).unwrap().ended, Ended::Finished);
    assert_eq!(app.runs.get(1).unwrap().results, before);
    cleanup(&model);
}

// ---------------------------------------------------------------------------------------------
// delete

#[test]
fn a_run_is_deleted_after_a_question_that_names_it_and_its_files_go() {
    let model = scratch("delete");
    let dir = runs_dir(&model);
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    let fx = app.start();
    run(&mut app, fx);
    for gap in ["0.006", "0.005"] {
        edit_draft(&mut app, gap);
        let fx = act(&mut app, Action::Rerun);
        run(&mut app, fx);
    }
    assert_eq!(numbers(&app), [1, 2, 3]);
    update(&mut app, key('#'));
    app.runs.selected = 1;
    update(&mut app, key('d'));
    assert_eq!(app.mode, Mode::Confirm(Confirm::DeleteRun { number: 2 }));
    let name = app.runs.get(2).unwrap().name.clone();
    assert_eq!(
        app.status,
        format!("delete #2 ({name}, done) and its files? (y/n)")
    );
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("Delete run #2"), "{s}");
    // no: kept
    update(&mut app, key('n'));
    assert_eq!(numbers(&app), [1, 2, 3]);
    assert_eq!(files(&dir).len(), 9);
    // yes: gone, files and all; the others keep their numbers
    update(&mut app, key('d'));
    let fx = update(&mut app, key('y'));
    tui::execute_blocking(&mut app, fx);
    assert_eq!(numbers(&app), [1, 3]);
    assert!(app.status.starts_with("#2 deleted"), "{}", app.status);
    assert_eq!(
        files(&dir),
        [
            "0001.csv",
            "0001.json",
            "0001.toml",
            "0003.csv",
            "0003.json",
            "0003.toml"
        ]
    );
    // the baseline: the question says so; after it there is none
    app.runs.selected = 0;
    update(&mut app, key('d'));
    assert!(app.status.contains("the baseline"), "{}", app.status);
    let fx = update(&mut app, code(KeyCode::Enter));
    assert!(fx.is_empty(), "Enter answers nothing");
    let fx = update(&mut app, key('y'));
    tui::execute_blocking(&mut app, fx);
    assert_eq!(app.runs.baseline, None);
    assert_eq!(numbers(&app), [3]);
    // a later session: the list as left, the next run after the highest kept
    let again = App::new_from_path(&model, Options::default()).unwrap();
    assert_eq!(numbers(&again), [3]);
    assert_eq!(again.runs.baseline, None);
    assert_eq!(again.next_run, 4);
    cleanup(&model);
}

#[test]
fn a_deletion_cut_short_is_finished_at_the_next_opening() {
    let model = scratch("cut");
    let dir = runs_dir(&model);
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    let fx = app.start();
    run(&mut app, fx);
    // as if the workbench died after renaming the metadata away
    std::fs::rename(dir.join("0001.json"), dir.join(".0001.json.deleting")).unwrap();
    let again = App::new_from_path(&model, Options::default()).unwrap();
    assert!(again.runs.list.is_empty());
    assert!(!again.status.contains("skipped"), "{}", again.status);
    assert!(files(&dir).is_empty(), "{:?}", files(&dir));
    cleanup(&model);
}

// ---------------------------------------------------------------------------------------------
// open without running; numbers per model

#[test]
fn no_run_opens_the_model_without_a_worker() {
    let model = scratch("norun");
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    let fx = app.start_with(false);
    assert!(fx.is_empty(), "{fx:?}");
    assert!(app.current.is_none());
    assert_eq!(app.status, "four-span.toml not run (--no-run): r runs it");
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("not run (--no-run)"), "{s}");
    // r runs it: #1
    let fx = act(&mut app, Action::Rerun);
    assert_eq!(start_ids(&fx), [1]);
    run(&mut app, fx);
    // with a kept run of the same text: shown, still no worker
    let mut again = App::new_from_path(&model, Options::default()).unwrap();
    let fx = again.start_with(false);
    assert!(start_ids(&fx).is_empty());
    assert_eq!(series_asked(&fx), [1]);
    assert!(
        again
            .status
            .starts_with("#1 shown: same model text, not run")
    );
    cleanup(&model);
}

#[test]
fn another_model_opened_numbers_its_runs_from_its_own_store() {
    let model = scratch("numbers");
    let other = model.with_file_name("other.toml");
    std::fs::write(&other, short_bridge("0.006")).unwrap();
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    let fx = app.start();
    run(&mut app, fx);
    edit_draft(&mut app, "0.006");
    let fx = act(&mut app, Action::Rerun);
    run(&mut app, fx);
    assert_eq!(numbers(&app), [1, 2]);
    // O: the other model has no runs: its first is #1 (its worker's token goes on: 3)
    app.draft = app.text.clone();
    let fx = app.open_model(&other, &read(&other));
    assert_eq!(start_ids(&fx), [3]);
    assert_eq!(app.current.as_ref().unwrap().id, 1);
    assert!(app.status.contains("opened other.toml"), "{}", app.status);
    run(&mut app, fx);
    assert_eq!(numbers(&app), [1]);
    assert_eq!(
        files(&runs_dir(&other)),
        ["0001.csv", "0001.json", "0001.toml"]
    );
    // back: the first model's runs, #1 (as saved) reused, the next number 3
    let fx = app.open_model(&model, &read(&model));
    assert!(start_ids(&fx).is_empty(), "{fx:?}");
    assert_eq!(numbers(&app), [1, 2]);
    assert_eq!(app.current.as_ref().unwrap().id, 1);
    assert_eq!(app.next_run, 3);
    cleanup(&model);
}

// ---------------------------------------------------------------------------------------------
// only the metadata at the start

/// `n` runs stored in `dir`, each of its own model text (a comment line), #1 the baseline.
fn store_runs(dir: &Path, template: &RunData, text: &str, n: u64) {
    let jobs: Vec<run_store::Job> = (1..=n)
        .map(|k| {
            let mut r = template.clone();
            r.id = k;
            let mut e = Entry::of_run(&r, format!("{text}# stored run {k}\n"));
            e.name = format!("stored {k}");
            run_store::Job {
                entry: Box::new(e),
                baseline: k == 1,
                full: true,
            }
        })
        .collect();
    run_store::store(dir, &jobs, &[]).unwrap();
}

#[test]
fn with_50_stored_runs_the_start_reads_only_their_metadata() {
    let model = scratch("lazy");
    let dir = runs_dir(&model);
    let text = read(&model);
    let template = run_of(&text, &model, 1);
    store_runs(&dir, &template, &text, 50);
    let meta_bytes = || -> usize {
        (1..=50)
            .flat_map(|k| ["json", "toml"].map(|x| dir.join(format!("{k:04}.{x}"))))
            .map(|p| std::fs::metadata(p).unwrap().len() as usize)
            .sum()
    };
    let before = meta_bytes();
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    assert_eq!(app.runs.list.len(), 50);
    assert_eq!(app.runs_read.files, 100, "50 metadata and 50 model files");
    assert_eq!(app.runs_read.bytes, before, "and not one series file");
    assert!(
        app.runs.list.iter().all(|e| e.series == Series::OnDisk),
        "every series on disk"
    );
    // these runs were stored without their diff against the baseline: computed once here
    // (the baseline's own, empty, too)
    assert_eq!(app.runs_rediffed, (1..=50).collect::<Vec<u64>>());
    // the model's own text is none of theirs: it runs (#51); the baseline's series is asked,
    // and the diffs are stored with their runs
    let fx = app.start();
    assert_eq!(start_ids(&fx), [51]);
    assert_eq!(
        series_asked(&fx),
        [1],
        "the baseline, overlaid, and only it"
    );
    let stored: Vec<u64> = fx
        .iter()
        .flat_map(|e| match e {
            Effect::StoreRuns { jobs, remove, .. } => {
                assert!(remove.is_empty() && jobs.iter().all(|j| !j.full));
                jobs.iter().map(|j| j.entry.number).collect()
            }
            _ => Vec::new(),
        })
        .collect();
    assert_eq!(stored, (1..=50).collect::<Vec<u64>>());
    let rest: Vec<Effect> = (fx.into_iter())
        .filter(|e| !matches!(e, Effect::StartRun { .. }))
        .collect();
    tui::execute_blocking(&mut app, rest);
    let base = app.runs.get(1).unwrap();
    assert_eq!(base.series, Series::InMemory);
    assert_eq!(base.data.t, Entry::of_run(&template, String::new()).data.t);
    // overlaying another asks for its series alone
    app.view = View::Runs;
    app.runs.selected = 9;
    let fx = update(&mut app, key(' '));
    assert_eq!(series_asked(&fx), [10]);
    let on_disk = (app.runs.list.iter()).filter(|e| e.series == Series::OnDisk);
    assert_eq!(on_disk.count(), 48);
    // the next opening diffs none: their diffs came back with their metadata
    let again = App::new_from_path(&model, Options::default()).unwrap();
    assert!(again.runs_rediffed.is_empty(), "{:?}", again.runs_rediffed);
    assert_eq!(again.runs_read.files, 100);
    assert_eq!(again.runs_read.bytes, meta_bytes());
    let two = again.runs.get(2).unwrap();
    assert_eq!(two.changes, [], "a comment: no value changed");
    assert_eq!(
        two.diff_base,
        Some(run_list::text_hash(&again.runs.get(1).unwrap().model))
    );
    cleanup(&model);
}

#[test]
fn a_series_that_does_not_read_is_said_when_it_is_needed() {
    let model = scratch("badseries");
    let dir = runs_dir(&model);
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    let fx = app.start();
    run(&mut app, fx);
    std::fs::write(dir.join("0001.csv"), "t,q:deck.theta\n0,abc\n").unwrap();
    let mut again = App::new_from_path(&model, Options::default()).unwrap();
    let fx = again.start();
    tui::execute_blocking(&mut again, fx);
    assert!(
        again
            .status
            .contains("#1: 0001.csv: line 2: `abc` is not a number"),
        "{}",
        again.status
    );
    assert!(matches!(
        again.runs.get(1).unwrap().series,
        Series::Unreadable(_)
    ));
    let _ = screen(&render(&mut again, 80, 24));
    cleanup(&model);
}

// ---------------------------------------------------------------------------------------------
// the whole reason of a failure

const REASON: &str = "t = 1.234567890 s: Painlevé configuration at contact(s) left_top, \
right_bottom: the normal contact matrix has a negative diagonal entry at the second corner \
after the shear key of abutment 2 failed and the deck slid along its face while rotating, \
so the acceleration LCP of eq. 8-10 has no solution or several (the contact LCP has no or \
several solutions)";

/// The text inside the popup's frame, its rows joined (the label column dropped).
fn popup_text(s: &str) -> String {
    let mut words = Vec::new();
    for l in s.lines().skip(2) {
        let inner: Vec<char> = l.chars().collect();
        if inner.len() < 3 || inner[0] != '│' {
            continue;
        }
        let body: String = inner[1..inner.len() - 1].iter().skip(14).collect();
        words.push(body.trim().to_string());
    }
    words.join(" ")
}

#[test]
fn the_whole_failure_reason_is_one_key_away_wrapped_at_80x24() {
    let path = root().join("models/four-span.toml");
    let text = short_bridge("0.004");
    let mut app = App::new_from_text(&text, &path);
    let mut r = RunData::new(
        1,
        "#1".into(),
        vec!["deck.theta".into()],
        vec![],
        vec![],
        2.0,
    );
    r.t_sim = 1.2345;
    r.status = RunStatus::Finished;
    let mut e = Entry::of_run(&r, text.clone());
    e.ended = Ended::Failed(REASON.into());
    app.runs.add(e, &text);
    let mut cur = app.runs.get(1).unwrap().data.clone();
    cur.status = RunStatus::Cancelled;
    app.current = Some(cur);
    // the run list: a short reason
    app.view = View::Runs;
    let s = screen(&render(&mut app, 80, 24));
    let row = s.lines().find(|l| l.starts_with("│  #1 ")).expect(&s);
    assert!(row.contains("failed: Painlevé"), "{s}");
    // i: the whole reason, wrapped
    update(&mut app, key('i'));
    assert!(matches!(app.mode, Mode::RunInfo(_)));
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("#1 as saved — run info"), "{s}");
    let inside = popup_text(&s);
    assert!(inside.contains(REASON), "{inside}\n{s}");
    assert!(s.contains("t = 1.2345 s of 2 s (62 %)"), "{s}");
    assert!(s.contains("event-driven") || s.contains("(event)"), "{s}");
    assert!(s.contains("adaptive (DP5): rtol 1e-4"), "{s}");
    // every line within the screen, the frame whole
    assert!(s.lines().all(|l| l.chars().count() == 80));
    // Esc closes; from the charts the shown run's info is the same key
    update(&mut app, code(KeyCode::Esc));
    assert_eq!(app.mode, Mode::Normal);
    app.view = View::Charts;
    update(&mut app, key('i'));
    let Mode::RunInfo(info) = &app.mode else {
        panic!("{:?}", app.mode)
    };
    assert_eq!(info.number, 1);
    // a longer reason on a short screen scrolls: the last line reachable
    update(&mut app, key('i'));
    app.runs.get_mut(1).unwrap().ended = Ended::Failed(format!("{REASON} {REASON}"));
    update(&mut app, key('i'));
    let s = screen(&render(&mut app, 80, 18));
    assert!(s.contains("lines 1–13 of 19"), "{s}");
    assert!(!s.contains("│events        0"), "{s}");
    update(&mut app, code(KeyCode::End));
    let s = screen(&render(&mut app, 80, 18));
    assert!(s.contains("lines 7–19 of 19"), "{s}");
    assert!(s.contains("│events        0"), "{s}");
    assert!(!s.contains("│status"), "{s}");
}

/// As the workbench starts: the terminal's size first (its message asks for the baseline's
/// series), then the start showing the kept run of the same text; the effects of both done,
/// the kept run's series are on the charts (they were asked for once and the answer dropped).
#[test]
fn a_kept_run_reused_after_the_first_resize_is_drawn() {
    let model = scratch("resize-first");
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    let fx = app.start();
    run(&mut app, fx);
    let want = app.runs.get(1).unwrap().data.t.len();
    let mut again = App::new_from_path(&model, Options::default()).unwrap();
    let mut fx = update(&mut again, Msg::Resize(120, 40));
    fx.extend(again.start());
    assert!(start_ids(&fx).is_empty(), "{fx:?}");
    tui::execute_blocking(&mut again, fx);
    assert_eq!(again.current.as_ref().unwrap().t.len(), want);
    let s = screen(&render(&mut again, 120, 40));
    assert!(s.contains("deck.theta ["), "{s}");
}

/// A kept run's series file has the layout and column names of the engine's `history.csv`
/// (one writer and reader, `output::series`): every column of it is a column of the CLI's
/// history.csv for the same model, its time column holds the same instants, and each value is
/// the f32 of the engine's; a file of the workbench's first layout (`q:`, `gap:`, `def:`,
/// `force:`) still reads, to the same run.
#[test]
fn a_kept_runs_series_is_history_csvs_layout() {
    let model = scratch("layout");
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    let fx = app.start();
    run(&mut app, fx);
    let dir = runs_dir(&model);
    let kept = std::fs::read_to_string(dir.join("0001.csv")).unwrap();
    // the CLI's history.csv of the same model
    let out = model.parent().unwrap().join("cli-out");
    let r = std::process::Command::new(env!("CARGO_BIN_EXE_deckspin"))
        .args([
            "run",
            &model.display().to_string(),
            "--out",
            &out.display().to_string(),
        ])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let history = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let head: Vec<&str> = history.lines().next().unwrap().split(',').collect();
    let cols = deckspin::output::series::read_columns(&kept).unwrap();
    assert!(cols.len() > 10, "{}", cols.len());
    let rows: Vec<Vec<&str>> = history
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    let mut checked = 0;
    for (name, values) in &cols {
        let j = (head.iter().position(|h| h == name))
            .unwrap_or_else(|| panic!("{name} is no column of history.csv"));
        // each kept sample is one of history.csv's, its value the f32 of the engine's
        let mut k = 0;
        for (i, v) in values.iter().enumerate() {
            let t = cols[0].1[i];
            while rows[k][0].parse::<f64>().unwrap() < t {
                k += 1;
            }
            // (an event's instant has its samples before and after the event)
            let same: Vec<f64> = (rows[k..].iter())
                .take_while(|r| r[0].parse::<f64>().unwrap() == t)
                .map(|r| r[j].parse().unwrap())
                .collect();
            assert!(!same.is_empty(), "t = {t} is no sample of history.csv");
            if name == "t" {
                assert_eq!(*v, same[0], "t");
            } else {
                assert!(
                    same.iter().any(|&e| *v as f32 == e as f32),
                    "{name} at t = {t}: {v} is none of {same:?}"
                );
            }
            checked += 1;
        }
    }
    assert!(checked > 1000, "{checked}");
    // the first layout, written by hand from the kept file: the same run reads back
    let mut lines = kept.lines();
    let names: Vec<String> = (lines.next().unwrap().split(','))
        .map(|h| {
            if let Some(c) = h.strip_suffix(".gap") {
                format!("gap:{c}")
            } else if let Some(e) = h.strip_suffix(".deformation") {
                format!("def:{e}")
            } else if let Some(e) = h.strip_suffix(".force") {
                format!("force:{e}")
            } else if h == "t" {
                h.to_string()
            } else {
                format!("q:{h}")
            }
        })
        .collect();
    let old = std::iter::once(names.join(",")).chain(lines.map(str::to_string));
    let old: String = old.map(|l| l + "\n").collect();
    let t_end = app.runs.get(1).unwrap().data.t_end;
    let now = run_store::load_series(&dir, 1, t_end).unwrap();
    std::fs::write(dir.join("0001.csv"), old).unwrap();
    let then = run_store::load_series(&dir, 1, t_end).unwrap();
    assert_eq!(
        (then.t.len(), then.q.len(), then.gap.len()),
        (now.t.len(), now.q.len(), now.gap.len())
    );
    assert_eq!(
        (&then.dof_names, &then.contact_names, &then.element_names),
        (&now.dof_names, &now.contact_names, &now.element_names)
    );
    assert_eq!((&then.q, &then.gap, &then.el), (&now.q, &now.gap, &now.el));
    cleanup(&model);
}
