//! A study's table ([`StudyTable`]) as CSV, and back: numbers as their shortest round-trip
//! text ([`crate::output::number`]), so a table read back holds the same f64 bit for bit; a
//! file that is not such a table is refused with its path, line and the reason.
//!
//! The PGA, μ and suite studies, one line per run:
//! `study,run,pga_x,pga_y,contact,mu,peak_rotation,residual_rotation,impacts,status` —
//! `study` is `pga`, `mu` or `suite` (`run` the record pair's number, `pga_x` the level, g,
//! `pga_y` NaN), `mu` is empty where the model's own μ applies (the PGA study, the
//! μ study's runs without contact), `status` is `ok`, `not run` (the study was cancelled
//! first) or the reason the run failed.
//!
//! Work–precision, one line per planned point: see [`crate::precision_study`].
//!
//! The screening, one line per item:
//! `item,name,l_over_b,skew_deg,mu,restitution,outcome,acute_sticks,obtuse_sticks,stick_mu,spin,note`
//! — `item` is `cell` (a map cell: its flush outcome, which corners stick alone, `spin` the
//! acute corner's θ̇⁺ L / v), `end` (a flush end of the model, `name` its two contacts joined by
//! ` + `) or `corner_rigid` / `corner_body` (a corner struck alone against a rigid face or the
//! face's own body: `outcome` `sticks`, `slides` or `none` with the `note`).
//!
//! The model ladder, one line per model (the full one first): `deckspin adequacy`'s
//! `adequacy.csv` ([`crate::design::adequacy_report::variants_csv`]); the swings, one line per
//! input and quantity: `deckspin sensitivity`'s `sensitivity.csv` ([`Sensitivity::csv`]).
//! Neither is read back: the ladder's variants need the model's text, the swings their runs.

use crate::design::adequacy_report::variants_csv;
use crate::design::screen::{CornerAlone, Flush, MapCell, ModelEnd, ScreenStudy};
use crate::design::swings::{SUMMARY_HEADER, Sensitivity};
use crate::output::number::Numbers;
use crate::precision_study;
use crate::study_table::{PointStatus, RunTable, StudyKind, StudyRun, StudyTable};
use std::path::{Path, PathBuf};

const RUN_HEADER: [&str; 10] = [
    "study",
    "run",
    "pga_x",
    "pga_y",
    "contact",
    "mu",
    "peak_rotation",
    "residual_rotation",
    "impacts",
    "status",
];

const SCREEN_HEADER: [&str; 12] = [
    "item",
    "name",
    "l_over_b",
    "skew_deg",
    "mu",
    "restitution",
    "outcome",
    "acute_sticks",
    "obtuse_sticks",
    "stick_mu",
    "spin",
    "note",
];

/// Why a file is not a study's CSV.
#[derive(Debug, thiserror::Error)]
pub enum StudyCsvError {
    #[error("{}: cannot read: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// Line `line` (from 1) of the file is not what a study's CSV holds there.
    #[error("{}:{line}: {reason}", path.display())]
    Bad {
        path: PathBuf,
        line: u64,
        reason: String,
    },
}

/// The CSV text of a table.
pub fn to_csv(table: &StudyTable) -> String {
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut n = Numbers::new();
    let mut num = |x: f64| n.format(x).to_string();
    let result = match table {
        StudyTable::Runs(t) => write_runs(&mut w, t, &mut num),
        StudyTable::Screen(s) => write_screen(&mut w, s, &mut num),
        StudyTable::Precision(t) => precision_study::write_rows(&mut w, t, &mut num),
        StudyTable::Adequacy(a) => return variants_csv(a),
        StudyTable::Sensitivity(s) => return Sensitivity::csv(s),
    };
    // writing to memory fails only on a bug of the csv crate: keep what was written
    let _ = result;
    let bytes = w.into_inner().unwrap_or_default();
    String::from_utf8(bytes).unwrap_or_default()
}

type Num<'a> = dyn FnMut(f64) -> String + 'a;

fn write_runs(w: &mut csv::Writer<Vec<u8>>, t: &RunTable, num: &mut Num) -> Result<(), csv::Error> {
    w.write_record(RUN_HEADER)?;
    for r in &t.runs {
        let status = match &r.status {
            PointStatus::Ok => "ok".to_string(),
            PointStatus::NotRun => "not run".to_string(),
            PointStatus::Failed(e) => e.clone(),
        };
        w.write_record([
            t.kind.key().to_string(),
            r.run.to_string(),
            num(r.pga_x),
            num(r.pga_y),
            r.contact.to_string(),
            r.mu.map_or(String::new(), &mut *num),
            num(r.peak_rotation),
            num(r.residual_rotation),
            r.impacts.to_string(),
            status,
        ])?;
    }
    Ok(())
}

fn flush_text(f: Flush) -> &'static str {
    match f {
        Flush::Straight => "Straight",
        Flush::RotatesSticking => "RotatesSticking",
        Flush::RotatesSliding => "RotatesSliding",
    }
}

fn opt_bool(b: Option<bool>) -> String {
    b.map_or(String::new(), |v| v.to_string())
}

fn write_screen(
    w: &mut csv::Writer<Vec<u8>>,
    s: &ScreenStudy,
    num: &mut Num,
) -> Result<(), csv::Error> {
    w.write_record(SCREEN_HEADER)?;
    for c in &s.cells {
        w.write_record([
            "cell".to_string(),
            String::new(),
            num(c.l_over_b),
            num(c.skew_deg),
            num(s.mu),
            num(s.restitution),
            flush_text(c.flush).to_string(),
            opt_bool(c.acute_sticks),
            opt_bool(c.obtuse_sticks),
            String::new(),
            num(c.acute_spin),
            String::new(),
        ])?;
    }
    for e in &s.ends {
        w.write_record([
            "end".to_string(),
            format!("{} + {}", e.contacts[0], e.contacts[1]),
            num(e.l_over_b),
            num(e.skew_deg),
            num(e.mu),
            num(e.restitution),
            flush_text(e.flush).to_string(),
            String::new(),
            String::new(),
            String::new(),
            String::new(),
            String::new(),
        ])?;
    }
    for c in &s.corners {
        let outcome = match c.sticks {
            Some(true) => "sticks",
            Some(false) => "slides",
            None => "none",
        };
        w.write_record([
            if c.rigid_face {
                "corner_rigid"
            } else {
                "corner_body"
            }
            .to_string(),
            c.contact.clone(),
            String::new(),
            String::new(),
            num(c.mu),
            num(c.restitution),
            outcome.to_string(),
            String::new(),
            String::new(),
            num(c.stick_mu),
            num(c.spin),
            c.note.clone().unwrap_or_default(),
        ])?;
    }
    Ok(())
}

/// Reads a study's CSV file.
pub fn read_file(path: &Path) -> Result<StudyTable, StudyCsvError> {
    let text = std::fs::read_to_string(path).map_err(|source| StudyCsvError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    read_csv(&text, path)
}

/// Reads a study's CSV text (`path` names it in errors): the kind of study from its header.
pub fn read_csv(text: &str, path: &Path) -> Result<StudyTable, StudyCsvError> {
    let bad = |line: u64, reason: String| StudyCsvError::Bad {
        path: path.to_path_buf(),
        line,
        reason,
    };
    let mut r = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(text.as_bytes());
    let mut records = Vec::new();
    for rec in r.records() {
        let rec = rec.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line());
            bad(line, format!("not CSV: {e}"))
        })?;
        let line = rec.position().map_or(0, |p| p.line());
        records.push((line, rec));
    }
    let Some((_, head)) = records.first() else {
        return Err(bad(1, "empty: no header".into()));
    };
    let head: Vec<&str> = head.iter().collect();
    let body = &records[1..];
    if body.is_empty() {
        return Err(bad(2, "no rows after the header".into()));
    }
    let widths = |width: usize| {
        for (line, rec) in body {
            if rec.len() != width {
                let why = format!("{} fields, the header has {width}", rec.len());
                return Err(bad(*line, why));
            }
        }
        Ok(())
    };
    if head == RUN_HEADER {
        let mut runs = Vec::new();
        let mut kind = None;
        widths(RUN_HEADER.len())?;
        for (line, rec) in body {
            let (k, run) = run_row(rec, kind).map_err(|e| bad(*line, e))?;
            kind = Some(k);
            runs.push(run);
        }
        let kind = kind.unwrap_or(StudyKind::Pga);
        return Ok(StudyTable::Runs(RunTable { kind, runs }));
    }
    if head == SCREEN_HEADER {
        widths(SCREEN_HEADER.len())?;
        return screen_rows(body).map_err(|(line, e)| bad(line, e));
    }
    if head == precision_study::HEADER {
        widths(precision_study::HEADER.len())?;
        return (precision_study::read_rows(body))
            .map(StudyTable::Precision)
            .map_err(|(line, e)| bad(line, e));
    }
    let written = |what: &str| {
        let why = format!(
            "the {what} study's CSV: written for reading elsewhere, not reopened here (Enter \
             runs the study again)"
        );
        Err(bad(1, why))
    };
    if head.starts_with(&["variant", "status", "cpu_s", "steps", "events", "speedup"]) {
        return written("model adequacy");
    }
    if head == SUMMARY_HEADER {
        return written("sensitivity");
    }
    Err(bad(
        1,
        format!(
            "not a study's CSV: the header is `{}`, expected `{}`, `{}` or `{}`",
            head.join(","),
            RUN_HEADER.join(","),
            SCREEN_HEADER.join(","),
            precision_study::HEADER.join(",")
        ),
    ))
}

fn number(rec: &csv::StringRecord, i: usize, head: &[&str]) -> Result<f64, String> {
    let s = &rec[i];
    s.parse::<f64>()
        .map_err(|_| format!("{}: `{s}` is not a number", head[i]))
}

fn boolean(rec: &csv::StringRecord, i: usize, head: &[&str]) -> Result<Option<bool>, String> {
    match &rec[i] {
        "" => Ok(None),
        "true" => Ok(Some(true)),
        "false" => Ok(Some(false)),
        s => Err(format!("{}: `{s}` is not true, false or empty", head[i])),
    }
}

/// One line of the PGA or μ study; `kind`: that of the lines before.
fn run_row(
    rec: &csv::StringRecord,
    kind: Option<StudyKind>,
) -> Result<(StudyKind, StudyRun), String> {
    let h = &RUN_HEADER;
    let k = match &rec[0] {
        "pga" => StudyKind::Pga,
        "mu" => StudyKind::Mu,
        "suite" => StudyKind::Suite,
        s => return Err(format!("study: `{s}` is not pga, mu or suite")),
    };
    if kind.is_some_and(|p| p != k) {
        return Err(format!("study: `{}` after lines of another study", &rec[0]));
    }
    let run: usize = (rec[1].parse().ok())
        .filter(|&r| r >= 1)
        .ok_or_else(|| format!("run: `{}` is not a run number (1, 2, …)", &rec[1]))?;
    let contact = boolean(rec, 4, h)?.ok_or("contact: empty, expected true or false")?;
    let mu = match &rec[5] {
        "" => None,
        _ => Some(number(rec, 5, h)?),
    };
    match (k, contact, mu) {
        (StudyKind::Pga | StudyKind::Suite, _, Some(_)) => {
            return Err(format!("mu: given in the {} study", k.key()));
        }
        (StudyKind::Suite, false, _) => return Err("contact: false in the suite".into()),
        (StudyKind::Mu, true, None) => return Err("mu: empty on a run with contact".into()),
        (StudyKind::Mu, false, Some(_)) => return Err("mu: given on a run without contact".into()),
        _ => {}
    }
    let impacts =
        (rec[8].parse().ok()).ok_or_else(|| format!("impacts: `{}` is not a count", &rec[8]))?;
    let status = match &rec[9] {
        "ok" => PointStatus::Ok,
        "not run" => PointStatus::NotRun,
        "" => return Err("status: empty, expected ok, not run or the reason of a failure".into()),
        e => PointStatus::Failed(e.to_string()),
    };
    let run = StudyRun {
        run,
        pga_x: number(rec, 2, h)?,
        pga_y: number(rec, 3, h)?,
        contact,
        mu,
        peak_rotation: number(rec, 6, h)?,
        residual_rotation: number(rec, 7, h)?,
        impacts,
        status,
    };
    Ok((k, run))
}

fn flush(rec: &csv::StringRecord) -> Result<Flush, String> {
    match &rec[6] {
        "Straight" => Ok(Flush::Straight),
        "RotatesSticking" => Ok(Flush::RotatesSticking),
        "RotatesSliding" => Ok(Flush::RotatesSliding),
        s => Err(format!(
            "outcome: `{s}` is not Straight, RotatesSticking or RotatesSliding"
        )),
    }
}

/// The lines of the screening: the map's cells (row by row of skew), ends and corners.
fn screen_rows(body: &[(u64, csv::StringRecord)]) -> Result<StudyTable, (u64, String)> {
    let h = &SCREEN_HEADER;
    let mut s = ScreenStudy {
        mu: f64::NAN,
        restitution: f64::NAN,
        l_over_b: Vec::new(),
        skew_deg: Vec::new(),
        cells: Vec::new(),
        ends: Vec::new(),
        corners: Vec::new(),
    };
    let mut cell_lines = Vec::new();
    for (line, rec) in body {
        let at = |e: String| (*line, e);
        match &rec[0] {
            "cell" => {
                let (mu, eps) = (
                    number(rec, 4, h).map_err(at)?,
                    number(rec, 5, h).map_err(at)?,
                );
                if s.cells.is_empty() {
                    (s.mu, s.restitution) = (mu, eps);
                } else if mu.to_bits() != s.mu.to_bits() || eps.to_bits() != s.restitution.to_bits()
                {
                    return Err(at(
                        "mu, restitution: differ from the map's first cell".into()
                    ));
                }
                s.cells.push(MapCell {
                    l_over_b: number(rec, 2, h).map_err(at)?,
                    skew_deg: number(rec, 3, h).map_err(at)?,
                    flush: flush(rec).map_err(at)?,
                    acute_sticks: boolean(rec, 7, h).map_err(at)?,
                    obtuse_sticks: boolean(rec, 8, h).map_err(at)?,
                    acute_spin: number(rec, 10, h).map_err(at)?,
                });
                cell_lines.push(*line);
            }
            "end" => {
                let (a, b) = (rec[1].split_once(" + "))
                    .ok_or_else(|| at(format!("name: `{}` is not `contact + contact`", &rec[1])))?;
                s.ends.push(ModelEnd {
                    contacts: [a.to_string(), b.to_string()],
                    l_over_b: number(rec, 2, h).map_err(at)?,
                    skew_deg: number(rec, 3, h).map_err(at)?,
                    mu: number(rec, 4, h).map_err(at)?,
                    restitution: number(rec, 5, h).map_err(at)?,
                    flush: flush(rec).map_err(at)?,
                });
            }
            item @ ("corner_rigid" | "corner_body") => {
                let sticks = match &rec[6] {
                    "sticks" => Some(true),
                    "slides" => Some(false),
                    "none" => None,
                    o => return Err(at(format!("outcome: `{o}` is not sticks, slides or none"))),
                };
                s.corners.push(CornerAlone {
                    contact: rec[1].to_string(),
                    rigid_face: item == "corner_rigid",
                    mu: number(rec, 4, h).map_err(at)?,
                    restitution: number(rec, 5, h).map_err(at)?,
                    sticks,
                    stick_mu: number(rec, 9, h).map_err(at)?,
                    spin: number(rec, 10, h).map_err(at)?,
                    note: Some(rec[11].to_string()).filter(|n| !n.is_empty()),
                });
            }
            o => {
                return Err(at(format!(
                    "item: `{o}` is not cell, end, corner_rigid or corner_body"
                )));
            }
        }
    }
    map_axes_of(&mut s, &cell_lines)?;
    Ok(StudyTable::Screen(Box::new(s)))
}

/// The map's axes from its cells, which must come row by row of skew over the same L/B.
fn map_axes_of(s: &mut ScreenStudy, lines: &[u64]) -> Result<(), (u64, String)> {
    let Some(first) = s.cells.first() else {
        let line = lines.first().copied().unwrap_or(2);
        return Err((line, "no map cells (item `cell`)".into()));
    };
    let skew0 = first.skew_deg.to_bits();
    s.l_over_b = (s.cells.iter())
        .take_while(|c| c.skew_deg.to_bits() == skew0)
        .map(|c| c.l_over_b)
        .collect();
    let nl = s.l_over_b.len();
    s.skew_deg = s.cells.iter().step_by(nl).map(|c| c.skew_deg).collect();
    for (k, c) in s.cells.iter().enumerate() {
        let (i, j) = (k % nl, k / nl);
        if c.l_over_b.to_bits() != s.l_over_b[i].to_bits()
            || c.skew_deg.to_bits() != s.skew_deg[j].to_bits()
        {
            return Err((
                lines[k],
                "the map's cells do not come row by row of skew over the same L/B".into(),
            ));
        }
    }
    if !s.cells.len().is_multiple_of(nl) {
        let line = lines[s.cells.len() - 1];
        return Err((line, "the map's last row of skew is not complete".into()));
    }
    Ok(())
}
