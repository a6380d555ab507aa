//! Sweeps: a study reads each record once and processes it once per processing.
mod common;

use deckspin::studies::{Study, run_pgas};

const FOUR_SPAN: &str = "models/four-span.toml";

fn study(base: &[&str]) -> Study {
    let base: Vec<String> = base.iter().map(|s| s.to_string()).collect();
    Study::open(&common::model(FOUR_SPAN), &base).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn a_study_reads_each_record_once_and_processes_it_once_per_scaling() {
    let s = study(&[]);
    assert_eq!(s.motions.records_read(), 2, "the two components of run 4");
    assert_eq!(s.motions.motions_processed(), 2);
    let pgas = run_pgas(&s.text);
    for k in 1..=pgas.len() {
        s.scene(&[format!("excitation.run={k}")]).unwrap();
    }
    // each component scaled to each distinct PGA of the runs, once
    let distinct = |v: Vec<f64>| {
        let mut v = v;
        v.sort_by(f64::total_cmp);
        v.dedup();
        v.len()
    };
    let xs = distinct(pgas.iter().map(|p| p.0).collect());
    let ys = distinct(pgas.iter().map(|p| p.1).collect());
    assert_eq!((xs, ys), (6, 6));
    assert_eq!(s.motions.records_read(), 2);
    assert_eq!(s.motions.motions_processed(), xs + ys);
}
