//! Errors of reading or processing a record.

use std::path::PathBuf;

/// Errors from reading or processing a record.
#[derive(Debug, thiserror::Error)]
pub enum ExcitationError {
    /// The file could not be read (missing, permissions, not UTF-8 …).
    #[error("{}: {source}", path.display())]
    Io {
        /// The record file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// Missing or garbled header (`NPTS`/`DT` line of an AT2, unit directive of a text file).
    #[error("{}:{line}: bad header: {reason}", path.display())]
    Header {
        /// The record file.
        path: PathBuf,
        /// Line, from 1.
        line: usize,
        /// What is wrong.
        reason: String,
    },
    /// A value that is not a finite number.
    #[error("{}:{line}: not a finite number: {token:?}", path.display())]
    Value {
        /// The record file.
        path: PathBuf,
        /// Line, from 1.
        line: usize,
        /// The text that is not a number.
        token: String,
    },
    /// `NPTS` disagrees with the number of values.
    #[error("{}: header says NPTS = {expected}, found {found} values", path.display())]
    Count {
        /// The record file.
        path: PathBuf,
        /// How many were expected.
        expected: usize,
        /// How many were found.
        found: usize,
    },
    /// A two-column file row with the wrong number of columns.
    #[error("{}:{line}: expected {expected} columns, found {found}", path.display())]
    Columns {
        /// The record file.
        path: PathBuf,
        /// Line, from 1.
        line: usize,
        /// How many were expected.
        expected: usize,
        /// How many were found.
        found: usize,
    },
    /// A two-column file whose time column is not uniformly increasing.
    #[error("{}:{line}: {reason}", path.display())]
    Sampling {
        /// The record file.
        path: PathBuf,
        /// Line, from 1.
        line: usize,
        /// What is wrong.
        reason: String,
    },
    /// Bad processing parameter or sample data.
    #[error("invalid {field}: {reason}")]
    Invalid {
        /// The parameter or data.
        field: &'static str,
        /// What is wrong.
        reason: String,
    },
}

pub(super) type Result<T> = std::result::Result<T, ExcitationError>;

pub(super) fn invalid(field: &'static str, reason: impl Into<String>) -> ExcitationError {
    ExcitationError::Invalid {
        field,
        reason: reason.into(),
    }
}
