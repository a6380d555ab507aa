//! The form view: the parameters in groups (a header per group, folding), the search being
//! typed, and the selected field's details (label, place in the file, type, unit and the units
//! it takes, saved value, comment, live verdict while typing); the list of models to open.

use super::common::Theme;
use super::side::draw_summary;
use super::studies::draw_picker;
use crate::tui::app::{App, Mode, StatusKind};
use crate::tui::form::model_files::folder_of;
use crate::tui::form::{self, Field, Row};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::{Color, Style};
use ratatui::text::{Line, Span};
use ratatui::widgets::{Paragraph, Wrap};
use std::path::PathBuf;

/// The narrowest value column (`(default)` fits).
const VALUE_MIN: usize = 9;
/// The widest unit column (wider units are not drawn in the list; the detail shows them).
const UNIT_MAX: usize = 12;

/// Draws the form view.
pub(super) fn draw_form(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let left_w = (area.width * 55 / 100).max(34);
    let [left, right] =
        Layout::horizontal([Constraint::Length(left_w), Constraint::Min(0)]).areas(area);
    let title = if app.dirty() {
        " parameters — edited (* unsaved; s saves) "
    } else {
        " parameters "
    };
    let block = th.block(th.text(title));
    let mut inner = block.inner(left);
    frame.render_widget(block, left);
    if let Mode::Search { query, .. } = &app.mode {
        let [list, prompt] =
            Layout::vertical([Constraint::Min(0), Constraint::Length(1)]).areas(inner);
        inner = list;
        let n = app.form.fields.iter().filter(|f| f.matches(query)).count();
        let found = match n {
            _ if query.is_empty() => String::new(),
            0 => "  no match".into(),
            1 => "  1 match".into(),
            n => format!("  {n} matches"),
        };
        let line = Line::from(vec![
            Span::styled(format!("/{query}_"), th.bold()),
            Span::styled(found, th.dim()),
        ]);
        frame.render_widget(Paragraph::new(line), prompt);
    }
    frame.render_widget(Paragraph::new(list_lines(app, inner, th)), inner);

    let sum_h = if right.height >= 20 { 9 } else { 0 };
    let [detail, sum] =
        Layout::vertical([Constraint::Min(0), Constraint::Length(sum_h)]).areas(right);
    draw_field_detail(frame, detail, app, th);
    if sum_h > 0 {
        draw_summary(frame, sum, app, th);
    }
}

/// A unit as the list shows it (none for a list of words).
fn unit_shown(f: &Field, th: &Theme) -> String {
    if f.unit.contains('|') {
        String::new()
    } else {
        th.text(&f.unit)
    }
}

/// The rows of the parameter list that fit `area`, the selection in view.
fn list_lines<'a>(app: &App, area: Rect, th: &Theme) -> Vec<Line<'a>> {
    let form = &app.form;
    if form.fields.is_empty() {
        return vec![Line::from("the file is not valid TOML: nothing to edit")];
    }
    let rows = form.rows();
    let height = area.height as usize;
    let sel = form.row(&rows);
    let off = sel
        .saturating_sub(height / 2)
        .min(rows.len().saturating_sub(height));
    let lw = (area.width as usize).saturating_sub(1);
    let count = |s: &str| s.chars().count();
    let unit_w = (form.fields.iter())
        .map(|f| count(&unit_shown(f, th)))
        .filter(|&w| w <= UNIT_MAX)
        .max()
        .unwrap_or(0);
    let longest = (form.fields.iter())
        .map(|f| count(&th.text(&f.label)))
        .max()
        .unwrap_or(0);
    let label_w = longest
        .min(lw.saturating_sub(unit_w + VALUE_MIN + 2))
        .max(6);
    let value_w = lw.saturating_sub(label_w + unit_w + 2);
    let mut lines = Vec::new();
    for (k, row) in rows.iter().enumerate().skip(off).take(height) {
        let selected = k == sel;
        let line = match *row {
            Row::Header(first) => header_line(app, first, lw, th),
            Row::Field(i) => {
                let f = &form.fields[i];
                let editing = selected && matches!(app.mode, Mode::Editing { .. });
                let value = match (&app.mode, editing) {
                    (Mode::Editing { buffer, .. }, true) => format!("{buffer}_"),
                    _ => f.value.clone().unwrap_or_else(|| "(default)".into()),
                };
                let value = th.text(&value);
                // too wide: the text typed keeps its end, a value its start marked cut
                let value: String = match count(&value) {
                    n if n <= value_w => value,
                    n if editing => value.chars().skip(n - value_w).collect(),
                    _ => {
                        let cut = th.text("…");
                        let keep = value_w.saturating_sub(count(&cut));
                        let head: String = value.chars().take(keep).collect();
                        format!("{head}{cut}")
                    }
                };
                let label = short_label(f, label_w, th);
                let unit = unit_shown(f, th);
                // a value typed with its own unit ("20 mm_") is not followed by the field's
                let own_unit = match &app.mode {
                    Mode::Editing { buffer, .. } if editing => {
                        crate::tui::form::units::carries_unit(buffer)
                    }
                    _ => false,
                };
                let unit = if own_unit || count(&unit) > unit_w {
                    String::new()
                } else {
                    unit
                };
                let mark = if f.edited() { "*" } else { " " };
                let text = format!("{mark}{label:<label_w$} {value:>value_w$} {unit:<unit_w$}");
                let mut style = if f.curated {
                    Style::default()
                } else {
                    th.dim()
                };
                if f.edited() {
                    style = style.patch(th.fg(Color::Yellow));
                }
                Line::styled(text, style)
            }
        };
        lines.push(if selected {
            line.patch_style(th.selected())
        } else {
            line
        });
    }
    lines
}

/// A field's label fitted to `width`: the group's word dropped first when the label starts
/// with it (the header above says it), then [`form::fit_label`].
fn short_label(f: &Field, width: usize, th: &Theme) -> String {
    let label = th.text(&f.label);
    if label.chars().count() <= width {
        return label;
    }
    let rest = label
        .strip_prefix(&format!("{} ", f.group))
        .filter(|r| !r.starts_with(|c: char| c.is_ascii_digit()));
    form::fit_label(rest.unwrap_or(&label), width)
}

/// A group's header row: its fold mark, title, number of fields and of edited ones.
fn header_line<'a>(app: &App, first: usize, width: usize, th: &Theme) -> Line<'a> {
    let form = &app.form;
    let g = &form.fields[first].group;
    let members = form.fields.iter().filter(|f| f.group == *g);
    let (n, edited) = members.fold((0, 0), |(n, e), f| (n + 1, e + usize::from(f.edited())));
    let folded = form.folded.contains(g);
    let mark = match (folded, th.ascii) {
        (true, false) => "▸",
        (false, false) => "▾",
        (true, true) => ">",
        (false, true) => "v",
    };
    let edits = if edited > 0 {
        format!(", {edited} edited")
    } else {
        String::new()
    };
    let text = format!("{mark} {} ({n}{edits})", form::group_title(g));
    let text: String = text.chars().take(width + 1).collect();
    let mut style = th.bold();
    if edited > 0 {
        style = style.patch(th.fg(Color::Yellow));
    }
    Line::styled(text, style)
}

/// Draws the selected field's details (or the selected group's).
fn draw_field_detail(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let block = th.block(" field ");
    let Some(f) = app.form.selected() else {
        let lines = group_detail(app, th);
        let p = Paragraph::new(lines).wrap(Wrap { trim: false });
        frame.render_widget(p.block(th.block(" group ")), area);
        return;
    };
    let sys = app
        .scene
        .as_ref()
        .map(|s| s.units)
        .unwrap_or_else(|| form_system(app));
    let unit = match f.unit.as_str() {
        "" | "–" | "#" => String::new(),
        "mixed" => format!(
            ", absolute, each state component in its own unit: {} (displacements), rad \
             (rotations), {} and rad/s (velocities)",
            sys.unit(crate::units::Quantity::Length),
            sys.unit(crate::units::Quantity::Velocity)
        ),
        u if u.contains('|') => format!(": {}", u.replace('|', ", ")),
        u => format!(", {u} ({sys})"),
    };
    let mut lines = vec![
        Line::styled(th.text(&f.label), th.bold()),
        Line::styled(
            format!("in the file: {}", form::place_of(&f.path)),
            th.dim(),
        ),
        Line::from(th.text(&format!("{}{unit}", f.kind.name()))),
    ];
    let others = crate::tui::form::units::others_taken(f.dim, sys);
    if f.kind == form::Kind::Float && !others.is_empty() {
        lines.push(Line::styled(
            th.text(&format!("also takes {}", others.join(", "))),
            th.dim(),
        ));
    }
    lines.push(Line::from(vec![
        Span::styled("saved: ", th.dim()),
        Span::raw(
            th.text(
                &f.saved
                    .clone()
                    .unwrap_or_else(|| "(absent: default)".into()),
            ),
        ),
    ]));
    if f.edited() {
        lines.push(Line::from(vec![
            Span::styled("draft: ", th.dim()),
            Span::styled(
                th.text(&f.value.clone().unwrap_or_else(|| "(absent)".into())),
                th.fg(Color::Yellow),
            ),
        ]));
    }
    match &app.mode {
        Mode::Editing { buffer, check } => {
            lines.push(Line::from(vec![
                Span::styled("> ", th.bold()),
                Span::raw(th.text(&format!("{buffer}_"))),
            ]));
            match check {
                Ok(()) => lines.push(Line::styled(
                    th.text("✓ valid — Enter accepts"),
                    th.status(StatusKind::Ok),
                )),
                Err(e) => {
                    let prefix = format!("{}:", app.path.display());
                    let short = e
                        .strip_prefix(&prefix)
                        .map_or(e.clone(), |r| format!("at {r}"));
                    lines.push(Line::styled(
                        th.text(&format!("✗ {short}")),
                        th.status(StatusKind::Error),
                    ));
                }
            }
        }
        _ => lines.push(Line::styled(
            th.text("Enter edits · u reverts · s saves · r runs"),
            th.dim(),
        )),
    }
    if !f.note.is_empty() {
        lines.push(Line::from(""));
        lines.push(Line::styled(th.text(&format!("# {}", f.note)), th.dim()));
    }
    frame.render_widget(
        Paragraph::new(lines)
            .wrap(Wrap { trim: false })
            .block(block),
        area,
    );
}

/// The unit system the draft declares (when no version of the model has compiled).
fn form_system(app: &App) -> crate::units::UnitSystem {
    app.draft
        .parse::<toml_edit::DocumentMut>()
        .map(|d| form::system_of(&d))
        .unwrap_or_default()
}

/// The selected group: its fields, the edited ones, the keys.
fn group_detail<'a>(app: &App, th: &Theme) -> Vec<Line<'a>> {
    let form = &app.form;
    let Some(g) = form.group() else {
        return Vec::new();
    };
    let fields: Vec<&Field> = form.fields.iter().filter(|f| f.group == g).collect();
    let edited = fields.iter().filter(|f| f.edited()).count();
    let folded = form.folded.contains(g);
    let mut lines = vec![
        Line::styled(form::group_title(g), th.bold()),
        Line::from(format!(
            "{} fields, {edited} edited{}",
            fields.len(),
            if folded { ", folded" } else { "" }
        )),
        Line::styled(
            th.text(if folded {
                "Enter/z unfolds · Z unfolds all"
            } else {
                "Enter/z folds · Z folds all"
            }),
            th.dim(),
        ),
        Line::from(""),
    ];
    for f in fields.iter().filter(|f| f.edited()).take(6) {
        let v = f.value.clone().unwrap_or_else(|| "(absent)".into());
        lines.push(Line::styled(
            th.text(&format!("* {} = {v}", f.label)),
            th.fg(Color::Yellow),
        ));
    }
    lines
}

/// Draws the list of models to open, named from the model's folder.
pub(super) fn draw_model_picker(
    frame: &mut Frame,
    area: Rect,
    app: &App,
    files: &[PathBuf],
    selected: usize,
    th: &Theme,
) {
    let dir = folder_of(&app.path);
    let names: Vec<PathBuf> = files
        .iter()
        .map(|p| p.strip_prefix(&dir).map_or(p.clone(), |r| r.to_path_buf()))
        .collect();
    let title = format!(" open a model of {} ", dir.display());
    draw_picker(frame, area, &title, &names, selected, th);
}
