//! `deckspin run`: a model's run streamed to its files, its report, the state at an instant.

use super::CliResult;

/// Run a model, streaming its history to `out/history.csv`; events.csv and summary.json
/// (with the run's status) are written however the run ends. Refused (exit 2) before it starts
/// when its output would exceed the budget.
pub fn cmd_run(
    model: &std::path::Path,
    out: &std::path::Path,
    set: &[String],
    at: Option<f64>,
) -> CliResult {
    use deckspin::run::{OutputBudget, RunFiles, Stop, check_output};
    let loaded = deckspin::model::load_checked(model, set)?;
    for w in &loaded.warnings {
        eprintln!("deckspin: warning: {w}");
    }
    let mut scene = loaded.scene;
    check_output(&scene, &OutputBudget::default())?;
    let cannot = |e: std::io::Error| format!("{}: cannot write results: {e}", out.display());
    // a step the method chose itself is refined while the judge finds the run outside its bounds
    let mut refinements = 0;
    let (run, written) = loop {
        if let Some(why) = &scene.settings.step_chosen {
            eprintln!("deckspin: {why}");
        }
        let mut files = RunFiles::create(out, &scene, at).map_err(cannot)?;
        files.stop_when(|| crate::cli::signals::requested().is_some());
        let run = deckspin::simulate::integrate(&scene, &mut files);
        if refinements < deckspin::simulate::MAX_REFINEMENTS
            && crate::cli::signals::requested().is_none()
            && let Some(next) = deckspin::simulate::refined(&scene, &run)
        {
            drop(files);
            refinements += 1;
            scene = next;
            continue;
        }
        let written = files.finish(&run).map_err(cannot)?;
        break (run, written);
    };
    print_report(&run.output.summary, &scene);
    if let (Some(t), Some(s)) = (at, &written.nearest) {
        print_state_at(&run.output, s, t);
    }
    let wrote = format!("{}/{{history.csv,events.csv,summary.json}}", out.display());
    match run.stop {
        Stop::Finished => {
            println!("  wrote {wrote}");
            Ok(())
        }
        // the reason goes to stderr once (main prints the error)
        Stop::Failed(e @ deckspin::run::SolverError::Inaccurate { .. }) => {
            println!("  finished outside the accuracy asked for (exit 3; why on stderr)");
            println!("  wrote {wrote}");
            Err(Box::new(e))
        }
        Stop::Failed(e) => {
            println!(
                "  failed at t = {:.9} s ({}; why on stderr)",
                e.time(),
                e.kind()
            );
            println!("  wrote {wrote} (up to t = {:.9} s)", e.time());
            Err(Box::new(e))
        }
        Stop::Cancelled { t } => {
            println!("  wrote {wrote} (up to t = {t:.9} s)");
            match crate::cli::signals::requested() {
                Some(signal) => Err(Box::new(crate::cli::signals::Interrupted { signal, t })),
                None => Err(format!("t = {t:.9} s: cancelled").into()),
            }
        }
    }
}

fn print_report(s: &deckspin::output::Summary, scene: &deckspin::scene::Scene) {
    println!(
        "{} — t = {:.3} s ({})",
        s.title,
        s.t_end,
        scene.settings.method.name()
    );
    println!(
        "  wall {:.1} ms, {} steps ({} rejected), {} RHS, {} LCPs",
        s.stats.wall_time * 1e3,
        s.stats.steps_accepted,
        s.stats.steps_rejected,
        s.stats.rhs_evals,
        s.stats.lcp_solves
    );
    println!(
        "  events: {} impact, {} stick, {} slip, {} release, {} accumulation",
        s.stats.impacts, s.stats.sticks, s.stats.slips, s.stats.releases, s.stats.accumulations
    );
    let controlled: usize = s.step_control.iter().map(|(_, c)| c).sum();
    if controlled > 0 {
        let top: Vec<String> = (s.step_control.iter().take(3))
            .map(|(name, c)| format!("{name} {:.0} %", 100.0 * *c as f64 / controlled as f64))
            .collect();
        println!("  step size set by: {}", top.join(", "));
    }
    let u = scene.units;
    println!(
        "  energy closure {:.3e} {} (rel {:.3e}; units {u}), max penetration {:.3e} {}",
        s.energy_closure_abs,
        u.unit(deckspin::units::Quantity::Energy),
        s.energy_closure_rel,
        s.max_penetration,
        u.unit(deckspin::units::Quantity::Length)
    );
    for p in &s.peaks {
        println!(
            "  peak |{}| = {:.6e} at t = {:.4} s (residual {:.6e})",
            p.name, p.max_abs, p.at, p.residual
        );
    }
    for (c, t) in &s.accumulation_times {
        println!("  accumulation of impacts at '{c}': t∞ ≈ {t:.9} s");
    }
    for k in s.key_failures.iter().flatten() {
        let (e, t, f) = (&k.element, k.t, k.peak_force);
        println!("  shear key '{e}' failed at t = {t:.9} s (peak force {f:.6e})");
    }
    for seat in &s.seats {
        let aashto = match (seat.required, seat.percent) {
            (Some(n), Some(p)) => format!("; AASHTO LRFD 4.7.4.4 N × {p} % = {n:.4} m"),
            _ => String::new(),
        };
        println!(
            "  seat at '{}': width {:.4} m, minimum margin {:.4} m at t = {:.4} s{aashto}",
            seat.contact, seat.width, seat.min_margin, seat.at
        );
    }
}

fn print_state_at(run: &deckspin::RunOutput, s: &deckspin::output::Sample, t: f64) {
    println!("  state at t = {:.4} s (nearest sample to {t}):", s.t);
    // columns as wide as the longest name
    let w = (run.dof_names.iter())
        .map(|n| n.chars().count())
        .max()
        .unwrap_or(0);
    for (i, n) in run.dof_names.iter().enumerate() {
        println!("    {n:<w$} {:>13.6e}   rate {:>13.6e}", s.q[i], s.v[i]);
    }
    let wc = (run.contact_names.iter())
        .map(|n| n.chars().count())
        .max()
        .unwrap_or(0);
    for (i, c) in s.contacts.iter().enumerate() {
        println!(
            "    contact {:<wc$} {:<7} g_N {:>11.4e}  λ_N {:>11.4e}  λ_T {:>11.4e}  ġ_T {:>11.4e}",
            run.contact_names[i],
            c.state.label(),
            c.gap,
            c.normal_force,
            c.tangential_force,
            c.slip_rate
        );
    }
}
