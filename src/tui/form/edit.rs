//! Edits of the model's text through `toml_edit`: a leaf set to what the user typed (the
//! comments, the layout and the column of a trailing comment kept), a key removed, a
//! hysteretic law's keys fixed after its kind changed.

use crate::tui::form::spec::{Dim, Kind, law_keys};
use crate::tui::form::units::parse_input;
use crate::units::UnitSystem;
use toml_edit::{DocumentMut, Item, Value};

/// The unit system a model text declares (its top-level `units` key; SI-kN without one or
/// with one not known).
pub fn system_of(doc: &DocumentMut) -> UnitSystem {
    doc.get("units")
        .and_then(|u| u.as_str())
        .and_then(|u| UnitSystem::parse(u).ok())
        .unwrap_or_default()
}

/// Sets the leaf at `path` to `value` as it is (a law kind changes alone: no keys are added
/// or dropped), keeping comments and layout. Missing tables and keys are created.
pub fn set_leaf(text: &str, path: &str, value: Value) -> Result<String, String> {
    let mut doc: DocumentMut = text
        .parse()
        .map_err(|e: toml_edit::TomlError| format!("the file is not valid TOML: {e}"))?;
    let segs: Vec<&str> = path.split('.').collect();
    set_in_item(doc.as_item_mut(), &segs, value)?;
    Ok(doc.to_string())
}

/// Sets `path` to what the user typed (a number with a unit of the field's quantity converted
/// to the unit of the file's system), keeping comments, layout and the column of a trailing
/// comment. Missing tables and keys are created. Changing a hysteretic law kind (`…law.law`)
/// drops the keys the new law does not take and adds the ones it needs.
pub fn set_value(
    text: &str,
    path: &str,
    kind: Kind,
    raw: &str,
    dim: Dim,
) -> Result<String, String> {
    let mut doc: DocumentMut = text
        .parse()
        .map_err(|e: toml_edit::TomlError| format!("the file is not valid TOML: {e}"))?;
    let value = parse_input(kind, raw, dim, system_of(&doc))?;
    let segs: Vec<&str> = path.split('.').collect();
    set_in_item(doc.as_item_mut(), &segs, value.clone())?;
    if segs.len() >= 2
        && segs[segs.len() - 1] == "law"
        && let Value::String(kind) = &value
    {
        fix_law(doc.as_item_mut(), &segs[..segs.len() - 1], kind.value())?;
    }
    Ok(doc.to_string())
}

/// Removes a key (reverting a field that was absent in the saved file).
pub fn remove_value(text: &str, path: &str) -> Result<String, String> {
    let mut doc: DocumentMut = text
        .parse()
        .map_err(|e: toml_edit::TomlError| format!("the file is not valid TOML: {e}"))?;
    let segs: Vec<&str> = path.split('.').collect();
    let (last, parent) = segs.split_last().ok_or("empty path")?;
    let removed = if let Some(t) = table_at(doc.as_table_mut(), parent) {
        t.remove(last).is_some()
    } else if let Some(Value::InlineTable(t)) = value_at(doc.as_item_mut(), parent) {
        t.remove(last).is_some()
    } else {
        false
    };
    if removed {
        Ok(doc.to_string())
    } else {
        Err(format!("cannot remove '{path}'"))
    }
}

/// The table at a path of table keys and array-of-table indices.
fn table_at<'a>(t: &'a mut toml_edit::Table, segs: &[&str]) -> Option<&'a mut toml_edit::Table> {
    let Some((first, rest)) = segs.split_first() else {
        return Some(t);
    };
    match t.get_mut(first)? {
        Item::Table(c) => table_at(c, rest),
        Item::ArrayOfTables(a) => {
            let (i, rest2) = rest.split_first()?;
            table_at(a.get_mut(i.parse().ok()?)?, rest2)
        }
        _ => None,
    }
}

/// The value at a path (through tables, arrays of tables, arrays and inline tables).
fn value_at<'a>(item: &'a mut Item, segs: &[&str]) -> Option<&'a mut Value> {
    match item {
        Item::Value(v) => value_in(v, segs),
        Item::Table(t) => {
            let (first, rest) = segs.split_first()?;
            value_at(t.get_mut(first)?, rest)
        }
        Item::ArrayOfTables(a) => {
            let (i, rest) = segs.split_first()?;
            let t = a.get_mut(i.parse().ok()?)?;
            let (k, rest2) = rest.split_first()?;
            value_at(t.get_mut(k)?, rest2)
        }
        Item::None => None,
    }
}

fn value_in<'a>(v: &'a mut Value, segs: &[&str]) -> Option<&'a mut Value> {
    let Some((first, rest)) = segs.split_first() else {
        return Some(v);
    };
    match v {
        Value::Array(a) => value_in(a.get_mut(first.parse().ok()?)?, rest),
        Value::InlineTable(t) => value_in(t.get_mut(first)?, rest),
        _ => None,
    }
}

/// Replaces `slot` by `new`, keeping its decor and the column of a trailing comment.
fn replace_keep_decor(slot: &mut Value, mut new: Value) {
    let old_len = display_len(slot);
    *new.decor_mut() = slot.decor().clone();
    *slot = new;
    keep_comment_column(slot, old_len);
}

/// After a value on one line changed from `old_len` characters to its width now: the spaces
/// before its trailing comment changed by the difference, so that the comment keeps its
/// column (at least one space before it).
fn keep_comment_column(v: &mut Value, old_len: usize) {
    let shown = display(v);
    if shown.contains('\n') {
        return;
    }
    let new_len = shown.chars().count();
    let suffix = v.decor().suffix().and_then(|s| s.as_str());
    if let Some(s) = suffix.and_then(|s| shift_comment(s, old_len, new_len)) {
        v.decor_mut().set_suffix(s);
    }
}

/// `decor` (spaces, then a comment) with the spaces changed so that the comment stays in its
/// column after the text before it went from `old_len` to `new_len` characters; None when
/// there is no comment to keep in place or nothing changed.
fn shift_comment(decor: &str, old_len: usize, new_len: usize) -> Option<String> {
    let spaces = decor.len() - decor.trim_start_matches(' ').len();
    let rest = &decor[spaces..];
    if !rest.starts_with('#') || spaces == 0 || old_len == new_len {
        return None;
    }
    let target = (spaces + old_len).saturating_sub(new_len).max(1);
    Some(format!("{}{rest}", " ".repeat(target)))
}

/// A value as written, without its decor.
fn display(v: &Value) -> String {
    let mut c = v.clone();
    c.decor_mut().clear();
    c.to_string()
}

fn display_len(v: &Value) -> usize {
    display(v).chars().count()
}

fn set_in_item(item: &mut Item, segs: &[&str], value: Value) -> Result<(), String> {
    let Some((first, rest)) = segs.split_first() else {
        return Err("empty path".into());
    };
    match item {
        Item::Table(t) => {
            if rest.is_empty() {
                match t.get_mut(first) {
                    Some(Item::Value(v)) if !v.is_array() && !v.is_inline_table() => {
                        replace_keep_decor(v, value);
                        Ok(())
                    }
                    Some(Item::None) | None => {
                        t.insert(first, Item::Value(value));
                        Ok(())
                    }
                    Some(_) => Err(format!("'{first}' is not a single value")),
                }
            } else {
                if !t.contains_key(first) {
                    let mut nt = toml_edit::Table::new();
                    nt.set_implicit(false);
                    t.insert(first, Item::Table(nt));
                }
                set_in_item(t.get_mut(first).expect("inserted"), rest, value)
            }
        }
        Item::ArrayOfTables(a) => {
            let i: usize = first
                .parse()
                .map_err(|_| format!("'{first}' is not an index"))?;
            let t = a.get_mut(i).ok_or_else(|| format!("no element {i}"))?;
            let (k, rest2) = rest.split_first().ok_or("path ends at a table")?;
            if rest2.is_empty() {
                match t.get_mut(k) {
                    Some(Item::Value(v)) if !v.is_array() && !v.is_inline_table() => {
                        replace_keep_decor(v, value);
                    }
                    Some(Item::None) | None => {
                        t.insert(k, Item::Value(value));
                    }
                    Some(_) => return Err(format!("'{k}' is not a single value")),
                }
                Ok(())
            } else {
                let child = t.get_mut(k).ok_or_else(|| format!("no key '{k}'"))?;
                set_in_item(child, rest2, value)
            }
        }
        Item::Value(v) => {
            // an element of an array on the key's line: the line's comment keeps its column
            let before = display_len(v);
            set_in_value(v, segs, value)?;
            keep_comment_column(v, before);
            Ok(())
        }
        Item::None => Err(format!("no key '{first}'")),
    }
}

fn set_in_value(v: &mut Value, segs: &[&str], value: Value) -> Result<(), String> {
    let Some((first, rest)) = segs.split_first() else {
        replace_keep_decor(v, value);
        return Ok(());
    };
    match v {
        Value::Array(a) => {
            let i: usize = first
                .parse()
                .map_err(|_| format!("'{first}' is not an index"))?;
            let x = a.get_mut(i).ok_or_else(|| format!("no element {i}"))?;
            let before = display_len(x);
            set_in_value(x, rest, value)?;
            let after = a.get(i).map_or(before, display_len);
            // an array over several lines: the comment after this element (in the next
            // element's prefix, or the array's trailing text) keeps its column
            match a.get_mut(i + 1) {
                Some(next) => {
                    let prefix = next.decor().prefix().and_then(|p| p.as_str());
                    if let Some(p) = prefix.and_then(|p| shift_comment(p, before, after)) {
                        next.decor_mut().set_prefix(p);
                    }
                }
                None => {
                    let trailing = a.trailing().as_str().unwrap_or("").to_string();
                    if let Some(t) = shift_comment(&trailing, before, after) {
                        a.set_trailing(t);
                    }
                }
            }
            Ok(())
        }
        Value::InlineTable(t) => match t.get_mut(first) {
            Some(x) => set_in_value(x, rest, value),
            None if rest.is_empty() => {
                t.insert(*first, value);
                Ok(())
            }
            None => Err(format!("no key '{first}'")),
        },
        _ => Err(format!("cannot descend into '{first}'")),
    }
}

/// After a law kind change: keep the keys shared with the new law, drop the others, add the
/// required ones with plausible values derived from the stiffness.
fn fix_law(root: &mut Item, segs: &[&str], kind: &str) -> Result<(), String> {
    let keys =
        law_keys(kind).ok_or_else(|| format!("unknown law '{kind}' (linear, bilinear, takeda)"))?;
    let Some(Value::InlineTable(t)) = value_at(root, segs) else {
        return Ok(());
    };
    let stale: Vec<String> = t
        .iter()
        .map(|(k, _)| k.to_string())
        .filter(|k| k != "law" && !keys.contains(&k.as_str()))
        .collect();
    for k in stale {
        t.remove(&k);
    }
    let k = t
        .get("stiffness")
        .and_then(|v| v.as_float())
        .unwrap_or(1000.0);
    for key in keys {
        if t.contains_key(key) {
            continue;
        }
        let v = match *key {
            "stiffness" => Value::from(k),
            "yield_force" => Value::from(k * 0.01),
            "post_yield_ratio" => Value::from(0.05),
            _ => continue, // optional Takeda keys keep their defaults
        };
        t.insert(*key, v);
    }
    t.fmt();
    Ok(())
}
