//! `deckspin bench`: one run of a model and the μ × runs sweep, timed by CPU clocks; with
//! `--instructions`, the instructions of `deckspin run MODEL --out DIR` counted by callgrind.

use clap::Args;
use deckspin::clock::{process_cpu_seconds, thread_cpu};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// Benchmark: one run of the model and the μ × runs sweep (medians).
#[derive(Args)]
pub struct BenchArgs {
    #[arg(default_value = "models/four-span.toml")]
    pub model: PathBuf,
    /// Repetitions of the single run.
    #[arg(long, default_value_t = 11)]
    pub repeat: usize,
    /// Repetitions of the sweep (0: the single run only).
    #[arg(long, default_value_t = 3)]
    pub sweeps: usize,
    /// Also count the instructions of `deckspin run MODEL --out DIR` (history written) under
    /// `valgrind --tool=callgrind`: the whole process and its integration.
    #[arg(long)]
    pub instructions: bool,
}

use super::CliResult;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn fastest(v: &[f64]) -> f64 {
    v.iter().copied().fold(f64::INFINITY, f64::min)
}

pub fn cmd_bench(a: &BenchArgs) -> CliResult {
    use deckspin::studies::{Axis, Study, run_count};
    // one read of the model and its records for the single run and the sweep
    let study = Study::open(&a.model, &[])?;
    let scene = deckspin::model::load_str_checked(&study.text, &a.model, &[], &study.motions)?;
    let scene = scene.scene;
    let (mut cpu, mut wall) = (Vec::new(), Vec::new());
    let mut steps = 0;
    for _ in 0..a.repeat.max(1) {
        let t0 = Instant::now();
        let (r, c) = thread_cpu(|| deckspin::run(&scene, &mut deckspin::Silent));
        wall.push(t0.elapsed().as_secs_f64());
        cpu.push(c);
        steps = r?.summary.stats.steps_accepted;
    }
    println!(
        "single run ({}): CPU median {:.1} ms over {} runs (fastest {:.1} ms; wall median {:.1} ms; {} steps)",
        scene.title,
        median(cpu.clone()) * 1e3,
        cpu.len(),
        fastest(&cpu) * 1e3,
        median(wall) * 1e3,
        steps
    );
    let n = run_count(&study.text);
    // `--sweeps 0`: the single run only
    if n > 0 && a.sweeps > 0 {
        let axes = [
            Axis {
                key: "contacts.mu".into(),
                values: (0..=7).map(|i| format!("{}", i as f64 / 10.0)).collect(),
            },
            Axis {
                key: "excitation.run".into(),
                values: (1..=n).map(|i| i.to_string()).collect(),
            },
        ];
        let (mut wall, mut cpu) = (Vec::new(), Vec::new());
        let mut integrations = 0;
        for _ in 0..a.sweeps {
            let (t0, c0) = (Instant::now(), process_cpu_seconds());
            let out = study.sweep_counted(&axes);
            wall.push(t0.elapsed().as_secs_f64());
            cpu.push(process_cpu_seconds() - c0);
            integrations = out.integrations;
            if let Some(e) = out.rows.iter().find_map(|r| r.error.clone()) {
                return Err(e.into());
            }
        }
        println!(
            "μ × runs sweep ({} runs, {integrations} integrated, {} threads): wall median {:.3} s over {} sweeps (fastest {:.3} s); process CPU median {:.3} s",
            8 * n,
            rayon::current_num_threads(),
            median(wall.clone()),
            wall.len(),
            fastest(&wall),
            median(cpu)
        );
    }
    if a.instructions {
        instructions(&a.model)?;
    }
    Ok(())
}

/// Counts the instructions of `deckspin run MODEL --out DIR` (DIR a temporary directory) under
/// callgrind, in all and inside `simulate::integrate`, and prints them.
fn instructions(model: &Path) -> CliResult {
    let exe = std::env::current_exe()?;
    let dir = std::env::temp_dir().join(format!("deckspin-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let count = |toggle: Option<&str>| -> Result<u64, Box<dyn std::error::Error>> {
        let mut cmd = Command::new("valgrind");
        cmd.arg("--tool=callgrind")
            .arg(format!(
                "--callgrind-out-file={}",
                dir.join("callgrind.out").display()
            ))
            .args(toggle.map(|t| format!("--toggle-collect={t}")))
            .arg(&exe)
            .arg("run")
            .arg(model)
            .arg("--out")
            .arg(dir.join("out"));
        let out = cmd.output().map_err(|e| format!("valgrind: {e}"))?;
        let err = String::from_utf8_lossy(&out.stderr);
        if !out.status.success() {
            return Err(format!("valgrind exited with {}: {err}", out.status).into());
        }
        collected(&err)
            .ok_or_else(|| format!("no instruction count in valgrind's output: {err}").into())
    };
    // the function's path as the compiler names it (its crate's, not this one's), exactly: a
    // pattern ending in `*` also matches a closure inside it (`integrate::{{closure}}`), on
    // whose entry callgrind toggles collection off, so that its instructions go uncounted
    let toggle = std::any::type_name_of_val(&deckspin::simulate::integrate).to_string();
    let counts = count(None).and_then(|all| Ok((all, count(Some(&toggle))?)));
    let _ = std::fs::remove_dir_all(&dir);
    let (all, integration) = counts?;
    if integration == 0 {
        return Err(format!("callgrind counted nothing inside {toggle}").into());
    }
    println!(
        "`deckspin run {} --out DIR` under callgrind: {:.1} M instructions, {:.1} M inside simulate::integrate (the run, history.csv written as it goes), {:.1} M the rest (setup, events.csv, summary.json)",
        model.display(),
        all as f64 * 1e-6,
        integration as f64 * 1e-6,
        all.saturating_sub(integration) as f64 * 1e-6
    );
    Ok(())
}

/// The count of callgrind's `==pid== Collected : N` line.
fn collected(stderr: &str) -> Option<u64> {
    stderr
        .lines()
        .find_map(|l| l.split_once("Collected :").map(|(_, n)| n.trim()))
        .and_then(|n| n.replace(',', "").parse().ok())
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_count_is_read_from_callgrinds_summary() {
        let err = "==12== Callgrind, a call-graph generating cache profiler\n==12== \n==12== Events    : Ir\n==12== Collected : 391478125\n==12== \n==12== I   refs:      391,478,125\n";
        assert_eq!(super::collected(err), Some(391_478_125));
        assert_eq!(super::collected("no count"), None);
    }
}
