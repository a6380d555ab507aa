//! The shake-table bridge model (paper §2, §4): compiled into a general scene.

use crate::model::ModelError;
use crate::scene::Scene;
use std::path::Path;

/// Compile a bridge model file's text into a scene.
pub fn compile_str(_text: &str, path: &Path) -> Result<Scene, ModelError> {
    Err(ModelError::Invalid {
        path: path.to_path_buf(),
        line: 0,
        field: "deck".into(),
        reason: "bridge models are not supported yet".into(),
    })
}
