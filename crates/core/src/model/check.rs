//! Validation helpers: [`ModelError`] with file, line and field, [`Check`] for located
//! `Invalid` errors, and the search of a dotted field path in the TOML text.

use crate::excitation::ExcitationError;
use nalgebra::Vector2;
use std::path::{Path, PathBuf};

/// One field set by a `--set` argument: the argument as given and the concrete dotted path it
/// set (`bent.*.x=1` sets `bent.0.x`, `bent.1.x`, …), so errors about the field name the
/// argument rather than a line of the file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Applied {
    /// The `--set` argument as given.
    pub argument: String,
    /// The field's dotted path.
    pub field: String,
}

/// Errors of reading, overriding or validating a model.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// The file could not be read.
    #[error("{}: cannot read: {source}", path.display())]
    Io {
        /// The model file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// Not TOML.
    #[error("{}:{line}:{column}: {message}", path.display())]
    Parse {
        /// The model file.
        path: PathBuf,
        /// Line in the file, from 1.
        line: usize,
        /// Column, from 1.
        column: usize,
        /// The parser's message.
        message: String,
    },
    /// A value the model refuses.
    #[error("{}:{line}: {field}: {reason}", path.display())]
    Invalid {
        /// The model file.
        path: PathBuf,
        /// 0 when the field is absent from the file.
        line: usize,
        /// The field's dotted path.
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// A `--set` argument that is not `key=value` or names no field.
    #[error("--set {key}: {reason}")]
    Override {
        /// The key of the `--set` argument.
        key: String,
        /// What is wrong.
        reason: String,
    },
    /// A value given by a `--set` argument that the model refuses: the argument is named, not
    /// the line of the file it replaced.
    #[error("--set {argument}: {field}: {reason}")]
    OverrideInvalid {
        /// The `--set` argument as given.
        argument: String,
        /// The field's dotted path.
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// A record refused for what processing made of it (no signal left, absurd scaling), with
    /// the model field naming it.
    #[error("{}:{line}: {field}: {record}: {source}", path.display())]
    Record {
        /// The model file.
        path: PathBuf,
        /// 0 when the field is absent from the file.
        line: usize,
        /// The field's dotted path.
        field: String,
        /// The record's file.
        record: String,
        /// The underlying error.
        #[source]
        source: Box<ExcitationError>,
    },
    /// A record that could not be read or processed.
    #[error("{}: {source}", path.display())]
    Excitation {
        /// The model file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: ExcitationError,
    },
}

impl ModelError {
    /// Line of the error in the model file, when known.
    pub fn line(&self) -> Option<usize> {
        match self {
            ModelError::Parse { line, .. }
            | ModelError::Invalid { line, .. }
            | ModelError::Record { line, .. }
                if *line > 0 =>
            {
                Some(*line)
            }
            _ => None,
        }
    }
}

/// Locates a dotted field path (`body.1.mass`) in TOML text: (line, column), 1-based. Falls
/// back to the nearest enclosing table or key that exists.
pub fn locate(text: &str, path: &str) -> Option<(usize, usize)> {
    let doc = toml_edit::Document::parse(text).ok()?;
    let segs: Vec<&str> = path.split('.').collect();
    let span = find_in_table(doc.as_table(), &segs, None)?;
    Some(line_col(text, span.start))
}

type Span = Option<std::ops::Range<usize>>;

fn find_in_table(t: &toml_edit::Table, segs: &[&str], best: Span) -> Span {
    let Some((first, rest)) = segs.split_first() else {
        return best.or(t.span());
    };
    match t.get_key_value(first) {
        None => best.or(t.span()),
        Some((k, item)) => {
            let here = k.span().or(item.span()).or(best);
            find_in_item(item, rest, here)
        }
    }
}

fn find_in_item(item: &toml_edit::Item, segs: &[&str], best: Span) -> Span {
    if segs.is_empty() {
        return best;
    }
    match item {
        toml_edit::Item::Table(t) => find_in_table(t, segs, best),
        toml_edit::Item::ArrayOfTables(a) => {
            match segs[0].parse::<usize>().ok().and_then(|i| a.get(i)) {
                Some(t) => find_in_table(t, &segs[1..], t.span().or(best)),
                None => best,
            }
        }
        toml_edit::Item::Value(v) => find_in_value(v, segs, best),
        _ => best,
    }
}

fn find_in_value(v: &toml_edit::Value, segs: &[&str], best: Span) -> Span {
    let Some((first, rest)) = segs.split_first() else {
        return best;
    };
    match v {
        toml_edit::Value::InlineTable(t) => match (t.key(first), t.get(first)) {
            (Some(k), Some(v)) => find_in_value(v, rest, k.span().or(v.span()).or(best)),
            _ => best,
        },
        toml_edit::Value::Array(a) => match first.parse::<usize>().ok().and_then(|i| a.get(i)) {
            Some(v) => find_in_value(v, rest, v.span().or(best)),
            None => best,
        },
        _ => best,
    }
}

fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before
        .rfind('\n')
        .map_or(before.len(), |p| before.len() - p - 1)
        + 1;
    (line, col)
}

/// A TOML syntax or schema error, located in `text` (file:line:column); on a line whose value
/// a `--set` argument wrote, the argument is named instead.
pub(super) fn parse_error(
    e: &toml::de::Error,
    text: &str,
    path: &Path,
    applied: &[Applied],
) -> ModelError {
    let (line, column) = e.span().map_or((0, 0), |s| line_col(text, s.start));
    let by_set = applied
        .iter()
        .find(|a| line > 0 && locate(text, &a.field).map(|l| l.0) == Some(line));
    if let Some(a) = by_set {
        return ModelError::OverrideInvalid {
            argument: a.argument.clone(),
            field: a.field.clone(),
            reason: e.message().to_string(),
        };
    }
    ModelError::Parse {
        path: path.to_path_buf(),
        line,
        column,
        message: e.message().to_string(),
    }
}

/// Validation context: builds `Invalid` errors located in the text, or naming the `--set`
/// argument that gave the field its value.
pub struct Check<'a> {
    /// The model's text.
    pub text: &'a str,
    /// The model file.
    pub path: &'a Path,
    /// The fields `--set` arguments wrote.
    pub applied: &'a [Applied],
    /// The file's `units` (SI-kN when absent).
    pub units: crate::units::UnitSystem,
}

impl Check<'_> {
    /// The `--set` argument that wrote `field`, a table containing it, or a part of it.
    pub(crate) fn set_by(&self, field: &str) -> Option<&Applied> {
        let within = |a: &str, b: &str| a == b || a.starts_with(&format!("{b}."));
        (self.applied.iter().rev()).find(|a| within(field, &a.field) || within(&a.field, field))
    }

    /// Line of `field` in the file, 0 when absent.
    pub fn line(&self, field: &str) -> usize {
        locate(self.text, field).map_or(0, |l| l.0)
    }

    /// An `Invalid` error at `field` (its line, or the `--set` argument that wrote it).
    pub fn err(&self, field: &str, reason: impl Into<String>) -> ModelError {
        if let Some(a) = self.set_by(field) {
            return ModelError::OverrideInvalid {
                argument: a.argument.clone(),
                field: field.to_string(),
                reason: reason.into(),
            };
        }
        ModelError::Invalid {
            path: self.path.to_path_buf(),
            line: locate(self.text, field).map_or(0, |l| l.0),
            field: field.to_string(),
            reason: reason.into(),
        }
    }
    /// `x`, or an error at `field` if it is not finite.
    pub fn finite(&self, field: &str, x: f64) -> Result<f64, ModelError> {
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.err(field, format!("must be a finite number, got {x}")))
        }
    }
    /// `x`, or an error at `field` if it is not finite and > 0.
    pub fn positive(&self, field: &str, x: f64) -> Result<f64, ModelError> {
        self.finite(field, x)?;
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(field, format!("must be > 0, got {x}")))
        }
    }
    /// `x`, or an error at `field` if it is not finite and ≥ 0.
    pub(crate) fn nonneg(&self, field: &str, x: f64) -> Result<f64, ModelError> {
        self.finite(field, x)?;
        if x >= 0.0 {
            Ok(x)
        } else {
            Err(self.err(field, format!("must be ≥ 0, got {x}")))
        }
    }
    /// `v` as a vector, or an error at `field` if a component is not finite.
    pub(crate) fn vec2(&self, field: &str, v: [f64; 2]) -> Result<Vector2<f64>, ModelError> {
        for (i, x) in v.iter().enumerate() {
            self.finite(&format!("{field}[{i}]"), *x)
                .map_err(|_| self.err(field, "must be finite"))?;
        }
        Ok(Vector2::new(v[0], v[1]))
    }
    /// `v` normalised, or an error at `field` if it is not finite or zero.
    pub fn unit(&self, field: &str, v: [f64; 2]) -> Result<Vector2<f64>, ModelError> {
        let v = self.vec2(field, v)?;
        let n = v.norm();
        if n < 1e-12 {
            return Err(self.err(field, "must be a nonzero direction"));
        }
        Ok(v / n)
    }
}
