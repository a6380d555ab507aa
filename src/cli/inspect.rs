//! `deckspin modes` and `deckspin excitation`: a model's modes and a processed record, without
//! a run.

use super::CliResult;

/// The modes of a model's initial system as a table.
pub fn cmd_modes(model: &std::path::Path, set: &[String]) -> CliResult {
    let scene = deckspin::load(model, set)?;
    let modes = deckspin::modal::modes(&scene);
    print!("{}", crate::cli::tables::modes_table(&scene, &modes));
    Ok(())
}

/// A record as processed (PGA, PGV, PGD, durations, end drift); its t, a, v, d to `csv`.
pub fn cmd_excitation(
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
