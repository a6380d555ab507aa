//! The stress test of real records: a bridge model under every record pair of a folder, at
//! each of its runs (target PGAs), restitution, friction and column law, each run to the end of
//! its longer record plus a free-vibration tail. Every run must finish with no penetration
//! above 1e-9 m and an energy closure within rtol/10.

use crate::model::ModelError;
use crate::progress::{Progress, Unwatched};
use crate::run::Stop;
use crate::scene::Motion;
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A record pair: longitudinal and transverse components of one station.
#[derive(Clone, Debug, PartialEq)]
pub struct RecordPair {
    pub name: String,
    pub longitudinal: PathBuf,
    pub transverse: PathBuf,
}

/// The `.AT2` files of `dir` in pairs: sorted by name, two consecutive files of one station
/// (their names equal but for the last 3 characters of the stem) make a pair; the first is
/// the longitudinal component. Files without a partner are returned apart.
pub fn record_pairs(dir: &Path) -> std::io::Result<(Vec<RecordPair>, Vec<PathBuf>)> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("at2")))
        .collect();
    files.sort();
    let stem = |p: &Path| {
        p.file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .to_string()
    };
    let station = |s: &str| s[..s.len().saturating_sub(3)].to_string();
    let (mut pairs, mut single) = (Vec::new(), Vec::new());
    let mut i = 0;
    while i < files.len() {
        let a = stem(&files[i]);
        match files.get(i + 1) {
            Some(b) if station(&stem(b)) == station(&a) => {
                pairs.push(RecordPair {
                    name: station(&a).trim_end_matches(['_', '-']).to_string(),
                    longitudinal: files[i].clone(),
                    transverse: b.clone(),
                });
                i += 2;
            }
            _ => {
                single.push(files[i].clone());
                i += 1;
            }
        }
    }
    Ok((pairs, single))
}

/// The grid of a stress test.
#[derive(Clone, Debug)]
pub struct StressGrid {
    /// Indices of the model's `[[run]]` table (1-based, as `excitation.run`); empty: every
    /// run of the table.
    pub runs: Vec<usize>,
    pub restitution: Vec<f64>,
    pub mu: Vec<f64>,
    /// Column laws: "takeda" (the model's) and/or "bilinear" (its backbone without the
    /// Takeda unloading rules).
    pub laws: Vec<String>,
    /// Free vibration after the end of the longer record, s.
    pub tail: f64,
}

impl Default for StressGrid {
    fn default() -> Self {
        Self {
            runs: Vec::new(),
            restitution: vec![0.0, 0.5, 1.0],
            mu: vec![0.1, 0.5, 1.0],
            laws: vec!["takeda".into(), "bilinear".into()],
            tail: 2.0,
        }
    }
}

/// A stress test refused before any run.
#[derive(Debug, thiserror::Error)]
pub enum StressError {
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A run asked for that the model's `[[run]]` table does not have (`count` runs).
    #[error("--runs: {}: no run {run} ({})", path.display(), match count {
        0 => "the model has no [[run]] table".to_string(),
        n => format!("its [[run]] table has 1..={n}"),
    })]
    NoRun {
        path: PathBuf,
        run: usize,
        count: usize,
    },
}

/// The largest pull a stress run may show, relative to its largest normal force.
pub(crate) const PULL_TOL: f64 = 1e-9;

/// One run of a stress test.
#[derive(Clone, Debug)]
pub struct StressRow {
    pub record: String,
    pub run: usize,
    pub restitution: f64,
    pub mu: f64,
    pub law: String,
    pub t_end: f64,
    /// "finished", "failed: <error>" or "refused: <model error>".
    pub status: String,
    pub max_penetration: f64,
    pub closure_rel: f64,
    pub rtol: f64,
    /// Contacts an impact left approaching (`stats.approaching_after_impact`): must be 0.
    pub approaching: usize,
    /// The largest pull of a contact at a sample relative to the largest normal force
    /// (`max_pull`, [`crate::output::Summary`]): a unilateral contact never pulls.
    pub pull_rel: f64,
    pub wall: f64,
    /// CPU seconds of the run's thread (waiting for a core not counted).
    pub cpu: f64,
}

impl StressRow {
    /// Finished, no penetration above 1e-9 m, energy closure within rtol/10, no contact left
    /// approaching by an impact, no pull above 1e-9 of the largest normal force.
    pub fn passes(&self) -> bool {
        self.status == "finished"
            && self.max_penetration <= 1e-9
            && self.closure_rel <= self.rtol / 10.0
            && self.approaching == 0
            && self.pull_rel <= PULL_TOL
    }
}

/// The model text with its column law replaced by the bilinear law of the same backbone (the
/// Takeda parameters other than stiffness, yield force and post-yield ratio dropped).
fn bilinear_text(text: &str) -> Result<String, String> {
    let mut doc: toml_edit::DocumentMut = text.parse().map_err(|e| format!("{e}"))?;
    let law = doc
        .get_mut("column")
        .and_then(|c| c.get_mut("law"))
        .and_then(|l| l.as_inline_table_mut())
        .ok_or("the model has no inline [column] law")?;
    let keep = ["stiffness", "yield_force", "post_yield_ratio"];
    let mut out = toml_edit::InlineTable::new();
    out.insert("law", "bilinear".into());
    for k in keep {
        if let Some(v) = law.get(k) {
            out.insert(k, v.clone());
        }
    }
    *law = out;
    Ok(doc.to_string())
}

/// The longest support record of a scene ends at this time (0 without records).
fn records_end(scene: &crate::scene::Scene) -> f64 {
    (scene.supports.iter())
        .filter_map(|s| match &s.motion {
            Motion::Record(g) => Some(g.end_time()),
            Motion::Harmonic { .. } => None,
        })
        .fold(0.0, f64::max)
}

/// One stress run: the model under `pair` with the grid point's settings.
fn stress_run(
    text: &str,
    path: &Path,
    pair: &RecordPair,
    (run, eps, mu, law): (usize, f64, f64, &str),
    tail: f64,
) -> StressRow {
    let wall = Instant::now();
    let cpu0 = crate::clock::thread_cpu_seconds();
    let mut row = StressRow {
        record: pair.name.clone(),
        run,
        restitution: eps,
        mu,
        law: law.to_string(),
        t_end: 0.0,
        status: String::new(),
        max_penetration: 0.0,
        closure_rel: 0.0,
        rtol: 0.0,
        approaching: 0,
        pull_rel: 0.0,
        wall: 0.0,
        cpu: 0.0,
    };
    let mut set = vec![
        format!(
            "excitation.longitudinal=\"{}\"",
            pair.longitudinal.display()
        ),
        format!("excitation.transverse=\"{}\"", pair.transverse.display()),
        format!("excitation.run={run}"),
        format!("contacts.restitution={eps}"),
        format!("contacts.mu={mu}"),
    ];
    let load = |set: &[String]| -> Result<crate::scene::Scene, ModelError> {
        crate::model::load_str(text, path, set)
    };
    let scene = load(&set).and_then(|s| {
        // to the end of the longer record plus the tail
        set.push(format!("solver.t_end={}", records_end(&s) + tail));
        let mut s = load(&set)?;
        s.settings.keep_history = false;
        Ok(s)
    });
    match scene {
        Err(e) => row.status = format!("refused: {e}"),
        Ok(scene) => {
            row.t_end = scene.settings.t_end;
            row.rtol = scene.settings.rtol;
            let r = crate::simulate::integrate(&scene, &mut crate::Silent);
            row.max_penetration = r.output.summary.max_penetration;
            row.closure_rel = r.output.summary.energy_closure_rel;
            row.approaching = r.output.summary.stats.approaching_after_impact;
            let contacts = &r.output.summary.contacts;
            let scale = (contacts.iter())
                .map(|c| c.max_normal_force.max(-c.min_normal_force))
                .fold(0.0f64, f64::max);
            let pull = r.output.summary.max_pull;
            row.pull_rel = if pull > 0.0 { pull / scale } else { 0.0 };
            row.status = match r.stop {
                Stop::Finished => "finished".into(),
                Stop::Cancelled { t } => format!("cancelled at {t}"),
                Stop::Failed(e) => format!("failed: {e}"),
            };
        }
    }
    row.wall = wall.elapsed().as_secs_f64();
    row.cpu = crate::clock::thread_cpu_seconds() - cpu0;
    row
}

/// Every record pair × run × ε × μ × column law of `grid` on the bridge model at `path`, in
/// parallel.
pub fn stress(
    path: &Path,
    pairs: &[RecordPair],
    grid: &StressGrid,
) -> Result<Vec<StressRow>, StressError> {
    stress_watched(path, pairs, grid, &Unwatched)
}

/// [`stress`], `progress` told of each run as it is done.
pub(crate) fn stress_watched(
    path: &Path,
    pairs: &[RecordPair],
    grid: &StressGrid,
    progress: &dyn Progress,
) -> Result<Vec<StressRow>, StressError> {
    let rows = stress_listed(path, pairs, grid, &|_| false, progress, &|_, _| {})?;
    Ok(rows.into_iter().map(|(_, r)| r).collect())
}

/// [`stress_watched`] without the runs `skip` names (by index in the grid's order: pair, run,
/// ε, μ, law, the last varying fastest), `each` handed every row as it finishes; once
/// [`Progress::go_on`] says no, the runs not started are left out. The rows by index, in order.
pub fn stress_listed(
    path: &Path,
    pairs: &[RecordPair],
    grid: &StressGrid,
    skip: &(dyn Fn(usize) -> bool + Sync),
    progress: &dyn Progress,
    each: &(dyn Fn(usize, &StressRow) + Sync),
) -> Result<Vec<(usize, StressRow)>, StressError> {
    let text = crate::input::read_bounded(path, crate::input::MAX_MODEL_BYTES).map_err(|e| {
        ModelError::Io {
            path: path.to_path_buf(),
            source: e,
        }
    })?;
    let count = crate::studies::run_count(&text);
    let runs: Vec<usize> = if grid.runs.is_empty() {
        (1..=count).collect()
    } else {
        grid.runs.clone()
    };
    // a model without a [[run]] table has not even run 1
    let missing = if runs.is_empty() {
        Some(1)
    } else {
        runs.iter().copied().find(|&r| r == 0 || r > count)
    };
    if let Some(run) = missing {
        return Err(StressError::NoRun {
            path: path.to_path_buf(),
            run,
            count,
        });
    }
    let bilinear = bilinear_text(&text).unwrap_or_else(|_| text.clone());
    let mut jobs = Vec::new();
    for pair in pairs {
        for &run in &runs {
            for &eps in &grid.restitution {
                for &mu in &grid.mu {
                    for law in &grid.laws {
                        jobs.push((pair, run, eps, mu, law.as_str()));
                    }
                }
            }
        }
    }
    let todo: Vec<usize> = (0..jobs.len()).filter(|&i| !skip(i)).collect();
    progress.plan(todo.len());
    Ok(todo
        .par_iter()
        .filter_map(|&i| {
            // once told to stop, the runs not started are left for a resume
            if !progress.go_on() {
                return None;
            }
            let (pair, run, eps, mu, law) = jobs[i];
            let text = if law == "bilinear" { &bilinear } else { &text };
            let row = stress_run(text, path, pair, (run, eps, mu, law), grid.tail);
            progress.done(1);
            each(i, &row);
            Some((i, row))
        })
        .collect())
}

/// The number of runs of a stress test of `pairs` on a model of `run_count` runs.
pub fn stress_size(pairs: usize, run_count: usize, grid: &StressGrid) -> usize {
    let runs = if grid.runs.is_empty() {
        run_count
    } else {
        grid.runs.len()
    };
    pairs * runs * grid.restitution.len() * grid.mu.len() * grid.laws.len()
}

/// The CSV header of a stress test's rows.
pub const CSV_HEADER: &str = "record,run,restitution,mu,law,t_end,status,max_penetration,closure_rel,rtol,approaching_after_impact,pull_rel,wall_s,cpu_s";

/// A stress row's CSV line (with its line break), [`CSV_HEADER`]'s columns; its numbers read
/// back exactly ([`StressRow::from_csv`]) but for the times, given to 0.1 ms.
pub fn csv_line(r: &StressRow) -> String {
    format!(
        "{},{},{},{},{},{},\"{}\",{:e},{:e},{:e},{},{:e},{:.4},{:.4}\n",
        crate::shard::csv_line(&[&r.record]).trim_end(),
        r.run,
        r.restitution,
        r.mu,
        crate::shard::csv_line(&[&r.law]).trim_end(),
        r.t_end,
        r.status.replace('"', "'").replace(['\n', '\r'], " "),
        r.max_penetration,
        r.closure_rel,
        r.rtol,
        r.approaching,
        r.pull_rel,
        r.wall,
        r.cpu
    )
}

impl StressRow {
    /// A row read back from its CSV line ([`csv_line`]).
    pub fn from_csv(line: &str) -> Result<StressRow, String> {
        let fields = crate::shard::csv_fields_of(line)?;
        let f: Vec<&str> = fields.iter().map(String::as_str).collect();
        let columns = CSV_HEADER.split(',').count();
        if f.len() != columns {
            return Err(format!("{} fields, a stress row has {columns}", f.len()));
        }
        let num = |k: usize| -> Result<f64, String> {
            (f[k].parse::<f64>())
                .map_err(|_| format!("field {}: '{}' is not a number", k + 1, f[k]))
        };
        let whole = |k: usize| -> Result<usize, String> {
            (f[k].parse::<usize>())
                .map_err(|_| format!("field {}: '{}' is not a whole number", k + 1, f[k]))
        };
        Ok(StressRow {
            record: f[0].into(),
            run: whole(1)?,
            restitution: num(2)?,
            mu: num(3)?,
            law: f[4].into(),
            t_end: num(5)?,
            status: f[6].into(),
            max_penetration: num(7)?,
            closure_rel: num(8)?,
            rtol: num(9)?,
            approaching: whole(10)?,
            pull_rel: num(11)?,
            wall: num(12)?,
            cpu: num(13)?,
        })
    }
}

/// The tally of a stress test: runs, finished, passing, the failures by reason, the worst
/// penetration, the worst closure relative to rtol and the slowest run.
pub fn tally(rows: &[StressRow]) -> String {
    let finished = rows.iter().filter(|r| r.status == "finished").count();
    let passing = rows.iter().filter(|r| r.passes()).count();
    let worst = |f: &dyn Fn(&StressRow) -> f64| {
        rows.iter()
            .max_by(|a, b| f(a).total_cmp(&f(b)))
            .map(|r| (f(r), r))
    };
    let label = |r: &StressRow| {
        format!(
            "{} run {} ε {} μ {} {}",
            r.record, r.run, r.restitution, r.mu, r.law
        )
    };
    let mut out = format!(
        "{} runs: {finished} finished, {passing} pass (penetration ≤ 1e-9 m, closure ≤ rtol/10, no contact left approaching by an impact, no pull above 1e-9 of the largest normal force)\n",
        rows.len()
    );
    let approaching: usize = rows.iter().map(|r| r.approaching).sum();
    out += &format!("contacts left approaching by an impact: {approaching}\n");
    for r in rows.iter().filter(|r| !r.passes()) {
        out += &format!(
            "  {}: {} (penetration {:.3e} m, closure {:.3e}, left approaching {}, pull {:.3e})\n",
            label(r),
            r.status,
            r.max_penetration,
            r.closure_rel,
            r.approaching,
            r.pull_rel
        );
    }
    if let Some((p, r)) = worst(&|r| r.max_penetration) {
        out += &format!("worst penetration {p:.3e} m ({})\n", label(r));
    }
    if let Some((p, r)) = worst(&|r| r.pull_rel) {
        out += &format!(
            "worst pull {p:.3e} of the largest normal force ({})\n",
            label(r)
        );
    }
    if let Some((c, r)) = worst(&|r| r.closure_rel / r.rtol.max(1e-300)) {
        out += &format!(
            "worst closure {:.3e} = {c:.3} rtol ({})\n",
            c * r.rtol,
            label(r)
        );
    }
    if let Some((w, r)) = worst(&|r| r.wall) {
        out += &format!("slowest {w:.2} s ({}, t_end {:.1} s)\n", label(r), r.t_end);
    }
    // the CPU time of the runs' threads, not a sum of their wall times
    let cpu: f64 = rows.iter().map(|r| r.cpu).sum();
    out += &format!("CPU {cpu:.1} s in all\n");
    out
}
