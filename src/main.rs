//! `deckspin` command line: a thin layer over the library.

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "deckspin",
    version,
    about = "Nonsmooth seismic analysis of bridges whose decks pound their abutments and rotate in plan",
    args_conflicts_with_subcommands = true
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Open the workbench on this model.
    model: Option<PathBuf>,
}

#[derive(Subcommand)]
enum Command {
    /// Run a model and write history.csv, events.csv and summary.json.
    Run {
        model: PathBuf,
        /// Output directory.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Override a scalar by its dotted TOML path (key.path=value); repeatable.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Also print the state at this instant (velocities, contact states and forces).
        #[arg(long)]
        at: Option<f64>,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Some(Command::Run {
            model,
            out,
            set,
            at,
        }) => cmd_run(&model, &out, &set, at),
        None => match cli.model {
            Some(m) => deckspin::tui::run(&m),
            None => Err("no model given: `deckspin run MODEL.toml --out DIR` (see --help)".into()),
        },
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("deckspin: {e}");
            ExitCode::FAILURE
        }
    }
}

type CliResult = Result<(), Box<dyn std::error::Error>>;

fn cmd_run(model: &std::path::Path, out: &std::path::Path, set: &[String], at: Option<f64>) -> CliResult {
    let scene = deckspin::load(model, set)?;
    let run = deckspin::run(&scene, &mut deckspin::Silent)?;
    run.write_all(out)
        .map_err(|e| format!("{}: cannot write results: {e}", out.display()))?;
    let s = &run.summary;
    println!("{} — t = {:.3} s", s.title, s.t_end);
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
    println!(
        "  energy closure {:.3e} J (rel {:.3e}), max penetration {:.3e} m",
        s.energy_closure_abs, s.energy_closure_rel, s.max_penetration
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
    if let Some(t) = at {
        print_state_at(&run, t);
    }
    println!("  wrote {}/{{history.csv,events.csv,summary.json}}", out.display());
    Ok(())
}

fn print_state_at(run: &deckspin::RunOutput, t: f64) {
    let Some(s) = run
        .samples
        .iter()
        .min_by(|a, b| (a.t - t).abs().total_cmp(&(b.t - t).abs()))
    else {
        return;
    };
    println!("  state at t = {:.4} s (nearest sample to {t}):", s.t);
    for (i, n) in run.dof_names.iter().enumerate() {
        println!("    {n:<16} {:>13.6e}   rate {:>13.6e}", s.q[i], s.v[i]);
    }
    for (i, c) in s.contacts.iter().enumerate() {
        println!(
            "    contact {:<10} {:<7} g_N {:>11.4e}  λ_N {:>11.4e}  λ_T {:>11.4e}  ġ_T {:>11.4e}",
            run.contact_names[i],
            c.state.label(),
            c.gap,
            c.normal_force,
            c.tangential_force,
            c.slip_rate
        );
    }
}
