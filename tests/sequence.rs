//! Run sequences: run k+1 starts from the final state of run k (q, q̇, each element's branch
//! and memory), relative to the ground; `[[run]] gaps` set the gaps at a run's start.
mod common;

use deckspin::excitation::END_TOLERANCE;
use deckspin::model::ModelError;
use deckspin::output::RunOutput;
use deckspin::run::Stop;
use deckspin::scene::{Motion, Scene};
use deckspin::sequence::{
    BridgeSequence, Sequence, SequenceError, Stage, ground_at_end, handover, run_stages,
};
use deckspin::studies::Study;
use std::path::Path;

const BRIDGE: &str = "models/four-span.toml";

fn bridge(set: &[&str]) -> BridgeSequence {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    BridgeSequence::open(&common::model(BRIDGE), &set).unwrap_or_else(|e| panic!("{e}"))
}

/// The bridge with `line` added after `name = "run2"`, read as if it were the model file.
fn bridge_with_run2(line: &str) -> Result<BridgeSequence, SequenceError> {
    let path = common::model(BRIDGE);
    let text = std::fs::read_to_string(&path).unwrap();
    let text = text.replacen(
        "name = \"run2\"\n",
        &format!("name = \"run2\"\n{line}\n"),
        1,
    );
    assert!(text.contains(line));
    BridgeSequence::from_study(Study {
        path,
        text,
        base: Vec::new(),
        motions: Default::default(),
    })
}

/// Runs `runs` of `b` in one sequence, every sample kept.
fn sequence(b: &BridgeSequence, runs: &[usize]) -> Sequence {
    let mut seq = Sequence::new();
    for &k in runs {
        let stage = b.stage(k, &[]).unwrap();
        let name = stage.name.clone();
        let scene = seq.prepare(stage).unwrap();
        seq.run(&name, &scene, &mut deckspin::Silent)
            .unwrap_or_else(|e| panic!("{e}"));
    }
    seq
}

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

fn output(seq: &Sequence, i: usize) -> &RunOutput {
    &seq.runs[i].run.output
}

#[test]
fn processed_records_end_at_rest_at_zero_before_the_runs_end() {
    let b = bridge(&[]);
    for k in [1, 4, 7] {
        let scene = b.stage(k, &[]).unwrap().scene;
        let t_end = scene.settings.t_end;
        for s in &scene.supports {
            let Motion::Record(g) = &s.motion else {
                panic!("{}: not a record", s.name)
            };
            let pgd = g.disp.iter().fold(0.0f64, |m, d| m.max(d.abs()));
            let pgv = g.vel.iter().fold(0.0f64, |m, d| m.max(d.abs()));
            let (d, v) = (*g.disp.last().unwrap(), *g.vel.last().unwrap());
            assert!(
                g.end_time() <= t_end,
                "{}: ends at {}",
                s.name,
                g.end_time()
            );
            assert!(
                d.abs() <= END_TOLERANCE * pgd,
                "{}: d_end {d:e}, PGD {pgd}",
                s.name
            );
            assert!(
                v.abs() <= END_TOLERANCE * pgv,
                "{}: v_end {v:e}, PGV {pgv}",
                s.name
            );
            assert_eq!(ground_at_end(s, t_end), (0.0, 0.0));
        }
    }
}

#[test]
fn the_state_handed_over_is_the_final_state_bit_for_bit() {
    let b = bridge(&[]);
    let seq = sequence(&b, &[3]);
    let out = output(&seq, 0).clone();
    let end = &out.final_state;
    let last = out.samples.last().unwrap();
    let scene1 = b.stage(3, &[]).unwrap().scene;
    // the final state is the run's end: its last sample, at t_end
    assert_eq!(end.t, scene1.settings.t_end);
    assert_eq!(last.t, end.t);
    assert_eq!(bits(&last.q), bits(&end.q));
    assert_eq!(bits(&last.v), bits(&end.v));
    // the final laws are those of the end: the last sample's element forces are theirs
    for (law, &(e, f)) in out.final_laws.iter().zip(&last.elements) {
        assert_eq!(law.force(e).to_bits(), f.to_bits());
    }
    assert!(out.final_laws.iter().any(|l| l.branch().u_ref != 0.0));
    // handed over: the records ended at rest at zero, so nothing is subtracted
    let h = seq.carry.as_ref().unwrap();
    assert!(
        h.ground
            .iter()
            .chain(h.ground_rate.iter())
            .all(|x| *x == 0.0)
    );
    let scene2 = seq.prepare(b.stage(4, &[]).unwrap()).unwrap();
    assert_eq!(bits(scene2.q0.as_slice()), bits(&end.q));
    assert_eq!(bits(scene2.v0.as_slice()), bits(&end.v));
    assert_eq!(scene2.hysteretic.len(), out.final_laws.len());
    for (el, law) in scene2.hysteretic.iter().zip(&out.final_laws) {
        let (a, b) = (el.law.branch(), law.branch());
        let fields = |b: &deckspin::hysteresis::Branch| {
            bits(&[b.u_ref, b.f_ref, b.stiffness, b.lower, b.upper, b.direction])
        };
        assert_eq!(fields(a), fields(b), "{}", el.name);
        assert_eq!(a.ends_on_reversal, b.ends_on_reversal);
        let u = law.displacement();
        assert_eq!(el.law.displacement().to_bits(), u.to_bits());
        assert_eq!(el.law.force(u).to_bits(), law.force(u).to_bits());
        // the memory too (Debug prints every f64 exactly)
        assert_eq!(format!("{:?}", el.law), format!("{law:?}"));
    }
    // …and run 4 starts there: its first sample is run 3's last, gaps included; the element
    // deformations e = d·(P(q) − P(0)) − u_g differ by the ground's d_end ≈ 1e-15 m (≤ 1e-9
    // PGD), counted as zero
    let mut seq = seq;
    seq.run("run4", &scene2, &mut deckspin::Silent).unwrap();
    let first = &output(&seq, 1).samples[0];
    assert_eq!(bits(&first.q), bits(&last.q));
    assert_eq!(bits(&first.v), bits(&last.v));
    for (a, b) in first.elements.iter().zip(&last.elements) {
        assert!(
            (a.0 - b.0).abs() <= 1e-12 && (a.1 - b.1).abs() <= 1e-8,
            "{a:?} {b:?}"
        );
    }
    for (a, b) in first.contacts.iter().zip(&last.contacts) {
        assert_eq!(a.gap.to_bits(), b.gap.to_bits());
    }
}

#[test]
fn run_1_of_a_sequence_is_run_1_alone_and_run_2_is_not_run_2_alone() {
    let b = bridge(&[]);
    let seq = sequence(&b, &[1, 2]);
    let alone = |k: usize| {
        let scene = b.stage(k, &[]).unwrap().scene;
        deckspin::simulate(&scene, &mut deckspin::Silent).unwrap()
    };
    let (one, two) = (alone(1), alone(2));
    let s1 = output(&seq, 0);
    assert_eq!(s1.samples.len(), one.samples.len());
    for (a, b) in s1.samples.iter().zip(&one.samples) {
        assert_eq!(a.t.to_bits(), b.t.to_bits());
        assert_eq!(bits(&a.q), bits(&b.q));
        assert_eq!(bits(&a.v), bits(&b.v));
    }
    let th = s1.dof("deck.theta").unwrap();
    assert_eq!(
        s1.summary.peaks[th].max_abs.to_bits(),
        one.summary.peaks[th].max_abs.to_bits()
    );
    // run 1 leaves the deck displaced, the columns loaded: run 2 starts there, not at rest
    let s2 = output(&seq, 1);
    assert_eq!(bits(&s2.samples[0].q), bits(&s1.final_state.q));
    assert!(s1.final_state.q.iter().any(|x| x.abs() > 1e-6));
    assert!(two.samples[0].q.iter().all(|x| *x == 0.0));
    let (p_seq, p_alone) = (s2.summary.peaks[th].max_abs, two.summary.peaks[th].max_abs);
    let (r_seq, r_alone) = (
        s2.summary.peaks[th].residual,
        two.summary.peaks[th].residual,
    );
    assert!(
        (p_seq - p_alone).abs() > 1e-3 * p_alone,
        "{p_seq} {p_alone}"
    );
    assert!((r_seq - r_alone).abs() > 1e-6, "{r_seq} {r_alone}");
}

#[test]
fn a_gap_override_gives_those_gaps_at_the_start_of_the_run() {
    let gaps = [0.0101, 0.0113, 0.0147, 0.0089];
    let b = bridge_with_run2(&format!("gaps = {gaps:?}")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(b.runs[1].gaps.as_deref(), Some(&gaps[..]));
    assert_eq!(b.runs[0].gaps, None);
    let seq = sequence(&b, &[1, 2]);
    let s1 = output(&seq, 0);
    // run 1 moved the deck: without the override run 2 would start at other gaps
    let before: Vec<f64> = s1
        .samples
        .last()
        .unwrap()
        .contacts
        .iter()
        .map(|c| c.gap)
        .collect();
    assert!(before.iter().zip(&gaps).all(|(a, b)| (a - b).abs() > 1e-4));
    assert!(
        seq.runs[0]
            .start_gaps
            .iter()
            .all(|g| (g - 0.0127).abs() <= 1e-12)
    );
    let first = &output(&seq, 1).samples[0];
    for (i, g) in gaps.iter().enumerate() {
        assert!((seq.runs[1].start_gaps[i] - g).abs() <= 1e-12);
        assert!((first.contacts[i].gap - g).abs() <= 1e-12, "{i}");
    }
    // the pose is the one handed over: only the faces moved
    assert_eq!(bits(&first.q), bits(&s1.final_state.q));
}

#[test]
fn bad_gap_overrides_name_file_line_and_field() {
    let msg = |line: &str| match bridge_with_run2(line) {
        Err(SequenceError::Load(e @ ModelError::Invalid { .. })) => (e.line(), e.to_string()),
        Err(e) => panic!("{line}: {e}"),
        Ok(_) => panic!("{line}: accepted"),
    };
    let (line, text) = msg("gaps = [0.01, 0.01, 0.01]");
    assert_eq!(line, Some(81));
    assert!(
        text.contains("four-span.toml:81: run.1.gaps: expected 4 gaps"),
        "{text}"
    );
    let (line, text) = msg("gaps = [0.01, 0.01, -0.002, 0.01]");
    assert_eq!(line, Some(81));
    assert!(
        text.contains("run.1.gaps.2: must be ≥ 0, got -0.002"),
        "{text}"
    );
    let (_, text) = msg("gaps = [0.01, 0.01, nan, 0.01]");
    assert!(
        text.contains("run.1.gaps.2: must be a finite number"),
        "{text}"
    );
}

/// A free two-DOF oscillator: x on a linear hysteretic element, y on a spring, no support.
const OSCILLATOR: &str = r#"
title = "free oscillator"
[solver]
t_end = T_END
output_dt = 0.01
rtol = 1e-11
atol = 1e-13
[[body]]
name = "mass"
mass = 2.0
dofs = ["x", "y"]
initial_displacement = [0.01, 0.0, 0.0]
initial_velocity = [0.3, -0.2, 0.0]
[[hysteretic]]
name = "column"
body = "mass"
direction = [1.0, 0.0]
law = { law = "linear", stiffness = 80.0 }
[[spring]]
name = "spring"
body = "mass"
direction = [0.0, 1.0]
stiffness = 50.0
"#;

fn oscillator(t_end: f64) -> Scene {
    let text = OSCILLATOR.replace("T_END", &format!("{t_end:?}"));
    deckspin::model::load_str(&text, Path::new("oscillator.toml"), &[]).unwrap()
}

#[test]
fn a_free_vibration_continues_across_runs_as_one_long_run() {
    let (t1, t2) = (0.75, 1.3);
    let stages = [t1, t2].map(|t| Stage {
        name: format!("{t}"),
        scene: oscillator(t),
        gaps: None,
    });
    let (seq, error) = run_stages(stages.to_vec());
    assert!(error.is_none(), "{error:?}");
    let long = deckspin::simulate(&oscillator(t1 + t2), &mut deckspin::Silent).unwrap();
    // closed form: x = x0 cos ωt + v0/ω sin ωt per axis
    let exact = |t: f64| {
        let (wx, wy) = ((80.0f64 / 2.0).sqrt(), (50.0f64 / 2.0).sqrt());
        let x = 0.01 * (wx * t).cos() + 0.3 / wx * (wx * t).sin();
        (x, -0.2 / wy * (wy * t).sin())
    };
    let (mut worst_long, mut worst_exact, mut compared) = (0.0f64, 0.0f64, 0);
    for (k, r) in seq.runs.iter().enumerate() {
        let offset = if k == 0 { 0.0 } else { t1 };
        for s in &r.run.output.samples {
            let t = s.t + offset;
            let (x, y) = exact(t);
            worst_exact = worst_exact.max((s.q[0] - x).abs()).max((s.q[1] - y).abs());
            if let Some(l) = long.samples.iter().find(|l| (l.t - t).abs() < 1e-9) {
                let d = (0..2).map(|i| (s.q[i] - l.q[i]).abs() + (s.v[i] - l.v[i]).abs());
                worst_long = worst_long.max(d.fold(0.0, f64::max));
                compared += 1;
            }
        }
    }
    assert!(compared >= 200, "{compared}");
    // amplitudes ≈ 0.05 m: both within the integrator's tolerance (rtol 1e-11)
    assert!(
        worst_long <= 1e-9,
        "concatenated vs one run: {worst_long:e}"
    );
    assert!(
        worst_exact <= 1e-9,
        "concatenated vs closed form: {worst_exact:e}"
    );
}

#[test]
fn a_run_cut_mid_record_hands_over_the_state_relative_to_the_ground() {
    let b = bridge(&["solver.t_end=3.1"]);
    let seq = sequence(&b, &[5, 5]);
    let h = output(&seq, 0);
    let scene = b.stage(5, &[]).unwrap().scene;
    let carry = handover(&scene, h).unwrap();
    // the table is still moving at 3.1 s: the ground's displacement is subtracted
    assert!(carry.ground.amax() > 1e-3, "{}", carry.ground);
    let (last, first) = (h.samples.last().unwrap(), &output(&seq, 1).samples[0]);
    // every element deformation and force is kept (the columns' bases return to 0 with the
    // deck)
    for (a, b) in first.elements.iter().zip(&last.elements) {
        assert!(
            (a.0 - b.0).abs() <= 1e-12 && (a.1 - b.1).abs() <= 1e-8,
            "{a:?} {b:?}"
        );
    }
    // the abutments have no y: the deck moves by −u_g,y past their faces, which are turned
    // by θ_a, so each gap changes by sin θ_a · u_g,y (exactly, as the faces are straight)
    let y = h.dof("deck.y").unwrap();
    let uy = carry.ground[y];
    assert!(uy.abs() > 1e-3);
    let faces = ["left_abutment.theta", "right_abutment.theta"].map(|n| h.dof(n).unwrap());
    for (i, (a, b)) in first.contacts.iter().zip(&last.contacts).enumerate() {
        let th = last.q[faces[i / 2]];
        let expected = b.gap + th.sin() * uy * if i < 2 { -1.0 } else { 1.0 };
        assert!(
            (a.gap - expected).abs() <= 1e-12,
            "{i}: {} {} {expected}",
            a.gap,
            b.gap
        );
    }
    let x = h.dof("deck.x").unwrap();
    let dx = first.q[x] - (last.q[x] - carry.ground[x]);
    assert!(dx.abs() <= 1e-15, "{dx:e}");
    let s = &scene.supports[0];
    assert!((carry.ground[x] - s.at(3.1).0).abs() <= 1e-12 * carry.ground[x].abs());
}

#[test]
fn a_failed_run_ends_the_sequence_naming_it_and_keeps_what_ran() {
    let scene = |t_end: f64, max_steps: usize| {
        let mut s = oscillator(t_end);
        s.settings.max_steps = max_steps;
        s
    };
    let stages = vec![
        Stage {
            name: "first".into(),
            scene: scene(0.5, 100_000),
            gaps: None,
        },
        Stage {
            name: "second".into(),
            scene: scene(0.5, 5),
            gaps: None,
        },
        Stage {
            name: "third".into(),
            scene: scene(0.5, 100_000),
            gaps: None,
        },
    ];
    let (seq, error) = run_stages(stages);
    match error {
        Some(SequenceError::Failed { run, failure }) => {
            assert_eq!(run, "second");
            assert_eq!(failure.kind, "TooManySteps");
        }
        e => panic!("{e:?}"),
    }
    assert_eq!(seq.runs.len(), 2);
    assert!(seq.runs[0].run.finished());
    let failed = &seq.runs[1].run;
    assert!(matches!(failed.stop, Stop::Failed(_)));
    assert!(!failed.output.samples.is_empty());
    assert!(failed.output.samples[0].t == 0.0);
}

#[test]
fn runs_are_parsed_and_checked() {
    let b = bridge(&[]);
    assert_eq!(b.parse_runs(None).unwrap(), (1..=7).collect::<Vec<_>>());
    assert_eq!(b.parse_runs(Some("2..4")).unwrap(), vec![2, 3, 4]);
    assert_eq!(b.parse_runs(Some("1,3,4")).unwrap(), vec![1, 3, 4]);
    for bad in ["0..3", "1,8", "1,1", "a", "3..1", ""] {
        assert!(
            matches!(b.parse_runs(Some(bad)), Err(SequenceError::Runs { .. })),
            "{bad}"
        );
    }
    let scene_file = common::model("models/validation/elastic-rattle.toml");
    assert!(matches!(
        BridgeSequence::open(&scene_file, &[]),
        Err(SequenceError::NoRuns { .. })
    ));
}

#[test]
fn the_command_writes_each_run_and_the_table() {
    let dir = std::env::temp_dir().join(format!("deckspin-sequence-{}", std::process::id()));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_deckspin"))
        .args([
            "sequence",
            BRIDGE,
            "--runs",
            "3,4",
            "--set",
            "solver.t_end=2",
        ])
        .arg("--out")
        .arg(&dir)
        .current_dir(common::root())
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    for k in [3, 4] {
        for f in ["history.csv", "events.csv", "summary.json"] {
            assert!(dir.join(format!("run{k}")).join(f).is_file(), "run{k}/{f}");
        }
    }
    let csv = std::fs::read_to_string(dir.join("sequence.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 3, "{csv}");
    assert!(lines[1].starts_with("3,run3,0.4,0.333,"), "{csv}");
    assert!(lines[2].starts_with("4,run4,0.6,0.5,") && lines[2].ends_with(",\"finished\""));
    // the table's peak is run 4's summary.json peak
    let summary = std::fs::read_to_string(dir.join("run4/summary.json")).unwrap();
    let json: serde_json::Value = serde_json::from_str(&summary).unwrap();
    let peak = json["peaks"][4]["max_abs"].as_f64().unwrap();
    let col: f64 = lines[2].split(',').nth(4).unwrap().parse().unwrap();
    assert!((col - peak).abs() <= 1e-9 * peak, "{col} {peak}");
    std::fs::remove_dir_all(&dir).unwrap();
}
