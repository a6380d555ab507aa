//! Limit states: a response column, `>` or `<`, a threshold (`peak_rotation>0.005`,
//! `min_seat_margin<0`); given on the command line or in a model file's `[[limit_state]]`
//! tables (`name`, `expression`), checked with file, line and field.

use super::check::{self, Check, ModelError};
use serde::{Deserialize, Serialize};
use std::path::Path;
use toml::Spanned;
use toml::de::{DeTable, Deserializer};

/// A `[[limit_state]]` table of a model file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LimitStateSpec {
    /// Its name.
    pub name: String,
    /// `column>threshold` or `column<threshold`.
    pub expression: String,
}

/// Which side of the threshold is exceedance.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Op {
    /// value > threshold.
    #[serde(rename = ">")]
    Above,
    /// value < threshold.
    #[serde(rename = "<")]
    Below,
}

/// A limit state: exceeded when `column` `op` `threshold`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LimitState {
    /// Its name.
    pub name: String,
    /// The suite CSV's column it reads.
    pub column: String,
    /// The comparison.
    pub op: Op,
    /// The threshold.
    pub threshold: f64,
}

/// An expression that is not `column>number` or `column<number`.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("limit state '{text}': {reason}")]
pub struct LimitStateError {
    /// The expression as given.
    pub text: String,
    /// What is wrong.
    pub reason: String,
}

impl LimitState {
    /// Parses `column>number` or `column<number` (blanks around the parts allowed); the name
    /// is the expression as given, trimmed.
    pub fn parse(text: &str) -> Result<Self, LimitStateError> {
        Self::named(text.trim(), text)
    }

    /// As [`LimitState::parse`], with its own name.
    pub fn named(name: &str, text: &str) -> Result<Self, LimitStateError> {
        let err = |reason: String| LimitStateError {
            text: text.to_string(),
            reason,
        };
        let ops: Vec<(usize, char)> = text
            .char_indices()
            .filter(|(_, c)| matches!(c, '>' | '<' | '='))
            .collect();
        let (at, c) = match ops.as_slice() {
            [(at, c)] if *c != '=' => (*at, *c),
            [] => return Err(err("expected column>number or column<number".into())),
            _ => {
                return Err(err(
                    "one comparison, > or < (a limit is exceeded strictly: no >=, <=, ==)".into(),
                ));
            }
        };
        let column = text[..at].trim();
        let number = text[at + 1..].trim();
        if column.is_empty() {
            return Err(err(format!("no column before '{c}'")));
        }
        if let Some(bad) = (column.chars()).find(|c| !(c.is_ascii_alphanumeric() || *c == '_')) {
            return Err(err(format!(
                "'{column}' is not a column name (letters, digits, _; found '{bad}')"
            )));
        }
        let threshold: f64 = number
            .parse()
            .map_err(|_| err(format!("'{number}' after '{c}' is not a number")))?;
        if !threshold.is_finite() {
            return Err(err(format!("the threshold {number} is not finite")));
        }
        if name.trim().is_empty() {
            return Err(err("the name is empty".into()));
        }
        Ok(Self {
            name: name.trim().to_string(),
            column: column.to_string(),
            op: if c == '>' { Op::Above } else { Op::Below },
            threshold,
        })
    }

    /// Whether `value` exceeds the limit state.
    pub fn exceeded(&self, value: f64) -> bool {
        match self.op {
            Op::Above => value > self.threshold,
            Op::Below => value < self.threshold,
        }
    }

    /// The expression, `column>threshold`.
    pub fn expression(&self) -> String {
        let c = if self.op == Op::Above { '>' } else { '<' };
        format!("{}{c}{}", self.column, self.threshold)
    }
}

/// The limit states of a model file's `[[limit_state]]` tables: names not empty and distinct,
/// expressions parsed; errors name `limit_state.K.name` or `limit_state.K.expression` and its
/// line.
pub(crate) fn check_specs(
    specs: &[LimitStateSpec],
    ck: &Check,
) -> Result<Vec<LimitState>, ModelError> {
    let mut out: Vec<LimitState> = Vec::with_capacity(specs.len());
    for (k, s) in specs.iter().enumerate() {
        let name = s.name.trim();
        if name.is_empty() {
            return Err(ck.err(&format!("limit_state.{k}.name"), "is empty"));
        }
        if let Some(j) = out.iter().position(|l| l.name == name) {
            return Err(ck.err(
                &format!("limit_state.{k}.name"),
                format!("'{name}' is also the name of limit_state.{j}"),
            ));
        }
        let ls = LimitState::named(name, &s.expression)
            .map_err(|e| ck.err(&format!("limit_state.{k}.expression"), e.to_string()))?;
        out.push(ls);
    }
    Ok(out)
}

/// The `[[limit_state]]` tables of a model file alone (the rest of the file is not compiled).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct OnlyLimitStates {
    #[serde(default, rename = "limit_state")]
    specs: Vec<LimitStateSpec>,
}

/// The limit states of the model file at `path` (none when it has no `[[limit_state]]`).
pub fn read(path: &Path) -> Result<Vec<LimitState>, ModelError> {
    let text = crate::input::read_bounded(path, crate::input::MAX_MODEL_BYTES).map_err(|e| {
        ModelError::Io {
            path: path.to_path_buf(),
            source: e,
        }
    })?;
    from_text(&text, path)
}

/// As [`read`], from the text of the file at `path`.
pub fn from_text(text: &str, path: &Path) -> Result<Vec<LimitState>, ModelError> {
    let located = |e: toml::de::Error| check::parse_error(&e, text, path, &[]);
    let mut doc = DeTable::parse(text).map_err(located)?;
    let mut table = DeTable::new();
    if let Some((k, v)) = doc.get_mut().remove_entry("limit_state") {
        table.insert(k, v);
    }
    let doc = Spanned::new(doc.span(), table);
    let only = OnlyLimitStates::deserialize(Deserializer::from(doc)).map_err(located)?;
    let ck = Check {
        text,
        path,
        applied: &[],
        units: Default::default(),
    };
    check_specs(&only.specs, &ck)
}
