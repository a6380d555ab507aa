//! The terminal workbench (ratatui + crossterm) over the engine's public API.

use std::path::Path;

/// Open the workbench on a model file.
pub fn run(_model: &Path) -> Result<(), Box<dyn std::error::Error>> {
    Err("the workbench is not built yet; use `deckspin run MODEL`".into())
}
