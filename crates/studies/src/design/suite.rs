//! The per-run CSV of a record suite (`deckspin suite`): columns
//! `pair,longitudinal,transverse,measure,level,scale`, then the swept parameters (by their
//! dotted keys), then `status` and the response columns (`peak_rotation`, …,
//! `energy_columns`). `level` is the intensity (g) at which the pair was run; `status` is
//! `finished`, `failed: <reason>` or `refused: <reason>`; an empty response means "does not
//! apply".

use std::path::{Path, PathBuf};

/// The leading columns, in order (those the suite writes).
pub(crate) use crate::suite::row::LEAD as HEAD;

/// Most runs a suite file may hold (the read keeps them all in memory).
pub(crate) const MAX_RUNS: usize = 1_000_000;

/// How a run ended.
#[derive(Clone, Debug, PartialEq)]
pub enum RunStatus {
    Finished,
    /// `failed: <reason>`.
    Failed(String),
    /// `refused: <reason>`.
    Refused(String),
}

/// One row of the suite.
#[derive(Clone, Debug, PartialEq)]
pub struct SuiteRun {
    /// Line of the row in the file (1-based; the header is line 1).
    pub line: usize,
    pub pair: String,
    /// Intensity, g.
    pub level: f64,
    /// Values of the swept parameters, in the order of [`Suite::params`].
    pub params: Vec<String>,
    pub status: RunStatus,
    /// Responses in the order of [`Suite::responses`]: `None` where empty (does not apply)
    /// or the run did not finish.
    pub values: Vec<Option<f64>>,
}

/// A suite's runs.
#[derive(Clone, Debug, PartialEq)]
pub struct Suite {
    pub path: PathBuf,
    /// The intensity measure of `level` (one per suite).
    pub measure: String,
    /// The swept parameters' keys (columns between `scale` and `status`).
    pub params: Vec<String>,
    /// The response columns (after `status`).
    pub responses: Vec<String>,
    pub runs: Vec<SuiteRun>,
}

/// A suite file that cannot be read as one.
#[derive(Debug, thiserror::Error)]
pub enum SuiteError {
    #[error("{}: cannot read: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{}:{line}: {message}", path.display())]
    Csv {
        path: PathBuf,
        line: usize,
        message: String,
    },
    #[error("{}:1: header: {reason}", path.display())]
    Header { path: PathBuf, reason: String },
    #[error("{}:{line}: {column}: '{text}': {reason}", path.display())]
    Field {
        path: PathBuf,
        line: usize,
        column: String,
        text: String,
        reason: String,
    },
    #[error(
        "{}:{line}: measure '{found}' differs from '{first}' of line {first_line}: one intensity measure per suite",
        path.display()
    )]
    MixedMeasures {
        path: PathBuf,
        line: usize,
        found: String,
        first: String,
        first_line: usize,
    },
    #[error("{}: no runs", path.display())]
    Empty { path: PathBuf },
    #[error("{}: more than {max} runs", path.display())]
    TooLarge { path: PathBuf, max: usize },
}

impl Suite {
    /// Reads a suite file.
    pub fn read(path: &Path) -> Result<Self, SuiteError> {
        let text = std::fs::read_to_string(path).map_err(|e| SuiteError::Io {
            path: path.to_path_buf(),
            source: e,
        })?;
        Self::parse(&text, path)
    }

    /// Parses the text of a suite file (`path` names it in errors).
    pub fn parse(text: &str, path: &Path) -> Result<Self, SuiteError> {
        let mut rdr = csv::ReaderBuilder::new()
            .has_headers(true)
            .from_reader(text.as_bytes());
        let csv_err = |e: csv::Error| SuiteError::Csv {
            path: path.to_path_buf(),
            line: e.position().map_or(0, |p| p.line() as usize),
            message: e.to_string(),
        };
        let head: Vec<String> = rdr
            .headers()
            .map_err(csv_err)?
            .iter()
            .map(|h| h.trim().to_string())
            .collect();
        let header = |reason: String| SuiteError::Header {
            path: path.to_path_buf(),
            reason,
        };
        for (k, want) in HEAD.iter().enumerate() {
            if head.get(k).map(String::as_str) != Some(*want) {
                return Err(header(format!(
                    "column {} is '{}', expected '{want}' (columns start {})",
                    k + 1,
                    head.get(k).map_or("", String::as_str),
                    HEAD.join(",")
                )));
            }
        }
        let status = (head.iter().position(|h| h == "status"))
            .ok_or_else(|| header("no 'status' column".into()))?;
        let mut suite = Suite {
            path: path.to_path_buf(),
            measure: String::new(),
            params: head[HEAD.len()..status].to_vec(),
            responses: head[status + 1..].to_vec(),
            runs: Vec::new(),
        };
        let mut first_measure: Option<usize> = None;
        for rec in rdr.records() {
            let rec = rec.map_err(csv_err)?;
            let line = rec.position().map_or(0, |p| p.line() as usize);
            if suite.runs.len() == MAX_RUNS {
                return Err(SuiteError::TooLarge {
                    path: path.to_path_buf(),
                    max: MAX_RUNS,
                });
            }
            let run = suite.row(&rec, line, status)?;
            let measure = rec[3].trim();
            match first_measure {
                None => {
                    suite.measure = measure.to_string();
                    first_measure = Some(line);
                }
                Some(first_line) if measure != suite.measure => {
                    return Err(SuiteError::MixedMeasures {
                        path: path.to_path_buf(),
                        line,
                        found: measure.to_string(),
                        first: suite.measure.clone(),
                        first_line,
                    });
                }
                Some(_) => {}
            }
            suite.runs.push(run);
        }
        if suite.runs.is_empty() {
            return Err(SuiteError::Empty {
                path: path.to_path_buf(),
            });
        }
        Ok(suite)
    }

    /// One row: its pair, level, parameters, status and (for a finished run) responses.
    fn row(
        &self,
        rec: &csv::StringRecord,
        line: usize,
        status: usize,
    ) -> Result<SuiteRun, SuiteError> {
        let field = |column: &str, text: &str, reason: &str| SuiteError::Field {
            path: self.path.clone(),
            line,
            column: column.to_string(),
            text: text.to_string(),
            reason: reason.to_string(),
        };
        let pair = rec[0].trim();
        if pair.is_empty() {
            return Err(field("pair", "", "empty"));
        }
        let level_text = rec[4].trim();
        let level: f64 = level_text
            .parse()
            .map_err(|_| field("level", level_text, "not a number"))?;
        if !(level.is_finite() && level > 0.0) {
            return Err(field("level", level_text, "must be a finite intensity > 0"));
        }
        let s = rec[status].trim();
        let status_of = |word: &str| {
            s.strip_prefix(word)
                .filter(|rest| rest.is_empty() || rest.starts_with(':'))
                .map(|rest| rest.trim_start_matches(':').trim().to_string())
        };
        let st = if s == "finished" {
            RunStatus::Finished
        } else if let Some(r) = status_of("failed") {
            RunStatus::Failed(r)
        } else if let Some(r) = status_of("refused") {
            RunStatus::Refused(r)
        } else {
            return Err(field(
                "status",
                s,
                "expected finished, failed: <reason> or refused: <reason>",
            ));
        };
        let mut values = vec![None; self.responses.len()];
        if st == RunStatus::Finished {
            for (k, name) in self.responses.iter().enumerate() {
                let t = rec[status + 1 + k].trim();
                if t.is_empty() {
                    continue;
                }
                let v: f64 = t.parse().map_err(|_| field(name, t, "not a number"))?;
                if !v.is_finite() {
                    return Err(field(
                        name,
                        t,
                        "not finite (an empty field means: does not apply)",
                    ));
                }
                values[k] = Some(v);
            }
        }
        Ok(SuiteRun {
            line,
            pair: pair.to_string(),
            level,
            params: (HEAD.len()..status)
                .map(|k| rec[k].trim().to_string())
                .collect(),
            status: st,
            values,
        })
    }

    /// The combinations of swept parameters, in order of first appearance: (key, value) pairs.
    pub fn groups(&self) -> Vec<Vec<(String, String)>> {
        let mut known = std::collections::HashSet::new();
        let mut seen: Vec<&Vec<String>> = Vec::new();
        for r in &self.runs {
            if known.insert(&r.params) {
                seen.push(&r.params);
            }
        }
        (seen.into_iter())
            .map(|v| self.params.iter().cloned().zip(v.iter().cloned()).collect())
            .collect()
    }
}
