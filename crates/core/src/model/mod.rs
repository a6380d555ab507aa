//! Model files (TOML): a general scene of bodies, contacts, springs, supports and solver
//! settings, or a bridge (a `[deck]` table). Unknown keys are rejected; every error names the
//! file, line and field.
//!
//! [`load_str_with`] is the one entry: the text is read once, `--set` overrides applied, the
//! TOML parsed once, and the file compiled as a bridge or a general scene.

pub mod bridge;
pub mod check;
pub mod limit_state;
pub mod limits;
pub mod overrides;
pub mod records;
pub mod scene_file;

pub mod solver;
pub mod uncertain;
pub mod warnings;

pub use check::{Applied, Check, ModelError, locate};
pub(crate) use limits::StepLimit;
pub use limits::{FREE_VIBRATION_TAIL, event_limit, step_limit};
pub use overrides::apply_overrides;
pub(crate) use overrides::apply_overrides_traced;
pub use records::Motions;
pub use scene_file::{SceneFile, compile};
pub use solver::settings;
pub use warnings::ModelWarning;

use crate::scene::Scene;
use crate::units::UnitSystem;
use serde::Deserialize;
use std::path::Path;
use toml::de::{DeTable, Deserializer};

/// A compiled model and what it was compiled with that its file does not say.
#[derive(Debug)]
pub struct Loaded {
    /// The compiled scene.
    pub scene: Scene,
    /// Defaults taken, records cut, unresolved steps (docs/engine.md, bad input); the front
    /// ends show them, the library never prints.
    pub warnings: Vec<ModelWarning>,
}

/// Reads a model file (general scene or bridge), applies overrides, validates, compiles.
/// Warnings are dropped: [`load_checked`] returns them.
pub fn load(path: &Path, overrides: &[String]) -> Result<Scene, ModelError> {
    load_checked(path, overrides).map(|l| l.scene)
}

/// As [`load`], with the warnings.
pub fn load_checked(path: &Path, overrides: &[String]) -> Result<Loaded, ModelError> {
    let text = crate::input::read_bounded(path, crate::input::MAX_MODEL_BYTES).map_err(|e| {
        ModelError::Io {
            path: path.to_path_buf(),
            source: e,
        }
    })?;
    load_str_checked(&text, path, overrides, &Motions::default())
}

/// As [`load`], from text already read (`path` names it in errors and resolves relative files).
pub fn load_str(text: &str, path: &Path, overrides: &[String]) -> Result<Scene, ModelError> {
    load_str_checked(text, path, overrides, &Motions::default()).map(|l| l.scene)
}

/// As [`load_str`], with the warnings, taking processed records from (and adding them to)
/// `motions`. An explicit step above its stability limit is refused.
pub fn load_str_checked(
    text: &str,
    path: &Path,
    overrides: &[String],
    motions: &Motions,
) -> Result<Loaded, ModelError> {
    compile_text(text, path, overrides, motions, StepLimit::Refuse)
}

/// As [`load_str`], taking processed records from (and adding them to) `motions`: the entry
/// of the studies, which probe where methods fail, so an explicit step above its stability
/// limit is accepted here (with a warning, dropped) and fails at run time as unstable.
pub fn load_str_with(
    text: &str,
    path: &Path,
    overrides: &[String],
    motions: &Motions,
) -> Result<Scene, ModelError> {
    compile_text(text, path, overrides, motions, StepLimit::Warn).map(|l| l.scene)
}

/// The top-level `units` key (SI-kN when absent).
fn units_of(table: &toml::Table, ck: &Check) -> Result<UnitSystem, ModelError> {
    match table.get("units") {
        None => Ok(UnitSystem::default()),
        Some(toml::Value::String(s)) => UnitSystem::parse(s).map_err(|m| ck.err("units", m)),
        Some(v) => Err(ck.err(
            "units",
            format!("must be a string (SI-kN, SI, kip-in), got {}", v.type_str()),
        )),
    }
}

/// The one path: overrides applied, the TOML parsed once, compiled as a bridge or a general
/// scene, then the checks of the whole scene (`limits`).
fn compile_text(
    text: &str,
    path: &Path,
    overrides: &[String],
    motions: &Motions,
    step_limit: StepLimit,
) -> Result<Loaded, ModelError> {
    let (text, applied) = apply_overrides_traced(text, overrides)?;
    let located = |e: toml::de::Error| check::parse_error(&e, &text, path, &applied);
    let doc = DeTable::parse(&text).map_err(located)?;
    // the document as a plain table: what kind of file, and the values toml's own `Table`
    // rejects (integers beyond i64) rejected first, as when it was read that way
    let table = toml::Table::deserialize(Deserializer::from(doc.clone())).map_err(located)?;
    let mut ck = Check {
        text: &text,
        path,
        applied: &applied,
        units: Default::default(),
    };
    ck.units = units_of(&table, &ck)?;
    let mut warnings = Vec::new();
    let bridge = table.contains_key("deck") || table.contains_key("frame");
    let (mut scene, solver) = if bridge {
        let file = bridge::BridgeFile::deserialize(Deserializer::from(doc)).map_err(located)?;
        let scene = bridge::compile(&file, &ck, motions)?;
        warnings.extend(bridge::warnings(&file, &ck));
        if !table.contains_key("damping") {
            let path = ck.path.to_path_buf();
            warnings.push(ModelWarning::NoDamping { path });
        }
        limit_state::check_specs(&file.limit_states, &ck)?;
        uncertain::check_specs(&file.uncertain, &ck)?;
        (scene, file.solver)
    } else {
        bridge::refuse_without_deck(&table, &ck)?;
        let file = SceneFile::deserialize(Deserializer::from(doc)).map_err(located)?;
        limit_state::check_specs(&file.limit_states, &ck)?;
        uncertain::check_specs(&file.uncertain, &ck)?;
        (scene_file::compile(&file, &ck, motions)?, file.solver)
    };
    let given = limits::Given {
        solver: table.contains_key("solver"),
        t_end: solver.t_end.is_some(),
        max_events: solver.max_events.is_some(),
        max_steps: solver.max_steps.is_some(),
        step: solver.step.is_some(),
        contact_stiffness: solver.contact_stiffness.is_some(),
        max_closure: solver.max_closure.is_some(),
        max_penetration: solver.max_penetration.is_some(),
        bridge,
        step_limit,
    };
    scene.units = ck.units;
    escape_controls_in(&mut scene);
    limits::finish(&mut scene, &given, &ck, &mut warnings)?;
    Ok(Loaded { scene, warnings })
}

/// `text` with each control character written as its escape (`\u{1b}`): a model's title and
/// names go to terminals and CSV headers, where a raw escape sequence or line break would act.
pub(crate) fn escape_controls(text: &str) -> String {
    if !text.chars().any(char::is_control) {
        return text.to_string();
    }
    text.chars()
        .map(|c| {
            if c.is_control() {
                c.escape_unicode().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
}

/// The scene's title and every name with their control characters escaped.
fn escape_controls_in(scene: &mut Scene) {
    scene.title = escape_controls(&scene.title);
    let names = (scene.bodies.iter_mut().map(|b| &mut b.name))
        .chain(scene.contacts.iter_mut().map(|c| &mut c.name))
        .chain(scene.springs.iter_mut().map(|s| &mut s.name))
        .chain(scene.hysteretic.iter_mut().map(|h| &mut h.name))
        .chain(scene.supports.iter_mut().map(|s| &mut s.name))
        .chain(scene.dof_names.iter_mut());
    for n in names {
        if n.chars().any(char::is_control) {
            *n = escape_controls(n);
        }
    }
}
