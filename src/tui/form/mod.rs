//! The parameter form: a curated list of bridge parameters followed by every other scalar leaf
//! of the TOML document, in groups (one per table, each folding), each field with its label in
//! the user's words (lists numbered from 1) and its unit in the model's unit system. Edits are
//! applied to the text with `toml_edit`, keeping comments and layout (`form_edit`); validation
//! is the engine's own (`load_str`).

pub mod edit;
pub mod list_edit;
pub mod merge;
pub mod model_files;
pub mod spec;
pub mod swap;
pub mod units;

pub use edit::{remove_value, set_leaf, set_value, system_of};
pub use spec::{Dim, Kind, fit_label, group_of, group_title, label_of, place_of};
pub use units::parse_input;

use spec::{BRIDGE, SOLVER, law_keys};
use std::collections::BTreeSet;
use std::path::Path;
use toml_edit::{DocumentMut, Item, Value};

#[derive(Clone, Debug)]
pub struct Field {
    /// Dotted path: tables, array-of-table and array indices (0-based, as `--set` takes
    /// them), inline tables.
    pub path: String,
    /// The field in the user's words, list elements numbered from 1.
    pub label: String,
    /// What its number measures.
    pub dim: Dim,
    /// Its unit in the model's system (or the words it takes).
    pub unit: String,
    pub kind: Kind,
    /// Value in the draft (None: absent, the default applies).
    pub value: Option<String>,
    /// Value in the file as last loaded or saved.
    pub saved: Option<String>,
    /// The trailing comment of the line, if any.
    pub note: String,
    pub curated: bool,
    /// The group (table) it is shown in: [`group_of`] its path.
    pub group: String,
}

impl Field {
    pub fn edited(&self) -> bool {
        self.value != self.saved
    }
    /// Text to start editing from.
    pub fn edit_text(&self) -> String {
        self.value.clone().unwrap_or_default()
    }
    /// Whether the search text is in its label or its path (case-insensitive).
    pub fn matches(&self, query: &str) -> bool {
        let q = query.to_lowercase();
        !q.is_empty() && (self.label.to_lowercase().contains(&q) || self.path.contains(&q))
    }
}

/// A row of the form: a group's header or a field.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Row {
    /// The header of the group of field `first` (its first field).
    Header(usize),
    Field(usize),
}

/// Where the form's selection was (what `Esc` goes back to after a search).
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Spot {
    pub selected: usize,
    pub on_header: bool,
    pub folded: BTreeSet<String>,
}

#[derive(Clone, Debug, Default)]
pub struct Form {
    /// The fields, group after group.
    pub fields: Vec<Field>,
    /// The selected field (or, `on_header`, its group's header).
    pub selected: usize,
    pub on_header: bool,
    /// The folded groups (kept when the form is rebuilt).
    pub folded: BTreeSet<String>,
    /// The last search (`n`/`N` look for it again).
    pub query: String,
}

impl Form {
    /// The selected field (None on a group's header).
    pub fn selected(&self) -> Option<&Field> {
        if self.on_header {
            None
        } else {
            self.fields.get(self.selected)
        }
    }
    pub fn index_of(&self, path: &str) -> Option<usize> {
        self.fields.iter().position(|f| f.path == path)
    }
    /// Selects field `i`, unfolding its group.
    pub fn select(&mut self, i: usize) {
        if let Some(f) = self.fields.get(i) {
            self.folded.remove(&f.group);
            self.selected = i;
            self.on_header = false;
        }
    }
    /// The group of the selection.
    pub fn group(&self) -> Option<&str> {
        self.fields.get(self.selected).map(|f| f.group.as_str())
    }
    /// The rows shown: each group's header, then its fields unless it is folded.
    pub fn rows(&self) -> Vec<Row> {
        let mut out = Vec::new();
        for (i, f) in self.fields.iter().enumerate() {
            if i == 0 || self.fields[i - 1].group != f.group {
                out.push(Row::Header(i));
            }
            if !self.folded.contains(&f.group) {
                out.push(Row::Field(i));
            }
        }
        out
    }
    /// The selection's row among [`Form::rows`].
    pub fn row(&self, rows: &[Row]) -> usize {
        let first = self.first_of_group(self.selected);
        let want = if self.on_header || self.folded.contains(self.group().unwrap_or("")) {
            Row::Header(first)
        } else {
            Row::Field(self.selected)
        };
        rows.iter().position(|r| *r == want).unwrap_or(0)
    }
    fn first_of_group(&self, i: usize) -> usize {
        let Some(g) = self.fields.get(i).map(|f| &f.group) else {
            return 0;
        };
        (0..=i)
            .rev()
            .take_while(|&k| self.fields[k].group == *g)
            .last()
            .unwrap_or(i)
    }
    /// Moves the selection `d` rows (headers count), within the rows.
    pub fn move_by(&mut self, d: i64) {
        let rows = self.rows();
        if rows.is_empty() {
            return;
        }
        let at = (self.row(&rows) as i64 + d).clamp(0, rows.len() as i64 - 1) as usize;
        self.go_to(rows[at]);
    }
    /// Selects the first (`last` false) or the last row.
    pub fn go_end(&mut self, last: bool) {
        let rows = self.rows();
        let r = if last { rows.last() } else { rows.first() };
        if let Some(r) = r.copied() {
            self.go_to(r);
        }
    }
    fn go_to(&mut self, r: Row) {
        match r {
            Row::Header(i) => {
                self.selected = i;
                self.on_header = true;
            }
            Row::Field(i) => {
                self.selected = i;
                self.on_header = false;
            }
        }
    }
    /// Folds or unfolds the selection's group; folding puts the selection on its header.
    /// Returns the group and whether it is folded now.
    pub fn toggle_fold(&mut self) -> Option<(String, bool)> {
        let g = self.group()?.to_string();
        let folded = if self.folded.remove(&g) {
            false
        } else {
            self.folded.insert(g.clone());
            self.selected = self.first_of_group(self.selected);
            self.on_header = true;
            true
        };
        Some((g, folded))
    }
    /// Folds every group; unfolds them all when any is folded.
    pub fn toggle_fold_all(&mut self) -> bool {
        let groups: BTreeSet<String> = self.fields.iter().map(|f| f.group.clone()).collect();
        let fold = self.folded.is_empty();
        if fold {
            self.folded = groups;
            self.selected = self.first_of_group(self.selected);
            self.on_header = true;
        } else {
            self.folded.clear();
        }
        fold
    }
    pub fn spot(&self) -> Spot {
        Spot {
            selected: self.selected,
            on_header: self.on_header,
            folded: self.folded.clone(),
        }
    }
    pub fn restore(&mut self, s: &Spot) {
        self.selected = s.selected.min(self.fields.len().saturating_sub(1));
        self.on_header = s.on_header;
        self.folded = s.folded.clone();
    }
    /// The first field matching `query` from field `from` on (`forward`) or back from it,
    /// wrapping around.
    pub fn find(&self, query: &str, from: usize, forward: bool) -> Option<usize> {
        let n = self.fields.len();
        (0..n)
            .map(|k| {
                if forward {
                    (from + k) % n
                } else {
                    (from + n - k % n) % n
                }
            })
            .find(|&i| self.fields[i].matches(query))
    }
    /// Carries the folds, the last search and the selection (by path) over from the form
    /// before a rebuild.
    pub fn keep_from(&mut self, old: &Form) {
        self.folded = old.folded.clone();
        self.query = old.query.clone();
        let path = old.fields.get(old.selected).map(|f| f.path.as_str());
        self.selected = path
            .and_then(|p| self.index_of(p))
            .unwrap_or(old.selected.min(self.fields.len().saturating_sub(1)));
        self.on_header = old.on_header;
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

/// Whether a model text is a bridge file (has a `[deck]` table or `[[frame]]` tables).
pub fn is_bridge(text: &str) -> bool {
    text.parse::<DocumentMut>()
        .map(|d| d.contains_key("deck") || d.contains_key("frame"))
        .unwrap_or(false)
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
    let sys = edit::system_of(&doc);
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
            dim: sp.dim,
            unit: sp.dim.unit(sys),
            kind: leaf.map_or(sp.kind, |l| l.kind),
            value: leaf.map(|l| l.value.clone()),
            saved: saved_of(sp.path),
            note: leaf.map(|l| l.note.clone()).unwrap_or_default(),
            curated: true,
            group: group_of(sp.path).to_string(),
        });
    }
    for l in &draft_leaves {
        if fields.iter().any(|f| f.path == l.path) {
            continue;
        }
        let dim = dim_of_path(&l.path, l.kind);
        fields.push(Field {
            path: l.path.clone(),
            label: label_of(&l.path),
            dim,
            unit: dim.unit(sys),
            kind: l.kind,
            value: Some(l.value.clone()),
            saved: saved_of(&l.path),
            note: l.note.clone(),
            curated: false,
            group: group_of(&l.path).to_string(),
        });
    }
    // group after group (stable: the curated fields first within each)
    let mut first_seen: Vec<String> = Vec::new();
    for f in &fields {
        if !first_seen.contains(&f.group) {
            first_seen.push(f.group.clone());
        }
    }
    let rank = |g: &str| spec::group_rank(g, first_seen.iter().position(|x| x == g).unwrap_or(0));
    fields.sort_by_key(|f| rank(&f.group));
    Form {
        fields,
        ..Form::default()
    }
}

/// The quantity of a leaf that is not a curated parameter, from its key (or its list's name
/// for an array's element); words and true/false have none.
fn dim_of_path(path: &str, kind: Kind) -> Dim {
    if path == "units" {
        return Dim::Choice("SI-kN|SI|kip-in");
    }
    if matches!(kind, Kind::Str | Kind::Bool) {
        return Dim::Plain;
    }
    let key = path
        .rsplit('.')
        .find(|s| s.parse::<usize>().is_err())
        .unwrap_or(path);
    spec::dim_of_key(key)
}

/// A model error with line and column: (`file:line:col: …` message, the message without the
/// location, (line, column)). `Invalid` errors carry a field whose column is located in the text.
/// The paths in the messages are numbered from 1, as the form's labels ([`spec::one_based`]).
pub fn describe_error(
    e: &crate::ModelError,
    text: &str,
) -> (String, String, Option<(usize, usize)>) {
    let (message, detail, at) = describe_engine_error(e, text);
    (spec::one_based(&message), spec::one_based(&detail), at)
}

/// A model error as the workbench shows it: [`crate::ModelError`]'s text with its paths
/// numbered from 1 ([`spec::one_based`]).
pub fn shown_error(e: &crate::ModelError) -> String {
    spec::one_based(&e.to_string())
}

/// [`describe_error`] in the engine's words (paths numbered from 0).
fn describe_engine_error(
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
