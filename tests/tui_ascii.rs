//! The workbench's ASCII drawing: every view of the four-span and the three-frame bridges drawn
//! in ASCII alone by the panels themselves (before the last pass that would stand in for
//! anything left), the zero line told apart from every series, the glyphs told by the
//! terminal or overridden, and a snapshot of the charts view with its plan.

#![cfg(feature = "workbench")]

mod common;

use common::root;
use common::tui::*;

use deckspin::tui::app::{Confirm, Mode, StatusKind, View};
use deckspin::tui::keymap::Action;
use deckspin::tui::results::Page;
use deckspin::tui::runs::data::{RunData, RunStatus};
use deckspin::tui::runs::list::Entry;
use deckspin::tui::term::{GLYPHS_VAR, Glyphs};
use deckspin::tui::{self, App, Msg, Options, update};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

// ---------------------------------------------------------------------------------------------
// fixtures

/// The two bridges drawn: their model file and how long their runs are.
#[derive(Clone, Copy, Debug)]
enum Bridge {
    FourSpan,
    ThreeFrame,
}

impl Bridge {
    const ALL: [Bridge; 2] = [Bridge::FourSpan, Bridge::ThreeFrame];

    /// The model's path relative to the package root (snapshots hold no checkout location).
    fn rel(self) -> &'static str {
        match self {
            Bridge::FourSpan => "models/four-span.toml",
            Bridge::ThreeFrame => "models/three-frame.toml",
        }
    }

    /// The model shortened to a couple of seconds, its gaps narrowed so that it pounds early:
    /// `gap` m at the four-span's corners, at the three-frame's joints.
    fn text(self, gap: &str) -> String {
        let path = root().join(self.rel());
        let t = set(&read(&path), "solver.t_end", "2.0");
        match self {
            Bridge::FourSpan => (0..4).fold(t, |t, i| set(&t, &format!("contacts.gaps.{i}"), gap)),
            Bridge::ThreeFrame => t,
        }
    }

    /// Runs 1 and 2 of the bridge (a wider then a narrower gap), computed once per binary.
    fn runs(self) -> &'static (RunData, RunData) {
        static FOUR: OnceLock<(RunData, RunData)> = OnceLock::new();
        static THREE: OnceLock<(RunData, RunData)> = OnceLock::new();
        let cell = match self {
            Bridge::FourSpan => &FOUR,
            Bridge::ThreeFrame => &THREE,
        };
        cell.get_or_init(|| {
            let path = root().join(self.rel());
            (
                run_of(&self.text("0.006"), &path, 1),
                run_of(&self.text("0.004"), &path, 2),
            )
        })
    }

    /// The bridge in ASCII mode (with or without colour): run 2 shown, run 1 the baseline.
    fn app(self, color: bool) -> App {
        let opts = Options { color, ascii: true };
        let text = self.text("0.004");
        let mut app = App::with_options(&text, Path::new(self.rel()), opts);
        let (r1, r2) = self.runs();
        app.runs.add(Entry::of_run(r1, self.text("0.006")), &text);
        app.runs.pin(1);
        app.runs.add(Entry::of_run(r2, text.clone()), &text);
        app.runs.selected = 1;
        app.current = Some(r2.clone());
        app.next_run = 3;
        app.set_status(StatusKind::Ok, "#2 finished");
        app
    }
}

/// One frame of `app` at `w`×`h` as the panels draw it, without the last ASCII pass.
fn render_panels(app: &mut App, w: u16, h: u16) -> Terminal<TestBackend> {
    update(app, Msg::Resize(w, h));
    let mut t = Terminal::new(TestBackend::new(w, h)).unwrap();
    let mut cache = tui::ui::Cache::default();
    t.draw(|f| tui::ui::draw_screen(f, app, &mut cache))
        .unwrap();
    t
}

/// The cells whose symbol is not ASCII, with their positions.
fn not_ascii(t: &Terminal<TestBackend>) -> Vec<(u16, u16, String)> {
    let b = t.backend().buffer();
    let mut bad = Vec::new();
    for y in 0..b.area.height {
        for x in 0..b.area.width {
            let s = b[(x, y)].symbol();
            if !s.is_ascii() || s.is_empty() {
                bad.push((x, y, s.to_string()));
            }
        }
    }
    bad
}

/// Puts an app in the state a test draws.
type Setup = Box<dyn Fn(&mut App)>;

/// Every view and overlay: the charts (event strip, plan, loop, comparison), the event list,
/// a running run (the header's gauge), the form and a value being typed, the studies and
/// every results page, the run list, the help, the message log, the questions and pickers.
fn states() -> Vec<(String, Setup)> {
    let mut v: Vec<(String, Setup)> = vec![
        ("charts".into(), Box::new(|_| {})),
        (
            "event list".into(),
            Box::new(|a| {
                act(a, Action::ToggleEvents);
            }),
        ),
        (
            "running".into(),
            Box::new(|a| {
                let r = a.current.as_mut().unwrap();
                r.status = RunStatus::Running;
                r.t_sim = 1.2;
            }),
        ),
        ("form".into(), Box::new(|a| a.view = View::Form)),
        (
            "editing".into(),
            Box::new(|a| {
                a.view = View::Form;
                update(a, code(crossterm::event::KeyCode::Enter));
                update(a, key('x'));
            }),
        ),
        ("studies".into(), Box::new(|a| a.view = View::Studies)),
        ("run list".into(), Box::new(|a| a.view = View::Runs)),
        ("help".into(), Box::new(|a| a.mode = Mode::Help)),
        (
            "message log".into(),
            Box::new(|a| {
                a.set_status(StatusKind::Warn, "a warning — with a dash");
                a.mode = Mode::Messages;
            }),
        ),
        (
            "quit question".into(),
            Box::new(|a| a.mode = Mode::Confirm(Confirm::Quit)),
        ),
        (
            "study picker".into(),
            Box::new(|a| {
                a.view = View::Studies;
                a.mode = Mode::Pick {
                    files: vec![PathBuf::from("models/four-span.studies/pga-1.csv")],
                    selected: 0,
                };
            }),
        ),
        (
            "model picker".into(),
            Box::new(|a| {
                a.mode = Mode::OpenModel {
                    files: vec![PathBuf::from("models/three-frame.toml")],
                    selected: 0,
                };
            }),
        ),
    ];
    for page in Page::ALL {
        v.push((
            format!("results {page:?}"),
            Box::new(move |a| {
                a.view = View::Studies;
                for _ in 0..20 {
                    if a.results.page == Some(page) {
                        return;
                    }
                    let fx = act(a, Action::StudyNext);
                    tui::execute_blocking(a, fx);
                }
                panic!("{page:?} not reached");
            }),
        ));
    }
    v
}

// ---------------------------------------------------------------------------------------------
// every view in ASCII

#[test]
fn every_view_of_both_bridges_is_drawn_in_ascii_by_the_panels_themselves() {
    let states = states();
    for bridge in Bridge::ALL {
        for color in [true, false] {
            for (name, setup) in &states {
                for (w, h) in [(80, 24), (120, 40)] {
                    let mut app = bridge.app(color);
                    update(&mut app, Msg::Resize(w, h));
                    setup(&mut app);
                    let what = format!("{bridge:?} {name} {w}x{h} colour {color}");
                    // as the panels draw it: no stand-in needed
                    let t = render_panels(&mut app, w, h);
                    let bad = not_ascii(&t);
                    assert!(bad.is_empty(), "{what}: {bad:?}\n{}", screen(&t));
                    // as the terminal gets it: the same frame
                    let sent = render(&mut app, w, h);
                    assert_eq!(screen(&sent), screen(&t), "{what}");
                    // a few concrete marks of each view
                    let s = screen(&t);
                    if name == "help" {
                        assert!(s.contains("+ help - keys"), "{what}\n{s}");
                    }
                    if name == "charts" {
                        assert!(s.contains("theta ["), "{what}\n{s}");
                        assert!(s.contains(" plan x"), "{what}\n{s}");
                        assert!(s.contains("+-"), "{what}: the borders\n{s}");
                    }
                }
            }
        }
    }
}

#[test]
fn the_plan_and_the_loop_are_drawn_with_ascii_marks_and_the_unicode_ones_with_braille() {
    for bridge in Bridge::ALL {
        let mut app = bridge.app(true);
        app.ascii = false;
        let t = render_panels(&mut app, 120, 40);
        let s = screen(&t);
        let braille = |s: &str| s.chars().any(|c| ('\u{2801}'..='\u{28ff}').contains(&c));
        assert!(braille(&s), "{bridge:?}\n{s}");
        assert!(s.contains('┌') && s.contains('│'), "{bridge:?}\n{s}");
        // `m`: the same screen in ASCII, the plan's outline in dots
        update(&mut app, key('m'));
        assert!(app.ascii);
        assert!(app.status.contains("ASCII"), "{}", app.status);
        let t = render_panels(&mut app, 120, 40);
        assert!(not_ascii(&t).is_empty(), "{bridge:?}");
        let s = screen(&t);
        let plan: Vec<&str> = s
            .lines()
            .skip_while(|l| !l.contains(" plan x"))
            .take(5)
            .collect();
        assert!(plan.len() == 5, "{bridge:?}\n{s}");
        assert!(plan[1..].iter().any(|l| l.contains('.')), "{plan:?}");
        update(&mut app, key('m'));
        assert!(
            !app.ascii && app.status.contains("Unicode"),
            "{}",
            app.status
        );
    }
}

// ---------------------------------------------------------------------------------------------
// the zero line

/// The rows of the chart whose header line contains `title`, down to the next header (a line
/// that does not start with the label column's blanks or a label).
fn chart_rows(s: &str, title: &str) -> Vec<String> {
    let lines: Vec<&str> = s.lines().collect();
    let start = lines
        .iter()
        .position(|l| l.contains(title))
        .unwrap_or_else(|| panic!("no {title}:\n{s}"));
    lines[start + 1..]
        .iter()
        .take_while(|l| l.starts_with(' ') || l.starts_with('-'))
        .take_while(|l| !l.contains(" ["))
        .map(|l| l.to_string())
        .collect()
}

#[test]
fn the_zero_line_is_a_character_no_series_is_drawn_with() {
    for bridge in Bridge::ALL {
        let mut app = bridge.app(true);
        let s = screen(&render_panels(&mut app, 120, 40));
        let rows = chart_rows(&s, "theta [");
        assert!(rows.len() >= 4, "{bridge:?}\n{s}");
        // the row labelled 0 is the zero line: its character is `-`, and the θ series (its
        // mark named in the legend) is drawn with another
        let zero = rows
            .iter()
            .find(|r| r.get(..12).is_some_and(|l| l.trim() == "0"))
            .unwrap_or_else(|| panic!("{bridge:?}: no zero row\n{}", rows.join("\n")));
        // (where the series runs along zero it covers the line)
        let dashes = zero[12..].chars().filter(|&c| c == '-').count();
        assert!(dashes >= 3, "{bridge:?}: {zero:?}");
        assert!(
            rows.iter().all(|r| r == zero || !r[12..].contains('-')),
            "{bridge:?}"
        );
        let header = s.lines().find(|l| l.contains("theta [")).unwrap();
        let marks: Vec<char> = header
            .match_indices('[')
            .filter_map(|(i, _)| {
                let m: Vec<char> = header[i + 1..].chars().take(2).collect();
                (m.len() == 2 && m[1] == ']').then_some(m[0])
            })
            .collect();
        assert!(!marks.contains(&'-'), "{bridge:?}: {header}");
        // the series' own marks and the zero line's meet in the chart
        let series = rows.iter().any(|r| r[12..].contains('.'));
        assert!(series, "{bridge:?}\n{}", rows.join("\n"));
    }
    // without colour, in Unicode, the zero line stays Braille: not a series mark either
    let mut app = Bridge::FourSpan.app(false);
    app.ascii = false;
    let s = screen(&render_panels(&mut app, 120, 40));
    let rows = chart_rows(&s, "theta [");
    let zero = rows
        .iter()
        .find(|r| r.get(..12).is_some_and(|l| l.trim() == "0"))
        .unwrap();
    assert!(
        zero.chars().any(|c| ('\u{2801}'..='\u{28ff}').contains(&c)),
        "{zero}"
    );
}

// ---------------------------------------------------------------------------------------------
// the glyphs: from the terminal, or overridden

fn env(vars: &[(&str, &str)]) -> impl Fn(&str) -> Option<String> {
    let vars: Vec<(String, String)> = vars
        .iter()
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    move |k| vars.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone())
}

#[test]
fn the_terminal_tells_the_glyphs_and_the_override_wins() {
    let opts = |vars: &[(&str, &str)]| Options::from_vars(&env(vars)).unwrap();
    for term in ["dumb", "linux", "vt100", "vt102", "vt220", "ansi"] {
        assert!(opts(&[("TERM", term)]).ascii, "{term}");
    }
    for term in [
        "xterm-256color",
        "xterm",
        "screen-256color",
        "tmux-256color",
    ] {
        assert!(!opts(&[("TERM", term)]).ascii, "{term}");
    }
    // dumb: ASCII and no colour; NO_COLOR alone: no colour, the glyphs kept
    let dumb = opts(&[("TERM", "dumb")]);
    assert!(dumb.ascii && !dumb.color);
    let no_color = opts(&[("TERM", "xterm-256color"), ("NO_COLOR", "1")]);
    assert!(!no_color.ascii && !no_color.color);
    // the environment's override, either way
    assert!(!opts(&[("TERM", "vt100"), (GLYPHS_VAR, "unicode")]).ascii);
    assert!(opts(&[("TERM", "xterm-256color"), (GLYPHS_VAR, "ascii")]).ascii);
    let bad = Options::from_vars(&env(&[(GLYPHS_VAR, "braille")])).unwrap_err();
    assert!(bad.contains(GLYPHS_VAR) && bad.contains("braille"), "{bad}");
    // the app starts in the mode told, and `m` still toggles it
    let mut app = App::with_options(
        &Bridge::FourSpan.text("0.004"),
        Path::new("models/four-span.toml"),
        opts(&[("TERM", "vt220")]),
    );
    assert!(app.ascii);
    update(&mut app, key('m'));
    assert!(!app.ascii);
    assert_eq!(Glyphs::parse("ascii"), Some(Glyphs::Ascii));
}

#[test]
fn the_glyphs_option_is_in_the_help_and_a_bad_value_is_refused() {
    let bin = env!("CARGO_BIN_EXE_deckspin");
    let out = std::process::Command::new(bin)
        .arg("--help")
        .output()
        .unwrap();
    let help = String::from_utf8_lossy(&out.stdout);
    assert!(help.contains("--glyphs <ascii|unicode>"), "{help}");
    assert!(help.contains(GLYPHS_VAR), "{help}");
    let out = std::process::Command::new(bin)
        .args(["models/four-span.toml", "--glyphs", "braille"])
        .current_dir(root())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--glyphs") && err.contains("braille"), "{err}");
    // the environment's override, refused the same way before the terminal is taken
    let out = std::process::Command::new(bin)
        .arg("models/four-span.toml")
        .env(GLYPHS_VAR, "braille")
        .current_dir(root())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("DECKSPIN_GLYPHS='braille'"), "{err}");
}

// ---------------------------------------------------------------------------------------------
// snapshot

#[test]
fn snapshot_charts_with_the_plan_80x24_all_ascii() {
    let mut app = Bridge::FourSpan.app(true);
    let t = render_panels(&mut app, 80, 24);
    assert!(not_ascii(&t).is_empty());
    snapshot_settings().bind(|| insta::assert_snapshot!("charts_80x24_all_ascii", t.backend()));
}
