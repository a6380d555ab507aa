//! Hot paths: Lemke on the impact LCP of 4–12 contacts, an event-driven stretch of the bridge,
//! Moreau–Jean steps of the bridge. `cargo bench`.
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use deckspin::lemke::{LemkeOptions, lemke};
use nalgebra::{DMatrix, DVector};
use std::hint::black_box;
use std::path::Path;

/// Impact LCP (eq. 5) of n corners of a deck against walls, μ = 0.5: size 3n.
fn impact_lcp(n: usize) -> (DMatrix<f64>, DVector<f64>) {
    let mut text = String::from(
        "[[body]]\nname='deck'\nmass=140.5\ninertia=13090.0\ndofs=['x','y','theta']\n",
    );
    for i in 0..n {
        let y = -1.2 + 2.4 * i as f64 / (n.max(2) - 1) as f64;
        let x = if i % 2 == 0 { -16.1 } else { 16.1 };
        let nx = if i % 2 == 0 { 1.0 } else { -1.0 };
        text += &format!(
            "[[contact]]\nname='c{i}'\nbody='deck'\npoint=[{x},{y}]\nnormal=[{nx},0.0]\ngap=0.0\nmu=0.5\n"
        );
    }
    let scene = deckspin::model::load_str(&text, Path::new("bench.toml"), &[]).unwrap();
    let q = DVector::zeros(3);
    let v = DVector::from_vec(vec![-0.3, 0.2, 0.01]);
    let minv = scene.mass.map(|m| 1.0 / m);
    let kin: Vec<_> = scene
        .contacts
        .iter()
        .map(|c| scene.contact_kinematics(&scene.frame(0.0, &q, &v), c))
        .collect();
    let nc = kin.len();
    let m3 = 3 * nc;
    let g = |a: &DVector<f64>, b: &DVector<f64>| a.component_mul(&minv).dot(b);
    let mut m = DMatrix::zeros(m3, m3);
    let mut qv = DVector::zeros(m3);
    for i in 0..nc {
        for j in 0..nc {
            m[(i, j)] = g(&kin[i].w_n, &kin[j].w_n) - 0.5 * g(&kin[i].w_n, &kin[j].w_t);
            m[(i, nc + j)] = g(&kin[i].w_n, &kin[j].w_t);
            m[(nc + i, j)] = g(&kin[i].w_t, &kin[j].w_n) - 0.5 * g(&kin[i].w_t, &kin[j].w_t);
            m[(nc + i, nc + j)] = g(&kin[i].w_t, &kin[j].w_t);
        }
        m[(nc + i, 2 * nc + i)] = 1.0;
        m[(2 * nc + i, i)] = 1.0;
        m[(2 * nc + i, nc + i)] = -1.0;
        qv[i] = kin[i].gap_rate.min(-0.1);
        qv[nc + i] = kin[i].slip_rate;
    }
    (m, qv)
}

fn bench_lemke(c: &mut Criterion) {
    let mut group = c.benchmark_group("lemke impact LCP");
    for n in [4usize, 8, 12] {
        let (m, q) = impact_lcp(n);
        group.bench_with_input(
            BenchmarkId::from_parameter(format!("{n} contacts")),
            &n,
            |b, _| b.iter(|| lemke(black_box(&m), black_box(&q), &LemkeOptions::default()).ok()),
        );
    }
    group.finish();
}

fn bridge(set: &[&str]) -> deckspin::scene::Scene {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    deckspin::load(&root.join("models/four-span.toml"), &set).unwrap()
}

fn bench_steps(c: &mut Criterion) {
    // t = 4.5 … 4.6 s of run 4 is full of impacts; start there by running the first 0.1 s of a
    // shifted record is not possible, so bench the first 0.1 s (smooth) and a contact stretch
    let event = bridge(&["solver.t_end=0.1"]);
    c.bench_function("event-driven bridge, 0.1 s", |b| {
        b.iter(|| deckspin::simulate(black_box(&event), &mut deckspin::Silent).unwrap())
    });
    let moreau = bridge(&[
        "solver.method=\"moreau\"",
        "solver.step=0.001",
        "solver.t_end=0.1",
    ]);
    c.bench_function("Moreau–Jean bridge, 100 steps", |b| {
        b.iter(|| deckspin::simulate(black_box(&moreau), &mut deckspin::Silent).unwrap())
    });
    let full = bridge(&[]);
    let mut g = c.benchmark_group("full run");
    g.sample_size(10);
    g.bench_function("event-driven bridge run 4 (0.60 g), 16 s", |b| {
        b.iter(|| deckspin::simulate(black_box(&full), &mut deckspin::Silent).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench_lemke, bench_steps);
criterion_main!(benches);
