//! What the run info (`i`) says of a run: gathered from the run going or the kept run, its
//! method and step from the model text it ran.

use crate::methods::Method;
use crate::tui::app::App;
use crate::tui::form;
use crate::tui::runs::data::RunStatus;
use crate::tui::runs::info::Info;
use crate::tui::runs::list::{Ended, cell};

/// The info of run `n`: the run going when it is shown, else the kept run (None: no such
/// run). The method and step come from the model text it ran (compiled here, as the form
/// validates it).
pub(super) fn of(app: &App, n: u64) -> Option<Info> {
    let live = app.current.as_ref().filter(|c| c.id == n && c.running());
    let kept = app.runs.get(n);
    let (status, reason, text) = match (live, kept) {
        (Some(c), _) => {
            let text = app.runs.started.as_ref().map(|(_, t)| t.clone());
            let s = if c.status == RunStatus::Cancelling {
                "cancelling"
            } else {
                "running"
            };
            (s.to_string(), None, text)
        }
        (None, Some(e)) => {
            let s = match &e.ended {
                Ended::Finished => "finished".to_string(),
                Ended::Cancelled => "cancelled".to_string(),
                Ended::Failed(_) => e.ended.short(),
                Ended::Inaccurate(_) => "finished outside its accuracy bounds (inexact)".into(),
            };
            (
                s,
                e.ended.reason().map(str::to_string),
                Some(e.model.clone()),
            )
        }
        (None, None) => {
            let c = app.current.as_ref().filter(|c| c.id == n)?;
            let reason = match &c.status {
                RunStatus::Failed(f) => Some(f.to_string()),
                _ => None,
            };
            let s = match &c.status {
                RunStatus::Finished => "finished",
                RunStatus::Failed(_) => "failed",
                _ => "cancelled",
            };
            (s.to_string(), reason, None)
        }
    };
    let data = live.or(kept.map(|e| &e.data));
    let name = kept.map_or(String::new(), |e| format!(" {}", e.name));
    let mut rows = vec![("status".to_string(), status)];
    rows.push(("reason".into(), reason.unwrap_or_else(|| "—".into())));
    if let Some(d) = data {
        let t_sim = kept.map_or(d.t_sim, |e| e.results.t_sim);
        let pct = if d.t_end > 0.0 {
            format!(" ({:.0} %)", 100.0 * t_sim / d.t_end)
        } else {
            String::new()
        };
        rows.push((
            "time reached".into(),
            format!("t = {t_sim:.4} s of {} s{pct}", d.t_end),
        ));
        if let Some(k) = d.steps {
            rows.push(("steps taken".into(), k.to_string()));
        }
    }
    let (method, step) = match text.as_deref() {
        Some(t) if t == app.draft && app.scene.is_some() => method_step(app.scene.as_ref()),
        Some(t) => method_step(form::validate(t, &app.path).ok().as_ref()),
        None => method_step(None),
    };
    rows.push(("method".into(), method));
    rows.push(("step".into(), step));
    if let Some(e) = kept {
        let r = &e.results;
        rows.push(("peak |θ|".into(), cell(r.peak_rot)));
        rows.push(("impacts".into(), r.impacts.to_string()));
        rows.push(("events".into(), r.events.to_string()));
        if let Some(d) = &app.runs.dir {
            rows.push(("files".into(), format!("{}/{:04}.*", d.display(), n)));
        }
    }
    Some(Info {
        number: n,
        title: format!("#{n}{name}"),
        rows,
    })
}

/// The method's name and the step it ran with, from the compiled model (`—` without one).
fn method_step(scene: Option<&crate::scene::Scene>) -> (String, String) {
    let Some(s) = scene.map(|s| &s.settings) else {
        return ("—".into(), "—".into());
    };
    let method = format!("{} ({})", s.method.title(), s.method.name());
    let step = match s.method {
        Method::Event => {
            let h_max = if s.h_max > 0.0 {
                format!("{:e} s", s.h_max)
            } else {
                "none".into()
            };
            format!(
                "adaptive (DP5): rtol {:e}, atol {:e}, h_max {h_max}",
                s.rtol, s.atol
            )
        }
        _ => match &s.step_chosen {
            Some(why) => format!("{:.4e} s, chosen from {why}", s.step),
            None => format!("{:e} s (solver.step)", s.step),
        },
    };
    (method, step)
}
