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
use deckspin::tui::study_points::{cell, points};
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
        dirs: deckspin::tui::out_folder::out_dirs(&model),
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
