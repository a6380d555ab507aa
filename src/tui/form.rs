//! The parameter form: a curated list of bridge parameters (with units) followed by every other
//! scalar leaf of the TOML document under its dotted path. Edits are applied to the text with
//! `toml_edit`, keeping comments and layout; validation is the engine's own (`load_str`).

use super::units::{split_unit, unit_factor, unit_hint};
use std::path::Path;
use toml_edit::{DocumentMut, Item, Value};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Float,
    Int,
    Bool,
    Str,
}

impl Kind {
    fn of(v: &Value) -> Option<Kind> {
        match v {
            Value::Float(_) => Some(Kind::Float),
            Value::Integer(_) => Some(Kind::Int),
            Value::Boolean(_) => Some(Kind::Bool),
            Value::String(_) => Some(Kind::Str),
            _ => None,
        }
    }
    pub fn name(self) -> &'static str {
        match self {
            Kind::Float => "number",
            Kind::Int => "integer",
            Kind::Bool => "true/false",
            Kind::Str => "text",
        }
    }
}

/// A curated bridge parameter.
struct Spec {
    path: &'static str,
    label: &'static str,
    unit: &'static str,
    kind: Kind,
    /// Shown when the key is absent (the engine's default applies).
    optional: bool,
}

const fn s(
    path: &'static str,
    label: &'static str,
    unit: &'static str,
    kind: Kind,
    optional: bool,
) -> Spec {
    Spec {
        path,
        label,
        unit,
        kind,
        optional,
    }
}

use Kind::{Bool as B, Float as F, Int as I, Str as S};

/// Bridge parameters in form order (units: t, kN, m, s).
#[rustfmt::skip]
const BRIDGE: &[Spec] = &[
    s("deck.mass", "deck mass", "t", F, false),
    s("deck.inertia", "deck inertia", "t·m²", F, false),
    s("deck.length", "deck length", "m", F, false),
    s("deck.width", "deck width", "m", F, false),
    s("deck.skew", "deck skew", "°", F, true),
    s("abutment.mass", "abutment mass", "t", F, false),
    s("abutment.inertia", "abutment inertia", "t·m²", F, false),
    s("abutment.actuator_stiffness", "actuator stiffness", "kN/m", F, false),
    s("abutment.actuator_damping", "actuator damping", "kN·s/m", F, true),
    s("abutment.actuator_offset", "actuator offset", "m", F, false),
    s("contacts.gaps.0", "gap left_top", "m", F, false),
    s("contacts.gaps.1", "gap left_bottom", "m", F, false),
    s("contacts.gaps.2", "gap right_top", "m", F, false),
    s("contacts.gaps.3", "gap right_bottom", "m", F, false),
    s("contacts.mu", "friction μ", "–", F, false),
    s("contacts.restitution", "restitution ε", "–", F, false),
    s("contacts.enabled", "contacts enabled", "", B, true),
    s("column.law.law", "column law", "linear|bilinear|takeda", S, false),
    s("column.law.stiffness", "column stiffness", "kN/m", F, false),
    s("column.law.yield_force", "column yield force", "kN", F, false),
    s("column.law.post_yield_ratio", "post-yield ratio", "–", F, false),
    s("column.law.unloading_exponent", "unloading exponent", "–", F, false),
    s("column.law.crack_force", "crack force", "kN", F, false),
    s("column.law.yield_displacement", "yield displacement", "m", F, false),
    s("column.reference_height", "column ref. height", "m", F, false),
    s("column.offset", "column offset", "m", F, false),
    s("column.torsion_stiffness", "column torsion k", "kN·m/rad", F, false),
    s("damping.ratio", "damping ratio ζ", "–", F, true),
    s("excitation.run", "excitation run", "#", I, true),
    s("excitation.time_scale", "time scale", "–", F, true),
];

/// Solver settings, offered for every model (absent keys can be added).
#[rustfmt::skip]
const SOLVER: &[Spec] = &[
    s("solver.method", "solver method", "event|moreau|penalty|penalty-explicit", S, true),
    s("solver.t_end", "t_end", "s", F, true),
    s("solver.rtol", "rtol", "–", F, true),
    s("solver.output_dt", "output step", "s", F, true),
];

/// Keys of each hysteretic law (required first).
fn law_keys(kind: &str) -> Option<&'static [&'static str]> {
    match kind {
        "linear" => Some(&["stiffness"]),
        "bilinear" => Some(&["stiffness", "yield_force", "post_yield_ratio"]),
        "takeda" => Some(&[
            "stiffness",
            "yield_force",
            "post_yield_ratio",
            "unloading_exponent",
            "crack_force",
            "yield_displacement",
        ]),
        _ => None,
    }
}

#[derive(Clone, Debug)]
pub struct Field {
    /// Dotted path: tables, array-of-table and array indices, inline tables.
    pub path: String,
    pub label: String,
    pub unit: String,
    pub kind: Kind,
    /// Value in the draft (None: absent, the default applies).
    pub value: Option<String>,
    /// Value in the file as last loaded or saved.
    pub saved: Option<String>,
    /// The trailing comment of the line, if any.
    pub note: String,
    pub curated: bool,
}

impl Field {
    pub fn edited(&self) -> bool {
        self.value != self.saved
    }
    /// Text to start editing from.
    pub fn edit_text(&self) -> String {
        self.value.clone().unwrap_or_default()
    }
}

#[derive(Clone, Debug, Default)]
pub struct Form {
    pub fields: Vec<Field>,
    pub selected: usize,
}

impl Form {
    pub fn selected(&self) -> Option<&Field> {
        self.fields.get(self.selected)
    }
    pub fn index_of(&self, path: &str) -> Option<usize> {
        self.fields.iter().position(|f| f.path == path)
    }
}

/// A scalar leaf of a document.
struct Leaf {
    path: String,
    kind: Kind,
    value: String,
    /// The value itself, without its decor.
    raw: Value,
    note: String,
}

fn display(v: &Value) -> String {
    match v {
        Value::String(s) => s.value().clone(),
        Value::Float(f) => f.display_repr().into_owned(),
        Value::Integer(i) => i.display_repr().into_owned(),
        Value::Boolean(b) => b.display_repr().into_owned(),
        other => other.to_string().trim().to_string(),
    }
}

fn comment(suffix: Option<&str>) -> String {
    suffix
        .and_then(|s| s.trim_start().strip_prefix('#'))
        .map(|c| c.trim().to_string())
        .unwrap_or_default()
}

fn leaves(doc: &DocumentMut) -> Vec<Leaf> {
    let mut out = Vec::new();
    walk_table(doc.as_table(), "", &mut out);
    out
}

fn join(prefix: &str, k: &str) -> String {
    if prefix.is_empty() {
        k.to_string()
    } else {
        format!("{prefix}.{k}")
    }
}

fn walk_table(t: &toml_edit::Table, prefix: &str, out: &mut Vec<Leaf>) {
    for (k, item) in t.iter() {
        let p = join(prefix, k);
        match item {
            Item::Value(v) => walk_value(
                v,
                &p,
                comment(v.decor().suffix().and_then(|s| s.as_str())),
                out,
            ),
            Item::Table(t) => walk_table(t, &p, out),
            Item::ArrayOfTables(a) => {
                for (i, t) in a.iter().enumerate() {
                    walk_table(t, &format!("{p}.{i}"), out);
                }
            }
            Item::None => {}
        }
    }
}

fn walk_value(v: &Value, p: &str, note: String, out: &mut Vec<Leaf>) {
    match v {
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                walk_value(x, &format!("{p}.{i}"), note.clone(), out);
            }
        }
        Value::InlineTable(t) => {
            for (k, x) in t.iter() {
                walk_value(x, &join(p, k), note.clone(), out);
            }
        }
        _ => {
            if let Some(kind) = Kind::of(v) {
                let mut raw = v.clone();
                raw.decor_mut().clear();
                out.push(Leaf {
                    path: p.to_string(),
                    kind,
                    value: display(v),
                    raw,
                    note,
                });
            }
        }
    }
}

/// Every scalar leaf of a TOML text in document order: (dotted path, value without its
/// decor). None when the text is not TOML.
pub fn scalars(text: &str) -> Option<Vec<(String, Value)>> {
    let doc = text.parse::<DocumentMut>().ok()?;
    Some(leaves(&doc).into_iter().map(|l| (l.path, l.raw)).collect())
}

/// A value as the form shows it (a string without its quotes).
pub fn show(v: &Value) -> String {
    display(v)
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

/// Whether a model text is a bridge file (has a `[deck]` table or `[[frame]]` tables).
pub fn is_bridge(text: &str) -> bool {
    text.parse::<DocumentMut>()
        .map(|d| d.contains_key("deck") || d.contains_key("frame"))
        .unwrap_or(false)
}

/// Label and unit of a field of the bridge's lists (frames, their bents, joints, keys), with
/// the list numbers 1-based as in the bridge's words (`frame 2 bent 1 height`).
fn list_label(path: &str) -> Option<(String, &'static str)> {
    let segs: Vec<&str> = path.split('.').collect();
    let n = |s: &str| s.parse::<usize>().ok().map(|i| i + 1);
    let unit = |key: &str| match key {
        "mass" => "t",
        "inertia" => "t·m²",
        "length" | "width" | "x" | "height" | "gap" | "seat_width" | "failure_displacement" => "m",
        "skew" | "heading" => "°",
        "stiffness" => "kN/m",
        "capacity" => "kN",
        "seat_percent" => "%",
        "mu" | "restitution" => "–",
        _ => "",
    };
    match segs.as_slice() {
        ["frame", i, "bent", j, key] => {
            Some((format!("frame {} bent {} {key}", n(i)?, n(j)?), unit(key)))
        }
        ["frame" | "joint" | "key" | "bent", i, key] => {
            Some((format!("{} {} {key}", segs[0], n(i)?), unit(key)))
        }
        ["joint", i, "gaps", k] => Some((
            format!(
                "joint {} gap {}",
                n(i)?,
                ["top", "bottom"].get(k.parse::<usize>().ok()?)?
            ),
            "m",
        )),
        _ => None,
    }
}

/// Builds the form from the draft text and the saved text. A draft that is not TOML gives an
/// empty form.
pub fn build(draft: &str, saved: &str) -> Form {
    let Ok(doc) = draft.parse::<DocumentMut>() else {
        return Form::default();
    };
    let draft_leaves = leaves(&doc);
    let saved_leaves = saved
        .parse::<DocumentMut>()
        .map(|d| leaves(&d))
        .unwrap_or_default();
    let saved_of = |p: &str| {
        saved_leaves
            .iter()
            .find(|l| l.path == p)
            .map(|l| l.value.clone())
    };
    let mut fields = Vec::new();
    let bridge = doc.contains_key("deck") || doc.contains_key("frame");
    let law = draft_leaves
        .iter()
        .find(|l| l.path == "column.law.law")
        .map(|l| l.value.clone())
        .unwrap_or_default();
    let law_set = law_keys(&law).unwrap_or(&[]);
    let specs = if bridge { BRIDGE } else { &[] };
    for sp in specs.iter().chain(SOLVER) {
        if sp.path.starts_with("deck.") && !doc.contains_key("deck") {
            continue;
        }
        let leaf = draft_leaves.iter().find(|l| l.path == sp.path);
        if let Some(k) = sp.path.strip_prefix("column.law.")
            && k != "law"
            && leaf.is_none()
            && !law_set.contains(&k)
        {
            continue;
        }
        if leaf.is_none() && !sp.optional && !sp.path.starts_with("column.law.") {
            continue;
        }
        fields.push(Field {
            path: sp.path.to_string(),
            label: sp.label.to_string(),
            unit: sp.unit.to_string(),
            kind: leaf.map_or(sp.kind, |l| l.kind),
            value: leaf.map(|l| l.value.clone()),
            saved: saved_of(sp.path),
            note: leaf.map(|l| l.note.clone()).unwrap_or_default(),
            curated: true,
        });
    }
    for l in &draft_leaves {
        if fields.iter().any(|f| f.path == l.path) {
            continue;
        }
        let (label, unit) = list_label(&l.path).unwrap_or((l.path.clone(), ""));
        fields.push(Field {
            path: l.path.clone(),
            label,
            unit: unit.to_string(),
            kind: l.kind,
            value: Some(l.value.clone()),
            saved: saved_of(&l.path),
            note: l.note.clone(),
            curated: false,
        });
    }
    Form {
        fields,
        selected: 0,
    }
}

/// Parses what the user typed for a field of this kind. A number may carry a unit: the
/// field's own ("0.02 m") or one that converts to it ([`super::units::CONVERSIONS`]: "20 mm", "1e4 kN/mm",
/// "650 kg"); any other unit is refused, naming the ones taken.
pub fn parse_input(kind: Kind, raw: &str, unit: &str) -> Result<Value, String> {
    let t = raw.trim();
    if t.is_empty() {
        return Err(format!("empty: expected a {}", kind.name()));
    }
    match kind {
        Kind::Float => {
            let (number, typed) = split_unit(t);
            let factor = unit_factor(typed, unit)?;
            let v = match number.parse::<Value>() {
                Ok(Value::Float(f)) => *f.value(),
                Ok(Value::Integer(i)) => *i.value() as f64,
                _ => number
                    .parse::<f64>()
                    .map_err(|_| format!("'{number}' is not a number{}", unit_hint(unit)))?,
            };
            Ok(Value::from(v * factor))
        }
        Kind::Int => match t
            .strip_suffix(unit)
            .unwrap_or(t)
            .trim_end()
            .parse::<Value>()
        {
            Ok(Value::Integer(i)) => Ok(Value::Integer(i)),
            _ => Err(format!("'{t}' is not an integer")),
        },
        Kind::Bool => match t.to_ascii_lowercase().as_str() {
            "true" | "yes" | "on" | "1" => Ok(Value::from(true)),
            "false" | "no" | "off" | "0" => Ok(Value::from(false)),
            _ => Err(format!("'{t}' is not true or false")),
        },
        Kind::Str => match t.parse::<Value>() {
            Ok(Value::String(s)) => Ok(Value::String(s)),
            _ => Ok(Value::from(t)),
        },
    }
}

/// Sets `path` to what the user typed, keeping comments, layout and the column of a trailing
/// comment. Missing tables and keys are created. Changing a hysteretic law kind (`…law.law`)
/// drops the keys the new law does not take and adds the ones it needs.
pub fn set_value(
    text: &str,
    path: &str,
    kind: Kind,
    raw: &str,
    unit: &str,
) -> Result<String, String> {
    let value = parse_input(kind, raw, unit)?;
    let mut doc: DocumentMut = text
        .parse()
        .map_err(|e: toml_edit::TomlError| format!("the file is not valid TOML: {e}"))?;
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
    let decor = slot.decor().clone();
    *new.decor_mut() = decor;
    let new_len = display_len(&new);
    if let Some(suffix) = new
        .decor()
        .suffix()
        .and_then(|s| s.as_str())
        .map(str::to_string)
    {
        let spaces = suffix.len() - suffix.trim_start_matches(' ').len();
        let rest = &suffix[spaces..];
        if rest.starts_with('#') && spaces > 0 {
            let target = (spaces + old_len).saturating_sub(new_len).max(1);
            new.decor_mut()
                .set_suffix(format!("{}{rest}", " ".repeat(target)));
        }
    }
    *slot = new;
}

fn display_len(v: &Value) -> usize {
    let mut c = v.clone();
    c.decor_mut().clear();
    c.to_string().chars().count()
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
        Item::Value(v) => set_in_value(v, segs, value),
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
            set_in_value(x, rest, value)
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

/// A model error with line and column: (`file:line:col: …` message, the message without the
/// location, (line, column)). `Invalid` errors carry a field whose column is located in the text.
pub fn describe_error(
    e: &crate::ModelError,
    text: &str,
) -> (String, String, Option<(usize, usize)>) {
    use crate::ModelError as E;
    match e {
        E::Parse {
            line,
            column,
            message,
            ..
        } if *line > 0 => (e.to_string(), message.clone(), Some((*line, *column))),
        E::Invalid {
            path,
            line,
            field,
            reason,
        } => {
            let detail = format!("{field}: {reason}");
            let at = crate::model::locate(text, field).filter(|(l, _)| *l == *line);
            match at {
                Some((l, c)) if *line > 0 => (
                    format!("{}:{l}:{c}: {detail}", path.display()),
                    detail,
                    Some((l, c)),
                ),
                _ => (e.to_string(), detail, e.line().map(|l| (l, 1))),
            }
        }
        _ => (e.to_string(), e.to_string(), e.line().map(|l| (l, 1))),
    }
}

/// [`describe_error`]'s full message and location.
pub fn error_with_column(e: &crate::ModelError, text: &str) -> (String, Option<(usize, usize)>) {
    let (m, _, at) = describe_error(e, text);
    (m, at)
}

/// Validates a model text with the engine (the same path as loading the file).
pub fn validate(text: &str, path: &Path) -> Result<crate::scene::Scene, crate::ModelError> {
    crate::model::load_str(text, path, &[])
}

#[cfg(test)]
mod tests {
    use crate::methods::Method;

    #[test]
    fn the_method_field_lists_the_registry() {
        let spec = super::SOLVER
            .iter()
            .find(|s| s.path == "solver.method")
            .unwrap();
        assert_eq!(spec.unit, Method::names("|"));
    }
}
