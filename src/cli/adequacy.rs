//! `deckspin adequacy`: the model ladder (library `design::adequacy`) — which simplifications
//! of a bridge model change its answers by less than a tolerance, and what each saves.

use super::progress::Bar;
use clap::Args;
use deckspin::design::adequacy::{Options, adequacy};
use deckspin::design::adequacy_report::{chart, runs_csv, table, variants_csv};
use deckspin::design::cases::Cases;
use deckspin::design::ladder::Simplification;
use deckspin::output::files::{FolderLock, write_atomic};
use deckspin::suite::DEFAULT_TAIL;
use deckspin::suite::intensity::{parse_levels, parse_measure};
use deckspin::suite::records::suite_pairs;
use std::path::{Component, Path, PathBuf};

/// Which simplifications of a bridge model are safe for its runs: every variant's error per
/// quantity against the full model and its cost; the cheapest within a tolerance.
#[derive(Args)]
pub struct AdequacyArgs {
    #[command(flatten)]
    pub model: super::args::ModelArgs,
    /// Run on a record suite instead of the model's [[run]]s: a folder of .AT2 pairs or a
    /// list file, as `deckspin suite --records`.
    #[arg(long)]
    pub records: Option<PathBuf>,
    /// With --records: the intensity measure (pga, sa:T, sa:T1).
    #[arg(long, default_value = "pga")]
    pub measure: String,
    /// With --records: the levels, g (a:b:step or v1,v2,…).
    #[arg(long, default_value = "1.0")]
    pub levels: String,
    /// With --records: free vibration after the longer record, s.
    #[arg(long, default_value_t = DEFAULT_TAIL)]
    pub tail: f64,
    /// The quantities to compare, comma-separated (default: every one that applies):
    /// peak_rotation, residual_rotation, peak_x, peak_y, min_seat_margin, key_failures,
    /// max_drift_ratio, impacts, energy_impacts, energy_friction, energy_columns.
    #[arg(long, value_delimiter = ',')]
    pub quantities: Vec<String>,
    /// The largest relative error of an adequate variant (0.05: 5 %).
    #[arg(long, default_value_t = 0.05)]
    pub tolerance: f64,
    /// Only these simplifications, comma-separated (default: all that apply): rigid-abutments,
    /// no-backfill, bilinear-columns, linear-columns, frictionless, plastic-impacts,
    /// no-contacts, translating-deck, no-keys, no-bearings, strong-motion, longitudinal-only.
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,
    /// The singles and the fixed combinations only: no search for the combination of every
    /// simplification within the tolerance.
    #[arg(long)]
    pub no_combine: bool,
    /// Folder of adequacy.csv, adequacy-runs.csv and adequacy.svg.
    #[arg(long, default_value = "out/adequacy")]
    pub out: PathBuf,
    /// Write the cheapest variant within the tolerance in every quantity as a copy of the
    /// model (comments kept, each change marked with why) to FILE.
    #[arg(long, value_name = "FILE")]
    pub write: Option<PathBuf>,
}

use super::CliResult;

pub fn cmd_adequacy(a: &AdequacyArgs) -> CliResult {
    let only = if a.only.is_empty() {
        None
    } else {
        let parsed = (a.only.iter())
            .map(|s| {
                Simplification::parse(s.trim()).ok_or_else(|| {
                    let names: Vec<&str> = Simplification::ALL.iter().map(|x| x.name()).collect();
                    format!("--only '{s}': not a simplification ({})", names.join(", "))
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Some(parsed)
    };
    let cases = match &a.records {
        None => Cases::ModelRuns,
        Some(dir) => {
            let (pairs, single) = suite_pairs(dir)?;
            for s in &single {
                eprintln!("deckspin: {}: no partner component, left out", s.display());
            }
            Cases::Suite {
                pairs,
                measure: parse_measure(&a.measure, None)?,
                levels: parse_levels(&a.levels)?,
                tail: a.tail,
            }
        }
    };
    let text = deckspin::input::read_bounded(&a.model.path, deckspin::input::MAX_MODEL_BYTES)
        .map_err(|e| format!("{}: {e}", a.model.path.display()))?;
    if let Some(w) = &a.write
        && same_file(w, &a.model.path)
    {
        return Err(format!(
            "--write {}: that is the model itself; choose another file (nothing written)",
            w.display()
        )
        .into());
    }
    std::fs::create_dir_all(&a.out)?;
    // one job writes this folder at a time
    let _lock = FolderLock::acquire(&a.out)?;
    let opts = Options {
        quantities: a.quantities.iter().map(|q| q.trim().to_string()).collect(),
        tolerance: a.tolerance,
        only,
        combine: !a.no_combine,
    };
    let bar = Bar::with_lines();
    let study = adequacy(&text, &a.model.path, &a.model.set, &cases, &opts, &bar)?;
    drop(bar);
    print!("{}", table(&study));
    write_atomic(a.out.join("adequacy.csv"), variants_csv(&study))?;
    write_atomic(a.out.join("adequacy-runs.csv"), runs_csv(&study))?;
    super::show::chart(&chart(&study, None), &a.out.join("adequacy.svg"))?;
    for q in &study.quantities {
        let (w, h) = super::show::SVG_SIZE;
        let svg = deckspin::plot::svg::render(&chart(&study, Some(q)), w, h);
        write_atomic(a.out.join(format!("adequacy-{q}.svg")), svg)?;
    }
    println!(
        "\nwrote {0}/adequacy.csv, {0}/adequacy-runs.csv, {0}/adequacy.svg (the largest error), {0}/adequacy-QUANTITY.svg (each quantity)",
        a.out.display()
    );
    if let Some(w) = &a.write {
        write_reduced(a, &study, &text, w)?;
    }
    Ok(())
}

/// The cheapest variant within the tolerance in every quantity, written to `to` as an edited
/// copy of the model (its record paths made relative to `to`'s folder), then read back.
fn write_reduced(
    a: &AdequacyArgs,
    study: &deckspin::design::adequacy::Adequacy,
    text: &str,
    to: &Path,
) -> CliResult {
    let Some(v) = study.cheapest(None) else {
        println!(
            "--write: no variant is within {} % in every quantity and cheaper than the full model: nothing written",
            100.0 * study.tolerance
        );
        return Ok(());
    };
    let variant = &study.variants[v].variant;
    let mut reduced = variant.text(text, true)?;
    reduced = rebase_records(&reduced, &a.model.path, to)?;
    let head = format!(
        "# Reduced by `deckspin adequacy` from {}: {} (within {} % of the full model in {} over {} runs).\n",
        a.model.path.display(),
        variant.name,
        100.0 * study.tolerance,
        study.quantities.join(", "),
        study.cases.len()
    );
    if let Some(dir) = to.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    write_atomic(to, format!("{head}{reduced}"))?;
    deckspin::model::load(to, &[])
        .map_err(|e| format!("--write: the reduced model does not load: {e}"))?;
    println!("wrote {} ({})", to.display(), variant.name);
    Ok(())
}

/// Whether `a` and `b` name one file (both existing).
fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// The record paths of `text` (relative to `from`'s folder) made relative to `to`'s folder.
fn rebase_records(
    text: &str,
    from: &Path,
    to: &Path,
) -> Result<String, Box<dyn std::error::Error>> {
    let folder = |p: &Path| -> std::io::Result<PathBuf> {
        let d = p.parent().filter(|d| !d.as_os_str().is_empty());
        let d = d.unwrap_or(Path::new("."));
        std::fs::create_dir_all(d)?;
        d.canonicalize()
    };
    let (src, dst) = (folder(from)?, folder(to)?);
    if src == dst {
        return Ok(text.to_string());
    }
    let mut doc: toml_edit::DocumentMut = text.parse()?;
    if let Some(e) = doc
        .get_mut("excitation")
        .and_then(|e| e.as_table_like_mut())
    {
        for key in ["longitudinal", "transverse"] {
            let Some(rel) = e.get(key).and_then(|v| v.as_str()).map(PathBuf::from) else {
                continue;
            };
            if rel.is_absolute() {
                continue;
            }
            let abs = src.join(&rel);
            let abs = abs.canonicalize().unwrap_or(abs);
            let new = relative(&abs, &dst).display().to_string();
            if let Some(toml_edit::Item::Value(v)) = e.get_mut(key) {
                let decor = v.decor().clone();
                *v = toml_edit::Value::from(new);
                *v.decor_mut() = decor;
            }
        }
    }
    Ok(doc.to_string())
}

/// `path` relative to the folder `base` (both absolute).
fn relative(path: &Path, base: &Path) -> PathBuf {
    let p: Vec<Component> = path.components().collect();
    let b: Vec<Component> = base.components().collect();
    let common = p.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut out = PathBuf::new();
    for _ in common..b.len() {
        out.push("..");
    }
    for c in &p[common..] {
        out.push(c.as_os_str());
    }
    out
}
