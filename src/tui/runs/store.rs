//! The run list on disk: `<model stem>.runs/` beside the model, three files per run `N`
//! (`0007.json` its number, name, baseline flag, status and key results; `0007.toml` the model
//! text it ran; `0007.csv` its thinned series), each written atomically (a temporary file in
//! the folder, then renamed). Read back when the workbench opens the model again; a file that
//! is not a run's, or does not read, is named in the report and skipped. Opening reads the
//! metadata and the model texts only (what the list, the diffs and the reuse of a run with the
//! same model text need); a run's series is read when it is shown or overlaid
//! ([`load_series`]). A run is deleted by renaming its metadata away first (`.0007.json.deleting`:
//! from then on it is not listed), then removing its other files and that one; a deletion cut
//! short is finished at the next opening.

use crate::output::series::read_columns;
use crate::tui::runs::data::{RunData, RunStatus, fresh_token};
use crate::tui::runs::export::series_csv;
use crate::tui::runs::list::{Change, Ended, Entry, KEEP, Results, Runs, Series};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The time charts' preferences, kept in the same folder ([`crate::tui::chart_prefs`]): not a
/// run's file.
pub const CHARTS_FILE: &str = "charts.json";

/// The first line of every metadata file's `format` field.
const FORMAT: &str = "deckspin run list 1";

/// `models/four-span.runs` for `models/four-span.toml`.
pub fn runs_dir(model: &Path) -> PathBuf {
    let stem = model
        .file_stem()
        .map_or("model".into(), |s| s.to_string_lossy().into_owned());
    let name = format!("{stem}.runs");
    match model.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.join(name),
        _ => PathBuf::from(name),
    }
}

#[derive(Serialize, Deserialize)]
struct Meta {
    format: String,
    number: u64,
    name: String,
    named: bool,
    baseline: bool,
    ended: Ended,
    t_end: f64,
    results: Results,
    /// Its model diff against the baseline's model text of this hash (`run_list::text_hash`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    diff: Option<Diff>,
}

#[derive(Serialize, Deserialize)]
struct Diff {
    base: String,
    changes: Vec<Change>,
}

fn stem(n: u64) -> String {
    format!("{n:04}")
}

/// What to write of a run: its metadata, and with `full` its model text and series.
#[derive(Clone, Debug)]
pub struct Job {
    pub entry: Box<Entry>,
    pub baseline: bool,
    pub full: bool,
}

/// The metadata file of a run.
pub fn meta_text(e: &Entry, baseline: bool) -> String {
    let m = Meta {
        format: FORMAT.into(),
        number: e.number,
        name: e.name.clone(),
        named: e.named,
        baseline,
        ended: e.ended.clone(),
        t_end: e.data.t_end,
        results: e.results.clone(),
        diff: e.diff_base.map(|h| Diff {
            base: format!("{h:016x}"),
            changes: e.changes.clone(),
        }),
    };
    serde_json::to_string_pretty(&m).unwrap_or_default() + "\n"
}

/// The series file: the run's columns by the names of `history.csv`
/// ([`crate::tui::runs::export::series_columns`], [`series_csv`]), the time exactly and the rest in single
/// precision ([`crate::output::series`]).
pub fn series_text(d: &RunData) -> String {
    series_csv(d, true)
}

/// Writes `text` to `path` as one transaction ([`crate::output::files::write_atomic`]: a new
/// temporary file beside it, flushed, renamed over), the error naming the path.
pub fn write_atomic(path: &Path, text: &str) -> Result<(), String> {
    crate::output::files::write_atomic(path, text).map_err(|e| format!("{}: {e}", path.display()))
}

/// Writes the jobs' files into `dir` (created if need be) and removes the files of the runs
/// `remove`.
pub fn store(dir: &Path, jobs: &[Job], remove: &[u64]) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for j in jobs {
        let s = stem(j.entry.number);
        if j.full {
            write_atomic(&dir.join(format!("{s}.toml")), &j.entry.model)?;
            write_atomic(&dir.join(format!("{s}.csv")), &series_text(&j.entry.data))?;
        }
        // the metadata last: a run is listed once its other files are there
        write_atomic(
            &dir.join(format!("{s}.json")),
            &meta_text(&j.entry, j.baseline),
        )?;
    }
    for n in remove {
        delete(dir, *n)?;
    }
    Ok(())
}

/// The marker of run `n` being deleted: its metadata renamed away.
fn deleting(dir: &Path, n: u64) -> PathBuf {
    dir.join(format!(".{}.json.deleting", stem(n)))
}

/// Deletes run `n`'s files: its metadata renamed away first (the run is no longer listed),
/// then its model and series, then the metadata. A missing file is no error.
pub fn delete(dir: &Path, n: u64) -> Result<(), String> {
    let gone = |p: &Path, r: std::io::Result<()>| match r {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(format!("{}: {e}", p.display())),
        _ => Ok(()),
    };
    let meta = dir.join(format!("{}.json", stem(n)));
    let mark = deleting(dir, n);
    gone(&meta, std::fs::rename(&meta, &mark))?;
    for ext in ["csv", "toml"] {
        let p = dir.join(format!("{}.{ext}", stem(n)));
        gone(&p, std::fs::remove_file(&p))?;
    }
    gone(&mark, std::fs::remove_file(&mark))
}

/// What opening the store read: files and bytes (the metadata and the model texts; no
/// series).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReadCount {
    pub files: usize,
    pub bytes: usize,
}

/// The runs read back: the list (newest [`KEEP`] and the baseline), the numbers of older
/// runs left on disk, and what was skipped (`file: why`).
pub struct Loaded {
    pub runs: Runs,
    pub older: Vec<u64>,
    pub skipped: Vec<String>,
    pub read: ReadCount,
    /// The runs whose diff against the baseline was not stored with them (computed here; their
    /// metadata to store again).
    pub rediffed: Vec<u64>,
}

/// Reads the series of run `n` (`t_end` from its metadata) from `dir`.
pub fn load_series(dir: &Path, n: u64, t_end: f64) -> Result<RunData, String> {
    let name = format!("{}.csv", stem(n));
    let text = std::fs::read_to_string(dir.join(&name)).map_err(|e| format!("{name}: {e}"))?;
    let mut d = read_series(&text, n, t_end).map_err(|e| format!("{name}: {e}"))?;
    d.token = fresh_token();
    Ok(d)
}

/// A column name of a series file as `history.csv` names it; the names of the workbench's
/// first layout (`q:<dof>`, `gap:<contact>`, `def:<element>`, `force:<element>`) read too.
fn history_name(h: &str) -> String {
    if let Some(d) = h.strip_prefix("q:") {
        d.to_string()
    } else if let Some(c) = h.strip_prefix("gap:") {
        format!("{c}.gap")
    } else if let Some(e) = h.strip_prefix("def:") {
        format!("{e}.deformation")
    } else if let Some(e) = h.strip_prefix("force:") {
        format!("{e}.force")
    } else {
        h.to_string()
    }
}

/// Reads the series file of run `n`: `t`, then the DOFs, the gaps (`<contact>.gap`) and each
/// element's deformation and force (`<element>.deformation`, `<element>.force`, in pairs).
fn read_series(text: &str, n: u64, t_end: f64) -> Result<RunData, String> {
    let mut cols = read_columns(text).map_err(|e| e.to_string())?.into_iter();
    let (_, t) = cols.next().ok_or("no columns")?;
    let (mut dofs, mut contacts, mut elements) = (Vec::new(), Vec::new(), Vec::new());
    let (mut q, mut gap, mut el) = (Vec::new(), Vec::new(), Vec::new());
    while let Some((h, values)) = cols.next() {
        let h = history_name(&h);
        if let Some(c) = h.strip_suffix(".gap") {
            contacts.push(c.to_string());
            gap.push(values);
        } else if let Some(e) = h.strip_suffix(".deformation") {
            let (force, f) = cols.next().ok_or(format!("{h} without its force"))?;
            if history_name(&force) != format!("{e}.force") {
                return Err(format!("{h} is followed by {force}, not {e}.force"));
            }
            elements.push(e.to_string());
            el.push((values, f));
        } else if !contacts.is_empty() || !elements.is_empty() {
            return Err(format!("{h}: a DOF after the gaps and elements"));
        } else {
            dofs.push(h);
            q.push(values);
        }
    }
    let mut d = RunData::new(n, format!("#{n}"), dofs, contacts, elements, t_end);
    d.t = t;
    d.q = q;
    d.gap = gap;
    for (j, (a, b)) in el.into_iter().enumerate() {
        let (x, y) = (&a, &b);
        let finite = x
            .iter()
            .zip(y)
            .filter(|(x, y)| x.is_finite() && y.is_finite());
        d.el_range[j] = finite.fold(d.el_range[j], |e, (&x, &y)| {
            [e[0].min(x), e[1].max(x), e[2].min(y), e[3].max(y)]
        });
        d.el[j] = (a, b);
    }
    d.state = vec![Vec::new(); d.gap.len()];
    Ok(d)
}

/// Reads run `n`'s metadata and model text (its series stays on disk, [`Series::OnDisk`]).
fn read_run(dir: &Path, n: u64, count: &mut ReadCount) -> Result<(Entry, bool), String> {
    let s = stem(n);
    let mut read = |ext: &str| {
        let p = dir.join(format!("{s}.{ext}"));
        let text = std::fs::read_to_string(&p).map_err(|e| format!("{s}.{ext}: {e}"))?;
        count.files += 1;
        count.bytes += text.len();
        Ok::<_, String>(text)
    };
    let meta: Meta = serde_json::from_str(&read("json")?).map_err(|e| format!("{s}.json: {e}"))?;
    if meta.format != FORMAT || meta.number != n {
        return Err(format!("{s}.json: not the metadata of run #{n}"));
    }
    let model = read("toml")?;
    if !dir.join(format!("{s}.csv")).is_file() {
        return Err(format!("{s}.csv: missing"));
    }
    let mut data = RunData::new(n, format!("#{n}"), vec![], vec![], vec![], meta.t_end);
    data.token = fresh_token();
    stored_status(&mut data, &meta.ended, meta.results.t_sim);
    let (diff_base, changes) = match meta.diff {
        Some(d) => (u64::from_str_radix(&d.base, 16).ok(), d.changes),
        None => (None, Vec::new()),
    };
    let e = Entry {
        number: n,
        name: meta.name,
        named: meta.named,
        model,
        ended: meta.ended,
        results: meta.results,
        data,
        overlay: false,
        changes,
        diff_base,
        series: Series::OnDisk,
    };
    Ok((e, meta.baseline))
}

/// The status and time reached of a stored run's data: how it ended is the entry's `ended`
/// (with a failure's reason); the data only says whether it ran to the end.
pub fn stored_status(data: &mut RunData, ended: &Ended, t_sim: f64) {
    data.t_sim = t_sim;
    data.status = match ended {
        Ended::Finished | Ended::Inaccurate(_) => RunStatus::Finished,
        _ => RunStatus::Cancelled,
    };
}

/// Reads the runs stored in `dir` (none when it does not exist).
pub fn load(dir: &Path) -> Loaded {
    let mut skipped = Vec::new();
    let mut read = ReadCount::default();
    let mut marks = Vec::new();
    let mut numbers: BTreeMap<u64, Vec<String>> = BTreeMap::new();
    if let Ok(entries) = std::fs::read_dir(dir) {
        for f in entries.flatten() {
            let name = f.file_name().to_string_lossy().into_owned();
            if let Some(n) = (name.strip_prefix('.'))
                .and_then(|r| r.strip_suffix(".json.deleting"))
                .and_then(|n| n.parse::<u64>().ok())
            {
                marks.push(n);
            }
            if name.starts_with('.') || name == CHARTS_FILE {
                continue;
            }
            let parsed = name.rsplit_once('.').and_then(|(n, ext)| {
                let ok = ["json", "toml", "csv"].contains(&ext) && !n.is_empty();
                n.parse::<u64>().ok().filter(|_| ok).map(|n| (n, ext))
            });
            match parsed {
                Some((n, ext)) => numbers.entry(n).or_default().push(ext.to_string()),
                None => skipped.push(format!("{name}: not a run's file")),
            }
        }
    }
    // a deletion cut short: finished (unless a run of that number was stored since)
    for n in marks {
        if numbers
            .get(&n)
            .is_some_and(|e| e.iter().any(|x| x == "json"))
        {
            let _ = std::fs::remove_file(deleting(dir, n));
        } else if delete(dir, n).is_ok() {
            numbers.remove(&n);
        }
    }
    let mut list = Vec::new();
    let mut baseline = None;
    for (&n, exts) in &numbers {
        if !exts.iter().any(|e| e == "json") {
            skipped.push(format!("{}.{}: no {}.json", stem(n), exts[0], stem(n)));
            continue;
        }
        match read_run(dir, n, &mut read) {
            Ok((e, b)) => {
                if b {
                    baseline = Some(n);
                }
                list.push(e);
            }
            Err(e) => skipped.push(e),
        }
    }
    let mut runs = Runs {
        list,
        dir: Some(dir.to_path_buf()),
        ..Runs::default()
    };
    let rediffed = baseline.map_or_else(Vec::new, |b| runs.pin(b));
    let older = runs.bound();
    debug_assert!(runs.list.len() <= KEEP + 1);
    runs.selected = runs.list.len().saturating_sub(1);
    Loaded {
        runs,
        older,
        skipped,
        read,
        rediffed,
    }
}
