//! `deck.rotation = false` (and `frame.N.rotation`): a deck that translates, its θ held at 0 —
//! no θ DOF, no column torsion, the damping of the bridge whose deck rotates.
mod common;
use common::*;
use deckspin::output::deck::DeckPeaks;
use deckspin::output::{HistoryWriter, RunOutput, SampleKind};
use deckspin::scene::Scene;

const FOUR_SPAN: &str = "models/four-span.toml";

fn load(rel: &str, set: &[&str]) -> Scene {
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    deckspin::load(&model(rel), &set).unwrap_or_else(|e| panic!("{e}"))
}

fn simulate(scene: &Scene) -> RunOutput {
    deckspin::run(scene, &mut deckspin::Silent).unwrap_or_else(|e| panic!("{e}"))
}

/// deck.x at each grid sample.
fn grid_x(r: &RunOutput) -> Vec<(f64, f64)> {
    let k = r.dof("deck.x").unwrap();
    (r.samples.iter())
        .filter(|s| s.kind == SampleKind::Grid)
        .map(|s| (s.t, s.q[k]))
        .collect()
}

/// A straight bridge symmetric about its axis (the four-span specimen) under longitudinal
/// motion only (harmonic, the abutments driven with the bents): the deck of the full model
/// stays at y = θ = 0 to round-off, so holding θ at 0 changes nothing but the integration:
/// the step-size control measures one DOF less, so the steps (and the event times located
/// within them) differ by the integration tolerance. The x histories agree to that tolerance
/// and converge together as it tightens.
#[test]
fn a_symmetric_bridge_translates_the_same_with_its_rotation_held() {
    let base = [
        "excitation.kind=\"harmonic\"",
        "excitation.amplitude_x=0.03",
        "excitation.frequency=2.0",
        "solver.t_end=6.0",
    ];
    let mut last = f64::INFINITY;
    for (rtol, atol) in [(1e-6, 1e-9), (1e-9, 1e-12)] {
        let tol = [format!("solver.rtol={rtol}"), format!("solver.atol={atol}")];
        let mut set: Vec<&str> = base.to_vec();
        set.extend(tol.iter().map(|s| s.as_str()));
        let full = simulate(&load(FOUR_SPAN, &set));
        set.push("deck.rotation=false");
        let held = simulate(&load(FOUR_SPAN, &set));
        let theta = full.dof("deck.theta").unwrap();
        let y = full.dof("deck.y").unwrap();
        assert!(
            full.summary.peaks[theta].max_abs < 1e-15,
            "θ of the full model"
        );
        assert!(full.summary.peaks[y].max_abs < 1e-14, "y of the full model");
        assert!(full.summary.stats.impacts > 20);
        assert_eq!(full.summary.stats.impacts, held.summary.stats.impacts);
        let (a, b) = (grid_x(&full), grid_x(&held));
        assert_eq!(a.len(), b.len());
        let peak = a.iter().fold(0.0f64, |m, p| m.max(p.1.abs()));
        let diff = (a.iter().zip(&b))
            .map(|(p, q)| {
                assert_eq!(p.0, q.0);
                (p.1 - q.1).abs()
            })
            .fold(0.0f64, f64::max);
        // measured 9.4e-11 at rtol 1e-6, 7.2e-14 at 1e-9 (peak 0.144 m)
        assert!(diff <= rtol * peak, "rtol {rtol}: max |Δx| {diff:e}");
        assert!(diff < last);
        last = diff;
    }
}

/// The specimen with a translating deck under its own record: runs to the end, turns by
/// exactly 0 in every output, never penetrates, closes its energy as the full model does.
#[test]
fn the_specimen_with_a_translating_deck_runs_to_the_end_without_rotation() {
    let full = simulate(&load(FOUR_SPAN, &[]));
    let scene = load(FOUR_SPAN, &["deck.rotation=false"]);
    let r = simulate(&scene);
    let s = &r.summary;
    assert_eq!(s.t_end, scene.settings.t_end);
    assert!(r.dof("deck.theta").is_none());
    let mut w = HistoryWriter::new(Vec::new(), &r).unwrap();
    w.write(&r.samples[..1]).unwrap();
    let text = String::from_utf8(w.finish().unwrap()).unwrap();
    let head = text.lines().next().unwrap();
    assert!(
        head.contains("deck.x") && !head.contains("deck.theta"),
        "{head}"
    );
    let deck = DeckPeaks::of(&r);
    assert_eq!((deck.rotation, deck.residual), (0.0, 0.0));
    assert!(deck.x > 0.05 && deck.y > 0.01, "{deck:?}");
    let row = deckspin::studies::row_of(Vec::new(), &r);
    assert_eq!((row.peak_rotation, row.residual_rotation), (0.0, 0.0));
    assert!(DeckPeaks::of(&full).rotation > 1e-3);
    // as the full model at the model's tolerance (bridge.rs): nanometres, 1e-5 (measured:
    // closure 2.3e-6 against 1.1e-6, penetration 5.8e-13 m against 1.0e-13 m)
    closes_as(&r, &full);
    for o in [&r, &full] {
        assert!(
            o.summary.max_penetration < 1e-8,
            "{:e}",
            o.summary.max_penetration
        );
        assert!(
            o.summary.energy_closure_rel < 1e-5,
            "{:e}",
            o.summary.energy_closure_rel
        );
        assert!(o.summary.stats.impacts > 20);
    }
}

/// The energy closure of `held` is of the order of the full model's (within a factor 4).
fn closes_as(held: &RunOutput, full: &RunOutput) {
    let (a, b) = (
        held.summary.energy_closure_rel,
        full.summary.energy_closure_rel,
    );
    assert!(a <= 4.0 * b, "closure {a:e}, the full model's {b:e}");
}

/// One DOF less, one mode less; the deck's x and y modes are single-column-law sway modes
/// k = Σ 2 k(h) of both directions (no torsion to couple y); the Rayleigh coefficients are the
/// full model's (its modes 1 and 3), and modes it does not have are refused as for it.
#[test]
fn a_translating_deck_has_one_mode_less_and_the_full_models_damping() {
    let full = load(FOUR_SPAN, &[]);
    let held = load(FOUR_SPAN, &["deck.rotation=false"]);
    assert_eq!((full.ndof(), held.ndof()), (7, 6));
    let (mf, mh) = (deckspin::modal::modes(&full), deckspin::modal::modes(&held));
    assert_eq!((mf.len(), mh.len()), (7, 6));
    let k = 9320.0;
    let sway: f64 = [1.83, 2.44, 1.52]
        .iter()
        .map(|h| 2.0 * k * (1.83f64 / h).powi(3))
        .sum();
    let t = 2.0 * std::f64::consts::PI * (140.5 / sway).sqrt();
    let deck = |s: &Scene, name: &str| s.dof_names.iter().position(|n| n == name).unwrap();
    for name in ["deck.x", "deck.y"] {
        let i = deck(&held, name);
        let m = (mh.iter())
            .find(|m| m.shape[i].abs() > 0.99 * m.shape.amax())
            .unwrap();
        assert_rel(m.period, t, 1e-10, name);
    }
    // the torsion springs of the six columns are gone, nothing else
    assert_eq!(full.springs.len() - held.springs.len(), 6);
    assert_eq!(full.mass_damping.alpha, held.mass_damping.alpha);
    for (a, b) in full.hysteretic.iter().zip(&held.hysteretic) {
        assert_eq!(a.damping, b.damping);
    }
    let set = |r: bool| format!("deck.rotation={r}");
    for r in [true, false] {
        let args = vec![set(r), "damping.modes=[1, 8]".to_string()];
        let e = deckspin::load(&model(FOUR_SPAN), &args).expect_err("mode 8");
        let e = e.to_string();
        assert!(e.contains("damping.modes") && e.contains("1..=7"), "{e}");
    }
}

/// A frame of a multi-frame bridge may translate too: its θ gone, the others' kept.
#[test]
fn one_frame_of_three_translates() {
    let full = load("models/three-frame.toml", &["solver.t_end=4.0"]);
    let held = load(
        "models/three-frame.toml",
        &["solver.t_end=4.0", "frame.1.rotation=false"],
    );
    assert_eq!(held.ndof() + 1, full.ndof());
    let body = held.bodies.iter().find(|b| b.name == "frame2").unwrap();
    assert_eq!(body.dofs[2], None);
    assert!(held.dof_names.iter().any(|n| n == "frame1.theta"));
    assert_eq!(full.mass_damping.alpha, held.mass_damping.alpha);
    let r = simulate(&held);
    assert!(r.summary.max_penetration < 1e-8);
    // measured 1.40e-5 against the full model's 1.46e-5
    closes_as(&r, &simulate(&full));
    let deck = DeckPeaks::of(&r);
    let theta = |n: &str| r.summary.peaks[r.dof(n).unwrap()].max_abs;
    assert_eq!(
        deck.rotation,
        theta("frame1.theta").max(theta("frame3.theta"))
    );
    let x = |n: &str| r.summary.peaks[r.dof(n).unwrap()].max_abs;
    assert_eq!(deck.x, x("frame1.x").max(x("frame2.x")).max(x("frame3.x")));
}
