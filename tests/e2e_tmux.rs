//! End-to-end: the real `deckspin MODEL.toml` workbench in a detached tmux session (120×40).
//! Runs a 3 s copy of the four-span bridge, edits a gap in the form, saves, sees the rerun
//! and the comparison change, edits the file on disk and sees "reloaded", quits with `q` and
//! checks the terminal is back on the normal screen; a whole session from an interactive shell
//! (edit, run, pin, compare, events, the work-precision study, Ctrl-Z and `fg`, quit); panics,
//! signals, suspension. Skipped (passes) without tmux.

#![cfg(feature = "workbench")]

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

struct Tmux {
    socket: String,
}

impl Tmux {
    fn cmd(&self, args: &[&str]) -> std::process::Output {
        Command::new("tmux")
            .args(["-L", &self.socket, "-f", "/dev/null"])
            .args(args)
            .output()
            .expect("run tmux")
    }
    fn capture(&self) -> String {
        String::from_utf8_lossy(&self.cmd(&["capture-pane", "-p", "-t", "e2e"]).stdout).into_owned()
    }
    fn keys(&self, keys: &[&str]) {
        for k in keys {
            let out = self.cmd(&["send-keys", "-t", "e2e", k]);
            assert!(
                out.status.success(),
                "send-keys {k}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            std::thread::sleep(Duration::from_millis(30));
        }
    }
    fn text(&self, s: &str) {
        let out = self.cmd(&["send-keys", "-t", "e2e", "-l", s]);
        assert!(out.status.success());
    }
    /// Polls the pane until `pred` holds, returning the screen. A hang is a screen that stops
    /// changing for ten times `secs` (two minutes at least), not a slow one: every change of
    /// the screen (a run's progress) starts the stretch again, so a busy machine only waits.
    fn wait(&self, what: &str, secs: u64, pred: impl Fn(&str) -> bool) -> String {
        let stretch = Duration::from_secs((10 * secs).max(120));
        let (mut last, mut since) = (String::new(), Instant::now());
        loop {
            let s = self.capture();
            if pred(&s) {
                return s;
            }
            if s != last {
                (last, since) = (s.clone(), Instant::now());
            }
            if since.elapsed() > stretch {
                panic!("no progress waiting for {what}; screen:\n{s}");
            }
            std::thread::sleep(Duration::from_millis(100));
        }
    }
    /// Waits for the workbench to end and the shell's prompt to be the last line: keys typed
    /// before the process has exited go to its terminal, which drops them when it restores
    /// the mode.
    fn wait_prompt(&self) {
        self.wait("the workbench to end and the prompt", 10, |s| {
            self.alternate_on() == "0"
                && s.lines()
                    .rev()
                    .find(|l| !l.trim().is_empty())
                    .map(str::trim)
                    == Some("shell$")
        });
    }
    fn alternate_on(&self) -> String {
        self.format("#{alternate_on}")
    }
    /// 1 when the cursor is shown.
    fn cursor_flag(&self) -> String {
        self.format("#{cursor_flag}")
    }
    fn format(&self, f: &str) -> String {
        let out = self.cmd(&["display-message", "-p", "-t", "e2e", f]);
        String::from_utf8_lossy(&out.stdout).trim().to_string()
    }
}

impl Drop for Tmux {
    fn drop(&mut self) {
        let _ = self.cmd(&["kill-server"]);
    }
}

fn have_tmux() -> bool {
    Command::new("tmux")
        .arg("-V")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// tmp/models/four-span.toml (t_end = 3 s) + tmp/excitations/*.AT2, as the model expects.
fn workspace() -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    static N: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = N.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
    let d = std::env::temp_dir().join(format!("deckspin-e2e-{}-{n}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(d.join("models")).unwrap();
    std::fs::create_dir_all(d.join("excitations")).unwrap();
    for e in std::fs::read_dir(root.join("excitations")).unwrap() {
        let e = e.unwrap();
        if e.path().is_file() {
            std::fs::copy(e.path(), d.join("excitations").join(e.file_name())).unwrap();
        }
    }
    let text = std::fs::read_to_string(root.join("models/four-span.toml")).unwrap();
    let text = deckspin::tui::form::set_value(
        &text,
        "solver.t_end",
        deckspin::tui::form::Kind::Float,
        "3.0",
        deckspin::tui::form::Dim::Plain,
    )
    .unwrap();
    std::fs::write(d.join("models/four-span.toml"), text).unwrap();
    d
}

/// The first two numbers of a row of the runs compared (the baseline, the shown run).
fn row(screen: &str, name: &str) -> (String, String) {
    let line = screen
        .lines()
        .find(|l| l.contains(&format!("│{name}")))
        .unwrap_or_else(|| panic!("no row {name}:\n{screen}"));
    let cells: Vec<String> = line
        .rsplit('│')
        .nth(1)
        .unwrap()
        .trim_start_matches(name)
        .split_whitespace()
        .map(str::to_string)
        .collect();
    (cells[0].clone(), cells.get(1).cloned().unwrap_or_default())
}

/// Starts the workbench on tmp/models/four-span.toml in session "e2e" (120×40) through a shell
/// that reports the exit code and whether the terminal is back in canonical (cooked) mode.
/// The workbench's process id goes to tmp/deckspin.pid.
fn start(tmux: &Tmux, d: &Path, env: &str) {
    let script = format!(
        "cd '{}' && {env} sh -c 'echo $$ > deckspin.pid; exec \"$0\" \"$@\"' '{}' \
         models/four-span.toml; echo deckspin-exited-$?; \
         stty -a | tr ' ;' '\\n\\n' | grep -x -e icanon -e -icanon; echo stty-done; exec sleep 120",
        d.display(),
        env!("CARGO_BIN_EXE_deckspin")
    );
    let out = tmux.cmd(&[
        "new-session",
        "-d",
        "-s",
        "e2e",
        "-x",
        "120",
        "-y",
        "40",
        "sh",
        "-c",
        &script,
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn unix_ms() -> f64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .as_secs_f64()
        * 1e3
}

#[test]
fn workbench_in_tmux() {
    if !have_tmux() {
        println!("tmux is not on PATH: skipping the end-to-end terminal test");
        return;
    }
    let d = workspace();
    let model = d.join("models/four-span.toml");
    let timing = d.join("timing.log");
    let tmux = Tmux {
        socket: format!("deckspin-e2e-{}", std::process::id()),
    };
    start(
        &tmux,
        &d,
        &format!("DECKSPIN_TIMING='{}'", timing.display()),
    );
    // the first run streams and finishes
    let s = tmux.wait("#1 to finish", 30, |s| s.contains("#1 done"));
    assert_eq!(
        tmux.alternate_on(),
        "1",
        "the workbench uses the alternate screen"
    );
    assert!(s.contains("deck.theta [µrad]"), "{s}");
    assert!(s.contains("gaps g_N [mm]"), "{s}");
    assert!(s.contains("events "), "{s}");
    assert!(s.contains("plan ×"), "{s}");
    assert!(
        s.contains("watch: notify") || s.contains("watch: polling"),
        "{s}"
    );

    // jump from event to event, open the event list, go to an event in it, close it
    tmux.keys(&["Home"]);
    tmux.text("]");
    tmux.wait("the first event", 5, first_event);
    tmux.text("]");
    tmux.wait("the second event", 5, |s| later_event(s).is_some());
    tmux.text("E");
    tmux.wait("the event list", 5, |s| s.contains("t [s] contact"));
    tmux.keys(&["Down", "Enter"]);
    tmux.wait("the cursor on the selected event", 5, |s| {
        later_event(s).is_some()
    });
    tmux.text("E");
    tmux.wait("the side panels back", 5, |s| s.contains("plan ×"));
    tmux.keys(&["End"]);

    // edit the left_top gap in the form
    tmux.keys(&["Tab"]);
    tmux.wait("the form", 5, |s| s.contains("parameters"));
    // found by the form's search
    tmux.text("/gap 1");
    tmux.keys(&["Enter"]);
    tmux.wait("the gap field", 5, |s| {
        s.contains("contacts gap 1 (left_top)")
    });
    tmux.keys(&["Enter", "C-u"]);
    tmux.text("0.002");
    tmux.wait("a valid value", 5, |s| s.contains("✓ valid"));
    tmux.keys(&["Enter"]);
    tmux.wait("the edit to be accepted", 5, |s| {
        s.contains("four-span.toml [+]")
    });

    // save: the file keeps its comments, the model reruns, the comparison changes
    tmux.keys(&["s"]);
    let s = tmux.wait("#2 to finish", 30, |s| s.contains("#2 done"));
    let saved = std::fs::read_to_string(&model).unwrap();
    assert!(
        saved.contains("gaps = [0.002, 0.0127, 0.0127, 0.0127]"),
        "{saved}"
    );
    assert!(saved.contains("# m, corners left_top, left_bottom, right_top, right_bottom"));
    assert!(!s.contains("[+]"), "saved: no unsaved edits left\n{s}");
    let (base, now) = row(&s, "peak |θ|");
    assert_ne!(now, base, "the rotation peak changed with the gap:\n{s}");
    assert!(s.contains("#1 base"), "the baseline compared:\n{s}");

    // the run list: #2 against the baseline #1, its model diff; kept beside the model
    tmux.keys(&["#"]);
    let s = tmux.wait("the run list", 5, |s| {
        s.contains("#2 against #1: 1 changed")
    });
    assert!(
        s.contains("contacts gap 1 (left_top): 0.0127 → 0.002"),
        "{s}"
    );
    let stored = d.join("models/four-span.runs/0002.json");
    tmux.wait("the run stored", 10, |_| stored.is_file());

    // change the file on disk like an editor (write a temporary file, rename it over); from
    // the run list, S-Tab is the studies view
    tmux.keys(&["BTab"]);
    let edited = saved.replace("mu = 0.5 ", "mu = 0.4 ") + "# touched by the e2e test\n";
    let tmp = d.join("models/.four-span.toml.swp");
    std::fs::write(&tmp, &edited).unwrap();
    let t_write = unix_ms();
    std::fs::rename(&tmp, &model).unwrap();
    tmux.wait("reloaded", 10, |s| s.contains("reloaded"));
    tmux.wait("#3 to finish", 30, |s| s.contains("#3 done"));

    // the studies view: the PGA study runs in its own thread on the model,
    // is drawn, and its CSV is written beside the model
    tmux.wait("the studies view", 5, |s| s.contains(">PGA (Fig. 7)"));
    tmux.keys(&["Enter"]);
    let s = tmux.wait("the PGA study", 60, |s| s.contains(">PGA (Fig. 7): done"));
    assert!(
        s.contains("# with contact") && s.contains("PGA x [g]"),
        "{s}"
    );
    let csv = d.join("models/four-span.out/pga-1.csv");
    tmux.wait("its CSV", 10, |_| csv.is_file());

    // quit: back to the shell on the normal screen
    tmux.keys(&["q"]);
    let s = tmux.wait("the shell", 10, |s| s.contains("deckspin-exited-0"));
    assert_eq!(tmux.alternate_on(), "0", "alternate screen left");
    assert!(
        !s.contains("deck.theta ["),
        "workbench still on screen:\n{s}"
    );

    // timings (printed, not asserted)
    let log = std::fs::read_to_string(&timing).unwrap_or_default();
    let at = |label: &str| {
        log.lines()
            .filter(|l| l.contains(label))
            .filter_map(|l| l.split_whitespace().next()?.parse::<f64>().ok())
            .collect::<Vec<f64>>()
    };
    if let (Some(start), Some(first)) = (at("start").first(), at("first-frame").first()) {
        println!("startup to first frame: {:.1} ms", first - start);
    }
    if let Some(f3) = at("first-run-frame 3").first() {
        println!(
            "file saved on disk to first chart frame of the new run: {:.1} ms",
            f3 - t_write
        );
    }
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn panics_restore_the_terminal() {
    if !have_tmux() {
        println!("tmux is not on PATH: skipping the end-to-end terminal test");
        return;
    }
    let d = workspace();
    // a panic in the simulation thread is a failed run; the workbench goes on
    let tmux = Tmux {
        socket: format!("deckspin-e2e-worker-{}", std::process::id()),
    };
    start(&tmux, &d, "DECKSPIN_TEST_PANIC=worker");
    let s = tmux.wait("the failed run", 30, |s| s.contains("#1 failed"));
    assert!(s.contains("the engine panicked"), "{s}");
    assert!(s.contains("DECKSPIN_TEST_PANIC=worker"), "{s}");
    tmux.keys(&["q"]);
    let s = tmux.wait("the shell", 10, |s| s.contains("stty-done"));
    assert!(s.contains("deckspin-exited-0"), "{s}");
    drop(tmux);

    // a panic on the UI thread: the hook restores the terminal, then the message is printed
    let tmux = Tmux {
        socket: format!("deckspin-e2e-ui-{}", std::process::id()),
    };
    start(&tmux, &d, "DECKSPIN_TEST_PANIC=ui");
    let s = tmux.wait("the shell", 30, |s| s.contains("stty-done"));
    assert!(s.contains("deckspin-exited-101"), "{s}");
    assert!(
        s.contains("DECKSPIN_TEST_PANIC=ui: a panic on the UI thread"),
        "message printed:\n{s}"
    );
    assert_eq!(tmux.alternate_on(), "0", "alternate screen left");
    assert!(
        s.lines().any(|l| l.trim() == "icanon"),
        "raw mode left on:\n{s}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// Sends `sig` (TERM, HUP, INT) to the workbench started by [`start`] in `d`.
fn kill(d: &Path, sig: &str) {
    let pid = std::fs::read_to_string(d.join("deckspin.pid")).unwrap();
    let out = Command::new("kill")
        .args([&format!("-{sig}"), pid.trim()])
        .output()
        .expect("run kill");
    assert!(out.status.success(), "kill -{sig} {pid}");
}

/// Starts the workbench, optionally edits the left_top gap without saving, sends `sig`, and
/// checks the shell is back on the normal screen with the cursor shown and raw mode off, and
/// the exit status is the signal's. Returns the screen.
fn signal_round(d: &Path, sig: &str, status: i32, edit: bool) -> String {
    let tmux = Tmux {
        socket: format!("deckspin-e2e-{sig}-{}", std::process::id()),
    };
    start(&tmux, d, "");
    tmux.wait("the workbench", 30, |s| s.contains("deck.theta ["));
    assert_eq!(tmux.alternate_on(), "1");
    assert_eq!(tmux.cursor_flag(), "0", "the workbench hides the cursor");
    if edit {
        tmux.keys(&["Tab"]);
        tmux.wait("the form", 5, |s| s.contains("parameters"));
        // found by the form's search
        tmux.text("/gap 1");
        tmux.keys(&["Enter"]);
        tmux.wait("the gap field", 5, |s| {
            s.contains("contacts gap 1 (left_top)")
        });
        tmux.keys(&["Enter", "C-u"]);
        tmux.text("0.002");
        tmux.wait("a valid value", 5, |s| s.contains("✓ valid"));
        tmux.keys(&["Enter"]);
        tmux.wait("the edit", 5, |s| s.contains("four-span.toml [+]"));
    }
    kill(d, sig);
    let s = tmux.wait("the shell", 10, |s| s.contains("stty-done"));
    assert!(s.contains(&format!("deckspin-exited-{status}")), "{s}");
    assert_eq!(
        tmux.alternate_on(),
        "0",
        "alternate screen left after {sig}"
    );
    assert_eq!(tmux.cursor_flag(), "1", "cursor shown after {sig}");
    assert!(
        s.lines().any(|l| l.trim() == "icanon"),
        "raw mode left on after {sig}:\n{s}"
    );
    assert!(
        !s.contains("deck.theta ["),
        "workbench still on screen:\n{s}"
    );
    assert!(s.contains(&format!("deckspin: SIG{sig} received")), "{s}");
    s
}

#[test]
fn signals_restore_the_terminal_and_keep_unsaved_edits() {
    if !have_tmux() {
        println!("tmux is not on PATH: skipping the end-to-end terminal test");
        return;
    }
    let d = workspace();
    let model = d.join("models/four-span.toml");
    let original = std::fs::read_to_string(&model).unwrap();
    let recovered = d.join("models/four-span.toml.recovered");
    // SIGTERM with an unsaved edit: recovery file, the model untouched
    let s = signal_round(&d, "TERM", 143, true);
    assert!(
        s.contains("unsaved edits written to models/four-span.toml.recovered"),
        "{s}"
    );
    assert_eq!(std::fs::read_to_string(&model).unwrap(), original);
    let r = std::fs::read_to_string(&recovered).unwrap();
    assert!(r.contains("gaps = [0.002, 0.0127, 0.0127, 0.0127]"), "{r}");
    // SIGHUP (the terminal's connection dropped) with an edit: the next free recovery name
    let s = signal_round(&d, "HUP", 129, true);
    assert!(s.contains("four-span.toml.recovered.1"), "{s}");
    let r1 = std::fs::read_to_string(d.join("models/four-span.toml.recovered.1")).unwrap();
    assert_eq!(r1, r);
    assert_eq!(std::fs::read_to_string(&model).unwrap(), original);
    // an external SIGINT without edits: restored, no recovery file
    let s = signal_round(&d, "INT", 130, false);
    assert!(!s.contains("unsaved edits"), "{s}");
    assert!(!d.join("models/four-span.toml.recovered.2").exists());
    let _ = std::fs::remove_dir_all(&d);
}

/// Ctrl-Z in the workbench started from an interactive shell: the shell's screen comes back
/// with the job stopped, `fg` brings the workbench back redrawn whole, `q` quits to the shell.
#[test]
fn ctrl_z_suspends_to_the_shell_and_fg_resumes() {
    if !have_tmux() || Command::new("bash").arg("--version").output().is_err() {
        println!("tmux or bash is not on PATH: skipping the suspend test");
        return;
    }
    let d = workspace();
    let tmux = Tmux {
        socket: format!("deckspin-e2e-z-{}", std::process::id()),
    };
    start_in_shell(&tmux, &d, (80, 24));

    tmux.keys(&["C-z"]);
    let s = tmux.wait("the stopped job", 10, |s| s.contains("Stopped"));
    assert_eq!(tmux.alternate_on(), "0", "the main screen is back:\n{s}");
    assert_eq!(tmux.cursor_flag(), "1", "the cursor is shown:\n{s}");
    assert!(!s.contains("deck.theta [rad]"), "{s}");

    tmux.text("fg");
    tmux.keys(&["Enter"]);
    let s = tmux.wait("the workbench again", 10, |s| {
        s.contains("deck.theta [") && s.contains("#1 done") && s.contains("q quit")
    });
    assert_eq!(tmux.alternate_on(), "1", "{s}");
    // redrawn whole: the header, the charts, the status and hint lines are all there
    assert!(
        s.lines().next().unwrap_or("").starts_with("deckspin"),
        "{s}"
    );
    assert!(s.contains("gaps g_N [") && s.contains("events "), "{s}");
    // and it still takes keys
    tmux.keys(&["Tab"]);
    tmux.wait("the form", 5, |s| s.contains("parameters"));
    tmux.keys(&["q"]);
    tmux.wait_prompt();
    tmux.text("echo deckspin-exited-$?");
    tmux.keys(&["Enter"]);
    tmux.wait("the shell", 10, |s| s.contains("deckspin-exited-0"));
    let _ = std::fs::remove_dir_all(&d);
}

/// Starts an interactive bash (prompt `shell$ `) in session "e2e" at `w`×`h`, in `d`, and the
/// workbench in it on models/four-span.toml, as a user would (so that Ctrl-Z stops it as a
/// job); waits for the first run to end.
fn start_in_shell(tmux: &Tmux, d: &Path, (w, h): (u16, u16)) {
    let (w, h) = (w.to_string(), h.to_string());
    let out = tmux.cmd(&[
        "new-session",
        "-d",
        "-s",
        "e2e",
        "-x",
        &w,
        "-y",
        &h,
        "env",
        "PS1=shell$ ",
        "bash",
        "--norc",
        "--noprofile",
        "-i",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    tmux.wait("the shell", 10, |s| s.contains("shell$"));
    tmux.text(&format!(
        "cd '{}' && '{}' models/four-span.toml",
        d.display(),
        env!("CARGO_BIN_EXE_deckspin")
    ));
    tmux.keys(&["Enter"]);
    tmux.wait("run 1 to finish", 30, |s| s.contains("#1 done"));
    assert_eq!(tmux.alternate_on(), "1");
}

/// In the form: finds the left_top gap by the search and types `value` into it (not saved).
fn edit_gap(tmux: &Tmux, value: &str) {
    tmux.text("/gap 1");
    tmux.keys(&["Enter"]);
    tmux.wait("the gap field", 5, |s| {
        s.contains("contacts gap 1 (left_top)")
    });
    tmux.keys(&["Enter", "C-u"]);
    tmux.text(value);
    tmux.wait("a valid value", 5, |s| {
        s.contains("✓ valid") && s.contains(value)
    });
    tmux.keys(&["Enter"]);
    tmux.wait("the edit to be accepted", 5, |s| {
        s.contains("four-span.toml [+]")
            && s.lines()
                .any(|l| l.contains("contacts gap 1 (left_top)") && l.contains(value))
            && !s.contains("✓ valid")
    });
}

/// A whole session as a user has it: an edit run before saving, the run pinned as the
/// baseline, another edit run and compared with it (run list, overlay, runs compared), the
/// cursor from event to event, the work-precision study in the studies view, Ctrl-Z and `fg`,
/// and quitting without saving. Asserts on the screen at each step; bounded in time.
#[test]
fn a_whole_session_edit_run_pin_compare_study_suspend_quit() {
    if !have_tmux() || Command::new("bash").arg("--version").output().is_err() {
        println!("tmux or bash is not on PATH: skipping the whole-session test");
        return;
    }
    let d = workspace();
    let model = d.join("models/four-span.toml");
    let saved = std::fs::read_to_string(&model).unwrap();
    let tmux = Tmux {
        socket: format!("deckspin-e2e-session-{}", std::process::id()),
    };
    start_in_shell(&tmux, &d, (120, 40));

    // edit the left_top gap and run the draft (not saved): #2
    tmux.keys(&["Tab"]);
    tmux.wait("the form", 5, |s| s.contains("parameters"));
    edit_gap(&tmux, "0.008");
    tmux.keys(&["r"]);
    tmux.wait("#2 to finish", 30, |s| s.contains("#2 done"));

    // the run list: #2 selected, pinned as the baseline
    tmux.keys(&["#"]);
    let s = tmux.wait("the run list", 5, |s| s.contains("runs (2) · baseline #1"));
    assert!(s.contains("#2 against #1: 1 changed"), "{s}");
    assert!(
        s.contains("contacts gap 1 (left_top): 0.0127 → 0.008"),
        "{s}"
    );
    tmux.keys(&["b"]);
    let s = tmux.wait("#2 pinned", 5, |s| s.contains("runs (2) · baseline #2"));
    assert!(s.contains("#2 is the baseline"), "{s}");
    assert!(s.lines().any(|l| l.contains("│B #2 ")), "#2 marked B:\n{s}");

    // edit again, run: #3, compared with the baseline #2
    tmux.keys(&["Tab"]);
    tmux.wait("the form", 5, |s| s.contains("parameters"));
    edit_gap(&tmux, "0.004");
    tmux.keys(&["r"]);
    tmux.wait("#3 to finish", 30, |s| s.contains("#3 done"));
    tmux.keys(&["#"]);
    let s = tmux.wait("the run list", 5, |s| s.contains("runs (3) · baseline #2"));
    assert!(s.contains("#3 against #2: 1 changed"), "{s}");
    assert!(
        s.contains("contacts gap 1 (left_top): 0.008 → 0.004"),
        "{s}"
    );
    assert!(s.contains("runs compared"), "{s}");
    assert!(s.contains("#2 base"), "{s}");
    let (base, now) = row(&s, "peak |θ|");
    assert!(base.parse::<f64>().unwrap() > 0.0, "{s}");
    assert!(now.parse::<f64>().unwrap() > 0.0, "{s}");
    assert_ne!(base, now, "the gaps differ, so do the peaks:\n{s}");
    // overlay #1 as well, then back to the charts: #2 and #1 drawn under #3
    tmux.keys(&["Up", "Up"]);
    tmux.keys(&["Space"]);
    tmux.wait("#1 overlaid", 5, |s| {
        s.contains("#1 overlaid on the charts and compared")
    });
    tmux.keys(&["Enter"]);
    let s = tmux.wait("the charts with the overlay", 5, |s| {
        s.contains("deck.theta [") && s.contains("┈#2") && s.contains("┈#1")
    });
    assert!(s.contains("#3 done"), "{s}");

    // from event to event
    tmux.keys(&["Home"]);
    tmux.text("]");
    tmux.wait("the first event", 5, first_event);
    tmux.text("]");
    let s = tmux.wait("the second event", 5, |s| later_event(s).is_some());
    let t2 = later_event(&s).unwrap();
    assert!(t2.contains("at t = "), "{s}");
    tmux.text("[");
    tmux.wait("back to the first event", 5, first_event);

    // the studies view: the work-precision study, run and drawn
    tmux.keys(&["Tab", "Tab"]);
    tmux.wait("the studies view", 5, |s| s.contains(">PGA (Fig. 7)"));
    tmux.keys(&["l", "l", "l", "l"]);
    tmux.wait("the work-precision study", 5, |s| {
        s.contains(">work-precision")
    });
    tmux.keys(&["Enter"]);
    let s = tmux.wait("the work-precision chart", 40, |s| {
        s.contains(">work-precision: done") && s.contains("CPU time [s], log")
    });
    assert!(s.contains("1 %"), "the 1 % line in the legend:\n{s}");
    assert!(
        s.contains("model: form draft (unsaved edits)"),
        "run on the draft:\n{s}"
    );

    // Ctrl-Z: the shell with the job stopped; fg: the same view redrawn
    tmux.keys(&["C-z"]);
    let s = tmux.wait("the stopped job", 10, |s| s.contains("Stopped"));
    assert_eq!(tmux.alternate_on(), "0", "{s}");
    tmux.text("fg");
    tmux.keys(&["Enter"]);
    let s = tmux.wait("the workbench again", 10, |s| {
        s.contains(">work-precision: done") && s.contains("CPU time [s], log")
    });
    assert_eq!(tmux.alternate_on(), "1", "{s}");
    assert!(
        s.lines().next().unwrap_or("").starts_with("deckspin"),
        "{s}"
    );

    // quit: asked about the unsaved edits, quit without saving
    tmux.keys(&["q"]);
    tmux.wait("the question", 5, |s| {
        s.contains("four-span.toml has unsaved edits.")
    });
    tmux.keys(&["y"]);
    tmux.wait_prompt();
    tmux.text("echo deckspin-exited-$?");
    tmux.keys(&["Enter"]);
    tmux.wait("the shell", 10, |s| s.contains("deckspin-exited-0"));
    assert_eq!(std::fs::read_to_string(&model).unwrap(), saved, "not saved");
    // the runs are kept beside the model
    for n in 1..=3 {
        assert!(
            d.join(format!("models/four-span.runs/000{n}.json"))
                .is_file()
        );
    }

    let _ = std::fs::remove_dir_all(&d);
}

/// SIGKILL after an accepted edit: the swap file written within about a second holds it, and
/// the next start offers it with the difference shown; `r` recovers it as an unsaved edit, `s`
/// saves it and the swap file goes.
#[test]
fn a_killed_workbench_offers_its_unsaved_edit_at_the_next_start() {
    if !have_tmux() {
        println!("tmux is not on PATH: skipping the end-to-end terminal test");
        return;
    }
    let d = workspace();
    let model = d.join("models/four-span.toml");
    let swap = d.join("models/.four-span.toml.swp");
    let original = std::fs::read_to_string(&model).unwrap();
    let tmux = Tmux {
        socket: format!("deckspin-e2e-swap-{}", std::process::id()),
    };
    start(&tmux, &d, "");
    tmux.wait("the workbench", 30, |s| s.contains("deck.theta ["));
    tmux.keys(&["Tab"]);
    tmux.wait("the form", 5, |s| s.contains("parameters"));
    tmux.text("/gap 1");
    tmux.keys(&["Enter"]);
    tmux.wait("the gap field", 5, |s| {
        s.contains("contacts gap 1 (left_top)")
    });
    tmux.keys(&["Enter", "C-u"]);
    tmux.text("0.002");
    tmux.wait("a valid value", 5, |s| s.contains("✓ valid"));
    tmux.keys(&["Enter"]);
    tmux.wait("the edit", 5, |s| s.contains("four-span.toml [+]"));
    // the swap is written SETTLE after the edit; a hang is no swap while the screen is idle
    let mut polls = 0;
    while !std::fs::read_to_string(&swap).is_ok_and(|t| t.contains("0.002")) {
        polls += 1;
        assert!(polls < 1200, "no swap file with the edit after 120 s");
        std::thread::sleep(Duration::from_millis(100));
    }
    kill(&d, "KILL");
    tmux.wait("the shell", 10, |s| s.contains("stty-done"));
    drop(tmux);
    assert_eq!(std::fs::read_to_string(&model).unwrap(), original);
    assert!(swap.exists(), "a killed workbench leaves its swap file");
    let tmux = Tmux {
        socket: format!("deckspin-e2e-swap2-{}", std::process::id()),
    };
    start(&tmux, &d, "");
    let s = tmux.wait("the recovery question", 30, |s| {
        s.contains("Unsaved edits of")
    });
    assert!(s.contains("0.002"), "the difference is shown:\n{s}");
    tmux.keys(&["r"]);
    let s = tmux.wait("the recovered edit", 10, |s| {
        s.contains("four-span.toml [+]")
    });
    assert!(s.contains("recovered"), "{s}");
    tmux.keys(&["s"]);
    tmux.wait("the save", 30, |s| !s.contains("four-span.toml [+]"));
    let saved = std::fs::read_to_string(&model).unwrap();
    assert!(
        saved.contains("gaps = [0.002, 0.0127, 0.0127, 0.0127]"),
        "{saved}"
    );
    tmux.keys(&["q"]);
    tmux.wait("the shell", 10, |s| s.contains("stty-done"));
    assert!(!swap.exists(), "a clean save and quit leaves no swap file");
    let _ = std::fs::remove_dir_all(&d);
}

/// Ctrl-C while typing a value in the real terminal: the quit question comes, `n` stays with
/// the value kept as an unsaved edit.
#[test]
fn ctrl_c_while_typing_asks_in_the_terminal() {
    if !have_tmux() {
        println!("tmux is not on PATH: skipping the end-to-end terminal test");
        return;
    }
    let d = workspace();
    let tmux = Tmux {
        socket: format!("deckspin-e2e-ctrlc-{}", std::process::id()),
    };
    start(&tmux, &d, "");
    tmux.wait("the workbench", 30, |s| s.contains("deck.theta ["));
    tmux.keys(&["Tab"]);
    tmux.wait("the form", 5, |s| s.contains("parameters"));
    tmux.text("/gap 1");
    tmux.keys(&["Enter"]);
    tmux.wait("the gap field", 5, |s| {
        s.contains("contacts gap 1 (left_top)")
    });
    tmux.keys(&["Enter", "C-u"]);
    tmux.text("0.003");
    tmux.wait("a valid value", 5, |s| s.contains("✓ valid"));
    tmux.keys(&["C-c"]);
    let s = tmux.wait("the quit question", 10, |s| s.contains("has unsaved edits"));
    assert!(s.contains("four-span.toml"), "{s}");
    tmux.keys(&["n"]);
    let s = tmux.wait("the edit kept", 10, |s| s.contains("four-span.toml [+]"));
    assert!(s.contains("0.003"), "{s}");
    tmux.keys(&["q"]);
    tmux.wait("the question again", 10, |s| {
        s.contains("has unsaved edits")
    });
    tmux.keys(&["y"]);
    tmux.wait("the shell", 10, |s| s.contains("stty-done"));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_vt100_gets_ascii_and_the_override_gives_unicode_back() {
    if !have_tmux() {
        println!("tmux is not on PATH: skipping the end-to-end terminal test");
        return;
    }
    let d = workspace();
    // TERM=vt100: the whole screen ASCII, the zero line `-`
    let tmux = Tmux {
        socket: format!("deckspin-e2e-vt100-{}", std::process::id()),
    };
    start(&tmux, &d, "TERM=vt100");
    let s = tmux.wait("#1 to finish", 30, |s| s.contains("#1 done"));
    assert!(s.contains("deck.theta [urad]"), "{s}");
    let wide: Vec<char> = s.chars().filter(|c| !c.is_ascii()).collect();
    assert!(wide.is_empty(), "{wide:?}\n{s}");
    assert!(s.contains("+ plan x"), "{s}");
    tmux.keys(&["q"]);
    let s = tmux.wait("the shell", 10, |s| s.contains("stty-done"));
    assert!(s.contains("deckspin-exited-0"), "{s}");
    drop(tmux);
    // the same terminal with DECKSPIN_GLYPHS=unicode: Braille and box drawing again
    let tmux = Tmux {
        socket: format!("deckspin-e2e-unicode-{}", std::process::id()),
    };
    start(&tmux, &d, "TERM=vt100 DECKSPIN_GLYPHS=unicode");
    // the same model text: #1 is shown again, not rerun
    let s = tmux.wait("#1 reused", 30, |s| {
        s.contains("#1 reused") && s.contains("deck.theta [")
    });
    assert!(s.contains("deck.theta [µrad]"), "{s}");
    assert!(s.contains('│'), "{s}");
    tmux.keys(&["q"]);
    tmux.wait("the shell", 10, |s| s.contains("stty-done"));
    drop(tmux);
    let _ = std::fs::remove_dir_all(&d);
}
/// The message log in the real terminal: `M` shows every message said since the start with its
/// time (the load, the run's start and end), `M` again closes it and the status line still says
/// the last message.
#[test]
fn the_message_log_opens_and_closes_in_the_terminal() {
    if !have_tmux() {
        println!("tmux is not on PATH: skipping the end-to-end terminal test");
        return;
    }
    let d = workspace();
    let tmux = Tmux {
        socket: format!("deckspin-e2e-log-{}", std::process::id()),
    };
    start(&tmux, &d, "");
    tmux.wait("the workbench", 30, |s| s.contains("deck.theta ["));
    tmux.wait("the first run's end", 60, |s| {
        s.contains("#1 finished at t =")
    });
    tmux.keys(&["M"]);
    let s = tmux.wait("the message log", 10, |s| s.contains(" messages ("));
    for said in [
        "loaded four-span.toml",
        "#1 started",
        "#1 finished at t = 3.000 s",
    ] {
        assert!(s.contains(said), "{said}:\n{s}");
    }
    // each with its time, HH:MM:SS
    let timed = s
        .lines()
        .filter(|l| {
            let t: Vec<char> = l.trim_start_matches(['│', ' ']).chars().take(8).collect();
            t.len() == 8 && t[2] == ':' && t[5] == ':'
        })
        .count();
    assert!(timed >= 3, "{s}");
    tmux.keys(&["M"]);
    let s = tmux.wait("the log closed", 10, |s| !s.contains(" messages ("));
    assert!(s.contains("#1 finished at t = 3.000 s"), "{s}");
    tmux.keys(&["q"]);
    tmux.wait("the shell", 10, |s| s.contains("stty-done"));
    let _ = std::fs::remove_dir_all(&d);
}

/// The status line after a jump to the first instant with events: `event 1/N …`, or
/// `events 1–2/N …` when it holds several.
fn first_event(s: &str) -> bool {
    s.contains("event 1/") || s.contains("events 1–")
}

/// The status line after a jump to a later instant: `event k/N at t = …` (or `events k–m/N`)
/// with k above 1.
fn later_event(s: &str) -> Option<String> {
    s.lines()
        .find(|l| {
            (l.contains("event ") || l.contains("events "))
                && l.contains(" at t = ")
                && !first_event(l)
        })
        .map(str::to_string)
}

/// A failed run picked from the run list (`#`), its whole reason read on its info page (`i`):
/// longer than the status line, whole there.
#[test]
fn a_failed_runs_whole_reason_from_the_run_list() {
    if !have_tmux() {
        println!("tmux is not on PATH: skipping the end-to-end terminal test");
        return;
    }
    let d = workspace();
    let tmux = Tmux {
        socket: format!("deckspin-e2e-info-{}", std::process::id()),
    };
    start(&tmux, &d, "DECKSPIN_TEST_PANIC=worker");
    let s = tmux.wait("the failed run", 30, |s| s.contains("#1 failed"));
    let status = s.lines().find(|l| l.contains("#1 failed")).unwrap();
    assert!(
        !status.contains("a panic in the simulation thread"),
        "cut: {s}"
    );
    tmux.keys(&["#"]);
    let s = tmux.wait("the run list", 10, |s| s.contains("runs (1)"));
    assert!(
        s.lines()
            .any(|l| l.contains("#1 ") && l.contains("failed: panic")),
        "{s}"
    );
    tmux.keys(&["i"]);
    let s = tmux.wait("the run info", 10, |s| s.contains("run info"));
    // the text beside the labels, its lines joined
    let text: Vec<String> = (s.lines())
        .filter(|l| l.starts_with('│'))
        .map(|l| l.chars().skip(15).collect::<String>())
        .map(|l| l.trim_end_matches('│').trim().to_string())
        .collect();
    let text = text.join(" ");
    // the panic's place (file:line:column), then its message on the next line
    assert!(
        text.contains("the engine panicked: panicked at src/tui/workers/run.rs:"),
        "{text}\n{s}"
    );
    assert!(
        text.contains("DECKSPIN_TEST_PANIC=worker: a panic in the simulation thread"),
        "{text}\n{s}"
    );
    assert!(s.contains("event-driven"), "the method: {s}");
    tmux.keys(&["q"]);
    tmux.wait("the run list again", 10, |s| {
        !s.contains("run info") && s.contains("runs (1)")
    });
    tmux.keys(&["q"]);
    let s = tmux.wait("the shell", 10, |s| s.contains("stty-done"));
    assert!(s.contains("deckspin-exited-0"), "{s}");
    let _ = std::fs::remove_dir_all(&d);
}
