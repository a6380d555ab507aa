//! `deckspin fragility`: fragility curves of a record suite's per-run CSV (`design` module):
//! a table of θ, β and their bands per limit state, the runs per level, and
//! DIR/fragility.{csv,json,svg}.

use super::show;
use clap::Args;
use deckspin::design::fragility::{
    DEFAULT_BOOTSTRAP, Fragility, FragilityError, LevelCount, Method, Options, fragility,
    group_text,
};
use deckspin::design::{Suite, chart::chart};
use deckspin::model::limit_state::{self, LimitState};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::CliResult;

/// Fragility curves of a record suite.
#[derive(Args)]
pub struct FragilityArgs {
    /// The suite's per-run CSV (`deckspin suite`).
    pub suite: PathBuf,
    /// A limit state: COLUMN>NUMBER or COLUMN<NUMBER, e.g. peak_rotation>0.005 (repeatable).
    #[arg(long = "limit", value_name = "EXPR")]
    pub limits: Vec<String>,
    /// Also the [[limit_state]] tables (name, expression) of this model file.
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// Likelihood: multiple stripes (binomial counts per level) or IDA (censored capacities).
    #[arg(long, default_value = "stripes", value_parser = ["stripes", "ida"])]
    pub method: String,
    /// Bootstrap replicates over pairs for the 5–95 % band (0: no band).
    #[arg(long, default_value_t = DEFAULT_BOOTSTRAP)]
    pub bootstrap: usize,
    /// Seed of the bootstrap's generator (the same seed, the same band).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Output directory: fragility.csv (curve points and band), fragility.json, fragility.svg.
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
}

/// The limit states of `--limit` and of the model's `[[limit_state]]` tables.
fn limit_states(a: &FragilityArgs) -> Result<Vec<LimitState>, Box<dyn std::error::Error>> {
    let mut out = Vec::new();
    for t in &a.limits {
        out.push(LimitState::parse(t)?);
    }
    if let Some(m) = &a.model {
        out.extend(limit_state::read(m)?);
    }
    if out.is_empty() {
        return Err(
            "no limit state: give --limit EXPR (e.g. peak_rotation>0.005) or --model with \
             [[limit_state]] tables"
                .into(),
        );
    }
    Ok(out)
}

pub fn cmd_fragility(a: &FragilityArgs) -> CliResult {
    let limits = limit_states(a)?;
    let method =
        Method::parse(&a.method).ok_or_else(|| format!("unknown method '{}'", a.method))?;
    let opts = Options {
        method,
        bootstrap: a.bootstrap,
        seed: a.seed,
    };
    let suite = Suite::read(&a.suite)?;
    std::fs::create_dir_all(&a.out)?;
    // one job writes this folder at a time
    let _lock = deckspin::output::files::FolderLock::acquire(&a.out)?;
    let groups = suite.groups();
    let mut text = format!(
        "Fragility of {} ({} runs): {}, maximum likelihood; P(exceed | {} = x) = Φ(ln(x/θ)/β)\n",
        a.suite.display(),
        suite.runs.len(),
        method.title(),
        suite.measure
    );
    if opts.bootstrap > 0 {
        writeln!(
            text,
            "5–95 % bands: bootstrap over pairs, {} replicates, seed {}",
            opts.bootstrap, opts.seed
        )?;
    }
    let mut fits: Vec<Fragility> = Vec::new();
    let mut errors: Vec<FragilityError> = Vec::new();
    let mut wrote = Vec::new();
    for (k, group) in groups.iter().enumerate() {
        let mut here = Vec::new();
        let mut failed = Vec::new();
        for l in &limits {
            match fragility(&suite, group, l, &opts) {
                Ok(f) => here.push(f),
                Err(e @ FragilityError::Fit { .. }) => failed.push(e),
                Err(e) => return Err(e.into()),
            }
        }
        report(&mut text, group, &here, &failed)?;
        print!("{text}");
        text.clear();
        if !here.is_empty() {
            let name = if groups.len() == 1 {
                "fragility.svg".to_string()
            } else {
                format!("fragility-{}.svg", k + 1)
            };
            show::chart(&chart(&here, &suite.measure), &a.out.join(&name))?;
            wrote.push(name);
        }
        fits.extend(here);
        errors.extend(failed);
    }
    write_csv(&fits, &suite, &a.out.join("fragility.csv"))?;
    write_json(&fits, &errors, &suite, &opts, &a.out.join("fragility.json"))?;
    let mut files = vec!["fragility.csv".to_string(), "fragility.json".to_string()];
    files.extend(wrote);
    println!("wrote {}/{{{}}}", a.out.display(), files.join(","));
    if !errors.is_empty() {
        return Err(format!(
            "{} limit state(s) could not be fitted (see above)",
            errors.len()
        )
        .into());
    }
    Ok(())
}

/// "a–b" of a band's bounds.
fn range(b: [f64; 2], digits: usize) -> String {
    format!("{:.digits$}–{:.digits$}", b[0], b[1])
}

/// The table of one group: θ, β and bands per limit state, then the runs per level.
fn report(
    text: &mut String,
    group: &[(String, String)],
    fits: &[Fragility],
    failed: &[FragilityError],
) -> std::fmt::Result {
    if !group.is_empty() {
        writeln!(text, "\nat {}", group_text(group))?;
    }
    writeln!(
        text,
        "\n{:<28} {:>8} {:>7} {:>13} {:>15} {:>13} {:>7}",
        "limit state", "θ (g)", "β", "P(θ) 5–95 %", "θ 5–95 % (g)", "β 5–95 %", "records"
    )?;
    for f in fits {
        let (at, th, be) = f
            .band
            .as_ref()
            .map_or(("-".into(), "-".into(), "-".into()), |b| {
                (range(b.at_theta, 2), range(b.theta, 3), range(b.beta, 3))
            });
        writeln!(
            text,
            "{:<28} {:>8.4} {:>7.4} {at:>13} {th:>15} {be:>13} {:>7}",
            f.limit.name, f.fit.theta, f.fit.beta, f.records
        )?;
        if let Some(b) = &f.band
            && b.fitted < b.replicates
        {
            writeln!(
                text,
                "  ({} of {} bootstrap samples could not be fitted and are left out of the band)",
                b.replicates - b.fitted,
                b.replicates
            )?;
        }
    }
    for e in failed {
        writeln!(text, "{e}")?;
    }
    let tables: Vec<(&String, &Vec<LevelCount>)> = (fits.iter())
        .map(|f| (&f.limit.name, &f.levels))
        .chain(failed.iter().filter_map(|e| match e {
            FragilityError::Fit { limit, levels, .. } => Some((limit, levels)),
            _ => None,
        }))
        .collect();
    levels_table(text, &tables)
}

/// The runs per level: failed and refused runs, and per limit state the runs that exceed of
/// those in the likelihood, with the finished runs it does not apply to (n/a); failed,
/// refused and n/a runs are left out of the likelihood.
fn levels_table(text: &mut String, tables: &[(&String, &Vec<LevelCount>)]) -> std::fmt::Result {
    let Some((_, first)) = tables.first() else {
        return Ok(());
    };
    writeln!(
        text,
        "\nruns per level: exceeding / in the likelihood (failed, refused, n/a: left out)"
    )?;
    let widths: Vec<usize> = (tables.iter())
        .map(|(n, _)| n.chars().count().max(14))
        .collect();
    write!(text, "{:>9} {:>6} {:>7}", "level (g)", "failed", "refused")?;
    for ((name, _), w) in tables.iter().zip(&widths) {
        write!(text, "  {name:>w$}")?;
    }
    writeln!(text)?;
    for (i, l) in first.iter().enumerate() {
        write!(text, "{:>9} {:>6} {:>7}", l.level, l.failed, l.refused)?;
        for ((_, levels), w) in tables.iter().zip(&widths) {
            let Some(c) = levels.get(i) else { continue };
            let na = if c.not_applicable > 0 {
                format!(" n/a {}", c.not_applicable)
            } else {
                String::new()
            };
            write!(text, "  {:>w$}", format!("{}/{}{na}", c.exceed, c.runs))?;
        }
        writeln!(text)?;
    }
    Ok(())
}

/// The curve points and bands: one row per point.
fn write_csv(
    fits: &[Fragility],
    suite: &Suite,
    path: &Path,
) -> Result<(), Box<dyn std::error::Error>> {
    let mut w = csv::Writer::from_path(path)?;
    let mut head: Vec<String> = suite.params.clone();
    head.extend(
        [
            "limit_state",
            "expression",
            "method",
            "theta",
            "beta",
            "im",
            "p",
            "p05",
            "p95",
        ]
        .map(String::from),
    );
    w.write_record(&head)?;
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.6e}"));
    for f in fits {
        for p in &f.curve {
            let mut rec: Vec<String> = f.group.iter().map(|(_, v)| v.clone()).collect();
            rec.extend([
                f.limit.name.clone(),
                f.expression.clone(),
                a_method(f.method).into(),
                format!("{:.6e}", f.fit.theta),
                format!("{:.6e}", f.fit.beta),
                format!("{:.6e}", p.x),
                format!("{:.6e}", p.p),
                opt(p.lo),
                opt(p.hi),
            ]);
            w.write_record(&rec)?;
        }
    }
    w.flush()?;
    Ok(())
}

fn a_method(m: Method) -> &'static str {
    match m {
        Method::Stripes => "stripes",
        Method::Ida => "ida",
    }
}

/// Every fit (with its levels, band and curve) and every limit state that could not be fitted.
fn write_json(
    fits: &[Fragility],
    errors: &[FragilityError],
    suite: &Suite,
    opts: &Options,
    path: &Path,
) -> Result<(), Box<dyn std::error::Error>> {
    let errs: Vec<serde_json::Value> = (errors.iter())
        .map(|e| match e {
            FragilityError::Fit {
                limit,
                group,
                levels,
                source,
            } => serde_json::json!({
                "limit_state": limit, "group": group, "levels": levels, "error": source.to_string()
            }),
            e => serde_json::json!({ "error": e.to_string() }),
        })
        .collect();
    let doc = serde_json::json!({
        "suite": suite.path.display().to_string(),
        "measure": suite.measure,
        "method": a_method(opts.method),
        "bootstrap": opts.bootstrap,
        "seed": opts.seed,
        "curves": fits,
        "errors": errs,
    });
    deckspin::output::files::write_atomic(path, serde_json::to_string_pretty(&doc)? + "\n")?;
    Ok(())
}
