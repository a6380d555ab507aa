//! Events of a run as the cursor meets them: in time order, the next and previous event
//! instant, what happened at an instant, the state of each contact at the cursor and the last
//! impact before it. Used by `]`/`[`, the event list and the readouts.

use crate::output::{ContactState, EventKind, EventRecord};
use crate::tui::app::App;
use crate::tui::chart;
use crate::tui::eng;
use crate::tui::runs::data::RunData;
use crate::units::Quantity;

/// The events' indices in time order (events of one instant keep their order).
pub fn in_time_order(run: &RunData) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..run.events.len()).collect();
    if !run.events.windows(2).all(|w| w[0].t <= w[1].t) {
        idx.sort_by(|&a, &b| run.events[a].t.total_cmp(&run.events[b].t));
    }
    idx
}

/// The distinct instants of the run's events, increasing.
pub fn event_times(run: &RunData) -> Vec<f64> {
    let mut t: Vec<f64> = run
        .events
        .iter()
        .map(|e| e.t)
        .filter(|t| t.is_finite())
        .collect();
    t.sort_by(f64::total_cmp);
    t.dedup();
    t
}

/// The first event instant after `t`.
pub fn next_time(run: &RunData, t: f64) -> Option<f64> {
    let times = event_times(run);
    times.get(times.partition_point(|&x| x <= t)).copied()
}

/// The last event instant before `t`.
pub fn prev_time(run: &RunData, t: f64) -> Option<f64> {
    let times = event_times(run);
    times
        .partition_point(|&x| x < t)
        .checked_sub(1)
        .map(|i| times[i])
}

/// Force unit of the model's numbers: a bridge file's from its `units` (kN in SI-kN, N in SI,
/// kip in kip-in), one deck or several frames; none for a scene file, whose forces are its
/// author's.
pub fn force_unit(app: &App) -> &'static str {
    match &app.scene {
        Some(s) if s.bridge => s.units.unit(Quantity::Force),
        _ => "",
    }
}

/// Length unit of the model's numbers, from its `units` (m; in for kip-in).
pub fn length_unit(app: &App) -> &'static str {
    let sys = app.scene.as_ref().map(|s| s.units).unwrap_or_default();
    sys.unit(Quantity::Length)
}

/// The model's units of length, force and energy for the time charts (a scene file's force
/// and energy: none, its author's).
pub fn units(app: &App) -> crate::tui::chart_prefs::Units {
    let force = force_unit(app);
    let energy = match &app.scene {
        Some(s) if s.bridge => s.units.unit(Quantity::Energy),
        _ => "",
    };
    crate::tui::chart_prefs::Units {
        length: length_unit(app),
        force,
        energy,
    }
}

/// Who an event is about: its contact, or for a key failure its element.
pub fn subject(run: &RunData, e: &EventRecord) -> String {
    let names = if e.kind == EventKind::KeyFailure {
        &run.element_names
    } else {
        &run.contact_names
    };
    names
        .get(e.contact)
        .cloned()
        .unwrap_or_else(|| format!("#{}", e.contact + 1))
}

/// The normal impulse of an impact with its unit (`1.234 kN·s`; `force`: the model's force
/// unit, [`force_unit`], none when empty); None for other events.
pub fn impulse(e: &EventRecord, force: &str, ascii: bool) -> Option<String> {
    (e.kind == EventKind::Impact && e.normal.is_finite()).then(|| {
        let dot = if ascii { "*" } else { "·" };
        let unit = if force.is_empty() {
            String::new()
        } else {
            format!("{force}{dot}s")
        };
        eng::eng(e.normal, &unit, ascii)
    })
}

/// One event in words: `left_top impact 1.234 kN·s`.
pub fn describe(run: &RunData, e: &EventRecord, force: &str, ascii: bool) -> String {
    let mut s = format!("{} {}", subject(run, e), e.kind.label());
    if let Some(i) = impulse(e, force, ascii) {
        s.push(' ');
        s.push_str(&i);
    }
    s
}

/// A time as the event readouts print it (6 significant digits: events are exact instants).
pub fn fmt_time(t: f64) -> String {
    chart::fmt_sig(t, 6)
}

/// The status line after a jump to the events at `t`: their numbers among all the run's
/// events in time order (as the event list and the header count them: `event 4/148`, or
/// `events 4–5/148` for two at one instant), the time, and each event in words.
pub fn jump_status(run: &RunData, t: f64, force: &str, ascii: bool) -> String {
    let order = in_time_order(run);
    let first = order.partition_point(|&i| run.events[i].t < t);
    let here = order[first..]
        .iter()
        .take_while(|&&i| run.events[i].t == t)
        .count();
    let what: Vec<String> = (order[first..first + here].iter())
        .map(|&i| describe(run, &run.events[i], force, ascii))
        .collect();
    let dash = if ascii { "-" } else { "–" };
    let which = match here {
        0 | 1 => format!("event {}", first + 1),
        n => format!("events {}{dash}{}", first + 1, first + n),
    };
    format!(
        "{which}/{} at t = {} s: {}",
        run.events.len(),
        fmt_time(t),
        what.join(", ")
    )
}

/// The row of the event list at time `tc`: the last event at or before it (in time order).
pub fn row_at(order: &[usize], run: &RunData, tc: f64) -> Option<usize> {
    order
        .partition_point(|&i| run.events[i].t <= tc)
        .checked_sub(1)
}

/// The first row of the event list at time `t` exactly (or the row at `t`).
pub fn first_row_at(order: &[usize], run: &RunData, t: f64) -> Option<usize> {
    let i = order.partition_point(|&i| run.events[i].t < t);
    if i < order.len() && run.events[order[i]].t == t {
        Some(i)
    } else {
        row_at(order, run, t)
    }
}

/// The state of contact `i` at time `tc` (the last sample at or before it).
pub fn state_at(run: &RunData, i: usize, tc: f64) -> Option<ContactState> {
    let k = chart::at_or_before(&run.t, tc)?;
    run.state.get(i)?.get(k).copied()
}

/// The last impact at or before `tc`.
pub fn last_impact(run: &RunData, tc: f64) -> Option<&EventRecord> {
    run.events
        .iter()
        .filter(|e| e.kind == EventKind::Impact && e.t <= tc)
        .max_by(|a, b| a.t.total_cmp(&b.t))
}

/// The state of every contact at `tc` in words, each as one item: all of them
/// (`left_top stick`, `left_bottom open`, …) when `all`, else the closed ones and `others open`
/// (or `all open`).
pub fn contact_items(run: &RunData, tc: f64, all: bool) -> Vec<String> {
    let states: Vec<(usize, ContactState)> = (0..run.contact_names.len())
        .filter_map(|i| state_at(run, i, tc).map(|s| (i, s)))
        .collect();
    let item = |&(i, s): &(usize, ContactState)| format!("{} {}", run.contact_names[i], s.label());
    if all {
        return states.iter().map(item).collect();
    }
    let closed: Vec<String> = states
        .iter()
        .filter(|(_, s)| *s != ContactState::Open)
        .map(item)
        .collect();
    let mut out = closed.clone();
    if closed.is_empty() && !states.is_empty() {
        out.push("all open".into());
    } else if closed.len() < states.len() {
        out.push("others open".into());
    }
    out
}
