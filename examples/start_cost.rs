//! The workbench's start with N runs kept beside the model: from reading the model to the
//! first frame (120×40 on a TestBackend), the model's own text among the kept runs (so the
//! kept run is shown, not run again; without kept runs the run is started, not computed), as
//! `deckspin MODEL.toml` starts. Prints what opening the
//! run list read (files, bytes, series files parsed), the series read for the first frame and
//! the wall time; run `measure` under `valgrind --tool=callgrind` for its instruction count.
//!
//!     cargo run --release --example start_cost -- prepare DIR N
//!     cargo run --release --example start_cost -- measure DIR

use deckspin::tui::runs::list::{Entry, Series};
use deckspin::tui::{self, App, Effect, Options, runs::store as run_store};
use std::path::{Path, PathBuf};

/// DIR/models/four-span.toml (the bridge shortened to 2 s) with its records, and N runs kept:
/// #1..#N-1 of other gaps, the last of the model's own text.
fn prepare(dir: &Path, n: u64) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let _ = std::fs::remove_dir_all(dir);
    std::fs::create_dir_all(dir.join("models")).unwrap();
    std::fs::create_dir_all(dir.join("excitations")).unwrap();
    for e in std::fs::read_dir(root.join("excitations")).unwrap() {
        let e = e.unwrap();
        if e.path().is_file() {
            std::fs::copy(e.path(), dir.join("excitations").join(e.file_name())).unwrap();
        }
    }
    let text = std::fs::read_to_string(root.join("models/four-span.toml")).unwrap();
    let set = |t: &str, p: &str, v: &str| {
        tui::form::set_value(t, p, tui::form::Kind::Float, v, tui::form::Dim::Plain).unwrap()
    };
    let text = set(&text, "solver.t_end", "2.0");
    let model = dir.join("models/four-span.toml");
    std::fs::write(&model, &text).unwrap();
    if n == 0 {
        return;
    }
    let mut app = App::new_from_text(&text, &model);
    let fx = app.start();
    tui::execute_blocking(&mut app, fx);
    let run = app.current.expect("a run");
    let jobs: Vec<run_store::Job> = (1..=n)
        .map(|k| {
            let mut r = run.clone();
            r.id = k;
            let model_text = if k == n {
                text.clone()
            } else {
                set(&text, "contacts.gaps.0", &format!("{}", 0.001 * k as f64))
            };
            run_store::Job {
                entry: Box::new(Entry::of_run(&r, model_text)),
                baseline: k == 1,
                full: true,
            }
        })
        .collect();
    run_store::store(&run_store::runs_dir(&model), &jobs, &[]).unwrap();
    // opened once, as the workbench leaves it: the diffs against the baseline stored
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    let fx = (app.start().into_iter())
        .filter(|e| !matches!(e, Effect::StartRun { .. }))
        .collect();
    tui::execute_blocking(&mut app, fx);
}

fn measure(dir: &Path) {
    let t0 = std::time::Instant::now();
    let model = dir.join("models/four-span.toml");
    let mut app = App::new_from_path(&model, Options::default()).unwrap();
    let read = app.runs_read;
    let rediffed = app.runs_rediffed.len();
    // the run a model without a kept run of its text starts goes to a worker: not counted
    let fx: Vec<Effect> = (app.start().into_iter())
        .filter(|e| !matches!(e, Effect::StartRun { .. }))
        .collect();
    tui::execute_blocking(&mut app, fx);
    let mut term = ratatui::Terminal::new(ratatui::backend::TestBackend::new(120, 40)).unwrap();
    tui::update(&mut app, tui::Msg::Resize(120, 40));
    let mut cache = tui::ui::Cache::default();
    term.draw(|f| tui::ui::draw(f, &app, &mut cache)).unwrap();
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    let series = (app.runs.list.iter())
        .filter(|e| e.series == Series::InMemory)
        .count();
    println!(
        "{} runs kept: opening read {} files, {} bytes, diffed {} runs; the first frame read {series} series; {ms:.1} ms",
        app.runs.list.len(),
        read.files,
        read.bytes,
        rediffed,
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    match args.get(1).map(String::as_str) {
        Some("prepare") => prepare(
            &PathBuf::from(&args[2]),
            args.get(3).and_then(|n| n.parse().ok()).unwrap_or(0),
        ),
        Some("measure") => measure(&PathBuf::from(&args[2])),
        _ => eprintln!("start_cost prepare DIR N | start_cost measure DIR"),
    }
}
