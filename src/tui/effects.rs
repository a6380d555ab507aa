//! The effect executor, shared by the terminal runtime and headless use (tests): what differs
//! (threads or blocking calls, timing) is a [`Host`].

use super::app::App;
use super::msg::{Effect, Msg};
use super::results::ResultSpec;
use super::update::update;
use super::{
    form::model_files, runs::store as run_store, studies::files as study_files,
    workers::run as worker, workers::study as study_worker,
};
use crate::scene::Scene;
use crate::tui::runs::export;
use crate::tui::studies::StudySpec;
use crate::tui::workers::results as results_worker;
use std::collections::VecDeque;
use std::io::{self, Write};
use std::path::Path;

/// Writes `text` to `path` atomically: a temporary file in the same directory (same file
/// system), flushed to disk, given the original's permissions, then renamed over `path`.
pub fn save_atomic(path: &Path, text: &str) -> io::Result<()> {
    // a symbolic link stays a link: write the file it points to
    let resolved;
    let path = if std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink()) {
        resolved = std::fs::canonicalize(path)?;
        resolved.as_path()
    } else {
        path
    };
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .ok_or_else(|| io::Error::other("no file name"))?
        .to_string_lossy();
    // a file with other names (hard links) is written in place, so that they all see it
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if std::fs::metadata(path).is_ok_and(|m| m.nlink() > 1) {
            return save_in_place(path, dir, &name, text);
        }
    }
    let tmp = dir.join(format!(".{name}.deckspin-{}.tmp", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(text.as_bytes())?;
        f.sync_all()?;
        if let Ok(m) = std::fs::metadata(path) {
            std::fs::set_permissions(&tmp, m.permissions())?;
        }
        std::fs::rename(&tmp, path)?;
        if let Ok(d) = std::fs::File::open(dir) {
            let _ = d.sync_all();
        }
        Ok(())
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Writes `text` into the file `path` itself (its inode kept, as vim's `backupcopy=yes`): a
/// backup copy is made beside it (else in the temp directory) first and removed after; when
/// the write fails the backup is copied back, and if that fails too the error names it.
fn save_in_place(path: &Path, dir: &Path, name: &str, text: &str) -> io::Result<()> {
    let pid = std::process::id();
    let backup = [
        dir.join(format!(".{name}.deckspin-backup-{pid}")),
        std::env::temp_dir().join(format!("deckspin-backup-{pid}-{name}")),
    ]
    .into_iter()
    .find(|b| std::fs::copy(path, b).is_ok())
    .ok_or_else(|| io::Error::other("no room for a backup copy before writing in place"))?;
    let write = || -> io::Result<()> {
        let mut f = std::fs::OpenOptions::new().write(true).open(path)?;
        f.write_all(text.as_bytes())?;
        f.set_len(text.len() as u64)?;
        f.sync_all()
    };
    match write() {
        Ok(()) => {
            let _ = std::fs::remove_file(&backup);
            Ok(())
        }
        Err(e) => match std::fs::copy(&backup, path) {
            Ok(_) => {
                let _ = std::fs::remove_file(&backup);
                Err(e)
            }
            Err(_) => Err(io::Error::other(format!(
                "{e}; the previous content is in {}",
                backup.display()
            ))),
        },
    }
}

/// A job for [`Host::background`]: its message is the result.
pub type Job = Box<dyn FnOnce() -> Msg + Send>;

/// Where effects run: the runtime's threads, or blocking calls.
pub trait Host {
    /// Starts simulation `id`; returns the messages available now (all of them when blocking,
    /// none when they come later through the runtime's channel).
    fn start_run(&mut self, id: u64, scene: Scene) -> Vec<Msg>;
    fn cancel_run(&mut self, id: u64);
    /// Starts study `id`; returns the messages available now (as [`Host::start_run`]).
    fn start_study(&mut self, id: u64, spec: StudySpec) -> Vec<Msg>;
    fn cancel_study(&mut self, id: u64);
    /// Starts results computation `id`; returns the messages available now (by default it
    /// runs to its end here).
    fn start_result(&mut self, id: u64, spec: ResultSpec) -> Vec<Msg> {
        results_worker::run_blocking(id, &spec)
    }
    fn cancel_result(&mut self, _id: u64) {}
    /// Runs a slow job (export formatting); returns its message now or sends it later.
    fn background(&mut self, job: Job) -> Vec<Msg>;
    /// Runs a job after the jobs given to it before (the run list's files); by default at
    /// once.
    fn in_order(&mut self, job: Job) -> Vec<Msg> {
        vec![job()]
    }
    /// A timing milestone.
    fn log(&mut self, _label: &str) {}
    /// Suspend the workbench to the shell (Ctrl-Z) once the messages at hand are handled;
    /// nothing without a terminal.
    fn suspend(&mut self) {}
    /// Watches `path` instead of the file watched so far (none without a terminal).
    fn watch(&mut self, _path: &Path) {}
}

/// Executes effects; the messages they produce at once are fed back to [`update`] and their
/// effects executed in turn.
pub fn perform(app: &mut App, host: &mut impl Host, effects: Vec<Effect>) {
    let mut queue: VecDeque<Effect> = effects.into();
    while let Some(e) = queue.pop_front() {
        for m in execute(app, host, e) {
            queue.extend(update(app, m));
        }
    }
}

/// The file's content when it is not the version `base` (a hash of [`super::app::hash_text`]);
/// None when it is, when no version is expected, or when the file cannot be read (gone).
fn changed_on_disk(path: &Path, base: Option<u64>) -> Option<String> {
    let base = base?;
    let disk = std::fs::read_to_string(path).ok()?;
    (super::app::hash_text(&disk) != base).then_some(disk)
}

/// Executes one effect.
fn execute(app: &mut App, host: &mut impl Host, e: Effect) -> Vec<Msg> {
    match e {
        Effect::StartRun { id, scene } => host.start_run(id, *scene),
        Effect::CancelRun { id } => {
            host.cancel_run(id);
            Vec::new()
        }
        Effect::Save { path, text, base } => {
            if let Some(disk) = changed_on_disk(&path, base) {
                return vec![Msg::SaveConflict(disk)];
            }
            let result = save_atomic(&path, &text)
                .map(|_| path)
                .map_err(|e| e.to_string());
            host.log("saved");
            vec![Msg::Saved { text, result }]
        }
        Effect::Export {
            dirs,
            run,
            window,
            element,
        } => host.background(Box::new(move || {
            let files = export::export_files(&run, window, element);
            Msg::Exported(export::write_exports(&dirs, &files))
        })),
        Effect::StartStudy { id, spec } => host.start_study(id, *spec),
        Effect::CancelStudy { id } => {
            host.cancel_study(id);
            Vec::new()
        }
        Effect::WriteStudy { id, dirs, table } => host.background(Box::new(move || {
            let result = study_files::write(&dirs, &table);
            Msg::StudyWritten { id, result }
        })),
        Effect::ListStudies { dirs } => {
            host.background(Box::new(move || Msg::StudyFiles(study_files::list(&dirs))))
        }
        Effect::LoadStudy { path } => host.background(Box::new(move || {
            let result = study_files::load(&path);
            Msg::StudyLoaded { path, result }
        })),
        Effect::StoreRuns { dir, jobs, remove } => host.in_order(Box::new(move || {
            Msg::RunsStored(run_store::store(&dir, &jobs, &remove))
        })),
        Effect::StoreCharts { path, text } => host.in_order(Box::new(move || {
            Msg::ChartsStored(super::chart_prefs::store(&path, &text))
        })),
        Effect::LoadSeries { dir, runs } => host.in_order(Box::new(move || {
            let loaded = (runs.iter())
                .map(|&(n, t_end)| (n, run_store::load_series(&dir, n, t_end)))
                .collect();
            Msg::SeriesLoaded { dir, loaded }
        })),
        Effect::StartResult { id, spec } => host.start_result(id, *spec),
        Effect::CancelResult { id } => {
            host.cancel_result(id);
            Vec::new()
        }
        Effect::ListModels { dir } => {
            host.background(Box::new(move || Msg::ModelFiles(model_files::list(&dir))))
        }
        Effect::ReadModel { path } => {
            let result = std::fs::read_to_string(&path)
                .map_err(|e| format!("{}: cannot read: {e}", path.display()));
            vec![Msg::ModelRead { path, result }]
        }
        Effect::Watch { path } => {
            host.watch(&path);
            Vec::new()
        }
        Effect::Quit => {
            app.quit = true;
            Vec::new()
        }
        Effect::Suspend => {
            host.suspend();
            Vec::new()
        }
    }
}

/// Headless host: simulations run to completion in this thread, jobs run at once.
pub struct Blocking;

impl Host for Blocking {
    fn start_run(&mut self, id: u64, scene: Scene) -> Vec<Msg> {
        worker::run_blocking(id, &scene)
    }
    fn cancel_run(&mut self, _id: u64) {}
    fn start_study(&mut self, id: u64, spec: StudySpec) -> Vec<Msg> {
        study_worker::run_blocking(id, &spec)
    }
    fn cancel_study(&mut self, _id: u64) {}
    fn background(&mut self, job: Job) -> Vec<Msg> {
        vec![job()]
    }
}

/// Executes effects without a terminal ([`Blocking`]): tests, headless use.
pub fn execute_blocking(app: &mut App, effects: Vec<Effect>) {
    perform(app, &mut Blocking, effects);
}
