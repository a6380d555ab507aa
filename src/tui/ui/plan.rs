//! The plan view: the reference geometry (bodies, contact points, abutment faces) with the
//! displacements at the cursor time magnified, stuck and sliding contacts marked.

use super::common::{Theme, shown_run};
use crate::output::ContactState;
use crate::scene::{BodyRef, Contact, Scene};
use crate::tui::app::{App, StatusKind};
use crate::tui::chart::{self, fmt_num};
use crate::tui::runs::data::RunData;
use nalgebra::Vector2;
use ratatui::Frame;
use ratatui::layout::Rect;
use ratatui::style::{Color, Style};
use ratatui::text::Span;
use ratatui::widgets::Paragraph;
use ratatui::widgets::canvas::{Canvas, Context, Line as CLine};

/// Scale factor of the plan view: the largest displacement (or gap) drawn as ~6 % of the view.
fn plan_scale(app: &App, half: f64) -> f64 {
    let Some(scene) = &app.scene else {
        return 1.0;
    };
    let mut d: f64 = 0.0;
    for c in &scene.contacts {
        d = d.max(contact_gap0(scene, c).abs());
    }
    if let Some(r) = shown_run(app) {
        for (k, n) in r.dof_names.iter().enumerate() {
            let m = r.q_peak(k);
            d = d.max(if n.ends_with(".theta") {
                m * half * 0.5
            } else {
                m
            });
        }
    }
    if d <= 0.0 {
        return 1.0;
    }
    let s = 0.06 * half / d;
    let n = chart::nice_factor(s);
    if n > s { n / 2.0 } else { n }.max(1.0)
}

fn body_ref(scene: &Scene, b: BodyRef) -> Vector2<f64> {
    match b {
        BodyRef::Body(i) => scene.bodies[i].reference,
        BodyRef::Ground => Vector2::zeros(),
    }
}

/// Initial gap of a contact (q = 0).
fn contact_gap0(scene: &Scene, c: &Contact) -> f64 {
    let xa = body_ref(scene, c.point_body);
    let xb = body_ref(scene, c.face_body);
    c.face_normal.dot(&(xa + c.point - xb - c.face_point))
}

/// The bodies' configuration at one sample, with displacements magnified by `s`.
struct Pose<'a> {
    scene: &'a Scene,
    run: Option<&'a RunData>,
    idx: Option<usize>,
    s: f64,
    /// Time of the sample (the ground's motion moves driven bodies).
    t: f64,
    /// A mode shape instead of a run's sample: its DOFs' names and amplitudes.
    mode: Option<(&'a [String], &'a [f64])>,
}

impl Pose<'_> {
    /// Displacement (x, y) and rotation of body `b` (a driven body's: its supports' u_g(t)).
    fn disp(&self, b: usize) -> (Vector2<f64>, f64) {
        let body = &self.scene.bodies[b];
        if body.is_driven() {
            let supports = &self.scene.supports;
            let u = body.drive.map(|s| {
                s.and_then(|s| supports.get(s))
                    .map_or(0.0, |s| s.at(self.t).0)
            });
            return (Vector2::new(u[0], u[1]), 0.0);
        }
        let get = |a: usize| -> f64 {
            if let (Some(k), Some((names, phi))) = (body.dofs[a], self.mode) {
                let name = &self.scene.dof_names[k];
                let i = names.iter().position(|n| n == name);
                return i.and_then(|i| phi.get(i).copied()).unwrap_or(0.0);
            }
            match (body.dofs[a], self.run, self.idx) {
                (Some(k), Some(r), Some(i)) => {
                    let name = &self.scene.dof_names[k];
                    r.dof(name)
                        .and_then(|kk| r.q[kk].get(i).copied())
                        .unwrap_or(0.0)
                }
                _ => 0.0,
            }
        };
        (Vector2::new(get(0), get(1)), get(2))
    }

    /// Where point `p` of body `b` is drawn.
    fn place(&self, b: BodyRef, p: Vector2<f64>) -> Vector2<f64> {
        match b {
            BodyRef::Ground => p,
            BodyRef::Body(i) => {
                let (u, th_) = self.disp(i);
                let a = self.s * th_;
                let r = Vector2::new(a.cos() * p.x - a.sin() * p.y, a.sin() * p.x + a.cos() * p.y);
                self.scene.bodies[i].reference + self.s * u + r
            }
        }
    }

    /// Direction `v` of body `b`, rotated.
    fn rot(&self, b: BodyRef, v: Vector2<f64>) -> Vector2<f64> {
        match b {
            BodyRef::Ground => v,
            BodyRef::Body(i) => {
                let a = self.s * self.disp(i).1;
                Vector2::new(a.cos() * v.x - a.sin() * v.y, a.sin() * v.x + a.cos() * v.y)
            }
        }
    }

    /// State of every contact of the scene (open without data).
    fn states(&self) -> Vec<ContactState> {
        (0..self.scene.contacts.len())
            .map(|ci| {
                match (self.run, self.idx) {
                    (Some(r), Some(i)) => r
                        .contact_names
                        .iter()
                        .position(|n| *n == self.scene.contacts[ci].name)
                        .and_then(|k| r.state[k].get(i).copied()),
                    _ => None,
                }
                .unwrap_or(ContactState::Open)
            })
            .collect()
    }
}

/// Centre and half extents (cx, cy, hx, hy) of the view of the reference configuration.
fn view_box(scene: &Scene, inner: Rect) -> (f64, f64, f64, f64) {
    let mut pts: Vec<Vector2<f64>> = scene.bodies.iter().map(|b| b.reference).collect();
    for c in &scene.contacts {
        pts.push(body_ref(scene, c.point_body) + c.point);
    }
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for p in &pts {
        x0 = x0.min(p.x);
        x1 = x1.max(p.x);
        y0 = y0.min(p.y);
        y1 = y1.max(p.y);
    }
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let mut hx = (0.5 * (x1 - x0)).max(0.5 * (y1 - y0)).max(0.5) * 1.2;
    let (w, h) = (inner.width.max(1) as f64, inner.height.max(1) as f64);
    let mut hy = 2.0 * hx * h / w;
    let need_y = (0.5 * (y1 - y0)).max(0.05 * hx) * 1.4;
    if hy < need_y {
        hy = need_y;
        hx = hy * w / (2.0 * h);
        hx = hx.max(0.5 * (x1 - x0) * 1.2);
    }
    (cx, cy, hx, hy)
}

/// Draws the plan view at `tc`: the cursor time, or the instant the readouts hold while a
/// running run is followed ([`super::Cache::readout_time`]).
pub(super) fn draw_plan(frame: &mut Frame, area: Rect, app: &App, tc: f64, th: &Theme) {
    let Some(scene) = &app.scene else {
        frame.render_widget(Paragraph::new("no model").block(th.block(" plan ")), area);
        return;
    };
    let inner = th.block("").inner(area);
    let (cx, cy, hx, hy) = view_box(scene, inner);
    let s = plan_scale(app, hx);
    let run = shown_run(app);
    let idx = run.and_then(|r| chart::at_or_before(&r.t, tc));
    let t = (run.zip(idx))
        .and_then(|(r, i)| r.t.get(i).copied())
        .unwrap_or(tc);
    let pose = Pose {
        scene,
        run,
        idx,
        s,
        t,
        mode: None,
    };
    let states = pose.states();
    let body_color = th.series(0).fg.unwrap_or(Color::Reset);
    let face_color = if th.color { Color::Gray } else { Color::Reset };
    let face_len = 0.06 * hx.max(hy);
    let depth = 0.03 * hx;
    let short = th.text(&format!(" plan ×{} t={} s ", fmt_num(s, 8), fmt_num(tc, 7)));
    // the seat margin when it fits whole
    let title = match seat_margin(scene, run, idx) {
        Some(m) => th.text(&format!(
            " plan ×{} t={} s seat margin {} {} ",
            fmt_num(s, 8),
            fmt_num(tc, 7),
            fmt_num(m, 5),
            crate::tui::runs::nav::length_unit(app)
        )),
        None => short.clone(),
    };
    let title = if title.chars().count() + 2 <= area.width as usize {
        title
    } else {
        short
    };
    let canvas = Canvas::default()
        .block(th.block(title))
        .marker(th.marker())
        .x_bounds([cx - hx, cx + hx])
        .y_bounds([cy - hy, cy + hy])
        .paint(|ctx: &mut Context| {
            paint_faces(ctx, &pose, face_len, depth, face_color);
            ctx.layer();
            paint_bodies(ctx, &pose, hx, body_color);
            paint_contacts(ctx, &pose, &states, th);
            paint_keys(ctx, &pose, tc, th);
        });
    frame.render_widget(canvas, area);
}

/// Draws mode `number`'s shape on the plan: the bodies and abutment faces displaced and
/// rotated by the shape (`names`: its DOFs, `shape`: their amplitudes, largest 1), magnified
/// so that the largest displacement is drawn as a tenth of the view (the factor in the title),
/// over the outline at rest (dimmed; left out without colours, where the two would not be told
/// apart).
pub(super) fn draw_mode_plan(
    frame: &mut Frame,
    area: Rect,
    scene: &Scene,
    (number, names, shape): (usize, &[String], &[f64]),
    th: &Theme,
) {
    let inner = th.block("").inner(area);
    let (cx, cy, hx, hy) = view_box(scene, inner);
    // a rotation counts by the displacement it gives half a view away
    let d = (names.iter().zip(shape))
        .map(|(n, a)| {
            if n.ends_with(".theta") {
                a.abs() * 0.5 * hx
            } else {
                a.abs()
            }
        })
        .fold(0.0, f64::max);
    let s = if d > 0.0 {
        chart::nice_factor(0.1 * hx / d)
    } else {
        1.0
    };
    let at = |s: f64| Pose {
        scene,
        run: None,
        idx: None,
        s,
        t: 0.0,
        mode: Some((names, shape)),
    };
    let (rest, moved) = (at(0.0), at(s));
    let body_color = th.series(0).fg.unwrap_or(Color::Reset);
    let face_color = if th.color { Color::Gray } else { Color::Reset };
    let (face_len, depth) = (0.06 * hx.max(hy), 0.03 * hx);
    let title = th.text(&format!(" mode {number} on the plan ×{} ", fmt_num(s, 8)));
    let canvas = Canvas::default()
        .block(th.block(title))
        .marker(th.marker())
        .x_bounds([cx - hx, cx + hx])
        .y_bounds([cy - hy, cy + hy])
        .paint(|ctx: &mut Context| {
            if th.color {
                paint_faces(ctx, &rest, face_len, depth, Color::DarkGray);
                paint_bodies(ctx, &rest, hx, Color::DarkGray);
                ctx.layer();
            }
            paint_faces(ctx, &moved, face_len, depth, face_color);
            paint_bodies(ctx, &moved, hx, body_color);
        });
    frame.render_widget(canvas, area);
}

/// The smallest seat margin edge − g_N over the seats at sample `idx`.
fn seat_margin(scene: &Scene, run: Option<&RunData>, idx: Option<usize>) -> Option<f64> {
    let (r, i) = (run?, idx?);
    scene
        .seats
        .iter()
        .filter_map(|seat| {
            let name = &scene.contacts.get(seat.contact)?.name;
            let k = r.contact_names.iter().position(|n| n == name)?;
            Some(seat.edge - r.gap[k].get(i)?)
        })
        .min_by(f64::total_cmp)
}

/// The abutment faces (exaggerated gaps) with a block behind each.
fn paint_faces(ctx: &mut Context, pose: &Pose, face_len: f64, depth: f64, color: Color) {
    let (scene, s) = (pose.scene, pose.s);
    for c in &scene.contacts {
        let g0 = contact_gap0(scene, c);
        let fp = body_ref(scene, c.point_body) + c.point
            - s * g0 * c.face_normal
            - body_ref(scene, c.face_body);
        let f = pose.place(c.face_body, fp);
        let n = pose.rot(c.face_body, c.face_normal);
        let t = Vector2::new(-n.y, n.x) * face_len;
        let (a, b) = (f + t, f - t);
        let (a2, b2) = (a - n * depth, b - n * depth);
        for (p, q) in [(a, b), (a, a2), (b, b2), (a2, b2)] {
            ctx.draw(&CLine::new(p.x, p.y, q.x, q.y, color));
        }
    }
}

/// The bodies: a polygon through their contact points and the points of the faces they carry
/// (a frame between two joints: its own corners and the face its neighbour's corners meet),
/// else a cross.
fn paint_bodies(ctx: &mut Context, pose: &Pose, hx: f64, color: Color) {
    let scene = pose.scene;
    for bi in 0..scene.bodies.len() {
        let me = BodyRef::Body(bi);
        let own: Vec<Vector2<f64>> = (scene.contacts.iter())
            .filter(|c| c.point_body == me)
            .map(|c| c.point)
            .collect();
        let mut cps = own.clone();
        cps.extend(
            (scene.contacts.iter())
                .filter(|c| c.face_body == me && matches!(c.point_body, BodyRef::Body(_)))
                .map(|c| c.face_point),
        );
        if cps.len() < 3 {
            cps = own;
        }
        let centre = pose.place(me, Vector2::zeros());
        if cps.len() >= 3 {
            cps.sort_by(|p, q| p.y.atan2(p.x).total_cmp(&q.y.atan2(q.x)));
            for k in 0..cps.len() {
                let p = pose.place(BodyRef::Body(bi), cps[k]);
                let q = pose.place(BodyRef::Body(bi), cps[(k + 1) % cps.len()]);
                ctx.draw(&CLine::new(p.x, p.y, q.x, q.y, color));
            }
        } else if !scene
            .contacts
            .iter()
            .any(|c| c.face_body == BodyRef::Body(bi))
        {
            let e = 0.02 * hx;
            ctx.draw(&CLine::new(
                centre.x - e,
                centre.y,
                centre.x + e,
                centre.y,
                color,
            ));
            ctx.draw(&CLine::new(
                centre.x,
                centre.y - e,
                centre.x,
                centre.y + e,
                color,
            ));
            for p in &cps {
                let q = pose.place(BodyRef::Body(bi), *p);
                ctx.draw(&CLine::new(centre.x, centre.y, q.x, q.y, color));
            }
        }
    }
}

/// Marks the shear keys at their deck points: `k` intact, `X` (`╳`) once failed at the cursor.
fn paint_keys(ctx: &mut Context, pose: &Pose, tc: f64, th: &Theme) {
    use crate::hysteresis::Law;
    use crate::output::EventKind;
    use crate::scene::Attachment;
    let failed_style: Style = th.status(StatusKind::Error);
    let failed_sym = if th.ascii { "X" } else { "╳" };
    for (j, el) in pose.scene.hysteretic.iter().enumerate() {
        if !matches!(el.law.law(), Law::Key { .. }) {
            continue;
        }
        let (body, point) = match el.attachment {
            Attachment::Point { body, point, .. } | Attachment::Relative { body, point, .. } => {
                (body, point)
            }
            Attachment::Rotation { .. } => continue,
        };
        let p = pose.place(BodyRef::Body(body), point);
        let failed = pose.run.is_some_and(|r| {
            (r.events.iter())
                .any(|e| e.kind == EventKind::KeyFailure && e.contact == j && e.t <= tc)
        });
        if failed {
            ctx.print(p.x, p.y, Span::styled(failed_sym, failed_style));
        } else {
            ctx.print(p.x, p.y, Span::raw("k"));
        }
    }
}

/// Marks the contact points that are stuck or closed and sliding.
fn paint_contacts(ctx: &mut Context, pose: &Pose, states: &[ContactState], th: &Theme) {
    let stick_style: Style = th.status(StatusKind::Error);
    let contact_style: Style = th.status(StatusKind::Warn);
    let (stuck_sym, touch_sym) = if th.ascii { ("S", "*") } else { ("■", "●") };
    for (ci, c) in pose.scene.contacts.iter().enumerate() {
        let p = pose.place(c.point_body, c.point);
        match states[ci] {
            ContactState::Stick => ctx.print(p.x, p.y, Span::styled(stuck_sym, stick_style)),
            ContactState::Slide(_) => ctx.print(p.x, p.y, Span::styled(touch_sym, contact_style)),
            ContactState::Open => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Pose;
    use crate::scene::BodyRef;
    use nalgebra::Vector2;

    #[test]
    fn a_driven_wall_is_placed_at_its_supports_motion() {
        let text = r#"
[[support]]
name = "ground"
kind = "harmonic"
amplitude = 0.2
frequency = 0.5
[[body]]
name = "wall"
mass = 0.0
position = [-1.0, 0.5]
drive_x = "ground"
[[body]]
name = "block"
mass = 1.0
dofs = ["x"]
[[contact]]
name = "face"
body = "block"
face_body = "wall"
normal = [1.0, 0.0]
gap = 0.1
"#;
        let scene = crate::model::load_str(text, std::path::Path::new("wall.toml"), &[]).unwrap();
        // a quarter period: u_g = A; magnified 10 times
        let pose = Pose {
            scene: &scene,
            run: None,
            idx: None,
            s: 10.0,
            t: 0.5,
            mode: None,
        };
        let (u, th) = pose.disp(0);
        assert!((u - Vector2::new(0.2, 0.0)).norm() < 1e-15 && th == 0.0);
        let p = pose.place(BodyRef::Body(0), Vector2::new(0.3, 0.0));
        assert!((p - Vector2::new(-1.0 + 10.0 * 0.2 + 0.3, 0.5)).norm() < 1e-14);
        // the block without run data stays at its reference
        assert_eq!(pose.disp(1).0, Vector2::zeros());
    }
}
