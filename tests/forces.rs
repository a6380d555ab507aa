//! The one smooth-force path every method uses (`ForceModel`: flattened, identical springs
//! merged, sums per body) against the plain element-by-element reference of eq. 1
//! (`smooth_forces_in`), at random states of every model: h, the ledger's power terms and the
//! element deformations agree to rounding.
mod common;

use deckspin::scene::{ForceModel, Scene, smooth_forces_in};
use nalgebra::DVector;
use proptest::prelude::*;

fn scenes() -> Vec<(String, Scene)> {
    let mut paths = vec![common::model("models/four-span.toml")];
    let mut validation: Vec<_> = std::fs::read_dir(common::model("models/validation"))
        .unwrap()
        .map(|e| e.unwrap().path())
        // the models only: the workbench keeps a model's runs beside it (`<stem>.runs/`)
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    validation.sort();
    paths.extend(validation);
    paths
        .into_iter()
        .map(|p| {
            let s = deckspin::load(&p, &[]).unwrap_or_else(|e| panic!("{e}"));
            (p.display().to_string(), s)
        })
        .collect()
}

/// Largest |a − b| relative to `scale` over the entries.
fn worst(a: &[f64], b: &[f64], scale: f64) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / scale.max(1e-300))
        .fold(0.0, f64::max)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn force_model_matches_the_plain_sum(
        t in 0.0f64..16.0,
        q in proptest::collection::vec(-0.05f64..0.05, 16),
        v in proptest::collection::vec(-1.0f64..1.0, 16),
    ) {
        for (name, scene) in scenes() {
            let n = scene.ndof();
            let q = DVector::from_column_slice(&q[..n]);
            let v = DVector::from_column_slice(&v[..n]);
            let laws: Vec<_> = scene.hysteretic.iter().map(|h| h.law.clone()).collect();
            let fr = scene.frame(t, &q, &v);
            let mut h_ref = DVector::zeros(n);
            let mut e_ref = vec![(0.0, 0.0); laws.len()];
            let p_ref = smooth_forces_in(&scene, Some(&laws), &fr, &v, &mut h_ref, Some(&mut e_ref));
            let model = ForceModel::new(&scene);
            let mut h = DVector::zeros(n);
            let mut e = vec![(0.0, 0.0); laws.len()];
            let p = model.eval(&scene, &laws, &fr, &v, &mut h, &mut e);
            // rounding of sums of terms up to the largest term: scale by Σ|h| of the reference
            let scale = h_ref.iter().map(|x| x.abs()).sum::<f64>().max(1.0);
            prop_assert!(worst(h.as_slice(), h_ref.as_slice(), scale) < 1e-13, "{name}: h {h} vs {h_ref}");
            let pw = [p.loads, p.supports, p.damping, p.hysteretic];
            let pw_ref = [p_ref.loads, p_ref.supports, p_ref.damping, p_ref.hysteretic];
            let pscale = pw_ref.iter().map(|x| x.abs()).sum::<f64>().max(1e-12);
            prop_assert!(worst(&pw, &pw_ref, pscale) < 1e-12, "{name}: power {pw:?} vs {pw_ref:?}");
            let flat = |e: &[(f64, f64)]| e.iter().flat_map(|&(a, b)| [a, b]).collect::<Vec<_>>();
            prop_assert!(worst(&flat(&e), &flat(&e_ref), 1.0) < 1e-15, "{name}: deformations");
            // the elastic energy of the springs, Σ ½ k e², both ways
            let u = model.spring_energy(&scene, &fr);
            let u_ref = scene.spring_energy(t, &q, &v);
            prop_assert!((u - u_ref).abs() <= 1e-12 * u_ref.abs().max(1e-12), "{name}: {u} vs {u_ref}");
        }
    }
}

/// The test can fail: a force model of another scene (stiffer springs) disagrees.
#[test]
fn a_different_force_model_is_caught() {
    let (_, scene) = scenes().remove(0);
    let mut stiffer = scene.clone();
    for s in &mut stiffer.springs {
        s.stiffness *= 1.001;
    }
    let n = scene.ndof();
    let q = DVector::from_fn(n, |i, _| 0.01 * (i as f64 + 1.0));
    let v = DVector::zeros(n);
    let laws: Vec<_> = scene.hysteretic.iter().map(|h| h.law.clone()).collect();
    let fr = scene.frame(1.0, &q, &v);
    let mut h_ref = DVector::zeros(n);
    smooth_forces_in(&scene, Some(&laws), &fr, &v, &mut h_ref, None);
    let mut h = DVector::zeros(n);
    let mut e = vec![(0.0, 0.0); laws.len()];
    ForceModel::new(&stiffer).eval(&stiffer, &laws, &fr, &v, &mut h, &mut e);
    let scale = h_ref.iter().map(|x| x.abs()).sum::<f64>();
    assert!(worst(h.as_slice(), h_ref.as_slice(), scale) > 1e-6);
}
