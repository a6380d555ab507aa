//! A model's output folder, `<model stem>.out/` beside the model: the workbench's exports
//! (`export-<n>-chart.csv`, `export-<n>-history.csv`, `export-<n>-events.csv`) and its study
//! tables (`pga-<n>.csv`, …) all go there, each under a name no file has yet (the first free
//! `n`), so nothing is ever overwritten. When the model's folder is not writable, the same
//! folder name in the current directory takes them. Study tables written before this folder
//! existed, in `<model stem>.studies/`, are still listed by `f`.

use std::path::{Path, PathBuf};

/// The suffix of the output folder's name.
pub const OUT_SUFFIX: &str = "out";
/// The suffix of the older folder of study tables (read, never written).
pub const OLD_STUDIES_SUFFIX: &str = "studies";
/// The first part of an export's file names (`export-3-chart.csv`).
pub const EXPORT_PREFIX: &str = "export-";

/// `<stem>.<suffix>` beside the model, then in the current directory.
fn dirs_named(model: &Path, suffix: &str) -> Vec<PathBuf> {
    let stem = model
        .file_stem()
        .map_or("model".into(), |s| s.to_string_lossy().into_owned());
    let name = format!("{stem}.{suffix}");
    let beside = match model.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.join(&name),
        _ => PathBuf::from(&name),
    };
    let here = PathBuf::from(&name);
    if beside == here {
        vec![beside]
    } else {
        vec![beside, here]
    }
}

/// Where the model's exports and study tables are written: `<stem>.out/` beside the model
/// (`models/four-span.out` for `models/four-span.toml`), then in the current directory.
pub fn out_dirs(model: &Path) -> Vec<PathBuf> {
    dirs_named(model, OUT_SUFFIX)
}

/// Where `f` looks for study tables: [`out_dirs`], then the older `<stem>.studies/`.
pub fn reopen_dirs(model: &Path) -> Vec<PathBuf> {
    let mut dirs = out_dirs(model);
    dirs.extend(dirs_named(model, OLD_STUDIES_SUFFIX));
    dirs
}

/// An export's file (not a study table) by its name.
pub fn is_export(path: &Path) -> bool {
    path.file_name()
        .is_some_and(|n| n.to_string_lossy().starts_with(EXPORT_PREFIX))
}
