//! The general-scene file: bodies, contacts, springs, hysteretic elements, supports, and its
//! compilation into a [`Scene`].

use super::check::{Check, ModelError};
use super::limit_state::LimitStateSpec;
use super::records::{Motions, record_error};
use super::solver::{SolverSpec, settings};
use crate::contact::law::ContactLaw;
use crate::excitation::Processing;
use crate::hysteresis::{Hysteretic, Law};
use crate::scene::{
    Attachment, Body, BodyRef, Contact, HystereticElement, MassDamping, Motion, Scene, Spring,
    Support,
};
use nalgebra::{DVector, Vector2};
use serde::Deserialize;
use std::collections::HashMap;
use std::path::Path;

/// A `[[body]]` table of a scene file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// The file's `name`.
    pub name: String,
    /// The file's `mass`.
    pub mass: f64,
    /// The file's `inertia`.
    #[serde(default)]
    pub inertia: f64,
    /// Subset of "x", "y", "theta" (empty for a body driven by the ground).
    #[serde(default)]
    pub dofs: Vec<String>,
    /// Support whose motion moves the body's x (a body without DOFs: a rigid abutment moving
    /// with the ground).
    pub drive_x: Option<String>,
    /// Support whose motion moves the body's y.
    pub drive_y: Option<String>,
    /// The file's `position`.
    #[serde(default)]
    pub position: [f64; 2],
    /// The file's `initial_displacement`.
    #[serde(default)]
    pub initial_displacement: [f64; 3],
    /// The file's `initial_velocity`.
    #[serde(default)]
    pub initial_velocity: [f64; 3],
    /// Constant force (x, y) and moment on the body.
    #[serde(default)]
    pub load: [f64; 3],
}

/// A `[[contact]]` table.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// The file's `name`.
    pub name: String,
    /// Body carrying the contact point.
    pub body: String,
    /// Point in the body frame (relative to the centre).
    #[serde(default)]
    pub point: [f64; 2],
    /// Body owning the face ("ground" = fixed).
    #[serde(default = "ground")]
    pub face_body: String,
    /// Outward face normal in the face body's frame.
    pub normal: [f64; 2],
    /// g_N at the reference configuration (q = 0), m.
    pub gap: f64,
    /// The file's `mu`.
    #[serde(default)]
    pub mu: f64,
    /// The file's `restitution`.
    #[serde(default)]
    pub restitution: f64,
    /// Support length of the contact point on a seat at the reference configuration, m: the
    /// point is unseated when its gap exceeds `gap` + this (the event-driven run stops there);
    /// absent: no seat.
    pub seat_width: Option<f64>,
}

fn ground() -> String {
    "ground".into()
}

/// A `[[spring]]` table.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringSpec {
    /// The file's `name`.
    pub name: String,
    /// The file's `body`.
    pub body: String,
    /// The file's `point`.
    #[serde(default)]
    pub point: [f64; 2],
    /// World direction of a translational spring.
    pub direction: Option<[f64; 2]>,
    /// A second body: the spring measures d·[(P − P₀) − (P_other − P_other,₀)].
    pub other: Option<String>,
    /// The point of `other`, in its frame.
    pub other_point: Option<[f64; 2]>,
    /// Torsional spring on θ instead.
    #[serde(default)]
    pub rotational: bool,
    /// The file's `stiffness`.
    pub stiffness: f64,
    /// The file's `damping`.
    #[serde(default)]
    pub damping: f64,
    /// The file's `support`.
    pub support: Option<String>,
}

/// A `[[hysteretic]]` table.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HystereticSpec {
    /// The file's `name`.
    pub name: String,
    /// The file's `body`.
    pub body: String,
    /// The file's `point`.
    #[serde(default)]
    pub point: [f64; 2],
    /// The file's `direction`.
    pub direction: Option<[f64; 2]>,
    /// A second body, as for springs.
    pub other: Option<String>,
    /// The file's `other_point`.
    pub other_point: Option<[f64; 2]>,
    /// The file's `rotational`.
    #[serde(default)]
    pub rotational: bool,
    /// The file's `law`.
    pub law: Law,
    /// The file's `damping`.
    #[serde(default)]
    pub damping: f64,
    /// The file's `support`.
    pub support: Option<String>,
}

/// A `[[support]]` table.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SupportSpec {
    /// The file's `name`.
    pub name: String,
    /// "harmonic" or "record".
    pub kind: String,
    /// The file's `amplitude`.
    pub amplitude: Option<f64>,
    /// Hz.
    pub frequency: Option<f64>,
    /// The file's `phase`.
    pub phase: Option<f64>,
    /// Record file (AT2 or two columns), relative to the model file.
    pub file: Option<String>,
    /// The file's `processing`.
    pub processing: Option<Processing>,
    /// The file's `factor`.
    #[serde(default = "one")]
    pub factor: f64,
}

fn one() -> f64 {
    1.0
}

/// A general scene file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// The file's `title`.
    pub title: Option<String>,
    /// The unit system (read before the rest: `Check::units`).
    #[allow(dead_code)]
    pub units: Option<String>,
    /// The file's `solver`.
    #[serde(default)]
    pub solver: SolverSpec,
    /// Gravity vector (x, y), m/s², applied as m·g to x/y DOFs.
    pub gravity: Option<[f64; 2]>,
    /// The file's `bodies`.
    #[serde(default, rename = "body")]
    pub bodies: Vec<BodySpec>,
    /// The file's `contacts`.
    #[serde(default, rename = "contact")]
    pub contacts: Vec<ContactSpec>,
    /// The file's `springs`.
    #[serde(default, rename = "spring")]
    pub springs: Vec<SpringSpec>,
    /// The file's `hysteretic`.
    #[serde(default, rename = "hysteretic")]
    pub hysteretic: Vec<HystereticSpec>,
    /// The file's `supports`.
    #[serde(default, rename = "support")]
    pub supports: Vec<SupportSpec>,
    /// Limit states of a fragility (`deckspin fragility --model`).
    #[serde(default, rename = "limit_state")]
    pub limit_states: Vec<LimitStateSpec>,
    /// Uncertain inputs of `deckspin sensitivity` (a run ignores them).
    #[serde(default, rename = "uncertain")]
    pub uncertain: Vec<crate::model::uncertain::UncertainSpec>,
}

fn axis_index(s: &str) -> Option<usize> {
    match s {
        "x" => Some(0),
        "y" => Some(1),
        "theta" => Some(2),
        _ => None,
    }
}

/// Validate and compile a general scene file.
pub fn compile(f: &SceneFile, ck: &Check, motions: &Motions) -> Result<Scene, ModelError> {
    let (ck, path) = (ck, ck.path);
    let settings = settings(&f.solver, ck)?;
    let gravity = match f.gravity {
        Some(g) => ck.vec2("gravity", g)?,
        None => Vector2::zeros(),
    };
    let mut dofs = compile_bodies(f, ck, gravity)?;
    let (supports, support_names) = compile_supports(f, ck, path, motions)?;
    drives(f, ck, &support_names, &mut dofs.bodies)?;
    let refs = Refs {
        ck,
        bodies: &dofs.bodies,
        names: &dofs.names,
        supports: &support_names,
    };
    let contacts = f
        .contacts
        .iter()
        .enumerate()
        .map(|(i, c)| compile_contact(i, c, &refs))
        .collect::<Result<Vec<_>, _>>()?;
    let mut seats = Vec::new();
    for (contact, c) in f.contacts.iter().enumerate() {
        if let Some(w) = c.seat_width {
            let width = ck.positive(&format!("contact.{contact}.seat_width"), w)?;
            seats.push(crate::scene::Seat {
                contact,
                width,
                edge: width + c.gap,
                required: None,
            });
        }
    }
    let springs = compile_springs(f, &refs)?;
    let hysteretic = compile_hysteretic(f, &refs)?;
    let Dofs {
        bodies,
        mass,
        dof_names,
        q0,
        v0,
        loads,
        ..
    } = dofs;
    Ok(Scene {
        units: ck.units,
        bridge: false,
        seats,
        title: f.title.clone().unwrap_or_else(|| {
            path.file_stem()
                .map_or("scene".into(), |s| s.to_string_lossy().into_owned())
        }),
        bodies,
        contacts,
        springs,
        hysteretic,
        supports,
        mass_damping: MassDamping::default(),
        loads: DVector::from_vec(loads),
        mass: DVector::from_vec(mass),
        dof_names,
        q0: DVector::from_vec(q0),
        v0: DVector::from_vec(v0),
        settings,
    })
}

/// The bodies and their degrees of freedom, in file order.
#[derive(Default)]
struct Dofs {
    bodies: Vec<Body>,
    names: HashMap<String, usize>,
    mass: Vec<f64>,
    dof_names: Vec<String>,
    q0: Vec<f64>,
    v0: Vec<f64>,
    loads: Vec<f64>,
}

/// `[[body]]` tables: names, masses, DOFs, initial state and loads (m·g on x/y).
fn compile_bodies(f: &SceneFile, ck: &Check, gravity: Vector2<f64>) -> Result<Dofs, ModelError> {
    let mut d = Dofs::default();
    for (i, b) in f.bodies.iter().enumerate() {
        compile_body(i, b, ck, gravity, &mut d)?;
    }
    if d.mass.is_empty() {
        return Err(ck.err("body", "the scene has no degrees of freedom"));
    }
    Ok(d)
}

fn compile_body(
    i: usize,
    b: &BodySpec,
    ck: &Check,
    gravity: Vector2<f64>,
    d: &mut Dofs,
) -> Result<(), ModelError> {
    let fld = |k: &str| format!("body.{i}.{k}");
    if b.name.is_empty() || b.name == "ground" || d.names.contains_key(&b.name) {
        return Err(ck.err(
            &fld("name"),
            format!("'{}' is empty, reserved or repeated", b.name),
        ));
    }
    let driven = b.drive_x.is_some() || b.drive_y.is_some();
    if driven {
        ck.nonneg(&fld("mass"), b.mass)?;
    } else {
        ck.positive(&fld("mass"), b.mass)?;
    }
    let mut dofs = body_dofs(b, driven, ck, &fld)?;
    if dofs[2].is_some() {
        ck.positive(&fld("inertia"), b.inertia)?;
    } else {
        ck.nonneg(&fld("inertia"), b.inertia)?;
    }
    let reference = ck.vec2(&fld("position"), b.position)?;
    for a in 0..3 {
        for (k, arr) in [
            ("initial_displacement", &b.initial_displacement),
            ("initial_velocity", &b.initial_velocity),
            ("load", &b.load),
        ] {
            ck.finite(&fld(k), arr[a])?;
            if dofs[a].is_none() && arr[a] != 0.0 && k != "load" {
                return Err(ck.err(
                    &fld(k),
                    format!("component {a} is nonzero but the body has no such DOF"),
                ));
            }
        }
        if dofs[a].is_some() {
            dofs[a] = Some(d.mass.len());
            d.mass.push(if a == 2 { b.inertia } else { b.mass });
            d.dof_names
                .push(format!("{}.{}", b.name, ["x", "y", "theta"][a]));
            d.q0.push(b.initial_displacement[a]);
            d.v0.push(b.initial_velocity[a]);
            let g = if a < 2 { b.mass * gravity[a] } else { 0.0 };
            d.loads.push(g + b.load[a]);
        }
    }
    d.names.insert(b.name.clone(), i);
    d.bodies.push(Body {
        name: b.name.clone(),
        mass: b.mass,
        inertia: b.inertia,
        reference,
        dofs,
        drive: [None; 2],
    });
    Ok(())
}

/// `drive_x`, `drive_y` of the bodies driven by the ground, resolved to supports.
fn drives(
    f: &SceneFile,
    ck: &Check,
    supports: &HashMap<String, usize>,
    bodies: &mut [Body],
) -> Result<(), ModelError> {
    for (i, (b, body)) in f.bodies.iter().zip(bodies.iter_mut()).enumerate() {
        for (a, name) in [&b.drive_x, &b.drive_y].into_iter().enumerate() {
            if let Some(name) = name {
                let field = format!("body.{i}.drive_{}", ["x", "y"][a]);
                let s = supports
                    .get(name)
                    .ok_or_else(|| ck.err(&field, format!("no support named '{name}'")))?;
                body.drive[a] = Some(*s);
            }
        }
    }
    Ok(())
}

/// Which of x, y, θ the body moves in (`Some` placeholders; indices are set by the caller).
fn body_dofs(
    b: &BodySpec,
    driven: bool,
    ck: &Check,
    fld: &dyn Fn(&str) -> String,
) -> Result<[Option<usize>; 3], ModelError> {
    let mut dofs = [None; 3];
    if driven && !b.dofs.is_empty() {
        return Err(ck.err(
            &fld("dofs"),
            "a body driven by the ground (drive_x, drive_y) has no DOFs: its motion is the \
             support's",
        ));
    }
    if b.dofs.is_empty() && !driven {
        return Err(ck.err(
            &fld("dofs"),
            "a body needs at least one of \"x\", \"y\", \"theta\" (or drive_x / drive_y)",
        ));
    }
    for d in &b.dofs {
        let a = axis_index(d)
            .ok_or_else(|| ck.err(&fld("dofs"), format!("unknown DOF '{d}' (x, y, theta)")))?;
        if dofs[a].is_some() {
            return Err(ck.err(&fld("dofs"), format!("'{d}' repeated")));
        }
        dofs[a] = Some(0);
    }
    Ok(dofs)
}

/// `[[support]]` tables: harmonic or recorded ground motions, and their names.
fn compile_supports(
    f: &SceneFile,
    ck: &Check,
    path: &Path,
    motions: &Motions,
) -> Result<(Vec<Support>, HashMap<String, usize>), ModelError> {
    let mut supports = Vec::new();
    let mut names: HashMap<String, usize> = HashMap::new();
    for (i, s) in f.supports.iter().enumerate() {
        let fld = |k: &str| format!("support.{i}.{k}");
        if names.contains_key(&s.name) {
            return Err(ck.err(&fld("name"), format!("'{}' repeated", s.name)));
        }
        ck.finite(&fld("factor"), s.factor)?;
        let motion = support_motion(s, ck, &fld, path, motions)?;
        names.insert(s.name.clone(), i);
        supports.push(Support {
            name: s.name.clone(),
            motion,
            factor: s.factor,
        });
    }
    Ok((supports, names))
}

fn support_motion(
    s: &SupportSpec,
    ck: &Check,
    fld: &dyn Fn(&str) -> String,
    path: &Path,
    motions: &Motions,
) -> Result<Motion, ModelError> {
    Ok(match s.kind.as_str() {
        "harmonic" => Motion::Harmonic {
            amplitude: ck.finite(
                &fld("amplitude"),
                s.amplitude
                    .ok_or_else(|| ck.err(&fld("amplitude"), "required for a harmonic support"))?,
            )?,
            omega: 2.0
                * std::f64::consts::PI
                * ck.positive(
                    &fld("frequency"),
                    s.frequency.ok_or_else(|| {
                        ck.err(&fld("frequency"), "required for a harmonic support")
                    })?,
                )?,
            phase: ck.finite(&fld("phase"), s.phase.unwrap_or(0.0))?,
        },
        "record" => {
            let file = s
                .file
                .as_ref()
                .ok_or_else(|| ck.err(&fld("file"), "required for a record support"))?;
            let p = Processing {
                per_metre: ck.units.per_metre(),
                ..s.processing.clone().unwrap_or_default()
            };
            let processing = |f: &str| Some(fld(&format!("processing.{f}")));
            let motion = (motions.get(path, file, p))
                .map_err(|e| record_error(e, ck, &fld("file"), file, &processing))?;
            Motion::Record(motion)
        }
        k => {
            return Err(ck.err(
                &fld("kind"),
                format!("unknown support kind '{k}' (harmonic, record)"),
            ));
        }
    })
}

/// Where an element acts, as the file gives it.
struct Placement<'a> {
    body: &'a str,
    point: [f64; 2],
    direction: Option<[f64; 2]>,
    rotational: bool,
    other: Option<&'a str>,
    other_point: Option<[f64; 2]>,
    support: &'a Option<String>,
}

/// Names in the file resolved to bodies and supports.
struct Refs<'a> {
    ck: &'a Check<'a>,
    bodies: &'a [Body],
    names: &'a HashMap<String, usize>,
    supports: &'a HashMap<String, usize>,
}

impl Refs<'_> {
    fn body(&self, field: &str, name: &str) -> Result<BodyRef, ModelError> {
        if name == "ground" {
            Ok(BodyRef::Ground)
        } else {
            self.names
                .get(name)
                .map(|&i| BodyRef::Body(i))
                .ok_or_else(|| self.ck.err(field, format!("no body named '{name}'")))
        }
    }

    fn support(&self, field: &str, s: &Option<String>) -> Result<Option<usize>, ModelError> {
        match s {
            None => Ok(None),
            Some(n) => self
                .supports
                .get(n)
                .copied()
                .map(Some)
                .ok_or_else(|| self.ck.err(field, format!("no support named '{n}'"))),
        }
    }

    /// A body of the scene (not the ground) for field `field`.
    fn scene_body(&self, field: &str, name: &str) -> Result<usize, ModelError> {
        match self.body(field, name)? {
            BodyRef::Body(b) => Ok(b),
            BodyRef::Ground => Err(self.ck.err(field, "must be a body")),
        }
    }

    /// Where a spring or hysteretic element acts: a point and direction (against a support, or
    /// relative to a point of `other`), or a body's θ; and its support.
    fn attachment(
        &self,
        fld: &dyn Fn(&str) -> String,
        p: &Placement,
    ) -> Result<(Attachment, Option<usize>), ModelError> {
        let ck = self.ck;
        let b = self.scene_body(&fld("body"), p.body)?;
        let support = self.support(&fld("support"), p.support)?;
        if p.rotational {
            if self.bodies[b].dofs[2].is_none() {
                return Err(ck.err(&fld("rotational"), "the body has no theta DOF"));
            }
            if p.other.is_some() {
                return Err(ck.err(&fld("other"), "a rotational element has no other body"));
            }
            return Ok((Attachment::Rotation { body: b }, support));
        }
        let d = (p.direction)
            .ok_or_else(|| ck.err(&fld("direction"), "required unless rotational = true"))?;
        let (point, direction) = (
            ck.vec2(&fld("point"), p.point)?,
            ck.unit(&fld("direction"), d)?,
        );
        let Some(other) = p.other else {
            if p.other_point.is_some() {
                return Err(ck.err(&fld("other_point"), "given without `other`"));
            }
            if self.bodies[b].has_no_dofs() {
                return Err(ck.err(
                    &fld("body"),
                    "the body has no DOFs (it moves with the ground): the element would act on \
                     nothing",
                ));
            }
            let att = Attachment::Point {
                body: b,
                point,
                direction,
            };
            return Ok((att, support));
        };
        let o = self.scene_body(&fld("other"), other)?;
        if o == b {
            return Err(ck.err(&fld("other"), "an element cannot join a body to itself"));
        }
        if support.is_some() {
            return Err(ck.err(
                &fld("support"),
                "an element between two bodies has no support",
            ));
        }
        if self.bodies[b].has_no_dofs() && self.bodies[o].has_no_dofs() {
            return Err(ck.err(
                &fld("other"),
                "neither body has DOFs: the element would act on nothing",
            ));
        }
        let other_point = ck.vec2(&fld("other_point"), p.other_point.unwrap_or([0.0; 2]))?;
        let att = Attachment::Relative {
            body: b,
            point,
            other: o,
            other_point,
            direction,
        };
        Ok((att, None))
    }

    /// Reference position of a body (ground: the origin).
    fn reference(&self, r: BodyRef) -> Vector2<f64> {
        match r {
            BodyRef::Body(k) => self.bodies[k].reference,
            BodyRef::Ground => Vector2::zeros(),
        }
    }
}

/// One `[[contact]]`: a point on a body against a face, with its gap, μ and restitution.
fn compile_contact(i: usize, c: &ContactSpec, refs: &Refs) -> Result<Contact, ModelError> {
    let ck = refs.ck;
    let fld = |k: &str| format!("contact.{i}.{k}");
    let pb = refs.body(&fld("body"), &c.body)?;
    let fb = refs.body(&fld("face_body"), &c.face_body)?;
    if pb == fb {
        return Err(ck.err(&fld("face_body"), "a body cannot touch itself"));
    }
    if pb == BodyRef::Ground {
        return Err(ck.err(
            &fld("body"),
            "the contact point must be on a body (put the face on ground)",
        ));
    }
    let no_dofs = |r: BodyRef| match r {
        BodyRef::Body(k) => refs.bodies[k].has_no_dofs(),
        BodyRef::Ground => true,
    };
    if no_dofs(pb) && no_dofs(fb) {
        return Err(ck.err(
            &fld("face_body"),
            "neither body has DOFs (fixed or moved by the ground): the contact could not act",
        ));
    }
    let point = ck.vec2(&fld("point"), c.point)?;
    let normal = ck.unit(&fld("normal"), c.normal)?;
    let gap = ck.finite(&fld("gap"), c.gap)?;
    let mu = ck.nonneg(&fld("mu"), c.mu)?;
    let eps = ck.nonneg(&fld("restitution"), c.restitution)?;
    if eps > 1.0 {
        return Err(ck.err(&fld("restitution"), format!("must be in [0, 1], got {eps}")));
    }
    let xa = refs.reference(pb);
    let xb = refs.reference(fb);
    Ok(Contact {
        name: c.name.clone(),
        point_body: pb,
        point,
        face_body: fb,
        face_point: xa + point - xb - gap * normal,
        face_normal: normal,
        law: ContactLaw {
            mu,
            restitution: eps,
        },
    })
}

/// `[[spring]]` tables: linear spring–dampers.
fn compile_springs(f: &SceneFile, refs: &Refs) -> Result<Vec<Spring>, ModelError> {
    let ck = refs.ck;
    let mut springs = Vec::new();
    for (i, s) in f.springs.iter().enumerate() {
        let fld = |k: &str| format!("spring.{i}.{k}");
        let (attachment, support) = refs.attachment(
            &fld,
            &Placement {
                body: &s.body,
                point: s.point,
                direction: s.direction,
                rotational: s.rotational,
                other: s.other.as_deref(),
                other_point: s.other_point,
                support: &s.support,
            },
        )?;
        springs.push(Spring {
            name: s.name.clone(),
            attachment,
            stiffness: ck.nonneg(&fld("stiffness"), s.stiffness)?,
            damping: ck.nonneg(&fld("damping"), s.damping)?,
            support,
        });
    }
    Ok(springs)
}

/// `[[hysteretic]]` tables: elements following a hysteretic law.
fn compile_hysteretic(f: &SceneFile, refs: &Refs) -> Result<Vec<HystereticElement>, ModelError> {
    let ck = refs.ck;
    let mut out = Vec::new();
    for (i, s) in f.hysteretic.iter().enumerate() {
        let fld = |k: &str| format!("hysteretic.{i}.{k}");
        let law = Hysteretic::new(s.law.clone()).map_err(|e| ck.err(&fld("law"), e.to_string()))?;
        let (attachment, support) = refs.attachment(
            &fld,
            &Placement {
                body: &s.body,
                point: s.point,
                direction: s.direction,
                rotational: s.rotational,
                other: s.other.as_deref(),
                other_point: s.other_point,
                support: &s.support,
            },
        )?;
        out.push(HystereticElement {
            name: s.name.clone(),
            attachment,
            law,
            damping: ck.nonneg(&fld("damping"), s.damping)?,
            support,
        });
    }
    Ok(out)
}
