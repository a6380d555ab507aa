//! The terminal runtime: raw mode and alternate screen (restored on every exit, on panics and
//! on SIGTERM, SIGHUP and SIGINT, and for the time of a Ctrl-Z suspension), colours written
//! to the terminal's depth ([`term::SgrFilter`]),
//! the input thread, and the loop that drains the message channel, feeds [`update`], executes
//! effects through [`Threads`] and draws once per drain.

use super::app::{App, Confirm, Mode, Options, StatusKind};
use super::effects::{Host, Job, perform};
use super::msg::Msg;
use super::term::{ColorDepth, Glyphs, SgrFilter};
use super::ui;
use super::update::update;
use super::{
    form::swap, signals, workers::results as results_worker, workers::run as worker,
    workers::study as study_worker, workers::watch,
};
use crate::scene::Scene;
use crate::tui::studies::StudySpec;
use crossterm::event::{self, Event};
use crossterm::execute;
use crossterm::terminal::{
    EnterAlternateScreen, LeaveAlternateScreen, disable_raw_mode, enable_raw_mode,
};
use ratatui::Terminal;
use ratatui::backend::CrosstermBackend;
use std::collections::HashMap;
use std::io::{self, Write};
use std::path::Path;
use std::sync::mpsc::{self, Receiver, Sender};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

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

/// Raw mode, alternate screen, cursor hidden.
fn take_terminal() -> io::Result<()> {
    enable_raw_mode()?;
    TERMINAL_TAKEN.store(true, std::sync::atomic::Ordering::SeqCst);
    execute!(io::stdout(), EnterAlternateScreen, crossterm::cursor::Hide)
}

impl TerminalGuard {
    fn enter() -> io::Result<Self> {
        let guard = TerminalGuard;
        take_terminal()?;
        Ok(guard)
    }
}

/// The terminal as the workbench draws on it: stdout through the colour filter.
type Term = Terminal<CrosstermBackend<SgrFilter<io::Stdout>>>;

/// Ctrl-Z: gives the terminal back, stops the process as Ctrl-Z does in a shell (SIGTSTP;
/// the shell's `fg` continues it), then takes the terminal again and redraws it whole.
#[cfg(unix)]
fn suspend(terminal: &mut Term, app: &mut App) -> io::Result<()> {
    restore_terminal();
    signal_hook::low_level::raise(signal_hook::consts::SIGTSTP)?;
    // continued (SIGCONT): the screen may have changed size meanwhile
    take_terminal()?;
    // cleared and drawn whole at the size of now (not `Terminal::clear`, which asks the
    // terminal for the cursor position: the input thread would take the answer)
    let size = terminal.size()?;
    terminal.resize(ratatui::layout::Rect::new(0, 0, size.width, size.height))?;
    update(app, Msg::Resize(size.width, size.height));
    Ok(())
}

#[cfg(not(unix))]
fn suspend(_terminal: &mut Term, _app: &mut App) -> io::Result<()> {
    Ok(())
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

/// The runtime's [`Host`]: runs in worker threads, jobs in their own thread, results back
/// through the channel.
struct Threads {
    tx: Sender<Msg>,
    runs: HashMap<u64, worker::RunHandle>,
    studies: HashMap<u64, study_worker::StudyHandle>,
    timing: Timing,
    /// The thread that writes the run list's files, one job after the other.
    writer: Option<(Sender<Job>, std::thread::JoinHandle<()>)>,
    /// Ctrl-Z asked for a suspension (done by the loop, which holds the terminal).
    suspend: bool,
    /// The results pages' computations.
    results: HashMap<u64, results_worker::ResultHandle>,
    /// The model file's watcher (replaced when another model is opened).
    watch: Option<watch::Watch>,
}

impl Host for Threads {
    fn start_run(&mut self, id: u64, scene: Scene) -> Vec<Msg> {
        self.timing.log(&format!("run-start {id}"));
        self.runs.retain(|_, h| h.id + 8 > id);
        self.runs
            .insert(id, worker::spawn(id, scene, self.tx.clone()));
        Vec::new()
    }
    fn cancel_run(&mut self, id: u64) {
        if let Some(h) = self.runs.get(&id) {
            h.cancel();
        }
    }
    fn start_study(&mut self, id: u64, spec: StudySpec) -> Vec<Msg> {
        self.timing.log(&format!("study-start {id}"));
        self.studies.retain(|_, h| h.id + 8 > id);
        let h = study_worker::spawn(id, spec, self.tx.clone());
        self.studies.insert(id, h);
        Vec::new()
    }
    fn cancel_study(&mut self, id: u64) {
        if let Some(h) = self.studies.get(&id) {
            h.cancel();
        }
    }
    fn background(&mut self, job: Job) -> Vec<Msg> {
        // formatting 10⁵ rows takes a while: off the UI thread
        let tx = self.tx.clone();
        std::thread::spawn(move || {
            let _ = tx.send(job());
        });
        Vec::new()
    }
    fn in_order(&mut self, job: Job) -> Vec<Msg> {
        if self.writer.is_none() {
            let (jobs, queue) = mpsc::channel::<Job>();
            let tx = self.tx.clone();
            let spawned = std::thread::Builder::new()
                .name("deckspin-runs".into())
                .spawn(move || {
                    for job in queue {
                        let _ = tx.send(job());
                    }
                });
            if let Ok(h) = spawned {
                self.writer = Some((jobs, h));
            }
        }
        match &self.writer {
            Some((w, _)) => match w.send(job) {
                Ok(()) => Vec::new(),
                Err(mpsc::SendError(job)) => vec![job()],
            },
            // no writer thread: write here
            None => vec![job()],
        }
    }
    fn log(&mut self, label: &str) {
        self.timing.log(label);
    }
    fn suspend(&mut self) {
        self.suspend = true;
    }
    fn start_result(&mut self, id: u64, spec: super::results::ResultSpec) -> Vec<Msg> {
        self.results.retain(|_, h| h.id + 8 > id);
        let h = results_worker::spawn(id, spec, self.tx.clone());
        self.results.insert(id, h);
        Vec::new()
    }
    fn cancel_result(&mut self, id: u64) {
        if let Some(h) = self.results.get(&id) {
            h.cancel();
        }
    }
    fn watch(&mut self, path: &Path) {
        // the watcher before stops when dropped
        self.watch = None;
        self.watch = Some(watch::spawn(path, self.tx.clone()));
    }
}

impl Threads {
    /// Waits for the run list's files being written.
    fn finish_writes(&mut self) {
        if let Some((jobs, h)) = self.writer.take() {
            drop(jobs);
            let _ = h.join();
        }
    }

    fn cancel_all(&self) {
        for h in self.runs.values() {
            h.cancel();
        }
        for h in self.studies.values() {
            h.cancel();
        }
        for h in self.results.values() {
            h.cancel();
        }
    }
}

/// Sends key and resize events to the loop.
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

/// Waits for a message, then takes what else is queued (up to 4096).
fn drain(rx: &Receiver<Msg>) -> Option<Vec<Msg>> {
    let first = rx.recv().ok()?;
    let mut batch = vec![first];
    while batch.len() < 4096 {
        match rx.try_recv() {
            Ok(m) => batch.push(m),
            Err(_) => break,
        }
    }
    Some(batch)
}

/// The shortest time between two frames drawn for a run's data alone: 80 ms, at most 12.5
/// frames a second while a run streams in (its batches come every 40 ms); a key, a resize or
/// any other message is drawn at once, and so is the first batch of a run.
pub const DATA_FRAME: Duration = Duration::from_millis(80);

/// Whether `m` is a run's data (drawn at most every [`DATA_FRAME`]).
fn is_data(m: &Msg) -> bool {
    matches!(m, Msg::Batch { .. })
}

/// Waits until `until` for more messages while those that come are a run's data, so that its
/// batches are drawn together; returns them (the first other message ends the wait, and is
/// returned last).
pub fn pace(rx: &Receiver<Msg>, until: Instant) -> Vec<Msg> {
    let mut more = Vec::new();
    loop {
        let Some(left) = until.checked_duration_since(Instant::now()) else {
            return more;
        };
        match rx.recv_timeout(left) {
            Ok(m) => {
                let data = is_data(&m);
                more.push(m);
                if !data {
                    return more;
                }
            }
            Err(_) => return more,
        }
    }
}

/// Open the workbench on a model file, with the glyphs `glyphs` (`--glyphs`) or, when None,
/// those the environment tells ([`Options::from_env`]); with `run` false (`--no-run`) the model
/// is not run (a kept run of the same model text is shown).
pub fn run(
    model: &Path,
    glyphs: Option<Glyphs>,
    run: bool,
) -> Result<(), Box<dyn std::error::Error>> {
    let mut timing = Timing::from_env();
    timing.log("start");
    let mut app = App::new_from_path(model, Options::from_env(glyphs)?)?;
    let (tx, rx) = mpsc::channel::<Msg>();
    install_panic_hook();
    // before the terminal is taken: from here on a signal restores it
    signals::spawn(tx.clone(), restore_terminal)?;
    let guard = TerminalGuard::enter()?;
    let out = SgrFilter::new(io::stdout(), ColorDepth::from_env());
    let mut terminal = Terminal::new(CrosstermBackend::new(out))?;
    terminal.clear()?;
    let size = terminal.size()?;
    // (what the first message asks for — a kept run's series — is done like any other's)
    let mut fx = update(&mut app, Msg::Resize(size.width, size.height));
    spawn_input(tx.clone());
    let mut host = Threads {
        tx: tx.clone(),
        runs: HashMap::new(),
        studies: HashMap::new(),
        timing,
        writer: None,
        suspend: false,
        results: HashMap::new(),
        watch: None,
    };
    host.watch(&app.path);
    fx.extend(app.start_with(run));
    perform(&mut app, &mut host, fx);
    let mut swapper = offer_swap(&mut app);
    let ended = event_loop(&mut terminal, &mut app, &mut host, &rx, &mut swapper);
    host.cancel_all();
    host.finish_writes();
    drop(terminal);
    drop(guard);
    let owns_swap = swapper.is_some();
    // a clean quit removes the swap; anything else keeps it until the edits are safe
    let clean = matches!(ended, Ok(None)) && signals::received().is_none();
    if let Some(s) = swapper {
        s.finish(!clean);
    }
    // a signal ends the loop, or the terminal went away after one (SIGHUP) and drawing failed
    match (ended, signals::received()) {
        (Ok(Some(sig)), _) | (Err(_), Some(sig)) => signals::exit_after(sig, &app, owns_swap),
        (Ok(None), _) => Ok(()),
        (Err(e), None) => Err(e.into()),
    }
}

/// A swap file of the model found at the start: offered for recovery (its edits differ from
/// the model), removed (they do not), or left to the live workbench that writes it. Returns
/// this workbench's swap writer (none while another one writes the model's swap).
fn offer_swap(app: &mut App) -> Option<swap::Swapper> {
    if let Some(found) = swap::find(&app.path) {
        if swap::alive(found.pid) {
            app.set_status(
                StatusKind::Warn,
                format!(
                    "process {} edits {} too (its swap file {}): this workbench keeps no swap file",
                    found.pid,
                    app.file_name(),
                    found.path.display()
                ),
            );
            return None;
        }
        if found.text == app.text && found.typing.is_none() {
            let _ = std::fs::remove_file(&found.path);
        } else {
            let differences = crate::tui::form::merge::differences(&app.text, &found.text);
            app.mode = Mode::Confirm(Confirm::Recover { found, differences });
            app.set_status(
                StatusKind::Warn,
                "unsaved edits found in a swap file: r recovers them, k keeps them in a file, d deletes them",
            );
        }
    }
    swap::Swapper::spawn(&app.path).ok()
}

/// Draws, drains the channel into [`update`] and performs the effects until the app quits
/// (None) or a signal arrives (Some).
fn event_loop(
    terminal: &mut Term,
    app: &mut App,
    host: &mut Threads,
    rx: &Receiver<Msg>,
    swapper: &mut Option<swap::Swapper>,
) -> io::Result<Option<i32>> {
    let mut cache = ui::Cache::default();
    let mut first_frame = true;
    // run id whose first batch arrived but is not drawn yet
    let mut first_batch_of: Option<u64> = None;
    let mut framed: u64 = 0;
    loop {
        terminal.draw(|f| ui::draw(f, app, &mut cache))?;
        let drawn = Instant::now();
        if first_frame {
            host.timing.log("first-frame");
            first_frame = false;
            if worker::test_panic("ui") {
                panic!("DECKSPIN_TEST_PANIC=ui: a panic on the UI thread");
            }
        }
        if let Some(id) = first_batch_of.take() {
            host.timing.log(&format!("first-run-frame {id}"));
            framed = id;
        }
        if app.quit {
            return Ok(None);
        }
        let Some(mut batch) = drain(rx) else {
            return Ok(None);
        };
        // a run's data alone waits for the next frame's time (a new run's first batch does not)
        let fresh = |m: &Msg| matches!(m, Msg::Batch { run, .. } if *run > framed);
        if batch.iter().all(is_data) && !batch.iter().any(fresh) {
            batch.extend(pace(rx, drawn + DATA_FRAME));
        }
        for m in batch {
            match &m {
                Msg::Signal(sig) => return Ok(Some(*sig)),
                Msg::Batch { run, .. }
                    if *run > framed && app.current.as_ref().is_some_and(|c| c.token == *run) =>
                {
                    first_batch_of = Some(*run)
                }
                Msg::FileChanged(_) => host.timing.log("file-changed"),
                _ => {}
            }
            let fx = update(app, m);
            perform(app, host, fx);
        }
        if let Some(s) = swapper.as_mut() {
            s.update(signals::swap_content(app));
        }
        if std::mem::take(&mut host.suspend) {
            suspend(terminal, app)?;
        }
    }
}
