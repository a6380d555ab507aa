//! The terminal workbench (ratatui + crossterm) over the engine's public API.
//!
//! Event-driven: an input thread (crossterm key and resize events), the simulation worker
//! ([`worker`]) and the file watcher ([`watch`]) all send [`Msg`]s into one channel; the loop
//! drains it, feeds each message to [`app::update`], executes the returned [`Effect`]s, and
//! draws once per drain. See `docs/workbench.md`.

pub mod app;
pub mod chart;
pub mod form;
pub mod keymap;
pub mod ui;
pub mod watch;
pub mod worker;

pub use app::{App, Effect, Msg, Options, update};

use crossterm::event::{self, Event};
use crossterm::execute;
use crossterm::terminal::{
    EnterAlternateScreen, LeaveAlternateScreen, disable_raw_mode, enable_raw_mode,
};
use ratatui::Terminal;
use ratatui::backend::CrosstermBackend;
use std::collections::{HashMap, VecDeque};
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::mpsc::{self, Sender};
use std::time::{Instant, SystemTime, UNIX_EPOCH};

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

/// Writes export files into the first directory that accepts all of them.
pub fn write_exports(dirs: &[PathBuf], files: &[(String, String)]) -> Result<Vec<PathBuf>, String> {
    let mut last = String::from("no directory");
    for d in dirs {
        let mut written = Vec::new();
        let mut ok = true;
        for (name, content) in files {
            let p = d.join(name);
            if let Err(e) = std::fs::write(&p, content) {
                last = format!("{}: {e}", p.display());
                ok = false;
                break;
            }
            written.push(p);
        }
        if ok {
            return Ok(written);
        }
    }
    Err(last)
}

/// Executes effects without a terminal: simulations run to completion in this thread, files
/// are written, and the resulting messages are fed back to [`update`] (tests, headless use).
pub fn execute_blocking(app: &mut App, effects: Vec<Effect>) {
    let mut queue: VecDeque<Effect> = effects.into();
    while let Some(e) = queue.pop_front() {
        let msgs = match e {
            Effect::StartRun { id, scene } => worker::run_blocking(id, &scene),
            Effect::CancelRun { .. } => Vec::new(),
            Effect::Save { path, text } => {
                let result = save_atomic(&path, &text)
                    .map(|_| path)
                    .map_err(|e| e.to_string());
                vec![Msg::Saved { text, result }]
            }
            Effect::Export {
                dirs,
                stem,
                run,
                window,
                element,
            } => {
                let files = app::export_files(&stem, &run, window, element);
                vec![Msg::Exported(write_exports(&dirs, &files))]
            }
            Effect::Quit => Vec::new(),
        };
        for m in msgs {
            queue.extend(update(app, m));
        }
    }
}

/// Test hook: `DECKSPIN_TEST_PANIC=ui` panics on the UI thread after the first frame,
/// `=worker` inside the simulation thread (the end-to-end test checks the terminal is restored
/// and the worker's panic is reported as a failed run).
pub(crate) fn test_panic(place: &str) -> bool {
    std::env::var("DECKSPIN_TEST_PANIC").is_ok_and(|v| v == place)
}

/// Whether the terminal is in workbench mode (raw, alternate screen).
static TERMINAL_TAKEN: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Restores the terminal once: raw mode off, main screen, cursor shown. (Leaving the
/// alternate screen twice would move the cursor back over what was printed in between.)
fn restore_terminal() {
    if TERMINAL_TAKEN.swap(false, std::sync::atomic::Ordering::SeqCst) {
        let _ = disable_raw_mode();
        let _ = execute!(io::stdout(), LeaveAlternateScreen, crossterm::cursor::Show);
    }
}

/// Restores the terminal when dropped (normal return, `?` errors, unwinding).
struct TerminalGuard;

impl TerminalGuard {
    fn enter() -> io::Result<Self> {
        enable_raw_mode()?;
        TERMINAL_TAKEN.store(true, std::sync::atomic::Ordering::SeqCst);
        let guard = TerminalGuard;
        execute!(io::stdout(), EnterAlternateScreen, crossterm::cursor::Hide)?;
        Ok(guard)
    }
}

impl Drop for TerminalGuard {
    fn drop(&mut self) {
        restore_terminal();
    }
}

/// A panic on the UI thread restores the terminal before the message is printed; a panic on a
/// worker thread is recorded for the worker to report and leaves the screen alone.
fn install_panic_hook() {
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let on_worker = std::thread::current()
            .name()
            .is_some_and(|n| n.starts_with(worker::THREAD_PREFIX));
        if on_worker {
            worker::LAST_PANIC.with(|l| *l.borrow_mut() = Some(info.to_string()));
            return;
        }
        restore_terminal();
        previous(info);
    }));
}

/// Optional timing log (`DECKSPIN_TIMING=FILE`): one line per milestone, `unix_ms label`.
struct Timing {
    file: Option<std::fs::File>,
    start: Instant,
}

impl Timing {
    fn from_env() -> Self {
        let file = std::env::var_os("DECKSPIN_TIMING").and_then(|p| {
            std::fs::OpenOptions::new()
                .create(true)
                .append(true)
                .open(p)
                .ok()
        });
        Self {
            file,
            start: Instant::now(),
        }
    }
    fn log(&mut self, label: &str) {
        if let Some(f) = &mut self.file {
            let now = SystemTime::now()
                .duration_since(UNIX_EPOCH)
                .map_or(0.0, |d| d.as_secs_f64() * 1e3);
            let _ = writeln!(
                f,
                "{now:.3} {label} +{:.3}ms",
                self.start.elapsed().as_secs_f64() * 1e3
            );
        }
    }
}

struct Runtime {
    tx: Sender<Msg>,
    runs: HashMap<u64, worker::RunHandle>,
}

impl Runtime {
    /// Executes effects; synchronous ones (save, export) feed their result back at once.
    fn perform(&mut self, app: &mut App, effects: Vec<Effect>, timing: &mut Timing) {
        let mut queue: VecDeque<Effect> = effects.into();
        while let Some(e) = queue.pop_front() {
            match e {
                Effect::StartRun { id, scene } => {
                    timing.log(&format!("run-start {id}"));
                    self.runs.retain(|_, h| h.id + 8 > id);
                    self.runs
                        .insert(id, worker::spawn(id, *scene, self.tx.clone()));
                }
                Effect::CancelRun { id } => {
                    if let Some(h) = self.runs.get(&id) {
                        h.cancel();
                    }
                }
                Effect::Save { path, text } => {
                    let result = save_atomic(&path, &text)
                        .map(|_| path)
                        .map_err(|e| e.to_string());
                    timing.log("saved");
                    queue.extend(update(app, Msg::Saved { text, result }));
                }
                Effect::Export {
                    dirs,
                    stem,
                    run,
                    window,
                    element,
                } => {
                    // formatting 10⁵ rows takes a while: off the UI thread
                    let tx = self.tx.clone();
                    std::thread::spawn(move || {
                        let files = app::export_files(&stem, &run, window, element);
                        let _ = tx.send(Msg::Exported(write_exports(&dirs, &files)));
                    });
                }
                Effect::Quit => app.quit = true,
            }
        }
    }

    fn cancel_all(&self) {
        for h in self.runs.values() {
            h.cancel();
        }
    }
}

fn spawn_input(tx: Sender<Msg>) {
    let _ = std::thread::Builder::new()
        .name("deckspin-input".into())
        .spawn(move || {
            loop {
                let msg = match event::read() {
                    Ok(Event::Key(k)) => Msg::Key(k),
                    Ok(Event::Resize(w, h)) => Msg::Resize(w, h),
                    Ok(_) => continue,
                    Err(_) => return,
                };
                if tx.send(msg).is_err() {
                    return;
                }
            }
        });
}

/// Open the workbench on a model file.
pub fn run(model: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let mut timing = Timing::from_env();
    timing.log("start");
    let mut app = App::new_from_path(model, Options::from_env())?;
    let (tx, rx) = mpsc::channel::<Msg>();
    install_panic_hook();
    let guard = TerminalGuard::enter()?;
    let mut terminal = Terminal::new(CrosstermBackend::new(io::stdout()))?;
    terminal.clear()?;
    let size = terminal.size()?;
    update(&mut app, Msg::Resize(size.width, size.height));
    spawn_input(tx.clone());
    let _watch = watch::spawn(&app.path, tx.clone());
    let mut rt = Runtime {
        tx: tx.clone(),
        runs: HashMap::new(),
    };
    let fx = app.start();
    rt.perform(&mut app, fx, &mut timing);
    let mut first_frame = true;
    // run id whose first batch arrived but is not drawn yet
    let mut first_batch_of: Option<u64> = None;
    let mut framed: u64 = 0;
    loop {
        terminal.draw(|f| ui::draw(f, &app))?;
        if first_frame {
            timing.log("first-frame");
            first_frame = false;
            if test_panic("ui") {
                panic!("DECKSPIN_TEST_PANIC=ui: a panic on the UI thread");
            }
        }
        if let Some(id) = first_batch_of.take() {
            timing.log(&format!("first-run-frame {id}"));
            framed = id;
        }
        if app.quit {
            break;
        }
        let Ok(first) = rx.recv() else { break };
        let mut batch = vec![first];
        while batch.len() < 4096 {
            match rx.try_recv() {
                Ok(m) => batch.push(m),
                Err(_) => break,
            }
        }
        for m in batch {
            match &m {
                Msg::Batch { run, .. }
                    if *run > framed && app.current.as_ref().is_some_and(|c| c.id == *run) =>
                {
                    first_batch_of = Some(*run)
                }
                Msg::FileChanged(_) => timing.log("file-changed"),
                _ => {}
            }
            let fx = update(&mut app, m);
            rt.perform(&mut app, fx, &mut timing);
        }
    }
    rt.cancel_all();
    drop(terminal);
    drop(guard);
    Ok(())
}
