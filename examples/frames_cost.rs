//! The cost of a bridge of N frames in series: `models/three-frame.toml` with its frames, bents
//! and joints replaced by N frames of 40 m, one bent each (heights 8, 9, 10, 9, 8, … m), and
//! N − 1 joints of 25 mm. Prints steps, events, right-hand sides, the run's wall time and the
//! peak rotation of each body;
//! run it under `valgrind --tool=callgrind` for its instruction count.
//!
//!     cargo run --release --example frames_cost -- N [key=value …]

use std::fmt::Write as _;

/// The three-frame model with N frames in series.
fn n_frames(template: &str, n: usize) -> String {
    let mut doc: toml_edit::DocumentMut = template.parse().expect("the example model is TOML");
    doc.remove("frame");
    doc.remove("joint");
    let mut text = String::new();
    for k in 0..n {
        let h = [8.0, 9.0, 10.0, 9.0][k % 4];
        let _ = write!(
            text,
            "[[frame]]\nname = \"frame{}\"\nmass = 480.0\ninertia = 69760.0\nlength = 40.0\n\
             width = 12.0\nskew = 30.0\n\n[[frame.bent]]\nname = \"bent{}\"\nx = 0.0\n\
             height = {h}\n\n",
            k + 1,
            k + 1
        );
    }
    for _ in 1..n {
        text.push_str("[[joint]]\ngaps = [0.025, 0.025]\n\n");
    }
    format!("{doc}\n{text}")
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: usize = match args.first().map(|a| a.parse()) {
        Some(Ok(n)) if n >= 1 => n,
        _ => return Err("usage: frames_cost N [key=value …] (N ≥ 1)".into()),
    };
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = root.join("models/three-frame.toml");
    let text = n_frames(&std::fs::read_to_string(&path)?, n);
    let scene = deckspin::model::load_str(&text, &path, &args[1..])?;
    let start = std::time::Instant::now();
    let run = deckspin::simulate::integrate(&scene, &mut deckspin::Silent);
    let cpu = start.elapsed().as_secs_f64();
    let s = &run.output.stats;
    println!(
        "{n} frames: {} ({} DOFs), {} steps ({} rejected), {} events ({} impacts, {} column \
         branch events), {} RHS, {:.1} ms wall",
        run.stop.label(),
        scene.ndof(),
        s.steps_accepted,
        s.steps_rejected,
        s.events_located,
        s.impacts,
        s.branch_events,
        s.rhs_evals,
        cpu * 1e3
    );
    for p in run
        .output
        .summary
        .peaks
        .iter()
        .filter(|p| p.name.ends_with(".theta"))
    {
        println!("  {:<24} {:.9e} at {:.6}", p.name, p.max_abs, p.at);
    }
    Ok(())
}
