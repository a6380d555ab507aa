//! The inputs of the fuzz harness: seed files (the project's model files, and a small scene
//! driven by an AT2 record) and the mutations applied to them, drawn with proptest strategies.

use proptest::prelude::*;
use proptest::sample::Index;
use proptest::strategy::ValueTree;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use std::path::{Path, PathBuf};

/// A small scene whose ground moves as the AT2 record `rec.AT2` next to it: a deck on a
/// spring and a Takeda column to the moving ground, with two corner contacts.
pub const RECORD_SCENE: &str = r#"title = "fuzz record scene"
[solver]
t_end = 2.0
output_dt = 0.01
[[support]]
name = "ground"
kind = "record"
file = "rec.AT2"
processing = { taper = 0.05 }
[[body]]
name = "deck"
mass = 140.5
inertia = 13090.0
dofs = ["x", "y", "theta"]
[[spring]]
name = "kx"
body = "deck"
direction = [1.0, 0.0]
stiffness = 2000.0
damping = 10.0
support = "ground"
[[hysteretic]]
name = "col"
body = "deck"
point = [0.0, 1.0]
direction = [0.0, 1.0]
law = { law = "takeda", stiffness = 9320.0, yield_force = 98.0, post_yield_ratio = 0.05, unloading_exponent = 0.4 }
support = "ground"
[[contact]]
name = "left"
body = "deck"
point = [-16.1, 1.2]
normal = [1.0, 0.0]
gap = 0.005
mu = 0.5
restitution = 0.3
[[contact]]
name = "right"
body = "deck"
point = [16.1, -1.2]
normal = [-1.0, 0.0]
gap = 0.005
mu = 0.5
restitution = 0.3
"#;

/// One seed: a model file (its text, the path it is loaded as), and for the record seeds
/// the AT2 text written next to it as `rec.AT2`.
#[derive(Clone, Debug)]
pub struct Seed {
    pub name: String,
    pub model: String,
    pub path: PathBuf,
    pub at2: Option<String>,
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The model seeds: four-span.toml, four-span-rigid.toml, three-frame.toml and every
/// validation model, comments dropped; then the
/// record scene with each AT2 file of `excitations/`, three-frame.toml by islands, and the
/// bridge driven by one of them.
pub fn seeds() -> Vec<Seed> {
    let mut out = Vec::new();
    let mut models = vec![root().join("models/four-span.toml")];
    // bridges beyond the specimen: rigid abutments moving with the ground; frames, joints,
    // keys that fail and backfill
    models.push(root().join("models/four-span-rigid.toml"));
    models.push(root().join("models/three-frame.toml"));
    let mut val: Vec<PathBuf> = std::fs::read_dir(root().join("models/validation"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    val.sort();
    models.extend(val);
    for p in &models {
        out.push(Seed {
            name: rel(p),
            model: strip_comments(&std::fs::read_to_string(p).unwrap()),
            path: p.clone(),
            at2: None,
        });
    }
    let mut at2s: Vec<PathBuf> = std::fs::read_dir(root().join("excitations"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "AT2"))
        .collect();
    at2s.sort();
    for p in &at2s {
        out.push(Seed {
            name: format!("record scene + {}", rel(p)),
            model: RECORD_SCENE.to_string(),
            path: PathBuf::from("rec-scene.toml"),
            at2: Some(std::fs::read_to_string(p).unwrap()),
        });
    }
    // the longitudinal record mutated, the transverse one as it is
    let transverse = root().join("excitations/NORTHR_MUL279.AT2");
    let bridge = strip_comments(&std::fs::read_to_string(&models[0]).unwrap())
        .replace("\"../excitations/NORTHR_MUL009.AT2\"", "\"rec.AT2\"")
        .replace(
            "\"../excitations/NORTHR_MUL279.AT2\"",
            &format!("{:?}", transverse.display().to_string()),
        );
    // islands on their own steps (`solver.islands`): the bridge of three frames, keys
    // joining its frames, its abutments apart
    let frames = root().join("models/three-frame.toml");
    out.push(Seed {
        name: format!("{} by islands", rel(&frames)),
        model: strip_comments(&std::fs::read_to_string(&frames).unwrap()).replacen(
            "[solver]",
            "[solver]\nislands = true",
            1,
        ),
        path: frames,
        at2: None,
    });
    out.push(Seed {
        name: format!("four-span + mutated {}", rel(&at2s[2])),
        model: bridge,
        path: PathBuf::from("bridge.toml"),
        at2: Some(std::fs::read_to_string(root().join("excitations/NORTHR_MUL009.AT2")).unwrap()),
    });
    out
}

fn rel(p: &Path) -> String {
    p.strip_prefix(root()).unwrap_or(p).display().to_string()
}

/// Each line without its `#` comment (outside strings) and trailing blanks.
pub fn strip_comments(text: &str) -> String {
    let mut out = String::new();
    for line in text.lines() {
        let mut in_str = false;
        let mut end = line.len();
        for (i, c) in line.char_indices() {
            match c {
                '"' => in_str = !in_str,
                '#' if !in_str => {
                    end = i;
                    break;
                }
                _ => {}
            }
        }
        let l = line[..end].trim_end();
        if !l.is_empty() {
            out.push_str(l);
            out.push('\n');
        }
    }
    out
}

/// What replaces a number.
#[derive(Clone, Debug)]
pub enum NewNumber {
    Scale(i32),
    Negate,
    Literal(&'static str),
}

const LITERALS: &[&str] = &[
    "0",
    "0.0",
    "-0.0",
    "nan",
    "inf",
    "-inf",
    "1e308",
    "-1e308",
    "1e-308",
    "5e-324",
    "1e400",
    "9223372036854775807",
    "-9223372036854775808",
    "18446744073709551616",
    "1",
    "-1",
    "2",
    "0.5",
    "1e-9",
    "1e9",
    "\"x\"",
    "true",
    "[]",
    "{}",
];

/// One mutation of a model file (TOML) or of its record (AT2).
#[derive(Clone, Debug)]
pub enum Mutation {
    /// The n-th number (mod their count) of the model file.
    Number(Index, NewNumber),
    DeleteLine(Index),
    DuplicateLine(Index),
    /// Swap two top-level tables (`[x]` / `[[x]]` blocks).
    SwapTables(Index, Index),
    /// A junk `key = value` line inserted after the n-th line.
    JunkKey(Index, &'static str),
    /// The file cut at a fraction of its length.
    Truncate(Index),
    /// In the n-th array: drop its last element, or repeat its first.
    ArrayLength(Index, bool),
    /// `method = …` set in the `[solver]` table.
    Method(&'static str),
    /// The record: NPTS or DT of the header set to a value.
    At2Header(bool, &'static str),
    /// The record: the data cut after a fraction of its lines.
    At2Truncate(Index),
    /// The record: the n-th data token replaced.
    At2Token(Index, &'static str),
    /// The record: a line deleted or duplicated anywhere.
    At2Line(Index, bool),
}

const JUNK: &[&str] = &[
    "junk = 1",
    "t_end = 1e300",
    "output_dt = 1e-300",
    "max_steps = 0",
    "max_events = 0",
    "mu = 1e9",
    "restitution = 2.0",
    "gap = -1.0",
    "[junk]",
    "[[body]]",
    "[[contact]]",
    "name = \"deck\"",
    "=",
    "\"",
];
const METHODS: &[&str] = &["event", "moreau", "penalty", "penalty-explicit", "nope"];
const HEADER_VALUES: &[&str] = &[
    "0",
    "-1",
    "1",
    "3",
    "1e12",
    "99999999999",
    "2.5",
    "nan",
    "x",
    "0.0",
    "-0.01",
    "1e-12",
    "1e9",
    "inf",
    "",
];
const TOKENS: &[&str] = &[
    "x", "nan", "inf", "-inf", "1e300", "-1e300", "1e308", "1e-320", "0", "--1", "1.0.0", "9e9",
];

fn new_number() -> impl Strategy<Value = NewNumber> {
    prop_oneof![
        (-12i32..=12).prop_map(NewNumber::Scale),
        Just(NewNumber::Negate),
        proptest::sample::select(LITERALS).prop_map(NewNumber::Literal),
    ]
}

fn model_mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        10 => (any::<Index>(), new_number()).prop_map(|(i, n)| Mutation::Number(i, n)),
        1 => any::<Index>().prop_map(Mutation::DeleteLine),
        1 => any::<Index>().prop_map(Mutation::DuplicateLine),
        1 => (any::<Index>(), any::<Index>()).prop_map(|(a, b)| Mutation::SwapTables(a, b)),
        1 => (any::<Index>(), proptest::sample::select(JUNK)).prop_map(|(i, j)| Mutation::JunkKey(i, j)),
        1 => any::<Index>().prop_map(Mutation::Truncate),
        1 => (any::<Index>(), any::<bool>()).prop_map(|(i, b)| Mutation::ArrayLength(i, b)),
        2 => proptest::sample::select(METHODS).prop_map(Mutation::Method),
    ]
}

fn at2_mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        2 => (any::<bool>(), proptest::sample::select(HEADER_VALUES))
            .prop_map(|(n, v)| Mutation::At2Header(n, v)),
        1 => any::<Index>().prop_map(Mutation::At2Truncate),
        2 => (any::<Index>(), proptest::sample::select(TOKENS)).prop_map(|(i, t)| Mutation::At2Token(i, t)),
        1 => (any::<Index>(), any::<bool>()).prop_map(|(i, d)| Mutation::At2Line(i, d)),
    ]
}

/// One fuzz input: a seed and the mutations applied to it, in order.
#[derive(Clone, Debug)]
pub struct Input {
    pub seed: usize,
    pub mutations: Vec<Mutation>,
}

/// Input `case` of the run seeded by `base`: drawn from its own generator, so that any input
/// can be made again alone.
pub fn input(base: u64, case: u64, seeds: &[Seed]) -> Input {
    let mut bytes = [0u8; 32];
    bytes[..8].copy_from_slice(&base.to_le_bytes());
    bytes[8..16].copy_from_slice(&case.to_le_bytes());
    let rng = TestRng::from_seed(RngAlgorithm::ChaCha, &bytes);
    let mut runner = TestRunner::new_with_rng(Config::default(), rng);
    let seed = (0..seeds.len()).new_tree(&mut runner).unwrap().current();
    let record = seeds[seed].at2.is_some();
    let one = if record {
        prop_oneof![1 => model_mutation(), 3 => at2_mutation()].boxed()
    } else {
        model_mutation().boxed()
    };
    let mutations = proptest::collection::vec(one, 1..=3)
        .new_tree(&mut runner)
        .unwrap()
        .current();
    Input { seed, mutations }
}

/// The model text and record text of `input`.
pub fn apply(input: &Input, seeds: &[Seed]) -> (String, Option<String>) {
    let s = &seeds[input.seed];
    let mut model = s.model.clone();
    let mut at2 = s.at2.clone();
    for m in &input.mutations {
        match m {
            Mutation::At2Header(..)
            | Mutation::At2Truncate(_)
            | Mutation::At2Token(..)
            | Mutation::At2Line(..) => {
                if let Some(a) = at2.as_mut() {
                    *a = crate::edits::at2(a, m);
                }
            }
            _ => model = crate::edits::model(&model, m),
        }
    }
    (model, at2)
}
