//! The studies as tables: watched sweeps (progress and cancel), the tables they fill, their
//! CSV read back bit for bit, and malformed CSV refused with the file and line.

use deckspin::progress::{Progress, Unwatched};
use deckspin::studies::{Row, Study, Watch, increase_vs_mu};
use deckspin::study_csv::{StudyCsvError, read_csv, to_csv};
use deckspin::study_table::{PointStatus, RunTable, StudyKind, StudyTable, SuiteSubset, run_study};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

fn bridge_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("models/four-span.toml")
}

/// The four-span bridge with its first `runs` `[[run]]` tables (run 1 applied).
fn bridge_text(runs: usize) -> String {
    let text = std::fs::read_to_string(bridge_path()).unwrap();
    let mut doc: toml_edit::DocumentMut = text.parse().unwrap();
    doc["run"].as_array_of_tables_mut().unwrap().retain({
        let mut k = 0;
        move |_| {
            k += 1;
            k <= runs
        }
    });
    doc["excitation"]["run"] = toml_edit::value(1);
    doc.to_string()
}

/// The workbench's default record suite of the bridge.
fn subset() -> SuiteSubset {
    SuiteSubset::near(&bridge_path())
}

/// A study of the bridge with `runs` runs, each 0.6 s long.
fn short_study(runs: usize) -> Study {
    let set = ["solver.t_end=0.6".to_string()];
    Study::from_text(&bridge_text(runs), &bridge_path(), &set).unwrap()
}

/// Records every row it is told of; says stop after `stop_after` rows.
struct Recorder {
    rows: Mutex<Vec<(usize, Row)>>,
    stop_after: usize,
    stopped: AtomicBool,
}

impl Recorder {
    fn new(stop_after: usize) -> Self {
        Self {
            rows: Mutex::new(Vec::new()),
            stop_after,
            stopped: AtomicBool::new(false),
        }
    }
}

impl Progress for Recorder {
    fn plan(&self, _: usize) {}
    fn done(&self, _: usize) {}
    fn go_on(&self) -> bool {
        !self.stopped.load(Ordering::SeqCst)
    }
}

impl Watch for Recorder {
    fn row(&self, index: usize, row: &Row) {
        let mut rows = self.rows.lock().unwrap();
        rows.push((index, row.clone()));
        if rows.len() >= self.stop_after {
            self.stopped.store(true, Ordering::SeqCst);
        }
    }
}

fn runs(t: &StudyTable) -> &RunTable {
    match t {
        StudyTable::Runs(r) => r,
        t => panic!("a run table expected: {:?}", t.kind()),
    }
}

#[test]
fn the_pga_study_tells_each_row_once_and_fills_its_table() {
    let study = short_study(3);
    let rec = Recorder::new(usize::MAX);
    let t = run_study(StudyKind::Pga, &study, &[], &subset(), &rec).unwrap();
    let t = runs(&t);
    assert_eq!(t.kind, StudyKind::Pga);
    assert_eq!(t.runs.len(), 6);
    assert_eq!(t.done(), 6);
    assert_eq!(t.failed(), 0);
    let mut told = rec.rows.into_inner().unwrap();
    told.sort_by_key(|(i, _)| *i);
    assert_eq!(
        told.iter().map(|(i, _)| *i).collect::<Vec<_>>(),
        vec![0, 1, 2, 3, 4, 5]
    );
    for (i, row) in &told {
        let r = &t.runs[*i];
        assert_eq!(r.run, i / 2 + 1);
        assert_eq!(r.contact, i % 2 == 1);
        assert_eq!(r.peak_rotation.to_bits(), row.peak_rotation.to_bits());
        assert!(r.peak_rotation > 0.0, "{r:?}");
    }
    // the model's PGAs of runs 1–3, and contact makes impacts
    let pgas: Vec<f64> = t.runs.iter().map(|r| r.pga_x).collect();
    assert_eq!(pgas, vec![0.09, 0.09, 0.25, 0.25, 0.40, 0.40]);
    assert!(t.runs.iter().filter(|r| !r.contact).all(|r| r.impacts == 0));
    let [without, with] = t.fig7();
    assert_eq!(without.len(), 3);
    assert_eq!(with.len(), 3);
    assert_eq!(with[2], (0.40, t.runs[5].peak_rotation));
}

#[test]
fn a_cancelled_study_keeps_the_rows_already_run() {
    let study = short_study(4);
    let rec = Recorder::new(2);
    let t = run_study(StudyKind::Pga, &study, &[], &subset(), &rec).unwrap();
    let t = runs(&t);
    let told = rec.rows.into_inner().unwrap();
    // the runs started before the cancel finish (at most one per thread), the rest are skipped
    assert!(
        told.len() >= 2 && told.len() < 8,
        "{} rows told",
        told.len()
    );
    assert_eq!(t.done(), told.len());
    let not_run = t.runs.iter().filter(|r| r.status == PointStatus::NotRun);
    assert_eq!(not_run.count(), 8 - told.len());
    for (i, row) in &told {
        assert_eq!(t.runs[*i].status, PointStatus::Ok);
        assert_eq!(
            t.runs[*i].peak_rotation.to_bits(),
            row.peak_rotation.to_bits()
        );
    }
}

#[test]
fn the_mu_table_gives_the_increase_of_the_mu_study() {
    let study = short_study(2);
    let mus = [0.2, 0.6];
    let t = run_study(
        StudyKind::Mu,
        &study,
        &mus,
        &subset(),
        &Recorder::new(usize::MAX),
    )
    .unwrap();
    let t = runs(&t);
    // two runs without contact, then each run with each μ
    assert_eq!(t.runs.len(), 2 + 2 * 2);
    assert_eq!(t.runs[0].mu, None);
    assert_eq!(t.runs[3].mu, Some(0.6));
    assert_eq!(t.runs[3].run, 1);
    assert_eq!(t.mus(), vec![0.2, 0.6]);
    let reference = increase_vs_mu(&study, &mus, &Unwatched);
    let curves = t.fig8();
    assert_eq!(curves.len(), 2);
    for (r, c) in curves.iter().enumerate() {
        assert_eq!(c.run, r + 1);
        assert_eq!(c.points.len(), 2);
        for (k, &(mu, inc)) in c.points.iter().enumerate() {
            assert_eq!(mu, mus[k]);
            assert_eq!(inc.to_bits(), reference.increase(r, k).to_bits());
        }
    }
}

/// The text of `t` read back, written again, is the same; every number the same f64.
fn round_trip(t: &StudyTable) -> StudyTable {
    let csv = to_csv(t);
    let back = read_csv(&csv, Path::new("x.csv")).unwrap_or_else(|e| panic!("{e}\n{csv}"));
    assert_eq!(to_csv(&back), csv);
    back
}

#[test]
fn study_csv_reads_back_bit_for_bit() {
    let study = short_study(2);
    let t = run_study(
        StudyKind::Mu,
        &study,
        &[0.1 + 0.2, 0.5],
        &subset(),
        &Recorder::new(3),
    )
    .unwrap();
    let back = round_trip(&t);
    let (a, b) = (runs(&t), runs(&back));
    assert_eq!(b.kind, StudyKind::Mu);
    assert_eq!(a.runs.len(), b.runs.len());
    for (x, y) in a.runs.iter().zip(&b.runs) {
        assert_eq!(x.status, y.status);
        assert_eq!(x.mu.map(f64::to_bits), y.mu.map(f64::to_bits));
        assert_eq!(
            x.peak_rotation.to_bits(),
            y.peak_rotation.to_bits(),
            "{x:?}"
        );
        assert_eq!(x.residual_rotation.to_bits(), y.residual_rotation.to_bits());
        assert_eq!((x.run, x.contact, x.impacts), (y.run, y.contact, y.impacts));
    }
    assert!(
        b.runs.iter().any(|r| r.status == PointStatus::NotRun),
        "cancelled rows kept"
    );
    assert_eq!(b.mus(), vec![0.1 + 0.2, 0.5]);
    // the screening, with a failed run's reason (commas, quotes) in a run table too
    let screen = run_study(StudyKind::Screen, &study, &[], &subset(), &Recorder::new(1)).unwrap();
    let StudyTable::Screen(s) = round_trip(&screen) else {
        panic!("a screening")
    };
    let StudyTable::Screen(orig) = &screen else {
        unreachable!()
    };
    assert_eq!((s.l_over_b.len(), s.skew_deg.len()), (31, 13));
    assert_eq!(s.cells, orig.cells);
    assert_eq!(s.ends, orig.ends);
    assert_eq!(s.corners.len(), 8);
    assert_eq!(s.mark(), orig.mark());
    let mut failed = runs(&t).clone();
    failed.runs[0].status = PointStatus::Failed("failed: \"x\", at t = 1".into());
    let back = round_trip(&StudyTable::Runs(failed));
    assert_eq!(
        runs(&back).runs[0].status,
        PointStatus::Failed("failed: \"x\", at t = 1".into())
    );
}

fn error_of(text: &str) -> String {
    match read_csv(text, Path::new("dir/pga-1.csv")) {
        Err(e @ StudyCsvError::Bad { .. }) => e.to_string(),
        other => panic!("{other:?}"),
    }
}

#[test]
fn malformed_study_csv_names_the_file_and_line() {
    let head = "study,run,pga_x,pga_y,contact,mu,peak_rotation,residual_rotation,impacts,status\n";
    let ok = "pga,1,0.09,0.075,false,,1e-4,2e-5,0,ok\n";
    assert_eq!(
        error_of(&format!("{head}{ok}{ok}pga,2,0.25,0.2,true,,x,0,3,ok\n")),
        "dir/pga-1.csv:4: peak_rotation: `x` is not a number"
    );
    assert_eq!(
        error_of(&format!("{head}{ok}pga,2,0.25\n")),
        "dir/pga-1.csv:3: 3 fields, the header has 10"
    );
    assert_eq!(
        error_of(&format!("{head}mu,1,0.09,0.075,true,,1e-4,2e-5,0,ok\n")),
        "dir/pga-1.csv:2: mu: empty on a run with contact"
    );
    assert_eq!(
        error_of(&format!(
            "{head}{ok}mu,1,0.09,0.075,false,,1e-4,2e-5,0,ok\n"
        )),
        "dir/pga-1.csv:3: study: `mu` after lines of another study"
    );
    assert_eq!(
        error_of(&format!("{head}{}", ok.replace(",ok", ","))),
        "dir/pga-1.csv:2: status: empty, expected ok, not run or the reason of a failure"
    );
    assert_eq!(error_of(""), "dir/pga-1.csv:1: empty: no header");
    assert_eq!(error_of(head), "dir/pga-1.csv:2: no rows after the header");
    assert!(error_of("t,deck.theta\n0,0\n").starts_with("dir/pga-1.csv:1: not a study's CSV"));
    // a screening whose cells are out of order
    let screen = run_study(
        StudyKind::Screen,
        &short_study(1),
        &[],
        &subset(),
        &Recorder::new(1),
    )
    .unwrap();
    let csv = to_csv(&screen);
    let mut lines: Vec<&str> = csv.lines().collect();
    lines.swap(2, 40);
    let e = error_of(&(lines.join("\n") + "\n"));
    assert!(e.starts_with("dir/pga-1.csv:3: the map's cells"), "{e}");
    // a file that cannot be read
    let e = deckspin::study_csv::read_file(Path::new("no/such/study.csv")).unwrap_err();
    assert!(
        e.to_string().starts_with("no/such/study.csv: cannot read"),
        "{e}"
    );
}

#[test]
fn the_suite_study_runs_the_subset_as_deckspin_suite_does_and_reads_back() {
    use deckspin::suite::intensity::MeasureSpec;
    use deckspin::suite::{Suite, SuiteSpec};
    let mut sub = subset();
    sub.pairs = 2;
    sub.levels = vec![0.2, 0.4];
    let text = std::fs::read_to_string(bridge_path()).unwrap();
    let study = Study::from_text(&text, &bridge_path(), &[]).unwrap();
    let rec = Recorder::new(usize::MAX);
    let t = run_study(StudyKind::Suite, &study, &[], &sub, &rec).unwrap();
    let table = runs(&t);
    assert_eq!(table.kind, StudyKind::Suite);
    assert_eq!((table.done(), table.runs.len(), table.failed()), (4, 4, 0));
    assert_eq!(rec.rows.lock().unwrap().len(), 4);
    // the same runs by the suite itself: pair p, level l at index 2 p + l
    let spec = SuiteSpec {
        measure: MeasureSpec::Pga,
        levels: sub.levels.clone(),
        axes: Vec::new(),
        tail: 2.0,
    };
    let suite = Suite::open(&bridge_path(), &[], sub.read_pairs().unwrap(), spec).unwrap();
    let rows = suite.run(0..4, &Unwatched);
    for (r, s) in table.runs.iter().zip(&rows) {
        assert_eq!(
            (r.pga_x, r.run),
            (s.level, 1 + (s.pair != rows[0].pair) as usize)
        );
        assert_eq!(r.peak_rotation.to_bits(), s.metrics[0].unwrap().to_bits());
    }
    let [points, medians] = table.suite_points();
    assert_eq!(points.len(), 4);
    let m02 = 0.5 * (rows[0].metrics[0].unwrap() + rows[2].metrics[0].unwrap());
    assert_eq!(medians[0], (0.2, m02));
    // its CSV reads back bit for bit
    let back = read_csv(&to_csv(&t), Path::new("suite-1.csv")).unwrap();
    assert_eq!(to_csv(&back), to_csv(&t)); // pga_y is NaN: compared as text
    for (a, b) in runs(&back).runs.iter().zip(&table.runs) {
        assert_eq!(a.peak_rotation.to_bits(), b.peak_rotation.to_bits());
    }
    let bad = to_csv(&t).replacen(",true,", ",false,", 1);
    let e = read_csv(&bad, Path::new("s.csv")).unwrap_err().to_string();
    assert!(e.contains("s.csv:2: contact: false in the suite"), "{e}");
}
