//! `deckspin` command line: a thin layer over the library.

mod cli;

use clap::{Parser, Subcommand};
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
        model: PathBuf,
        /// Output directory.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Override a scalar by its dotted TOML path (key.path=value); repeatable.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Also print the state at this instant (velocities, contact states and forces).
        #[arg(long, value_parser = cli::finite_time)]
        at: Option<f64>,
        /// Integration method (default: the model's).
        #[arg(long, help = format!("Integration method: {} (default: the model's)", Method::names(", ")))]
        method: Option<String>,
    },
    /// Eigen-analysis of the initial system: periods and mode shapes.
    Modes {
        model: PathBuf,
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
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
        /// `pga`: peak rotation against PGA (Fig. 7); `mu`: its increase against μ (Fig. 8).
        #[arg(value_parser = ["pga", "mu"])]
        kind: String,
        model: PathBuf,
        /// Override a scalar by its dotted TOML path (key.path=value); repeatable.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Output directory: the study's table as TEXT and CSV and its chart as SVG.
        #[arg(long, default_value = "out")]
        out: PathBuf,
    },
    /// Work–precision: CPU time against error for each method and knob.
    Precision {
        model: PathBuf,
        /// Comma-separated method names.
        #[arg(long, default_value_t = Method::names(","), help = format!("Comma-separated: {}", Method::names(",")))]
        methods: String,
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Fewer knob values.
        #[arg(long)]
        quick: bool,
        /// Error measure for the chart and the 1 % summary: peak, rms, impact
        /// (default: peak for a rotation, rms otherwise).
        #[arg(long)]
        metric: Option<String>,
        #[arg(long, default_value = "out")]
        out: PathBuf,
    },
    /// Where each method fails: method × knob → ok / unstable / inaccurate.
    Stability {
        model: PathBuf,
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
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
            model,
            out,
            mut set,
            at,
            method,
        }) => {
            if let Some(m) = method {
                if deckspin::methods::Method::parse(&m).is_none() {
                    let names = deckspin::methods::Method::names(", ");
                    eprintln!("deckspin: --method '{m}': unknown method ({names})");
                    return ExitCode::from(2);
                }
                set.push(format!("solver.method=\"{m}\""));
            }
            cmd_run(&model, &out, &set, at)
        }
        Some(Command::Modes { model, set }) => cmd_modes(&model, &set),
        Some(Command::Excitation {
            file,
            target_pga,
            time_scale,
            lag,
            baseline,
            csv,
        }) => cmd_excitation(&file, target_pga, time_scale, lag, baseline, csv.as_deref()),
        Some(Command::Sweep(a)) => cli::sweep::cmd_sweep(&a),
        Some(Command::Study {
            kind,
            model,
            set,
            out,
        }) => cmd_study(&kind, &model, &set, &out),
        Some(Command::Precision {
            model,
            methods,
            set,
            quick,
            metric,
            out,
        }) => cmd_precision(&model, &methods, &set, quick, metric, &out),
        Some(Command::Stability {
            model,
            set,
            tolerance,
            quick,
            out,
        }) => cmd_stability(&model, &set, tolerance, quick, &out),
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
            exit_code(e.as_ref())
        }
    }
}

/// 2 for a job refused before it starts (its output or its number of runs above a limit),
/// else 1.
fn exit_code(e: &(dyn std::error::Error + 'static)) -> ExitCode {
    use deckspin::suite::SuiteError;
    if let Some(i) = e.downcast_ref::<cli::signals::Interrupted>() {
        return ExitCode::from((128 + i.signal).clamp(0, 255) as u8);
    }
    if let Some(i) = e.downcast_ref::<cli::jobs::JobInterrupted>() {
        return ExitCode::from((128 + i.signal).clamp(0, 255) as u8);
    }
    // a run that finished outside its accuracy bounds is told apart from a failure
    if let Some(deckspin::run::SolverError::Inaccurate { .. }) =
        e.downcast_ref::<deckspin::run::SolverError>()
    {
        return ExitCode::from(3);
    }
    let suite_too_large =
        (e.downcast_ref::<SuiteError>()).is_some_and(|s| matches!(s, SuiteError::TooLarge(_)));
    if e.is::<deckspin::run::LimitError>()
        || e.is::<deckspin::studies::SweepTooLarge>()
        || suite_too_large
    {
        ExitCode::from(2)
    } else {
        ExitCode::FAILURE
    }
}

type CliResult = Result<(), Box<dyn std::error::Error>>;

/// Run a model, streaming its history to `out/history.csv`; events.csv and summary.json
/// (with the run's status) are written however the run ends. Refused (exit 2) before it starts
/// when its output would exceed the budget.
fn cmd_run(
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
        files.stop_when(|| cli::signals::requested().is_some());
        let run = deckspin::simulate::integrate(&scene, &mut files);
        if refinements < deckspin::simulate::MAX_REFINEMENTS
            && cli::signals::requested().is_none()
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
            match cli::signals::requested() {
                Some(signal) => Err(Box::new(cli::signals::Interrupted { signal, t })),
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

fn cmd_modes(model: &std::path::Path, set: &[String]) -> CliResult {
    let scene = deckspin::load(model, set)?;
    let modes = deckspin::modal::modes(&scene);
    print!("{}", cli::tables::modes_table(&scene, &modes));
    Ok(())
}

fn cmd_excitation(
    file: &std::path::Path,
    target_pga: Option<f64>,
    time_scale: f64,
    lag: f64,
    baseline: usize,
    csv: Option<&std::path::Path>,
) -> CliResult {
    use deckspin::excitation::{Baseline, GroundMotion, Processing, read_any};
    let rec = read_any(file)?;
    let p = Processing {
        target_pga,
        time_scale,
        lag,
        baseline: if baseline == 0 {
            Baseline::None
        } else {
            Baseline::Polynomial { order: baseline }
        },
        ..Processing::default()
    };
    let g = GroundMotion::from_record(&rec, &p)?;
    let s = g.stats();
    for h in &rec.header {
        println!("  | {h}");
    }
    println!(
        "{}: {} samples, dt = {} s (processed {} s)",
        file.display(),
        rec.accel_g.len(),
        rec.dt,
        g.dt
    );
    println!(
        "  PGA {:.4} g ({:.4} m/s²)   PGV {:.4} m/s   PGD {:.4} m",
        s.pga_g, s.pga, s.pgv, s.pgd
    );
    println!(
        "  duration {:.3} s, 5–95 % Arias duration {:.3} s, lag {:.3} s",
        s.duration, s.significant_duration, lag
    );
    println!(
        "  end drift: displacement {:.3e} m, velocity {:.3e} m/s (baseline change of PGA {:.2e})",
        s.final_displacement, s.final_velocity, s.correction_pga_change
    );
    if let Some(path) = csv {
        let mut w = csv::Writer::from_path(path)?;
        w.write_record(["t", "acc_m_s2", "vel_m_s", "disp_m"])?;
        for t in g.sample_times() {
            let (d, v, a) = g.at(t);
            w.write_record([t, a, v, d].map(|x| format!("{x:.9e}")))?;
        }
        w.flush()?;
        println!("  wrote {}", path.display());
    }
    Ok(())
}

fn cmd_study(
    kind: &str,
    model: &std::path::Path,
    set: &[String],
    out: &std::path::Path,
) -> CliResult {
    use deckspin::studies::Study;
    use std::fmt::Write as _;
    let study = Study::open(model, set)?;
    std::fs::create_dir_all(out)?;
    // one job writes this folder at a time
    let _lock = deckspin::output::files::FolderLock::acquire(out)?;
    let t0 = std::time::Instant::now();
    let bar = cli::progress::Bar::new();
    let (mut text, csv, figure) = match kind {
        "pga" => {
            let rows = deckspin::studies::rotation_vs_pga(&study, &bar);
            let (text, csv) = cli::tables::pga_table(&rows, "")?;
            (text, csv, deckspin::figures::rotation_vs_pga(&rows))
        }
        _ => {
            let mus = deckspin::studies::fig8_mus();
            let m = deckspin::studies::increase_vs_mu(&study, &mus, &bar);
            let runs: Vec<usize> = (1..=m.rows.len()).collect();
            let (text, csv) = cli::tables::mu_table(&m, &runs, "")?;
            (text, csv, deckspin::figures::increase_vs_mu(&m, &runs))
        }
    };
    bar.clear();
    writeln!(
        text,
        "({:.2} s wall on {} threads)",
        t0.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    )?;
    print!("{text}");
    let stem = if kind == "pga" {
        "rotation_vs_pga"
    } else {
        "increase_vs_mu"
    };
    deckspin::output::files::write_atomic(out.join(format!("{stem}.csv")), csv)?;
    deckspin::output::files::write_atomic(out.join(format!("{stem}.txt")), text)?;
    cli::show::chart(&figure, &out.join(format!("{stem}.svg")))?;
    println!("wrote {}/{stem}.{{csv,txt,svg}}", out.display());
    Ok(())
}

fn precision_points(
    model: &std::path::Path,
    methods: &[Method],
    set: &[String],
    quick: bool,
) -> Result<
    (
        deckspin::precision::Reference,
        Vec<deckspin::precision::Point>,
    ),
    Box<dyn std::error::Error>,
> {
    use deckspin::precision::{Bench, knobs};
    use deckspin::progress::Progress;
    let bench = Bench::open(model, set)?;
    let scene = bench.study.scene(&[])?;
    // every run of the study keeps its history in memory
    deckspin::run::check_memory(&scene)?;
    let (t_end, k) = (scene.settings.t_end, scene.settings.contact_stiffness);
    let plan: Vec<_> = (methods.iter())
        .flat_map(|&m| knobs(m, t_end, k, quick).into_iter().map(move |x| (m, x)))
        .collect();
    let bar = cli::progress::Bar::new();
    bar.plan(plan.len() + 1);
    let reference = bench.reference(1e-10)?;
    bar.done(1);
    bar.note(&format!(
        "reference: event-driven, rtol 1e-10: peak |{}| = {:.9e}",
        reference.run.dof_names[reference.dof], reference.peak
    ));
    let mut points = Vec::new();
    for (m, (label, ov)) in plan {
        let p = bench.measure(&reference, m, &label, &ov);
        bar.done(1);
        bar.note(&format!(
            "  {m:<17} {label:<22} {:>10.4} s  peak err {:.3e}  {}",
            p.cpu_s,
            p.peak_error,
            status(&p)
        ));
        points.push(p);
    }
    bar.clear();
    Ok((reference, points))
}

/// The point's verdict as `stability` gives it (ok / inaccurate above
/// [`deckspin::precision::INACCURATE_ABOVE`] / unstable / failed), one legend for both.
fn status(p: &deckspin::precision::Point) -> String {
    deckspin::precision::verdict(p, deckspin::precision::INACCURATE_ABOVE).to_string()
}

fn cmd_precision(
    model: &std::path::Path,
    methods: &str,
    set: &[String],
    quick: bool,
    metric: Option<String>,
    out: &std::path::Path,
) -> CliResult {
    use deckspin::precision::{cheapest_within, write_csv};
    let methods = (methods.split(',').map(|s| s.trim()))
        .map(|m| Method::parse(m).ok_or_else(|| format!("unknown method '{m}'")))
        .collect::<Result<Vec<_>, _>>()?;
    std::fs::create_dir_all(out)?;
    // one job writes this folder at a time
    let _lock = deckspin::output::files::FolderLock::acquire(out)?;
    let (reference, points) = precision_points(model, &methods, set, quick)?;
    let metric = metric.unwrap_or_else(|| {
        if reference.run.dof_names[reference.dof].ends_with("theta") {
            "peak".into()
        } else {
            "rms".into()
        }
    });
    if !["peak", "rms", "impact"].contains(&metric.as_str()) {
        return Err(format!("unknown metric '{metric}' (peak, rms, impact)").into());
    }
    let stem = model
        .file_stem()
        .map_or("model".into(), |s| s.to_string_lossy().into_owned());
    let csv = out.join(format!("precision-{stem}.csv"));
    write_csv(&points, &csv)?;
    let mut text = String::new();
    text += &format!(
        "{:<17} {:<22} {:>10} {:>11} {:>11} {:>11} {:>8}  status\n",
        "method", "knob", "cpu s", "peak err", "rms err", "t1 err s", "steps"
    );
    for p in &points {
        text += &format!(
            "{:<17} {:<22} {:>10.4} {:>11.3e} {:>11.3e} {:>11.3e} {:>8}  {}\n",
            p.method,
            p.knob,
            p.cpu_s,
            p.peak_error,
            p.rms_error,
            p.impact_time_error,
            p.steps,
            status(p)
        );
    }
    text += "\n";
    text += &format!("watched: {}\n", reference.run.dof_names[reference.dof]);
    let tol = if metric == "impact" { 1e-3 } else { 0.01 };
    text += &format!("\ncheapest run within {tol} ({metric} error):\n");
    let event = cheapest_within(&points, Method::Event, &metric, tol).map(|p| p.cpu_s);
    for &m in &methods {
        match cheapest_within(&points, m, &metric, tol) {
            Some(p) => {
                let ratio =
                    event.map_or(String::new(), |e| format!(" ({:.1} × event)", p.cpu_s / e));
                text += &format!("  {m:<17} {:<22} {:.4} s{ratio}\n", p.knob, p.cpu_s)
            }
            None => text += &format!("  {m:<17} none of the tried knobs reaches it\n"),
        }
    }
    print!("{text}");
    let figure = deckspin::figures::work_precision(&points, &metric, tol);
    text += "\n";
    text += &deckspin::plot::text::render(&figure, 80, 30);
    deckspin::output::files::write_atomic(out.join(format!("precision-{stem}.txt")), &text)?;
    cli::show::chart(&figure, &out.join(format!("precision-{stem}.svg")))?;
    println!("wrote {} and .txt, .svg", csv.display());
    Ok(())
}

fn cmd_stability(
    model: &std::path::Path,
    set: &[String],
    tolerance: f64,
    quick: bool,
    out: &std::path::Path,
) -> CliResult {
    use deckspin::precision::verdict;
    std::fs::create_dir_all(out)?;
    // one job writes this folder at a time
    let _lock = deckspin::output::files::FolderLock::acquire(out)?;
    let (_, points) = precision_points(model, &Method::ALL, set, quick)?;
    println!(
        "{:<17} {:<22} verdict (inaccurate above {:.0} % peak or history error)",
        "method",
        "knob",
        tolerance * 100.0
    );
    for p in &points {
        println!("{:<17} {:<22} {}", p.method, p.knob, verdict(p, tolerance));
    }
    let stem = model
        .file_stem()
        .map_or("model".into(), |s| s.to_string_lossy().into_owned());
    let path = out.join(format!("stability-{stem}.svg"));
    cli::show::grid(&deckspin::figures::stability(&points, tolerance), &path)?;
    // the grid's numbers: one line per method and knob
    let mut n = deckspin::output::number::Numbers::new();
    let mut csv = deckspin::shard::csv_line(&[
        "method",
        "knob",
        "verdict",
        "peak_error",
        "history_error",
        "steps",
        "cpu_s",
        "reason",
    ]);
    for p in &points {
        let v = verdict(p, tolerance);
        let word = v.to_string();
        let word = word
            .split([' ', ':'])
            .next()
            .unwrap_or_default()
            .to_string();
        csv += &deckspin::shard::csv_line(&[
            p.method.name().to_string(),
            p.knob.clone(),
            word,
            n.format(p.peak_error).to_string(),
            n.format(p.rms_error).to_string(),
            p.steps.to_string(),
            n.format(p.cpu_s).to_string(),
            p.failure.as_ref().map_or(String::new(), |f| f.to_string()),
        ]);
    }
    let csv_path = out.join(format!("stability-{stem}.csv"));
    deckspin::output::files::write_atomic(&csv_path, csv)?;
    println!("wrote {}, {}", path.display(), csv_path.display());
    Ok(())
}
