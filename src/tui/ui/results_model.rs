//! The results pages computed from the form's model: the modes (periods, participating mass
//! ratios along x, y and θ, the selected mode's shape by DOF in full names and drawn on the
//! plan) and the input
//! records (acceleration and displacement of the selected support, its 5 %-damped
//! pseudo-acceleration spectrum with the first mode's period marked).

use super::common::Theme;
use super::line_plot::{Look, draw_line_plot};
use super::plan::draw_mode_plan;
use crate::plot::{Axis, Chart, RefLine, Series};
use crate::tui::app::App;
use crate::tui::chart::{downsample_minmax, fmt_sig};
use crate::tui::results::{Component, JobState, ModesData, Page, RecordsData};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::text::Line;
use ratatui::widgets::{Paragraph, Wrap};

/// The state line of a model page.
pub(super) fn info(app: &App, page: Page) -> Vec<String> {
    let r = &app.results;
    let stale = |hash: u64| {
        if hash == crate::tui::app::hash_text(&app.draft) {
            String::new()
        } else {
            "the form changed since: Enter recomputes".into()
        }
    };
    let job = match page {
        Page::Modes => r.modes.as_ref().map(|j| {
            (
                j.hash,
                j.running(),
                state_words(&j.state, |m: &ModesData| {
                    let i = r.mode.min(m.periods.len().saturating_sub(1));
                    format!("mode {} of {} (j/k)", i + 1, m.periods.len())
                }),
            )
        }),
        _ => r.records.as_ref().map(|j| {
            (
                j.hash,
                j.running(),
                state_words(&j.state, |d: &RecordsData| {
                    let i = r.record.min(d.components.len().saturating_sub(1));
                    format!("record {} of {} (j/k)", i + 1, d.components.len())
                }),
            )
        }),
    };
    match job {
        None => vec!["not computed: Enter computes it on the form's model".into()],
        Some((hash, true, words)) => vec![words, "Esc cancels".into(), stale(hash)],
        Some((hash, false, words)) => vec![words, stale(hash)],
    }
}

fn state_words<T>(s: &JobState<T>, ready: impl Fn(&T) -> String) -> String {
    match s {
        JobState::Running { done, all } if *all > 0 => format!("computing {done}/{all}…"),
        JobState::Running { .. } => "computing…".into(),
        JobState::Cancelling => "cancelling…".into(),
        JobState::Ready(d) => ready(d),
        JobState::Cancelled => "cancelled: Enter computes it again".into(),
        JobState::Failed(why) => format!("failed: {why}"),
    }
}

/// The page's data, or what to say instead.
fn ready<'a, T>(
    frame: &mut Frame,
    area: Rect,
    s: Option<&'a JobState<T>>,
    th: &Theme,
) -> Option<&'a T> {
    let text = match s {
        Some(JobState::Ready(d)) => return Some(d),
        None => "not computed yet: Enter computes it on the form's model".to_string(),
        Some(JobState::Running { .. } | JobState::Cancelling) => "computing…".into(),
        Some(JobState::Cancelled) => "cancelled: Enter computes it again".into(),
        Some(JobState::Failed(why)) => format!("failed: {why}"),
    };
    note(frame, area, &text, th);
    None
}

/// The height under which the modes page leaves the selected mode's plan out.
const MODE_PLAN_MIN_H: u16 = 6;

/// A ratio in percent, one decimal.
fn pct(x: f64) -> String {
    format!("{:.1}", 100.0 * x)
}

pub(super) fn draw_modes(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let Some(m) = ready(
        frame,
        area,
        app.results.modes.as_ref().map(|j| &j.state),
        th,
    ) else {
        return;
    };
    if m.periods.is_empty() {
        return note(frame, area, "this model has no degrees of freedom", th);
    }
    let sel = app.results.mode.min(m.periods.len() - 1);
    let name_w = m
        .dof_names
        .iter()
        .map(|n| n.chars().count())
        .max()
        .unwrap_or(4);
    let shape_w = (name_w + 9) as u16;
    let [left, right] = Layout::horizontal([
        Constraint::Min(0),
        Constraint::Length(shape_w.min(area.width / 2)),
    ])
    .areas(area);
    let rot = if th.ascii { "Mrot %" } else { "Mθ %" };
    let head = format!(
        "{:>4} {:>9} {:>8} {:>6} {:>6} {:>6}",
        "mode", "T [s]", "f [Hz]", "Mx %", "My %", rot
    );
    let mut lines = vec![Line::styled(head, th.bold())];
    let rows = left.height.saturating_sub(2) as usize;
    let off = sel.saturating_sub(rows.saturating_sub(1));
    for i in (off..m.periods.len()).take(rows) {
        let t = m.periods[i];
        let f = if t.is_finite() { 1.0 / t } else { 0.0 };
        let [x, y, r] = m.ratios[i];
        let row = format!(
            "{:>4} {:>9} {:>8} {:>6} {:>6} {:>6}",
            i + 1,
            fmt_sig(t, 4),
            fmt_sig(f, 4),
            pct(x),
            pct(y),
            pct(r)
        );
        lines.push(if i == sel {
            Line::styled(row, th.selected())
        } else {
            Line::from(row)
        });
    }
    let sums: Vec<f64> = (0..3)
        .map(|k| m.ratios.iter().map(|r| r[k]).sum())
        .collect();
    lines.push(Line::styled(
        format!(
            "{:>4} {:>18} {:>6} {:>6} {:>6}",
            "sum",
            "",
            pct(sums[0]),
            pct(sums[1]),
            pct(sums[2])
        ),
        th.dim(),
    ));
    // the selected mode on the plan under the table, when there is room for it
    let table_h = (lines.len() as u16).min(left.height);
    let [table, below] =
        Layout::vertical([Constraint::Length(table_h), Constraint::Min(0)]).areas(left);
    frame.render_widget(Paragraph::new(lines), table);
    if let Some(scene) = app
        .scene
        .as_ref()
        .filter(|_| below.height >= MODE_PLAN_MIN_H)
    {
        let mode = (sel + 1, m.dof_names.as_slice(), m.shapes[sel].as_slice());
        draw_mode_plan(frame, below, scene, mode, th);
    }
    let mut shape = vec![Line::styled(
        th.text(&format!("shape of mode {}", sel + 1)),
        th.bold(),
    )];
    let w = (right.width as usize).saturating_sub(8).max(1);
    for (n, a) in m.dof_names.iter().zip(&m.shapes[sel]) {
        let a = if a.abs() < 5e-5 { 0.0 } else { *a };
        let name: String = if n.chars().count() > w {
            // a name that does not fit keeps its end (the DOF: x, y, theta)
            let k = n.chars().count() - w;
            n.chars().skip(k).collect()
        } else {
            n.clone()
        };
        shape.push(Line::from(th.text(&format!("{name:<w$} {a:>7.4}"))));
    }
    frame.render_widget(Paragraph::new(shape), right);
}

pub(super) fn draw_records(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let Some(d) = ready(
        frame,
        area,
        app.results.records.as_ref().map(|j| &j.state),
        th,
    ) else {
        return;
    };
    let Some(c) = d
        .components
        .get(app.results.record.min(d.components.len().saturating_sub(1)))
    else {
        let text = if d.harmonic.is_empty() {
            "this model has no support motion".to_string()
        } else {
            format!(
                "harmonic support motion only ({}): no record",
                d.harmonic.join(", ")
            )
        };
        return note(frame, area, &text, th);
    };
    let [left, right] =
        Layout::horizontal([Constraint::Percentage(50), Constraint::Min(0)]).areas(area);
    let [acc, disp] =
        Layout::vertical([Constraint::Percentage(50), Constraint::Min(0)]).areas(left);
    let series = |y: &[f64], width: u16| {
        let t: Vec<f64> = (0..y.len()).map(|i| c.t0 + i as f64 * c.dt).collect();
        let (t0, t1) = (
            t.first().copied().unwrap_or(0.0),
            t.last().copied().unwrap_or(0.0),
        );
        downsample_minmax(&t, y, t0, t1, width as usize * th.per_cell())
    };
    let history = |title: String, mark: char, y: &[f64], area: Rect, k: usize| {
        let t1 = c.t0 + y.len().saturating_sub(1) as f64 * c.dt;
        let mut p = Chart::new(
            "",
            Axis::linear("t [s]", "").with_range(c.t0, t1),
            Axis::linear(&title, ""),
        );
        let points = series(y, area.width);
        p.series.push(Series::line("", points).color(k).glyph(mark));
        p.lines.push(RefLine::horizontal(0.0, "", 7));
        p
    };
    let pa = history(
        format!("{} acceleration [g], PGA {}", c.name, fmt_sig(c.pga_g(), 3)),
        'a',
        &c.acc_g,
        acc,
        0,
    );
    draw_line_plot(frame, acc, &pa, &Look::default(), th);
    let pd = history(
        format!(
            "displacement [{}], PGD {}",
            crate::tui::runs::nav::length_unit(app),
            fmt_sig(c.pgd(), 3)
        ),
        'd',
        &c.disp,
        disp,
        1,
    );
    draw_line_plot(frame, disp, &pd, &Look::default(), th);
    let (spectrum, look) = spectrum_plot(c, d.t1);
    draw_line_plot(frame, right, &spectrum, &look, th);
}

/// The spectrum of a component with T₁ marked (a vertical line and a stem to Sa(T₁)).
fn spectrum_plot(c: &Component, t1: f64) -> (Chart, Look) {
    let title = if t1.is_finite() {
        format!(
            "Sa 5 % [g]; T1 {} s: Sa {} g",
            fmt_sig(t1, 3),
            fmt_sig(c.sa_t1, 3)
        )
    } else {
        "Sa 5 % [g]".to_string()
    };
    let mut p = Chart::new("", Axis::log("T [s], log", ""), Axis::linear(&title, ""));
    p.series
        .push(Series::line("", c.spectrum.clone()).color(2).glyph('s'));
    let mut look = Look::default();
    if t1.is_finite() {
        p.lines.push(RefLine::vertical(t1, "T1", 7));
        look.stems.push((t1, c.sa_t1));
        look.stem_mark = '*';
    }
    (p, look)
}

/// A sentence in place of a page's chart.
pub(super) fn note(frame: &mut Frame, area: Rect, text: &str, th: &Theme) {
    let p = Paragraph::new(th.text(text)).wrap(Wrap { trim: true });
    frame.render_widget(p, area);
}
