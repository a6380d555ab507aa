//! The studies view's numbers: the table of a study's points beside its chart holds the
//! numbers of its CSV, the cursor (`[`, `]`) reads them; Fig. 7's marks mean the same as in the
//! CLI's chart; every study's name is on screen at 80 columns; study tables and exports go to
//! the model's output folder, the older `<stem>.studies/` still read.

#![cfg(feature = "workbench")]

mod common;

use common::tui::*;

use crossterm::event::KeyCode;
use deckspin::figures::{FIG7_WITH_CONTACT, FIG7_WITHOUT_CONTACT};
use deckspin::progress::Unwatched;
use deckspin::studies::{Study, rotation_vs_pga};
use deckspin::study_csv::to_csv;
use deckspin::study_table::{RunTable, StudyKind, StudyTable};
use deckspin::tui::app::{Mode, View};
use deckspin::tui::chart::fmt_sig;
use deckspin::tui::keymap::Action;
use deckspin::tui::msg::StudyOutcome;
use deckspin::tui::studies::points::{cell, points};
use deckspin::tui::{self, App, Effect, Msg, update};
use ratatui::style::Modifier;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The short bridge (2 s, 4 mm gaps) with its first three `[[run]]` tables.
fn three_runs() -> String {
    let text = short_bridge("0.004");
    let mut doc: toml_edit::DocumentMut = text.parse().unwrap();
    doc["run"].as_array_of_tables_mut().unwrap().retain({
        let mut k = 0;
        move |_| {
            k += 1;
            k <= 3
        }
    });
    doc["excitation"]["run"] = toml_edit::value(1);
    doc.to_string()
}

/// One Fig. 7 row: run, PGA x and y, without and with contact.
type PgaRow = (
    usize,
    f64,
    f64,
    deckspin::studies::Row,
    deckspin::studies::Row,
);

/// The CLI's Fig. 7 rows of the three runs (`deckspin study pga` computes these), once.
fn cli_rows() -> &'static Vec<PgaRow> {
    static R: OnceLock<Vec<PgaRow>> = OnceLock::new();
    R.get_or_init(|| {
        let study = Study::from_text(&three_runs(), &bridge_path(), &[]).unwrap();
        rotation_vs_pga(&study, &Unwatched)
    })
}

/// The same rows as the workbench's table (as `run_study` fills it).
fn pga_table() -> StudyTable {
    let mut t = RunTable::pga_plan(&three_runs());
    for (k, (_, _, _, without, with)) in cli_rows().iter().enumerate() {
        assert!(t.record(2 * k, without) && t.record(2 * k + 1, with));
    }
    StudyTable::Runs(t)
}

/// The workbench in the studies view with the PGA study of [`pga_table`] finished and its CSV
/// said to be `models/four-span.out/pga-1.csv` (nothing written).
fn pga_app() -> App {
    let mut app = App::new_from_text(&three_runs(), Path::new("models/four-span.toml"));
    app.view = View::Studies;
    app.studies.selected = 0;
    assert_eq!(app.studies.kind(), StudyKind::Pga);
    let fx = act(&mut app, Action::StudyRun);
    let Some(Effect::StartStudy { id, .. }) = fx.first() else {
        panic!("{fx:?} {}", app.status)
    };
    let id = *id;
    let outcome = StudyOutcome::Finished(Box::new(pga_table()));
    let fx = update(&mut app, Msg::StudyDone { id, outcome });
    let Some(Effect::WriteStudy { dirs, .. }) = fx.first() else {
        panic!("{fx:?}")
    };
    assert_eq!(dirs[0], PathBuf::from("models/four-span.out"));
    let result = Ok(PathBuf::from("models/four-span.out/pga-1.csv"));
    update(&mut app, Msg::StudyWritten { id, result });
    app
}

/// The CSV's peak |θ| of run `run` without (false) or with (true) contact.
fn csv_peak(csv: &str, run: usize, contact: bool) -> f64 {
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let line = lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .find(|f| f[col("run")] == run.to_string() && f[col("contact")] == contact.to_string())
        .unwrap_or_else(|| panic!("run {run} contact {contact} not in\n{csv}"));
    line[col("peak_rotation")].parse().unwrap()
}

/// The screen line holding the table row of `label` (`>3 ` at the cursor, ` 3 ` elsewhere),
/// not the readout (which gives units).
fn table_line<'a>(s: &'a [String], label: &str) -> &'a String {
    s.iter()
        .find(|l| l.contains(label) && !l.contains(" rad"))
        .unwrap_or_else(|| panic!("{label:?} not in\n{}", s.join("\n")))
}

#[test]
fn the_study_table_holds_the_numbers_of_its_csv_and_the_cursor_reads_them() {
    let mut app = pga_app();
    let table = app.studies.entry(StudyKind::Pga).unwrap().table.clone();
    let csv = to_csv(table.as_ref().unwrap());
    let p = points(table.as_ref().unwrap()).expect("a table of points");
    assert_eq!(p.rows.len(), 3);
    for (k, r) in p.rows.iter().enumerate() {
        assert_eq!(r.label, (k + 1).to_string());
        for (c, contact) in [false, true].into_iter().enumerate() {
            let want = csv_peak(&csv, k + 1, contact);
            assert_eq!(
                r.values[c].to_bits(),
                want.to_bits(),
                "run {} {contact}",
                k + 1
            );
            assert!(want > 0.0);
        }
    }
    assert_eq!(
        p.rows.iter().map(|r| r.x).collect::<Vec<_>>(),
        vec![0.09, 0.25, 0.4]
    );
    // on screen at 80×24: each row with its numbers, the first at the cursor, highlighted
    let t = render(&mut app, 80, 24);
    let s = lines(&t);
    assert!(
        s.iter()
            .any(|l| l.contains("o no contact") && l.contains("# contact"))
    );
    for (k, r) in p.rows.iter().enumerate() {
        let mark = if k == 0 { '>' } else { ' ' };
        let line = table_line(&s, &format!("{mark}{} ", k + 1));
        for v in &r.values {
            assert!(line.contains(&cell(*v)), "{} in {line}", cell(*v));
        }
    }
    let y = s.iter().position(|l| l.contains(">1 ")).unwrap() as u16;
    let x = s[y as usize].chars().position(|c| c == '>').unwrap() as u16;
    let buf = t.backend().buffer();
    assert!(buf[(x, y)].modifier.contains(Modifier::REVERSED));
    assert!(!buf[(x, y + 1)].modifier.contains(Modifier::REVERSED));
    // `]` twice: run 3, its values in the readout
    update(&mut app, key(']'));
    update(&mut app, key(']'));
    assert_eq!(app.studies.cursor(), 2);
    let s = lines(&render(&mut app, 80, 24));
    let r = &p.rows[2];
    let readout = s
        .iter()
        .find(|l| l.contains("run 3 (3/3) · PGA x"))
        .unwrap_or_else(|| panic!("{}", s.join("\n")));
    for want in [
        "PGA x 0.4 g".to_string(),
        format!("o no contact {} rad", fmt_sig(r.values[0], 4)),
        format!("# contact {} rad", fmt_sig(r.values[1], 4)),
    ] {
        assert!(readout.contains(&want), "{want} not in {readout}");
    }
    table_line(&s, ">3 ");
    // held at the ends
    update(&mut app, key(']'));
    assert_eq!(app.studies.cursor(), 2);
    for _ in 0..5 {
        update(&mut app, key('['));
    }
    assert_eq!(app.studies.cursor(), 0);
    let s = lines(&render(&mut app, 80, 24));
    assert!(
        s.iter().any(|l| l.contains("run 1 (1/3) · PGA x 0.09 g")),
        "{}",
        s.join("\n")
    );
    // the screening has no points: said so, nothing moves
    app.studies.selected = StudyKind::ALL
        .iter()
        .position(|k| *k == StudyKind::Screen)
        .unwrap();
    update(&mut app, key(']'));
    assert_eq!(app.status, "the screening has no points to step through");
}

#[test]
fn fig7s_marks_mean_the_same_in_the_cli_and_the_workbench() {
    assert_eq!((FIG7_WITHOUT_CONTACT, FIG7_WITH_CONTACT), ('o', '#'));
    // the CLI's chart (`deckspin study pga`: its SVG and, on a terminal, this text)
    let chart = deckspin::figures::rotation_vs_pga(cli_rows());
    let text = deckspin::plot::text::render(&chart, 80, 24);
    assert!(text.contains("  o without contact"), "{text}");
    assert!(text.contains("  # with contact"), "{text}");
    let grid: String = text.lines().skip(2).take(12).collect();
    assert!(grid.contains('o') && grid.contains('#'), "{text}");
    // the workbench's chart of the same rows: the same legend, the same marks on its points
    let mut app = pga_app();
    let s = lines(&render(&mut app, 80, 24));
    // the legend under the y title, on two lines beside the table
    let y = s.iter().position(|l| l.contains("peak |θ| [rad]")).unwrap();
    let legend = format!("{}\n{}", &s[y][..s[y].find(" run ").unwrap()], s[y + 1]);
    assert!(
        legend.contains("o without contact") && legend.contains("# with contact"),
        "{legend}"
    );
    // the chart's columns (left of the table): both marks drawn
    let chart_cells: String = (s.iter().skip(6).take(12))
        .map(|l| l.chars().take(40).collect::<String>())
        .collect();
    assert!(
        chart_cells.contains('o') && chart_cells.contains('#'),
        "{}",
        s.join("\n")
    );
    // and the table's headings
    assert!(
        s.iter()
            .any(|l| l.contains("o no contact") && l.contains("# contact"))
    );
}

#[test]
fn every_study_and_page_name_is_on_screen_at_80_columns() {
    let names = [
        "PGA (Fig. 7)",
        "μ (Fig. 8)",
        "screen",
        "suite",
        "work-precision",
        "adequacy",
        "sensitivity",
        "energy",
        "contacts",
        "modes",
        "records",
    ];
    for (w, h) in [(80, 24), (100, 30)] {
        let mut app = pga_app();
        for sel in 0..StudyKind::ALL.len() {
            app.studies.selected = sel;
            let s = lines(&render(&mut app, w, h));
            let top = s[1..3].join("\n");
            for n in names {
                assert!(top.contains(n), "{n} at {w}x{h}, {sel}:\n{}", s.join("\n"));
            }
            // the selected one with its state
            let want = match sel {
                0 => ">PGA (Fig. 7): done".to_string(),
                k => format!(">{}: not run", names[k]),
            };
            assert!(top.contains(&want), "{want}\n{top}");
        }
    }
}

#[test]
fn study_tables_go_to_the_output_folder_and_the_older_folder_is_still_read() {
    let d = std::env::temp_dir().join(format!("deckspin-tui-studies-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(d.join("models")).unwrap();
    let model = d.join("models/four-span.toml");
    std::fs::write(&model, three_runs()).unwrap();
    let mut app = App::new_from_text(&read(&model), &model);
    app.view = View::Studies;
    // an older study table and an export, beside the one the study writes
    let old = d.join("models/four-span.studies");
    std::fs::create_dir_all(&old).unwrap();
    std::fs::write(old.join("pga-1.csv"), to_csv(&pga_table())).unwrap();
    let out = d.join("models/four-span.out");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("export-1-chart.csv"), "t\n0\n").unwrap();
    std::fs::write(out.join("pga-1.csv"), "mine\n").unwrap();
    let fx = vec![Effect::WriteStudy {
        id: 0,
        dirs: deckspin::tui::runs::out_folder::out_dirs(&model),
        table: Box::new(pga_table()),
    }];
    tui::execute_blocking(&mut app, fx);
    // pga-1.csv was there: pga-2.csv, the first untouched
    assert_eq!(read(&out.join("pga-1.csv")), "mine\n");
    assert_eq!(read(&out.join("pga-2.csv")), to_csv(&pga_table()));
    let fx = update(&mut app, key('f'));
    tui::execute_blocking(&mut app, fx);
    let Mode::Pick { files, .. } = &app.mode else {
        panic!("{:?} {}", app.mode, app.status)
    };
    let mut found: Vec<PathBuf> = files.clone();
    found.sort();
    assert_eq!(
        found,
        vec![
            out.join("pga-1.csv"),
            out.join("pga-2.csv"),
            old.join("pga-1.csv")
        ]
    );
    // the older one opens
    let i = files.iter().position(|f| f.starts_with(&old)).unwrap();
    if let Mode::Pick { selected, .. } = &mut app.mode {
        *selected = i;
    }
    let fx = update(&mut app, code(KeyCode::Enter));
    tui::execute_blocking(&mut app, fx);
    assert!(
        app.status
            .starts_with(&format!("opened {}", old.join("pga-1.csv").display())),
        "{}",
        app.status
    );
    assert_eq!(
        app.studies.entry(StudyKind::Pga).unwrap().table,
        Some(pga_table())
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn snapshot_studies_pga_table_80x24() {
    let mut app = pga_app();
    update(&mut app, key(']'));
    let t = render(&mut app, 80, 24);
    snapshot_settings().bind(|| insta::assert_snapshot!("studies_pga_table_80x24", t.backend()));
}

// ---------------------------------------------------------------------------------------------
// the design studies: the model ladder and the swings of the uncertain inputs

use deckspin::design::adequacy::Adequacy;
use deckspin::design::swings::Sensitivity;
use deckspin::tui::studies::{Phase, StudySpec};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

/// The workbench on the specimen bridge with its runs cut to 3 s through the form (typed
/// into `solver.t_end`, not saved: its ladder and its swings take a second or two), in the
/// studies view on `kind`.
fn design_app(kind: StudyKind) -> App {
    let mut app = App::new_from_text(&read(&bridge_path()), Path::new("models/four-span.toml"));
    app.view = View::Form;
    let i = app.form.index_of("solver.t_end").expect("the t_end field");
    app.form.select(i);
    update(&mut app, code(KeyCode::Enter));
    let ctrl_u = crossterm::event::KeyEvent::new(
        KeyCode::Char('u'),
        crossterm::event::KeyModifiers::CONTROL,
    );
    update(&mut app, Msg::Key(ctrl_u));
    for c in "3".chars() {
        update(&mut app, key(c));
    }
    update(&mut app, code(KeyCode::Enter));
    assert!(
        app.draft.contains("t_end = 3.0") && app.dirty(),
        "{}",
        app.status
    );
    app.view = View::Studies;
    app.studies.selected = StudyKind::ALL.iter().position(|k| *k == kind).unwrap();
    app
}

/// `Enter` on the selected study: its id and its worker's spec.
fn start_design(app: &mut App) -> (u64, Box<StudySpec>) {
    match act(app, Action::StudyRun).into_iter().next() {
        Some(Effect::StartStudy { id, spec }) => (id, spec),
        e => panic!("{e:?} {}", app.status),
    }
}

/// The worker's messages of `kind` on the short specimen (run once per kind): its progress
/// counts and its table.
fn design_run(kind: StudyKind) -> &'static (Vec<(usize, usize)>, StudyTable) {
    static L: OnceLock<(Vec<(usize, usize)>, StudyTable)> = OnceLock::new();
    static S: OnceLock<(Vec<(usize, usize)>, StudyTable)> = OnceLock::new();
    let cell = if kind == StudyKind::Adequacy { &L } else { &S };
    cell.get_or_init(|| {
        let mut app = design_app(kind);
        let (id, spec) = start_design(&mut app);
        assert_eq!(spec.text, app.draft, "the form's model, its edit included");
        let mut counts = Vec::new();
        let mut table = None;
        for m in tui::workers::study::run_blocking(id, &spec) {
            match m {
                Msg::StudyProgress { done, all, .. } => counts.push((done, all)),
                Msg::StudyDone {
                    outcome: StudyOutcome::Finished(t),
                    ..
                } => table = Some(*t),
                m => panic!("{m:?}"),
            }
        }
        (counts, table.expect("finished"))
    })
}

fn ladder() -> &'static Adequacy {
    match &design_run(StudyKind::Adequacy).1 {
        StudyTable::Adequacy(a) => a,
        t => panic!("{t:?}"),
    }
}

fn swings() -> &'static Sensitivity {
    match &design_run(StudyKind::Sensitivity).1 {
        StudyTable::Sensitivity(s) => s,
        t => panic!("{t:?}"),
    }
}

/// The ladder with each run's CPU time made its steps × 1 µs: the same on every machine (for
/// the snapshot).
fn steady(a: &Adequacy) -> Adequacy {
    let mut a = a.clone();
    for o in std::iter::once(&mut a.full).chain(&mut a.variants) {
        for r in &mut o.runs {
            r.cpu = 1e-6 * r.steps as f64;
        }
    }
    a
}

/// The workbench with study `kind` ended with `table` (its CSV said written to
/// `models/four-span.out/<kind>-1.csv`).
fn design_done(kind: StudyKind, table: StudyTable) -> App {
    let mut app = design_app(kind);
    let (id, _) = start_design(&mut app);
    let outcome = StudyOutcome::Finished(Box::new(table));
    let fx = update(&mut app, Msg::StudyDone { id, outcome });
    let Some(Effect::WriteStudy { dirs, .. }) = fx.first() else {
        panic!("{fx:?}")
    };
    assert_eq!(dirs[0], PathBuf::from("models/four-span.out"));
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

/// The row of the ladder's variant `name` (0 is the full model).
fn row_of(name: &str) -> usize {
    let v = (ladder().variants.iter())
        .position(|o| o.variant.name == name)
        .unwrap_or_else(|| panic!("no variant {name}"));
    v + 1
}

/// `j`/`k` until the selected study's cursor is on `row`.
fn go_to_row(app: &mut App, row: usize) {
    for _ in 0..40 {
        let c = app.studies.cursor();
        if c == row {
            return;
        }
        update(app, key(if c < row { 'j' } else { 'k' }));
    }
    panic!("row {row} not reached: {}", app.studies.cursor());
}

#[test]
fn the_ladder_runs_in_a_worker_with_its_progress_and_shows_every_variant() {
    let (counts, table) = design_run(StudyKind::Adequacy);
    // its runs counted as they finish, to the last
    assert!(counts.len() > 10, "{counts:?}");
    assert!(
        counts
            .windows(2)
            .all(|w| w[0].0 <= w[1].0 && w[0].1 <= w[1].1)
    );
    assert!(counts.iter().all(|(d, a)| d <= a));
    let last = *counts.last().unwrap();
    assert_eq!(last.0, last.1);
    assert_eq!(table.progress(), (last.1, last.1));
    let a = ladder();
    assert_eq!(a.cases.len(), 7, "the specimen's seven [[run]]s");
    assert_eq!(a.tolerance, 0.05);
    assert!(
        a.variants
            .iter()
            .any(|o| o.variant.name == "rigid-abutments")
    );
    // the progress as it comes: the state line and the header
    let mut app = design_app(StudyKind::Adequacy);
    let (id, _) = start_design(&mut app);
    let (done, all) = counts[counts.len() / 2];
    assert!(update(&mut app, Msg::StudyProgress { id, done, all }).is_empty());
    let e = app.studies.entry(StudyKind::Adequacy).unwrap();
    assert_eq!((e.progress(), &e.phase), ((done, all), &Phase::Running));
    let s = screen(&render(&mut app, 80, 24));
    assert!(
        s.contains(&format!("{done}/{all} runs")) && s.contains("Esc cancels"),
        "{s}"
    );
    let header = s.lines().next().unwrap();
    assert!(header.contains(&format!("adequacy {done}/{all}")), "{s}");
    // the end: its table, every variant on screen at 80 columns by its letter and name, its
    // CSV written to the model's output folder
    let outcome = StudyOutcome::Finished(Box::new(table.clone()));
    let fx = update(&mut app, Msg::StudyDone { id, outcome });
    let [Effect::WriteStudy { dirs, table: t, .. }] = fx.as_slice() else {
        panic!("{fx:?}")
    };
    assert_eq!(dirs[0], PathBuf::from("models/four-span.out"));
    assert_eq!(
        to_csv(t),
        deckspin::design::adequacy_report::variants_csv(a)
    );
    let status = format!("adequacy finished: {} variants on 7 runs", a.variants.len());
    assert!(app.status.starts_with(&status), "{}", app.status);
    let s = lines(&render(&mut app, 80, 24));
    assert!(s.iter().any(|l| l.contains("  full ")), "{}", s.join("\n"));
    assert!(
        s.iter().any(|l| l.contains("cheapest within 5 %:")),
        "{}",
        s.join("\n")
    );
    for (v, o) in a.variants.iter().enumerate() {
        let letter = char::from(b'a' + v as u8);
        let head: String = o.variant.name.chars().take(12).collect();
        let want = format!("{letter} {head}");
        assert!(
            s.iter().any(|l| l.contains(&want)),
            "{want}\n{}",
            s.join("\n")
        );
    }
    // j/k select a row: marked, its errors in every quantity under the table
    go_to_row(&mut app, row_of("frictionless"));
    let s = lines(&render(&mut app, 80, 24));
    let row = s
        .iter()
        .find(|l| l.starts_with(">") && l.contains("frictionless"));
    assert!(row.is_some(), "{}", s.join("\n"));
    let v = row_of("frictionless") - 1;
    let errors = s.join("\n");
    for q in &a.quantities {
        let want = format!(
            "{} {}",
            deckspin::design::adequacy_report::short(q),
            deckspin::design::adequacy_report::percent(a.error(v, q))
        );
        assert!(errors.contains(&want), "{want}\n{errors}");
    }
    // held at the ends
    for _ in 0..20 {
        update(&mut app, key('j'));
    }
    assert_eq!(app.studies.cursor(), a.variants.len());
}

#[test]
fn applying_a_variant_edits_the_form_and_one_undo_takes_it_back() {
    let mut app = design_done(
        StudyKind::Adequacy,
        design_run(StudyKind::Adequacy).1.clone(),
    );
    let original = app.draft.clone();
    // the full model: nothing to apply
    go_to_row(&mut app, 0);
    update(&mut app, key('a'));
    assert_eq!(app.draft, original);
    assert!(
        app.status.starts_with("the full model is the form's model"),
        "{}",
        app.status
    );
    // rigid abutments: its keys changed in the draft, each marked, the form's values edited
    go_to_row(&mut app, row_of("rigid-abutments"));
    update(&mut app, key('a'));
    let keys = ladder().variants[row_of("rigid-abutments") - 1]
        .variant
        .changes
        .len();
    assert!(keys >= 2, "{keys}");
    let want = format!("applied rigid-abutments: {keys} keys changed; u undoes");
    assert!(app.status.starts_with(&want), "{}", app.status);
    assert_ne!(app.draft, original);
    let doc: toml::Table = toml::from_str(&app.draft).unwrap();
    assert_eq!(doc["abutment"]["kind"].as_str(), Some("rigid"));
    assert!(app.draft.contains("kind = \"rigid\""), "{}", app.draft);
    assert!(
        app.draft.contains("# simplified (rigid-abutments)"),
        "{}",
        app.draft
    );
    assert!(app.draft.contains("t_end = 3.0"), "the edit before is kept");
    assert!(app.dirty());
    let kind = app
        .form
        .index_of("abutment.kind")
        .expect("the abutments' kind");
    let f = &app.form.fields[kind];
    assert!(f.edited() && f.value.as_deref() == Some("rigid"), "{f:?}");
    // u in the form: the draft as it was, byte for byte, in one step
    app.view = View::Form;
    update(&mut app, key('u'));
    assert_eq!(app.draft, original);
    assert!(
        app.status.starts_with("undid rigid-abutments"),
        "{}",
        app.status
    );
    // applied again, u in the studies view takes it back too; then there is nothing to undo
    app.view = View::Studies;
    update(&mut app, key('a'));
    assert_ne!(app.draft, original);
    update(&mut app, key('u'));
    assert_eq!(app.draft, original);
    update(&mut app, key('u'));
    assert_eq!(app.draft, original);
    assert!(app.status.starts_with("nothing to undo"), "{}", app.status);
    // an edit after the variant: u no longer takes the variant back (it reverts a field)
    update(&mut app, key('a'));
    let after = app.draft.clone();
    app.draft = set(&after, "contacts.mu", "0.4");
    update(&mut app, key('u'));
    assert!(
        app.status.starts_with("nothing to undo: the form changed"),
        "{}",
        app.status
    );
}

#[test]
fn esc_cancels_the_design_studies() {
    for kind in [StudyKind::Adequacy, StudyKind::Sensitivity] {
        let mut app = design_app(kind);
        let (id, spec) = start_design(&mut app);
        // the worker, its flag raised after a few runs as Esc would
        let cancel = AtomicBool::new(false);
        let sent = Mutex::new(Vec::new());
        let send = |m: Msg| {
            if let Msg::StudyProgress { done, .. } = m
                && done >= 4
            {
                cancel.store(true, Ordering::SeqCst);
            }
            sent.lock().unwrap().push(m);
        };
        let done = tui::workers::study::run(id, &spec, &cancel, &send);
        let sent = sent.into_inner().unwrap();
        let progress: Vec<(usize, usize)> = (sent.iter())
            .filter_map(|m| match m {
                Msg::StudyProgress { done, all, .. } => Some((*done, *all)),
                _ => None,
            })
            .collect();
        assert!(!progress.is_empty(), "{kind:?}: its progress");
        for m in sent {
            update(&mut app, m);
        }
        let fx = update(&mut app, code(KeyCode::Esc));
        assert!(
            matches!(fx.as_slice(), [Effect::CancelStudy { id: i }] if *i == id),
            "{fx:?}"
        );
        let s = screen(&render(&mut app, 80, 24));
        assert!(s.contains("cancelling after"), "{s}");
        let fx = update(&mut app, done);
        let e = app.studies.entry(kind).unwrap();
        assert_eq!(e.phase, Phase::Cancelled, "{kind:?}");
        match kind {
            // the ladder keeps nothing (its errors need every run), writes nothing
            StudyKind::Adequacy => {
                assert!(fx.is_empty() && e.table.is_none(), "{fx:?}");
                assert!(
                    app.status.contains("adequacy cancelled: nothing kept"),
                    "{}",
                    app.status
                );
                let s = screen(&render(&mut app, 80, 24));
                assert!(
                    s.contains(">adequacy: cancelled") && s.contains("nothing kept"),
                    "{s}"
                );
            }
            // the swings keep the runs that finished, their CSV written
            _ => {
                let (done, all) = e.progress();
                assert!(done > 0 && done < all, "{done}/{all}");
                assert!(
                    matches!(fx.as_slice(), [Effect::WriteStudy { .. }]),
                    "{fx:?}"
                );
                let s = screen(&render(&mut app, 80, 24));
                assert!(s.contains(">sensitivity: cancelled"), "{s}");
            }
        }
        // it can run again
        assert!(matches!(
            act(&mut app, Action::StudyRun).as_slice(),
            [Effect::StartStudy { .. }]
        ));
    }
}

#[test]
fn the_swings_run_in_a_worker_and_n_shows_the_next_quantity() {
    let (counts, table) = design_run(StudyKind::Sensitivity);
    let s = swings();
    let last = *counts.last().unwrap();
    assert_eq!(last, (s.rows.len(), s.rows.len()));
    assert_eq!(s.cases(), 7);
    assert!(s.failed().is_empty());
    let mut app = design_done(StudyKind::Sensitivity, table.clone());
    assert!(
        app.status.contains("sensitivity finished"),
        "{}",
        app.status
    );
    // every input, widest swing of the first quantity first, with its tornado bar
    let order = deckspin::tui::studies::design_rows::order(s, 0);
    let sc = lines(&render(&mut app, 80, 24));
    let screen_text = sc.join("\n");
    assert!(screen_text.contains(&s.quantities[0]), "{screen_text}");
    let rows: Vec<usize> = (order.iter())
        .map(|&i| {
            let name = &s.inputs[i].input.name;
            (sc.iter().position(|l| l[1..].starts_with(name.as_str())))
                .unwrap_or_else(|| panic!("{name}\n{screen_text}"))
        })
        .collect();
    assert!(rows.windows(2).all(|w| w[0] < w[1]), "{rows:?}");
    let widest = &sc[rows[0]];
    assert!(
        widest.starts_with('>') && widest.contains('#') && widest.contains('='),
        "{widest}"
    );
    // the tornado's numbers: the swing of the widest input
    let sw = &s.inputs[order[0]].swings[0];
    let swing = deckspin::tui::studies::points::cell(sw.swing().unwrap());
    assert!(widest.contains(&swing), "{swing} {widest}");
    // n: the next quantity, the row at the cursor keeps its input; round to the first
    update(&mut app, key('j'));
    let input = order[1];
    let n = s.quantities.len();
    update(&mut app, key('n'));
    let want = format!("sensitivity: the tornado of {} (2/{n})", s.quantities[1]);
    assert!(app.status.starts_with(&want), "{}", app.status);
    let order1 = deckspin::tui::studies::design_rows::order(s, 1);
    assert_eq!(order1[app.studies.cursor()], input);
    let sc = screen(&render(&mut app, 80, 24));
    assert!(
        sc.contains(&format!("{} (2/{n}; n the next)", s.quantities[1])),
        "{sc}"
    );
    for _ in 1..n {
        update(&mut app, key('n'));
    }
    assert_eq!(app.studies.quantity, 0);
    assert_eq!(order[app.studies.cursor()], input);
}

#[test]
fn the_design_studies_write_their_csv_and_are_not_reopened() {
    let d = std::env::temp_dir().join(format!("deckspin-tui-design-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(d.join("models")).unwrap();
    let model = d.join("models/four-span.toml");
    std::fs::write(&model, read(&bridge_path())).unwrap();
    let mut app = App::new_from_text(&read(&model), &model);
    app.view = View::Studies;
    let dirs = deckspin::tui::runs::out_folder::out_dirs(&model);
    for kind in [StudyKind::Adequacy, StudyKind::Sensitivity] {
        let table = Box::new(design_run(kind).1.clone());
        let fx = vec![Effect::WriteStudy {
            id: 0,
            dirs: dirs.clone(),
            table,
        }];
        tui::execute_blocking(&mut app, fx);
    }
    let out = d.join("models/four-span.out");
    assert_eq!(
        read(&out.join("adequacy-1.csv")),
        deckspin::design::adequacy_report::variants_csv(ladder())
    );
    assert_eq!(read(&out.join("sensitivity-1.csv")), swings().csv());
    // listed with the others; opened, each says why it is not read back
    let fx = update(&mut app, key('f'));
    tui::execute_blocking(&mut app, fx);
    let Mode::Pick { files, .. } = &app.mode else {
        panic!("{:?} {}", app.mode, app.status)
    };
    assert_eq!(files.len(), 2, "{files:?}");
    let fx = update(&mut app, code(KeyCode::Enter));
    tui::execute_blocking(&mut app, fx);
    assert!(
        app.status
            .contains("study's CSV: written for reading elsewhere, not reopened here"),
        "{}",
        app.status
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// One frame of `app` as its panels draw it (without the last ASCII pass).
fn render_panels(
    app: &mut App,
    w: u16,
    h: u16,
) -> ratatui::Terminal<ratatui::backend::TestBackend> {
    update(app, Msg::Resize(w, h));
    let mut t = ratatui::Terminal::new(ratatui::backend::TestBackend::new(w, h)).unwrap();
    let mut cache = tui::ui::Cache::default();
    t.draw(|f| tui::ui::draw_screen(f, app, &mut cache))
        .unwrap();
    t
}

#[test]
fn the_design_studies_are_drawn_in_ascii_by_their_panels() {
    let apps = [
        design_done(
            StudyKind::Adequacy,
            StudyTable::Adequacy(Box::new(steady(ladder()))),
        ),
        design_done(
            StudyKind::Sensitivity,
            design_run(StudyKind::Sensitivity).1.clone(),
        ),
    ];
    for mut app in apps {
        app.ascii = true;
        update(&mut app, key('j'));
        for (w, h) in [(80, 24), (120, 40), (60, 18)] {
            let t = render_panels(&mut app, w, h);
            let s = screen(&t);
            for (y, line) in s.lines().enumerate() {
                let wide: Vec<char> = line.chars().filter(|c| *c as u32 > 0x7e).collect();
                assert!(wide.is_empty(), "{w}x{h} line {y}: {wide:?}\n{s}");
            }
        }
    }
}

#[test]
fn snapshot_studies_adequacy_80x24() {
    let table = StudyTable::Adequacy(Box::new(steady(ladder())));
    let mut app = design_done(StudyKind::Adequacy, table);
    go_to_row(&mut app, row_of("rigid-abutments"));
    let t = render(&mut app, 80, 24);
    snapshot_settings().bind(|| insta::assert_snapshot!("studies_adequacy_80x24", t.backend()));
}

#[test]
fn snapshot_studies_sensitivity_80x24() {
    let mut app = design_done(
        StudyKind::Sensitivity,
        design_run(StudyKind::Sensitivity).1.clone(),
    );
    let t = render(&mut app, 80, 24);
    snapshot_settings().bind(|| insta::assert_snapshot!("studies_sensitivity_80x24", t.backend()));
}
