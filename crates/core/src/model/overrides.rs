//! `--set key.path=value` overrides, applied to the TOML text before it is read.

use super::check::{Applied, ModelError};

/// Applies `key.path=value` overrides to TOML text. Array-of-table segments are an index, a
/// `name`, or `*` (all). The value is parsed as TOML (number, bool, string) or taken as a string.
pub fn apply_overrides(text: &str, overrides: &[String]) -> Result<String, ModelError> {
    apply_overrides_traced(text, overrides).map(|(t, _)| t)
}

/// As [`apply_overrides`], also returning the concrete fields each argument set.
pub(crate) fn apply_overrides_traced(
    text: &str,
    overrides: &[String],
) -> Result<(String, Vec<Applied>), ModelError> {
    let mut applied = Vec::new();
    if overrides.is_empty() {
        return Ok((text.to_string(), applied));
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
        let mut set = Vec::new();
        let n = set_path(doc.as_item_mut(), &segs, &value, "", &mut set).map_err(|reason| {
            ModelError::Override {
                key: key.to_string(),
                reason,
            }
        })?;
        applied.extend(set.into_iter().map(|field| Applied {
            argument: o.clone(),
            field,
        }));
        if n == 0 {
            return Err(ModelError::Override {
                key: key.to_string(),
                reason: "matches no field".into(),
            });
        }
    }
    Ok((doc.to_string(), applied))
}

/// `prefix.seg` (or `seg` at the top).
fn join(prefix: &str, seg: impl std::fmt::Display) -> String {
    if prefix.is_empty() {
        seg.to_string()
    } else {
        format!("{prefix}.{seg}")
    }
}

fn set_path(
    item: &mut toml_edit::Item,
    segs: &[&str],
    value: &toml_edit::Value,
    prefix: &str,
    set: &mut Vec<String>,
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
                    count += set_path(&mut it, rest, value, &join(prefix, i), set)?;
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
                set.push(join(prefix, first));
                Ok(1)
            } else {
                let child = t
                    .get_mut(first)
                    .ok_or_else(|| format!("no table '{first}'"))?;
                set_path(child, rest, value, &join(prefix, first), set)
            }
        }
        toml_edit::Item::Value(v) => set_in_value(v, segs, value, prefix, set),
        _ => Err(format!("cannot descend into '{first}'")),
    }
}

/// Set a scalar inside an inline table or array (`law.stiffness`, `gaps.0`).
fn set_in_value(
    v: &mut toml_edit::Value,
    segs: &[&str],
    value: &toml_edit::Value,
    prefix: &str,
    set: &mut Vec<String>,
) -> Result<usize, String> {
    let Some((first, rest)) = segs.split_first() else {
        return Err("empty key".into());
    };
    let child = match v {
        toml_edit::Value::InlineTable(t) => {
            if rest.is_empty() && !t.contains_key(first) {
                t.insert(*first, value.clone());
                set.push(join(prefix, first));
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
        set.push(join(prefix, first));
        Ok(1)
    } else {
        set_in_value(child, rest, value, &join(prefix, first), set)
    }
}
