//! Three-way merge of model texts, value by value: `base` (the file the edits were made on),
//! `mine` (base + the workbench's unsaved edits), `theirs` (the file as it is now on disk).
//! The result starts from `theirs` (its comments and layout), and the values the user changed
//! are applied on top; a value changed on both sides, differently, is a [`Conflict`] (mine is
//! applied until it is answered).

use crate::tui::form;
use std::collections::HashMap;
use toml_edit::Value;

/// A value changed both on disk and in the workbench, differently.
#[derive(Clone, Debug, PartialEq)]
pub struct Conflict {
    /// Dotted path of the value.
    pub path: String,
    /// The workbench's value (None: removed).
    pub mine: Option<String>,
    /// The value on disk (None: absent).
    pub theirs: Option<String>,
}

/// What [`merge`] made.
#[derive(Clone, Debug, Default)]
pub struct Merged {
    /// `theirs` with the user's changes applied (mine for the conflicts).
    pub text: String,
    /// Values changed on disk and not by the user (taken).
    pub taken: Vec<String>,
    /// Values changed on both sides, differently (mine applied until answered).
    pub conflicts: Vec<Conflict>,
    /// User changes that could not be applied to `theirs` (path, reason): theirs is kept.
    pub failed: Vec<(String, String)>,
}

/// path → (comparison key, value).
type Leaves = HashMap<String, (String, Value)>;

fn leaves(text: &str, what: &str) -> Result<(Vec<String>, Leaves), String> {
    let list = form::scalars(text).ok_or_else(|| format!("{what} is not valid TOML"))?;
    let order = list.iter().map(|(p, _)| p.clone()).collect();
    let map = list
        .into_iter()
        .map(|(p, v)| (p, (v.to_string(), v)))
        .collect();
    Ok((order, map))
}

fn key(l: &Leaves, p: &str) -> Option<String> {
    l.get(p).map(|(k, _)| k.clone())
}

fn shown(l: &Leaves, p: &str) -> Option<String> {
    l.get(p).map(|(_, v)| form::show(v))
}

/// Applies the value of `path` in `from` (or its absence) to `text`.
pub fn apply(text: &str, path: &str, from: Option<&Value>) -> Result<String, String> {
    match from {
        Some(v) => form::set_leaf(text, path, v.clone()),
        None => form::remove_value(text, path),
    }
}

/// Merges `mine` and `theirs`, both descended from `base`. Errors when a text is not TOML.
pub fn merge(base: &str, mine: &str, theirs: &str) -> Result<Merged, String> {
    let (_, b) = leaves(base, "the base version")?;
    let (order_m, m) = leaves(mine, "the edited model")?;
    let (order_t, t) = leaves(theirs, "the file on disk")?;
    let mut paths = order_m;
    for p in order_t.into_iter().chain(b.keys().cloned()) {
        if !paths.contains(&p) {
            paths.push(p);
        }
    }
    let mut out = Merged {
        text: theirs.to_string(),
        ..Merged::default()
    };
    for p in &paths {
        let (kb, km, kt) = (key(&b, p), key(&m, p), key(&t, p));
        if km == kb {
            if kt != kb {
                out.taken.push(p.clone());
            }
            continue;
        }
        if km == kt {
            continue; // the same change on both sides
        }
        if kt != kb {
            out.conflicts.push(Conflict {
                path: p.clone(),
                mine: shown(&m, p),
                theirs: shown(&t, p),
            });
        }
        match apply(&out.text, p, m.get(p).map(|(_, v)| v)) {
            Ok(text) => out.text = text,
            Err(e) => {
                out.conflicts.retain(|c| &c.path != p);
                out.failed.push((p.clone(), e));
            }
        }
    }
    Ok(out)
}

/// The value of `path` in `text` (None: absent or not TOML).
pub fn value_of(text: &str, path: &str) -> Option<Value> {
    form::scalars(text)?
        .into_iter()
        .find(|(p, _)| p == path)
        .map(|(_, v)| v)
}

/// The values that differ between `disk` and `mine`, one line each (`label: on disk A, here
/// B`), in `mine`'s order then those only on disk; the lines that differ when either is not
/// valid TOML.
pub fn differences(disk: &str, mine: &str) -> Vec<String> {
    let (Ok((order, m)), Ok((disk_order, d))) = (leaves(mine, "mine"), leaves(disk, "disk")) else {
        let (a, b): (Vec<&str>, Vec<&str>) = (disk.lines().collect(), mine.lines().collect());
        return (0..a.len().max(b.len()))
            .filter(|&i| a.get(i) != b.get(i))
            .map(|i| {
                let l = |x: Option<&&str>| x.map_or("(none)".to_string(), |s| format!("'{s}'"));
                format!(
                    "line {}: on disk {}, here {}",
                    i + 1,
                    l(a.get(i)),
                    l(b.get(i))
                )
            })
            .collect();
    };
    let none = || "(none)".to_string();
    let mut out = Vec::new();
    for p in order
        .iter()
        .chain(disk_order.iter().filter(|p| !m.contains_key(*p)))
    {
        if key(&d, p) != key(&m, p) {
            out.push(format!(
                "{}: on disk {}, here {}",
                form::label_of(p),
                shown(&d, p).unwrap_or_else(none),
                shown(&m, p).unwrap_or_else(none)
            ));
        }
    }
    out
}
