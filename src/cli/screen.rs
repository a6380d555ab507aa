//! `deckspin screen`: what the impact law says before any run (`design::screen`) and, with
//! `--equivalence`, which gap element reproduces the event-driven peak rotation
//! (`design::equivalence`).

use clap::Args;
use deckspin::design::equivalence::{Answer, Cell, answers, default_grid, grid};
use deckspin::design::screen::{
    Flush, MapCell, ModelCorner, map_axes, model_screen, screening_map,
};
use deckspin::design::screen_chart::map_grids;
use deckspin::plot::svg::render_grid;
use std::path::PathBuf;

/// Closed-form screening by the impact law; `--equivalence` adds the gap-element table.
#[derive(Args)]
pub struct ScreenArgs {
    #[command(flatten)]
    pub model: super::args::ModelArgs,
    /// Also run the penalty method over contact stiffness × step against the event-driven peak
    /// rotation (tens of runs of the whole record).
    #[arg(long)]
    pub equivalence: bool,
    /// Fewer stiffnesses and steps for `--equivalence`.
    #[arg(long)]
    pub quick: bool,
    /// Output directory (screen.json, screen-map.csv, equivalence.csv).
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
}

pub fn cmd_screen(a: &ScreenArgs) -> Result<(), Box<dyn std::error::Error>> {
    let scene = deckspin::load(&a.model.path, &a.model.set)?;
    let (rigid, blocks) = (model_screen(&scene, true).0, model_screen(&scene, false).0);
    let ends = model_screen(&scene, true).1;
    println!(
        "{}: screening by the impact law (eq. 5–7), before any run",
        scene.title
    );
    println!(
        "\nflush ends (both corners at once, deck moving along its axis into a parallel face):"
    );
    for e in &ends {
        println!(
            "  {:<28} L/B {:>6.2}  skew {:>5.1}°  μ {}  ε {}  → {}",
            format!("{} + {}", e.contacts[0], e.contacts[1]),
            e.l_over_b,
            e.skew_deg,
            e.mu,
            e.restitution,
            flush_text(e.flush)
        );
    }
    println!("\ncorners struck alone at 1 m/s along the deck's axis (θ̇⁺ in rad/s per m/s):");
    println!(
        "  {:<16} {:>30}   {:>30}",
        "contact", "against a rigid face", "against the face's own body"
    );
    println!(
        "  {:<16} {:>7} {:>10} {:>11}   {:>7} {:>10} {:>11}",
        "", "sticks", "μ needed", "θ̇⁺", "sticks", "μ needed", "θ̇⁺"
    );
    for (r, b) in rigid.iter().zip(&blocks) {
        println!(
            "  {:<16} {}   {}",
            r.contact,
            corner_text(r),
            corner_text(b)
        );
    }
    let (mu, eps) = ends
        .first()
        .map(|e| (e.mu, e.restitution))
        .or_else(|| rigid.first().map(|c| (c.mu, c.restitution)))
        .unwrap_or((0.0, 0.0));
    let (lb, skew) = map_axes();
    let cells = screening_map(&lb, &skew, mu, eps);
    let point = ends.first().map(|e| (e.l_over_b, e.skew_deg));
    let mark = point.map(|(l, s)| (nearest(l, &lb, true), nearest(s, &skew, false)));
    println!("\n{}", draw_map(&cells, &lb, &skew, mark, mu, eps));
    std::fs::create_dir_all(&a.out)?;
    // one job writes this folder at a time
    let _lock = deckspin::output::files::FolderLock::acquire(&a.out)?;
    let json = serde_json::json!({
        "model": a.model.path.display().to_string(),
        "ends": ends,
        "corners_rigid_face": rigid,
        "corners_face_body": blocks,
        "map": { "mu": mu, "restitution": eps, "cells": cells },
    });
    deckspin::output::files::write_atomic(
        a.out.join("screen.json"),
        serde_json::to_string_pretty(&json)?,
    )?;
    write_map_csv(&cells, &a.out.join("screen-map.csv"))?;
    let [flush, corner] = map_grids(&cells, &lb, &skew, mark, mu, eps);
    deckspin::output::files::write_atomic(a.out.join("screen-flush.svg"), render_grid(&flush))?;
    deckspin::output::files::write_atomic(a.out.join("screen-corner.svg"), render_grid(&corner))?;
    println!(
        "wrote {}/screen.json, screen-map.csv, screen-flush.svg, screen-corner.svg",
        a.out.display()
    );
    if a.equivalence {
        equivalence(a)?;
    }
    Ok(())
}

fn flush_text(f: Flush) -> &'static str {
    match f {
        Flush::Straight => "stays straight",
        Flush::RotatesSticking => "rotates (corners stick)",
        Flush::RotatesSliding => "rotates (corners slide)",
    }
}

fn corner_text(c: &ModelCorner) -> String {
    match &c.impact {
        Some(i) => format!(
            "{:>7} {:>10.4} {:>11.3e}",
            if i.sticks { "yes" } else { "no" },
            i.stick_mu,
            c.spin
        ),
        None => format!("{:>30}", c.note.as_deref().unwrap_or("—")),
    }
}

/// The flush-impact map as text: rows skew (top 60°), columns L/B (log), `.` straight,
/// `s` rotates sticking, `S` rotates sliding, `@` the model; beside it which corner sticks alone.
fn draw_map(
    cells: &[MapCell],
    lb: &[f64],
    skew: &[f64],
    mark: Option<(usize, usize)>,
    mu: f64,
    eps: f64,
) -> String {
    let mut out = format!(
        "after a flush impact (μ {mu}, ε {eps}):  . stays straight   s rotates, corners stick   \
         S rotates, corners slide   @ this model\n\
         and a corner struck alone:  B both corners stick   a only the acute   o only the obtuse   - neither\n"
    );
    for (r, &phi) in skew.iter().enumerate().rev() {
        let row = |f: &dyn Fn(&MapCell) -> char| -> String {
            (0..lb.len())
                .map(|c| {
                    if mark == Some((c, r)) {
                        '@'
                    } else {
                        f(&cells[r * lb.len() + c])
                    }
                })
                .collect()
        };
        let flush = row(&|m| m.flush.glyph());
        let corner = row(&|m| m.corners().glyph());
        out.push_str(&format!("{phi:>4.0}° |{flush}|   |{corner}|\n"));
    }
    let axis = format!(
        "L/B {:<8.0}{:^14.0}{:>8.0}",
        lb[0],
        lb[lb.len() / 2],
        lb[lb.len() - 1]
    );
    out.push_str(&format!("       {axis}     {axis}\n"));
    out
}

/// The index of `axis` nearest to `v` (in ln on a log axis).
fn nearest(v: f64, axis: &[f64], log: bool) -> usize {
    let f = |x: f64| if log { x.ln() } else { x };
    (0..axis.len())
        .min_by(|&i, &j| {
            (f(axis[i]) - f(v))
                .abs()
                .total_cmp(&(f(axis[j]) - f(v)).abs())
        })
        .unwrap_or(0)
}

fn write_map_csv(cells: &[MapCell], path: &std::path::Path) -> std::io::Result<()> {
    let mut s = String::from("l_over_b,skew_deg,flush,acute_sticks,obtuse_sticks,acute_spin\n");
    let b = |x: Option<bool>| x.map_or(String::new(), |v| v.to_string());
    for c in cells {
        s.push_str(&format!(
            "{},{},{:?},{},{},{}\n",
            c.l_over_b,
            c.skew_deg,
            c.flush,
            b(c.acute_sticks),
            b(c.obtuse_sticks),
            c.acute_spin
        ));
    }
    deckspin::output::files::write_atomic(path, s)
}

/// The penalty method over k × h against the event-driven reference.
fn equivalence(a: &ScreenArgs) -> Result<(), Box<dyn std::error::Error>> {
    use deckspin::methods::Method;
    let bench = deckspin::precision::Bench::open(&a.model.path, &a.model.set)?;
    deckspin::run::check_memory(&bench.study.scene(&[])?)?;
    let reference = bench.reference(1e-10)?;
    let (ks, hs) = default_grid(a.quick);
    eprintln!(
        "gap-element equivalence: event-driven reference (rtol 1e-10) peak |{}| = {:.6e}; {} penalty runs",
        reference.run.dof_names[reference.dof],
        reference.peak,
        ks.len() * hs.len()
    );
    let bar = super::progress::Bar::new();
    let cells = grid(&bench, &reference, Method::Penalty, &ks, &hs, &bar);
    bar.clear();
    println!("\n{}", equivalence_table(&cells, &ks, &hs));
    for ans in answers(&cells, &[0.01, 0.05, 0.10]) {
        println!("{}", answer_text(&ans));
    }
    let mut s = String::from("k,h,peak_error,steps,cpu_s,status\n");
    for c in &cells {
        let status = c
            .point
            .failure
            .as_ref()
            .map_or("ok".into(), |e| e.to_string());
        s.push_str(&format!(
            "{},{},{},{},{},\"{}\"\n",
            c.k,
            c.h,
            c.point.peak_error,
            c.point.steps,
            c.point.cpu_s,
            status.replace('"', "'")
        ));
    }
    deckspin::output::files::write_atomic(a.out.join("equivalence.csv"), s)?;
    println!("wrote {}/equivalence.csv", a.out.display());
    Ok(())
}

fn equivalence_table(cells: &[Cell], ks: &[f64], hs: &[f64]) -> String {
    let mut s = format!(
        "peak-rotation error of the penalty method (gap elements, Newmark) against the event-driven run\n{:>12}",
        "k \\ h (s)"
    );
    for h in hs {
        s.push_str(&format!(" {h:>9.0e}"));
    }
    s.push('\n');
    for &k in ks {
        s.push_str(&format!("{k:>12.0e}"));
        for &h in hs {
            let c = cells.iter().find(|c| c.k == k && c.h == h);
            let txt = match c {
                Some(c) if c.point.is_ok() => format!("{:.2} %", 100.0 * c.point.peak_error),
                Some(c) => (c.point.failure.as_ref()).map_or("failed".into(), |e| {
                    e.to_string()
                        .split(':')
                        .next()
                        .unwrap_or("failed")
                        .to_string()
                }),
                None => String::new(),
            };
            s.push_str(&format!(" {txt:>9}"));
        }
        s.push('\n');
    }
    s
}

fn answer_text(a: &Answer) -> String {
    let head = format!("within {:>2.0} %:", 100.0 * a.tol);
    match a.cheapest {
        Some((k, h)) => {
            let per_k: Vec<String> = (a.largest_step.iter())
                .map(|(k, h)| match h {
                    Some(h) => format!("k {k:.0e}: h ≤ {h:.0e} s"),
                    None => format!("k {k:.0e}: none"),
                })
                .collect();
            format!(
                "{head} k = {k:.0e} with h = {h:.0e} s is the cheapest ({})",
                per_k.join("; ")
            )
        }
        None => format!("{head} no stiffness and step tried"),
    }
}
