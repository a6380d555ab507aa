//! `deckspin` command line: a thin layer over the library.

mod cli;

use clap::{Parser, Subcommand};
use cli::args::{MethodArg, ModelArgs, StudyKind};
use deckspin::methods::Method;
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
    /// The workbench's characters: `ascii` (nothing above 0x7E) or `unicode` (Braille charts,
    /// box drawing). Default: DECKSPIN_GLYPHS if set, else from TERM (dumb, linux, vt100,
    /// vt102, vt220, ansi: ascii; others: unicode). The `m` key toggles them.
    #[arg(long, value_name = "ascii|unicode", value_parser = ["ascii", "unicode"], ignore_case = true)]
    #[cfg_attr(not(feature = "workbench"), allow(dead_code))]
    glyphs: Option<String>,
    /// Open the workbench without running the model (a kept run of the same model text is
    /// shown; `r` runs it).
    #[arg(long)]
    no_run: bool,
}

#[derive(Subcommand)]
enum Command {
    /// Run a model and write history.csv (streamed), events.csv and summary.json, also when
    /// the run fails (summary.json's "status" says how it ended).
    Run {
        #[command(flatten)]
        model: ModelArgs,
        /// Output directory.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Also print the state at this instant (velocities, contact states and forces).
        #[arg(long, value_parser = cli::finite_time)]
        at: Option<f64>,
        /// Integration method (default: the model's).
        #[arg(long)]
        method: Option<MethodArg>,
    },
    /// Eigen-analysis of the initial system: periods and mode shapes.
    Modes {
        #[command(flatten)]
        model: ModelArgs,
    },
    /// Show what a processed excitation looks like (PGA, PGV, PGD, duration).
    Excitation {
        /// AT2 or two-column record.
        file: PathBuf,
        /// Scale to this PGA (g).
        #[arg(long)]
        target_pga: Option<f64>,
        /// Time scale (quarter-scale similitude: 0.5).
        #[arg(long, default_value_t = 1.0)]
        time_scale: f64,
        /// Time lag, s.
        #[arg(long, default_value_t = 0.0)]
        lag: f64,
        /// Polynomial baseline order (0: no correction).
        #[arg(long, default_value_t = 3)]
        baseline: usize,
        /// Write t, a, v, d to this CSV.
        #[arg(long)]
        csv: Option<PathBuf>,
    },
    /// Run a model over every combination of swept scalars, in parallel (at most 100 000).
    Sweep(cli::sweep::SweepArgs),
    /// The paper's studies: `pga` (Fig. 7) or `mu` (Fig. 8).
    Study {
        /// Which study.
        kind: StudyKind,
        #[command(flatten)]
        model: ModelArgs,
        /// Output directory: the study's table as TEXT and CSV and its chart as SVG.
        #[arg(long, default_value = "out")]
        out: PathBuf,
    },
    /// Work–precision: CPU time against error for each method and knob.
    Precision {
        #[command(flatten)]
        model: ModelArgs,
        /// Comma-separated methods (default: all).
        #[arg(long, value_delimiter = ',')]
        methods: Vec<MethodArg>,
        /// Fewer knob values.
        #[arg(long)]
        quick: bool,
        /// Error measure for the chart and the 1 % summary (default: peak for a rotation, rms
        /// otherwise).
        #[arg(long, value_parser = ["peak", "rms", "impact"])]
        metric: Option<String>,
        #[arg(long, default_value = "out")]
        out: PathBuf,
    },
    /// Where each method fails: method × knob → ok / unstable / inaccurate.
    Stability {
        #[command(flatten)]
        model: ModelArgs,
        /// Peak error above this counts as inaccurate.
        #[arg(long, default_value_t = deckspin::precision::INACCURATE_ABOVE)]
        tolerance: f64,
        #[arg(long)]
        quick: bool,
        /// Output directory of the grid's SVG (stability-MODEL.svg).
        #[arg(long, default_value = "out")]
        out: PathBuf,
    },
    /// Benchmark: one run of the model and the μ × runs sweep (CPU medians).
    Bench(cli::bench::BenchArgs),
    /// Stress test: the bridge under every record pair of a folder × runs × ε × μ × column law.
    Stress(cli::stress::StressArgs),
    /// Runs of a bridge file in sequence, each from the final state of the one before.
    Sequence(cli::sequence::SequenceArgs),
    /// Before any run: what the impact law says of the model's corners and ends, where over
    /// L/B × skew a deck rotates; `--equivalence`: which gap element reproduces it.
    Screen(cli::screen::ScreenArgs),
    /// A record suite (incremental dynamic analysis): the bridge under every record pair
    /// scaled to each intensity level, × optional swept scalars.
    Suite(cli::suite::SuiteArgs),
    /// Which uncertain inputs the answer is most sensitive to: a tornado of swings.
    Sensitivity(cli::sensitivity::SensitivityArgs),
    /// Join the part files of a sharded `suite`, `sweep` or `sensitivity` into its output.
    Merge(cli::merge::MergeArgs),
    /// Fragility curves of a record suite's per-run CSV: lognormal, maximum likelihood,
    /// bootstrap band.
    Fragility(cli::fragility::FragilityArgs),
    /// Which simplifications of a bridge model are safe for its runs: the model ladder, each
    /// variant's error per quantity and cost, the cheapest within a tolerance (`--write`).
    Adequacy(cli::adequacy::AdequacyArgs),
}

fn main() -> ExitCode {
    // a closed pipe (`deckspin bench | head -1`) ends the process quietly, as for other tools,
    // instead of a panic in println!
    #[cfg(unix)]
    // SAFETY: restoring the default disposition of SIGPIPE before any thread starts.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    cli::stdout::quiet_on_failed_output();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return cli::stdout::clap_exit(&e),
    };
    if matches!(
        cli.command,
        Some(
            Command::Run { .. }
                | Command::Sequence(_)
                | Command::Suite(_)
                | Command::Sweep(_)
                | Command::Stress(_)
                | Command::Adequacy(_)
                | Command::Sensitivity(_)
        )
    ) {
        cli::signals::install();
    }
    let result = match cli.command {
        Some(Command::Run {
            model: ModelArgs { path, mut set },
            out,
            at,
            method,
        }) => {
            if let Some(MethodArg(m)) = method {
                set.push(format!("solver.method=\"{}\"", m.name()));
            }
            cli::run::cmd_run(&path, &out, &set, at)
        }
        Some(Command::Modes { model: m }) => cli::inspect::cmd_modes(&m.path, &m.set),
        Some(Command::Excitation {
            file,
            target_pga,
            time_scale,
            lag,
            baseline,
            csv,
        }) => cli::inspect::cmd_excitation(
            &file,
            target_pga,
            time_scale,
            lag,
            baseline,
            csv.as_deref(),
        ),
        Some(Command::Sweep(a)) => cli::sweep::cmd_sweep(&a),
        Some(Command::Study {
            kind,
            model: m,
            out,
        }) => cli::study::cmd_study(kind, &m.path, &m.set, &out),
        Some(Command::Precision {
            model: m,
            methods,
            quick,
            metric,
            out,
        }) => {
            let methods: Vec<Method> = if methods.is_empty() {
                Method::ALL.to_vec()
            } else {
                methods.into_iter().map(|MethodArg(m)| m).collect()
            };
            cli::study::cmd_precision(&m.path, &methods, &m.set, quick, metric, &out)
        }
        Some(Command::Stability {
            model: m,
            tolerance,
            quick,
            out,
        }) => cli::study::cmd_stability(&m.path, &m.set, tolerance, quick, &out),
        Some(Command::Bench(a)) => cli::bench::cmd_bench(&a),
        Some(Command::Stress(a)) => cli::stress::cmd_stress(&a),
        Some(Command::Sequence(a)) => cli::sequence::cmd_sequence(&a),
        Some(Command::Screen(a)) => cli::screen::cmd_screen(&a),
        Some(Command::Suite(a)) => cli::suite::cmd_suite(&a),
        Some(Command::Sensitivity(a)) => cli::sensitivity::cmd_sensitivity(&a),
        Some(Command::Merge(a)) => cli::merge::cmd_merge(&a),
        Some(Command::Fragility(a)) => cli::fragility::cmd_fragility(&a),
        Some(Command::Adequacy(a)) => cli::adequacy::cmd_adequacy(&a),
        None => match cli.model {
            #[cfg(feature = "workbench")]
            Some(m) => {
                let glyphs = cli
                    .glyphs
                    .as_deref()
                    .and_then(deckspin::tui::term::Glyphs::parse);
                deckspin::tui::run(&m, glyphs, !cli.no_run)
            }
            #[cfg(not(feature = "workbench"))]
            Some(_) => Err(
                "this deckspin was built without the workbench (cargo feature `workbench`)".into(),
            ),
            None => Err("no model given: `deckspin run MODEL.toml --out DIR` (see --help)".into()),
        },
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("deckspin: {e}");
            cli::exit::exit_code(e.as_ref())
        }
    }
}
