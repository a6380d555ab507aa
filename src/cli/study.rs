//! `deckspin study`, `precision` and `stability`: the paper's studies, work–precision and the
//! stability grid, their tables, CSVs and charts.

use super::CliResult;
use super::args::StudyKind;
use deckspin::methods::Method;

/// The study `kind` of the model: its table printed, its CSV, text and SVG in `out`.
pub fn cmd_study(
    kind: StudyKind,
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
    let bar = crate::cli::progress::Bar::new();
    let (mut text, csv, figure) = match kind {
        StudyKind::Pga => {
            let rows = deckspin::studies::rotation_vs_pga(&study, &bar);
            let (text, csv) = crate::cli::tables::pga_table(&rows, "")?;
            (text, csv, deckspin::figures::rotation_vs_pga(&rows))
        }
        StudyKind::Mu => {
            let mus = deckspin::studies::fig8_mus();
            let m = deckspin::studies::increase_vs_mu(&study, &mus, &bar);
            let runs: Vec<usize> = (1..=m.rows.len()).collect();
            let (text, csv) = crate::cli::tables::mu_table(&m, &runs, "")?;
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
    let stem = match kind {
        StudyKind::Pga => "rotation_vs_pga",
        StudyKind::Mu => "increase_vs_mu",
    };
    deckspin::output::files::write_atomic(out.join(format!("{stem}.csv")), csv)?;
    deckspin::output::files::write_atomic(out.join(format!("{stem}.txt")), text)?;
    crate::cli::show::chart(&figure, &out.join(format!("{stem}.svg")))?;
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
    let bar = crate::cli::progress::Bar::new();
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

/// Work–precision of `methods` on the model against an event-driven reference at rtol 1e-10.
pub fn cmd_precision(
    model: &std::path::Path,
    methods: &[Method],
    set: &[String],
    quick: bool,
    metric: Option<String>,
    out: &std::path::Path,
) -> CliResult {
    use deckspin::precision::{cheapest_within, write_csv};
    std::fs::create_dir_all(out)?;
    // one job writes this folder at a time
    let _lock = deckspin::output::files::FolderLock::acquire(out)?;
    let (reference, points) = precision_points(model, methods, set, quick)?;
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
    for &m in methods {
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
    crate::cli::show::chart(&figure, &out.join(format!("precision-{stem}.svg")))?;
    println!("wrote {} and .txt, .svg", csv.display());
    Ok(())
}

/// Where each method fails over its knob: the grid as text and SVG.
pub fn cmd_stability(
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
    crate::cli::show::grid(&deckspin::figures::stability(&points, tolerance), &path)?;
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
