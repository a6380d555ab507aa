//! The Fig. 7 and Fig. 8 analog tables (text and CSV) of `deckspin study` and of
//! `deckspin sequence --study`.

use deckspin::studies::{MuStudy, Row};
use std::fmt::Write as _;

/// Fig. 7 table: (text, CSV); `note` is appended to the title.
pub fn pga_table(
    rows: &[(usize, f64, f64, Row, Row)],
    note: &str,
) -> Result<(String, String), std::fmt::Error> {
    let (mut text, mut csv) = (String::new(), String::new());
    writeln!(
        text,
        "Peak deck rotation vs target PGA (Fig. 7 analog){note}"
    )?;
    writeln!(
        text,
        "{:>4} {:>7} {:>7} {:>14} {:>14} {:>7} {:>8}",
        "run", "PGA x", "PGA y", "θ no contact", "θ contact", "ratio", "impacts"
    )?;
    csv += "run,pga_x,pga_y,peak_rotation_no_contact,peak_rotation_contact,residual_rotation_contact,impacts\n";
    for (i, px, py, a, b) in rows {
        writeln!(
            text,
            "{i:>4} {px:>7.3} {py:>7.3} {:>14.4e} {:>14.4e} {:>7.2} {:>8}",
            a.peak_rotation,
            b.peak_rotation,
            b.peak_rotation / a.peak_rotation,
            b.impacts
        )?;
        writeln!(
            csv,
            "{i},{px},{py},{:.6e},{:.6e},{:.6e},{}",
            a.peak_rotation, b.peak_rotation, b.residual_rotation, b.impacts
        )?;
        for r in [a, b] {
            if let Some(e) = &r.error {
                writeln!(text, "     error: {e}")?;
            }
        }
    }
    Ok((text, csv))
}

/// Fig. 8 table: (text, CSV); rows labelled by `runs` (the `[[run]]` numbers), `note` appended
/// to the title.
pub fn mu_table(
    m: &MuStudy,
    runs: &[usize],
    note: &str,
) -> Result<(String, String), std::fmt::Error> {
    let (mut text, mut csv) = (String::new(), String::new());
    let mus = &m.mus;
    writeln!(
        text,
        "Percent increase of peak rotation over no contact vs μ (Fig. 8 analog){note}"
    )?;
    write!(text, "{:>16}", "run (PGA x)")?;
    csv += "run,pga_x";
    for mu in mus {
        write!(text, " {:>7}", format!("μ={mu}"))?;
        write!(csv, ",mu_{mu}")?;
    }
    writeln!(text)?;
    csv += "\n";
    for r in 0..m.rows.len() {
        let label = runs.get(r).copied().unwrap_or(r + 1);
        write!(text, "{:>16}", format!("{label} ({:.2} g)", m.pgas[r].0))?;
        write!(csv, "{label},{}", m.pgas[r].0)?;
        for k in 0..mus.len() {
            write!(text, " {:>7.1}", m.increase(r, k))?;
            write!(csv, ",{:.3}", m.increase(r, k))?;
        }
        writeln!(text)?;
        csv += "\n";
    }
    write!(text, "{:>16}", "mean")?;
    csv += "mean,";
    for k in 0..mus.len() {
        write!(text, " {:>7.1}", m.mean_increase(k))?;
        write!(csv, ",{:.3}", m.mean_increase(k))?;
    }
    writeln!(text)?;
    csv += "\n";
    for row in m.rows.iter().flatten().chain(m.baseline.iter()) {
        if let Some(e) = &row.error {
            writeln!(text, "error: {e}")?;
        }
    }
    Ok((text, csv))
}

/// `deckspin modes`: periods, frequencies and shapes (each scaled to its largest component),
/// every column as wide as its DOF's full name; a component that rounds to zero is shown as
/// 0, without a sign.
pub fn modes_table(scene: &deckspin::scene::Scene, modes: &[deckspin::modal::Mode]) -> String {
    use std::fmt::Write as _;
    let mut s = format!("{} — {} DOF\n", scene.title, scene.ndof());
    let widths: Vec<usize> = (scene.dof_names.iter())
        .map(|n| n.chars().count().max(8))
        .collect();
    let _ = write!(s, "{:>5} {:>10} {:>10}", "mode", "T (s)", "f (Hz)");
    for (n, w) in scene.dof_names.iter().zip(&widths) {
        let _ = write!(s, " {n:>w$}");
    }
    s.push('\n');
    for (i, m) in modes.iter().enumerate() {
        let big = m.shape.amax().max(1e-300);
        let f = m.omega / (2.0 * std::f64::consts::PI);
        let _ = write!(s, "{:>5} {:>10.5} {:>10.4}", i + 1, m.period, f);
        for (x, w) in m.shape.iter().zip(&widths) {
            let v = x / big;
            let v = if v.abs() < 5e-5 { 0.0 } else { v };
            let _ = write!(s, " {v:>w$.4}");
        }
        s.push('\n');
    }
    if scene.mass_damping.alpha != 0.0 {
        let _ = writeln!(
            s,
            "Rayleigh: a0 = {:.5e} 1/s (mass), element dashpots a1·k",
            scene.mass_damping.alpha
        );
    }
    s
}
