//! A CSV the library wrote that cannot be read back (a record suite's runs, a sensitivity
//! study's runs): which CSV, the line and why.

/// A line of a CSV that is not what the CSV holds there.
#[derive(Debug, thiserror::Error)]
#[error("{what} CSV line {line}: {reason}")]
pub struct CsvError {
    /// What the CSV is: `suite`, `sensitivity runs`.
    pub what: &'static str,
    /// The line, from 1 (the header).
    pub line: usize,
    /// Why the line cannot be read.
    pub reason: String,
}

impl CsvError {
    /// The error of line `line` of the `what` CSV.
    pub fn new(what: &'static str, line: usize, reason: impl Into<String>) -> Self {
        Self {
            what,
            line,
            reason: reason.into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::design::swings::read_runs;
    use crate::suite::row::read_csv;

    #[test]
    fn both_readers_name_their_csv_the_line_and_the_reason() {
        let e = read_csv("a,b\n").unwrap_err();
        assert_eq!((e.what, e.line), ("suite", 1));
        assert_eq!(
            e.to_string(),
            "suite CSV line 1: not the header of a suite CSV"
        );
        let e = read_runs("").unwrap_err();
        assert_eq!(
            (e.what, e.line, e.reason.as_str()),
            ("sensitivity runs", 1, "empty")
        );
        assert_eq!(e.to_string(), "sensitivity runs CSV line 1: empty");
    }
}
