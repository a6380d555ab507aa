//! Hot reload: watches the model file's directory (so editors that save by writing a temporary
//! file and renaming it over the model are seen) with a debounced notify watcher, and falls
//! back to polling mtime + content every second when the watcher cannot start or fails.
//! Every change sends the file's content; [`crate::tui::update`] compares content hashes, so
//! events that do not change the content are ignored there.

use crate::tui::app::hash_text;
use crate::tui::msg::Msg;
use notify::RecursiveMode;
use notify_debouncer_full::{DebounceEventResult, Debouncer, RecommendedCache, new_debouncer};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::Sender;
use std::time::{Duration, SystemTime};

/// Debounce window of the notify watcher.
pub const DEBOUNCE: Duration = Duration::from_millis(50);
/// Polling period of the fallback.
pub const POLL: Duration = Duration::from_secs(1);

/// Keeps the watcher alive; dropped, it stops (the notify watcher and the polling thread,
/// after its current sleep).
pub struct Watch {
    _debouncer: Option<Debouncer<notify::RecommendedWatcher, RecommendedCache>>,
    pub mode: String,
    stop: Arc<AtomicBool>,
}

impl Drop for Watch {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::SeqCst);
    }
}

fn read(path: &Path) -> Msg {
    match std::fs::read_to_string(path) {
        Ok(t) => Msg::FileChanged(t),
        Err(e) => Msg::FileUnreadable(e.to_string()),
    }
}

/// Watches `path` and sends [`Msg::FileChanged`] / [`Msg::WatchMode`] to `tx`. With
/// `DECKSPIN_WATCH=poll` in the environment it polls from the start.
pub fn spawn(path: &Path, tx: Sender<Msg>) -> Watch {
    let path = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let forced = std::env::var("DECKSPIN_WATCH").is_ok_and(|v| v == "poll");
    let stop = Arc::new(AtomicBool::new(false));
    if !forced {
        match notify_watch_until(&path, tx.clone(), stop.clone()) {
            Ok(d) => {
                let mode = "notify".to_string();
                let _ = tx.send(Msg::WatchMode(mode.clone()));
                return Watch {
                    _debouncer: Some(d),
                    mode,
                    stop,
                };
            }
            Err(e) => {
                let mode = format!("polling 1 s ({e})");
                let _ = tx.send(Msg::WatchMode(mode.clone()));
                spawn_poll_until(path, tx, POLL, stop.clone());
                return Watch {
                    _debouncer: None,
                    mode,
                    stop,
                };
            }
        }
    }
    let mode = "polling 1 s".to_string();
    let _ = tx.send(Msg::WatchMode(mode.clone()));
    spawn_poll_until(path, tx, POLL, stop.clone());
    Watch {
        _debouncer: None,
        mode,
        stop,
    }
}

/// A debounced watcher on the file's directory, reporting changes of that file name (created,
/// written, renamed onto). On a watcher error it starts the polling fallback (once).
pub fn notify_watch(
    path: &Path,
    tx: Sender<Msg>,
) -> Result<Debouncer<notify::RecommendedWatcher, RecommendedCache>, String> {
    notify_watch_until(path, tx, Arc::new(AtomicBool::new(false)))
}

/// [`notify_watch`] whose polling fallback stops when `stop` is set.
fn notify_watch_until(
    path: &Path,
    tx: Sender<Msg>,
    stop: Arc<AtomicBool>,
) -> Result<Debouncer<notify::RecommendedWatcher, RecommendedCache>, String> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
        .to_path_buf();
    let name = path
        .file_name()
        .ok_or("the model path has no file name")?
        .to_os_string();
    let target = path.to_path_buf();
    let fell_back = Arc::new(AtomicBool::new(false));
    let mut d = new_debouncer(DEBOUNCE, None, move |res: DebounceEventResult| match res {
        Ok(events) => {
            let ours = events.iter().any(|e| {
                !e.kind.is_access()
                    && e.paths
                        .iter()
                        .any(|p| p.file_name() == Some(name.as_os_str()))
            });
            if ours && target.exists() && !stop.load(Ordering::SeqCst) {
                let _ = tx.send(read(&target));
            }
        }
        Err(errors) => {
            if !fell_back.swap(true, Ordering::SeqCst) {
                let e = errors
                    .first()
                    .map_or("unknown".to_string(), |e| e.to_string());
                let _ = tx.send(Msg::WatchMode(format!("polling 1 s (watcher error: {e})")));
                spawn_poll_until(target.clone(), tx.clone(), POLL, stop.clone());
            }
        }
    })
    .map_err(|e| e.to_string())?;
    d.watch(&dir, RecursiveMode::NonRecursive)
        .map_err(|e| e.to_string())?;
    Ok(d)
}

fn stamp(path: &Path) -> Option<(SystemTime, u64)> {
    let m = std::fs::metadata(path).ok()?;
    Some((m.modified().ok()?, m.len()))
}

/// Polls the file every `every`: when mtime or size changed, reads it and sends it if the
/// content hash differs from the last one seen. Stops when the receiver is gone.
pub fn spawn_poll(path: PathBuf, tx: Sender<Msg>, every: Duration) -> std::thread::JoinHandle<()> {
    spawn_poll_until(path, tx, every, Arc::new(AtomicBool::new(false)))
}

/// [`spawn_poll`] that also stops once `stop` is set.
fn spawn_poll_until(
    path: PathBuf,
    tx: Sender<Msg>,
    every: Duration,
    stop: Arc<AtomicBool>,
) -> std::thread::JoinHandle<()> {
    std::thread::Builder::new()
        .name("deckspin-poll".into())
        .spawn(move || {
            let mut last_stamp = stamp(&path);
            let mut last_hash = std::fs::read_to_string(&path).ok().map(|t| hash_text(&t));
            loop {
                std::thread::sleep(every);
                if stop.load(Ordering::SeqCst) {
                    return;
                }
                let s = stamp(&path);
                if s == last_stamp {
                    continue;
                }
                last_stamp = s;
                let Ok(text) = std::fs::read_to_string(&path) else {
                    continue;
                };
                let h = hash_text(&text);
                if Some(h) == last_hash {
                    continue;
                }
                last_hash = Some(h);
                if tx.send(Msg::FileChanged(text)).is_err() {
                    return;
                }
            }
        })
        .expect("spawn the polling thread")
}
