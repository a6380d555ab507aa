//! The `units` key: the four-span bridge written in kip, in, s gives the same motion as in t, kN,
//! m, s (records stay in g; the Caltrans backfill and AASHTO's seat length convert).

mod common;

use deckspin::model;
use deckspin::units::UnitSystem;
use std::path::Path;
use toml_edit::{DocumentMut, Item, value};

const KIP_PER_KN: f64 = 1.0 / 4.448_221_615_260_5;
const IN_PER_M: f64 = 1.0 / 0.0254;

fn scale_item(item: &mut Item, f: f64) {
    match item {
        Item::Value(toml_edit::Value::Array(a)) => {
            for v in a.iter_mut() {
                *v = (v.as_float().unwrap() * f).into();
            }
        }
        Item::Value(v) => {
            let x = v.as_float().unwrap();
            *item = value(x * f);
        }
        _ => panic!("not a value"),
    }
}

fn scale(doc: &mut DocumentMut, path: &[&str], f: f64) {
    match path {
        [t, i, k] => {
            let a = doc[*t].as_array_of_tables_mut().unwrap();
            scale_item(&mut a.get_mut(i.parse().unwrap()).unwrap()[*k], f)
        }
        [t, k] => scale_item(&mut doc[*t][*k], f),
        _ => panic!("{path:?}"),
    }
}

/// The four-span bridge in kip, in, s: every dimensioned number converted.
fn in_kip_in(text: &str) -> String {
    let (l, f) = (IN_PER_M, KIP_PER_KN);
    let m = f / l; // kip·s²/in per t
    let mut d: DocumentMut = text.parse().unwrap();
    d["units"] = value("kip-in");
    for (p, k) in [
        ("deck.mass", m),
        ("deck.inertia", m * l * l),
        ("deck.length", l),
        ("deck.width", l),
        ("abutment.mass", m),
        ("abutment.inertia", m * l * l),
        ("abutment.actuator_stiffness", f / l),
        ("abutment.actuator_damping", f / l),
        ("abutment.actuator_offset", l),
        ("contacts.gaps", l),
        ("column.law.stiffness", f / l),
        ("column.law.yield_force", f),
        ("column.reference_height", l),
        ("column.offset", l),
        ("column.torsion_stiffness", f * l),
        ("bent.0.x", l),
        ("bent.1.x", l),
        ("bent.2.x", l),
        ("bent.0.height", l),
        ("bent.1.height", l),
        ("bent.2.height", l),
    ] {
        let path: Vec<&str> = p.split('.').collect();
        if path[0] == "column" && path[1] == "law" {
            let t = d["column"]["law"].as_inline_table_mut().unwrap();
            let x = t[path[2]].as_float().unwrap();
            t[path[2]] = (x * k).into();
        } else {
            scale(&mut d, &path, k);
        }
    }
    d.to_string()
}

/// The peak of `name` at rtol 1e-12, without the branch window: two column branch changes
/// 1e-4 s apart are applied together or one after the other as round-off says, which moves
/// the peaks by ~1e-6 whatever the units; the units alone move them by round-off.
fn peak(text: &str, path: &Path, name: &str) -> (f64, f64) {
    let set = [
        "solver.t_end=3.0",
        "solver.rtol=1e-12",
        "solver.atol=1e-15",
        "solver.branch_window=0",
    ];
    let set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    let scene = model::load_str(text, path, &set).unwrap();
    let r = deckspin::simulate::simulate(&scene, &mut deckspin::Silent).unwrap();
    let p = r.summary.peaks.iter().find(|p| p.name == name).unwrap();
    (p.max_abs, p.at)
}

#[test]
fn the_bridge_in_kip_in_moves_as_in_si_kn() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/four-span.toml");
    let si = std::fs::read_to_string(&path).unwrap();
    let us = in_kip_in(&si);
    let (th_si, t_si) = peak(&si, &path, "deck.theta");
    let (th_us, t_us) = peak(&us, &path, "deck.theta");
    assert!(th_si > 1e-5, "the run has a rotation to compare: {th_si}");
    assert!((th_us / th_si - 1.0).abs() < 1e-8, "{th_us} vs {th_si}");
    assert!((t_us - t_si).abs() < 1e-6, "{t_us} vs {t_si}");
    let (x_si, _) = peak(&si, &path, "deck.x");
    let (x_us, _) = peak(&us, &path, "deck.x");
    assert!(
        (x_us / (x_si * IN_PER_M) - 1.0).abs() < 1e-8,
        "{x_us} in vs {x_si} m"
    );
}

#[test]
fn records_in_g_become_the_systems_acceleration() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/four-span.toml");
    let si = std::fs::read_to_string(&path).unwrap();
    let us = in_kip_in(&si);
    let a = model::load_str(&si, &path, &[]).unwrap();
    let b = model::load_str(&us, &path, &[]).unwrap();
    assert_eq!((a.units, b.units), (UnitSystem::SiKn, UnitSystem::KipIn));
    let acc = |s: &deckspin::scene::Scene| match &s.supports[0].motion {
        deckspin::scene::Motion::Record(g) => g.acc.clone(),
        _ => panic!("record input"),
    };
    let (x, y) = (acc(&a), acc(&b));
    assert_eq!(x.len(), y.len());
    let worst = (x.iter().zip(&y))
        .map(|(p, q)| (q - p * IN_PER_M).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "{worst}");
}

#[test]
fn an_unknown_unit_system_names_the_key_and_the_choices() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/four-span.toml");
    let si = std::fs::read_to_string(&path).unwrap();
    let e = model::load_str(&si, &path, &["units=\"cgs\"".into()]).unwrap_err();
    let s = e.to_string();
    assert!(
        s.contains("units") && s.contains("SI-kN, SI, kip-in"),
        "{s}"
    );
}

/// The workbench's results pages in the model's units: the energy ledger of the bridge in
/// kip-in is in kip·in (1 kJ = 8.8507 kip·in), its contact forces in kip and kip·s.
#[cfg(feature = "workbench")]
#[test]
fn the_workbench_energy_page_is_in_the_models_energy_unit() {
    use common::tui::{render, screen};
    use deckspin::tui::app::View;
    use deckspin::tui::keymap::Action;
    use deckspin::tui::results::Page;
    use deckspin::tui::{self, App, Msg, update};

    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/four-span.toml");
    let short = |t: &str| {
        let mut d: DocumentMut = t.parse().unwrap();
        d["solver"]["t_end"] = value(2.0);
        d.to_string()
    };
    let si = short(&std::fs::read_to_string(&path).unwrap());
    let us = in_kip_in(&si);
    // the page of a model after its run: (screen, the ledger's input at the end)
    let page = |text: &str, page: Page| -> (String, f64) {
        let mut app = App::new_from_text(text, Path::new("models/four-span.toml"));
        let fx = app.start();
        tui::execute_blocking(&mut app, fx);
        let run = app.current.as_ref().expect("a run");
        let input = run.results.ledger.terms[0].last().copied().unwrap();
        app.view = View::Studies;
        for _ in 0..20 {
            if app.results.page == Some(page) {
                break;
            }
            let fx = update(&mut app, Msg::Action(Action::StudyNext));
            tui::execute_blocking(&mut app, fx);
        }
        assert_eq!(app.results.page, Some(page));
        (screen(&render(&mut app, 120, 40)), input)
    };
    let (s_si, in_si) = page(&si, Page::Energy);
    assert!(s_si.contains("energy ledger over time [kJ]"), "{s_si}");
    assert!(s_si.contains("energy [kJ]"), "{s_si}");
    let (s_us, in_us) = page(&us, Page::Energy);
    assert!(s_us.contains("energy ledger over time [kip·in]"), "{s_us}");
    assert!(s_us.contains("energy [kip·in]"), "{s_us}");
    assert!(!s_us.contains("kJ"), "{s_us}");
    // the same motion, its energy in the other unit: 1 kJ = 1 kN·m in kip·in
    let kip_in_per_kj = KIP_PER_KN * IN_PER_M;
    assert!((kip_in_per_kj - 8.8507).abs() < 1e-4);
    assert!(in_si > 0.0);
    // (the default tolerances of the solver, not scaled to inches: agreement to 1e-4)
    assert!(
        (in_us / (in_si * kip_in_per_kj) - 1.0).abs() < 1e-4,
        "{in_us} kip·in vs {in_si} kJ"
    );
    let shown = format!("input {} kip·in", tui::chart::fmt_sig(in_us, 4));
    assert!(s_us.contains(&shown), "{shown} in\n{s_us}");
    // the contact forces and impulses in kip and kip·s
    let (c_us, _) = page(&us, Page::Contacts);
    assert!(c_us.contains("forces [kip]"), "{c_us}");
    assert!(
        c_us.contains(" kip · max ΛN ") && c_us.contains(" kip·s "),
        "{c_us}"
    );
    assert!(!c_us.contains("kN"), "{c_us}");
    // SI: J
    let mut d: DocumentMut = si.parse().unwrap();
    d["units"] = value("SI");
    let (s_j, _) = page(&d.to_string(), Page::Energy);
    assert!(s_j.contains("energy ledger over time [J]"), "{s_j}");
}

/// The charts view of the bridge in kip-in: lengths in in (no SI prefix on them), the column
/// loop in kip, the runs compared in in; SI-kN keeps m and kN.
#[cfg(feature = "workbench")]
#[test]
fn the_workbench_charts_are_in_the_models_units() {
    use common::tui::{render, screen};
    use deckspin::tui::{self, App};

    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/four-span.toml");
    let mut d: DocumentMut = std::fs::read_to_string(&path).unwrap().parse().unwrap();
    d["solver"]["t_end"] = value(2.0);
    let si = d.to_string();
    let charts = |text: &str| -> String {
        let mut app = App::new_from_text(text, Path::new("models/four-span.toml"));
        let fx = app.start();
        tui::execute_blocking(&mut app, fx);
        screen(&render(&mut app, 120, 40))
    };
    let s = charts(&in_kip_in(&si));
    // (in takes no SI prefix: a scale of 1e-3 in is written out)
    assert!(s.contains("gaps g_N [1e-3 in]"), "{s}");
    assert!(s.contains("deck.x / deck.y [in]"), "{s}");
    assert!(s.contains("deck.theta [µrad]"), "{s}");
    assert!(s.contains("min gap [in]"), "{s}");
    assert!(
        s.contains(" kip│") && s.contains(" kip ───"),
        "the column loop's force: {s}"
    );
    assert!(
        !s.contains("mm") && !s.contains(" kN") && !s.contains("[m]"),
        "{s}"
    );
    let s = charts(&si);
    assert!(s.contains("gaps g_N [mm]"), "{s}");
    assert!(s.contains("min gap [m]") && s.contains(" kN"), "{s}");
}
