//! The time charts' keys: the chart in focus (`1`/`2`/`3`), the list of series to pick from
//! (`p`: type to filter, Space shows or hides one), the y zoom (`Y`/`y`), the log scale (`g`)
//! and θ's unit (`d`); what changes is stored beside the model ([`crate::tui::chart_prefs`]).

use crate::tui::app::{App, Mode, StatusKind};
use crate::tui::chart_prefs::{self, CHARTS};
use crate::tui::keymap::Action;
use crate::tui::msg::Effect;
use crate::tui::runs::series;

/// The keys of the time charts and of their list of series.
pub(super) fn chart_action(app: &mut App, a: Action) -> Vec<Effect> {
    use Action as A;
    let k = app.charts.focus.min(CHARTS - 1);
    match a {
        A::FocusChart1 | A::FocusChart2 | A::FocusChart3 => {
            let k = [A::FocusChart1, A::FocusChart2, A::FocusChart3]
                .iter()
                .position(|x| *x == a)
                .unwrap_or(0);
            app.charts.focus = k;
            let m = format!(
                "chart {} in focus: p picks its series, Y/y zooms its y axis, g its log scale",
                k + 1
            );
            app.set_status(StatusKind::Info, m);
            Vec::new()
        }
        A::PickSeries => open_list(app, k),
        A::YZoomIn | A::YZoomOut => {
            let c = &mut app.charts.charts[k];
            c.y_zoom = if a == A::YZoomIn {
                (c.y_zoom + 1).min(30)
            } else {
                c.y_zoom.saturating_sub(1)
            };
            let m = match c.y_zoom {
                0 => format!("chart {}: the y axis fits the data", k + 1),
                z => format!("chart {}: y zoom ×{}", k + 1, 1u64 << z),
            };
            app.generation += 1;
            app.set_status(StatusKind::Info, m);
            Vec::new()
        }
        A::LogScale => {
            app.charts.charts[k].log = !app.charts.charts[k].log;
            let m = if app.charts.charts[k].log {
                let zeros = zeros_in(app, k);
                let left = if zeros > 0 {
                    format!(" ({zeros} samples at 0 left out)")
                } else {
                    String::new()
                };
                format!("chart {}: log scale of |value|{left}", k + 1)
            } else {
                format!("chart {}: linear scale", k + 1)
            };
            app.generation += 1;
            app.set_status(StatusKind::Info, m);
            store(app)
        }
        A::ThetaUnit => {
            app.charts.theta = app.charts.theta.next();
            let m = format!("θ in {}", app.charts.theta.name(app.ascii));
            app.generation += 1;
            app.set_status(StatusKind::Info, m);
            store(app)
        }
        A::SeriesUp => move_selection(app, -1),
        A::SeriesDown => move_selection(app, 1),
        A::SeriesPageUp => move_selection(app, -10),
        A::SeriesPageDown => move_selection(app, 10),
        A::SeriesToggle => toggle(app),
        A::SeriesClose => {
            app.mode = Mode::Normal;
            app.set_status(StatusKind::Info, "list of series closed");
            Vec::new()
        }
        A::SeriesBackspace => {
            if let Mode::ChartPick {
                query, selected, ..
            } = &mut app.mode
            {
                query.pop();
                *selected = 0;
            }
            Vec::new()
        }
        A::SeriesDefaults => {
            let Mode::ChartPick { chart, .. } = app.mode else {
                return Vec::new();
            };
            app.charts.charts[chart].series = None;
            app.generation += 1;
            let m = format!("chart {}: its default series", chart + 1);
            app.set_status(StatusKind::Info, m);
            store(app)
        }
        _ => Vec::new(),
    }
}

/// `p`: the list of the series of the run shown, for chart `k`.
fn open_list(app: &mut App, k: usize) -> Vec<Effect> {
    if app.current.is_none() {
        app.set_status(StatusKind::Info, "no run yet: r runs the model");
        return Vec::new();
    }
    app.mode = Mode::ChartPick {
        chart: k,
        query: String::new(),
        selected: 0,
    };
    let m = format!(
        "chart {} series: type to filter, ↑↓ select, Space shows or hides, Enter closes",
        k + 1
    );
    app.set_status(StatusKind::Info, m);
    Vec::new()
}

/// A character typed into the list's filter.
pub(super) fn type_char(app: &mut App, c: char) {
    if let Mode::ChartPick {
        query, selected, ..
    } = &mut app.mode
    {
        query.push(c);
        *selected = 0;
    }
}

fn move_selection(app: &mut App, by: i64) -> Vec<Effect> {
    let n = match (&app.mode, &app.current) {
        (Mode::ChartPick { query, .. }, Some(run)) => chart_prefs::matching(run, query).len(),
        _ => 0,
    };
    if let Mode::ChartPick { selected, .. } = &mut app.mode {
        *selected = (*selected as i64 + by).clamp(0, n.saturating_sub(1) as i64) as usize;
    }
    Vec::new()
}

/// Space: the selected series shown in the chart, or no longer; one of another unit takes
/// the place of the chart's series (a chart has one y axis).
fn toggle(app: &mut App) -> Vec<Effect> {
    let (
        Mode::ChartPick {
            chart,
            query,
            selected,
        },
        Some(run),
    ) = (&app.mode, &app.current)
    else {
        return Vec::new();
    };
    let chart = *chart;
    let Some(id) = chart_prefs::matching(run, query).get(*selected).cloned() else {
        app.set_status(StatusKind::Info, "no series matches the filter");
        return Vec::new();
    };
    let mut list = app.charts.series(run, chart);
    let before = series::title(&list);
    let m = if let Some(i) = list.iter().position(|x| *x == id) {
        list.remove(i);
        format!("chart {}: {} hidden", chart + 1, id.label())
    } else if list.first().is_some_and(|f| f.dim() != id.dim()) {
        list = vec![id.clone()];
        format!(
            "chart {}: {} in place of {before} (another unit: one y axis per chart)",
            chart + 1,
            id.label()
        )
    } else {
        list.push(id.clone());
        format!("chart {}: {} shown", chart + 1, id.label())
    };
    let c = &mut app.charts.charts[chart];
    c.series = Some(list);
    c.y_zoom = 0;
    app.generation += 1;
    app.set_status(StatusKind::Info, m);
    store(app)
}

/// The samples at exactly 0 of chart `k`'s series in the run shown (a log scale leaves them
/// out).
fn zeros_in(app: &App, k: usize) -> usize {
    let Some(run) = &app.current else {
        return 0;
    };
    (app.charts.series(run, k).iter())
        .filter_map(|id| series::column(run, id))
        .map(|c| c.iter().filter(|v| **v == 0.0).count())
        .sum()
}

/// Stores the preferences beside a model opened from its file.
fn store(app: &App) -> Vec<Effect> {
    if app.runs.dir.is_none() {
        return Vec::new();
    }
    vec![Effect::StoreCharts {
        path: chart_prefs::path(&app.path),
        text: app.charts.to_text(),
    }]
}

/// The preferences were stored, or not.
pub(super) fn on_stored(app: &mut App, r: Result<(), String>) -> Vec<Effect> {
    if let Err(e) = r {
        let m = format!("the charts' series are not stored: {e}");
        app.set_status(StatusKind::Warn, m);
    }
    Vec::new()
}
