//! Shared by the panels: the theme (colours, glyphs, borders), the label width, which runs
//! are shown.

use crate::tui::app::{App, StatusKind};
use crate::tui::run_data::RunData;
use ratatui::style::{Color, Modifier, Style};
use ratatui::symbols::{Marker, border};
use ratatui::text::Line;
use ratatui::widgets::Block;

/// Width of the y-axis labels of the time charts (the event strip uses the same offset).
pub(super) const LABEL_W: u16 = 9;

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
            Marker::Dot
        } else {
            Marker::Braille
        }
    }
    pub(super) fn per_cell(&self) -> usize {
        if self.ascii { 1 } else { 2 }
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

/// The run whose layout (names) drives the charts: the current one, else the previous.
pub(super) fn shown_run(app: &App) -> Option<&RunData> {
    app.current.as_ref().or(app.previous.as_ref())
}

/// The overlay: the previous run, unless hidden.
pub(super) fn overlay_run(app: &App) -> Option<&RunData> {
    if app.overlay {
        app.previous.as_ref()
    } else {
        None
    }
}
