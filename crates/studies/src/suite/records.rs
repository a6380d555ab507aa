//! The record pairs of a suite: the `.AT2` files of a folder paired by station
//! ([`crate::stress::record_pairs`]: sorted by name, two consecutive files whose stems are equal
//! but for their last 3 characters are a pair, the first of them longitudinal), or a list file:
//! one pair per line, `longitudinal transverse [name]`, paths relative to the list file and
//! without blanks, `#` to the end of a line a comment. A pair's name is the list's third
//! field, else the station (the common stem without its last 3 characters and trailing `_` or
//! `-`), else the longitudinal file's stem; names are unique.

use crate::stress::record_pairs;
use std::path::{Path, PathBuf};

/// A pair of a suite: its name, the files the model reads (absolute) and the files as the
/// suite names them (in the folder, or as the list writes them).
#[derive(Clone, Debug, PartialEq)]
pub struct SuitePair {
    pub name: String,
    pub longitudinal: PathBuf,
    pub transverse: PathBuf,
    pub longitudinal_label: String,
    pub transverse_label: String,
}

/// Why the records of a suite cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum RecordsError {
    #[error("{path}: cannot read the records: {source}")]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    #[error("{path}:{line}: {reason}")]
    Line {
        path: PathBuf,
        line: usize,
        reason: String,
    },
    #[error("{path}: no record pairs")]
    Empty { path: PathBuf },
}

/// The pairs of `source` (a folder or a list file), and the folder's files without a partner.
pub fn suite_pairs(source: &Path) -> Result<(Vec<SuitePair>, Vec<PathBuf>), RecordsError> {
    let io = |e| RecordsError::Io {
        path: source.to_path_buf(),
        source: e,
    };
    let (pairs, single) = if source.is_dir() {
        folder_pairs(source).map_err(io)?
    } else {
        let text = crate::input::read_bounded(source, crate::input::MAX_MODEL_BYTES).map_err(io)?;
        (list_pairs(source, &text)?, Vec::new())
    };
    if pairs.is_empty() {
        return Err(RecordsError::Empty {
            path: source.to_path_buf(),
        });
    }
    Ok((pairs, single))
}

fn absolute(p: &Path) -> PathBuf {
    std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf())
}

fn file_name(p: &Path) -> String {
    p.file_name().unwrap_or_default().to_string_lossy().into()
}

/// The pairs of a folder and its files without a partner.
fn folder_pairs(dir: &Path) -> std::io::Result<(Vec<SuitePair>, Vec<PathBuf>)> {
    let (pairs, single) = record_pairs(dir)?;
    let pairs = (pairs.into_iter())
        .map(|p| SuitePair {
            name: p.name,
            longitudinal_label: file_name(&p.longitudinal),
            transverse_label: file_name(&p.transverse),
            longitudinal: absolute(&p.longitudinal),
            transverse: absolute(&p.transverse),
        })
        .collect();
    Ok((pairs, single))
}

/// The name of a pair the list does not name: the station of the two stems, else the
/// longitudinal stem.
fn default_name(longitudinal: &Path, transverse: &Path) -> String {
    let stem = |p: &Path| {
        p.file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .to_string()
    };
    let (a, b) = (stem(longitudinal), stem(transverse));
    let station = |s: &str| {
        let cut = s.char_indices().rev().nth(2).map_or(0, |(i, _)| i);
        s[..cut].to_string()
    };
    let common = station(&a);
    if !common.is_empty() && common == station(&b) {
        let name = common.trim_end_matches(['_', '-']);
        if !name.is_empty() {
            return name.to_string();
        }
    }
    a
}

/// The pairs of a list file's `text` (`path` names it in errors and anchors its paths).
pub fn list_pairs(path: &Path, text: &str) -> Result<Vec<SuitePair>, RecordsError> {
    let base = path.parent().unwrap_or(Path::new(""));
    let mut pairs: Vec<(usize, SuitePair)> = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let err = |reason: String| RecordsError::Line {
            path: path.to_path_buf(),
            line,
            reason,
        };
        let content = raw.split('#').next().unwrap_or("");
        let fields: Vec<&str> = content.split_whitespace().collect();
        if fields.is_empty() {
            continue;
        }
        if !(2..=3).contains(&fields.len()) {
            return Err(err(format!(
                "{} fields: expected `longitudinal transverse [name]`",
                fields.len()
            )));
        }
        let file = |f: &str| {
            let p = base.join(f);
            if p.is_file() {
                Ok(absolute(&p))
            } else {
                Err(err(format!(
                    "record '{f}' not found (paths are relative to the list file)"
                )))
            }
        };
        let (l, t) = (file(fields[0])?, file(fields[1])?);
        let name = fields
            .get(2)
            .map_or_else(|| default_name(&l, &t), |n| n.to_string());
        if let Some((first, _)) = pairs.iter().find(|(_, p)| p.name == name) {
            return Err(err(format!(
                "pair name '{name}' already used on line {first}"
            )));
        }
        pairs.push((
            line,
            SuitePair {
                name,
                longitudinal: l,
                transverse: t,
                longitudinal_label: fields[0].to_string(),
                transverse_label: fields[1].to_string(),
            },
        ));
    }
    Ok(pairs.into_iter().map(|(_, p)| p).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn root() -> PathBuf {
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
    }

    #[test]
    fn a_list_names_its_pairs_and_its_bad_lines() {
        let list = root().join("excitations/suite.txt");
        let text = "# two pairs\n\
                    far-field/KOBE_SHI000.AT2 far-field/KOBE_SHI090.AT2\n\
                    \n\
                    NORTHR_MUL009.AT2 far-field/NORTHR_LOS270.AT2 mixed  # a comment\n";
        let pairs = list_pairs(&list, text).unwrap();
        assert_eq!(pairs.len(), 2);
        assert_eq!(pairs[0].name, "KOBE_SHI");
        assert_eq!(pairs[0].longitudinal_label, "far-field/KOBE_SHI000.AT2");
        assert!(pairs[0].longitudinal.is_absolute());
        assert!(
            pairs[0]
                .transverse
                .ends_with("excitations/far-field/KOBE_SHI090.AT2")
        );
        assert_eq!(pairs[1].name, "mixed");
        let bad = |text: &str| list_pairs(&list, text).unwrap_err().to_string();
        let e = bad("# x\nfar-field/KOBE_SHI000.AT2\n");
        assert!(
            e.ends_with(
                "excitations/suite.txt:2: 1 fields: expected `longitudinal transverse [name]`"
            ),
            "{e}"
        );
        let e = bad("far-field/KOBE_SHI000.AT2 nowhere.AT2\n");
        assert!(
            e.ends_with(
                "suite.txt:1: record 'nowhere.AT2' not found (paths are relative to the list file)"
            ),
            "{e}"
        );
        let e =
            bad("NORTHR_MUL009.AT2 NORTHR_MUL279.AT2 a\nNORTHR_LOS000.AT2 NORTHR_LOS270.AT2 a\n");
        assert!(
            e.ends_with("suite.txt:2: pair name 'a' already used on line 1"),
            "{e}"
        );
    }

    #[test]
    fn a_folder_pairs_by_station() {
        let (pairs, single) = suite_pairs(&root().join("excitations/far-field")).unwrap();
        assert_eq!(pairs.len(), 19);
        assert!(single.is_empty());
        let kobe = pairs.iter().find(|p| p.name == "KOBE_SHI").unwrap();
        assert_eq!(kobe.longitudinal_label, "KOBE_SHI000.AT2");
        assert_eq!(kobe.transverse_label, "KOBE_SHI090.AT2");
        let e = suite_pairs(&root().join("src")).unwrap_err().to_string();
        assert!(e.ends_with("src: no record pairs"), "{e}");
    }
}
