//! A run's whole status (`i`, from the run list and the charts): how it ended and the whole
//! reason of a failure, the time it reached, its method and step, wrapped to the screen's
//! width and scrolled.

/// The run info: a title and its (label, text) rows, gathered when it is opened
/// (`update/info.rs`).
#[derive(Clone, Debug, PartialEq)]
pub struct Info {
    pub number: u64,
    pub title: String,
    pub rows: Vec<(String, String)>,
}

/// The width of the labels' column.
pub const LABEL: usize = 14;

/// The info's lines at `width` columns: each row's label, then its text wrapped beside it
/// (its own line breaks kept).
pub fn lines(info: &Info, width: usize) -> Vec<String> {
    let room = width.saturating_sub(LABEL).max(10);
    let mut out = Vec::new();
    for (label, text) in &info.rows {
        // a panic's message holds line breaks: each line wrapped
        let chunks = text
            .lines()
            .flat_map(|l| crate::tui::messages::wrap(l, room));
        for (i, chunk) in chunks.enumerate() {
            let head = if i == 0 { label.as_str() } else { "" };
            out.push(format!("{head:<LABEL$}{chunk}"));
        }
    }
    out
}
