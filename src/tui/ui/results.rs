//! The results pages of the studies view: their names in the list, the state line, and the
//! two pages of the current run, the energy ledger over time and the contact forces and
//! impulses of one corner (the modes and the records: `results_model.rs`).

use super::common::{Theme, fit, shown_run};
use super::line_plot::{Look, draw_line_plot};
use super::results_model::{draw_modes, draw_records, note};
use crate::output::EventKind;
use crate::plot::{Axis, Chart, RefLine, Series};
use crate::tui::app::App;
use crate::tui::chart::{downsample_minmax, fmt_sig};
use crate::tui::results::run::{ResultUnits, TERMS, units};
use crate::tui::results::{JobState, Page};
use crate::tui::runs::data::RunData;
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::Line;
use ratatui::widgets::{Block, Borders, Paragraph};

/// The marks of the ledger's terms, in [`TERMS`]' order.
pub(super) const TERM_MARKS: [char; 8] = ['I', 'K', 'E', 'D', 'H', 'F', 'X', 'C'];

/// The page's state in a word or two (the list of studies and pages).
pub(super) fn state(app: &App, page: Page) -> String {
    fn job<T>(s: Option<&JobState<T>>) -> String {
        match s {
            None => "not computed".into(),
            Some(JobState::Running { .. }) => "computing".into(),
            Some(JobState::Cancelling) => "cancelling".into(),
            Some(JobState::Ready(_)) => "done".into(),
            Some(JobState::Cancelled) => "cancelled".into(),
            Some(JobState::Failed(_)) => "failed".into(),
        }
    }
    match page {
        Page::Modes => job(app.results.modes.as_ref().map(|j| &j.state)),
        Page::Records => job(app.results.records.as_ref().map(|j| &j.state)),
        _ => match app.current.as_ref() {
            Some(r) if r.running() => "running".into(),
            Some(r) => r.label.split(' ').take(2).collect::<Vec<_>>().join(" "),
            None => "no run".into(),
        },
    }
}

/// Draws page `page` below the list of the studies view: its state line and its panel.
pub(super) fn draw_page(
    frame: &mut Frame,
    line: Rect,
    panel: Rect,
    app: &App,
    page: Page,
    th: &Theme,
) {
    let u = model_units(app);
    let items = info(app, page, &u, th);
    frame.render_widget(
        Paragraph::new(Line::from(fit(&items, th.sep(), line.width as usize))),
        line,
    );
    let title = match page {
        Page::Energy => format!("energy ledger over time [{}]", u.energy),
        Page::Contacts => "contact forces and impulses per corner".into(),
        Page::Modes => "modes of the form's model (K0, M; contacts open)".into(),
        Page::Records => "input records and the 5 % response spectrum".into(),
    };
    let block = Block::new()
        .borders(Borders::TOP)
        .border_set(th.border())
        .border_style(th.dim())
        .title(Line::styled(th.text(&title), th.bold()));
    let inner = block.inner(panel);
    frame.render_widget(block, panel);
    let run = shown_run(app);
    match (page, run) {
        (Page::Energy, Some(r)) if !r.t.is_empty() => draw_energy(frame, inner, r, &u, th),
        (Page::Contacts, Some(r)) if !r.t.is_empty() && !r.contact_names.is_empty() => {
            draw_contacts(frame, inner, r, (app.results.contact, &u), th)
        }
        (Page::Modes, _) => draw_modes(frame, inner, app, th),
        (Page::Records, _) => draw_records(frame, inner, app, th),
        (Page::Contacts, Some(r)) if r.contact_names.is_empty() => {
            note(frame, inner, "this model has no contacts", th)
        }
        _ => note(
            frame,
            inner,
            "no run yet: r runs the model, its samples are drawn here as they come",
            th,
        ),
    }
}

/// The units of the form's model (its `units` key; SI-kN when it does not load).
fn model_units(app: &App) -> ResultUnits {
    units(app.scene.as_ref().map(|s| s.units).unwrap_or_default())
}

/// The page's state line, items in order of importance.
fn info(app: &App, page: Page, u: &ResultUnits, th: &Theme) -> Vec<String> {
    let run = shown_run(app);
    let items: Vec<String> = match (page, run) {
        (Page::Energy, Some(r)) => {
            let closure = r.results.max_closure();
            let rel = r.summary.as_ref().map_or(String::new(), |s| {
                format!("rel {}", fmt_sig(s.energy_closure_rel, 3))
            });
            let input = r.results.ledger.terms[0].last().copied().unwrap_or(0.0);
            vec![
                format!(
                    "{}: max |closure| {} {}",
                    r.label,
                    fmt_sig(closure, 3),
                    u.energy
                ),
                rel,
                format!("input {} {}", fmt_sig(input, 4), u.energy),
            ]
        }
        (Page::Contacts, Some(r)) if !r.contact_names.is_empty() => {
            let i = app.results.contact.min(r.contact_names.len() - 1);
            let peak = r.results.forces.normal[i]
                .iter()
                .fold(0.0f64, |m, x| m.max(x.abs()));
            let imp = (r.events.iter())
                .filter(|e| e.kind == EventKind::Impact && e.contact == i)
                .fold(0.0f64, |m, e| m.max(e.normal));
            vec![
                format!(
                    "{} ({}/{})",
                    r.contact_names[i],
                    i + 1,
                    r.contact_names.len()
                ),
                format!("{} impacts", r.impacts.get(i).copied().unwrap_or(0)),
                format!("max λN {} {}", fmt_sig(peak, 3), u.force),
                format!("max ΛN {} {}", fmt_sig(imp, 3), u.impulse),
                "j/k corner".into(),
            ]
        }
        (Page::Modes | Page::Records, _) => super::results_model::info(app, page),
        _ => vec!["no run yet".into()],
    };
    items.iter().map(|i| th.text(i)).collect()
}

/// Columns of (t, y) for a plot `width` cells wide (min–max per column).
fn decimate(r: &RunData, y: &[f64], width: u16, th: &Theme) -> Vec<(f64, f64)> {
    let (t0, t1) = (
        r.t.first().copied().unwrap_or(0.0),
        r.t.last().copied().unwrap_or(0.0),
    );
    downsample_minmax(&r.t, y, t0, t1, width as usize * th.per_cell())
}

fn draw_energy(frame: &mut Frame, area: Rect, r: &RunData, u: &ResultUnits, th: &Theme) {
    let [t0, t1] = time_range(r);
    let mut p = Chart::new(
        "",
        Axis::linear("t [s]", "").with_range(t0, t1),
        Axis::linear(&format!("energy [{}]", u.energy), ""),
    );
    for (k, col) in r.results.ledger.terms.iter().enumerate() {
        let points = decimate(r, col, area.width, th);
        p.series
            .push(Series::line(TERMS[k], points).color(k).glyph(TERM_MARKS[k]));
    }
    p.lines.push(RefLine::horizontal(0.0, "", 7));
    draw_line_plot(frame, area, &p, &Look::default(), th);
}

/// The run's time span: 0 to its last sample.
fn time_range(r: &RunData) -> [f64; 2] {
    [0.0, r.t.last().copied().unwrap_or(0.0).max(r.t_sim)]
}

fn draw_contacts(
    frame: &mut Frame,
    area: Rect,
    r: &RunData,
    (selected, u): (usize, &ResultUnits),
    th: &Theme,
) {
    let i = selected.min(r.contact_names.len() - 1);
    let [top, bottom] =
        Layout::vertical([Constraint::Percentage(55), Constraint::Min(0)]).areas(area);
    let f = &r.results.forces;
    let [t0, t1] = time_range(r);
    let time = || Axis::linear("t [s]", "").with_range(t0, t1);
    let title = format!("{} forces [{}]", r.contact_names[i], u.force);
    let mut p = Chart::new("", time(), Axis::linear(&title, ""));
    for (k, (name, mark, col)) in [
        ("λN normal", 'N', &f.normal[i]),
        ("λT friction", 'T', &f.tangential[i]),
    ]
    .into_iter()
    .enumerate()
    {
        let points = decimate(r, col, top.width, th);
        p.series
            .push(Series::line(name, points).color(k).glyph(mark));
    }
    p.lines.push(RefLine::horizontal(0.0, "", 7));
    draw_line_plot(frame, top, &p, &Look::default(), th);
    let title = format!("impulses at impacts ΛN [{}], | each impact", u.impulse);
    let s = Chart::new("", time(), Axis::linear(&title, ""));
    let look = Look {
        stems: (r.events.iter())
            .filter(|e| e.kind == EventKind::Impact && e.contact == i)
            .map(|e| (e.t, e.normal))
            .collect(),
        ..Look::default()
    };
    if look.stems.is_empty() {
        note(frame, bottom, "no impact at this corner", th);
    } else {
        draw_line_plot(frame, bottom, &s, &look, th);
    }
}
