//! Model files (TOML): a general scene of bodies, contacts, springs, supports and solver
//! settings. Unknown keys are rejected; every error names the file, line and field.

use crate::excitation::{ExcitationError, GroundMotion, Processing};
use crate::hysteresis::{Hysteretic, Law};
use crate::scene::{
    Attachment, Body, BodyRef, Contact, HystereticElement, MassDamping, Motion, Scene, Settings,
    Spring, Support,
};
use nalgebra::{DVector, Vector2};
use serde::Deserialize;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Errors of reading, overriding or validating a model.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    #[error("{}: cannot read: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{}:{line}:{column}: {message}", path.display())]
    Parse {
        path: PathBuf,
        line: usize,
        column: usize,
        message: String,
    },
    #[error("{}:{line}: {field}: {reason}", path.display())]
    Invalid {
        path: PathBuf,
        /// 0 when the field is absent from the file.
        line: usize,
        field: String,
        reason: String,
    },
    #[error("--set {key}: {reason}")]
    Override { key: String, reason: String },
    #[error("{}: {source}", path.display())]
    Excitation {
        path: PathBuf,
        #[source]
        source: ExcitationError,
    },
}

impl ModelError {
    /// Line of the error in the model file, when known.
    pub fn line(&self) -> Option<usize> {
        match self {
            ModelError::Parse { line, .. } | ModelError::Invalid { line, .. } if *line > 0 => {
                Some(*line)
            }
            _ => None,
        }
    }
}

/// Solver settings as written in a model file (`[solver]`); absent keys take defaults.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    pub method: Option<String>,
    pub t_end: Option<f64>,
    pub output_dt: Option<f64>,
    pub rtol: Option<f64>,
    pub atol: Option<f64>,
    pub h_max: Option<f64>,
    pub event_time_tol: Option<f64>,
    pub gap_tol: Option<f64>,
    pub velocity_tol: Option<f64>,
    pub accumulation_rule: Option<bool>,
    pub zeno_velocity: Option<f64>,
    pub min_event_spacing: Option<f64>,
    pub max_events: Option<usize>,
    pub max_steps: Option<usize>,
    pub stop_at_samples: Option<bool>,
    /// Window (s) within which hysteretic branch events are applied together.
    pub branch_window: Option<f64>,
    pub lemke_max_pivots: Option<usize>,
    /// Fixed step of time-stepping / penalty methods.
    pub step: Option<f64>,
    /// Contact stiffness of the penalty method, N/m.
    pub contact_stiffness: Option<f64>,
    /// θ of the Moreau–Jean scheme (0.5–1).
    pub theta: Option<f64>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    pub name: String,
    pub mass: f64,
    #[serde(default)]
    pub inertia: f64,
    /// Subset of "x", "y", "theta".
    pub dofs: Vec<String>,
    #[serde(default)]
    pub position: [f64; 2],
    #[serde(default)]
    pub initial_displacement: [f64; 3],
    #[serde(default)]
    pub initial_velocity: [f64; 3],
    /// Constant force (x, y) and moment on the body.
    #[serde(default)]
    pub load: [f64; 3],
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
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
    #[serde(default)]
    pub mu: f64,
    #[serde(default)]
    pub restitution: f64,
}

fn ground() -> String {
    "ground".into()
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringSpec {
    pub name: String,
    pub body: String,
    #[serde(default)]
    pub point: [f64; 2],
    /// World direction of a translational spring.
    pub direction: Option<[f64; 2]>,
    /// Torsional spring on θ instead.
    #[serde(default)]
    pub rotational: bool,
    pub stiffness: f64,
    #[serde(default)]
    pub damping: f64,
    pub support: Option<String>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HystereticSpec {
    pub name: String,
    pub body: String,
    #[serde(default)]
    pub point: [f64; 2],
    pub direction: Option<[f64; 2]>,
    #[serde(default)]
    pub rotational: bool,
    pub law: Law,
    #[serde(default)]
    pub damping: f64,
    pub support: Option<String>,
}

#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SupportSpec {
    pub name: String,
    /// "harmonic" or "record".
    pub kind: String,
    pub amplitude: Option<f64>,
    /// Hz.
    pub frequency: Option<f64>,
    pub phase: Option<f64>,
    /// Record file (AT2 or two columns), relative to the model file.
    pub file: Option<String>,
    pub processing: Option<Processing>,
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
    pub title: Option<String>,
    #[serde(default)]
    pub solver: SolverSpec,
    /// Gravity vector (x, y), m/s², applied as m·g to x/y DOFs.
    pub gravity: Option<[f64; 2]>,
    #[serde(default, rename = "body")]
    pub bodies: Vec<BodySpec>,
    #[serde(default, rename = "contact")]
    pub contacts: Vec<ContactSpec>,
    #[serde(default, rename = "spring")]
    pub springs: Vec<SpringSpec>,
    #[serde(default, rename = "hysteretic")]
    pub hysteretic: Vec<HystereticSpec>,
    #[serde(default, rename = "support")]
    pub supports: Vec<SupportSpec>,
}

/// Locates a dotted field path (`body.1.mass`) in TOML text: (line, column), 1-based. Falls
/// back to the nearest enclosing table or key that exists.
pub fn locate(text: &str, path: &str) -> Option<(usize, usize)> {
    let doc = toml_edit::Document::parse(text).ok()?;
    let segs: Vec<&str> = path.split('.').collect();
    let span = find_in_table(doc.as_table(), &segs, None)?;
    Some(line_col(text, span.start))
}

type Span = Option<std::ops::Range<usize>>;

fn find_in_table(t: &toml_edit::Table, segs: &[&str], best: Span) -> Span {
    let Some((first, rest)) = segs.split_first() else {
        return best.or(t.span());
    };
    match t.get_key_value(first) {
        None => best.or(t.span()),
        Some((k, item)) => {
            let here = k.span().or(item.span()).or(best);
            find_in_item(item, rest, here)
        }
    }
}

fn find_in_item(item: &toml_edit::Item, segs: &[&str], best: Span) -> Span {
    if segs.is_empty() {
        return best;
    }
    match item {
        toml_edit::Item::Table(t) => find_in_table(t, segs, best),
        toml_edit::Item::ArrayOfTables(a) => {
            match segs[0].parse::<usize>().ok().and_then(|i| a.get(i)) {
                Some(t) => find_in_table(t, &segs[1..], t.span().or(best)),
                None => best,
            }
        }
        toml_edit::Item::Value(v) => find_in_value(v, segs, best),
        _ => best,
    }
}

fn find_in_value(v: &toml_edit::Value, segs: &[&str], best: Span) -> Span {
    let Some((first, rest)) = segs.split_first() else {
        return best;
    };
    match v {
        toml_edit::Value::InlineTable(t) => match (t.key(first), t.get(first)) {
            (Some(k), Some(v)) => find_in_value(v, rest, k.span().or(v.span()).or(best)),
            _ => best,
        },
        toml_edit::Value::Array(a) => match first.parse::<usize>().ok().and_then(|i| a.get(i)) {
            Some(v) => find_in_value(v, rest, v.span().or(best)),
            None => best,
        },
        _ => best,
    }
}

fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before
        .rfind('\n')
        .map_or(before.len(), |p| before.len() - p - 1)
        + 1;
    (line, col)
}

/// Applies `key.path=value` overrides to TOML text. Array-of-table segments are an index, a
/// `name`, or `*` (all). The value is parsed as TOML (number, bool, string) or taken as a string.
pub fn apply_overrides(text: &str, overrides: &[String]) -> Result<String, ModelError> {
    if overrides.is_empty() {
        return Ok(text.to_string());
    }
    let mut doc: toml_edit::DocumentMut =
        text.parse()
            .map_err(|e: toml_edit::TomlError| ModelError::Override {
                key: String::new(),
                reason: e.to_string(),
            })?;
    for o in overrides {
        let (key, raw) = o.split_once('=').ok_or_else(|| ModelError::Override {
            key: o.clone(),
            reason: "expected key.path=value".into(),
        })?;
        let value: toml_edit::Value = raw
            .trim()
            .parse()
            .unwrap_or_else(|_| toml_edit::Value::from(raw.trim()));
        let segs: Vec<&str> = key.trim().split('.').collect();
        let n =
            set_path(doc.as_item_mut(), &segs, &value).map_err(|reason| ModelError::Override {
                key: key.to_string(),
                reason,
            })?;
        if n == 0 {
            return Err(ModelError::Override {
                key: key.to_string(),
                reason: "matches no field".into(),
            });
        }
    }
    Ok(doc.to_string())
}

fn set_path(
    item: &mut toml_edit::Item,
    segs: &[&str],
    value: &toml_edit::Value,
) -> Result<usize, String> {
    let Some((first, rest)) = segs.split_first() else {
        return Err("empty key".into());
    };
    match item {
        toml_edit::Item::ArrayOfTables(a) => {
            let mut count = 0;
            for (i, t) in a.iter_mut().enumerate() {
                let named = t.get("name").and_then(|v| v.as_str()) == Some(*first);
                if *first == "*" || first.parse::<usize>() == Ok(i) || named {
                    let mut it = toml_edit::Item::Table(t.clone());
                    count += set_path(&mut it, rest, value)?;
                    if let toml_edit::Item::Table(nt) = it {
                        *t = nt;
                    }
                }
            }
            Ok(count)
        }
        toml_edit::Item::Table(t) => {
            if rest.is_empty() {
                match t.get_mut(first) {
                    Some(toml_edit::Item::Value(v))
                        if (!v.is_inline_table() && !v.is_array())
                            || (v.is_inline_table() && value.is_inline_table())
                            || (v.is_array() && value.is_array()) =>
                    {
                        let decor = v.decor().clone();
                        *v = value.clone();
                        *v.decor_mut() = decor;
                    }
                    Some(_) => {
                        return Err(format!(
                            "'{first}' is a table or array: give a value of the same kind"
                        ));
                    }
                    None => {
                        t.insert(first, toml_edit::Item::Value(value.clone()));
                    }
                }
                Ok(1)
            } else {
                let child = t
                    .get_mut(first)
                    .ok_or_else(|| format!("no table '{first}'"))?;
                set_path(child, rest, value)
            }
        }
        toml_edit::Item::Value(v) => set_in_value(v, segs, value),
        _ => Err(format!("cannot descend into '{first}'")),
    }
}

/// Set a scalar inside an inline table or array (`law.stiffness`, `gaps.0`).
fn set_in_value(
    v: &mut toml_edit::Value,
    segs: &[&str],
    value: &toml_edit::Value,
) -> Result<usize, String> {
    let Some((first, rest)) = segs.split_first() else {
        return Err("empty key".into());
    };
    let child = match v {
        toml_edit::Value::InlineTable(t) => {
            if rest.is_empty() && !t.contains_key(first) {
                t.insert(*first, value.clone());
                return Ok(1);
            }
            t.get_mut(first)
                .ok_or_else(|| format!("no key '{first}'"))?
        }
        toml_edit::Value::Array(a) => {
            let i: usize = first
                .parse()
                .map_err(|_| format!("'{first}' is not an index of an array"))?;
            let len = a.len();
            a.get_mut(i)
                .ok_or_else(|| format!("index {i} out of range (array of {len})"))?
        }
        _ => return Err(format!("cannot descend into '{first}'")),
    };
    if rest.is_empty() {
        if child.is_inline_table() != value.is_inline_table()
            || child.is_array() != value.is_array()
        {
            return Err(format!("'{first}': give a value of the same kind"));
        }
        let decor = child.decor().clone();
        *child = value.clone();
        *child.decor_mut() = decor;
        Ok(1)
    } else {
        set_in_value(child, rest, value)
    }
}

/// Reads a model file (general scene or bridge), applies overrides, validates, compiles.
pub fn load(path: &Path, overrides: &[String]) -> Result<Scene, ModelError> {
    let text = std::fs::read_to_string(path).map_err(|e| ModelError::Io {
        path: path.to_path_buf(),
        source: e,
    })?;
    load_str(&text, path, overrides)
}

/// As [`load`], from text already read (`path` names it in errors and resolves relative files).
pub fn load_str(text: &str, path: &Path, overrides: &[String]) -> Result<Scene, ModelError> {
    load_str_with(text, path, overrides, &Motions::default())
}

/// As [`load_str`], taking processed records from (and adding them to) `motions`.
pub fn load_str_with(
    text: &str,
    path: &Path,
    overrides: &[String],
    motions: &Motions,
) -> Result<Scene, ModelError> {
    let text = apply_overrides(text, overrides)?;
    let value: toml::Table = parse(&text, path)?;
    if value.contains_key("deck") {
        return crate::bridge::compile_str(&text, path, motions);
    }
    let file: SceneFile = parse(&text, path)?;
    compile(&file, &text, path, motions)
}

/// Deserialize with file/line/column on error.
pub fn parse<T: serde::de::DeserializeOwned>(text: &str, path: &Path) -> Result<T, ModelError> {
    toml::from_str(text).map_err(|e: toml::de::Error| {
        let (line, column) = e.span().map_or((0, 0), |s| line_col(text, s.start));
        ModelError::Parse {
            path: path.to_path_buf(),
            line,
            column,
            message: e.message().to_string(),
        }
    })
}

/// Validation context: builds `Invalid` errors located in the text.
pub struct Check<'a> {
    pub text: &'a str,
    pub path: &'a Path,
}

impl Check<'_> {
    pub fn err(&self, field: &str, reason: impl Into<String>) -> ModelError {
        ModelError::Invalid {
            path: self.path.to_path_buf(),
            line: locate(self.text, field).map_or(0, |l| l.0),
            field: field.to_string(),
            reason: reason.into(),
        }
    }
    pub fn finite(&self, field: &str, x: f64) -> Result<f64, ModelError> {
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.err(field, format!("must be a finite number, got {x}")))
        }
    }
    pub fn positive(&self, field: &str, x: f64) -> Result<f64, ModelError> {
        self.finite(field, x)?;
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(field, format!("must be > 0, got {x}")))
        }
    }
    pub fn nonneg(&self, field: &str, x: f64) -> Result<f64, ModelError> {
        self.finite(field, x)?;
        if x >= 0.0 {
            Ok(x)
        } else {
            Err(self.err(field, format!("must be ≥ 0, got {x}")))
        }
    }
    pub fn vec2(&self, field: &str, v: [f64; 2]) -> Result<Vector2<f64>, ModelError> {
        for (i, x) in v.iter().enumerate() {
            self.finite(&format!("{field}[{i}]"), *x)
                .map_err(|_| self.err(field, "must be finite"))?;
        }
        Ok(Vector2::new(v[0], v[1]))
    }
    pub fn unit(&self, field: &str, v: [f64; 2]) -> Result<Vector2<f64>, ModelError> {
        let v = self.vec2(field, v)?;
        let n = v.norm();
        if n < 1e-12 {
            return Err(self.err(field, "must be a nonzero direction"));
        }
        Ok(v / n)
    }
}

/// Settings from `[solver]`.
pub fn settings(s: &SolverSpec, ck: &Check) -> Result<Settings, ModelError> {
    let mut out = Settings::default();
    macro_rules! pos {
        ($f:ident) => {
            if let Some(x) = s.$f {
                out.$f = ck.positive(concat!("solver.", stringify!($f)), x)?;
            }
        };
    }
    pos!(t_end);
    pos!(output_dt);
    pos!(rtol);
    pos!(atol);
    pos!(event_time_tol);
    pos!(gap_tol);
    pos!(velocity_tol);
    pos!(zeno_velocity);
    pos!(min_event_spacing);
    if let Some(x) = s.h_max {
        out.h_max = ck.nonneg("solver.h_max", x)?;
    }
    if let Some(x) = s.branch_window {
        out.branch_window = ck.nonneg("solver.branch_window", x)?;
    }
    if let Some(b) = s.accumulation_rule {
        out.accumulation_rule = b;
    }
    if let Some(b) = s.stop_at_samples {
        out.stop_at_samples = b;
    }
    if let Some(n) = s.max_events {
        out.max_events = n;
    }
    if let Some(n) = s.max_steps {
        out.max_steps = n;
    }
    if let Some(n) = s.lemke_max_pivots {
        out.lemke.max_pivots = n;
    }
    if let Some(x) = s.step {
        out.step = ck.positive("solver.step", x)?;
    }
    if let Some(x) = s.contact_stiffness {
        out.contact_stiffness = ck.positive("solver.contact_stiffness", x)?;
    }
    if let Some(x) = s.theta {
        ck.finite("solver.theta", x)?;
        if !(0.5..=1.0).contains(&x) {
            return Err(ck.err("solver.theta", format!("must be in [0.5, 1], got {x}")));
        }
        out.theta = x;
    }
    if let Some(m) = &s.method {
        out.method = crate::scene::Method::parse(m).ok_or_else(|| {
            ck.err(
                "solver.method",
                format!("unknown method '{m}' (event, moreau, penalty, penalty-explicit)"),
            )
        })?;
    }
    Ok(out)
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
pub fn compile(
    f: &SceneFile,
    text: &str,
    path: &Path,
    motions: &Motions,
) -> Result<Scene, ModelError> {
    let ck = Check { text, path };
    let settings = settings(&f.solver, &ck)?;
    let mut bodies = Vec::new();
    let mut names: HashMap<String, usize> = HashMap::new();
    let mut mass = Vec::new();
    let mut dof_names = Vec::new();
    let mut q0 = Vec::new();
    let mut v0 = Vec::new();
    let mut loads = Vec::new();
    let gravity = match f.gravity {
        Some(g) => ck.vec2("gravity", g)?,
        None => Vector2::zeros(),
    };
    for (i, b) in f.bodies.iter().enumerate() {
        let fld = |k: &str| format!("body.{i}.{k}");
        if b.name.is_empty() || b.name == "ground" || names.contains_key(&b.name) {
            return Err(ck.err(
                &fld("name"),
                format!("'{}' is empty, reserved or repeated", b.name),
            ));
        }
        ck.positive(&fld("mass"), b.mass)?;
        let mut dofs = [None; 3];
        if b.dofs.is_empty() {
            return Err(ck.err(
                &fld("dofs"),
                "a body needs at least one of \"x\", \"y\", \"theta\"",
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
                dofs[a] = Some(mass.len());
                mass.push(if a == 2 { b.inertia } else { b.mass });
                dof_names.push(format!("{}.{}", b.name, ["x", "y", "theta"][a]));
                q0.push(b.initial_displacement[a]);
                v0.push(b.initial_velocity[a]);
                let g = if a < 2 { b.mass * gravity[a] } else { 0.0 };
                loads.push(g + b.load[a]);
            }
        }
        names.insert(b.name.clone(), i);
        bodies.push(Body {
            name: b.name.clone(),
            mass: b.mass,
            inertia: b.inertia,
            reference,
            dofs,
        });
    }
    if mass.is_empty() {
        return Err(ck.err("body", "the scene has no degrees of freedom"));
    }
    let body_ref = |field: &str, name: &str| -> Result<BodyRef, ModelError> {
        if name == "ground" {
            Ok(BodyRef::Ground)
        } else {
            names
                .get(name)
                .map(|&i| BodyRef::Body(i))
                .ok_or_else(|| ck.err(field, format!("no body named '{name}'")))
        }
    };
    let mut supports = Vec::new();
    let mut support_names: HashMap<String, usize> = HashMap::new();
    for (i, s) in f.supports.iter().enumerate() {
        let fld = |k: &str| format!("support.{i}.{k}");
        if support_names.contains_key(&s.name) {
            return Err(ck.err(&fld("name"), format!("'{}' repeated", s.name)));
        }
        ck.finite(&fld("factor"), s.factor)?;
        let motion = match s.kind.as_str() {
            "harmonic" => Motion::Harmonic {
                amplitude: ck.finite(
                    &fld("amplitude"),
                    s.amplitude.ok_or_else(|| {
                        ck.err(&fld("amplitude"), "required for a harmonic support")
                    })?,
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
                let motion = motions.get(path, file, s.processing.clone().unwrap_or_default())?;
                Motion::Record(motion)
            }
            k => {
                return Err(ck.err(
                    &fld("kind"),
                    format!("unknown support kind '{k}' (harmonic, record)"),
                ));
            }
        };
        support_names.insert(s.name.clone(), i);
        supports.push(Support {
            name: s.name.clone(),
            motion,
            factor: s.factor,
        });
    }
    let support_ref = |field: &str, s: &Option<String>| -> Result<Option<usize>, ModelError> {
        match s {
            None => Ok(None),
            Some(n) => support_names
                .get(n)
                .copied()
                .map(Some)
                .ok_or_else(|| ck.err(field, format!("no support named '{n}'"))),
        }
    };
    let mut contacts = Vec::new();
    for (i, c) in f.contacts.iter().enumerate() {
        let fld = |k: &str| format!("contact.{i}.{k}");
        let pb = body_ref(&fld("body"), &c.body)?;
        let fb = body_ref(&fld("face_body"), &c.face_body)?;
        if pb == fb {
            return Err(ck.err(&fld("face_body"), "a body cannot touch itself"));
        }
        if pb == BodyRef::Ground {
            return Err(ck.err(
                &fld("body"),
                "the contact point must be on a body (put the face on ground)",
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
        let xa = match pb {
            BodyRef::Body(k) => bodies[k].reference,
            BodyRef::Ground => Vector2::zeros(),
        };
        let xb = match fb {
            BodyRef::Body(k) => bodies[k].reference,
            BodyRef::Ground => Vector2::zeros(),
        };
        contacts.push(Contact {
            name: c.name.clone(),
            point_body: pb,
            point,
            face_body: fb,
            face_point: xa + point - xb - gap * normal,
            face_normal: normal,
            mu,
            restitution: eps,
        });
    }
    let attachment = |fld: &dyn Fn(&str) -> String,
                      body: &str,
                      point: [f64; 2],
                      direction: Option<[f64; 2]>,
                      rotational: bool|
     -> Result<Attachment, ModelError> {
        let b = match body_ref(&fld("body"), body)? {
            BodyRef::Body(b) => b,
            BodyRef::Ground => return Err(ck.err(&fld("body"), "must be a body")),
        };
        if rotational {
            if bodies[b].dofs[2].is_none() {
                return Err(ck.err(&fld("rotational"), "the body has no theta DOF"));
            }
            Ok(Attachment::Rotation { body: b })
        } else {
            let d = direction
                .ok_or_else(|| ck.err(&fld("direction"), "required unless rotational = true"))?;
            Ok(Attachment::Point {
                body: b,
                point: ck.vec2(&fld("point"), point)?,
                direction: ck.unit(&fld("direction"), d)?,
            })
        }
    };
    let mut springs = Vec::new();
    for (i, s) in f.springs.iter().enumerate() {
        let fld = |k: &str| format!("spring.{i}.{k}");
        springs.push(Spring {
            name: s.name.clone(),
            attachment: attachment(&fld, &s.body, s.point, s.direction, s.rotational)?,
            stiffness: ck.nonneg(&fld("stiffness"), s.stiffness)?,
            damping: ck.nonneg(&fld("damping"), s.damping)?,
            support: support_ref(&fld("support"), &s.support)?,
        });
    }
    let mut hysteretic = Vec::new();
    for (i, s) in f.hysteretic.iter().enumerate() {
        let fld = |k: &str| format!("hysteretic.{i}.{k}");
        let law = Hysteretic::new(s.law.clone()).map_err(|e| ck.err(&fld("law"), e.to_string()))?;
        hysteretic.push(HystereticElement {
            name: s.name.clone(),
            attachment: attachment(&fld, &s.body, s.point, s.direction, s.rotational)?,
            law,
            damping: ck.nonneg(&fld("damping"), s.damping)?,
            support: support_ref(&fld("support"), &s.support)?,
        });
    }
    Ok(Scene {
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

/// Read and process a record named relative to the model file.
pub fn load_motion(
    model: &Path,
    file: &str,
    p: Processing,
) -> Result<Arc<GroundMotion>, ModelError> {
    Motions::default().get(model, file, p)
}

/// The record file a model names: relative to the model file, else to the working directory,
/// else to a directory above the model (the project root above `models/`).
fn resolve_record(model: &Path, file: &str) -> PathBuf {
    let base = model.parent().unwrap_or(Path::new("."));
    let rp = base.join(file);
    if rp.exists() {
        return rp;
    }
    let alt = PathBuf::from(file);
    if alt.exists() {
        alt
    } else if let Some(root) = base.ancestors().find(|a| a.join(file).exists()) {
        root.join(file)
    } else {
        rp
    }
}

/// Processed ground motions by (record file, processing): the supports of one model that share
/// a record share one motion, and the loads of one study (its sweeps) read each record once.
#[derive(Debug, Default)]
pub struct Motions(std::sync::Mutex<Vec<(PathBuf, Processing, Arc<GroundMotion>)>>);

impl Motions {
    /// The motion of `file` (named relative to `model`) processed by `p`, read at first use.
    pub fn get(
        &self,
        model: &Path,
        file: &str,
        p: Processing,
    ) -> Result<Arc<GroundMotion>, ModelError> {
        let rp = resolve_record(model, file);
        let known = |list: &[(PathBuf, Processing, Arc<GroundMotion>)]| {
            list.iter()
                .find(|(f, q, _)| *f == rp && *q == p)
                .map(|(_, _, m)| m.clone())
        };
        // a panic elsewhere while the list was held leaves it intact: use it anyway
        let lock = || self.0.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(m) = known(&lock()) {
            return Ok(m);
        }
        let err = |e| ModelError::Excitation {
            path: model.to_path_buf(),
            source: e,
        };
        let rec = crate::excitation::read_any(&rp).map_err(err)?;
        let g = Arc::new(GroundMotion::from_record(&rec, &p).map_err(err)?);
        let mut list = lock();
        // another thread may have read it meanwhile: keep one
        if let Some(m) = known(&list) {
            return Ok(m);
        }
        list.push((rp, p, g.clone()));
        Ok(g)
    }
}
