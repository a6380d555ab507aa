//! The header line (file, title, view, run progress) and the model error banner.

use super::common::{Theme, cut_words};
use crate::tui::app::{App, LoadError, StatusKind, View};
use crate::tui::runs::data::RunStatus;
use crate::tui::studies::short_title;
use ratatui::Frame;
use ratatui::layout::{Alignment, Constraint, Layout, Rect};
use ratatui::style::Color;
use ratatui::text::{Line, Span};
use ratatui::widgets::Paragraph;

/// A progress bar of `width` cells.
fn gauge(frac: f64, width: usize, ascii: bool) -> String {
    let frac = frac.clamp(0.0, 1.0);
    let cells = frac * width as f64;
    let full = cells.floor() as usize;
    let mut s = String::new();
    if ascii {
        s.push('[');
        s.push_str(&"#".repeat(full));
        s.push_str(&" ".repeat(width - full));
        s.push(']');
    } else {
        const PART: [&str; 8] = ["", "▏", "▎", "▍", "▌", "▋", "▊", "▉"];
        s.push('▕');
        s.push_str(&"█".repeat(full));
        let mut used = full;
        if full < width {
            let p = ((cells - full as f64) * 8.0).floor() as usize;
            if p > 0 {
                s.push_str(PART[p]);
                used += 1;
            }
        }
        s.push_str(&" ".repeat(width - used));
        s.push('▏');
    }
    s
}

/// The run's progress, or how it ended.
fn run_progress(app: &App, th: &Theme) -> Line<'static> {
    let Some(r) = &app.current else {
        return Line::styled("no run", th.dim());
    };
    let ev = r.events.len();
    let label = format!("#{}", r.id);
    match &r.status {
        RunStatus::Running | RunStatus::Cancelling => {
            let mut spans = vec![
                Span::styled(label, th.bold()),
                Span::raw(" "),
                Span::styled(
                    gauge(r.t_sim / r.t_end.max(1e-300), 10, th.ascii),
                    th.fg(Color::Cyan),
                ),
                Span::raw(th.text(&format!(
                    " {}/{} s · {ev} events",
                    fmt_t(r.t_sim),
                    fmt_t(r.t_end)
                ))),
            ];
            if r.status == RunStatus::Cancelling {
                spans.push(Span::styled(
                    th.text(" · cancelling"),
                    th.status(StatusKind::Warn),
                ));
            }
            Line::from(spans)
        }
        RunStatus::Finished => Line::from(vec![
            Span::styled(label, th.bold()),
            Span::styled(" done", th.status(StatusKind::Ok)),
            Span::raw(th.text(&format!(" · {} s · {ev} events", fmt_t(r.t_sim)))),
        ]),
        RunStatus::Cancelled => Line::from(vec![
            Span::styled(label, th.bold()),
            Span::styled(
                format!(" cancelled at {} s", fmt_t(r.t_sim)),
                th.status(StatusKind::Warn),
            ),
        ]),
        RunStatus::Failed(e) if crate::tui::runs::list::is_inaccurate(e) => Line::from(vec![
            Span::styled(label, th.bold()),
            Span::styled(
                " done, outside its accuracy bounds",
                th.status(StatusKind::Warn),
            ),
            Span::raw(th.text(&format!(" · {} s · {ev} events", fmt_t(r.t_sim)))),
        ]),
        RunStatus::Failed(_) => Line::from(vec![
            Span::styled(label, th.bold()),
            Span::styled(
                format!(" failed at {} s", fmt_t(r.t_sim)),
                th.status(StatusKind::Error),
            ),
        ]),
    }
}

fn fmt_t(t: f64) -> String {
    format!("{t:.2}")
}

/// The running study and its progress (`PGA 5/14 · `), if any.
fn study_progress(app: &App, th: &Theme) -> Option<Vec<Span<'static>>> {
    let (k, e) = app.studies.running()?;
    let (done, all) = e.progress();
    let text = if all > 0 {
        format!("{} {done}/{all}", short_title(k))
    } else {
        format!("{} …", short_title(k))
    };
    Some(vec![
        Span::styled(th.text(&text), th.fg(Color::Magenta)),
        Span::styled(th.sep(), th.dim()),
    ])
}

/// Draws the header line.
pub(super) fn draw_header(frame: &mut Frame, area: Rect, app: &App, th: &Theme) {
    let mut right = run_progress(app, th);
    if let Some(mut spans) = study_progress(app, th) {
        let w: usize = spans.iter().map(Span::width).sum();
        if right.width() + w <= (area.width * 3 / 5) as usize {
            spans.append(&mut right.spans);
            right = Line::from(spans);
        }
    }
    let rw = (right.width() as u16).min(area.width * 3 / 5);
    let [l, r] = Layout::horizontal([Constraint::Min(0), Constraint::Length(rw + 1)]).areas(area);
    let mut name = app.file_name();
    if app.dirty() {
        name.push_str(" [+]");
    }
    let view = match app.view {
        View::Charts => "charts",
        View::Form => "form",
        View::Studies => "studies",
        View::Runs => "runs",
    };
    let bar = th.text(" │ ");
    let fixed = 8 + 3 + name.chars().count() + 3 + 3 + view.len();
    let room = (l.width as usize).saturating_sub(fixed);
    // the title cut after a whole word, or left out; then the name of the program, the file
    let title = cut_words(&th.text(&app.title()), room, &th.text("…"));
    let brand = Span::styled("deckspin", th.bold().patch(th.fg(Color::Cyan)));
    let file = Span::styled(name, th.bold());
    let lines = [
        vec![
            brand.clone(),
            Span::styled(bar.clone(), th.dim()),
            file.clone(),
        ],
        vec![file],
        vec![brand],
        vec![],
    ];
    let mut left = lines
        .into_iter()
        .map(|mut spans| {
            if !title.is_empty() && spans.len() == 3 {
                spans.extend([
                    Span::styled(bar.clone(), th.dim()),
                    Span::raw(title.clone()),
                ]);
            }
            let sep = if spans.is_empty() { "" } else { bar.as_str() };
            spans.push(Span::styled(format!("{sep}{view}"), th.dim()));
            Line::from(spans)
        })
        .skip_while(|line| line.width() > l.width as usize);
    let left = left.next().unwrap_or_default();
    frame.render_widget(Paragraph::new(left), l);
    frame.render_widget(Paragraph::new(right).alignment(Alignment::Right), r);
}

/// Draws the banner of a model that does not load: message, source line, caret.
pub(super) fn draw_error(frame: &mut Frame, area: Rect, le: &LoadError, th: &Theme) {
    let err = th.status(StatusKind::Error);
    let title = match (le.line, le.column) {
        (Some(l), Some(c)) => {
            format!(" model error at line {l}, column {c} — showing the last good model ")
        }
        _ => " model error — showing the last good model ".to_string(),
    };
    let block = th
        .block(Line::styled(th.text(&title), err))
        .border_style(err);
    let inner = block.inner(area);
    let mut lines = vec![Line::styled(le.detail.clone(), err)];
    if let (Some(l), Some(src)) = (le.line, &le.source_line) {
        let prefix = th.text(&format!("{l:>5} │ "));
        lines.push(Line::from(vec![
            Span::styled(prefix.clone(), th.dim()),
            Span::raw(src.clone()),
        ]));
        if let Some(c) = le.column {
            let pad = prefix.chars().count() + src.chars().take(c.saturating_sub(1)).count();
            lines.push(Line::styled(format!("{}^", " ".repeat(pad)), err));
        }
    }
    frame.render_widget(block, area);
    frame.render_widget(Paragraph::new(lines), inner);
}
