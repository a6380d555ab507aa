//! What the form knows of a field from its dotted path: the curated bridge parameters (label,
//! quantity), the label and quantity of every other leaf (list numbers 1-based, as the user
//! counts: `test run 4 pga x`, `contacts gap 1 (left_top)`), its group (the table it is in)
//! and the group's title.

use crate::units::{Quantity, UnitSystem};
use toml_edit::Value;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Float,
    Int,
    Bool,
    Str,
}

impl Kind {
    pub(super) fn of(v: &Value) -> Option<Kind> {
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

/// What a field's number measures: a quantity of the model's unit system, or a unit that no
/// system changes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dim {
    Q(Quantity),
    /// Acceleration in g (the records' PGAs).
    G,
    /// A ratio (no unit, shown as `–`).
    Ratio,
    Percent,
    /// A 1-based number of something (a test run, a mode).
    Count,
    /// One of the words listed, `|`-separated.
    Choice(&'static str),
    /// One of the registry's method names.
    Methods,
    /// The solver's absolute tolerance: in the unit of each state component.
    State,
    /// Text, true/false, names: no unit.
    Plain,
}

impl Dim {
    /// The unit as shown (in the model's system); the choices for words.
    pub fn unit(self, sys: UnitSystem) -> String {
        match self {
            Dim::Q(q) => sys.unit(q).to_string(),
            Dim::G => "g".into(),
            Dim::Ratio => "–".into(),
            Dim::Percent => "%".into(),
            Dim::Count => "#".into(),
            Dim::Choice(c) => c.into(),
            Dim::Methods => crate::methods::Method::names("|"),
            // an absolute tolerance on each state component, in that component's unit
            Dim::State => "mixed".into(),
            Dim::Plain => String::new(),
        }
    }
}

/// A curated bridge parameter.
pub(super) struct Spec {
    pub path: &'static str,
    pub label: &'static str,
    pub dim: Dim,
    pub kind: Kind,
    /// Shown when the key is absent (the engine's default applies).
    pub optional: bool,
}

const fn s(path: &'static str, label: &'static str, dim: Dim, kind: Kind, optional: bool) -> Spec {
    Spec {
        path,
        label,
        dim,
        kind,
        optional,
    }
}

use Kind::{Bool as B, Float as F, Int as I, Str as S};
use Quantity as Q;
const LEN: Dim = Dim::Q(Q::Length);
const MASS: Dim = Dim::Q(Q::Mass);
const INERTIA: Dim = Dim::Q(Q::Inertia);
const STIFF: Dim = Dim::Q(Q::Stiffness);
const FORCE: Dim = Dim::Q(Q::Force);
const TIME: Dim = Dim::Q(Q::Time);
const R: Dim = Dim::Ratio;

/// Bridge parameters in form order.
#[rustfmt::skip]
pub(super) const BRIDGE: &[Spec] = &[
    s("deck.mass", "deck mass", MASS, F, false),
    s("deck.inertia", "deck inertia", INERTIA, F, false),
    s("deck.length", "deck length", LEN, F, false),
    s("deck.width", "deck width", LEN, F, false),
    s("deck.skew", "deck skew", Dim::Q(Q::Degrees), F, true),
    s("abutment.mass", "abutment mass", MASS, F, false),
    s("abutment.inertia", "abutment inertia", INERTIA, F, false),
    s("abutment.actuator_stiffness", "actuator stiffness", STIFF, F, false),
    s("abutment.actuator_damping", "actuator damping", Dim::Q(Q::Damping), F, true),
    s("abutment.actuator_offset", "actuator offset", LEN, F, false),
    s("contacts.gaps.0", "contacts gap 1 (left_top)", LEN, F, false),
    s("contacts.gaps.1", "contacts gap 2 (left_bottom)", LEN, F, false),
    s("contacts.gaps.2", "contacts gap 3 (right_top)", LEN, F, false),
    s("contacts.gaps.3", "contacts gap 4 (right_bottom)", LEN, F, false),
    s("contacts.mu", "friction μ", R, F, false),
    s("contacts.restitution", "restitution ε", R, F, false),
    s("contacts.enabled", "contacts enabled", Dim::Plain, B, true),
    s("column.law.law", "column law", Dim::Choice("linear|bilinear|takeda"), S, false),
    s("column.law.stiffness", "column stiffness", STIFF, F, false),
    s("column.law.yield_force", "column yield force", FORCE, F, false),
    s("column.law.post_yield_ratio", "post-yield ratio", R, F, false),
    s("column.law.unloading_exponent", "unloading exponent", R, F, false),
    s("column.law.crack_force", "crack force", FORCE, F, false),
    s("column.law.yield_displacement", "yield displacement", LEN, F, false),
    s("column.reference_height", "column ref. height", LEN, F, false),
    s("column.offset", "column offset", LEN, F, false),
    s("column.torsion_stiffness", "column torsion stiffness", Dim::Q(Q::RotationalStiffness), F, false),
    s("damping.ratio", "damping ratio ζ", R, F, true),
    s("excitation.run", "test run", Dim::Count, I, true),
    s("excitation.time_scale", "time scale", R, F, true),
];

/// Solver settings, offered for every model (absent keys can be added).
#[rustfmt::skip]
pub(super) const SOLVER: &[Spec] = &[
    s("solver.method", "solver method", Dim::Methods, S, true),
    s("solver.t_end", "t_end", TIME, F, true),
    s("solver.rtol", "rtol", R, F, true),
    s("solver.output_dt", "output step", TIME, F, true),
];

/// Keys of each hysteretic law (required first).
pub(super) fn law_keys(kind: &str) -> Option<&'static [&'static str]> {
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

/// The quantity a key names (the key of a leaf, or of the list an element is in).
pub(super) fn dim_of_key(key: &str) -> Dim {
    let ends = |s: &str| key == s || key.ends_with(&format!("_{s}"));
    let starts = |s: &str| key == s || key.starts_with(&format!("{s}_"));
    if key.contains("torsion") && ends("stiffness") || key.contains("rotational") {
        return if key.contains("damping") {
            Dim::Q(Q::RotationalDamping)
        } else {
            Dim::Q(Q::RotationalStiffness)
        };
    }
    if starts("pga") {
        Dim::G
    } else if key == "atol" {
        Dim::State
    } else if ends("velocity") || key == "velocity_tol" {
        Dim::Q(Q::Velocity)
    } else if ["gap_tol", "max_penetration"].contains(&key) {
        LEN
    } else if ["window", "spacing", "h_max", "time_tol"]
        .iter()
        .any(|k| ends(k))
    {
        TIME
    } else if [
        "mu",
        "restitution",
        "ratio",
        "exponent",
        "scale",
        "rtol",
        "closure",
    ]
    .iter()
    .any(|k| ends(k))
    {
        Dim::Ratio
    } else if key == "seat_percent" || ends("percent") {
        Dim::Percent
    } else if ["skew", "heading", "angle"].iter().any(|k| ends(k)) {
        Dim::Q(Q::Degrees)
    } else if ends("mass") {
        MASS
    } else if ends("inertia") {
        INERTIA
    } else if ends("stiffness") {
        STIFF
    } else if ends("damping") {
        Dim::Q(Q::Damping)
    } else if ends("force") || key == "capacity" {
        FORCE
    } else if [
        "t_end", "step", "dt", "lag", "lags", "duration", "t_start", "max_step", "min_step",
    ]
    .iter()
    .any(|k| ends(k))
        || starts("lag")
    {
        TIME
    } else if [
        "gap",
        "gaps",
        "x",
        "y",
        "z",
        "height",
        "width",
        "length",
        "offset",
        "displacement",
        "radius",
        "thickness",
    ]
    .iter()
    .any(|k| ends(k))
    {
        LEN
    } else if key == "modes" || key == "run" {
        Dim::Count
    } else {
        Dim::Plain
    }
}

/// A list's name for one of its elements (`gaps` → `gap`, `run` → `test run`).
fn element_word(list: &str) -> String {
    match list {
        "run" => "test run".into(),
        "key" => "shear key".into(),
        _ => {
            let w = list.replace('_', " ");
            match w.strip_suffix('s') {
                Some(one) if !one.ends_with('s') => one.to_string(),
                _ => w,
            }
        }
    }
}

/// Names of the elements of some bridge lists, in the file's order.
fn element_name(path: &[&str], i: usize) -> Option<&'static str> {
    let names: &[&str] = match path {
        ["contacts", "gaps"] => &["left_top", "left_bottom", "right_top", "right_bottom"],
        ["joint", _, "gaps"] => &["top", "bottom"],
        ["excitation", "lag_abutments"] => &["left", "right"],
        _ => return None,
    };
    names.get(i).copied()
}

/// The label of a dotted path in the user's words, list elements numbered from 1:
/// `run.3.pga_x` → `test run 4 pga x`, `contacts.gaps.0` → `contacts gap 1 (left_top)`,
/// `frame.1.bent.0.height` → `frame 2 bent 1 height`.
pub fn label_of(path: &str) -> String {
    if let Some(sp) = BRIDGE.iter().chain(SOLVER).find(|s| s.path == path) {
        return sp.label.to_string();
    }
    let segs: Vec<&str> = path.split('.').collect();
    let mut words: Vec<String> = Vec::new();
    let mut name = None;
    for (k, seg) in segs.iter().enumerate() {
        match seg.parse::<usize>() {
            Ok(i) if k > 0 => {
                words.pop();
                words.push(format!("{} {}", element_word(segs[k - 1]), i + 1));
                if k + 1 == segs.len() {
                    name = element_name(&segs[..k], i);
                }
            }
            _ => words.push(seg.replace('_', " ")),
        }
    }
    let mut label = words.join(" ");
    if let Some(n) = name {
        label.push_str(&format!(" ({n})"));
    }
    label
}

/// Where a path is in the file, in the user's words and 1-based: `run.3.pga_x` →
/// `pga_x in [[run]] 4`, `contacts.gaps.0` → `contacts.gaps, element 1`.
pub fn place_of(path: &str) -> String {
    let segs: Vec<&str> = path.split('.').collect();
    let mut keys: Vec<&str> = Vec::new();
    let mut at: Vec<String> = Vec::new();
    for (k, seg) in segs.iter().enumerate() {
        match seg.parse::<usize>() {
            Ok(i) if k > 0 => at.push(format!("{} {}", segs[k - 1], i + 1)),
            _ => keys.push(seg),
        }
    }
    if at.is_empty() {
        keys.join(".")
    } else {
        format!("{} ({})", keys.join("."), at.join(", "))
    }
}

/// The group of a path: the table it is in (`""` for the top-level keys).
pub fn group_of(path: &str) -> &str {
    match path.split_once('.') {
        Some((g, _)) => g,
        None => "",
    }
}

/// A group's title.
pub fn group_title(group: &str) -> String {
    match group {
        "" => "model".into(),
        "abutment" => "abutments".into(),
        "frame" => "frames and bents".into(),
        "bent" => "bents".into(),
        "joint" => "joints".into(),
        "key" => "shear keys".into(),
        "column" => "columns".into(),
        "run" => "test runs".into(),
        g => g.replace('_', " "),
    }
}

/// The rank of a group in the form (known tables in the bridge's order, others after them in
/// the file's order, the solver last).
pub(super) fn group_rank(group: &str, first_seen: usize) -> usize {
    const ORDER: [&str; 12] = [
        "",
        "deck",
        "abutment",
        "contacts",
        "frame",
        "bent",
        "joint",
        "key",
        "column",
        "damping",
        "excitation",
        "run",
    ];
    match ORDER.iter().position(|g| *g == group) {
        Some(i) => i,
        None if group == "solver" => usize::MAX,
        None => ORDER.len() + first_seen,
    }
}

/// Words shortened in labels too long for the column.
const SHORT: [(&str, &str); 10] = [
    ("displacement", "displ."),
    ("stiffness", "stiff."),
    ("exponent", "exp."),
    ("reference", "ref."),
    ("restitution", "restit."),
    ("abutment", "abut."),
    ("actuator", "act."),
    ("longitudinal", "long."),
    ("transverse", "transv."),
    ("unloading", "unload."),
];

/// A message of the engine as the workbench shows it: every dotted path with a list index in
/// it (`contacts.gaps.0`, `frame.1.bent.0.height`, `body.0.initial_velocity[2]`, numbered from
/// 0 as the command line's `--set` takes them) replaced by its label, numbered from 1
/// ([`label_of`]: `contacts gap 1 (left_top)`, `frame 2 bent 1 height`); the rest unchanged.
pub fn one_based(message: &str) -> String {
    let is_part = |c: char| c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '[' | ']');
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    while let Some(start) = rest.find(is_part) {
        out.push_str(&rest[..start]);
        let len = rest[start..]
            .find(|c| !is_part(c))
            .unwrap_or(rest.len() - start);
        let token = &rest[start..start + len];
        // a sentence's full stop is not part of the path; a part of a file's path is none
        let path = token.trim_end_matches('.');
        let in_file_path = out.ends_with('/') || rest[start + len..].starts_with('/');
        match indexed_path(path).filter(|_| !in_file_path) {
            Some(dotted) => {
                out.push_str(&label_of(&dotted));
                out.push_str(&token[path.len()..]);
            }
            None => out.push_str(token),
        }
        rest = &rest[start + len..];
    }
    out.push_str(rest);
    out
}

/// `path` as a dotted path (`a.0.b`, `a[0]` read as `a.0`) when it is one with a list index
/// after its first key.
fn indexed_path(path: &str) -> Option<String> {
    let dotted = path.replace('[', ".").replace(']', "");
    if path.matches('[').count() != path.matches(']').count() || path.ends_with('.') {
        return None;
    }
    let segs: Vec<&str> = dotted.split('.').collect();
    let first = segs.first()?;
    let number = |s: &&str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    let ok = first.starts_with(|c: char| c.is_ascii_alphabetic())
        && segs.iter().all(|s| !s.is_empty())
        && segs[1..].iter().any(number);
    ok.then_some(dotted)
}

/// A label that fits `width` characters, never cut inside a word: long words shortened
/// (`displacement` → `displ.`), then whole words dropped from the end, marked by `…`.
pub fn fit_label(label: &str, width: usize) -> String {
    let count = |s: &str| s.chars().count();
    if count(label) <= width {
        return label.to_string();
    }
    let mut words: Vec<String> = label.split(' ').map(str::to_string).collect();
    for (long, short) in SHORT {
        for w in words.iter_mut() {
            if w == long {
                *w = short.to_string();
            }
        }
        let s = words.join(" ");
        if count(&s) <= width {
            return s;
        }
    }
    while words.len() > 1 {
        words.pop();
        let s = format!("{}…", words.join(" "));
        if count(&s) <= width {
            return s;
        }
    }
    // one word wider than the column: nothing but the mark
    "…".into()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::Method;

    #[test]
    fn the_method_field_lists_the_registry() {
        let spec = SOLVER.iter().find(|s| s.path == "solver.method").unwrap();
        assert_eq!(spec.dim.unit(UnitSystem::SiKn), Method::names("|"));
    }

    #[test]
    fn labels_number_list_elements_from_one() {
        assert_eq!(label_of("run.3.pga_x"), "test run 4 pga x");
        assert_eq!(label_of("contacts.gaps.0"), "contacts gap 1 (left_top)");
        assert_eq!(
            one_based("m.toml:12:8: contacts.gaps.0: must be ≥ 0, got -0.01."),
            "m.toml:12:8: contacts gap 1 (left_top): must be ≥ 0, got -0.01."
        );
        assert_eq!(
            one_based("frame.1.bent.0.height: must be > 0 (see frame.1.length.)"),
            "frame 2 bent 1 height: must be > 0 (see frame 2 length.)"
        );
        assert_eq!(
            one_based("body.0.initial_velocity[2] is not finite; solver.rtol too"),
            "body 1 initial velocity 3 is not finite; solver.rtol too"
        );
        assert_eq!(
            one_based("/w/v1.2/four-span.toml 1.5e3 x.0a"),
            "/w/v1.2/four-span.toml 1.5e3 x.0a"
        );
        assert_eq!(label_of("frame.1.bent.0.height"), "frame 2 bent 1 height");
        assert_eq!(label_of("joint.0.gaps.1"), "joint 1 gap 2 (bottom)");
        assert_eq!(label_of("excitation.lag_bents.2"), "excitation lag bent 3");
        assert_eq!(label_of("bent.0.x"), "bent 1 x");
        assert_eq!(label_of("damping.modes.1"), "damping mode 2");
        assert_eq!(label_of("joint.0.key.capacity"), "joint 1 key capacity");
        assert_eq!(label_of("title"), "title");
        assert_eq!(place_of("run.3.pga_x"), "run.pga_x (run 4)");
        assert_eq!(place_of("contacts.gaps.0"), "contacts.gaps (gaps 1)");
        assert_eq!(place_of("deck.mass"), "deck.mass");
    }

    #[test]
    fn keys_name_their_quantity() {
        let len = Dim::Q(Quantity::Length);
        for k in [
            "gap",
            "x",
            "height",
            "seat_width",
            "failure_displacement",
            "offset",
        ] {
            assert_eq!(dim_of_key(k), len, "{k}");
        }
        for k in ["t_end", "output_dt", "lag_bents", "step"] {
            assert_eq!(dim_of_key(k), Dim::Q(Quantity::Time), "{k}");
        }
        assert_eq!(dim_of_key("pga_x"), Dim::G);
        assert_eq!(dim_of_key("mu"), Dim::Ratio);
        assert_eq!(dim_of_key("post_yield_ratio"), Dim::Ratio);
        assert_eq!(dim_of_key("capacity"), Dim::Q(Quantity::Force));
        assert_eq!(
            dim_of_key("torsion_stiffness"),
            Dim::Q(Quantity::RotationalStiffness)
        );
        assert_eq!(dim_of_key("name"), Dim::Plain);
        assert_eq!(dim_of_key("skew"), Dim::Q(Quantity::Degrees));
        assert_eq!(
            Dim::Q(Quantity::Stiffness).unit(UnitSystem::KipIn),
            "kip/in"
        );
    }

    #[test]
    fn long_labels_lose_whole_words_never_half_of_one() {
        assert_eq!(fit_label("deck mass", 20), "deck mass");
        let long = "frame 2 bent 1 failure displacement";
        assert_eq!(fit_label(long, 29), "frame 2 bent 1 failure displ.");
        assert_eq!(fit_label(long, 28), "frame 2 bent 1 failure…");
        assert_eq!(
            fit_label("column yield displacement", 20),
            "column yield displ."
        );
        assert_eq!(fit_label("abcdefghijk", 5), "…");
    }
}
