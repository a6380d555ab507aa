//! `deckspin sequence`: the `[[run]]` tables of a bridge file in one sequence, each run from
//! the final state of the one before (`sequence` module).

use super::tables::{mu_table, pga_table};
use clap::Args;
use deckspin::run::{OutputBudget, RunFiles, check_output};
use deckspin::sequence::{BridgeSequence, Sequence, csv, table};
use std::path::{Path, PathBuf};

use super::CliResult;
use super::args::StudyKind;

/// Runs of a bridge file in sequence, each from the final state of the one before.
#[derive(Args)]
pub struct SequenceArgs {
    #[command(flatten)]
    pub model: super::args::ModelArgs,
    /// Runs of the model's [[run]] tables, in order: `a..b` (inclusive) or `a,b,c` (default:
    /// all).
    #[arg(long)]
    pub runs: Option<String>,
    /// Output directory: DIR/runK/{history.csv,events.csv,summary.json} per run and
    /// DIR/sequence.csv.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Instead: the Fig. 7 (`pga`) or Fig. 8 (`mu`) analog with the runs in sequence
    /// (DIR/sequence_rotation_vs_pga.{csv,txt,svg} or DIR/sequence_increase_vs_mu.{csv,txt,svg}).
    #[arg(long)]
    pub study: Option<super::args::StudyKind>,
}

pub fn cmd_sequence(a: &SequenceArgs) -> CliResult {
    let model = BridgeSequence::open(&a.model.path, &a.model.set)?;
    let runs = model.parse_runs(a.runs.as_deref())?;
    std::fs::create_dir_all(&a.out)?;
    // one job writes this folder at a time
    let _lock = deckspin::output::files::FolderLock::acquire(&a.out)?;
    if let Some(kind) = a.study {
        return study(&model, &runs, kind, &a.out);
    }
    let mut seq = Sequence::new();
    let mut error = None;
    for &k in &runs {
        if let Err(e) = one_run(&model, &mut seq, k, &a.out.join(format!("run{k}"))) {
            error = Some(e);
            break;
        }
    }
    let rows = model.rows(&seq, &runs);
    print!("{}", table(&rows));
    let path = a.out.join("sequence.csv");
    deckspin::output::files::write_atomic(&path, csv(&rows))?;
    println!(
        "wrote {}/run{{{}}}/{{history.csv,events.csv,summary.json}} and {}",
        a.out.display(),
        (seq.runs.iter().zip(&runs))
            .map(|(_, k)| k.to_string())
            .collect::<Vec<_>>()
            .join(","),
        path.display()
    );
    error.map_or(Ok(()), Err)
}

/// Run `k` of the sequence, streamed to `dir`; its files are written however it ends.
fn one_run(model: &BridgeSequence, seq: &mut Sequence, k: usize, dir: &Path) -> CliResult {
    let stage = model.stage(k, &[])?;
    let name = stage.name.clone();
    let scene = seq.prepare(stage)?;
    check_output(&scene, &OutputBudget::default())?;
    let cannot = |e: std::io::Error| format!("{}: cannot write results: {e}", dir.display());
    let mut files = RunFiles::create(dir, &scene, None).map_err(cannot)?;
    files.stop_when(|| super::signals::requested().is_some());
    let result = seq.run(&name, &scene, &mut files);
    if let Some(last) = seq.runs.last() {
        files.finish(&last.run).map_err(cannot)?;
    }
    Ok(result?)
}

/// `--study pga|mu`: the Fig. 7 or Fig. 8 analog of the sequence.
fn study(model: &BridgeSequence, runs: &[usize], kind: StudyKind, out: &Path) -> CliResult {
    let t0 = std::time::Instant::now();
    let note = " — runs in one sequence";
    let (mut text, csv, figure) = match kind {
        StudyKind::Pga => {
            let rows = model.rotation_vs_pga(runs);
            let (text, csv) = pga_table(&rows, note)?;
            (text, csv, deckspin::figures::rotation_vs_pga(&rows))
        }
        StudyKind::Mu => {
            let mus: Vec<f64> = (0..=7).map(|i| i as f64 / 10.0).collect();
            let m = model.increase_vs_mu(&mus, runs);
            let (text, csv) = mu_table(&m, runs, note)?;
            (text, csv, deckspin::figures::increase_vs_mu(&m, runs))
        }
    };
    text += &format!(
        "({:.2} s wall on {} threads)\n",
        t0.elapsed().as_secs_f64(),
        rayon::current_num_threads()
    );
    print!("{text}");
    let stem = match kind {
        StudyKind::Pga => "sequence_rotation_vs_pga",
        StudyKind::Mu => "sequence_increase_vs_mu",
    };
    deckspin::output::files::write_atomic(out.join(format!("{stem}.csv")), csv)?;
    deckspin::output::files::write_atomic(out.join(format!("{stem}.txt")), text)?;
    super::show::chart(&figure, &out.join(format!("{stem}.svg")))?;
    println!("wrote {}/{stem}.{{csv,txt,svg}}", out.display());
    Ok(())
}
