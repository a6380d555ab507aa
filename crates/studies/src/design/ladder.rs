//! The model ladder: the simplifications of a bridge model that apply to it, each an edit of
//! its TOML text ([`Edit`]); applied with the file's comments kept and, for a file a user
//! keeps, each change marked with why ([`apply`]).

use toml_edit::{DocumentMut, Item};

/// One simplification of a bridge model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Simplification {
    /// Abutments on actuators or backfill → rigid walls moved by the ground.
    RigidAbutments,
    /// Backfill behind the backwalls removed (the abutments stay on their actuators).
    NoBackfill,
    /// Takeda columns → bilinear (the same backbone, kinematic hardening).
    BilinearColumns,
    /// Takeda or bilinear columns → linear (the initial stiffness).
    LinearColumns,
    /// Coulomb friction at the corners → frictionless (μ = 0).
    Frictionless,
    /// Restitution ε > 0 → plastic impacts (ε = 0).
    PlasticImpacts,
    /// The deck–abutment and joint contacts removed.
    NoContacts,
    /// The deck's rotation held at 0 (a translating deck).
    TranslatingDeck,
    /// Shear keys removed (abutments and joints).
    NoKeys,
    /// Abutment bearings removed.
    NoBearings,
    /// The records cut to their strong-motion part (5–95 % Arias intensity) plus the model's
    /// free-vibration tail.
    StrongMotion,
    /// The longitudinal record alone (every support at rest in y).
    LongitudinalOnly,
}

impl Simplification {
    pub const ALL: [Self; 12] = [
        Self::RigidAbutments,
        Self::NoBackfill,
        Self::BilinearColumns,
        Self::LinearColumns,
        Self::Frictionless,
        Self::PlasticImpacts,
        Self::NoContacts,
        Self::TranslatingDeck,
        Self::NoKeys,
        Self::NoBearings,
        Self::StrongMotion,
        Self::LongitudinalOnly,
    ];

    /// Its name on the command line and in tables.
    pub fn name(self) -> &'static str {
        match self {
            Self::RigidAbutments => "rigid-abutments",
            Self::NoBackfill => "no-backfill",
            Self::BilinearColumns => "bilinear-columns",
            Self::LinearColumns => "linear-columns",
            Self::Frictionless => "frictionless",
            Self::PlasticImpacts => "plastic-impacts",
            Self::NoContacts => "no-contacts",
            Self::TranslatingDeck => "translating-deck",
            Self::NoKeys => "no-keys",
            Self::NoBearings => "no-bearings",
            Self::StrongMotion => "strong-motion",
            Self::LongitudinalOnly => "longitudinal-only",
        }
    }

    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|x| x.name() == s)
    }

    /// What it leaves out, in a line (the comment `--write` puts beside the change).
    pub(crate) fn leaves_out(self) -> &'static str {
        match self {
            Self::RigidAbutments => {
                "the abutments' own masses on their actuators or backfill: the walls move as the ground does"
            }
            Self::NoBackfill => "the passive backfill behind the backwalls",
            Self::BilinearColumns => {
                "Takeda's degrading unloading and reloading stiffness (the same backbone, kinematic hardening)"
            }
            Self::LinearColumns => "the columns' yielding: linear at their initial stiffness",
            Self::Frictionless => "Coulomb friction at the contact corners (μ = 0)",
            Self::PlasticImpacts => "the rebound of impacts (restitution 0)",
            Self::NoContacts => "the contacts at the abutments and joints: no pounding",
            Self::TranslatingDeck => "the deck's rotation in plan (held at 0)",
            Self::NoKeys => "the shear keys",
            Self::NoBearings => "the abutment bearings",
            Self::StrongMotion => {
                "the records before 5 % and after 95 % of their Arias intensity (the model's free-vibration tail kept)"
            }
            Self::LongitudinalOnly => {
                "the transverse component of the input (the supports at rest in y)"
            }
        }
    }

    /// The simplifications this one makes moot when combined with it.
    pub(crate) fn supersedes(self) -> &'static [Self] {
        match self {
            Self::LinearColumns => &[Self::BilinearColumns],
            Self::NoContacts => &[Self::Frictionless, Self::PlasticImpacts],
            Self::RigidAbutments => &[Self::NoBackfill],
            _ => &[],
        }
    }
}

/// A change of one key of the model file.
#[derive(Clone, Debug, PartialEq)]
pub struct Edit {
    /// The key's dotted path: tables by name, arrays of tables by 0-based index
    /// (`joint.1.mu`), as `--set` takes them.
    pub path: String,
    /// The new value (TOML text, e.g. `"rigid"` or `{ law = "linear", stiffness = 9320.0 }`),
    /// or none to remove the key.
    pub value: Option<String>,
}

impl Edit {
    fn set(path: impl Into<String>, value: impl Into<String>) -> Self {
        Self {
            path: path.into(),
            value: Some(value.into()),
        }
    }
    fn remove(path: impl Into<String>) -> Self {
        Self {
            path: path.into(),
            value: None,
        }
    }
}

/// What the model's runs say that the text does not: the strong-motion window of its records
/// and its free-vibration tail, s (from the compiled scene).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timing {
    /// The earliest 5 % and the latest 95 % Arias-intensity time over the records.
    pub strong_motion: Option<(f64, f64)>,
    /// The run's end after the records' end (`solver.t_end` − the records' end, at least 0).
    pub tail: f64,
}

/// The item at a dotted `path` (array-of-tables elements by index).
fn get<'a>(doc: &'a DocumentMut, path: &str) -> Option<&'a Item> {
    let mut item = doc.as_item();
    let mut parts = path.split('.').peekable();
    while let Some(p) = parts.next() {
        let next = item.get(p)?;
        item = match (next.as_array_of_tables(), parts.peek()) {
            (Some(a), Some(i)) => {
                let i: usize = i.parse().ok()?;
                parts.next();
                let t = a.get(i)?;
                match parts.next() {
                    Some(k) => t.get(k)?,
                    None => return None,
                }
            }
            _ => next,
        };
    }
    Some(item)
}

fn float(doc: &DocumentMut, path: &str) -> Option<f64> {
    let v = get(doc, path)?.as_value()?;
    v.as_float().or_else(|| v.as_integer().map(|i| i as f64))
}

fn string<'a>(doc: &'a DocumentMut, path: &str) -> Option<&'a str> {
    get(doc, path)?.as_str()
}

fn has(doc: &DocumentMut, path: &str) -> bool {
    get(doc, path).is_some()
}

/// The number of `[[name]]` tables.
fn count(doc: &DocumentMut, name: &str) -> usize {
    (doc.get(name).and_then(Item::as_array_of_tables)).map_or(0, |a| a.len())
}

/// A number as TOML text that reads back to the same f64.
fn num(x: f64) -> String {
    format!("{x:?}")
}

/// The edits of `s` on the model `doc`, or none when it does not apply (nothing to leave
/// out, or the model is not a bridge file).
pub fn edits(doc: &DocumentMut, s: Simplification, timing: &Timing) -> Option<Vec<Edit>> {
    let bridge = has(doc, "deck") || count(doc, "frame") > 0;
    if !bridge {
        return None;
    }
    let contacts = get(doc, "contacts.enabled")
        .and_then(Item::as_bool)
        .unwrap_or(true);
    let joints = count(doc, "joint");
    let abutment_kind = string(doc, "abutment.kind").unwrap_or("actuators");
    let column_law = string(doc, "column.law.law");
    let out = match s {
        Simplification::RigidAbutments | Simplification::NoBackfill => {
            abutment_edits(doc, s, abutment_kind)
        }
        Simplification::BilinearColumns => {
            if column_law != Some("takeda") {
                return None;
            }
            let (k, fy, r) = bilinear_of_takeda(doc)?;
            let law = format!(
                "{{ law = \"bilinear\", stiffness = {}, yield_force = {}, post_yield_ratio = {} }}",
                num(k),
                num(fy),
                num(r)
            );
            vec![Edit::set("column.law", law)]
        }
        Simplification::LinearColumns => {
            if !matches!(column_law, Some("takeda" | "bilinear")) {
                return None;
            }
            let k = float(doc, "column.law.stiffness")?;
            let law = format!("{{ law = \"linear\", stiffness = {} }}", num(k));
            vec![Edit::set("column.law", law)]
        }
        Simplification::Frictionless | Simplification::PlasticImpacts => {
            contact_edits(doc, s, contacts, joints)
        }
        Simplification::NoContacts => {
            if !contacts || !has(doc, "contacts") {
                return None;
            }
            vec![Edit::set("contacts.enabled", "false")]
        }
        Simplification::TranslatingDeck => {
            let decks = if has(doc, "deck") {
                vec!["deck".to_string()]
            } else {
                (0..count(doc, "frame"))
                    .map(|i| format!("frame.{i}"))
                    .collect()
            };
            (decks.into_iter())
                .map(|d| format!("{d}.rotation"))
                .filter(|p| get(doc, p).and_then(Item::as_bool) != Some(false))
                .map(|p| Edit::set(p, "false"))
                .collect()
        }
        Simplification::NoKeys => {
            let mut e = Vec::new();
            if has(doc, "abutment.key") {
                e.push(Edit::remove("abutment.key"));
            }
            for j in 0..joints {
                let p = format!("joint.{j}.key");
                if has(doc, &p) {
                    e.push(Edit::remove(p));
                }
            }
            e
        }
        Simplification::NoBearings => {
            if !has(doc, "abutment.bearing") {
                return None;
            }
            vec![Edit::remove("abutment.bearing")]
        }
        Simplification::LongitudinalOnly => {
            let moving_y = match string(doc, "excitation.kind") {
                Some("record") => has(doc, "excitation.transverse"),
                Some("harmonic") => float(doc, "excitation.amplitude_y").is_some_and(|a| a != 0.0),
                _ => false,
            };
            if !moving_y || string(doc, "excitation.components") == Some("longitudinal") {
                return None;
            }
            vec![Edit::set("excitation.components", "\"longitudinal\"")]
        }
        Simplification::StrongMotion => {
            let (t5, t95) = timing.strong_motion?;
            if has(doc, "excitation.window")
                || t95.partial_cmp(&t5) != Some(std::cmp::Ordering::Greater)
            {
                return None;
            }
            let window = format!("[{}, {}]", num(t5), num(t95));
            let t_end = (t95 - t5) + timing.tail;
            vec![
                Edit::set("excitation.window", window),
                Edit::set("solver.t_end", num(t_end)),
            ]
        }
    };
    (!out.is_empty()).then_some(out)
}

/// The edits of the abutment simplifications (rigid walls, no backfill).
fn abutment_edits(doc: &DocumentMut, s: Simplification, abutment_kind: &str) -> Vec<Edit> {
    match s {
        Simplification::RigidAbutments => {
            if abutment_kind == "rigid" {
                return Vec::new();
            }
            let mut e = vec![Edit::set("abutment.kind", "\"rigid\"")];
            for k in [
                "mass",
                "inertia",
                "actuator_stiffness",
                "actuator_damping",
                "actuator_offset",
                "backwall_height",
                "backfill_stiffness",
                "backfill_capacity",
            ] {
                if has(doc, &format!("abutment.{k}")) {
                    e.push(Edit::remove(format!("abutment.{k}")));
                }
            }
            e
        }
        Simplification::NoBackfill => {
            if abutment_kind != "backfill" {
                return Vec::new();
            }
            let mut e = vec![Edit::set("abutment.kind", "\"actuators\"")];
            for k in ["backwall_height", "backfill_stiffness", "backfill_capacity"] {
                if has(doc, &format!("abutment.{k}")) {
                    e.push(Edit::remove(format!("abutment.{k}")));
                }
            }
            e
        }
        _ => Vec::new(),
    }
}

/// The edits of the contact-law simplifications (frictionless, plastic impacts).
fn contact_edits(doc: &DocumentMut, s: Simplification, contacts: bool, joints: usize) -> Vec<Edit> {
    match s {
        Simplification::Frictionless => {
            let mut e = Vec::new();
            if contacts && float(doc, "contacts.mu").is_some_and(|m| m > 0.0) {
                e.push(Edit::set("contacts.mu", "0.0"));
            }
            for j in 0..joints {
                let p = format!("joint.{j}.mu");
                if float(doc, &p).is_some_and(|m| m > 0.0) {
                    e.push(Edit::set(p, "0.0"));
                }
            }
            e
        }
        Simplification::PlasticImpacts => {
            let mut e = Vec::new();
            if contacts && float(doc, "contacts.restitution").is_some_and(|r| r > 0.0) {
                e.push(Edit::set("contacts.restitution", "0.0"));
            }
            for j in 0..joints {
                let p = format!("joint.{j}.restitution");
                if float(doc, &p).is_some_and(|r| r > 0.0) {
                    e.push(Edit::set(p, "0.0"));
                }
            }
            e
        }
        _ => Vec::new(),
    }
}

/// The bilinear law of the model's Takeda columns: (k, f_y, r). With a trilinear backbone
/// (`crack_force`), the secant stiffness to yield f_y / d_y and the same post-yield slope.
fn bilinear_of_takeda(doc: &DocumentMut) -> Option<(f64, f64, f64)> {
    let k = float(doc, "column.law.stiffness")?;
    let fy = float(doc, "column.law.yield_force")?;
    let r = float(doc, "column.law.post_yield_ratio")?;
    match float(doc, "column.law.yield_displacement") {
        Some(dy) if dy > 0.0 && has(doc, "column.law.crack_force") => {
            let ks = fy / dy;
            Some((ks, fy, r * k / ks))
        }
        _ => Some((k, fy, r)),
    }
}

/// Why an edit could not be applied (a path the file does not have, a value that is not TOML).
#[derive(Debug, thiserror::Error)]
pub enum EditError {
    #[error("the model is not TOML: {0}")]
    Parse(String),
    #[error("{path}: {reason}")]
    Path { path: String, reason: String },
}

/// The table-like item holding the last key of `path` (array-of-tables elements by index),
/// and that key.
fn parent_mut<'a>(
    doc: &'a mut DocumentMut,
    path: &'a str,
) -> Result<(&'a mut dyn toml_edit::TableLike, &'a str), EditError> {
    let bad = |reason: &str| EditError::Path {
        path: path.to_string(),
        reason: reason.to_string(),
    };
    let parts: Vec<&str> = path.split('.').collect();
    let (last, head) = parts.split_last().ok_or_else(|| bad("empty path"))?;
    let mut table: &mut dyn toml_edit::TableLike = doc.as_table_mut();
    let mut i = 0;
    while i < head.len() {
        if !table.contains_key(head[i]) {
            // a table the model leaves out (e.g. `[solver]`) is made for the key
            table.insert(head[i], Item::Table(toml_edit::Table::new()));
        }
        let item = table.get_mut(head[i]).ok_or_else(|| bad("no such table"))?;
        if item.is_array_of_tables() {
            let k: usize = (head.get(i + 1).and_then(|s| s.parse().ok()))
                .ok_or_else(|| bad("an index is needed after an array of tables"))?;
            let a = item.as_array_of_tables_mut().expect("checked");
            table = a.get_mut(k).ok_or_else(|| bad("no such element"))?;
            i += 2;
        } else {
            table = item.as_table_like_mut().ok_or_else(|| bad("not a table"))?;
            i += 1;
        }
    }
    Ok((table, last))
}

/// `text` with `changes` applied (each an [`Edit`] made for a [`Simplification`]), comments and
/// layout kept. With `mark`, each changed key gets a comment line above it saying which
/// simplification changed it, what that leaves out and the old value; a removed key is named
/// in a comment above its table.
pub fn apply(
    text: &str,
    changes: &[(Simplification, Edit)],
    mark: bool,
) -> Result<String, EditError> {
    let mut doc: DocumentMut = text.parse().map_err(|e| EditError::Parse(format!("{e}")))?;
    // per table and simplification, the keys removed (`k = v`), noted above the table
    let mut removed: Vec<(String, Simplification, Vec<String>)> = Vec::new();
    for (s, edit) in changes {
        let (table, key) = parent_mut(&mut doc, &edit.path)?;
        let old = table.get(key).and_then(Item::as_value).map(|v| {
            let mut v = v.clone();
            v.decor_mut().clear();
            format!("{key} = {v}")
        });
        match &edit.value {
            Some(v) => {
                let mut value: toml_edit::Value = v.parse().map_err(|e| EditError::Path {
                    path: edit.path.clone(),
                    reason: format!("not a TOML value ({v}): {e}"),
                })?;
                match table.get_mut(key) {
                    // replaced in place: the key keeps its comments, the value its own
                    Some(item) => {
                        if let Item::Value(old) = &*item {
                            *value.decor_mut() = old.decor().clone();
                        }
                        *item = Item::Value(value);
                    }
                    None => {
                        table.insert(key, Item::Value(value));
                    }
                }
                if mark && let Some(mut k) = table.key_mut(key) {
                    let prefix = (k.leaf_decor().prefix())
                        .and_then(|p| p.as_str())
                        .unwrap_or("")
                        .to_string();
                    let was = old.unwrap_or_else(|| format!("{key} absent"));
                    let note = format!(
                        "# simplified ({}): leaves out {}; was {was}\n",
                        s.name(),
                        s.leaves_out()
                    );
                    k.leaf_decor_mut().set_prefix(format!("{prefix}{note}"));
                }
            }
            None => {
                keep_comments_of_removed(table, key);
                table.remove(key);
                let at = edit
                    .path
                    .rsplit_once('.')
                    .map_or("", |(t, _)| t)
                    .to_string();
                let was = old.unwrap_or_else(|| key.to_string());
                match removed.iter_mut().find(|(t, x, _)| *t == at && x == s) {
                    Some((_, _, keys)) => keys.push(was),
                    None => removed.push((at, *s, vec![was])),
                }
            }
        }
    }
    if mark {
        for (table, s, keys) in removed {
            if let Some(d) = table_decor(&mut doc, &table) {
                let prefix = d
                    .prefix()
                    .and_then(|p| p.as_str())
                    .unwrap_or("")
                    .to_string();
                let note = format!(
                    "# simplified ({}): leaves out {}; removed {}\n",
                    s.name(),
                    s.leaves_out(),
                    keys.join(", ")
                );
                d.set_prefix(format!("{prefix}{note}"));
            }
        }
    }
    Ok(doc.to_string())
}

/// The comment lines above `key` (its decor's prefix) moved onto the key that follows it,
/// so that removing `key` removes its line only.
fn keep_comments_of_removed(table: &mut dyn toml_edit::TableLike, key: &str) {
    let keys: Vec<String> = table.iter().map(|(k, _)| k.to_string()).collect();
    let Some(at) = keys.iter().position(|k| k == key) else {
        return;
    };
    let prefix = (table.key(key).and_then(|k| k.leaf_decor().prefix()))
        .and_then(|p| p.as_str())
        .unwrap_or("")
        .to_string();
    if prefix.trim().is_empty() {
        return;
    }
    if let Some(next) = keys.get(at + 1)
        && let Some(mut k) = table.key_mut(next)
    {
        let old = (k.leaf_decor().prefix())
            .and_then(|p| p.as_str())
            .unwrap_or("")
            .to_string();
        k.leaf_decor_mut().set_prefix(format!("{prefix}{old}"));
    }
}

/// The decor of the `[table]` (or `[[table]]` element) at `path` (`abutment`, `joint.1`).
fn table_decor<'a>(doc: &'a mut DocumentMut, path: &str) -> Option<&'a mut toml_edit::Decor> {
    let parts: Vec<&str> = path.split('.').collect();
    let item = doc.get_mut(parts.first()?)?;
    if item.is_array_of_tables() {
        let k: usize = parts.get(1)?.parse().ok()?;
        let a = item.as_array_of_tables_mut()?;
        return Some(a.get_mut(k)?.decor_mut());
    }
    Some(item.as_table_mut()?.decor_mut())
}

#[cfg(test)]
mod tests {
    use super::*;

    const MODEL: &str = r#"title = "t"
[deck]
mass = 1.0   # t

[abutment]
# the blocks
mass = 0.65           # t (paper)
inertia = 0.31
actuator_stiffness = 1.0e4  # kN/m
actuator_offset = 0.9
key = { gap = 0.01, stiffness = 100.0, capacity = 10.0, failure_displacement = 0.05 }

[contacts]
mu = 0.5              # paper §4.3
restitution = 0.2
gaps = [0.01, 0.01, 0.01, 0.01]

[column]
# takeda columns
law = { law = "takeda", stiffness = 9320.0, yield_force = 98.0, post_yield_ratio = 0.05, unloading_exponent = 0.4 }

[[joint]]
gaps = [0.01, 0.01]
mu = 0.3
"#;

    fn doc() -> DocumentMut {
        MODEL.parse().unwrap()
    }

    #[test]
    fn each_simplification_edits_what_it_names_and_nothing_else() {
        let t = Timing {
            strong_motion: Some((2.5, 11.25)),
            tail: 1.0,
        };
        let names = |s| {
            (edits(&doc(), s, &t).unwrap().into_iter())
                .map(|e| format!("{}={}", e.path, e.value.unwrap_or_else(|| "-".into())))
                .collect::<Vec<_>>()
                .join(" ")
        };
        use Simplification::*;
        assert_eq!(
            names(RigidAbutments),
            "abutment.kind=\"rigid\" abutment.mass=- abutment.inertia=- \
             abutment.actuator_stiffness=- abutment.actuator_offset=-"
        );
        assert_eq!(
            names(BilinearColumns),
            "column.law={ law = \"bilinear\", stiffness = 9320.0, yield_force = 98.0, post_yield_ratio = 0.05 }"
        );
        assert_eq!(
            names(LinearColumns),
            "column.law={ law = \"linear\", stiffness = 9320.0 }"
        );
        assert_eq!(names(Frictionless), "contacts.mu=0.0 joint.0.mu=0.0");
        assert_eq!(names(PlasticImpacts), "contacts.restitution=0.0");
        assert_eq!(names(NoContacts), "contacts.enabled=false");
        assert_eq!(names(NoKeys), "abutment.key=-");
        assert_eq!(names(TranslatingDeck), "deck.rotation=false");
        assert_eq!(
            names(StrongMotion),
            "excitation.window=[2.5, 11.25] solver.t_end=9.75"
        );
        let recorded: DocumentMut = format!(
            "{MODEL}[excitation]\nkind = \"record\"\nlongitudinal = \"a.AT2\"\ntransverse = \"b.AT2\"\n"
        )
        .parse()
        .unwrap();
        let e = edits(&recorded, LongitudinalOnly, &t).unwrap();
        assert_eq!(e, [Edit::set("excitation.components", "\"longitudinal\"")]);
        // nothing to leave out
        assert_eq!(edits(&doc(), LongitudinalOnly, &t), None);
        assert_eq!(edits(&doc(), NoBearings, &t), None);
        assert_eq!(edits(&doc(), NoBackfill, &t), None);
        assert_eq!(edits(&doc(), StrongMotion, &Timing::default()), None);
        // not a bridge file
        let scene: DocumentMut = "[[body]]\nname = \"b\"\n".parse().unwrap();
        assert_eq!(edits(&scene, Frictionless, &t), None);
    }

    #[test]
    fn edits_keep_comments_and_marked_ones_say_why() {
        use Simplification::*;
        let t = Timing::default();
        let changes: Vec<(Simplification, Edit)> = [RigidAbutments, Frictionless]
            .into_iter()
            .flat_map(|s| {
                edits(&doc(), s, &t)
                    .unwrap()
                    .into_iter()
                    .map(move |e| (s, e))
            })
            .collect();
        let plain = apply(MODEL, &changes, false).unwrap();
        assert!(
            plain.contains("mu = 0.0              # paper §4.3\n"),
            "{plain}"
        );
        assert!(plain.contains("kind = \"rigid\"") && !plain.contains("actuator"));
        assert!(
            plain.contains("# the blocks"),
            "comments above a removed key stay"
        );
        let back: toml::Table = toml::from_str(&plain).unwrap();
        assert_eq!(back["joint"][0]["mu"].as_float(), Some(0.0));
        let marked = apply(MODEL, &changes, true).unwrap();
        assert!(
            marked.contains(
                "# simplified (frictionless): leaves out Coulomb friction at the contact corners (μ = 0); was mu = 0.5\nmu = 0.0"
            ),
            "{marked}"
        );
        assert!(
            marked.contains("# simplified (rigid-abutments): leaves out the abutments' own masses on their actuators or backfill: the walls move as the ground does; removed mass = 0.65, inertia = 0.31, actuator_stiffness = 1.0e4, actuator_offset = 0.9\n[abutment]\n# the blocks\n"),
            "{marked}"
        );
        // the same data as the unmarked text
        let a: toml::Table = toml::from_str(&marked).unwrap();
        assert_eq!(a, back);
    }
}
