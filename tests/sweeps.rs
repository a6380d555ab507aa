//! Sweeps: rows that compile to the same scene run once and share the result; a study reads
//! each record once and processes it once per processing.
mod common;

use deckspin::studies::{Axis, Row, Study, run_pgas};

const FOUR_SPAN: &str = "models/four-span.toml";

fn study(base: &[&str]) -> Study {
    let base: Vec<String> = base.iter().map(|s| s.to_string()).collect();
    Study::open(&common::model(FOUR_SPAN), &base).unwrap_or_else(|e| panic!("{e}"))
}

fn axis(key: &str, values: &[&str]) -> Axis {
    Axis {
        key: key.into(),
        values: values.iter().map(|v| v.to_string()).collect(),
    }
}

/// The numbers of a row (NaN-free rows only), wall time included.
fn numbers(r: &Row) -> [f64; 8] {
    assert!(r.error.is_none(), "{:?}: {:?}", r.settings, r.error);
    [
        r.peak_rotation,
        r.residual_rotation,
        r.peak_x,
        r.peak_y,
        r.impacts as f64,
        r.stick_time,
        r.energy_closure_rel,
        r.wall_time,
    ]
}

fn label(r: &Row) -> Vec<(&str, &str)> {
    (r.settings.iter())
        .map(|(k, v)| (k.as_str(), v.as_str()))
        .collect()
}

#[test]
fn rows_with_the_same_scene_run_once_and_keep_their_labels() {
    let s = study(&["solver.t_end=5"]);
    // runs 6 and 7 of the model have the same PGAs: the same scene (only the title differs)
    let pgas = run_pgas(&s.text);
    assert_eq!(pgas[5], pgas[6]);
    let out = s.sweep_counted(&[axis("excitation.run", &["6", "7"])]);
    assert_eq!(out.integrations, 1);
    assert_eq!(out.rows.len(), 2);
    assert_eq!(label(&out.rows[0]), [("excitation.run", "6")]);
    assert_eq!(label(&out.rows[1]), [("excitation.run", "7")]);
    assert_eq!(numbers(&out.rows[0]), numbers(&out.rows[1]));
    // the shared result is run 7's own
    let (alone, _) = s.simulate(&["excitation.run=7".into()]).unwrap();
    let r = deckspin::studies::row_of(vec![], &alone);
    assert_eq!(numbers(&out.rows[1])[..7], numbers(&r)[..7]);

    // two texts of one value are one scene; a different μ is another, also through the fork
    let out = s.sweep_counted(&[
        axis("excitation.run", &["4"]),
        axis("contacts.mu", &["0.3", "0.30", "0.6"]),
    ]);
    assert_eq!(out.integrations, 2);
    let n: Vec<[f64; 8]> = out.rows.iter().map(numbers).collect();
    assert_eq!(n[0], n[1]);
    assert_ne!(n[0][..7], n[2][..7]);
    assert_eq!(label(&out.rows[1])[1], ("contacts.mu", "0.30"));
}

#[test]
fn rows_that_differ_in_their_scene_are_not_merged() {
    let s = study(&["solver.t_end=3"]);
    // other PGAs (other processed motions), another restitution
    let out = s.sweep_counted(&[
        axis("excitation.run", &["5", "6"]),
        axis("contacts.restitution", &["0", "0.2"]),
    ]);
    assert_eq!(out.integrations, 4);
    let n: Vec<[f64; 8]> = out.rows.iter().map(numbers).collect();
    for i in 0..4 {
        for j in 0..i {
            assert_ne!(n[i][..4], n[j][..4], "rows {i} and {j}");
        }
    }
    // a row that does not compile is its own, not run
    let out = s.sweep_counted(&[axis("contacts.mu", &["0.3", "-1"])]);
    assert_eq!(out.integrations, 1);
    assert!(out.rows[0].error.is_none() && out.rows[1].error.is_some());
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

/// A bridge of several frames: a sweep's row gives the peaks over every frame (the largest
/// |θ|, |x|, |y| and residual |θ(t_end)|), not the first frame's alone and no NaN (the
/// three-frame example under Hector Mine at μ = 0.2: frame 3 turns 2.39e-3 rad, frame 1
/// 2.28e-3, the row said 2.28e-3, and NaN for x and y).
#[test]
fn a_sweep_row_of_several_frames_gives_the_largest_over_the_frames() {
    let rec = |c: &str| {
        let p = common::model(&format!("excitations/far-field/HECTOR_HEC{c}.AT2"));
        p.to_string_lossy().to_string()
    };
    let base = [
        format!("excitation.longitudinal={}", rec("000")),
        format!("excitation.transverse={}", rec("090")),
        "contacts.mu=0.2".to_string(),
        "solver.t_end=20".to_string(),
    ];
    let s = Study::open(&common::model("models/three-frame.toml"), &base).unwrap();
    let (out, _) = s.simulate(&[]).unwrap();
    let row = deckspin::studies::row_of(vec![], &out);
    let peak = |name: &str| out.summary.peaks[out.dof(name).unwrap()].clone();
    let frames = ["frame1", "frame2", "frame3"];
    let max = |axis: &str| {
        (frames.iter())
            .map(|f| peak(&format!("{f}.{axis}")).max_abs)
            .fold(0.0, f64::max)
    };
    assert_eq!(row.peak_rotation, max("theta"));
    assert!(
        row.peak_rotation > 1.04 * peak("frame1.theta").max_abs,
        "{}",
        row.peak_rotation
    );
    assert_eq!((row.peak_x, row.peak_y), (max("x"), max("y")));
    assert!(row.peak_x > 0.1 && row.peak_y > 0.1, "{row:?}");
    let residual = (frames.iter())
        .map(|f| peak(&format!("{f}.theta")).residual)
        .fold(0.0, |a: f64, r| if r.abs() > a.abs() { r } else { a });
    assert_eq!(row.residual_rotation, residual);
    // a measure of one rotation (work–precision) follows the frame that turns most
    let k = deckspin::studies::largest_rotation_dof(&out);
    assert_eq!(out.dof_names[k], "frame3.theta");
    // the specimen's one deck: its own peaks
    let s = study(&["solver.t_end=3"]);
    let (out, _) = s.simulate(&[]).unwrap();
    let row = deckspin::studies::row_of(vec![], &out);
    let deck = |a: &str| out.summary.peaks[out.dof(&format!("deck.{a}")).unwrap()].max_abs;
    assert_eq!(
        (row.peak_rotation, row.peak_x, row.peak_y),
        (deck("theta"), deck("x"), deck("y"))
    );
}
