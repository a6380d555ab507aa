//! Charts of the commands: written as SVG beside their tables, and drawn as ASCII text after
//! the table when stdout is a terminal.

use deckspin::plot::{Chart, Grid, svg, text};
use std::io::IsTerminal;
use std::path::Path;

/// Canvas of the SVG files, px.
pub const SVG_SIZE: (f64, f64) = (900.0, 540.0);
/// Height of a chart drawn in the terminal, lines; its width is the terminal's (at most 120).
pub const TEXT_HEIGHT: usize = 28;

/// The terminal's width in columns when stdout is a terminal (80 when it does not say).
pub fn terminal_width() -> Option<usize> {
    if !std::io::stdout().is_terminal() {
        return None;
    }
    #[cfg(unix)]
    {
        // SAFETY: TIOCGWINSZ fills the winsize it is given; stdout is open.
        let mut ws: libc::winsize = unsafe { std::mem::zeroed() };
        let ok = unsafe { libc::ioctl(libc::STDOUT_FILENO, libc::TIOCGWINSZ, &mut ws) } == 0;
        if ok && ws.ws_col > 0 {
            return Some(ws.ws_col as usize);
        }
    }
    Some(80)
}

/// Writes `chart` to `path` as SVG and draws it in the terminal.
pub fn chart(chart: &Chart, path: &Path) -> std::io::Result<()> {
    deckspin::output::files::write_atomic(path, svg::render(chart, SVG_SIZE.0, SVG_SIZE.1))?;
    if let Some(w) = terminal_width() {
        print!("\n{}", text::render(chart, w.min(120), TEXT_HEIGHT));
    }
    Ok(())
}

/// Writes `grid` to `path` as SVG and draws it in the terminal.
pub fn grid(grid: &Grid, path: &Path) -> std::io::Result<()> {
    deckspin::output::files::write_atomic(path, svg::render_grid(grid))?;
    if let Some(w) = terminal_width() {
        print!("\n{}", text::render_grid(grid, w));
    }
    Ok(())
}
