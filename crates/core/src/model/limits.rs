//! Checks of the compiled scene as a whole, where a setting is judged against the model: the
//! run length against the records, the output step against the run, the tolerances against
//! the gaps, the fixed step against the fastest dynamics (docs/engine.md, bad input).

use super::check::{Check, ModelError};
use super::warnings::ModelWarning;
use crate::methods::Method;
use crate::modal::{modes, omega_max, omega_max_closed};
use crate::run::{OutputBudget, OutputEstimate};
use crate::scene::{Motion, Scene};

/// Free vibration after the end of the longest record when `solver.t_end` is absent, s: at
/// 2 % damping a 0.3 s mode keeps 12 % of its amplitude after 5 s and a 2 s (full-scale) mode
/// has made 2.5 cycles, so the peaks of the free vibration after the record are inside.
pub const FREE_VIBRATION_TAIL: f64 = 5.0;

/// A tolerance on gaps (`gap_tol`, `atol`) must be at most this fraction of the smallest
/// positive initial gap, and `velocity_tol` this fraction of the speed of a fundamental-mode
/// oscillation with that gap as amplitude (gap·ω₁): three digits of the quantity it decides on.
pub(crate) const TOLERANCE_FRACTION: f64 = 1e-3;

/// What to do with an explicit step above its stability limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum StepLimit {
    /// Refuse it (every entry but the studies').
    Refuse,
    /// Accept it with a warning (studies that map where methods fail).
    Warn,
}

/// What the file said, as far as the checks need it.
pub(super) struct Given {
    /// A `[solver]` table is present.
    pub solver: bool,
    /// `solver.t_end` is present.
    pub t_end: bool,
    /// `solver.max_events` is present.
    pub max_events: bool,
    /// `solver.max_steps` is present.
    pub max_steps: bool,
    /// `solver.step` is present.
    pub step: bool,
    /// `solver.contact_stiffness` is present.
    pub contact_stiffness: bool,
    /// `solver.max_closure` and `solver.max_penetration` are present.
    pub max_closure: bool,
    pub max_penetration: bool,
    /// A bridge file (else a scene file): the fields to blame.
    pub bridge: bool,
    pub step_limit: StepLimit,
}

/// The checks in order: run length (may set `t_end`), output step, tolerances, fixed step.
pub(super) fn finish(
    scene: &mut Scene,
    given: &Given,
    ck: &Check,
    warnings: &mut Vec<ModelWarning>,
) -> Result<(), ModelError> {
    run_length(scene, given, ck, warnings);
    if !given.max_events {
        scene.settings.max_events = default_max_events(scene);
    }
    if !given.max_steps {
        scene.settings.max_steps = step_limit(scene.settings.t_end);
    }
    let st = &scene.settings;
    if st.output_dt > st.t_end {
        let (dt, t) = (st.output_dt, st.t_end);
        return Err(ck.err(
            "solver.output_dt",
            format!("must be ≤ solver.t_end = {t} s, got {dt} s"),
        ));
    }
    tolerances(scene, ck, warnings)?;
    resolution(scene, given.bridge, ck)?;
    initial_penetration(scene, given.bridge, ck)?;
    if scene.settings.method != Method::Event {
        if scene.settings.method.compliant_contact()
            && !given.contact_stiffness
            && let Some(k) = chosen_contact_stiffness(scene)
        {
            scene.settings.contact_stiffness = k;
        }
        if !given.step {
            let (step, why) = chosen_step(scene);
            scene.settings.step = step;
            scene.settings.step_chosen = Some(why);
        }
        let (closure, penetration) = method_bounds(scene);
        if !given.max_closure {
            scene.settings.max_closure = closure;
        }
        if !given.max_penetration {
            scene.settings.max_penetration = penetration;
            // without a positive gap to measure it by: by the run's own motion
            if scene.settings.method == Method::Moreau && smallest_positive_gap(scene).is_none() {
                scene.settings.max_penetration_of_peak = Some(MOREAU_PENETRATION_OF_PEAK);
            }
        }
    }
    fixed_step(scene, given.step_limit, ck, warnings)
}

/// Steps per period of the fastest dynamics a fixed-step method chooses when `solver.step` is
/// absent: Moreau–Jean [`MOREAU_STEPS_PER_PERIOD`] of K₀'s shortest period (it is first order;
/// contacts are impulses, not springs), Newmark [`PENALTY_STEPS_PER_PERIOD`] and the central
/// difference [`EXPLICIT_STEPS_PER_PERIOD`] of the shortest period with every contact closed
/// at `contact_stiffness` (well inside the explicit scheme's limit 2/ω, which is T/π). On the
/// four-span bridge each lands within 1 % of the event-driven peak rotation
/// (`docs/engine.md`, "Fixed-step methods by default").
pub(crate) const MOREAU_STEPS_PER_PERIOD: f64 = 100.0;
/// Steps per shortest period of the Newmark penalty method's default step.
pub(crate) const PENALTY_STEPS_PER_PERIOD: f64 = 16.0;
/// Steps per shortest period of the explicit penalty method's default step.
pub(crate) const EXPLICIT_STEPS_PER_PERIOD: f64 = 25.0;
/// The implicit methods (Moreau–Jean, Newmark) take at most this many steps per output
/// interval when they choose their step: they are stable at any step, and dynamics faster than
/// that are not in the output.
pub(crate) const IMPLICIT_STEPS_PER_OUTPUT: f64 = 50.0;
/// Steps over the run when the scene has no stiffness to take a period from (at most one
/// output interval each).
pub(crate) const STEPS_WITHOUT_STIFFNESS: f64 = 5000.0;

/// The step of a fixed-step method when the model sets none, and how it was chosen: from the
/// fastest dynamics (`MOREAU_STEPS_PER_PERIOD`, `PENALTY_STEPS_PER_PERIOD`), at most the
/// sample interval of a recorded support motion, at least `t_end`/10⁷.
pub(crate) fn chosen_step(scene: &Scene) -> (f64, String) {
    let st = &scene.settings;
    let (omega, per, what) = match st.method {
        Method::Moreau | Method::Event => (
            omega_max(scene),
            MOREAU_STEPS_PER_PERIOD,
            "K₀'s shortest period".to_string(),
        ),
        Method::Penalty | Method::PenaltyExplicit => (
            omega_max_closed(scene, st.contact_stiffness),
            if st.method == Method::Penalty {
                PENALTY_STEPS_PER_PERIOD
            } else {
                EXPLICIT_STEPS_PER_PERIOD
            },
            format!(
                "the shortest period with every contact closed at contact_stiffness {:.4e}",
                st.contact_stiffness
            ),
        ),
    };
    let (mut h, mut why) = if omega.is_finite() && omega > 0.0 {
        let period = std::f64::consts::TAU / omega;
        (period / per, format!("{what} {period:.4e} s / {per}"))
    } else {
        let h = (st.t_end / STEPS_WITHOUT_STIFFNESS).min(st.output_dt);
        (
            h,
            format!(
                "t_end / {STEPS_WITHOUT_STIFFNESS}, at most solver.output_dt (no stiffness to take a period from)"
            ),
        )
    };
    let dt = (scene.supports.iter())
        .filter_map(|s| match &s.motion {
            Motion::Record(g) => Some(g.dt),
            Motion::Harmonic { .. } => None,
        })
        .fold(f64::INFINITY, f64::min);
    if dt < h {
        (h, why) = (dt, format!("the records' sample interval {dt:e} s"));
    }
    // the implicit methods are stable at any step: dynamics faster than the output's are left
    // unresolved rather than paid for
    let implicit = matches!(st.method, Method::Moreau | Method::Penalty);
    let output_floor = st.output_dt / IMPLICIT_STEPS_PER_OUTPUT;
    if implicit && h < output_floor {
        (h, why) = (
            output_floor,
            format!("solver.output_dt / {IMPLICIT_STEPS_PER_OUTPUT}, above {why}"),
        );
    }
    let floor = st.t_end / 1e7;
    if h < floor {
        (h, why) = (floor, "t_end / 10⁷".to_string());
    }
    // a step that divides t_end evenly is what the methods take
    let n = (st.t_end / h).ceil().max(1.0);
    let h = st.t_end / n;
    (
        h,
        format!(
            "{} chose solver.step = {h:.4e} s ({why}; {n} steps); set solver.step to choose another",
            st.method.name()
        ),
    )
}

/// The contact frequency of the penalty methods' gap elements when `solver.contact_stiffness`
/// is absent, in multiples of K₀'s highest frequency: the contacts' compliance then leaves the
/// structure's modes alone.
pub(crate) const CONTACT_FREQUENCY_RATIO: f64 = 10.0;
/// Moreau–Jean's penetration bound when the scene has no positive gap: this fraction of the
/// run's largest translation.
pub(crate) const MOREAU_PENETRATION_OF_PEAK: f64 = 0.01;
/// Moreau–Jean's penetration bound: this fraction of the smallest positive initial gap.
pub(crate) const MOREAU_PENETRATION_OF_GAP: f64 = 0.05;

/// The gap elements' stiffness when the model sets none: m_eff (CONTACT_FREQUENCY_RATIO ω_max)²
/// with m_eff = 1/(W_Nᵀ M⁻¹ W_N) the lightest contact's effective mass and ω_max K₀'s highest
/// frequency; none (the default stays) for a scene without stiffness.
pub(crate) fn chosen_contact_stiffness(scene: &Scene) -> Option<f64> {
    let omega = omega_max(scene);
    if !(omega.is_finite() && omega > 0.0) {
        return None;
    }
    let fr = scene.frame(0.0, &scene.q0, &scene.v0);
    let m_eff = (scene.contacts.iter())
        .map(|c| {
            let w = &scene.contact_kinematics(&fr, c).w_n;
            let inv: f64 = (w.iter().zip(scene.mass.iter()))
                .map(|(w, m)| w * w / m)
                .sum();
            1.0 / inv
        })
        .filter(|m| m.is_finite() && *m > 0.0)
        .min_by(f64::total_cmp)?;
    let k = m_eff * (CONTACT_FREQUENCY_RATIO * omega).powi(2);
    k.is_finite().then_some(k)
}

/// The accuracy bounds of a method when the model sets none: (max_closure, max_penetration).
/// Event-driven: 10⁻³ and 10⁻⁶ m (the defaults). Moreau–Jean and the explicit penalty scheme are
/// first order in energy (an impact's work is taken at the step's velocities; a gap element
/// switches on and off inside a step): closure 10⁻¹; Moreau–Jean's penetration is O(h ġ_N):
/// [`MOREAU_PENETRATION_OF_GAP`] of the smallest positive initial gap (without one,
/// [`MOREAU_PENETRATION_OF_PEAK`] of the run's largest translation, judged after the run). Newmark's average acceleration is second order:
/// closure 10⁻². The penalty methods are not judged on penetration (it is their contact law).
pub(crate) fn method_bounds(scene: &Scene) -> (f64, f64) {
    let st = &scene.settings;
    match st.method {
        Method::Event => (st.max_closure, st.max_penetration),
        Method::Moreau => {
            let gap = smallest_positive_gap(scene)
                .map_or(st.max_penetration, |g| MOREAU_PENETRATION_OF_GAP * g);
            (0.1, gap.max(st.max_penetration))
        }
        Method::PenaltyExplicit => (0.1, st.max_penetration),
        Method::Penalty => (0.01, st.max_penetration),
    }
}

/// The smallest positive initial gap of the scene's contacts.
fn smallest_positive_gap(scene: &Scene) -> Option<f64> {
    let fr = scene.frame(0.0, &scene.q0, &scene.v0);
    (scene.contacts.iter())
        .map(|c| scene.contact_kinematics(&fr, c).gap)
        .filter(|g| *g > 0.0 && g.is_finite())
        .min_by(f64::total_cmp)
}

/// Events a run may log per simulated second when `solver.max_events` is absent: a light
/// abutment rattling against the deck at ε = 1 makes about 21 000 per second under the
/// far-field records (docs/robustness.md).
pub(crate) const EVENTS_PER_SECOND: f64 = 50_000.0;
/// The event limit when `solver.max_events` is absent: at least 200 000, at most 5·10⁶ (an
/// event record is 88 bytes, two history rows).
pub(crate) const EVENT_LIMIT: (usize, usize) = (200_000, 5_000_000);

/// `solver.max_events` absent: [`EVENTS_PER_SECOND`] × `t_end` within [`EVENT_LIMIT`].
pub fn event_limit(t_end: f64) -> usize {
    per_second(EVENTS_PER_SECOND, EVENT_LIMIT, t_end)
}

/// `solver.max_events` absent: [`event_limit`], and no more than the default history budget
/// leaves for events (two rows each) after the output grid, so that the limit the file did not
/// set never refuses a run (a bridge of 8 frames, 31 s: 1.55·10⁶ events of 6.5 kB rows would
/// be 2.04·10¹⁰ bytes). A grid alone above the budget is refused by `run::check_output`.
fn default_max_events(scene: &Scene) -> usize {
    let limit = event_limit(scene.settings.t_end);
    let est = OutputEstimate::of(scene);
    let budget = OutputBudget::default();
    let room =
        ((budget.max_rows.min(budget.max_bytes / est.row_bytes) - est.grid_rows) / 2.0).floor();
    if room >= 1.0 && room < limit as f64 {
        room as usize
    } else {
        limit
    }
}

/// Steps a run may take per simulated second when `solver.max_steps` is absent: the bridge
/// needs 220 per second at ε = 0 and up to 14 000 with a light abutment rattling at ε = 1; a
/// scene far faster than that fails with its step count instead of running for minutes.
pub(crate) const STEPS_PER_SECOND: f64 = 200_000.0;
/// The step limit when `solver.max_steps` is absent: at least 10⁶, at most 5·10⁷.
pub(crate) const STEP_LIMIT: (usize, usize) = (1_000_000, 50_000_000);

/// `solver.max_steps` absent: [`STEPS_PER_SECOND`] × `t_end` within [`STEP_LIMIT`].
pub fn step_limit(t_end: f64) -> usize {
    per_second(STEPS_PER_SECOND, STEP_LIMIT, t_end)
}

/// ⌈rate × t_end⌉ within [lo, hi] (lo for a NaN t_end).
fn per_second(rate: f64, (lo, hi): (usize, usize), t_end: f64) -> usize {
    let n = (rate * t_end).ceil();
    if n.is_nan() {
        return lo;
    }
    (n.min(hi as f64) as usize).max(lo)
}

/// The support whose record ends last, and when.
fn longest_record(scene: &Scene) -> Option<(String, f64)> {
    let mut best: Option<(String, f64)> = None;
    for s in &scene.supports {
        if let Motion::Record(m) = &s.motion
            && best.as_ref().is_none_or(|b| m.end_time() > b.1)
        {
            best = Some((s.name.clone(), m.end_time()));
        }
    }
    best
}

/// `t_end` absent: the end of the longest record plus [`FREE_VIBRATION_TAIL`] (else the
/// default); given but shorter than a record: said.
fn run_length(scene: &mut Scene, given: &Given, ck: &Check, warnings: &mut Vec<ModelWarning>) {
    let path = ck.path.to_path_buf();
    let longest = longest_record(scene);
    let st = &mut scene.settings;
    match longest {
        Some((field, record_end)) if given.t_end && record_end > st.t_end => {
            warnings.push(ModelWarning::RecordCut {
                path: path.clone(),
                line: ck.line("solver.t_end"),
                t_end: st.t_end,
                record_end,
                field,
            });
        }
        Some((field, record_end)) if !given.t_end => {
            st.t_end = record_end + FREE_VIBRATION_TAIL;
            warnings.push(ModelWarning::TEndFromRecords {
                path: path.clone(),
                t_end: st.t_end,
                record_end,
                tail: FREE_VIBRATION_TAIL,
                field,
            });
        }
        None if given.solver && !given.t_end => warnings.push(ModelWarning::TEndDefault {
            path: path.clone(),
            t_end: st.t_end,
        }),
        _ => {}
    }
    if !given.solver {
        let t_end = st.t_end;
        warnings.insert(0, ModelWarning::NoSolver { path, t_end });
    }
}

/// Rounding of a coordinate x after the pose arithmetic, in ulp(x): a gap is resolved to
/// `gap_tol` only while 640 ε |x| ≤ gap_tol / 10 (7 km at the default 1e-9 m).
pub(crate) const ROUNDING_ULPS: f64 = 640.0;
/// Largest ratio of two body masses: the impact LCP's Delassus matrix has a condition number
/// of that order, and at 1e12 it keeps 4 of the 16 digits.
pub(crate) const MAX_MASS_RATIO: f64 = 1e12;

/// What double precision can resolve: contact points and faces within the reach where
/// rounding stays below `gap_tol` ([`ROUNDING_ULPS`]); initial speeds at which an event located
/// to `event_time_tol` penetrates at most `gap_tol` (speed × event_time_tol ≤ gap_tol); body
/// masses within [`MAX_MASS_RATIO`].
fn resolution(scene: &Scene, bridge: bool, ck: &Check) -> Result<(), ModelError> {
    let st = &scene.settings;
    let reach = st.gap_tol / (ROUNDING_ULPS * f64::EPSILON);
    let mut arm = vec![0.0f64; scene.bodies.len()];
    for (i, c) in scene.contacts.iter().enumerate() {
        let (p, f) = (c.point.norm(), c.face_point.norm());
        if let crate::scene::BodyRef::Body(b) = c.point_body {
            arm[b] = arm[b].max(p);
        }
        let x = p.max(f);
        if x.is_nan() || x > reach {
            let field = match (bridge, p >= f) {
                (true, _) => match c.point_body {
                    crate::scene::BodyRef::Body(b) if scene.bodies[b].name != "deck" => {
                        format!("frame.{}.length", b - 1)
                    }
                    _ => "deck.length".to_string(),
                },
                (false, true) => format!("contact.{i}.point"),
                (false, false) => format!("contact.{i}.gap"),
            };
            return Err(ck.err(
 &field,
 format!(
 "contact '{}' lies {x:.3e} m from its body's centre: rounding there ({ROUNDING_ULPS} ulp = {:.1e} m) is above solver.gap_tol / 10 = {:.1e} m, so its gap cannot be resolved (at most {reach:.3e} m at this gap_tol)",
 c.name,
 ROUNDING_ULPS * f64::EPSILON * x,
 st.gap_tol / 10.0
 ),
 ));
        }
    }
    let v_max = st.gap_tol / st.event_time_tol;
    for (i, b) in scene.bodies.iter().enumerate() {
        let v = |a: usize| b.dofs[a].map_or(0.0, |d| scene.v0[d]);
        let speed = v(0).hypot(v(1)) + v(2).abs() * arm[i];
        if (speed.is_nan() || speed > v_max) && !bridge {
            return Err(ck.err(
 &format!("body.{i}.initial_velocity"),
 format!(
 "body '{}' starts at {speed:.3e} m/s (at its contact points): an event located to solver.event_time_tol = {:e} s would leave up to {:.3e} m of penetration, above solver.gap_tol = {:e} m (at most {v_max:.3e} m/s)",
 b.name,
 st.event_time_tol,
 speed * st.event_time_tol,
 st.gap_tol
 ),
 ));
        }
    }
    // the masses a contact impulse meets: m of each body with DOFs, and I/r² at its farthest
    // contact point (a deck of 1e-9 t·m² with corners 16 m out sank 2.3 cm at 1e-2 t)
    let mut masses: Vec<(f64, String, String)> = Vec::new();
    for (i, b) in scene.bodies.iter().enumerate() {
        let field = |k: &str| match bridge {
            true if b.name == "deck" => format!("deck.{k}"),
            true if b.name.ends_with("_abutment") => format!("abutment.{k}"),
            true => format!("frame.{}.{k}", i - 1),
            false => format!("body.{i}.{k}"),
        };
        if b.mass > 0.0 && !b.has_no_dofs() {
            masses.push((b.mass, field("mass"), format!("'{}' mass", b.name)));
        }
        if b.dofs[2].is_some() && b.inertia > 0.0 && arm[i] > 0.0 {
            let m = b.inertia / (arm[i] * arm[i]);
            let what = format!("'{}' inertia / (contact arm {:.4e} m)²", b.name, arm[i]);
            masses.push((m, field("inertia"), what));
        }
    }
    let heavy = masses.iter().max_by(|a, b| a.0.total_cmp(&b.0));
    let light = masses.iter().min_by(|a, b| a.0.total_cmp(&b.0));
    if let (Some(h), Some(l)) = (heavy, light)
        && h.0 > MAX_MASS_RATIO * l.0
    {
        // blame the outlier: the one farther (in log) from the mean log of all (the lighter
        // on a tie: a mistyped 1e-9 is likelier than a mistyped 1e9)
        let ml = masses.iter().map(|m| m.0.ln()).sum::<f64>() / masses.len() as f64;
        let heavier = h.0.ln() - ml > ml - l.0.ln() + 1e-9;
        let (blamed, other) = if heavier { (h, l) } else { (l, h) };
        return Err(ck.err(
            &blamed.1,
            format!(
                "{} ({:.4e}) and {} ({:.4e}, {}) are {:.3e} apart: above {MAX_MASS_RATIO:e}, the \
                 impact LCP would lose the lighter body's velocities to rounding",
                blamed.2,
                blamed.0,
                other.2,
                other.0,
                other.1,
                h.0 / l.0
            ),
        ));
    }
    Ok(())
}

/// `rtol` < 1, `atol` and `gap_tol` against the smallest positive initial gap, `velocity_tol`
/// against gap·ω₁ ([`TOLERANCE_FRACTION`]). With `h_max` > 0, loose `rtol`/`atol` make a
/// fixed-step DP5 (order studies): accepted and said.
fn tolerances(
    scene: &Scene,
    ck: &Check,
    warnings: &mut Vec<ModelWarning>,
) -> Result<(), ModelError> {
    let st = &scene.settings;
    let fixed = st.h_max > 0.0;
    let (rtol, atol, h_max) = (st.rtol, st.atol, st.h_max);
    if rtol >= 1.0 && !fixed {
        return Err(ck.err(
            "solver.rtol",
            format!(
                "must be in (0, 1): a relative error of {rtol} is no error control (with \
 solver.h_max > 0 it would make a fixed-step DP5), got {rtol}"
            ),
        ));
    }
    let path = ck.path.to_path_buf();
    if fixed && rtol >= 1.0 {
        let path = path.clone();
        warnings.push(ModelWarning::ErrorControlOff {
            path,
            rtol,
            atol,
            h_max,
        });
    }
    let fr = scene.frame(0.0, &scene.q0, &scene.v0);
    // a gap within the rounding of its points' coordinates is a closed one (a joint given a
    // gap of 0 between skewed frames is 3e-15 m open)
    let rounding = |c: &crate::scene::Contact| {
        let reach = |b, r: nalgebra::Vector2<f64>| fr.pose(b).position.norm() + r.norm();
        ROUNDING_ULPS
            * f64::EPSILON
            * reach(c.point_body, c.point).max(reach(c.face_body, c.face_point))
    };
    let smallest = (scene.contacts.iter())
        .map(|c| {
            (
                c.name.as_str(),
                scene.contact_kinematics(&fr, c).gap,
                rounding(c),
            )
        })
        .filter(|(_, g, r)| *g > *r)
        .map(|(name, g, _)| (name, g))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    let Some((contact, gap)) = smallest else {
        return Ok(());
    };
    let limit = TOLERANCE_FRACTION * gap;
    if fixed && rtol < 1.0 && atol > limit {
        warnings.push(ModelWarning::ErrorControlOff {
            path,
            rtol,
            atol,
            h_max,
        });
    }
    for (field, x) in [("solver.atol", st.atol), ("solver.gap_tol", st.gap_tol)] {
        if x > limit && !(fixed && field == "solver.atol") {
            return Err(ck.err(
                field,
                format!(
                    "{x} is above {TOLERANCE_FRACTION:e} × the smallest initial gap \
 ({gap:.4e} m, contact {contact}) = {limit:.3e}: it would not resolve the gap"
                ),
            ));
        }
    }
    let w1 = modes(scene).iter().map(|m| m.omega).find(|w| *w > 0.0);
    if let Some(w1) = w1 {
        let speed = gap * w1;
        let limit = TOLERANCE_FRACTION * speed;
        let x = st.velocity_tol;
        if x > limit {
            return Err(ck.err(
                "solver.velocity_tol",
                format!(
                    "{x} is above {TOLERANCE_FRACTION:e} × gap·ω₁ = {TOLERANCE_FRACTION:e} × \
 {gap:.4e} m × {w1:.4} rad/s = {limit:.3e} m/s (smallest initial gap, contact \
 {contact}; ω₁ of the initial system): impacts this slow would count as rest"
                ),
            ));
        }
    }
    Ok(())
}

/// The fixed step against 2/ω_max. Explicit: above the limit of K₀ (unstable from the first
/// step, whatever the contacts do) refused (or warned, [`StepLimit::Warn`]); above the limit
/// with every contact closed (unstable while contacts are closed; the run-time energy guard
/// stops it) warned. Implicit methods are stable at any step: warned when the fastest
/// dynamics are not resolved.
fn fixed_step(
    scene: &Scene,
    step_limit: StepLimit,
    ck: &Check,
    warnings: &mut Vec<ModelWarning>,
) -> Result<(), ModelError> {
    let st = &scene.settings;
    let (step, k) = (st.step, st.contact_stiffness);
    let open = || (omega_max(scene), "K₀ of springs and columns".to_string());
    let closed = || {
        let what = format!("K₀ with every contact closed and sticking at contact_stiffness {k:e}");
        (omega_max_closed(scene, k), what)
    };
    let (path, line) = (ck.path.to_path_buf(), ck.line("solver.step"));
    match st.method {
        Method::Event => {}
        Method::PenaltyExplicit => {
            let (omega, what) = open();
            let limit = 2.0 / omega;
            if step > limit && step_limit == StepLimit::Refuse {
                let reason = format!(
                    "{step} s is above the stability limit 2/ω_max = {limit:.3e} s of the \
 explicit central-difference scheme (ω_max = {omega:.4e} rad/s, {what})"
                );
                return Err(ck.err("solver.step", reason));
            }
            let (omega, what) = if step > limit {
                (omega, what)
            } else {
                closed()
            };
            let limit = 2.0 / omega;
            if step > limit {
                warnings.push(ModelWarning::StepAboveStability {
                    path,
                    line,
                    step,
                    limit,
                    omega,
                    what,
                });
            }
        }
        Method::Moreau | Method::Penalty => {
            let (omega, what) = if st.method == Method::Moreau {
                open()
            } else {
                closed()
            };
            let limit = 2.0 / omega;
            if step > limit {
                let method = st.method.name().to_string();
                warnings.push(ModelWarning::StepUnresolved {
                    path,
                    line,
                    step,
                    limit,
                    omega,
                    what,
                    method,
                });
            }
        }
    }
    Ok(())
}

/// A contact through its face at t = 0 (g_N < −`gap_tol`), refused at the field that sets its
/// gap: `contact.I.gap` of a scene file, `contacts.gaps.I` or `joint.J.gaps.I` of a bridge (the
/// engine's own check names the contact only).
fn initial_penetration(scene: &Scene, bridge: bool, ck: &Check) -> Result<(), ModelError> {
    let fr = scene.frame(0.0, &scene.q0, &scene.v0);
    let tol = scene.settings.gap_tol;
    for (i, c) in scene.contacts.iter().enumerate() {
        let gap = scene.contact_kinematics(&fr, c).gap;
        if gap.is_nan() || gap >= -tol {
            continue;
        }
        let field = if !bridge {
            format!("contact.{i}.gap")
        } else if let Some(k) = super::bridge::schema::CORNERS
            .iter()
            .position(|n| *n == c.name)
        {
            format!("contacts.gaps.{k}")
        } else {
            bridge_joint_field(&c.name).unwrap_or_else(|| "contacts.gaps".into())
        };
        return Err(ck.err(
            &field,
            format!(
                "contact '{}' starts {:.6e} m through its face (g_N < −solver.gap_tol = {tol:e} m \
                 at t = 0): a larger gap, or initial displacements that keep it out",
                c.name, -gap
            ),
        ));
    }
    Ok(())
}

/// `joint.J.gaps.I` of a joint corner named `jointN_top` / `jointN_bottom` (N = J + 1).
fn bridge_joint_field(name: &str) -> Option<String> {
    let rest = name.strip_prefix("joint")?;
    let (n, side) = rest.split_once('_')?;
    let j: usize = n.parse::<usize>().ok()?.checked_sub(1)?;
    let i = ["top", "bottom"].iter().position(|s| *s == side)?;
    Some(format!("joint.{j}.gaps.{i}"))
}
