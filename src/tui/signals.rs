//! SIGTERM, SIGHUP and SIGINT: the first one ends the workbench's loop (the terminal is
//! restored and unsaved edits are written to a recovery file next to the model, never over
//! it); a second one, if the loop has not ended, restores the terminal and ends the process
//! at once. (Ctrl-C typed in the workbench is a key, not SIGINT: raw mode turns it off.)

use super::app::{App, Mode};
use super::msg::Msg;
use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
use signal_hook::iterator::Signals;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::mpsc::Sender;

/// The signals that end the workbench.
pub const SIGNALS: [i32; 3] = [SIGTERM, SIGHUP, SIGINT];

/// The first signal received (0: none).
static RECEIVED: AtomicI32 = AtomicI32::new(0);

pub fn name(sig: i32) -> &'static str {
    match sig {
        SIGTERM => "SIGTERM",
        SIGHUP => "SIGHUP",
        SIGINT => "SIGINT",
        _ => "a signal",
    }
}

/// The signal received, if any (also when the loop ended on an error first, e.g. the
/// terminal gone after SIGHUP).
pub fn received() -> Option<i32> {
    Some(RECEIVED.load(Ordering::SeqCst)).filter(|s| *s != 0)
}

/// Listens for [`SIGNALS`] in a thread: the first goes to the loop as [`Msg::Signal`]; a second
/// calls `restore` and ends the process as the signal would.
pub fn spawn(tx: Sender<Msg>, restore: fn()) -> io::Result<()> {
    let mut signals = Signals::new(SIGNALS)?;
    std::thread::Builder::new()
        .name("deckspin-signals".into())
        .spawn(move || {
            for sig in signals.forever() {
                let first = RECEIVED
                    .compare_exchange(0, sig, Ordering::SeqCst, Ordering::SeqCst)
                    .is_ok();
                if !first || tx.send(Msg::Signal(sig)).is_err() {
                    restore();
                    die(sig);
                }
            }
        })?;
    Ok(())
}

/// Ends the process as the default action of `sig` would (so the shell sees it).
pub fn die(sig: i32) -> ! {
    let _ = signal_hook::low_level::emulate_default_handler(sig);
    std::process::exit(128 + sig)
}

/// The unsaved work of the workbench.
#[derive(Debug, Default, PartialEq)]
pub struct Unsaved {
    /// The model with the unsaved edits (and the value being typed, when valid); None when it
    /// is the file as loaded or saved.
    pub text: Option<String>,
    /// What could not be kept (a value being typed that is not valid).
    pub note: Option<String>,
}

/// What a recovery file must hold.
pub fn unsaved(app: &App) -> Unsaved {
    let mut text = app.draft.clone();
    let mut note = None;
    if let Mode::Editing { buffer, .. } = &app.mode {
        let path = app.form.selected().map_or("?", |f| f.path.as_str());
        match app.check_edit(buffer) {
            Ok(t) => text = t,
            Err(e) => {
                note = Some(format!(
                    "the value being typed for {path}, '{buffer}', is not valid and is not kept \
                     ({e})"
                ))
            }
        }
    }
    Unsaved {
        text: (text != app.text).then_some(text),
        note,
    }
}

/// The swap text of `app`'s unsaved work (`tui::form::swap`; None: nothing unsaved).
pub fn swap_content(app: &App) -> Option<String> {
    let typing = match &app.mode {
        Mode::Editing { buffer, .. } => {
            let field = app.form.selected().map_or("?", |f| f.path.as_str());
            Some(format!("{field} = {}", buffer.replace(['\n', '\r'], " ")))
        }
        _ => None,
    };
    let u = unsaved(app);
    if u.text.is_none() && typing.is_none() {
        return None;
    }
    let text = u.text.unwrap_or_else(|| app.draft.clone());
    let mut out = format!(
        "{} pid={} model={}\n",
        crate::tui::form::swap::HEADER,
        std::process::id(),
        app.path.display()
    );
    if let Some(t) = typing {
        out += &format!("{}{t}\n", crate::tui::form::swap::TYPING);
    }
    out += &text;
    Some(out)
}

/// `NAME.recovered` in `dir`, or `NAME.recovered.N` (the first free N) when that exists.
pub fn recovery_path_in(dir: &Path, name: &str) -> PathBuf {
    let first = dir.join(format!("{name}.recovered"));
    if !first.exists() {
        return first;
    }
    (1..)
        .map(|i| dir.join(format!("{name}.recovered.{i}")))
        .find(|p| !p.exists())
        .expect("a free name")
}

/// `MODEL.toml.recovered` next to the model, or `MODEL.toml.recovered.N` (the first free N)
/// when that exists already.
pub fn recovery_path(model: &Path) -> PathBuf {
    let name = model
        .file_name()
        .map_or("model.toml".into(), |n| n.to_string_lossy().into_owned());
    recovery_path_in(model.parent().unwrap_or(Path::new("")), &name)
}

/// Where a recovery file may go, in order: next to the model, the state directory
/// (`tui::form::swap::state_dir`/recovered), the temp directory; the last two under the model's
/// whole path with `/` as `%`.
pub fn recovery_places(model: &Path) -> Vec<PathBuf> {
    let flat = crate::tui::form::swap::flattened(model);
    vec![
        recovery_path(model),
        recovery_path_in(
            &crate::tui::form::swap::state_dir().join("recovered"),
            &flat,
        ),
        recovery_path_in(&std::env::temp_dir(), &format!("deckspin-{flat}")),
    ]
}

/// Writes `text` to a new file (never over one), flushed to disk; a file left half written
/// (a full disk) is removed.
fn write_new(path: &Path, text: &str) -> io::Result<()> {
    if let Some(d) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(d)?;
    }
    let mut f = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(path)?;
    let r = f.write_all(text.as_bytes()).and_then(|()| f.sync_all());
    if r.is_err() {
        let _ = std::fs::remove_file(path);
    }
    r
}

/// Writes `text` to a new recovery file, in the first of [`recovery_places`] that takes it
/// whole; returns its path, or every place's error.
pub fn write_recovery(model: &Path, text: &str) -> io::Result<PathBuf> {
    let mut errors = Vec::new();
    for path in recovery_places(model) {
        match write_new(&path, text) {
            Ok(()) => return Ok(path),
            Err(e) => errors.push(format!("{}: {e}", path.display())),
        }
    }
    Err(io::Error::other(errors.join("; ")))
}

/// After `sig` ended the loop and the terminal is restored: save the unsaved work to a recovery
/// file, say so on stderr, and end the process as the signal would.
pub fn exit_after(sig: i32, app: &App, owns_swap: bool) -> ! {
    let u = unsaved(app);
    let mut err = io::stderr();
    let _ = writeln!(
        err,
        "deckspin: {} received, the workbench closed",
        name(sig)
    );
    if let Some(text) = &u.text {
        let _ = match write_recovery(&app.path, text) {
            Ok(p) => {
                // the edits are safe: this workbench's swap file goes
                if owns_swap {
                    crate::tui::form::swap::remove_all(&app.path);
                }
                writeln!(
                    err,
                    "deckspin: unsaved edits written to {} ({} is unchanged)",
                    p.display(),
                    app.path.display()
                )
            }
            Err(e) => writeln!(
                err,
                "deckspin: cannot write a recovery file ({e}); the edits stay in the swap file, offered at the next start"
            ),
        };
    }
    if let Some(n) = &u.note {
        let _ = writeln!(err, "deckspin: {n}");
    }
    die(sig)
}
