//! The swap file: the workbench's unsaved edits (and the value being typed) kept on disk
//! within about a second of every change, as vim's `.swp`: `.MODEL.toml.swp` beside the model,
//! or, when that folder cannot be written, in the state directory
//! (`$XDG_STATE_HOME/deckspin/swap`, else `~/.local/state/deckspin/swap`, else the temp
//! directory) under the model's whole path with `/` as `%`. Removed on a clean save or quit;
//! on start, a swap file whose edits differ from the model is offered for recovery.
//!
//! Layout: TOML comments first (`# deckspin-swap pid=N model=PATH`, and `# deckspin-swap-typing
//! FIELD = TEXT` while a value is being typed), then the model text with the edits.

use std::io;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::time::Duration;

/// How long the writer waits for more changes before it writes.
pub const SETTLE: Duration = Duration::from_millis(250);

/// The first line's start: `# deckspin-swap pid=N model=PATH`.
pub const HEADER: &str = "# deckspin-swap";
/// The line of the value being typed: `# deckspin-swap-typing FIELD = TEXT`.
pub const TYPING: &str = "# deckspin-swap-typing ";

/// `.NAME.swp` beside the model.
pub fn beside(model: &Path) -> PathBuf {
    let name = model
        .file_name()
        .map_or("model.toml".into(), |n| n.to_string_lossy().into_owned());
    model.with_file_name(format!(".{name}.swp"))
}

/// The state directory's folder of swap and recovery files.
pub fn state_dir() -> PathBuf {
    let base = std::env::var_os("XDG_STATE_HOME")
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .or_else(|| {
            std::env::var_os("HOME")
                .filter(|v| !v.is_empty())
                .map(|h| PathBuf::from(h).join(".local/state"))
        })
        .unwrap_or_else(std::env::temp_dir);
    base.join("deckspin")
}

/// The model's whole path with `/` as `%` (a file name unique to the model).
pub fn flattened(model: &Path) -> String {
    let abs = std::path::absolute(model).unwrap_or_else(|_| model.to_path_buf());
    abs.to_string_lossy().replace(['/', '\\'], "%")
}

/// Where the swap of `model` may be, in order: beside it, in the state directory.
pub fn places(model: &Path) -> Vec<PathBuf> {
    vec![
        beside(model),
        state_dir()
            .join("swap")
            .join(format!("{}.swp", flattened(model))),
    ]
}

/// A swap file found.
#[derive(Clone, Debug, PartialEq)]
pub struct Found {
    pub path: PathBuf,
    /// The process that wrote it.
    pub pid: u32,
    /// The model with the edits.
    pub text: String,
    /// The value that was being typed (`FIELD = TEXT`).
    pub typing: Option<String>,
    /// The swap is older than the model file.
    pub older_than_model: bool,
}

/// Reads a swap file's text: (pid, model text, typing).
pub fn parse(text: &str) -> Option<(u32, String, Option<String>)> {
    let (first, mut rest) = text.split_once('\n')?;
    let pid = (first.strip_prefix(HEADER)?.split_whitespace())
        .find_map(|f| f.strip_prefix("pid="))?
        .parse()
        .ok()?;
    let mut typing = None;
    if let Some(r) = rest.strip_prefix(TYPING) {
        let (t, r) = r.split_once('\n').unwrap_or((r, ""));
        typing = Some(t.to_string());
        rest = r;
    }
    Some((pid, rest.to_string(), typing))
}

/// The first swap of `model` found (beside it, then in the state directory).
pub fn find(model: &Path) -> Option<Found> {
    let model_time = std::fs::metadata(model).and_then(|m| m.modified()).ok();
    places(model).into_iter().find_map(|path| {
        let meta = std::fs::symlink_metadata(&path)
            .ok()
            .filter(|m| m.is_file())?;
        let text = crate::input::read_bounded(&path, crate::input::MAX_MODEL_BYTES).ok()?;
        let (pid, text, typing) = parse(&text)?;
        let older = match (meta.modified().ok(), model_time) {
            (Some(s), Some(m)) => s < m,
            _ => false,
        };
        Some(Found {
            path,
            pid,
            text,
            typing,
            older_than_model: older,
        })
    })
}

/// Whether process `pid` (not this one) is alive.
pub fn alive(pid: u32) -> bool {
    if pid == std::process::id() || pid == 0 || pid > i32::MAX as u32 {
        return false;
    }
    #[cfg(unix)]
    {
        // SAFETY: kill with signal 0 only checks that the process exists
        let r = unsafe { libc::kill(pid as i32, 0) };
        r == 0 || io::Error::last_os_error().raw_os_error() == Some(libc::EPERM)
    }
    #[cfg(not(unix))]
    {
        false
    }
}

/// Writes `text` to `path` through a temporary file and a rename (its folder made).
fn write_file(path: &Path, text: &str) -> io::Result<()> {
    if let Some(d) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(d)?;
    }
    crate::output::files::write_atomic(path, text)
}

/// Writes the swap to the first place that takes it; returns where.
pub fn write(model: &Path, text: &str) -> io::Result<PathBuf> {
    let mut last = io::Error::other("no place for a swap file");
    for p in places(model) {
        match write_file(&p, text) {
            Ok(()) => return Ok(p),
            Err(e) => last = e,
        }
    }
    Err(last)
}

/// A change for the writer: the new swap text, or None (nothing unsaved: remove it).
enum Order {
    Set(Option<String>),
    /// Stop; keep the swap (true) or remove it.
    Stop(bool),
}

/// The swap writer: a thread that writes the latest text [`SETTLE`] after the last change.
pub struct Swapper {
    tx: Sender<Order>,
    handle: Option<std::thread::JoinHandle<()>>,
    last: Option<Option<String>>,
}

impl Swapper {
    /// Starts the writer of `model`'s swap.
    pub fn spawn(model: &Path) -> io::Result<Swapper> {
        let (tx, rx) = mpsc::channel();
        let model = model.to_path_buf();
        let handle = std::thread::Builder::new()
            .name("deckspin-swap".into())
            .spawn(move || writer(&model, &rx))?;
        Ok(Swapper {
            tx,
            handle: Some(handle),
            last: None,
        })
    }

    /// The swap text of the unsaved work now (`tui::signals::swap_content`; None: nothing
    /// unsaved); nothing is sent when it has not changed.
    pub fn update(&mut self, now: Option<String>) {
        if self.last.as_ref() != Some(&now) {
            let _ = self.tx.send(Order::Set(now.clone()));
            self.last = Some(now);
        }
    }

    /// Writes what is pending and stops; the swap kept (`keep`) or removed.
    pub fn finish(mut self, keep: bool) {
        let _ = self.tx.send(Order::Stop(keep));
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

fn writer(model: &Path, rx: &Receiver<Order>) {
    let mut written: Option<PathBuf> = None;
    let remove = |w: &mut Option<PathBuf>| {
        if let Some(p) = w.take() {
            let _ = std::fs::remove_file(p);
        }
    };
    let mut pending: Option<Option<String>> = None;
    loop {
        let order = if pending.is_some() {
            match rx.recv_timeout(SETTLE) {
                Ok(o) => Some(o),
                Err(RecvTimeoutError::Timeout) => None,
                Err(RecvTimeoutError::Disconnected) => Some(Order::Stop(true)),
            }
        } else {
            match rx.recv() {
                Ok(o) => Some(o),
                Err(_) => return,
            }
        };
        match order {
            Some(Order::Set(t)) => pending = Some(t),
            Some(Order::Stop(keep)) => {
                if let Some(Some(t)) = pending.take().filter(|_| keep) {
                    written = write(model, &t).ok().or(written);
                }
                if !keep {
                    remove(&mut written);
                }
                return;
            }
            // settled: write it
            None => match pending.take() {
                Some(Some(t)) => match write(model, &t) {
                    Ok(p) => {
                        if written.as_ref().is_some_and(|w| *w != p) {
                            remove(&mut written);
                        }
                        written = Some(p);
                    }
                    Err(_) => pending = None,
                },
                Some(None) => remove(&mut written),
                None => {}
            },
        }
    }
}

/// Removes every swap of `model` (after its edits were recovered or declined).
pub fn remove_all(model: &Path) {
    for p in places(model) {
        let _ = std::fs::remove_file(p);
    }
}
