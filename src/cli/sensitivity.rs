//! `deckspin sensitivity`: which uncertain inputs the answer is most sensitive to (library
//! `design::sensitivity`), or a shard of its runs.

use super::jobs::{Recorder, counted, joined, stop_if_signalled};
use super::progress::Bar;
use clap::Args;
use deckspin::design::cases::Cases;
use deckspin::design::sensitivity::{Choice, Study, job_arguments};
use deckspin::design::swings::{Sensitivity, read_runs, run_fields, runs_header, summarize, table};
use deckspin::output::files::{FolderLock, write_atomic};
use deckspin::shard::journal::Journal;
use deckspin::shard::{JobId, Shard, csv_line, part_text};
use deckspin::suite::DEFAULT_TAIL;
use deckspin::suite::intensity::{parse_levels, parse_measure};
use deckspin::suite::records::{SuitePair, suite_pairs};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::CliResult;

/// Which uncertain inputs the answer is most sensitive to: each at its low and high value.
#[derive(Args)]
pub struct SensitivityArgs {
    pub model: PathBuf,
    /// Keep only these inputs, by name (comma-separated; default: the model's [[uncertain]]
    /// tables, or when it has none the defaults of docs/sensitivity.md).
    #[arg(long, value_delimiter = ',')]
    pub inputs: Option<Vec<String>>,
    /// Add an input: KEY=LOW:HIGH, or KEY=xLOW:xHIGH for factors on the model's value
    /// (repeatable; KEY a --set path, several joined by +).
    #[arg(long = "add", value_name = "KEY=LOW:HIGH")]
    pub add: Vec<String>,
    /// Quantities, comma-separated (the suite's metrics; the first sorts the table).
    #[arg(long, value_delimiter = ',')]
    pub quantities: Option<Vec<String>>,
    /// Fixed overrides applied to every run before the inputs' values.
    #[arg(long = "fix", value_name = "KEY=VALUE")]
    pub fix: Vec<String>,
    /// Cases from a record suite (a folder of .AT2 records or a list file, as `suite`) instead
    /// of the model's [[run]]s: every pair at every level of --measure.
    #[arg(long, requires_all = ["measure", "levels"])]
    pub records: Option<PathBuf>,
    /// With --records: pga, sa:T or sa:T1.
    #[arg(long, requires = "records")]
    pub measure: Option<String>,
    /// With --records: the damping ratio of Sa (default 0.05).
    #[arg(long, requires = "records")]
    pub damping: Option<f64>,
    /// With --records: the levels, g (a:b:step or v1,v2,…).
    #[arg(long, requires = "records")]
    pub levels: Option<String>,
    /// With --records: free vibration after the longer record of each pair, s.
    #[arg(long, default_value_t = DEFAULT_TAIL)]
    pub tail: f64,
    /// Output folder: sensitivity.csv, sensitivity-runs.csv, sensitivity-cpu.csv, tornado.svg.
    #[arg(long, default_value = "out/sensitivity")]
    pub out: PathBuf,
    /// Run only shard K of N (contiguous blocks of runs), written to
    /// OUT/sensitivity-part-K-of-N.csv for `deckspin merge`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Finish a job that was stopped: the runs in its journal are not run again.
    #[arg(long)]
    pub resume: bool,
}

/// The cases of the arguments, and the pairs of a suite (for the job's fingerprint).
fn cases(a: &SensitivityArgs) -> Result<(Cases, Vec<SuitePair>), Box<dyn std::error::Error>> {
    let Some(records) = &a.records else {
        return Ok((Cases::ModelRuns, Vec::new()));
    };
    let measure = parse_measure(a.measure.as_deref().unwrap_or_default(), a.damping)?;
    let levels = parse_levels(a.levels.as_deref().unwrap_or_default())?;
    if !(a.tail.is_finite() && a.tail >= 0.0) {
        return Err(deckspin::suite::SuiteError::Tail(a.tail).into());
    }
    let (pairs, single) = suite_pairs(records)?;
    for s in &single {
        eprintln!("deckspin: {}: no partner component, left out", s.display());
    }
    let cases = Cases::Suite {
        pairs: pairs.clone(),
        measure,
        levels,
        tail: a.tail,
    };
    Ok((cases, pairs))
}

/// The job's fingerprint: the model text, the inputs, cases and quantities, the records'
/// names and contents, deckspin's version.
fn job(
    a: &SensitivityArgs,
    study: &Study,
    cases: &Cases,
    pairs: &[SuitePair],
) -> Result<JobId, Box<dyn std::error::Error>> {
    let text = deckspin::input::read_bounded(&a.model, deckspin::input::MAX_MODEL_BYTES)
        .map_err(|e| format!("{}: {e}", a.model.display()))?;
    let mut records = Vec::new();
    for p in pairs {
        for f in [&p.longitudinal, &p.transverse] {
            let name = f.file_name().map(|n| n.to_string_lossy().into_owned());
            records.extend(name.unwrap_or_default().bytes());
            records.extend(std::fs::read(f)?);
        }
    }
    let args = job_arguments(study, cases, &a.fix);
    Ok(JobId::new(&text, &args).with("records", &records))
}

pub fn cmd_sensitivity(a: &SensitivityArgs) -> CliResult {
    let shard = a.shard.as_deref().map(Shard::parse).transpose()?;
    let shard = shard.unwrap_or(Shard::ALL);
    let (cases, pairs) = cases(a)?;
    std::fs::create_dir_all(&a.out)?;
    let file = if shard.is_all() {
        a.out.join(RUNS_FILE)
    } else {
        a.out
            .join(format!("sensitivity-part-{}-of-{}.csv", shard.k, shard.n))
    };
    // one job writes the folder at a time; shards each their own part file
    let _lock = if shard.is_all() {
        FolderLock::acquire(&a.out)?
    } else {
        FolderLock::for_file(&file)?
    };
    let choice = Choice {
        inputs: a.inputs.clone(),
        add: a.add.clone(),
        quantities: a.quantities.clone(),
    };
    let study = Study::open(&a.model, &a.fix, &cases, &choice)?;
    let job = job(a, &study, &cases, &pairs)?;
    let header = csv_line(&runs_header(study.quantities()));
    let total = study.runs();
    let (journal, mut done) = super::jobs::open_journal(
        &file,
        "sensitivity",
        &job,
        shard,
        total,
        header.trim_end(),
        a.resume,
    )?;
    let job = Job {
        a,
        study: &study,
        file: &file,
        header: &header,
        job: &job,
        shard,
    };
    match job.finish(&journal, &mut done) {
        Ok(()) => Ok(journal.finish()?),
        Err(e) => {
            journal.abandon();
            Err(e)
        }
    }
}

/// The runs CSV's name in the output folder.
pub const RUNS_FILE: &str = "sensitivity-runs.csv";

/// A study's job, its journal opened.
struct Job<'a> {
    a: &'a SensitivityArgs,
    study: &'a Study,
    /// The runs CSV, or the shard's part file.
    file: &'a Path,
    header: &'a str,
    job: &'a JobId,
    shard: Shard,
}

impl Job<'_> {
    /// The runs of the shard not in the journal's rows `done`, then the outputs.
    fn finish(&self, journal: &Journal, done: &mut BTreeMap<usize, String>) -> CliResult {
        let (study, shard) = (self.study, self.shard);
        let total = study.runs();
        let range = shard.range(total);
        let resumed = done.len();
        let todo: Vec<usize> = range.clone().filter(|i| !done.contains_key(i)).collect();
        let t0 = std::time::Instant::now();
        let bar = Bar::new();
        let recorder = Recorder::new(journal);
        let q = study.quantities();
        let fresh = std::sync::Mutex::new(Vec::new());
        let cancelled = deckspin::suite::row::Status::Refused(deckspin::suite::CANCELLED.into());
        let rows = study.run_listed(&todo, &bar, &|i, row| {
            if row.status != cancelled {
                let line = csv_line(&run_fields(q, row));
                recorder.record(i, &line);
                let mut f = fresh.lock().unwrap_or_else(|p| p.into_inner());
                f.push((i, line));
            }
        });
        bar.clear();
        stop_if_signalled(journal, range.len())?;
        done.extend(fresh.into_inner().unwrap_or_else(|p| p.into_inner()));
        let wall = t0.elapsed().as_secs_f64();
        let cpu: f64 = rows.iter().filter_map(|r| r.cpu).sum();
        if shard.is_all() {
            let text = joined(self.header, done);
            let s = write_outputs(&self.a.out, &text)?;
            write_cpu(&self.a.out, &todo, &rows)?;
            let failed = s.failed().len();
            println!(
                "{} ({failed} did not finish); wrote {}/{{sensitivity.csv,{RUNS_FILE},sensitivity-cpu.csv,tornado*.svg}}",
                counted(s.rows.len(), resumed),
                self.a.out.display()
            );
        } else {
            let lines: Vec<(usize, String)> = done.iter().map(|(i, l)| (*i, l.clone())).collect();
            let text = part_text("sensitivity", self.job, shard, total, self.header, &lines);
            write_atomic(self.file, text)?;
            println!(
                "{}: shard {shard}, runs {}..{} of {total}; wrote {} (join the parts with `deckspin merge`)",
                counted(lines.len(), resumed),
                range.start,
                range.end,
                self.file.display()
            );
        }
        eprintln!(
            "{} runs in {wall:.2} s wall, {cpu:.2} s CPU on {} threads",
            rows.len(),
            rayon::current_num_threads()
        );
        Ok(())
    }
}

/// `sensitivity-cpu.csv`: the CPU seconds of each run made now (`todo`, in run order; a
/// resumed job's runs from its journal are not in it).
fn write_cpu(out: &Path, todo: &[usize], rows: &[deckspin::design::swings::RunRow]) -> CliResult {
    let mut text = csv_line(&["run", "input", "side", "case", "cpu_s"]);
    let mut n = deckspin::output::number::Numbers::new();
    for (i, r) in todo.iter().zip(rows) {
        let name = r.input.as_ref().map_or("base", |x| x.name.as_str());
        let cpu = r.cpu.map_or(String::new(), |c| n.format(c).to_string());
        let fields = [
            i.to_string(),
            name.into(),
            r.side.text().into(),
            r.case.clone(),
            cpu,
        ];
        text += &csv_line(&fields);
    }
    write_atomic(out.join("sensitivity-cpu.csv"), text)?;
    Ok(())
}

/// The outputs of a runs CSV `runs` (a whole study's, or merged parts'): the runs CSV, the
/// swings (`sensitivity.csv`) and their table on stdout, `tornado.svg` of the first quantity
/// (drawn in the terminal) and with several quantities `tornado-QUANTITY.svg` of each.
pub fn write_outputs(out: &Path, runs: &str) -> Result<Sensitivity, Box<dyn std::error::Error>> {
    let (quantities, rows) = read_runs(runs)?;
    let s = summarize(&quantities, rows);
    write_atomic(out.join(RUNS_FILE), runs)?;
    write_atomic(out.join("sensitivity.csv"), s.csv())?;
    print!("{}", table(&s));
    let tornado = deckspin::design::tornado::tornado;
    if s.quantities.len() > 1 {
        for (q, name) in s.quantities.iter().enumerate() {
            if let Some(c) = tornado(&s, q) {
                let svg = deckspin::plot::svg::render(
                    &c,
                    super::show::SVG_SIZE.0,
                    super::show::SVG_SIZE.1,
                );
                write_atomic(out.join(format!("tornado-{name}.svg")), svg)?;
            }
        }
    }
    if let Some(c) = tornado(&s, 0) {
        super::show::chart(&c, &out.join("tornado.svg"))?;
    }
    Ok(s)
}
