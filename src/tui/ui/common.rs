//! Shared by the panels: the theme (colours, glyphs, borders), the label width, which runs
//! are shown.

use crate::tui::app::{App, StatusKind};
use crate::tui::runs::data::RunData;
use ratatui::style::{Color, Modifier, Style};
use ratatui::symbols::{Marker, border};
use ratatui::text::Line;
use ratatui::widgets::Block;

/// Width of the y-axis labels of the time charts (the event strip uses the same offset): a
/// label of 4 significant digits with its unit and sign (`-189.0 µrad`) and a space.
pub(super) const LABEL_W: u16 = 12;

/// Colours: the 16 named ANSI colours, or none at all (NO_COLOR).
pub(super) struct Theme {
    pub color: bool,
    pub ascii: bool,
}

const PALETTE: [Color; 8] = [
    Color::Cyan,
    Color::Yellow,
    Color::Green,
    Color::Magenta,
    Color::Blue,
    Color::Red,
    Color::LightCyan,
    Color::LightGreen,
];

impl Theme {
    pub(super) fn fg(&self, c: Color) -> Style {
        if self.color {
            Style::default().fg(c)
        } else {
            Style::default()
        }
    }
    pub(super) fn series(&self, i: usize) -> Style {
        self.fg(PALETTE[i % PALETTE.len()])
    }
    pub(super) fn previous(&self) -> Style {
        if self.color {
            Style::default().fg(Color::DarkGray)
        } else {
            Style::default().add_modifier(Modifier::DIM)
        }
    }
    /// The `i`-th overlaid run that is not the baseline.
    pub(super) fn overlay(&self, i: usize) -> Style {
        const OVERLAY: [Color; 4] = [
            Color::Gray,
            Color::LightBlue,
            Color::LightMagenta,
            Color::LightYellow,
        ];
        if self.color {
            Style::default().fg(OVERLAY[i % OVERLAY.len()])
        } else {
            Style::default().add_modifier(Modifier::DIM)
        }
    }
    pub(super) fn cursor(&self) -> Style {
        if self.color {
            Style::default().fg(Color::LightRed)
        } else {
            Style::default().add_modifier(Modifier::BOLD)
        }
    }
    pub(super) fn bold(&self) -> Style {
        Style::default().add_modifier(Modifier::BOLD)
    }
    pub(super) fn dim(&self) -> Style {
        if self.color {
            Style::default().fg(Color::DarkGray)
        } else {
            Style::default().add_modifier(Modifier::DIM)
        }
    }
    pub(super) fn status(&self, k: StatusKind) -> Style {
        match k {
            StatusKind::Info => Style::default(),
            StatusKind::Ok => self.fg(Color::Green),
            StatusKind::Warn => self.fg(Color::Yellow).add_modifier(Modifier::BOLD),
            StatusKind::Error => self.fg(Color::Red).add_modifier(Modifier::BOLD),
        }
    }
    pub(super) fn selected(&self) -> Style {
        Style::default().add_modifier(Modifier::REVERSED)
    }
    pub(super) fn marker(&self) -> Marker {
        if self.ascii {
            Marker::Custom('.')
        } else {
            Marker::Braille
        }
    }
    pub(super) fn per_cell(&self) -> usize {
        if self.marks() { 1 } else { 2 }
    }
    pub(super) fn border(&self) -> border::Set<'static> {
        if self.ascii {
            border::Set {
                top_left: "+",
                top_right: "+",
                bottom_left: "+",
                bottom_right: "+",
                vertical_left: "|",
                vertical_right: "|",
                horizontal_top: "-",
                horizontal_bottom: "-",
            }
        } else {
            border::PLAIN
        }
    }
    pub(super) fn block<'a>(&self, title: impl Into<Line<'a>>) -> Block<'a> {
        Block::bordered()
            .border_set(self.border())
            .border_style(self.dim())
            .title(title.into().style(self.bold()))
    }
}

pub(super) fn theme(app: &App) -> Theme {
    Theme {
        color: app.opts.color,
        ascii: app.ascii,
    }
}

/// The run whose layout (names) drives the charts: the current one.
pub(super) fn shown_run(app: &App) -> Option<&RunData> {
    app.current.as_ref()
}

/// A run drawn under the shown one: its series, its number, its style.
pub(super) struct Overlay<'a> {
    pub data: &'a RunData,
    pub number: u64,
    pub style: Style,
}

/// The runs overlaid on the charts (unless hidden with `o`): the baseline, then the runs
/// selected in the run list, each in its own style; never the shown run itself.
pub(super) fn overlay_runs<'a>(app: &'a App, th: &Theme) -> Vec<Overlay<'a>> {
    if !app.overlay {
        return Vec::new();
    }
    // the shown run by its token: a rerun of a kept run's text has its number
    let shown = shown_run(app).map(|r| r.token);
    app.runs
        .overlays()
        .into_iter()
        .enumerate()
        .filter(|(_, e)| Some(e.data.token) != shown)
        .map(|(i, e)| Overlay {
            data: &e.data,
            number: e.number,
            style: if Some(e.number) == app.runs.baseline {
                th.previous()
            } else {
                th.overlay(i)
            },
        })
        .collect()
}

/// The first overlaid run (the baseline, when it is not the shown run).
pub(super) fn overlay_run(app: &App) -> Option<&RunData> {
    let th = theme(app);
    overlay_runs(app, &th).first().map(|o| o.data)
}

/// The data marks of the series of one chart in ASCII mode or without colour (see
/// [`Theme::marks`]; each series' line is drawn in its mark), the previous run's and the
/// cursor's.
const MARKS: [char; 8] = ['.', '+', 'o', 'x', '%', '@', '&', '$'];
/// The mark of an overlaid run's series (the previous run's loop).
pub(super) const PREVIOUS_MARK: char = ':';
/// The mark of the time cursor's line.
pub(super) const CURSOR_MARK: char = '|';

/// The glyph of the `k`-th series of a chart: its mark where series are told apart by marks.
pub(super) fn series_glyph(k: usize) -> char {
    MARKS[k % MARKS.len()]
}

impl Theme {
    /// Series are told apart by their marks, not by colour: in ASCII mode and without colour
    /// (each series of a chart drawn with its own character, named in the legend).
    pub(super) fn marks(&self) -> bool {
        self.ascii || !self.color
    }
    /// The mark of the `k`-th series of a chart, when series are told apart by marks.
    pub(super) fn series_mark(&self, k: usize) -> Option<char> {
        self.marks().then_some(series_glyph(k))
    }
    /// The legend's sample of the `k`-th series (`━`, or its mark).
    pub(super) fn legend_mark(&self, k: usize) -> String {
        self.series_mark(k).map_or("━".into(), String::from)
    }
    /// The legend's sample of the previous run (`┈`, or its mark).
    pub(super) fn previous_mark(&self) -> String {
        if self.marks() {
            PREVIOUS_MARK.to_string()
        } else {
            "┈".into()
        }
    }
}

impl Theme {
    /// Text as drawn: in ASCII mode Greek letters and symbols are spelled out (`θ` theta,
    /// `μ` mu, `ε` eps, `…` ..., `×` x, `·` |, `→` ->, `≥` >=) and anything else above 0x7E
    /// becomes `?`.
    pub(super) fn text(&self, s: &str) -> String {
        if !self.ascii {
            return s.to_string();
        }
        let mut out = String::with_capacity(s.len());
        for c in s.chars() {
            match c {
                'θ' => out.push_str("theta"),
                'μ' => out.push_str("mu"),
                'ε' => out.push_str("eps"),
                '…' => out.push_str("..."),
                '×' => out.push('x'),
                '·' | '│' => out.push('|'),
                '→' => out.push_str("->"),
                '←' => out.push_str("<-"),
                '↑' => out.push('^'),
                '↓' => out.push('v'),
                '⇄' => out.push_str("<->"),
                '≥' => out.push_str(">="),
                '≤' => out.push_str("<="),
                '—' | '–' | '─' | '━' => out.push('-'),
                '┈' => out.push(':'),
                '°' => out.push_str(" deg"),
                '²' => out.push('2'),
                '³' => out.push('3'),
                'ζ' => out.push_str("zeta"),
                'λ' => out.push_str("lambda"),
                'Δ' => out.push('d'),
                '✓' => out.push_str("ok:"),
                '✗' => out.push_str("error:"),
                '█' | '■' => out.push('#'),
                '▒' => out.push('='),
                '●' | '•' => out.push('*'),
                '╳' => out.push('X'),
                c if (c as u32) < 0x7f => out.push(c),
                _ => out.push('?'),
            }
        }
        out
    }

    /// The separator of items on one line.
    pub(super) fn sep(&self) -> &'static str {
        if self.ascii { " | " } else { " · " }
    }
}

/// `s` in at most `width` columns: whole, or cut after its last whole word that fits with
/// `ellipsis` after it (never inside a word or a unit); empty when not even one word fits.
pub(super) fn cut_words(s: &str, width: usize, ellipsis: &str) -> String {
    if s.chars().count() <= width {
        return s.to_string();
    }
    let room = width.saturating_sub(ellipsis.chars().count());
    let mut end = 0;
    for (i, c) in s.char_indices() {
        if c == ' ' && s[..i].chars().count() <= room {
            end = i;
        }
    }
    let head = s[..end].trim_end();
    if head.is_empty() {
        String::new()
    } else {
        format!("{head}{ellipsis}")
    }
}

/// As many of `items` as fit whole in `width` columns, in order, joined by `sep` (an item
/// that does not fit is left out, never cut).
pub(super) fn fit(items: &[String], sep: &str, width: usize) -> String {
    let mut out = String::new();
    for it in items.iter().filter(|i| !i.is_empty()) {
        let extra = if out.is_empty() {
            0
        } else {
            sep.chars().count()
        };
        if out.chars().count() + extra + it.chars().count() <= width {
            if !out.is_empty() {
                out.push_str(sep);
            }
            out.push_str(it);
        }
    }
    out
}

/// `items` flowed in order into at most `lines` lines of `width` columns, joined by `sep`; an
/// item that does not fit on a line of its own, or finds no line left, is left out whole.
pub(super) fn fit_lines(items: &[String], sep: &str, width: usize, lines: usize) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for it in items.iter().filter(|i| !i.is_empty()) {
        let n = it.chars().count();
        if n > width {
            continue;
        }
        let fits = |l: &String| l.chars().count() + sep.chars().count() + n <= width;
        if let Some(l) = out.last_mut().filter(|l| fits(l)) {
            l.push_str(sep);
            l.push_str(it);
        } else if out.len() < lines {
            out.push(it.clone());
        }
    }
    out
}

/// The block of a scrolled page titled `title`: when it scrolls (`max` > 0), its bottom border
/// gives the lines shown of `total` from `scroll` (`rows` a page), then `keys`.
pub(super) fn scrolled_block<'a>(
    th: &Theme,
    title: &str,
    (scroll, rows, total, max): (usize, usize, usize, usize),
    keys: &str,
) -> Block<'a> {
    let block = th.block(th.text(title));
    if max == 0 {
        return block;
    }
    let at = format!(
        " lines {}–{} of {total}{keys} ",
        scroll + 1,
        (scroll + rows).min(total)
    );
    block.title_bottom(Line::styled(th.text(&at), th.bold()))
}
