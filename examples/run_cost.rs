//! The cost of one run without history, the figure `docs/results.md` (speed) reports: loads
//! MODEL with `--set`-style overrides, runs it with `solver.keep_history = false`, and prints
//! steps, events, right-hand sides and every peak to 15 digits. Run it under
//! `valgrind --tool=callgrind --toggle-collect='deckspin_core::simulate::integrate'` for the
//! instruction count of the integration alone.
//!
//!     cargo run --release --example run_cost -- [MODEL] [key=value …]

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (model, set) = match args.first() {
        Some(a) if !a.contains('=') => (a.clone(), &args[1..]),
        _ => ("models/four-span.toml".to_string(), &args[..]),
    };
    let mut scene = deckspin::load(std::path::Path::new(&model), set)?;
    scene.settings.keep_history = false;
    let start = std::time::Instant::now();
    let run = deckspin::simulate::integrate(&scene, &mut deckspin::Silent);
    let wall = start.elapsed().as_secs_f64();
    let s = &run.output.stats;
    println!(
        "{}: {} steps ({} rejected), {} events ({} impacts, {} branch), {} RHS, {:.2} ms wall",
        run.stop.label(),
        s.steps_accepted,
        s.steps_rejected,
        s.events_located,
        s.impacts,
        s.branch_events,
        s.rhs_evals,
        wall * 1e3
    );
    let summary = &run.output.summary;
    for p in &summary.peaks {
        println!("  {:<24} {:.15e} at {:.9}", p.name, p.max_abs, p.at);
    }
    Ok(())
}
