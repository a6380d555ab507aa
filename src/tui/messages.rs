//! The message log (as vim's `:messages`): every status message with the time it was said,
//! kept whole (the last [`KEEP`]), shown wrapped and scrollable (`M`).

/// What a status message is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StatusKind {
    Info,
    Ok,
    Warn,
    Error,
}

/// Messages kept.
pub const KEEP: usize = 1000;

/// One status message.
#[derive(Clone, Debug, PartialEq)]
pub struct Said {
    /// Local wall-clock time, `HH:MM:SS` (UTC when the offset is unknown).
    pub at: String,
    pub kind: StatusKind,
    pub text: String,
}

/// `HH:MM:SS` of now (UTC).
pub fn clock() -> String {
    let s = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    format!("{:02}:{:02}:{:02}", s / 3600 % 24, s / 60 % 60, s % 60)
}

/// Adds `text` to `log` unless it repeats the last message; the oldest go past [`KEEP`].
pub fn push(log: &mut Vec<Said>, kind: StatusKind, text: &str) {
    if text.is_empty() || log.last().is_some_and(|l| l.text == text && l.kind == kind) {
        return;
    }
    log.push(Said {
        at: clock(),
        kind,
        text: text.to_string(),
    });
    if log.len() > KEEP {
        let extra = log.len() - KEEP;
        log.drain(..extra);
    }
}

/// The log as lines of at most `width` characters: each message's first line starts with its
/// time, its continuation lines are indented under its text.
pub fn lines(log: &[Said], width: usize) -> Vec<(StatusKind, String)> {
    let lead = 10; // "HH:MM:SS  "
    let room = width.saturating_sub(lead).max(10);
    let mut out = Vec::new();
    for m in log {
        let mut first = true;
        for chunk in wrap(&m.text, room) {
            let head = if first {
                format!("{}  ", m.at)
            } else {
                " ".repeat(lead)
            };
            first = false;
            out.push((m.kind, format!("{head}{chunk}")));
        }
    }
    out
}

/// `text` cut into lines of at most `room` characters, at spaces where it can.
pub fn wrap(text: &str, room: usize) -> Vec<String> {
    let mut out = Vec::new();
    let mut line = String::new();
    for word in text.split(' ') {
        let n = line.chars().count();
        let w = word.chars().count();
        if n > 0 && n + 1 + w > room {
            out.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
        // a word longer than a line is cut
        while line.chars().count() > room {
            let cut: String = line.chars().take(room).collect();
            line = line.chars().skip(room).collect();
            out.push(cut);
        }
    }
    if !line.is_empty() || out.is_empty() {
        out.push(line);
    }
    out
}

/// The first line shown of `total` lines in `rows` rows: the end when `scroll` is past it.
pub fn max_scroll(total: usize, rows: usize) -> usize {
    total.saturating_sub(rows)
}
