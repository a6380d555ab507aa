//! The shape of the code (docs/architecture.md): no source file over 800 lines, no function
//! over 120 lines, no import circle between the files of the crates, and the engine crate
//! (`crates/core`) free of the front ends' crates.
//!
//! A file depends on another when it names a module path (`use`, or an inline `crate::…`,
//! `super::…` path) whose longest prefix is that file's module. Re-exports (`pub use`) are a
//! module's facade, not a use, and `#[cfg(test)]` modules are left out. The crates' modules
//! share one namespace (the top package re-exports the layers below it by their module names,
//! so `crate::scene` there is `deckspin_core::scene`); the Python binding's files are checked
//! for size only.
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const MAX_FILE_LINES: usize = 800;
const MAX_FN_LINES: usize = 120;

/// The source trees of the layers, the top package's last (its `src`).
const TREES: [&str; 3] = ["crates/core/src", "crates/studies/src", "src"];

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

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

/// Every file of the layers' source trees.
fn sources() -> Vec<PathBuf> {
    let mut out = Vec::new();
    for t in TREES {
        walk(&root().join(t), &mut out);
    }
    out.sort();
    out
}

/// A path relative to the repository.
fn rel(path: &Path) -> String {
    path.strip_prefix(root())
        .unwrap_or(path)
        .display()
        .to_string()
}

/// The module path of a file in its crate: crates/core/src/scene/forces.rs → ["scene",
/// "forces"]; lib.rs and main.rs are the roots.
fn module_of(path: &Path) -> Vec<String> {
    let src = (TREES.iter())
        .map(|t| root().join(t))
        .find(|t| path.starts_with(t))
        .unwrap();
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
    let mut files = sources();
    walk(&root().join("crates/python/src"), &mut files);
    for path in files {
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
        .filter(|p| !p.ends_with("main.rs") && !p.ends_with("lib.rs"))
        .map(|p| (module_of(p), p.clone()))
        .collect();
    let mut edges: BTreeMap<PathBuf, BTreeSet<PathBuf>> = BTreeMap::new();
    for path in files {
        let here = module_of(path);
        let code = without_tests(&code_only(&std::fs::read_to_string(path).unwrap()));
        for named in named_paths(&code) {
            let mut segs: Vec<&str> = named.split("::").collect();
            let mut base: Vec<String> = match segs.first() {
                Some(&"crate") | Some(&"deckspin") | Some(&"deckspin_core") => {
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
    // and across crates: the suite's runs name the engine's simulate
    let core = root().join("crates/core/src");
    assert!(edges.iter().any(|(f, t)| {
        module_of(f).first().is_some_and(|m| m == "suite")
            && t.iter()
                .any(|p| p.starts_with(&core) && module_of(p) == ["simulate"])
    }));
}

/// The names of the crates `cargo tree` lists for `package` (normal and build dependencies).
fn dependency_tree(package: &str) -> BTreeSet<String> {
    let out = std::process::Command::new(env!("CARGO"))
        .args([
            "tree",
            "--offline",
            "-e",
            "normal,build",
            "--prefix",
            "none",
            "-p",
            package,
        ])
        .current_dir(root())
        .output()
        .expect("cargo runs");
    assert!(
        out.status.success(),
        "cargo tree: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    (String::from_utf8_lossy(&out.stdout).lines())
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .collect()
}

/// The engine crate (scene, contact LCPs, Lemke, integrators, hysteresis, excitation, model
/// files, modes, the run API and its outputs) and the studies' crate over it hold none of the
/// front ends' crates, and the engine documents every public item.
#[test]
fn the_engine_and_studies_crates_hold_no_front_end() {
    let tree = dependency_tree("deckspin-core");
    let studies = dependency_tree("deckspin-studies");
    const FRONT_ENDS: [&str; 8] = [
        "clap",
        "indicatif",
        "ratatui",
        "crossterm",
        "notify",
        "notify-debouncer-full",
        "signal-hook",
        "pyo3",
    ];
    let held: Vec<&&str> = FRONT_ENDS.iter().filter(|c| tree.contains(**c)).collect();
    assert!(held.is_empty(), "deckspin-core depends on {held:?}");
    let held: Vec<&&str> = FRONT_ENDS
        .iter()
        .filter(|c| studies.contains(**c))
        .collect();
    assert!(held.is_empty(), "deckspin-studies depends on {held:?}");
    assert!(studies.contains("rayon") && studies.contains("deckspin-core"));
    // the check sees the tree (it can fail): the engine's own crates are in it, and the top
    // package's tree holds the front ends
    assert!(tree.contains("nalgebra") && tree.contains("deckspin-core"));
    let top = dependency_tree("deckspin");
    assert!(top.contains("clap") && top.contains("ratatui") && top.contains("deckspin-core"));
    // missing_docs over the whole crate (a warning the lints in CI make an error)
    let lib = std::fs::read_to_string(root().join("crates/core/src/lib.rs")).unwrap();
    assert!(lib.contains("#![warn(missing_docs)]"));
}
