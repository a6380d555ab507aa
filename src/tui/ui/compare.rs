//! The comparison of runs: one column per run (the baseline, the shown run, the runs selected
//! in the run list), one row per key result.

use super::common::Theme;
use crate::tui::app::App;
use crate::tui::chart;
use crate::tui::runs::list::{Results, cell};
use ratatui::Frame;
use ratatui::layout::{Constraint, Rect};
use ratatui::widgets::{Row, Table};

/// One column: its heading and the run's results.
pub(super) struct Column {
    pub number: u64,
    pub head: String,
    pub results: Results,
    /// The run is still going (its residual is not known yet).
    pub running: bool,
    pub status: String,
}

/// The columns: the baseline, the shown run (kept or still going), then the runs selected in
/// the run list, oldest first.
pub(super) fn columns(app: &App) -> Vec<Column> {
    let base = app.runs.baseline;
    let mut out: Vec<Column> = Vec::new();
    let mut add = |n: u64, results: Results, running: bool, status: String| {
        if out.iter().any(|c| c.number == n && c.running == running) {
            return;
        }
        // a rerun of a kept run's model text goes under its number: `new` beside the kept one
        let head = if running && out.iter().any(|c| c.number == n) {
            format!("#{n} new")
        } else if Some(n) == base && !running {
            format!("#{n} base")
        } else {
            format!("#{n}")
        };
        out.push(Column {
            number: n,
            head,
            results,
            running,
            status,
        });
    };
    if let Some(e) = app.runs.baseline_entry() {
        add(e.number, e.results.clone(), false, e.ended.word().into());
    }
    if let Some(cur) = &app.current {
        match app.runs.get(cur.id) {
            _ if cur.running() => add(cur.id, Results::of(cur), true, "running".into()),
            Some(e) => add(e.number, e.results.clone(), false, e.ended.word().into()),
            None => {}
        }
    }
    for e in app.runs.list.iter().filter(|e| e.overlay) {
        add(e.number, e.results.clone(), false, e.ended.word().into());
    }
    out
}

/// The symbol of a rotation or translation DOF in a row label (`θ` for `*.theta`).
fn short(name: &str) -> String {
    let axis = |a: &str| {
        if a == "theta" {
            "θ".to_string()
        } else {
            a.to_string()
        }
    };
    match name.rsplit_once('.') {
        // the specimen's deck goes without its name; a frame of several keeps it
        Some(("deck", a)) if ["theta", "x", "y"].contains(&a) => axis(a),
        Some((b, a)) if ["theta", "x", "y"].contains(&a) => format!("{b} {}", axis(a)),
        _ if name.is_empty() => "θ".into(),
        _ => name.into(),
    }
}

type Get = Box<dyn Fn(&Column) -> String>;

/// Rows of the comparison: (label, one cell per column), most telling first; lengths in `len`.
pub(super) fn rows(cols: &[Column], len: &str) -> Vec<(String, Vec<String>)> {
    let Some(first) = cols.first() else {
        return Vec::new();
    };
    let rot = short(&first.results.rotation);
    let mut defs: Vec<(String, Get)> = vec![
        (
            format!("peak |{rot}|"),
            Box::new(|c: &Column| cell(c.results.peak_rot)),
        ),
        (
            "  at t [s]".into(),
            Box::new(|c: &Column| cell(c.results.peak_rot_t)),
        ),
        // a run still going has no residual: its last value is not called one
        (
            format!("residual {rot}"),
            Box::new(|c: &Column| {
                if c.running {
                    "…".into()
                } else {
                    cell(c.results.residual_rot)
                }
            }),
        ),
    ];
    // a bridge of several frames: the frame that turns most, as sweeps and suites report it
    if first.results.peak_frames.is_some() {
        let frame = |c: &Column| c.results.peak_frames.clone();
        defs.push((
            "peak |θ| any frame".into(),
            Box::new(move |c: &Column| cell(frame(c).map(|f| f.0))),
        ));
        defs.push((
            "  frame".into(),
            Box::new(move |c: &Column| frame(c).map_or("—".into(), |f| f.1)),
        ));
    }
    defs.extend::<Vec<(String, Get)>>(vec![
        (
            "impacts".into(),
            Box::new(|c: &Column| c.results.impacts.to_string()),
        ),
        (
            "stick [s]".into(),
            Box::new(|c: &Column| cell(c.results.stick_time)),
        ),
        (
            format!("min gap [{len}]"),
            Box::new(|c: &Column| cell(c.results.min_gap)),
        ),
    ]);
    for (i, name) in first.results.translations.iter().enumerate() {
        defs.push((
            format!("peak |{}| [{len}]", short(name)),
            Box::new(move |c: &Column| cell(c.results.peak_xy.get(i).copied().flatten())),
        ));
    }
    defs.push((
        "closure".into(),
        Box::new(|c: &Column| {
            let Some(v) = c.results.closure else {
                return "—".into();
            };
            let v = format!("{} %", chart::fmt_sig(v * 100.0, 2));
            // over its bound (the run failed on it): the bound after `>`
            match c.results.closure_over {
                Some(max) => format!("{v} >{} %", chart::fmt_sig(max * 100.0, 2)),
                None => v,
            }
        }),
    ));
    defs.push((
        "t reached [s]".into(),
        Box::new(|c: &Column| chart::fmt_sig(c.results.t_sim, 4)),
    ));
    defs.push(("status".into(), Box::new(|c: &Column| c.status.clone())));
    defs.into_iter()
        .map(|(label, get)| (label, cols.iter().map(&get).collect()))
        .collect()
}

/// Draws the comparison table in `area` (as many columns as fit, the baseline first).
pub(super) fn draw_compare(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let cols = columns(app);
    // as drawn (ASCII spelled out) before it is measured
    let rows: Vec<(String, Vec<String>)> = rows(&cols, crate::tui::runs::nav::length_unit(app))
        .into_iter()
        .map(|(l, cells)| (th.text(&l), cells.iter().map(|c| th.text(c)).collect()))
        .collect();
    let width = |s: &String| s.chars().count() as u16;
    let label_w = rows.iter().map(|r| width(&r.0)).max().unwrap_or(0);
    // as wide as the widest value, so that none is cut
    let value_w = rows
        .iter()
        .flat_map(|r| r.1.iter())
        .chain(cols.iter().map(|c| &c.head))
        .map(width)
        .max()
        .unwrap_or(4)
        .max(4);
    let room = area.width.saturating_sub(2 + label_w) / (value_w + 1);
    let n = (room as usize).clamp(1, cols.len().max(1));
    let title = if cols.len() > n {
        format!(" runs compared ({n} of {}) ", cols.len())
    } else {
        " runs compared ".to_string()
    };
    let mut widths = vec![Constraint::Length(label_w)];
    widths.extend(std::iter::repeat_n(Constraint::Length(value_w), n));
    let header = Row::new(
        std::iter::once(String::new())
            .chain(cols.iter().take(n).map(|c| c.head.clone()))
            .collect::<Vec<_>>(),
    )
    .style(th.bold());
    let body = rows.into_iter().map(|(label, cells)| {
        Row::new(
            std::iter::once(label)
                .chain(cells.into_iter().take(n))
                .collect::<Vec<_>>(),
        )
    });
    let table = Table::new(body, widths)
        .header(header)
        .block(th.block(th.text(&title)));
    if cols.is_empty() {
        let empty = Table::new(
            [Row::new(vec!["no run kept yet".to_string()])],
            [Constraint::Min(0)],
        )
        .block(th.block(" runs compared "));
        frame.render_widget(empty, area);
        return;
    }
    frame.render_widget(table, area);
}

#[cfg(test)]
mod tests {
    use super::short;

    /// The specimen's deck is the rotation without a name; a bridge of several frames (or a
    /// scene's body) names the body its rows follow.
    #[test]
    fn a_row_names_the_frame_it_follows() {
        let cases = [
            ("deck.theta", "θ"),
            ("deck.x", "x"),
            ("frame1.theta", "frame1 θ"),
            ("frame3.y", "frame3 y"),
            ("block.x", "block x"),
            ("", "θ"),
        ];
        for (name, want) in cases {
            assert_eq!(short(name), want, "{name}");
        }
    }
}
