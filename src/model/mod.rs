//! Model files (TOML): a general scene of bodies, contacts, springs, supports and solver
//! settings, or a bridge (a `[deck]` table). Unknown keys are rejected; every error names the
//! file, line and field.
//!
//! [`load_str_with`] is the one entry: the text is read once, `--set` overrides applied, the
//! TOML parsed once, and the file compiled as a bridge or a general scene.

pub mod bridge;
pub mod check;
pub mod overrides;
pub mod records;
pub mod scene_file;
pub mod solver;

pub use check::{Check, ModelError, locate};
pub use overrides::apply_overrides;
pub use records::{Motions, load_motion};
pub use scene_file::{
    BodySpec, ContactSpec, HystereticSpec, SceneFile, SpringSpec, SupportSpec, compile,
};
pub use solver::{SolverSpec, settings};

use crate::scene::Scene;
use serde::Deserialize;
use std::path::Path;
use toml::de::{DeTable, Deserializer};

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
    let located = |e: toml::de::Error| check::parse_error(&e, &text, path);
    let doc = DeTable::parse(&text).map_err(located)?;
    // the document as a plain table: what kind of file, and the values toml's own `Table`
    // rejects (integers beyond i64) rejected first, as when it was read that way
    let table = toml::Table::deserialize(Deserializer::from(doc.clone())).map_err(located)?;
    if table.contains_key("deck") {
        let file = bridge::BridgeFile::deserialize(Deserializer::from(doc)).map_err(located)?;
        bridge::compile(&file, &text, path, motions)
    } else {
        let file = SceneFile::deserialize(Deserializer::from(doc)).map_err(located)?;
        scene_file::compile(&file, &text, path, motions)
    }
}
