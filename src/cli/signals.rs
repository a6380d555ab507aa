//! SIGINT, SIGTERM and SIGHUP during a run stop it like a failure: the run ends at its next
//! batch as cancelled and its files are written with that status (`suite`, `sweep`, `stress`:
//! the runs not started are left, the finished ones are in the journal); a second SIGINT ends
//! the process at once (exit 130).

use std::sync::atomic::{AtomicI32, Ordering};

/// The first stopping signal received (0: none).
static STOP: AtomicI32 = AtomicI32::new(0);

#[cfg(unix)]
extern "C" fn on_signal(sig: libc::c_int) {
    // async-signal-safe: an atomic swap and _exit
    if STOP.swap(sig, Ordering::SeqCst) != 0 && sig == libc::SIGINT {
        // SAFETY: _exit is async-signal-safe
        unsafe { libc::_exit(130) };
    }
}

/// Installs the handlers (before any run starts).
pub fn install() {
    #[cfg(unix)]
    for sig in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
        // SAFETY: a handler that only touches an atomic and calls _exit; sigaction's struct is
        // zeroed then filled
        unsafe {
            let mut sa: libc::sigaction = std::mem::zeroed();
            sa.sa_sigaction = on_signal as extern "C" fn(libc::c_int) as usize;
            libc::sigemptyset(&mut sa.sa_mask);
            sa.sa_flags = libc::SA_RESTART;
            libc::sigaction(sig, &sa, std::ptr::null_mut());
        }
    }
}

/// The signal that asked the run to stop, if any.
pub fn requested() -> Option<i32> {
    match STOP.load(Ordering::SeqCst) {
        0 => None,
        s => Some(s),
    }
}

/// A run stopped by a signal: exit 128 + the signal's number.
#[derive(Debug)]
pub struct Interrupted {
    pub signal: i32,
    pub t: f64,
}

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let name = name(self.signal);
        write!(
            f,
            "cancelled by {name} at t = {:.9} s (its files say \"cancelled\")",
            self.t
        )
    }
}

impl std::error::Error for Interrupted {}

/// SIGINT, SIGTERM, SIGHUP or "a signal".
pub fn name(signal: i32) -> &'static str {
    match signal {
        2 => "SIGINT",
        15 => "SIGTERM",
        1 => "SIGHUP",
        _ => "a signal",
    }
}
