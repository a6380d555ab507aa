//! The shake-table bridge (paper §2, §4.1): deck (x, y, θ), two abutments (x, θ) on two
//! actuator spring–dampers each, four deck-corner contacts, three two-column bents with
//! hysteretic columns, Rayleigh damping, multi-support excitation. A bridge file speaks in
//! bridge words and compiles into the engine's general [`Scene`].
//!
//! Units: t, kN, m, s (1 t·m/s² = 1 kN).

use crate::excitation::{Baseline, Processing};
use crate::hysteresis::{Hysteretic, Law};
use crate::model::{Check, ModelError, Motions, SolverSpec, parse, settings};
use crate::scene::{
    Attachment, Body, BodyRef, Contact, HystereticElement, MassDamping, Motion, Scene, Spring,
    Support,
};
use nalgebra::{DMatrix, DVector, Vector2};
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
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactsSpec {
    /// false: no deck–abutment contact (paper §4.2).
    #[serde(default = "yes")]
    pub enabled: bool,
    pub mu: f64,
    pub restitution: f64,
    /// Initial gaps of corners 1–4 (left +y, left −y, right +y, right −y), m.
    pub gaps: [f64; 4],
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

/// Compile a bridge model file's text into a scene.
pub fn compile_str(text: &str, path: &Path, motions: &Motions) -> Result<Scene, ModelError> {
    let f: BridgeFile = parse(text, path)?;
    compile(&f, text, path, motions)
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

pub fn compile(
    f: &BridgeFile,
    text: &str,
    path: &Path,
    motions: &Motions,
) -> Result<Scene, ModelError> {
    let ck = Check { text, path };
    let mut settings = settings(&f.solver, &ck)?;
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
    for (i, b) in f.bents.iter().enumerate() {
        ck.finite(&format!("bent.{i}.x"), b.x)?;
        ck.positive(&format!("bent.{i}.height"), b.height)?;
    }
    let skew = d.skew.to_radians();
    let (ls, lw) = (d.length / 2.0, d.width / 2.0);
    let tan = skew.tan();
    let gap0 = c.gaps.iter().sum::<f64>() / 4.0;
    // bodies: left abutment (x, θ), deck (x, y, θ), right abutment (x, θ): u = [x1, θ1, x2, y2, θ2, x3, θ3]
    let bodies = vec![
        Body {
            name: "left_abutment".into(),
            mass: a.mass,
            inertia: a.inertia,
            reference: Vector2::new(-ls - gap0, 0.0),
            dofs: [Some(0), None, Some(1)],
        },
        Body {
            name: "deck".into(),
            mass: d.mass,
            inertia: d.inertia,
            reference: Vector2::zeros(),
            dofs: [Some(2), Some(3), Some(4)],
        },
        Body {
            name: "right_abutment".into(),
            mass: a.mass,
            inertia: a.inertia,
            reference: Vector2::new(ls + gap0, 0.0),
            dofs: [Some(5), None, Some(6)],
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
    // skew: deck ends along (sin φ, cos φ); left face normal (cos φ, −sin φ) towards the deck
    let n_left = Vector2::new(skew.cos(), -skew.sin());
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
    // supports: per bent x and y, per abutment x
    let nb = f.bents.len();
    let mut supports = Vec::new();
    let ex = f.excitation.as_ref();
    if let Some(e) = ex {
        supports = excitation_supports(e, &f.runs, nb, &ck, path, motions, &mut settings)?;
    }
    let has_supports = !supports.is_empty();
    let sup = |i: usize| if has_supports { Some(i) } else { None };
    let mut springs = Vec::new();
    for (ab, side) in [(0usize, "left"), (2, "right")] {
        for (sgn, tag) in [(1.0, "top"), (-1.0, "bottom")] {
            springs.push(Spring {
                name: format!("{side}_actuator_{tag}"),
                attachment: Attachment::Point {
                    body: ab,
                    point: Vector2::new(0.0, sgn * a.actuator_offset),
                    direction: Vector2::new(1.0, 0.0),
                },
                stiffness: a.actuator_stiffness,
                damping: a.actuator_damping,
                support: if ex.is_some_and(|e| e.drive_abutments) {
                    sup(2 * nb + if ab == 0 { 0 } else { 1 })
                } else {
                    None
                },
            });
        }
    }
    let mut hysteretic = Vec::new();
    for (bi, b) in f.bents.iter().enumerate() {
        let ratio = col.reference_height / b.height;
        let law = scale_law(&col.law, ratio.powi(3), ratio);
        for (sgn, tag) in [(1.0, "top"), (-1.0, "bottom")] {
            let yc = sgn * col.offset;
            let point = Vector2::new(b.x + yc * tan, yc);
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
                    support: sup(s),
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
    let mut scene = Scene {
        title: f.title.clone().unwrap_or_else(|| "bridge".into()),
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

fn excitation_supports(
    e: &ExcitationSpec,
    runs: &[RunSpec],
    nb: usize,
    ck: &Check,
    path: &Path,
    motions: &Motions,
    settings: &mut crate::scene::Settings,
) -> Result<Vec<Support>, ModelError> {
    let lag_b = |i: usize| e.lag_bents.get(i).copied().unwrap_or(0.0);
    let lag_a = |i: usize| e.lag_abutments.get(i).copied().unwrap_or(0.0);
    for (i, l) in e.lag_bents.iter().enumerate() {
        ck.nonneg(&format!("excitation.lag_bents.{i}"), *l)?;
    }
    for (i, l) in e.lag_abutments.iter().enumerate() {
        ck.nonneg(&format!("excitation.lag_abutments.{i}"), *l)?;
    }
    let mut out = Vec::new();
    match e.kind.as_str() {
        "harmonic" => {
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
            for b in 0..nb {
                out.push(h(ax, lag_b(b), format!("bent{}.x", b + 1)));
                out.push(h(ay, lag_b(b), format!("bent{}.y", b + 1)));
            }
            out.push(h(ax, lag_a(0), "left_abutment.x".into()));
            out.push(h(ax, lag_a(1), "right_abutment.x".into()));
        }
        "record" => {
            let run = match e.run {
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
                motions.get(path, file, p)
            };
            let mut t_max: f64 = 0.0;
            for b in 0..nb {
                let mx = get(&e.longitudinal, "excitation.longitudinal", pga_x, lag_b(b))?;
                let my = get(&e.transverse, "excitation.transverse", pga_y, lag_b(b))?;
                t_max = t_max.max(mx.end_time()).max(my.end_time());
                out.push(Support {
                    name: format!("bent{}.x", b + 1),
                    motion: Motion::Record(mx),
                    factor: 1.0,
                });
                out.push(Support {
                    name: format!("bent{}.y", b + 1),
                    motion: Motion::Record(my),
                    factor: 1.0,
                });
            }
            for (i, side) in ["left", "right"].iter().enumerate() {
                let m = get(&e.longitudinal, "excitation.longitudinal", pga_x, lag_a(i))?;
                out.push(Support {
                    name: format!("{side}_abutment.x"),
                    motion: Motion::Record(m),
                    factor: 1.0,
                });
            }
            let _ = t_max;
        }
        k => {
            return Err(ck.err(
                "excitation.kind",
                format!("unknown excitation kind '{k}' (record, harmonic)"),
            ));
        }
    }
    let _ = settings;
    Ok(out)
}

/// Initial stiffness K₀ = Σ k J Jᵀ of springs and hysteretic elements at q = 0 (contacts open).
pub fn initial_stiffness(scene: &Scene) -> DMatrix<f64> {
    let n = scene.ndof();
    let z = DVector::zeros(n);
    let mut jac = DVector::zeros(n);
    let mut k = DMatrix::zeros(n, n);
    let mut add = |att: &Attachment, stiff: f64, jac: &mut DVector<f64>| {
        scene.deformation(att, None, 0.0, &z, &z, jac);
        k += &*jac * jac.transpose() * stiff;
    };
    for s in &scene.springs {
        add(&s.attachment, s.stiffness, &mut jac);
    }
    for h in &scene.hysteretic {
        add(&h.attachment, h.law.law().initial_stiffness(), &mut jac);
    }
    k
}

/// A mode of the initial system (K₀ φ = ω² M φ, φᵀMφ = 1).
#[derive(Clone, Debug)]
pub struct Mode {
    pub omega: f64,
    pub period: f64,
    pub shape: DVector<f64>,
}

/// Eigen-analysis of (K₀, M), modes sorted by frequency.
pub fn modes(scene: &Scene) -> Vec<Mode> {
    let k = initial_stiffness(scene);
    let s: DVector<f64> = scene.mass.map(|m| 1.0 / m.sqrt());
    let n = scene.ndof();
    let mut a = k.clone();
    for i in 0..n {
        for j in 0..n {
            a[(i, j)] *= s[i] * s[j];
        }
    }
    let eig = nalgebra::SymmetricEigen::new(a);
    let mut out: Vec<Mode> = (0..n)
        .map(|i| {
            let w2 = eig.eigenvalues[i].max(0.0);
            let omega = w2.sqrt();
            let mut shape = eig.eigenvectors.column(i).component_mul(&s);
            let big = shape
                .iter()
                .cloned()
                .fold(0.0f64, |m, x| if x.abs() > m.abs() { x } else { m });
            if big < 0.0 {
                shape = -shape;
            }
            Mode {
                omega,
                period: if omega > 0.0 {
                    2.0 * std::f64::consts::PI / omega
                } else {
                    f64::INFINITY
                },
                shape,
            }
        })
        .collect();
    out.sort_by(|a, b| a.omega.total_cmp(&b.omega));
    out
}

/// Rayleigh damping C = a₀M + a₁K₀ with ζ at modes i, j (Chopra, *Dynamics of Structures*
/// §11.4): a₀ = 2ζωᵢωⱼ/(ωᵢ+ωⱼ), a₁ = 2ζ/(ωᵢ+ωⱼ). The a₁K₀ part acts on element deformation
/// rates, the a₀M part on velocities relative to the quasi-static motion of the supports, so
/// damping forces vanish for rigid-body support motion.
pub fn apply_rayleigh(
    scene: &mut Scene,
    zeta: f64,
    modes_ij: [usize; 2],
) -> Result<(f64, f64), String> {
    let m = modes(scene);
    let [i, j] = modes_ij;
    if i == 0 || j == 0 || i > m.len() || j > m.len() || i == j {
        return Err(format!(
            "modes must be two different numbers in 1..={}",
            m.len()
        ));
    }
    let (wi, wj) = (m[i - 1].omega, m[j - 1].omega);
    if wi <= 0.0 || wj <= 0.0 {
        return Err("a chosen mode has zero frequency".into());
    }
    let a0 = 2.0 * zeta * wi * wj / (wi + wj);
    let a1 = 2.0 * zeta / (wi + wj);
    for s in &mut scene.springs {
        s.damping += a1 * s.stiffness;
    }
    for h in &mut scene.hysteretic {
        h.damping += a1 * h.law.law().initial_stiffness();
    }
    // quasi-static influence of each support: r_s = K₀⁻¹ Σ k J (unit support displacement)
    let k0 = initial_stiffness(scene);
    let n = scene.ndof();
    let lu = k0.lu();
    let z = DVector::zeros(n);
    let mut jac = DVector::zeros(n);
    let mut reference = Vec::new();
    for s in 0..scene.supports.len() {
        let mut f = DVector::zeros(n);
        for sp in scene.springs.iter().filter(|x| x.support == Some(s)) {
            scene.deformation(&sp.attachment, None, 0.0, &z, &z, &mut jac);
            f.axpy(sp.stiffness, &jac, 1.0);
        }
        for h in scene.hysteretic.iter().filter(|x| x.support == Some(s)) {
            scene.deformation(&h.attachment, None, 0.0, &z, &z, &mut jac);
            f.axpy(h.law.law().initial_stiffness(), &jac, 1.0);
        }
        if let Some(r) = lu.solve(&f) {
            for k in 0..n {
                if r[k].abs() > 1e-14 {
                    reference.push((k, s, r[k]));
                }
            }
        }
    }
    scene.mass_damping = MassDamping {
        alpha: a0,
        reference,
    };
    Ok((a0, a1))
}
