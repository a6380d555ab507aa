//! Uncertain inputs: a model file's `[[uncertain]]` tables (`deckspin sensitivity`), each an
//! override path (the paths `--set` takes, `overrides.rs`) or several moved together, with a
//! low and a high value — absolute, or factors on the model's own value (`relative = true`,
//! every element of an array). A run ignores them; they are checked at load with file, line
//! and field. [`resolve`] finds the numbers a path names; [`side_overrides`] writes the
//! `--set` arguments of one side.

use super::check::{Check, ModelError};
use serde::Deserialize;

/// One path, or several moved together (`["run.*.pga_x", "run.*.pga_y"]`).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum Keys {
    /// One key.
    One(String),
    /// Several keys varied together.
    Many(Vec<String>),
}

impl Keys {
    /// The keys.
    pub fn list(&self) -> Vec<String> {
        match self {
            Keys::One(k) => vec![k.clone()],
            Keys::Many(v) => v.clone(),
        }
    }
}

/// A `[[uncertain]]` table.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UncertainSpec {
    /// The key of the `--set` argument.
    pub key: Keys,
    /// The low value.
    pub low: f64,
    /// The high value.
    pub high: f64,
    /// `low` and `high` are factors on the model's value (every element of an array).
    #[serde(default)]
    pub relative: bool,
    /// Absent: the key (several joined by `+`).
    pub name: Option<String>,
}

impl UncertainSpec {
    /// Its name, or its keys joined by `+`.
    pub fn label(&self) -> String {
        self.name
            .clone()
            .unwrap_or_else(|| self.key.list().join("+"))
    }
}

/// What a path names in the model: one number, or an array of numbers.
#[derive(Clone, Debug, PartialEq)]
pub enum Leaf {
    /// One value.
    Number(f64),
    /// A list of values.
    Numbers(Vec<f64>),
    /// Not a number: its TOML type.
    Other(String),
}

/// Every field the override path `key` names in TOML `text` (array-of-table segments: an
/// index, a `name` or `*`, as `--set`), each with its concrete dotted path; an error when it
/// names none.
pub fn resolve(text: &str, key: &str) -> Result<Vec<(String, Leaf)>, String> {
    let doc: toml_edit::DocumentMut = text
        .parse()
        .map_err(|e: toml_edit::TomlError| format!("the model is not TOML: {}", e.message()))?;
    let segs: Vec<&str> = key.trim().split('.').collect();
    if segs.iter().any(|s| s.is_empty()) {
        return Err(format!("'{key}' is not a dotted path"));
    }
    let mut out = Vec::new();
    walk(doc.as_item(), &segs, String::new(), &mut out)?;
    if out.is_empty() {
        return Err(format!("'{key}' matches no field of the model"));
    }
    Ok(out)
}

fn join(prefix: &str, seg: impl std::fmt::Display) -> String {
    if prefix.is_empty() {
        seg.to_string()
    } else {
        format!("{prefix}.{seg}")
    }
}

fn walk(
    item: &toml_edit::Item,
    segs: &[&str],
    at: String,
    out: &mut Vec<(String, Leaf)>,
) -> Result<(), String> {
    let Some((first, rest)) = segs.split_first() else {
        out.push((at, leaf(item)));
        return Ok(());
    };
    match item {
        toml_edit::Item::Table(t) => {
            let child = t
                .get(first)
                .ok_or_else(|| format!("no key '{}' in the model", join(&at, first)))?;
            walk(child, rest, join(&at, first), out)
        }
        toml_edit::Item::ArrayOfTables(a) => {
            for (i, t) in a.iter().enumerate() {
                let named = t.get("name").and_then(|v| v.as_str()) == Some(*first);
                if *first == "*" || first.parse::<usize>() == Ok(i) || named {
                    let it = toml_edit::Item::Table(t.clone());
                    walk(&it, rest, join(&at, i), out)?;
                }
            }
            Ok(())
        }
        toml_edit::Item::Value(v) => walk_value(v, segs, at, out),
        _ => Err(format!("no key '{}' in the model", join(&at, first))),
    }
}

fn walk_value(
    v: &toml_edit::Value,
    segs: &[&str],
    at: String,
    out: &mut Vec<(String, Leaf)>,
) -> Result<(), String> {
    let Some((first, rest)) = segs.split_first() else {
        out.push((at, leaf_value(v)));
        return Ok(());
    };
    let missing = || format!("no key '{}' in the model", join(&at, first));
    let child = match v {
        toml_edit::Value::InlineTable(t) => t.get(first).ok_or_else(missing)?,
        toml_edit::Value::Array(a) => {
            let i: usize = first.parse().map_err(|_| missing())?;
            a.get(i).ok_or_else(missing)?
        }
        _ => return Err(missing()),
    };
    walk_value(child, rest, join(&at, first), out)
}

fn leaf(item: &toml_edit::Item) -> Leaf {
    match item {
        toml_edit::Item::Value(v) => leaf_value(v),
        toml_edit::Item::Table(_) => Leaf::Other("table".into()),
        toml_edit::Item::ArrayOfTables(_) => Leaf::Other("array of tables".into()),
        toml_edit::Item::None => Leaf::Other("nothing".into()),
    }
}

fn number(v: &toml_edit::Value) -> Option<f64> {
    v.as_float().or_else(|| v.as_integer().map(|i| i as f64))
}

fn leaf_value(v: &toml_edit::Value) -> Leaf {
    if let Some(x) = number(v) {
        return Leaf::Number(x);
    }
    if let toml_edit::Value::Array(a) = v {
        let xs: Option<Vec<f64>> = a.iter().map(number).collect();
        if let Some(xs) = xs.filter(|x| !x.is_empty()) {
            return Leaf::Numbers(xs);
        }
        return Leaf::Other("array of other values than numbers".into());
    }
    Leaf::Other(v.type_name().into())
}

/// Why `key` cannot be an uncertain input of the model `text` (absolute values need numbers,
/// `relative` also takes arrays of numbers).
pub fn check_key(text: &str, key: &str, relative: bool) -> Result<(), String> {
    for (path, leaf) in resolve(text, key)? {
        match leaf {
            Leaf::Number(_) => {}
            Leaf::Numbers(_) if relative => {}
            Leaf::Numbers(_) => {
                return Err(format!(
                    "{path} is an array: give relative = true (factors on every element)"
                ));
            }
            Leaf::Other(t) => return Err(format!("{path} is a {t}, not a number")),
        }
    }
    Ok(())
}

/// A number as TOML text (always with a point or an exponent: a float).
pub(crate) fn toml_number(x: f64) -> String {
    format!("{x:?}")
}

/// The `--set` arguments that give `keys` the value `value` (absolute), or the model's own
/// values (in `text`) times `value` (relative: one argument per concrete field, arrays
/// element by element).
pub fn side_overrides(
    text: &str,
    keys: &[String],
    value: f64,
    relative: bool,
) -> Result<Vec<String>, String> {
    let mut out = Vec::new();
    for key in keys {
        if !relative {
            check_key(text, key, false)?;
            out.push(format!("{}={}", key.trim(), toml_number(value)));
            continue;
        }
        for (path, leaf) in resolve(text, key)? {
            match leaf {
                Leaf::Number(x) => out.push(format!("{path}={}", toml_number(x * value))),
                Leaf::Numbers(xs) => {
                    let v: Vec<String> = xs.iter().map(|x| toml_number(x * value)).collect();
                    out.push(format!("{path}=[{}]", v.join(", ")));
                }
                Leaf::Other(t) => return Err(format!("{path} is a {t}, not a number")),
            }
        }
    }
    Ok(out)
}

/// Checks of the `[[uncertain]]` tables: keys that name numbers of the model (arrays only
/// with `relative`), finite `low` < `high`, names distinct and without commas.
pub(crate) fn check_specs(specs: &[UncertainSpec], ck: &Check) -> Result<(), ModelError> {
    for (i, s) in specs.iter().enumerate() {
        let field = |f: &str| format!("uncertain.{i}.{f}");
        ck.finite(&field("low"), s.low)?;
        ck.finite(&field("high"), s.high)?;
        if s.low >= s.high {
            let (l, h) = (s.low, s.high);
            return Err(ck.err(&field("high"), format!("must be above low ({l}), got {h}")));
        }
        let keys = s.key.list();
        if keys.is_empty() {
            return Err(ck.err(&field("key"), "names no field"));
        }
        for k in &keys {
            check_key(ck.text, k, s.relative).map_err(|why| ck.err(&field("key"), why))?;
        }
        let name = s.label();
        if name.trim().is_empty() || name.contains(',') {
            return Err(ck.err(&field("name"), "must be a name without commas"));
        }
        if specs[..i].iter().any(|o| o.label() == name) {
            let why = format!("'{name}' names an earlier [[uncertain]] table too");
            return Err(ck.err(&field("name"), why));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "[contacts]\nmu = 0.5\ngaps = [0.01, 0.02]\n[column]\n\
        law = { law = \"takeda\", stiffness = 10, yield_force = 2.0 }\n\
        [[run]]\nname = \"a\"\npga_x = 0.1\n[[run]]\nname = \"b\"\npga_x = 0.2\n";

    #[test]
    fn paths_resolve_like_set() {
        assert_eq!(
            resolve(TEXT, "column.law.stiffness").unwrap(),
            vec![("column.law.stiffness".into(), Leaf::Number(10.0))]
        );
        let runs = resolve(TEXT, "run.*.pga_x").unwrap();
        assert_eq!(runs[1], ("run.1.pga_x".into(), Leaf::Number(0.2)));
        assert_eq!(resolve(TEXT, "run.b.pga_x").unwrap().len(), 1);
        assert!(
            resolve(TEXT, "contacts.mew")
                .unwrap_err()
                .contains("contacts.mew")
        );
        assert!(check_key(TEXT, "contacts.gaps", false).is_err());
        assert!(check_key(TEXT, "contacts.gaps", true).is_ok());
        assert!(check_key(TEXT, "column.law.law", true).is_err());
        let set = side_overrides(TEXT, &["contacts.gaps".into()], 0.5, true).unwrap();
        assert_eq!(set, vec!["contacts.gaps=[0.005, 0.01]".to_string()]);
        let set = side_overrides(TEXT, &["run.*.pga_x".into()], 2.0, true).unwrap();
        assert_eq!(set, vec!["run.0.pga_x=0.2", "run.1.pga_x=0.4"]);
        let set = side_overrides(TEXT, &["contacts.mu".into()], 1.0, false).unwrap();
        assert_eq!(set, vec!["contacts.mu=1.0"]);
    }
}
