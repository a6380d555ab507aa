//! The model files a workbench can open: the `.toml` files of a folder and of its subfolders
//! (hidden folders, and the runs and studies folders beside models, left out).

use std::path::{Path, PathBuf};

/// How deep subfolders are searched, and how many files are listed at most.
const DEPTH: usize = 4;
const MOST: usize = 500;

/// The `.toml` files under `dir`, sorted by their path.
pub fn list(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let mut out = Vec::new();
    walk(dir, 0, &mut out).map_err(|e| format!("{}: {e}", dir.display()))?;
    out.sort();
    out.truncate(MOST);
    Ok(out)
}

fn walk(dir: &Path, depth: usize, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    for e in std::fs::read_dir(dir)?.flatten() {
        let p = e.path();
        let name = e.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') {
            continue;
        }
        let ty = e.file_type()?;
        if ty.is_dir() || (ty.is_symlink() && p.is_dir()) {
            let skip = name.ends_with(".runs") || name.ends_with(".studies") || name == "target";
            if depth + 1 < DEPTH && !skip {
                // an unreadable subfolder is left out, not an error
                let _ = walk(&p, depth + 1, out);
            }
        } else if p.extension().is_some_and(|x| x == "toml") && out.len() < 4 * MOST {
            out.push(p);
        }
    }
    Ok(())
}

/// The folder a model's list of models is taken from (the model's own).
pub fn folder_of(model: &Path) -> PathBuf {
    match model.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}
