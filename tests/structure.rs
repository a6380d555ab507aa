//! The shape of the code (docs/architecture.md): no file in `src/` over 800 lines, no function
//! over 120 lines, no import circle between the files of `src/`.
//!
//! A file depends on another when it names a module path (`use`, or an inline `crate::…`,
//! `super::…` path) whose longest prefix is that file's module. Re-exports (`pub use`) are a
//! module's facade, not a use, and `#[cfg(test)]` modules are left out.
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const MAX_FILE_LINES: usize = 800;
const MAX_FN_LINES: usize = 120;

fn sources() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    let mut out = Vec::new();
    walk(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src"), &mut out);
    out.sort();
    out
}

/// The module path of a file: src/scene/forces.rs → ["scene", "forces"]; lib.rs and main.rs
/// are the roots.
/// A path relative to the repository.
fn rel(path: &Path) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    path.strip_prefix(root)
        .unwrap_or(path)
        .display()
        .to_string()
}

fn module_of(path: &Path) -> Vec<String> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let rel = path.strip_prefix(&src).unwrap();
    let mut parts: Vec<String> = rel
        .iter()
        .map(|s| s.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    if matches!(
        parts.last().map(String::as_str),
        Some("mod" | "lib" | "main")
    ) {
        parts.pop();
    }
    parts
}

/// The code without comments, string and char literals (blanked, lines kept).
fn code_only(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let b: Vec<char> = text.chars().collect();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c == '/' && b.get(i + 1) == Some(&'/') {
            while i < b.len() && b[i] != '\n' {
                i += 1;
            }
        } else if c == '"' || (c == 'r' && b.get(i + 1) == Some(&'#')) {
            // (raw) string: blank to its end
            let mut hashes = 0;
            if c == 'r' {
                i += 1;
                while b.get(i) == Some(&'#') {
                    hashes += 1;
                    i += 1;
                }
            }
            i += 1;
            out.push('"');
            while i < b.len() {
                if hashes == 0 && b[i] == '\\' {
                    i += 2;
                    continue;
                }
                if b[i] == '"' && (0..hashes).all(|k| b.get(i + 1 + k) == Some(&'#')) {
                    i += 1 + hashes;
                    break;
                }
                if b[i] == '\n' {
                    out.push('\n');
                }
                i += 1;
            }
            out.push('"');
        } else if c == '\'' && b.get(i + 2) == Some(&'\'') {
            out.push_str("' '");
            i += 3;
        } else if c == '\'' && b.get(i + 1) == Some(&'\\') {
            let end = (i + 2..b.len()).find(|&k| b[k] == '\'').unwrap_or(i + 2);
            out.push_str("' '");
            i = end + 1;
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// Index of the `}` closing the `{` at `open`.
fn closing(code: &[char], open: usize) -> usize {
    let mut depth = 0;
    for (k, &c) in code.iter().enumerate().skip(open) {
        if c == '{' {
            depth += 1;
        } else if c == '}' {
            depth -= 1;
            if depth == 0 {
                return k;
            }
        }
    }
    code.len() - 1
}

/// `code` with its `#[cfg(test)]` items removed.
fn without_tests(code: &str) -> String {
    let mut code: Vec<char> = code.chars().collect();
    let pat: Vec<char> = "#[cfg(test)]".chars().collect();
    let mut i = 0;
    while i + pat.len() <= code.len() {
        if code[i..i + pat.len()] == pat[..]
            && let Some(open) = (i..code.len()).find(|&k| code[k] == '{' || code[k] == ';')
        {
            let end = if code[open] == '{' {
                closing(&code, open)
            } else {
                open
            };
            for c in &mut code[i..=end] {
                if *c != '\n' {
                    *c = ' ';
                }
            }
        }
        i += 1;
    }
    code.into_iter().collect()
}

/// Expands `a::{b, c::{d, e}}` into its paths.
fn expand(spec: &str) -> Vec<String> {
    let spec: String = spec.split_whitespace().collect();
    let Some(open) = spec.find('{') else {
        return vec![spec];
    };
    let prefix = &spec[..open];
    let inner = &spec[open + 1..spec.rfind('}').unwrap_or(spec.len())];
    let mut parts = Vec::new();
    let (mut depth, mut start) = (0, 0);
    for (k, c) in inner.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&inner[start..k]);
                start = k + 1;
            }
            _ => {}
        }
    }
    parts.push(&inner[start..]);
    parts
        .into_iter()
        .filter(|p| !p.is_empty())
        .flat_map(|p| expand(p).into_iter().map(move |x| format!("{prefix}{x}")))
        .collect()
}

/// The module paths a file names: its (non-pub) `use` items, and inline `crate::` and
/// `super::` paths.
fn named_paths(code: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(k) = rest.find("use ") {
        let before = &rest[..k];
        let is_pub = before.trim_end().ends_with(')') || before.trim_end().ends_with("pub");
        let word_start = k == 0 || !rest[..k].ends_with(|c: char| c.is_alphanumeric() || c == '_');
        let after = &rest[k + 4..];
        let end = after.find(';').unwrap_or(after.len());
        if word_start && !is_pub {
            out.extend(expand(&after[..end]));
        }
        rest = &after[end.min(after.len())..];
    }
    for prefix in ["crate::", "super::"] {
        let mut rest = code;
        while let Some(k) = rest.find(prefix) {
            let tail = &rest[k..];
            let len = tail
                .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
                .unwrap_or(tail.len());
            out.push(tail[..len].trim_end_matches(':').to_string());
            rest = &tail[len.max(1)..];
        }
    }
    out
}

#[test]
fn files_and_functions_are_small() {
    let mut long = Vec::new();
    for path in sources() {
        let text = std::fs::read_to_string(&path).unwrap();
        let lines = text.lines().count();
        if lines > MAX_FILE_LINES {
            long.push(format!("{}: {lines} lines", rel(&path)));
        }
        let code: Vec<char> = code_only(&text).chars().collect();
        let s: String = code.iter().collect();
        let line_at = |k: usize| code[..k].iter().filter(|&&c| c == '\n').count();
        let mut from = 0;
        while let Some(k) = s[from..].find("fn ").map(|k| k + from) {
            from = k + 3;
            let word_start = k == 0 || !s[..k].ends_with(|c: char| c.is_alphanumeric() || c == '_');
            if !word_start {
                continue;
            }
            // the body: the first `{` before any `;` at bracket depth 0
            let (mut par, mut open) = (0i32, None);
            for (j, &c) in code.iter().enumerate().skip(k) {
                match c {
                    '(' | '[' | '<' => par += 1,
                    ')' | ']' | '>' => par -= 1,
                    '{' if par <= 0 => {
                        open = Some(j);
                        break;
                    }
                    ';' if par <= 0 => break,
                    _ => {}
                }
            }
            if let Some(open) = open {
                let n = line_at(closing(&code, open)) - line_at(k) + 1;
                if n > MAX_FN_LINES {
                    let name: String = s[k + 3..]
                        .chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_')
                        .collect();
                    long.push(format!(
                        "{}:{}: fn {name}: {n} lines",
                        rel(&path),
                        line_at(k) + 1
                    ));
                }
            }
        }
    }
    assert!(long.is_empty(), "too long:\n{}", long.join("\n"));
}

/// Which source file imports which (`use` and paths naming `crate::`, `deckspin::`, `super::`,
/// `self::` or a child module), each file's edges to the module files it names.
fn import_edges(files: &[PathBuf]) -> BTreeMap<PathBuf, BTreeSet<PathBuf>> {
    let modules: BTreeMap<Vec<String>, PathBuf> = files
        .iter()
        .filter(|p| !p.ends_with("main.rs"))
        .map(|p| (module_of(p), p.clone()))
        .collect();
    let mut edges: BTreeMap<PathBuf, BTreeSet<PathBuf>> = BTreeMap::new();
    for path in files {
        let here = module_of(path);
        let code = without_tests(&code_only(&std::fs::read_to_string(path).unwrap()));
        for named in named_paths(&code) {
            let mut segs: Vec<&str> = named.split("::").collect();
            let mut base: Vec<String> = match segs.first() {
                Some(&"crate") | Some(&"deckspin") => {
                    segs.remove(0);
                    Vec::new()
                }
                Some(&"super") => {
                    let mut b = here.clone();
                    // a file's own module is `here`; super is its parent (for mod.rs files too)
                    while segs.first() == Some(&"super") {
                        segs.remove(0);
                        b.pop();
                    }
                    b
                }
                Some(&"self") => {
                    segs.remove(0);
                    here.clone()
                }
                Some(first)
                    if modules.contains_key(&[here.clone(), vec![first.to_string()]].concat()) =>
                {
                    here.clone()
                }
                _ => continue,
            };
            // the longest prefix that is a module file
            let mut target = modules.get(&base).cloned();
            for s in segs {
                base.push(s.to_string());
                match modules.get(&base) {
                    Some(p) => target = Some(p.clone()),
                    None => break,
                }
            }
            if let Some(t) = target
                && &t != path
            {
                edges.entry(path.clone()).or_default().insert(t);
            }
        }
    }
    edges
}

#[test]
fn no_import_circle_between_files() {
    let files = sources();
    let edges = import_edges(&files);
    // a file that reaches itself through its dependencies is on a circle
    let mut circles = Vec::new();
    for start in edges.keys() {
        let mut stack = vec![(start.clone(), vec![start.clone()])];
        let mut seen = BTreeSet::new();
        while let Some((node, trail)) = stack.pop() {
            for next in edges.get(&node).into_iter().flatten() {
                if next == start {
                    let names: Vec<String> = trail.iter().map(|p| rel(p)).collect();
                    circles.push(names.join(" -> "));
                } else if seen.insert(next.clone()) {
                    let mut t = trail.clone();
                    t.push(next.clone());
                    stack.push((next.clone(), t));
                }
            }
        }
    }
    assert!(
        circles.is_empty(),
        "import circles:\n{}",
        circles.join("\n")
    );
    // the check sees real dependencies (it can fail): the driver uses the engine
    let driver = files
        .iter()
        .find(|p| p.ends_with("event_driven/driver.rs"))
        .unwrap();
    assert!(
        edges[driver]
            .iter()
            .any(|p| p.ends_with("event_driven/engine.rs"))
    );
}

/// The engine (what a core crate would hold: scene, contact LCPs, Lemke, integrators,
/// hysteresis, excitation, model files, modes, the run API and its outputs) imports nothing
/// of the studies, the design answers or the front ends above it, and documents every public
/// item.
#[test]
fn the_engine_imports_nothing_of_the_layers_above_it() {
    const ENGINE: [&str; 18] = [
        "clock",
        "contact",
        "dopri",
        "event_driven",
        "excitation",
        "hysteresis",
        "input",
        "lemke",
        "linalg",
        "methods",
        "modal",
        "model",
        "output",
        "run",
        "scene",
        "simulate",
        "timestepping",
        "units",
    ];
    let files = sources();
    let edges = import_edges(&files);
    let top = |p: &Path| module_of(p).first().cloned().unwrap_or_default();
    let engine = |p: &Path| ENGINE.contains(&top(p).as_str());
    let mut up = Vec::new();
    for (from, tos) in edges.iter().filter(|(f, _)| engine(f)) {
        for to in tos.iter().filter(|t| !engine(t)) {
            up.push(format!("{} -> {}", rel(from), rel(to)));
        }
    }
    assert!(
        up.is_empty(),
        "the engine imports from above it:\n{}",
        up.join("\n")
    );
    // every engine module exists, documents every public item (`missing_docs`, a warning that
    // the lints in CI make an error), and the check sees edges upward into it (it can fail)
    for m in ENGINE {
        let root = (files.iter())
            .find(|p| module_of(p) == [m.to_string()])
            .unwrap_or_else(|| panic!("no module {m}"));
        let text = std::fs::read_to_string(root).unwrap();
        assert!(
            text.contains("#![warn(missing_docs)]"),
            "{}: no #![warn(missing_docs)]",
            rel(root)
        );
    }
    assert!(
        (edges.iter()).any(|(f, t)| top(f) == "suite" && t.iter().any(|p| top(p) == "simulate")),
        "the suite's import of simulate not seen"
    );
}
