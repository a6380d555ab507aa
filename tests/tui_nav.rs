//! The workbench's readouts and navigation: `]`/`[` from event to event, the event list, the
//! event strip's counts and mark order, value axes labelled with the data's extremes, the
//! readouts at the cursor, the cursor kept in a zoomed window on rerun; snapshots of them.

#![cfg(feature = "workbench")]

mod common;

use common::tui::lines as screen;
use common::tui::*;

use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use deckspin::output::{ContactState, EventKind, EventRecord};
use deckspin::tui::app::{StatusKind, View};
use deckspin::tui::eng::{eng, eng_sig};
use deckspin::tui::keymap::{Action, Ctx};
use deckspin::tui::runs::data::RunData;
use deckspin::tui::runs::list::Entry;
use deckspin::tui::{self, App, Effect, Msg, Options, chart, runs::nav, update};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use std::path::Path;
use std::sync::OnceLock;

// ---------------------------------------------------------------------------------------------
// fixtures

fn short_run() -> &'static RunData {
    static R: OnceLock<RunData> = OnceLock::new();
    R.get_or_init(|| run_of(&short_bridge("0.004"), &bridge_path(), 2))
}

fn short_prev_run() -> &'static RunData {
    static R: OnceLock<RunData> = OnceLock::new();
    R.get_or_init(|| run_of(&short_bridge("0.006"), &bridge_path(), 1))
}

/// The default model as shipped, run to its end (16 s).
fn default_run() -> &'static RunData {
    static R: OnceLock<RunData> = OnceLock::new();
    R.get_or_init(|| run_of(&read(&bridge_path()), &bridge_path(), 1))
}

/// The short bridge with run 2 current and run 1 overlaid (relative path: no checkout
/// location in the snapshots).
fn app_with(opts: Options) -> App {
    let mut app = App::with_options(
        &short_bridge("0.004"),
        Path::new("models/four-span.toml"),
        opts,
    );
    app.current = Some(short_run().clone());
    let saved = app.text.clone();
    app.runs.add(
        Entry::of_run(short_prev_run(), short_bridge("0.006")),
        &saved,
    );
    app.runs.pin(1);
    app.runs
        .add(Entry::of_run(short_run(), short_bridge("0.004")), &saved);
    app.next_run = 3;
    app.set_status(StatusKind::Ok, "run 2 finished");
    app
}

fn bridge_app() -> App {
    app_with(Options::default())
}

/// The y label of a chart row: what stands left of its axis `│` (trimmed).
fn label(line: &str) -> String {
    line.split('│').next().unwrap_or("").trim().to_string()
}

/// The rows of the chart whose header line starts with `title`: its top and bottom labels.
fn chart_labels(lines: &[String], title: &str) -> (String, String) {
    let h = lines
        .iter()
        .position(|l| l.starts_with(title))
        .unwrap_or_else(|| panic!("no chart {title}:\n{}", lines.join("\n")));
    let rows: Vec<&String> = lines[h + 1..]
        .iter()
        .take_while(|l| l.chars().nth(12) == Some('│'))
        .collect();
    (label(rows[0]), label(rows[rows.len() - 1]))
}

/// A label is `v` formatted with its unit at 2 to 4 significant digits.
fn is_label_of(label: &str, v: f64, unit: &str) -> bool {
    (2..=4).any(|sig| eng_sig(v, unit, sig, false) == label)
}

/// Smallest and largest value of column `y` in `t0..=t1`.
fn range_in(run: &RunData, y: &[f64], t0: f64, t1: f64) -> (f64, f64) {
    chart::window(&run.t, t0, t1)
        .map(|i| y[i])
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        })
}

// ---------------------------------------------------------------------------------------------
// jumps from event to event

#[test]
fn jumps_visit_every_event_instant_once_in_order() {
    let mut app = bridge_app();
    let run = short_run();
    let times = nav::event_times(run);
    assert!(times.len() > 10, "{}", times.len());
    assert!(times[0] > 0.0);
    act(&mut app, Action::CursorHome);
    let mut visited = Vec::new();
    for _ in 0..times.len() + 5 {
        update(&mut app, key(']'));
        if app.status == "no event after the cursor" {
            break;
        }
        assert!(!app.follow);
        visited.push(app.cursor_time());
        // the status line says which events (numbered as the event list numbers them),
        // when, which contact, what
        let e = run.events.iter().find(|e| e.t == app.cursor).unwrap();
        let name = &run.contact_names[e.contact];
        let before = run.events.iter().filter(|x| x.t < e.t).count();
        let here = run.events.iter().filter(|x| x.t == e.t).count();
        let which = match here {
            1 => format!("event {}", before + 1),
            n => format!("events {}–{}", before + 1, before + n),
        };
        assert!(
            app.status.starts_with(&format!(
                "{which}/{} at t = {} s: ",
                run.events.len(),
                nav::fmt_time(e.t)
            )) && app.status.contains(&format!("{name} {}", e.kind.label())),
            "{}",
            app.status
        );
    }
    assert_eq!(visited, times, "one jump per distinct event instant");
    // and back
    let mut back = Vec::new();
    loop {
        update(&mut app, key('['));
        if app.status == "no event before the cursor" {
            break;
        }
        back.push(app.cursor_time());
    }
    back.reverse();
    assert_eq!(back, times[..times.len() - 1]);
}

#[test]
fn jumps_move_a_zoomed_window_to_keep_the_cursor_in_it() {
    let mut app = bridge_app();
    act(&mut app, Action::CursorHome);
    for _ in 0..4 {
        act(&mut app, Action::ZoomIn);
    }
    let (a, b) = app.window();
    assert!((b - a - 0.125).abs() < 1e-12 && a == 0.0, "{a} {b}");
    let times = nav::event_times(short_run());
    for &t in &times {
        act(&mut app, Action::NextEvent);
        assert_eq!(app.cursor_time(), t);
        let (a, b) = app.window();
        assert!(a <= t && t <= b, "{t} outside {a}..{b}");
        assert!((b - a - 0.125).abs() < 1e-9, "the zoom is kept");
    }
}

#[test]
fn an_impact_is_described_with_its_normal_impulse() {
    let run = short_run();
    let e = run
        .events
        .iter()
        .find(|e| e.kind == EventKind::Impact)
        .unwrap();
    let s = nav::describe(run, e, "kN", false);
    assert_eq!(
        s,
        format!(
            "{} impact {}",
            run.contact_names[e.contact],
            eng(e.normal, "kN·s", false)
        )
    );
    // a scene file's units are its author's: the number alone
    assert_eq!(nav::impulse(e, "", false), Some(eng(e.normal, "", false)));
}

// ---------------------------------------------------------------------------------------------
// the event list

#[test]
fn the_event_list_follows_the_cursor_and_enter_moves_the_cursor() {
    let mut app = bridge_app();
    let run = short_run();
    let order = nav::in_time_order(run);
    assert!(!app.contexts().contains(&Ctx::Events));
    update(&mut app, key('E'));
    assert!(app.events_open);
    assert_eq!(app.contexts()[0], Ctx::Events);
    act(&mut app, Action::CursorHome);
    let s = screen(&render(&mut app, 80, 24)).join("\n");
    assert!(s.contains(&format!(" events ({}) ", order.len())), "{s}");
    // a jump selects the first event of its instant
    update(&mut app, key(']'));
    update(&mut app, key(']'));
    let t = app.cursor_time();
    let row = app.event_sel.unwrap();
    assert_eq!(run.events[order[row]].t, t);
    assert!(row == 0 || run.events[order[row - 1]].t < t);
    let s = screen(&render(&mut app, 80, 24)).join("\n");
    assert!(
        s.contains(&format!(" events {}/{} ", row + 1, order.len())),
        "{s}"
    );
    // moving the selection leaves the cursor; Enter brings it there
    for _ in 0..3 {
        update(
            &mut app,
            Msg::Key(KeyEvent::new(KeyCode::Down, KeyModifiers::NONE)),
        );
    }
    assert_eq!(app.event_sel, Some(row + 3));
    assert_eq!(app.cursor_time(), t);
    update(
        &mut app,
        Msg::Key(KeyEvent::new(KeyCode::Enter, KeyModifiers::NONE)),
    );
    assert_eq!(app.cursor_time(), run.events[order[row + 3]].t);
    assert_eq!(app.event_sel, Some(row + 3));
    // the cursor keys hand the selection back to the cursor
    update(&mut app, key('l'));
    assert_eq!(app.event_sel, None);
    // the list clamps at its ends, and pages
    act(&mut app, Action::EventPageUp);
    act(&mut app, Action::EventPageUp);
    act(&mut app, Action::EventPageUp);
    assert_eq!(app.event_sel, Some(0));
    for _ in 0..order.len() / 10 + 2 {
        act(&mut app, Action::EventPageDown);
    }
    assert_eq!(app.event_sel, Some(order.len() - 1));
    let s = screen(&render(&mut app, 80, 24)).join("\n");
    assert!(s.contains(&format!(" events {0}/{0} ", order.len())), "{s}");
    update(&mut app, key('E'));
    assert!(!app.events_open);
}

#[test]
fn the_event_list_scrolls_to_keep_the_selection_in_view() {
    use deckspin::tui::ui::scroll;
    assert_eq!(scroll(0, 10, 5), 0);
    assert_eq!(scroll(3, 10, 50), 0);
    assert_eq!(scroll(20, 10, 50), 15);
    assert_eq!(scroll(49, 10, 50), 40);
    for sel in 0..50 {
        let first = scroll(sel, 7, 50);
        assert!(first <= sel && sel < first + 7, "{sel}");
    }
}

#[test]
fn every_size_and_key_draws_with_the_event_list() {
    let mut app = bridge_app();
    update(&mut app, key('E'));
    for (w, h) in [
        (60, 18),
        (80, 24),
        (100, 30),
        (120, 40),
        (61, 19),
        (200, 60),
    ] {
        for k in [']', ']', 'j', 'k', '[', '+', ']', '-', '0'] {
            update(&mut app, key(k));
            let s = screen(&render(&mut app, w, h));
            assert!(s.iter().any(|l| l.contains(" events ")), "{w}x{h}");
        }
    }
    // an app without a run
    let mut empty = App::new_from_text(&short_bridge("0.004"), &bridge_path());
    for a in [
        Action::ToggleEvents,
        Action::NextEvent,
        Action::PrevEvent,
        Action::EventDown,
        Action::EventGo,
    ] {
        act(&mut empty, a);
        render(&mut empty, 80, 24);
    }
}

// ---------------------------------------------------------------------------------------------
// the event strip

#[test]
fn the_strip_counts_every_impact_of_the_default_model_at_full_view() {
    let run = default_run();
    let total: usize = run.impacts.iter().sum();
    assert_eq!(total, run.count(EventKind::Impact));
    assert!(total > 40, "{total}");
    let t1 = run.t_end;
    // the plot widths of 80 and 120 columns, with either marker
    for w in [39, 64] {
        for per_cell in [1, 2] {
            let mut shown = 0;
            for i in 0..run.contact_names.len() {
                let cells = tui::ui::strip_cells(run, i, 0.0, t1, w, per_cell, false);
                assert_eq!(cells.len(), w);
                let n: usize = cells.iter().map(|c| c.impacts).sum();
                assert_eq!(n, run.impacts[i], "contact {i}, {w} columns");
                for c in &cells {
                    // the mark says how many: `*` one, a digit, `+` ten or more
                    let want = match c.impacts {
                        0 => None,
                        1 => Some('*'),
                        n @ 2..=9 => char::from_digit(n as u32, 10),
                        _ => Some('+'),
                    };
                    if let Some(m) = want {
                        assert_eq!(c.mark, m);
                    }
                }
                shown += cells.iter().filter(|c| c.impacts > 0).count();
            }
            assert!(shown < total, "several impacts share a column at full view");
        }
    }
}

/// The kind a column shows: the events of the contact in it, the first of the fixed order.
fn expected_kind(
    run: &RunData,
    i: usize,
    col: usize,
    (w, per_cell): (usize, usize),
) -> Option<EventKind> {
    run.events
        .iter()
        .filter(|e| e.contact == i && e.kind.of_contact())
        .filter(|e| chart::column_of(e.t, 0.0, run.t_end, w, per_cell) == Some(col))
        .map(|e| e.kind)
        .max_by_key(|&k| tui::ui::priority(k))
}

#[test]
fn a_columns_mark_follows_one_order_whatever_the_marker() {
    // one instant with every kind of event: the impact shows, with either marker
    let mut run = RunData::new(
        1,
        "run 1".into(),
        vec!["deck.x".into()],
        vec!["wall".into()],
        vec![],
        1.0,
    );
    let ev = |t: f64, kind| EventRecord {
        t,
        contact: 0,
        kind,
        normal: 0.0,
        tangential: 0.0,
        gap_rate_before: 0.0,
        gap_rate_after: 0.0,
        slip_rate_after: 0.0,
        sticks: None,
        info: 0.0,
    };
    use EventKind as K;
    run.events = vec![
        ev(0.5, K::Stick),
        ev(0.5, K::Slip),
        ev(0.5, K::Impact),
        ev(0.5, K::Release),
        ev(0.8, K::Stick),
        ev(0.8, K::Release),
        ev(0.8, K::Slip),
        ev(0.2, K::Slip),
        ev(0.2, K::Stick),
    ];
    for (ascii, per_cell) in [(false, 2), (true, 1)] {
        let s = tui::ui::event_strip(&run, 0, 0.0, 1.0, 11, per_cell, ascii);
        let marks: String = s.iter().filter(|c| **c != ' ').collect();
        assert_eq!(marks, "~*^", "per cell {per_cell}");
    }
    // the real run: every column shows the first kind of the order among its events
    let run = default_run();
    for per_cell in [1, 2] {
        for i in 0..run.contact_names.len() {
            let cells = tui::ui::strip_cells(run, i, 0.0, run.t_end, 39, per_cell, per_cell == 1);
            for (c, cell) in cells.iter().enumerate() {
                assert_eq!(
                    cell.kind,
                    expected_kind(run, i, c, (39, per_cell)),
                    "contact {i} column {c}"
                );
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// value axes

#[test]
fn the_y_labels_are_the_data_extremes_and_the_gap_chart_shows_its_minimum() {
    let mut app = bridge_app();
    app.overlay = false;
    let run = short_run();
    let lines = screen(&render(&mut app, 120, 40));
    let r = run.rot.unwrap();
    let (lo, hi) = range_in(run, &run.q[r], 0.0, 2.0);
    let (top, bottom) = chart_labels(&lines, "deck.theta");
    assert!(is_label_of(&top, hi, "rad"), "{top} vs {hi}");
    assert!(is_label_of(&bottom, lo, "rad"), "{bottom} vs {lo}");
    // the deepest gap, not a padded bound
    let g_lo = (0..4)
        .map(|i| range_in(run, &run.gap[i], 0.0, 2.0).0)
        .fold(f64::INFINITY, f64::min);
    let g_hi = (0..4)
        .map(|i| range_in(run, &run.gap[i], 0.0, 2.0).1)
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(g_lo.abs() < 1e-9, "{g_lo}");
    let (top, bottom) = chart_labels(&lines, "gaps g_N");
    assert!(is_label_of(&top, g_hi, "m"), "{top} vs {g_hi}");
    assert!(is_label_of(&bottom, g_lo, "m"), "{bottom} vs {g_lo}");
    // a zero line labelled 0 inside the θ chart, which crosses zero
    assert!(lo < 0.0 && hi > 0.0);
    let h = lines
        .iter()
        .position(|l| l.starts_with("deck.theta"))
        .unwrap();
    assert!(lines[h + 2..h + 10].iter().any(|l| label(l) == "0"));
}

#[test]
fn zooming_rescales_y_to_the_window() {
    let mut app = bridge_app();
    app.overlay = false;
    let run = short_run();
    let r = run.rot.unwrap();
    act(&mut app, Action::CursorHome);
    for _ in 0..3 {
        act(&mut app, Action::ZoomIn);
    }
    let (a, b) = app.window();
    assert_eq!((a, b), (0.0, 0.25));
    let (lo, hi) = range_in(run, &run.q[r], a, b);
    let (whole_lo, whole_hi) = range_in(run, &run.q[r], 0.0, 2.0);
    assert!(hi < 0.1 * whole_hi && lo > 0.1 * whole_lo, "{lo} {hi}");
    let lines = screen(&render(&mut app, 120, 40));
    let (top, bottom) = chart_labels(&lines, "deck.theta");
    assert!(is_label_of(&top, hi, "rad"), "{top} vs {hi}");
    assert!(is_label_of(&bottom, lo, "rad"), "{bottom} vs {lo}");
}

// ---------------------------------------------------------------------------------------------
// readouts at the cursor

#[test]
fn the_readouts_give_every_series_and_contact_at_the_cursor() {
    let mut app = bridge_app();
    let run = short_run();
    let prev = short_prev_run();
    let times = nav::event_times(run);
    act(&mut app, Action::CursorHome);
    // an instant where some contact is closed
    let tc = *times
        .iter()
        .find(|&&t| (0..4).any(|i| nav::state_at(run, i, t) != Some(ContactState::Open)))
        .unwrap();
    while app.cursor_time() < tc {
        act(&mut app, Action::NextEvent);
    }
    let lines = screen(&render(&mut app, 200, 60));
    // θ now and in the earlier run, in the header's unit
    let r = run.rot.unwrap();
    let at = |d: &RunData, y: &[f64]| y[chart::at_or_before(&d.t, tc).unwrap()];
    let head = lines.iter().find(|l| l.starts_with("deck.theta")).unwrap();
    let (lo, hi) = range_in(run, &run.q[r], 0.0, 2.0);
    let (plo, phi) = range_in(prev, &prev.q[r], 0.0, 2.0);
    let big = lo.abs().max(hi.abs()).max(plo.abs()).max(phi.abs());
    let scale = deckspin::tui::eng::Scale::new(big, "rad", false);
    assert!(
        head.starts_with(&format!("deck.theta [{}]", scale.unit)),
        "{head}"
    );
    let now = scale.fmt(at(run, &run.q[r]));
    let before = scale.fmt(at(prev, &prev.q[r]));
    assert!(
        head.contains(&format!("━deck.theta {now}")) || head.contains(&format!("━{now}")),
        "{head}"
    );
    assert!(head.contains(&format!("┈#1 {before}")), "{head}");
    // every gap, by name
    let head = lines.iter().find(|l| l.starts_with("gaps g_N")).unwrap();
    for n in &run.contact_names {
        assert!(head.contains(&format!("━{n} ")), "{head}");
    }
    // the readout line: the time, every contact's state, the last impact's impulse
    let ro = lines
        .iter()
        .find(|l| l.starts_with("t = "))
        .unwrap_or_else(|| panic!("{}", lines.join("\n")));
    assert!(
        ro.starts_with(&format!("t = {} s", nav::fmt_time(tc))),
        "{ro}"
    );
    for (i, n) in run.contact_names.iter().enumerate() {
        let st = nav::state_at(run, i, tc).unwrap();
        assert!(ro.contains(&format!("{n} {}", st.label())), "{ro}");
    }
    if let Some(e) = nav::last_impact(run, tc) {
        let imp = eng(e.normal, "kN·s", false);
        assert!(
            ro.contains(&format!(
                "last impact {} {imp}",
                run.contact_names[e.contact]
            )),
            "{ro}"
        );
    }
    // the column loop's deformation and force
    let j = 0;
    let k = chart::at_or_before(&run.t, tc).unwrap();
    let want = format!(
        " {}, {} ",
        eng(run.el[j].0[k], "m", false),
        eng(run.el[j].1[k], "kN", false)
    );
    assert!(lines.iter().any(|l| l.contains(&want)), "{want}");
}

#[test]
fn at_80_columns_the_readouts_are_whole_items() {
    let mut app = bridge_app();
    act(&mut app, Action::CursorHome);
    for _ in 0..12 {
        act(&mut app, Action::NextEvent);
    }
    let lines = screen(&render(&mut app, 80, 24));
    let ro = lines.iter().find(|l| l.starts_with("t = ")).unwrap();
    let left: String = ro.chars().take(52).collect();
    // each item after the time is a contact with a state, a summary, or the last impact
    let items: Vec<&str> = left
        .trim_end()
        .split_once(" s ")
        .unwrap()
        .1
        .split(" · ")
        .collect();
    for it in items {
        let ok = it == "all open"
            || it == "others open"
            || it.starts_with("last impact ")
            || ["open", "stick", "slide+", "slide-", "slide"]
                .iter()
                .any(|s| it.ends_with(&format!(" {s}")));
        assert!(ok, "{it:?} in {ro}");
    }
    // the chart headers: values only, every one of them
    let head = lines.iter().find(|l| l.starts_with("gaps g_N")).unwrap();
    assert_eq!(head.matches('━').count(), 4, "{head}");
}

/// Draws `app` at 80×24 with `cache` (kept across frames as the runtime keeps it) and returns
/// its lines.
fn frame_with(app: &mut App, cache: &mut tui::ui::Cache) -> Vec<String> {
    update(app, Msg::Resize(80, 24));
    let mut t = Terminal::new(TestBackend::new(80, 24)).unwrap();
    t.draw(|f| tui::ui::draw(f, app, cache)).unwrap();
    screen(&t)
}

/// The readout line, left of the side panels.
fn readout_line(lines: &[String]) -> String {
    let ro = lines.iter().find(|l| l.starts_with("t = "));
    let ro = ro.unwrap_or_else(|| panic!("{}", lines.join("\n")));
    ro.chars().take(52).collect()
}

#[test]
fn while_a_run_is_followed_the_readouts_refresh_twice_a_second() {
    let mut app = App::new_from_text(&read(&bridge_path()), Path::new("models/four-span.toml"));
    let fx = app.start();
    let msgs = messages_of_started_run(fx);
    assert!(msgs.len() > 6, "{} messages", msgs.len());
    let mut msgs = msgs.into_iter();
    let mut feed = |app: &mut App, n: usize| {
        for m in msgs.by_ref().take(n) {
            update(app, m);
        }
    };
    let mut cache = tui::ui::Cache::default();
    feed(&mut app, 2);
    assert!(app.running() && app.follow);
    let t1 = app.cursor_time();
    let first = frame_with(&mut app, &mut cache);
    let ro1 = readout_line(&first);
    assert!(
        ro1.starts_with(&format!("t = {} s", nav::fmt_time(t1))),
        "{ro1}"
    );
    // more batches within the period: the charts and the header go on, the readouts stay
    feed(&mut app, 2);
    assert!(app.running());
    let t2 = app.cursor_time();
    assert!(t2 > t1);
    let started = std::time::Instant::now();
    let second = frame_with(&mut app, &mut cache);
    assert!(started.elapsed() < tui::ui::READOUT_PERIOD);
    assert_eq!(readout_line(&second), ro1);
    // the column loop's deformation and force, on its lower border
    let loop_readout = |l: &[String]| -> String {
        let mut right = l.iter().map(|s| s.chars().skip(52).collect::<String>());
        let border = right.rfind(|s| s.starts_with("└ ") && s.contains(", "));
        border.unwrap_or_else(|| panic!("{}", l.join("\n")))
    };
    assert_eq!(loop_readout(&second), loop_readout(&first));
    assert_ne!(second[0], first[0], "the header's progress goes on");
    let plan = |l: &[String]| l[1].chars().skip(50).collect::<String>();
    assert!(plan(&second).contains(&format!("t={} s", chart::fmt_num(t1, 7))));
    // after the period the readouts take the latest sample
    std::thread::sleep(tui::ui::READOUT_PERIOD);
    let third = frame_with(&mut app, &mut cache);
    let ro3 = readout_line(&third);
    assert!(
        ro3.starts_with(&format!("t = {} s", nav::fmt_time(t2))),
        "{ro3}"
    );
    assert!(plan(&third).contains(&format!("t={} s", chart::fmt_num(t2, 7))));
    // a cursor moved by hand is read at once
    act(&mut app, Action::CursorLeft);
    assert!(!app.follow);
    let tc = app.cursor_time();
    let ro = readout_line(&frame_with(&mut app, &mut cache));
    assert!(
        ro.starts_with(&format!("t = {} s", nav::fmt_time(tc))),
        "{ro}"
    );
    // and so is the end of the run once it is done
    act(&mut app, Action::CursorEnd);
    feed(&mut app, usize::MAX);
    assert!(!app.running());
    let end = app.cursor_time();
    assert_eq!(end, 16.0);
    let ro = readout_line(&frame_with(&mut app, &mut cache));
    assert!(
        ro.starts_with(&format!("t = {} s", nav::fmt_time(end))),
        "{ro}"
    );
}

// ---------------------------------------------------------------------------------------------
// reruns in a zoomed window

#[test]
fn a_rerun_keeps_the_cursor_in_the_zoomed_window() {
    // a cursor placed in the window stays where it was
    let mut app = bridge_app();
    act(&mut app, Action::CursorHome);
    for _ in 0..9 {
        act(&mut app, Action::CursorRightFast);
    }
    act(&mut app, Action::ZoomIn);
    let (a, b) = app.window();
    let tc = app.cursor_time();
    assert!(a <= tc && tc <= b && a > 0.0);
    let fx = update(&mut app, key('r'));
    assert!(fx.iter().any(|e| matches!(e, Effect::StartRun { .. })));
    assert_eq!(app.window(), (a, b));
    assert_eq!(app.cursor_time(), tc);
    assert!(!app.follow);
    // following the end of a zoomed run: the cursor stays at that end, not at the new run's
    // first sample (t = 0, outside the window)
    let mut app = bridge_app();
    act(&mut app, Action::ZoomIn);
    act(&mut app, Action::CursorEnd);
    assert!(app.follow);
    let (a, b) = app.window();
    assert_eq!((a, b), (1.0, 2.0));
    update(&mut app, key('r'));
    let tc = app.cursor_time();
    assert!(a <= tc && tc <= b, "{tc} outside {a}..{b}");
    // without a zoom the cursor follows the new run
    let mut app = bridge_app();
    act(&mut app, Action::CursorHome);
    update(&mut app, key('r'));
    assert!(app.follow);
}

// ---------------------------------------------------------------------------------------------
// snapshots

/// The cursor on the 12th event instant.
fn at_event(mut app: App) -> App {
    act(&mut app, Action::CursorHome);
    for _ in 0..12 {
        act(&mut app, Action::NextEvent);
    }
    app
}

#[test]
fn snapshot_readouts_80x24_and_120x40() {
    let mut app = at_event(bridge_app());
    let t = render(&mut app, 80, 24);
    snapshot_settings().bind(|| insta::assert_snapshot!("readouts_80x24", t.backend()));
    let t = render(&mut app, 120, 40);
    snapshot_settings().bind(|| insta::assert_snapshot!("readouts_120x40", t.backend()));
}

#[test]
fn snapshot_readouts_ascii_and_no_color_80x24() {
    let mut app = at_event(app_with(Options {
        color: false,
        ascii: true,
    }));
    let t = render(&mut app, 80, 24);
    let lines = screen(&t);
    assert!(
        lines.iter().any(|l| l.contains(" urad")) && !lines.iter().any(|l| l.contains('µ')),
        "{}",
        lines.join("\n")
    );
    snapshot_settings()
        .bind(|| insta::assert_snapshot!("readouts_80x24_ascii_no_color", t.backend()));
}

#[test]
fn snapshot_event_list_80x24_and_120x40() {
    let mut app = at_event(bridge_app());
    update(&mut app, key('E'));
    act(&mut app, Action::EventDown);
    let t = render(&mut app, 80, 24);
    snapshot_settings().bind(|| insta::assert_snapshot!("event_list_80x24", t.backend()));
    let t = render(&mut app, 120, 40);
    snapshot_settings().bind(|| insta::assert_snapshot!("event_list_120x40", t.backend()));
    let lines = screen(&t);
    assert!(
        lines.iter().any(|l| l.contains("impulse")),
        "{}",
        lines.join("\n")
    );
    app.view = View::Form;
    assert!(!app.contexts().contains(&Ctx::Events));
}

#[test]
fn at_60x18_with_the_event_list_the_labels_are_whole() {
    let mut app = at_event(bridge_app());
    app.overlay = false;
    update(&mut app, key('E'));
    let run = short_run();
    let r = run.rot.unwrap();
    let (lo, hi) = range_in(run, &run.q[r], 0.0, 2.0);
    let lines = screen(&render(&mut app, 60, 18));
    let (top, bottom) = chart_labels(&lines, "deck.theta");
    assert!(is_label_of(&top, hi, "rad"), "{top} vs {hi}");
    assert!(is_label_of(&bottom, lo, "rad"), "{bottom} vs {lo}");
    // the list names contacts as the strip does, and marks the kind as the strip does
    assert!(
        lines.iter().any(|l| l.contains(" r_bottom ")),
        "{}",
        lines.join("\n")
    );
}

/// A bridge of several frames names its forces in its units as the one-deck specimen does
/// (the force unit followed a body named `deck`, and the three-frame example's forces were
/// bare numbers); a scene file's are its author's.
#[test]
fn a_bridge_of_several_frames_names_its_force_unit() {
    let open = |rel: &str| {
        let text = std::fs::read_to_string(common::model(rel)).unwrap();
        App::with_options(&text, Path::new(rel), Options::default())
    };
    for (rel, unit) in [
        ("models/three-frame.toml", "kN"),
        ("models/four-span.toml", "kN"),
        ("models/validation/block-on-plane.toml", ""),
    ] {
        let app = open(rel);
        assert!(app.scene.is_some(), "{rel}");
        assert_eq!(nav::force_unit(&app), unit, "{rel}");
    }
}
