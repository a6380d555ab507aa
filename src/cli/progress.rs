//! The progress bar of long commands: runs done, rate and time left, drawn on stderr when it
//! is a terminal (tests and pipes see nothing).

use deckspin::progress::Progress;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressState, ProgressStyle};
use std::io::IsTerminal;

/// A bar on stderr (hidden when stderr is not a terminal), fed by the library's counts; with
/// [`Bar::with_lines`], a line at every tenth of the runs when stderr is not a terminal.
pub struct Bar(ProgressBar, Option<Lines>);

/// Progress lines for a log: the tenths said so far, and the start.
struct Lines {
    said: std::sync::atomic::AtomicU64,
    start: std::time::Instant,
}

impl Bar {
    /// An empty bar; the job plans its runs.
    pub fn new() -> Self {
        let target = if std::io::stderr().is_terminal() {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        };
        let bar = ProgressBar::with_draw_target(Some(0), target);
        let style = ProgressStyle::with_template(
            "{bar:30} {pos}/{len} runs, {rate} runs/s, {eta} left ({elapsed})",
        );
        if let Ok(style) = style {
            let rate = |s: &ProgressState, w: &mut dyn std::fmt::Write| {
                let _ = write!(w, "{:.1}", s.per_sec());
            };
            bar.set_style(style.with_key("rate", rate));
        }
        Self(bar, None)
    }

    /// [`Bar::new`], and where stderr is not a terminal (a log, a batch job) a line at every
    /// tenth of the runs: done, elapsed, and the time left at the rate so far.
    pub fn with_lines() -> Self {
        let mut b = Self::new();
        if b.0.is_hidden() {
            b.1 = Some(Lines {
                said: std::sync::atomic::AtomicU64::new(0),
                start: std::time::Instant::now(),
            });
        }
        b
    }

    /// Prints a line above the bar (stderr).
    pub fn note(&self, line: &str) {
        if self.0.is_hidden() {
            eprintln!("{line}");
        } else {
            self.0.println(line);
        }
    }

    /// Removes the bar.
    pub fn clear(&self) {
        self.0.finish_and_clear();
    }
}

impl Progress for Bar {
    fn plan(&self, runs: usize) {
        self.0.inc_length(runs as u64);
    }

    fn done(&self, runs: usize) {
        self.0.inc(runs as u64);
        if let Some(l) = &self.1 {
            let (pos, len) = (self.0.position(), self.0.length().unwrap_or(0).max(1));
            let tenth = pos * 10 / len;
            let said = l
                .said
                .fetch_max(tenth, std::sync::atomic::Ordering::Relaxed);
            if tenth > said {
                let t = l.start.elapsed().as_secs_f64();
                let left = t / pos as f64 * (len - pos) as f64;
                eprintln!(
                    "deckspin: {pos}/{len} runs ({} %) in {t:.1} s, about {left:.0} s left",
                    tenth * 10
                );
            }
        }
    }

    /// Not once a signal asked the job to stop.
    fn go_on(&self) -> bool {
        super::signals::requested().is_none()
    }
}

impl deckspin::studies::Watch for Bar {}

impl Drop for Bar {
    fn drop(&mut self) {
        self.0.finish_and_clear();
    }
}
