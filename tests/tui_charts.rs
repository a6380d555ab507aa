//! The charts view's time charts: one meaning of "event" with one count, distinct event-strip
//! row labels on every model; charts of any quantity picked per chart and remembered per
//! model, θ in rad, mrad or degrees, y zoom and log scale, the axis of the run shown.

#![cfg(feature = "workbench")]

mod common;

use common::root;
use common::tui::*;

use common::tui::lines;
use crossterm::event::{KeyCode, KeyEvent, KeyModifiers};
use deckspin::tui::app::{Mode, StatusKind};
use deckspin::tui::chart_prefs::{self, ChartPrefs, ThetaUnit};
use deckspin::tui::eng::{Scale, eng_sig};
use deckspin::tui::keymap::Action;
use deckspin::tui::runs::data::RunData;
use deckspin::tui::runs::list::Entry;
use deckspin::tui::runs::series::{Kind, SeriesId};
use deckspin::tui::{self, App, Effect, Msg, Options, chart, runs::nav, update};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// A special key as a message.
trait IntoMsg {
    fn into_msg(self) -> Msg;
}

impl IntoMsg for KeyCode {
    fn into_msg(self) -> Msg {
        code(self)
    }
}

// ---------------------------------------------------------------------------------------------
// fixtures

/// Run 2 of the short bridge (4 mm gaps), run 1 (6 mm), computed once.
fn short_run() -> &'static RunData {
    static R: OnceLock<RunData> = OnceLock::new();
    R.get_or_init(|| run_of(&short_bridge("0.004"), &bridge_path(), 2))
}

fn short_prev_run() -> &'static RunData {
    static R: OnceLock<RunData> = OnceLock::new();
    R.get_or_init(|| run_of(&short_bridge("0.006"), &bridge_path(), 1))
}

/// The short bridge with run 2 shown (relative path: no checkout location on screen).
fn bridge_app() -> App {
    let mut app = App::new_from_text(&short_bridge("0.004"), Path::new("models/four-span.toml"));
    app.current = Some(short_run().clone());
    app.next_run = 3;
    app
}

/// Every model file in models/ and its subfolders.
fn model_files() -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut dirs = vec![root().join("models")];
    while let Some(d) = dirs.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                dirs.push(p);
            } else if p.extension().is_some_and(|x| x == "toml") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

// ---------------------------------------------------------------------------------------------
// event-strip rows and the event count

#[test]
fn every_model_gets_distinct_row_labels_that_fit() {
    let files = model_files();
    assert!(files.len() >= 10, "{files:?}");
    for p in &files {
        let scene = deckspin::model::load(p, &[]).unwrap_or_else(|e| panic!("{p:?}: {e}"));
        let contacts: Vec<String> = scene.contacts.iter().map(|c| c.name.clone()).collect();
        let elements: Vec<String> = scene.hysteretic.iter().map(|h| h.name.clone()).collect();
        // the strip's label column, and the narrowest contact column of the event list
        for w in [11, 8] {
            for names in [&contacts, &elements] {
                let labels = deckspin::tui::ui::row_names(names, w);
                assert_eq!(labels.len(), names.len());
                for (i, l) in labels.iter().enumerate() {
                    assert!(l.chars().count() <= w, "{p:?}: {l} wider than {w}");
                    assert!(!l.is_empty(), "{p:?}: {} has an empty label", names[i]);
                    assert_eq!(
                        labels.iter().filter(|m| *m == l).count(),
                        1,
                        "{p:?} at {w}: {l} twice in {labels:?}"
                    );
                }
            }
        }
    }
}

#[test]
fn the_joints_of_the_three_frame_bridge_keep_their_numbers() {
    let p = root().join("models/three-frame.toml");
    let scene = deckspin::model::load(&p, &[]).unwrap();
    let names: Vec<String> = scene.contacts.iter().map(|c| c.name.clone()).collect();
    let labels = deckspin::tui::ui::row_names(&names, 11);
    let of = |n: &str| labels[names.iter().position(|m| m == n).unwrap()].clone();
    assert_eq!(of("joint1_bottom"), "j1_bottom");
    assert_eq!(of("joint2_bottom"), "j2_bottom");
    assert_eq!(of("joint1_top"), "joint1_top");
    assert_eq!(of("left_top"), "left_top");
    // a name alone is shortened as before
    let one = deckspin::tui::ui::row_names(&["right_bottom".to_string()], 11);
    assert_eq!(one, ["r_bottom"]);
    // names alike but for their end keep their last characters
    let alike: Vec<String> = ["Xaaaaaaaaaaaaa1", "Xaaaaaaaaaaaaa2"]
        .map(String::from)
        .to_vec();
    assert_eq!(
        deckspin::tui::ui::row_names(&alike, 11),
        ["aaaaaaaaaa1", "aaaaaaaaaa2"]
    );
    // alike at both ends: numbered
    let same_ends: Vec<String> = ["aaaaaaaa_1_zzzzzzzz", "aaaaaaaa_2_zzzzzzzz"]
        .map(String::from)
        .to_vec();
    assert_eq!(
        deckspin::tui::ui::row_names(&same_ends, 8),
        ["aaaaaa~1", "aaaaaa~2"]
    );
}

#[test]
fn the_header_the_jump_and_the_event_list_count_the_same_events() {
    let run = short_run();
    let n = run.events.len();
    let instants = nav::event_times(run).len();
    assert!(
        instants < n,
        "some instants hold several events: {instants} {n}"
    );
    let mut app = bridge_app();
    act(&mut app, Action::CursorHome);
    update(&mut app, key('E'));
    // to the first instant that holds two events or more
    let mut k = 0;
    loop {
        update(&mut app, key(']'));
        k += 1;
        assert!(k <= instants, "{}", app.status);
        let t = app.cursor_time();
        if run.events.iter().filter(|e| e.t == t).count() > 1 {
            break;
        }
    }
    let t = app.cursor_time();
    let before = run.events.iter().filter(|e| e.t < t).count();
    let here = run.events.iter().filter(|e| e.t == t).count();
    let said = format!("events {}–{}/{n} at t = ", before + 1, before + here);
    assert!(app.status.starts_with(&said), "{} / {said}", app.status);
    // a single event reads `event k/n`
    update(&mut app, key('['));
    let t = app.cursor_time();
    let before = run.events.iter().filter(|e| e.t < t).count();
    if run.events.iter().filter(|e| e.t == t).count() == 1 {
        let said = format!("event {}/{n} at t = ", before + 1);
        assert!(app.status.starts_with(&said), "{} / {said}", app.status);
    }
    update(&mut app, key(']'));
    let t = render(&mut app, 120, 40);
    let s = screen(&t);
    assert!(s.contains(&format!(" {n} events")), "{s}");
    let t0 = app.cursor_time();
    let first = run.events.iter().filter(|e| e.t < t0).count() + 1;
    assert!(s.contains(&format!(" events {first}/{n} ")), "{s}");
}

#[test]
fn the_event_list_and_the_strip_name_the_joints_apart() {
    let p = root().join("models/three-frame.toml");
    let text = set(&read(&p), "solver.t_end", "1.0");
    let run = run_of(&text, &p, 1);
    let mut app = App::new_from_text(&text, Path::new("models/three-frame.toml"));
    app.current = Some(run);
    let s = screen(&render(&mut app, 120, 40));
    assert!(!s.contains(" j_bottom "), "{s}");
    assert!(s.contains(" j1_bottom "), "{s}");
    assert!(s.contains(" j2_bottom "), "{s}");
}

// ---------------------------------------------------------------------------------------------
// series picked per chart

/// The y labels of the chart whose header starts with `title`: (top, bottom).
fn chart_labels(lines: &[String], title: &str) -> (String, String) {
    let h = lines
        .iter()
        .position(|l| l.starts_with(title))
        .unwrap_or_else(|| panic!("no chart {title}:\n{}", lines.join("\n")));
    let rows: Vec<&String> = lines[h + 1..]
        .iter()
        .take_while(|l| l.chars().nth(12) == Some('│'))
        .collect();
    let label = |l: &str| l.split('│').next().unwrap_or("").trim().to_string();
    (label(rows[0]), label(rows[rows.len() - 1]))
}

/// A label is `v` formatted with its unit at 2 to 4 significant digits.
fn is_label_of(label: &str, v: f64, unit: &str) -> bool {
    (2..=4).any(|sig| eng_sig(v, unit, sig, false) == label)
}

/// The smallest and largest value of a column.
fn range(y: &[f64]) -> (f64, f64) {
    y.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        })
}

/// The cursor on the sample of the largest |y|; the value the readouts give there.
fn cursor_on_peak(app: &mut App, run: &RunData, y: &[f64]) -> f64 {
    let i = (0..y.len())
        .max_by(|&a, &b| y[a].abs().total_cmp(&y[b].abs()))
        .unwrap();
    app.follow = false;
    app.cursor = run.t[i];
    y[chart::at_or_before(&run.t, run.t[i]).unwrap()]
}

/// Types `text` into the list of series.
fn type_text(app: &mut App, text: &str) {
    for c in text.chars() {
        update(app, key(c));
    }
}

#[test]
fn an_abutment_picked_for_the_top_chart_is_drawn_with_its_peak() {
    let mut app = bridge_app();
    let run = short_run();
    let k = run
        .dof("right_abutment.x")
        .expect("the abutment moves in x");
    let v = cursor_on_peak(&mut app, run, &run.q[k]);
    update(&mut app, key('1'));
    update(&mut app, key('p'));
    assert_eq!(
        app.mode,
        Mode::ChartPick {
            chart: 0,
            query: String::new(),
            selected: 0
        }
    );
    type_text(&mut app, "right_abutment.x");
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains(">[ ] right_abutment.x "), "{s}");
    assert!(s.contains(" [ ] right_abutment.x velocity "), "{s}");
    update(&mut app, key(' '));
    // a length in place of θ: one y axis per chart
    assert!(
        app.status.contains("in place of deck.theta"),
        "{}",
        app.status
    );
    update(&mut app, code(KeyCode::Enter));
    assert_eq!(app.mode, Mode::Normal);
    let id = SeriesId::new(Kind::Q, "right_abutment.x");
    assert_eq!(app.charts.charts[0].series, Some(vec![id]));
    let lines = lines(&render(&mut app, 120, 40));
    let (lo, hi) = range(&run.q[k]);
    let sc = Scale::new(lo.abs().max(hi.abs()), "m", false);
    let head = format!("right_abutment.x [{}] ━{}", sc.unit, sc.fmt(v));
    assert!(lines[1].starts_with(&head), "{} / {head}", lines[1]);
    let (top, bottom) = chart_labels(&lines, "right_abutment.x");
    assert!(is_label_of(&top, hi, "m"), "{top} vs {hi}");
    assert!(is_label_of(&bottom, lo, "m"), "{bottom} vs {lo}");
}

#[test]
fn a_column_force_is_charted_in_the_force_unit() {
    let mut app = bridge_app();
    let run = short_run();
    let name = run.element_names[0].clone();
    let f = &run.el[0].1;
    let v = cursor_on_peak(&mut app, run, f);
    update(&mut app, key('2'));
    update(&mut app, key('p'));
    type_text(&mut app, &format!("force:{name}"));
    update(&mut app, key(' '));
    update(&mut app, code(KeyCode::Esc));
    let lines = lines(&render(&mut app, 120, 40));
    let (lo, hi) = range(f);
    let title = format!("{name} force");
    let sc = Scale::new(lo.abs().max(hi.abs()), "kN", false);
    let h = lines.iter().position(|l| l.starts_with(&title)).unwrap();
    let head = format!("{title} [{}] ━{}", sc.unit, sc.fmt(v));
    assert!(lines[h].starts_with(&head), "{} / {head}", lines[h]);
    let (top, bottom) = chart_labels(&lines, &title);
    assert!(is_label_of(&top, hi, "kN"), "{top} vs {hi}");
    assert!(is_label_of(&bottom, lo, "kN"), "{bottom} vs {lo}");
    // the other charts as they were
    assert!(lines[1].starts_with("deck.theta ["), "{}", lines[1]);
}

#[test]
fn the_series_list_filters_and_marks_what_is_shown() {
    let mut app = bridge_app();
    let run = short_run();
    update(&mut app, key('p'));
    type_text(&mut app, "gap");
    // gap and gap rate of each contact
    let n = run.contact_names.len();
    assert_eq!(
        chart_prefs::matching(run, "gap").len(),
        2 * n,
        "{:?}",
        chart_prefs::matching(run, "gap")
    );
    let s = screen(&render(&mut app, 80, 24));
    assert!(
        s.contains("chart 2 series") || s.contains("chart 1 series"),
        "{s}"
    );
    // every series a run records is there to pick: coordinates and velocities, five per
    // contact, two per element, the eight energy terms
    let all = deckspin::tui::runs::series::catalogue(run);
    let want = 2 * run.dof_names.len() + 5 * n + 2 * run.element_names.len() + 8;
    assert_eq!(all.len(), want, "{all:?}");
    // the gaps of chart 2 marked shown, deselected one by one
    update(&mut app, code(KeyCode::Esc));
    update(&mut app, key('2'));
    update(&mut app, key('p'));
    // Space shows or hides: a filter is typed without one
    type_text(&mut app, "gap:left_top");
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains(">[x] left_top gap "), "{s}");
    update(&mut app, key(' '));
    assert_eq!(app.charts.series(run, 1).len(), n - 1);
    update(&mut app, KeyCode::Backspace.into_msg());
    update(&mut app, KeyCode::Down.into_msg());
    let s = screen(&render(&mut app, 80, 24));
    assert!(s.contains("filter: gap:left_to "), "{s}");
    // ^D: the defaults again
    update(
        &mut app,
        Msg::Key(KeyEvent::new(KeyCode::Char('d'), KeyModifiers::CONTROL)),
    );
    assert_eq!(app.charts.charts[1].series, None);
    assert_eq!(app.charts.series(run, 1).len(), n);
}

#[test]
fn snapshot_chart_picker_80x24() {
    let mut app = bridge_app();
    update(&mut app, key('2'));
    update(&mut app, key('p'));
    type_text(&mut app, "left");
    update(&mut app, code(KeyCode::Down));
    let t = render(&mut app, 80, 24);
    snapshot_settings().bind(|| insta::assert_snapshot!("chart_picker_80x24", t.backend()));
}

/// The short bridge's text in a scratch folder of its own: (folder, model path).
fn scratch_model(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("tui_charts/{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("bridge.toml");
    std::fs::write(&p, short_bridge("0.004")).unwrap();
    p
}

#[test]
fn the_series_picked_and_the_unit_of_theta_survive_reopening_the_model() {
    let p = scratch_model("reopen");
    let mut app = App::new_from_path(&p, Options::default()).unwrap();
    app.current = Some(short_run().clone());
    let mut fx = update(&mut app, key('3'));
    fx.extend(update(&mut app, key('p')));
    for c in "normal".chars() {
        fx.extend(update(&mut app, key(c)));
    }
    fx.extend(update(&mut app, key(' ')));
    fx.extend(update(&mut app, code(KeyCode::Enter)));
    fx.extend(update(&mut app, key('d')));
    fx.extend(update(&mut app, key('g')));
    assert!(
        fx.iter().any(|e| matches!(e, Effect::StoreCharts { .. })),
        "{fx:?}"
    );
    tui::execute_blocking(&mut app, fx);
    let file = p.parent().unwrap().join("bridge.runs/charts.json");
    let text = read(&file);
    let first = &short_run().contact_names[0];
    assert!(text.contains(&format!("\"normal:{first}\"")), "{text}");
    // no temporary file left
    let names: Vec<String> = std::fs::read_dir(file.parent().unwrap())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["charts.json"]);
    let again = App::new_from_path(&p, Options::default()).unwrap();
    assert_eq!(
        again.charts.charts,
        app.charts.charts.clone().map(|mut c| {
            c.y_zoom = 0;
            c
        })
    );
    assert_eq!(
        again.charts.charts[2].series,
        Some(vec![SeriesId::new(Kind::Normal, first)])
    );
    assert!(again.charts.charts[2].log);
    assert_eq!(again.charts.theta, ThetaUnit::Mrad);
    // the runs folder holds no run: nothing is skipped in it
    assert!(!again.status.contains("skipped"), "{}", again.status);
}

#[test]
fn a_corrupt_or_foreign_charts_file_gives_the_defaults_and_says_so() {
    let p = scratch_model("corrupt");
    let file = p.parent().unwrap().join("bridge.runs/charts.json");
    std::fs::create_dir_all(file.parent().unwrap()).unwrap();
    for (bad, why) in [
        ("{\"format\": \"deckspin charts 1\", \"charts\": [", "EOF"),
        ("{\"format\": \"something else\", \"charts\": []}", "format"),
        ("\u{0}\u{1}binary", "expected value"),
    ] {
        std::fs::write(&file, bad).unwrap();
        let app = App::new_from_path(&p, Options::default()).unwrap();
        assert_eq!(app.charts, ChartPrefs::default());
        assert_eq!(app.status_kind, StatusKind::Warn, "{}", app.status);
        assert!(
            app.status.contains("charts.json") && app.status.contains("the default charts"),
            "{}",
            app.status
        );
        assert!(app.status.contains(why), "{} / {why}", app.status);
    }
    // a series of another model is left out, the file's others kept
    std::fs::write(
        &file,
        r#"{"format":"deckspin charts 1","theta":"deg","charts":[{"series":["q:nothing.x","q:deck.x"]},{"series":null},{"series":["bogus"]}]}"#,
    )
    .unwrap();
    let mut app = App::new_from_path(&p, Options::default()).unwrap();
    app.current = Some(short_run().clone());
    let run = short_run();
    assert_eq!(
        app.charts.series(run, 0),
        [SeriesId::new(Kind::Q, "deck.x")]
    );
    assert_eq!(app.charts.series(run, 2), []);
    let s = screen(&render(&mut app, 120, 40));
    assert!(s.contains("deck.x ["), "{s}");
}

// ---------------------------------------------------------------------------------------------
// θ's unit, y zoom, log scale, the axis of the run shown

#[test]
fn theta_in_degrees_reads_the_peak_times_180_over_pi() {
    let mut app = bridge_app();
    let run = short_run();
    let r = run.rot.unwrap();
    let v = cursor_on_peak(&mut app, run, &run.q[r]);
    let (lo, hi) = range(&run.q[r]);
    let big = lo.abs().max(hi.abs());
    // rad (prefixed), mrad, degrees
    let lines0 = lines(&render(&mut app, 120, 40));
    let sc = Scale::new(big, "rad", false);
    assert!(
        lines0[1].starts_with(&format!("deck.theta [{}] ━{}", sc.unit, sc.fmt(v))),
        "{}",
        lines0[1]
    );
    update(&mut app, key('d'));
    assert_eq!(app.status, "θ in mrad");
    let l = lines(&render(&mut app, 120, 40));
    let sc = Scale::fixed(big * 1e3, "mrad");
    let head = format!("deck.theta [mrad] ━{}", sc.fmt(v * 1e3));
    assert!(l[1].starts_with(&head), "{} / {head}", l[1]);
    update(&mut app, key('d'));
    let deg = 180.0 / std::f64::consts::PI;
    let l = lines(&render(&mut app, 120, 40));
    let sc = Scale::fixed(big * deg, "°");
    let head = format!("deck.theta [°] ━{}", sc.fmt(v * deg));
    assert!(l[1].starts_with(&head), "{} / {head}", l[1]);
    // the labels: the extremes in degrees, plain numbers
    let (top, bottom) = chart_labels(&l, "deck.theta");
    let plain = |x: f64| (1..=4).map(move |s| format!("{} °", chart::fmt_sig(x, s)));
    assert!(plain(hi * deg).any(|s| s == top), "{top} vs {}", hi * deg);
    assert!(
        plain(lo * deg).any(|s| s == bottom),
        "{bottom} vs {}",
        lo * deg
    );
    // the peak in degrees, worked by hand: 180/π × the peak in rad
    assert!((sc.fmt(v * deg).parse::<f64>().unwrap() - v * 57.29577951308232).abs() < 1e-4);
    update(&mut app, key('d'));
    assert_eq!(app.status, "θ in rad");
    assert_eq!(lines(&render(&mut app, 120, 40))[1], lines0[1]);
}

#[test]
fn y_zoom_halves_the_axis_around_the_cursors_value() {
    let mut app = bridge_app();
    let run = short_run();
    let r = run.rot.unwrap();
    let (lo, hi) = range(&run.q[r]);
    app.follow = false;
    app.cursor = 1.0;
    let c = run.q[r][chart::at_or_before(&run.t, 1.0).unwrap()];
    assert!(lo < c && c < hi);
    update(&mut app, key('1'));
    update(&mut app, key('Y'));
    assert_eq!(app.status, "chart 1: y zoom ×2");
    let l = lines(&render(&mut app, 120, 40));
    let half = 0.25 * (hi - lo);
    let (top, bottom) = chart_labels(&l, "deck.theta");
    assert!(is_label_of(&top, c + half, "rad"), "{top} vs {}", c + half);
    assert!(
        is_label_of(&bottom, c - half, "rad"),
        "{bottom} vs {}",
        c - half
    );
    update(&mut app, key('Y'));
    let (top, bottom) = chart_labels(&lines(&render(&mut app, 120, 40)), "deck.theta");
    assert!(is_label_of(&top, c + half / 2.0, "rad"), "{top}");
    assert!(is_label_of(&bottom, c - half / 2.0, "rad"), "{bottom}");
    // the other charts keep their axes
    let (gtop, _) = chart_labels(&l, "gaps g_N");
    let g_hi = (0..run.gap.len())
        .map(|i| range(&run.gap[i]).1)
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(is_label_of(&gtop, g_hi, "m"), "{gtop} vs {g_hi}");
    update(&mut app, key('y'));
    update(&mut app, key('y'));
    assert_eq!(app.status, "chart 1: the y axis fits the data");
    let (top, bottom) = chart_labels(&lines(&render(&mut app, 120, 40)), "deck.theta");
    assert!(is_label_of(&top, hi, "rad") && is_label_of(&bottom, lo, "rad"));
}

#[test]
fn a_log_scale_labels_the_magnitudes_and_leaves_zeros_out() {
    let mut app = bridge_app();
    let run = short_run();
    let r = run.rot.unwrap();
    let (lo, hi) = range(&run.q[r]);
    update(&mut app, key('g'));
    assert!(
        app.status.starts_with("chart 1: log scale of |value|"),
        "{}",
        app.status
    );
    let l = lines(&render(&mut app, 120, 40));
    let (top, bottom) = chart_labels(&l, "log|deck.theta|");
    // the largest magnitude on top, a smaller positive one at the bottom
    assert!(is_label_of(&top, lo.abs().max(hi.abs()), "rad"), "{top}");
    assert!(!bottom.starts_with('-') && bottom != top, "{bottom}");
    // the gaps: zero samples counted out
    let zeros: usize = run
        .gap
        .iter()
        .map(|g| g.iter().filter(|v| **v == 0.0).count())
        .sum();
    update(&mut app, key('2'));
    update(&mut app, key('g'));
    if zeros > 0 {
        let said = format!("({zeros} samples at 0 left out)");
        assert!(app.status.contains(&said), "{} / {said}", app.status);
    } else {
        assert_eq!(app.status, "chart 2: log scale of |value|");
    }
    let l = lines(&render(&mut app, 120, 40));
    assert!(
        l.iter().any(|x| x.starts_with("log|gaps g_N| [")),
        "{}",
        l.join("\n")
    );
    update(&mut app, key('g'));
    assert_eq!(app.status, "chart 2: linear scale");
}

#[test]
fn after_a_second_run_the_axis_reads_the_current_runs_extremes() {
    let (a, b) = (short_run(), short_prev_run());
    let r = a.rot.unwrap();
    let peak = |d: &RunData| range(&d.q[d.rot.unwrap()]);
    // the run shown is the one of the smaller peak, the baseline the other
    let (shown, base, text) = if peak(a).1 - peak(a).0 < peak(b).1 - peak(b).0 {
        (a, b, short_bridge("0.006"))
    } else {
        (b, a, short_bridge("0.004"))
    };
    let mut app = App::new_from_text(&short_bridge("0.004"), Path::new("models/four-span.toml"));
    app.current = Some(shown.clone());
    let saved = app.text.clone();
    app.runs.add(Entry::of_run(base, text), &saved);
    app.runs.pin(base.id);
    let (lo, hi) = range(&shown.q[r]);
    let (blo, bhi) = peak(base);
    assert!(blo < lo || bhi > hi, "the baseline reaches beyond");
    let l = lines(&render(&mut app, 120, 40));
    let (top, bottom) = chart_labels(&l, "deck.theta");
    assert!(is_label_of(&top, hi, "rad"), "{top} vs {hi}");
    assert!(is_label_of(&bottom, lo, "rad"), "{bottom} vs {lo}");
    // the baseline's extremes in the header, marked with its number
    let sc = Scale::new(lo.abs().max(hi.abs()), "rad", false);
    let bl = &app.runs.list[0].data;
    let kept = range(&bl.q[bl.rot.unwrap()]);
    let marked = format!("┈#{} ", base.id);
    let ext = format!("({}…{})", sc.fmt(kept.0), sc.fmt(kept.1));
    assert!(
        l[1].contains(&marked) && l[1].contains(&ext),
        "{} / {ext}",
        l[1]
    );
}
