//! The shake-table bridge (paper §2, §4.1): deck (x, y, θ), two abutments (x, θ) on two
//! actuator spring–dampers each, four deck-corner contacts, three two-column bents with
//! hysteretic columns, Rayleigh damping, multi-support excitation. A bridge file speaks in
//! bridge words and compiles into the engine's general [`Scene`].
//!
//! Units: t, kN, m, s (1 t·m/s² = 1 kN).

use super::check::{Check, ModelError};
use super::records::{Motions, record_error};
use super::solver::{SolverSpec, settings};
use super::warnings::ModelWarning;
use crate::excitation::{Baseline, Processing};
use crate::hysteresis::{Hysteretic, Law};
use crate::modal::apply_rayleigh;
use crate::scene::{
    Attachment, Body, BodyRef, Contact, HystereticElement, MassDamping, Motion, Scene, Spring,
    Support,
};
use nalgebra::{DVector, Vector2};
use serde::Deserialize;
use std::path::Path;

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DeckSpec {
    /// t (paper: 140.5).
    pub mass: f64,
    /// t·m² about the vertical axis (paper: 13090).
    pub inertia: f64,
    /// Corner-to-corner length along the centreline, m (32.2).
    pub length: f64,
    /// m (2.4).
    pub width: f64,
    /// Skew angle of deck ends and abutment faces, degrees (0: straight).
    #[serde(default)]
    pub skew: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AbutmentSpec {
    /// t (0.65).
    pub mass: f64,
    /// t·m² (0.31).
    pub inertia: f64,
    /// Each of the two longitudinal actuators, kN/m.
    pub actuator_stiffness: f64,
    /// kN·s/m.
    #[serde(default)]
    pub actuator_damping: f64,
    /// Lateral offset ± of the two actuators from the abutment centre, m.
    pub actuator_offset: f64,
    /// Support length of each deck corner on its seat at the reference configuration (AASHTO's
    /// N: from the deck end to the seat's edge), m (absent: no seat output).
    pub seat_width: Option<f64>,
    /// The percentage of AASHTO LRFD 4.7.4.4's N to compare with (absent: 100).
    pub seat_percent: Option<f64>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactsSpec {
    /// false: no deck–abutment contact (paper §4.2).
    #[serde(default = "yes")]
    pub enabled: bool,
    pub mu: f64,
    pub restitution: f64,
    /// Initial gaps of corners 1–4 (left +y, left −y, right +y, right −y), m: exactly four.
    #[serde(deserialize_with = "four_gaps")]
    pub gaps: [f64; 4],
}

/// `gaps` with exactly four entries (a fixed-size array would drop a fifth silently).
fn four_gaps<'de, D: serde::Deserializer<'de>>(d: D) -> Result<[f64; 4], D::Error> {
    let v = Vec::<f64>::deserialize(d)?;
    let n = v.len();
    v.try_into().map_err(|_| {
        serde::de::Error::custom(format!(
            "expected 4 contacts.gaps (left_top, left_bottom, right_top, right_bottom), got {n}"
        ))
    })
}

fn yes() -> bool {
    true
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BentSpec {
    pub name: String,
    /// Plan position along the deck from its centre, m.
    pub x: f64,
    /// Clear column height, m (stiffness ∝ h⁻³, strength ∝ h⁻¹ for fixed–fixed columns).
    pub height: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColumnSpec {
    /// Law of one column in x and in y at `reference_height` (uncoupled directions).
    pub law: Law,
    pub reference_height: f64,
    /// Lateral offset ± of the two columns of a bent from the centreline, m.
    pub offset: f64,
    /// Elastic torsional stiffness of one column at the reference height, kN·m/rad (∝ h⁻¹).
    pub torsion_stiffness: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DampingSpec {
    /// Rayleigh ζ at two modes of the initial system (paper: 2 % at modes 1 and 3).
    pub ratio: f64,
    pub modes: [usize; 2],
}

impl Default for DampingSpec {
    fn default() -> Self {
        Self {
            ratio: 0.02,
            modes: [1, 3],
        }
    }
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    pub name: String,
    /// Target PGA, g, longitudinal and transverse.
    pub pga_x: f64,
    pub pga_y: f64,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ExcitationSpec {
    /// "record" or "harmonic".
    pub kind: String,
    /// Records (AT2 or two-column), relative to the model file.
    pub longitudinal: Option<String>,
    pub transverse: Option<String>,
    /// Which `[[run]]` sets the target PGAs (1-based).
    #[serde(default)]
    pub run: Option<usize>,
    /// Similitude time scale (quarter scale: 0.5).
    #[serde(default = "one")]
    pub time_scale: f64,
    /// Polynomial baseline order.
    #[serde(default = "three")]
    pub baseline_order: usize,
    #[serde(default)]
    pub taper: Option<f64>,
    /// Per-bent and per-abutment time lags, s.
    #[serde(default)]
    pub lag_bents: Vec<f64>,
    #[serde(default)]
    pub lag_abutments: Vec<f64>,
    /// Harmonic input: displacement amplitude x and y (m), frequency (Hz).
    pub amplitude_x: Option<f64>,
    pub amplitude_y: Option<f64>,
    pub frequency: Option<f64>,
    /// Abutment actuators follow the longitudinal input (true) or stay fixed.
    #[serde(default = "yes")]
    pub drive_abutments: bool,
}

fn one() -> f64 {
    1.0
}
fn three() -> usize {
    3
}

/// A bridge model file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BridgeFile {
    pub title: Option<String>,
    pub deck: DeckSpec,
    pub abutment: AbutmentSpec,
    pub contacts: ContactsSpec,
    #[serde(rename = "bent")]
    pub bents: Vec<BentSpec>,
    pub column: ColumnSpec,
    #[serde(default)]
    pub damping: DampingSpec,
    pub excitation: Option<ExcitationSpec>,
    #[serde(default, rename = "run")]
    pub runs: Vec<RunSpec>,
    #[serde(default)]
    pub solver: SolverSpec,
}

/// Scale a column law from the reference height to height h (fixed–fixed: k ∝ h⁻³, V_y ∝ h⁻¹).
fn scale_law(law: &Law, kf: f64, ff: f64) -> Law {
    match law.clone() {
        Law::Linear { stiffness } => Law::Linear {
            stiffness: stiffness * kf,
        },
        Law::Bilinear {
            stiffness,
            yield_force,
            post_yield_ratio,
        } => Law::Bilinear {
            stiffness: stiffness * kf,
            yield_force: yield_force * ff,
            post_yield_ratio,
        },
        Law::Takeda {
            stiffness,
            yield_force,
            post_yield_ratio,
            crack_force,
            yield_displacement,
            unloading_exponent,
        } => Law::Takeda {
            stiffness: stiffness * kf,
            yield_force: yield_force * ff,
            post_yield_ratio,
            crack_force: crack_force.map(|c| c * ff),
            yield_displacement: yield_displacement.map(|d| d * ff / kf),
            unloading_exponent,
        },
    }
}

/// Names of the four corners (paper: point 1 is the left, upper corner).
pub const CORNERS: [&str; 4] = ["left_top", "left_bottom", "right_top", "right_bottom"];

/// Validate and compile a bridge file into the engine's general scene.
pub fn compile(f: &BridgeFile, ck: &Check, motions: &Motions) -> Result<Scene, ModelError> {
    let (ck, path) = (ck, ck.path);
    let settings = settings(&f.solver, ck)?;
    validate(f, ck)?;
    let plan = Plan::of(f);
    let (bodies, mass, dof_names) = deck_and_abutments(f, &plan);
    let contacts = corner_contacts(&f.contacts, &plan, &bodies);
    // supports: per bent x and y, per abutment x
    let nb = f.bents.len();
    let ex = f.excitation.as_ref();
    let supports = match ex {
        Some(e) => excitation_supports(e, &f.runs, nb, ck, path, motions)?,
        None => Vec::new(),
    };
    let driven = !supports.is_empty();
    let mut springs = actuator_springs(&f.abutment, ex, nb, driven);
    let hysteretic = bent_columns(f, &plan, ck, driven, &mut springs)?;
    let nb = f.bents.len().max(1) as f64;
    let seat = super::seat::SeatSpec {
        width: f.abutment.seat_width,
        percent: f.abutment.seat_percent,
        gaps: f.contacts.gaps,
        length: f.deck.length,
        height: f.bents.iter().map(|b| b.height).sum::<f64>() / nb,
        skew: f.deck.skew,
    };
    let seats = super::seat::seats(&seat, ck)?;
    let mut scene = Scene {
        title: f.title.clone().unwrap_or_else(|| "bridge".into()),
        seats,
        bodies,
        contacts,
        springs,
        hysteretic,
        supports,
        mass_damping: MassDamping::default(),
        loads: DVector::zeros(7),
        mass,
        dof_names,
        q0: DVector::zeros(7),
        v0: DVector::zeros(7),
        settings,
    };
    if f.damping.ratio > 0.0 {
        apply_rayleigh(&mut scene, f.damping.ratio, f.damping.modes)
            .map_err(|r| ck.err("damping.modes", r))?;
    }
    Ok(scene)
}

/// Checks of the deck, abutments, contacts, bents, columns and damping, in file order.
fn validate(f: &BridgeFile, ck: &Check) -> Result<(), ModelError> {
    let d = &f.deck;
    ck.positive("deck.mass", d.mass)?;
    ck.positive("deck.inertia", d.inertia)?;
    ck.positive("deck.length", d.length)?;
    ck.positive("deck.width", d.width)?;
    ck.finite("deck.skew", d.skew)?;
    if d.skew.abs() >= 60.0 {
        return Err(ck.err("deck.skew", "must be within ±60°"));
    }
    let a = &f.abutment;
    ck.positive("abutment.mass", a.mass)?;
    ck.positive("abutment.inertia", a.inertia)?;
    ck.positive("abutment.actuator_stiffness", a.actuator_stiffness)?;
    ck.nonneg("abutment.actuator_damping", a.actuator_damping)?;
    ck.positive("abutment.actuator_offset", a.actuator_offset)?;
    let c = &f.contacts;
    ck.nonneg("contacts.mu", c.mu)?;
    ck.nonneg("contacts.restitution", c.restitution)?;
    if c.restitution > 1.0 {
        return Err(ck.err("contacts.restitution", "must be in [0, 1]"));
    }
    for (i, g) in c.gaps.iter().enumerate() {
        ck.nonneg(&format!("contacts.gaps.{i}"), *g)?;
    }
    if f.bents.is_empty() {
        return Err(ck.err("bent", "at least one bent"));
    }
    let col = &f.column;
    ck.positive("column.reference_height", col.reference_height)?;
    ck.positive("column.offset", col.offset)?;
    ck.nonneg("column.torsion_stiffness", col.torsion_stiffness)?;
    col.law
        .validate()
        .map_err(|e| ck.err("column.law", e.to_string()))?;
    ck.positive("damping.ratio", f.damping.ratio).or_else(|e| {
        if f.damping.ratio == 0.0 {
            Ok(0.0)
        } else {
            Err(e)
        }
    })?;
    validate_layout(f, ck)?;
    for (i, r) in f.runs.iter().enumerate() {
        ck.positive(&format!("run.{i}.pga_x"), r.pga_x)?;
        ck.positive(&format!("run.{i}.pga_y"), r.pga_y)?;
    }
    Ok(())
}

/// Bents and columns under the deck: |x| ≤ length/2, column offset ≤ width/2.
fn validate_layout(f: &BridgeFile, ck: &Check) -> Result<(), ModelError> {
    let (half_l, half_w) = (f.deck.length / 2.0, f.deck.width / 2.0);
    for (i, b) in f.bents.iter().enumerate() {
        let x = ck.finite(&format!("bent.{i}.x"), b.x)?;
        if x.abs() > half_l {
            let by_length = ck.set_by("deck.length").is_some();
            return Err(ck.err(
                &if by_length {
                    "deck.length".into()
                } else {
                    format!("bent.{i}.x")
                },
                format!(
                    "bent.{i}.x = {x} m is off the deck: a bent must stand under it, |x| ≤ \
                     deck.length/2 = {half_l} m"
                ),
            ));
        }
        ck.positive(&format!("bent.{i}.height"), b.height)?;
    }
    let off = f.column.offset;
    if off > half_w {
        let by_width = ck.set_by("deck.width").is_some();
        return Err(ck.err(
            if by_width {
                "deck.width"
            } else {
                "column.offset"
            },
            format!(
                "columns at ±{off} m (column.offset) stand outside the deck: offset ≤ \
                 deck.width/2 = {half_w} m"
            ),
        ));
    }
    Ok(())
}

/// Per-support lags: none (all 0) or one per support; fields the kind does not read refused.
fn validate_excitation(e: &ExcitationSpec, nb: usize, ck: &Check) -> Result<(), ModelError> {
    for (field, lags, n, what) in [
        ("excitation.lag_bents", &e.lag_bents, nb, "bent"),
        ("excitation.lag_abutments", &e.lag_abutments, 2, "abutment"),
    ] {
        if !lags.is_empty() && lags.len() != n {
            let k = lags.len();
            return Err(ck.err(
                field,
                format!("{k} lags for {n} {what}s: give one per {what} or none (all 0)"),
            ));
        }
        for (i, l) in lags.iter().enumerate() {
            ck.nonneg(&format!("{field}.{i}"), *l)?;
        }
    }
    Ok(())
}

/// Plan geometry of the deck: half length and width, tan of the skew, mean initial gap.
struct Plan {
    skew: f64,
    half_length: f64,
    half_width: f64,
    tan: f64,
    gap0: f64,
}

impl Plan {
    fn of(f: &BridgeFile) -> Self {
        let d = &f.deck;
        let skew = d.skew.to_radians();
        Self {
            skew,
            half_length: d.length / 2.0,
            half_width: d.width / 2.0,
            tan: skew.tan(),
            gap0: f.contacts.gaps.iter().sum::<f64>() / 4.0,
        }
    }
}

/// Left abutment (x, θ), deck (x, y, θ), right abutment (x, θ): u = [x1, θ1, x2, y2, θ2, x3, θ3].
fn deck_and_abutments(f: &BridgeFile, plan: &Plan) -> (Vec<Body>, DVector<f64>, Vec<String>) {
    let (a, d) = (&f.abutment, &f.deck);
    let (ls, gap0) = (plan.half_length, plan.gap0);
    let bodies = vec![
        Body {
            name: "left_abutment".into(),
            mass: a.mass,
            inertia: a.inertia,
            reference: Vector2::new(-ls - gap0, 0.0),
            dofs: [Some(0), None, Some(1)],
            drive: [None; 2],
        },
        Body {
            name: "deck".into(),
            mass: d.mass,
            inertia: d.inertia,
            reference: Vector2::zeros(),
            dofs: [Some(2), Some(3), Some(4)],
            drive: [None; 2],
        },
        Body {
            name: "right_abutment".into(),
            mass: a.mass,
            inertia: a.inertia,
            reference: Vector2::new(ls + gap0, 0.0),
            dofs: [Some(5), None, Some(6)],
            drive: [None; 2],
        },
    ];
    let mass = DVector::from_vec(vec![
        a.mass, a.inertia, d.mass, d.mass, d.inertia, a.mass, a.inertia,
    ]);
    let dof_names = [
        "left_abutment.x",
        "left_abutment.theta",
        "deck.x",
        "deck.y",
        "deck.theta",
        "right_abutment.x",
        "right_abutment.theta",
    ]
    .map(String::from)
    .to_vec();
    (bodies, mass, dof_names)
}

/// The four deck corners against the skewed abutment faces, each at its initial gap.
fn corner_contacts(c: &ContactsSpec, plan: &Plan, bodies: &[Body]) -> Vec<Contact> {
    let (ls, lw, tan) = (plan.half_length, plan.half_width, plan.tan);
    // skew: deck ends along (sin φ, cos φ); left face normal (cos φ, −sin φ) towards the deck
    let n_left = Vector2::new(plan.skew.cos(), -plan.skew.sin());
    let corners = [
        (Vector2::new(-ls + lw * tan, lw), 0usize, n_left),
        (Vector2::new(-ls - lw * tan, -lw), 0, n_left),
        (Vector2::new(ls + lw * tan, lw), 2, -n_left),
        (Vector2::new(ls - lw * tan, -lw), 2, -n_left),
    ];
    let mut contacts = Vec::new();
    if c.enabled {
        for (k, (p, ab, n)) in corners.iter().enumerate() {
            let xb = bodies[*ab].reference;
            contacts.push(Contact {
                name: CORNERS[k].into(),
                point_body: BodyRef::Body(1),
                point: *p,
                face_body: BodyRef::Body(*ab),
                face_point: *p - xb - c.gaps[k] * n,
                face_normal: *n,
                mu: c.mu,
                restitution: c.restitution,
            });
        }
    }
    contacts
}

/// Two longitudinal actuators per abutment, driven by the abutment supports if asked.
fn actuator_springs(
    a: &AbutmentSpec,
    ex: Option<&ExcitationSpec>,
    nb: usize,
    driven: bool,
) -> Vec<Spring> {
    let mut springs = Vec::new();
    for (ab, side) in [(0usize, "left"), (2, "right")] {
        for (sgn, tag) in [(1.0, "top"), (-1.0, "bottom")] {
            let support = 2 * nb + if ab == 0 { 0 } else { 1 };
            springs.push(Spring {
                name: format!("{side}_actuator_{tag}"),
                attachment: Attachment::Point {
                    body: ab,
                    point: Vector2::new(0.0, sgn * a.actuator_offset),
                    direction: Vector2::new(1.0, 0.0),
                },
                stiffness: a.actuator_stiffness,
                damping: a.actuator_damping,
                support: (driven && ex.is_some_and(|e| e.drive_abutments)).then_some(support),
            });
        }
    }
    springs
}

/// Two columns per bent, hysteretic in x and y (law scaled to the bent height), elastic in
/// torsion (torsion springs appended to `springs`).
fn bent_columns(
    f: &BridgeFile,
    plan: &Plan,
    ck: &Check,
    driven: bool,
    springs: &mut Vec<Spring>,
) -> Result<Vec<HystereticElement>, ModelError> {
    let col = &f.column;
    let mut hysteretic = Vec::new();
    for (bi, b) in f.bents.iter().enumerate() {
        let ratio = col.reference_height / b.height;
        let law = scale_law(&col.law, ratio.powi(3), ratio);
        for (sgn, tag) in [(1.0, "top"), (-1.0, "bottom")] {
            let yc = sgn * col.offset;
            let point = Vector2::new(b.x + yc * plan.tan, yc);
            for (dir, axis, s) in [
                (Vector2::new(1.0, 0.0), "x", 2 * bi),
                (Vector2::new(0.0, 1.0), "y", 2 * bi + 1),
            ] {
                hysteretic.push(HystereticElement {
                    name: format!("{}_{tag}.{axis}", b.name),
                    attachment: Attachment::Point {
                        body: 1,
                        point,
                        direction: dir,
                    },
                    law: Hysteretic::new(law.clone())
                        .map_err(|e| ck.err("column.law", e.to_string()))?,
                    damping: 0.0,
                    support: driven.then_some(s),
                });
            }
            if col.torsion_stiffness > 0.0 {
                springs.push(Spring {
                    name: format!("{}_{tag}.torsion", b.name),
                    attachment: Attachment::Rotation { body: 1 },
                    stiffness: col.torsion_stiffness * ratio,
                    damping: 0.0,
                    support: None,
                });
            }
        }
    }
    Ok(hysteretic)
}

/// Time lag of support `i` (0 beyond the list).
fn lag(lags: &[f64], i: usize) -> f64 {
    lags.get(i).copied().unwrap_or(0.0)
}

/// Supports of the `[excitation]`: per bent x and y, then left and right abutment x.
fn excitation_supports(
    e: &ExcitationSpec,
    runs: &[RunSpec],
    nb: usize,
    ck: &Check,
    path: &Path,
    motions: &Motions,
) -> Result<Vec<Support>, ModelError> {
    validate_excitation(e, nb, ck)?;
    match e.kind.as_str() {
        "harmonic" => harmonic_supports(e, nb, ck),
        "record" => record_supports(e, runs, nb, ck, path, motions),
        k => Err(ck.err(
            "excitation.kind",
            format!("unknown excitation kind '{k}' (record, harmonic)"),
        )),
    }
}

/// Sinusoidal displacement of every support, delayed by its lag.
fn harmonic_supports(
    e: &ExcitationSpec,
    nb: usize,
    ck: &Check,
) -> Result<Vec<Support>, ModelError> {
    let f = ck.positive(
        "excitation.frequency",
        e.frequency
            .ok_or_else(|| ck.err("excitation.frequency", "required for harmonic input"))?,
    )?;
    let ax = ck.finite("excitation.amplitude_x", e.amplitude_x.unwrap_or(0.0))?;
    let ay = ck.finite("excitation.amplitude_y", e.amplitude_y.unwrap_or(0.0))?;
    let w = 2.0 * std::f64::consts::PI * f;
    let h = |amp: f64, lag: f64, name: String| Support {
        name,
        motion: Motion::Harmonic {
            amplitude: amp,
            omega: w,
            phase: -w * lag,
        },
        factor: 1.0,
    };
    let mut out = Vec::new();
    for b in 0..nb {
        out.push(h(ax, lag(&e.lag_bents, b), format!("bent{}.x", b + 1)));
        out.push(h(ay, lag(&e.lag_bents, b), format!("bent{}.y", b + 1)));
    }
    out.push(h(ax, lag(&e.lag_abutments, 0), "left_abutment.x".into()));
    out.push(h(ax, lag(&e.lag_abutments, 1), "right_abutment.x".into()));
    Ok(out)
}

/// Recorded motions (longitudinal, transverse), scaled to the PGAs of the chosen run and
/// delayed by each support's lag.
fn record_supports(
    e: &ExcitationSpec,
    runs: &[RunSpec],
    nb: usize,
    ck: &Check,
    path: &Path,
    motions: &Motions,
) -> Result<Vec<Support>, ModelError> {
    let run =
        match e.run {
            Some(r) => Some(runs.get(r.wrapping_sub(1)).ok_or_else(|| {
                ck.err("excitation.run", format!("no run {r} (1..={})", runs.len()))
            })?),
            None => None,
        };
    let (pga_x, pga_y) = run.map_or((None, None), |r| (Some(r.pga_x), Some(r.pga_y)));
    let base = Processing {
        time_scale: ck.positive("excitation.time_scale", e.time_scale)?,
        baseline: Baseline::Polynomial {
            order: e.baseline_order,
        },
        taper: e.taper.unwrap_or(Processing::default().taper),
        ..Processing::default()
    };
    // supports with the same record, PGA and lag share one motion
    let get = |file: &Option<String>, field: &str, pga: Option<f64>, lag: f64| {
        let file = file
            .as_ref()
            .ok_or_else(|| ck.err(field, "required for record input"))?;
        let p = Processing {
            target_pga: pga,
            lag,
            ..base.clone()
        };
        let axis = if field.ends_with("longitudinal") {
            "x"
        } else {
            "y"
        };
        let model_field = |f: &str| match f {
            "target_pga" => e
                .run
                .map(|r| format!("run.{}.pga_{axis}", r.wrapping_sub(1))),
            "time_scale" | "taper" => Some(format!("excitation.{f}")),
            _ => None,
        };
        (motions.get(path, file, p)).map_err(|e| record_error(e, ck, field, file, &model_field))
    };
    let record = |name: String, m| Support {
        name,
        motion: Motion::Record(m),
        factor: 1.0,
    };
    let mut out = Vec::new();
    for b in 0..nb {
        let l = lag(&e.lag_bents, b);
        let mx = get(&e.longitudinal, "excitation.longitudinal", pga_x, l)?;
        let my = get(&e.transverse, "excitation.transverse", pga_y, l)?;
        out.push(record(format!("bent{}.x", b + 1), mx));
        out.push(record(format!("bent{}.y", b + 1), my));
    }
    for (i, side) in ["left", "right"].iter().enumerate() {
        let l = lag(&e.lag_abutments, i);
        let m = get(&e.longitudinal, "excitation.longitudinal", pga_x, l)?;
        out.push(record(format!("{side}_abutment.x"), m));
    }
    Ok(out)
}

/// What a bridge file leaves to defaults or does not use: no `[excitation]`, `[[run]]` tables
/// that no `excitation.run` picks, excitation fields its kind does not read (kept so that
/// `--set excitation.kind=…` can switch kinds).
pub fn warnings(f: &BridgeFile, ck: &Check) -> Vec<ModelWarning> {
    let path = ck.path.to_path_buf();
    let Some(e) = &f.excitation else {
        return vec![ModelWarning::NoExcitation { path }];
    };
    let mut out = Vec::new();
    if e.kind == "record" && e.run.is_none() && !f.runs.is_empty() {
        let runs = f.runs.len();
        out.push(ModelWarning::RunsUnused {
            path: path.clone(),
            runs,
        });
    }
    let unread: &[(&str, bool)] = match e.kind.as_str() {
        "harmonic" => &[
            ("longitudinal", e.longitudinal.is_some()),
            ("transverse", e.transverse.is_some()),
            ("run", e.run.is_some()),
            ("taper", e.taper.is_some()),
        ],
        "record" => &[
            ("amplitude_x", e.amplitude_x.is_some()),
            ("amplitude_y", e.amplitude_y.is_some()),
            ("frequency", e.frequency.is_some()),
        ],
        _ => &[],
    };
    for (k, _) in unread.iter().filter(|(_, given)| *given) {
        let field = format!("excitation.{k}");
        out.push(ModelWarning::Unread {
            path: path.clone(),
            line: ck.line(&field),
            field,
            kind: e.kind.clone(),
        });
    }
    out
}

/// The tables only a bridge file has.
const BRIDGE_TABLES: [&str; 7] = [
    "abutment",
    "contacts",
    "bent",
    "column",
    "damping",
    "excitation",
    "run",
];

/// A file without `[deck]` but with a bridge's tables is a bridge missing its deck (not a
/// general scene with unknown fields).
pub fn refuse_without_deck(table: &toml::Table, ck: &Check) -> Result<(), ModelError> {
    let Some(key) = BRIDGE_TABLES.iter().find(|k| table.contains_key(**k)) else {
        return Ok(());
    };
    let line = ck.line(key);
    Err(ModelError::Invalid {
        path: ck.path.to_path_buf(),
        line,
        field: "deck".into(),
        reason: format!(
            "missing: [{key}] (line {line}) makes this a bridge file, which needs a [deck] \
             table (mass, inertia, length, width)"
        ),
    })
}
