//! No import loops between the modules of any crate: within each crate, the modules that
//! share a parent form a graph (an edge when a file of one names the other through a
//! `crate::` or `super::` path), and that graph must have no cycle. A module naming its own
//! parent or child is structure, not an edge; test modules (`#[cfg(test)] mod …`),
//! comments and string literals are not read.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// A module path inside a crate (`[]` is the crate root).
type ModPath = Vec<String>;

/// The module path of a source file below `src` (`a/mod.rs` and `a.rs` are `a`).
fn module_of(src: &Path, file: &Path) -> ModPath {
    let rel = file.strip_prefix(src).unwrap();
    let mut parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    let last = parts.pop().unwrap();
    let stem = last.trim_end_matches(".rs");
    let root = parts.is_empty() && matches!(stem, "lib" | "main");
    if stem != "mod" && !root {
        parts.push(stem.to_string());
    }
    parts
}

/// Every `.rs` file below `dir` except separate binaries (`src/bin`).
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() && p.file_name().is_some_and(|n| n != "bin") {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// `text` with comments, string and character literals blanked out (lifetimes kept).
fn code_only(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = String::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let rest = &text[i..];
        let skip = if rest.starts_with("//") {
            rest.find('\n').unwrap_or(rest.len())
        } else if rest.starts_with("/*") {
            rest.find("*/").map_or(rest.len(), |e| e + 2)
        } else if let Some(n) = raw_string_len(rest) {
            n
        } else if rest.starts_with('"') {
            quoted_len(rest, '"')
        } else if rest.starts_with('\'') && !is_lifetime(rest) {
            quoted_len(rest, '\'')
        } else {
            0
        };
        if skip > 0 {
            out.push(' ');
            i += skip;
        } else {
            let c = rest.chars().next().unwrap();
            out.push(c);
            i += c.len_utf8();
        }
    }
    out
}

/// Length of a raw string literal (`r"…"`, `r#"…"#`) at the start of `s`.
fn raw_string_len(s: &str) -> Option<usize> {
    let body = s.strip_prefix('r').or_else(|| s.strip_prefix("br"))?;
    let hashes = body.len() - body.trim_start_matches('#').len();
    let open = &body[hashes..];
    if !open.starts_with('"') {
        return None;
    }
    let close = format!("\"{}", "#".repeat(hashes));
    let end = open[1..].find(&close)? + 1 + close.len();
    Some(s.len() - open.len() + end)
}

/// Length of a literal quoted by `q` at the start of `s` (backslash escapes).
fn quoted_len(s: &str, q: char) -> usize {
    let mut escaped = false;
    for (i, c) in s.char_indices().skip(1) {
        match (escaped, c) {
            (false, '\\') => escaped = true,
            (false, c) if c == q => return i + 1,
            _ => escaped = false,
        }
    }
    s.len()
}

/// Whether the `'` at the start of `s` opens a lifetime or label rather than a character.
fn is_lifetime(s: &str) -> bool {
    let mut it = s.chars().skip(1);
    let first = it.next();
    first.is_some_and(|c| c.is_alphabetic() || c == '_') && it.next() != Some('\'')
}

/// `code` without the test modules declared inline (`#[cfg(test)] mod name { … }`), and the
/// names of those declared as files (`#[cfg(test)] mod name;`).
fn without_tests(code: &str) -> (String, Vec<String>) {
    let mut out = String::new();
    let mut files = Vec::new();
    let mut rest = code;
    while let Some(at) = rest.find("#[cfg(test)]") {
        out.push_str(&rest[..at]);
        let after = rest[at + 12..].trim_start();
        let Some(decl) = after.strip_prefix("mod ") else {
            out.push_str("#[cfg(test)]");
            rest = &rest[at + 12..];
            continue;
        };
        let name_end = decl
            .find(|c: char| !(c.is_alphanumeric() || c == '_'))
            .unwrap();
        let tail = decl[name_end..].trim_start();
        if let Some(t) = tail.strip_prefix(';') {
            files.push(decl[..name_end].to_string());
            rest = t;
        } else {
            rest = &tail[block_len(tail)..];
        }
    }
    out.push_str(rest);
    (out, files)
}

/// Length of the brace block at the start of `s`.
fn block_len(s: &str) -> usize {
    let mut depth = 0;
    for (i, c) in s.char_indices() {
        match c {
            '{' => depth += 1,
            '}' if depth == 1 => return i + 1,
            '}' => depth -= 1,
            _ => {}
        }
    }
    s.len()
}

/// The paths named after `crate::` or `super::` in `code`, resolved against module `here`
/// (grouped imports expanded).
fn references(code: &str, here: &ModPath) -> Vec<ModPath> {
    let mut found = Vec::new();
    let bytes = code.as_bytes();
    for start in 0..code.len() {
        let boundary = start == 0
            || !(bytes[start - 1].is_ascii_alphanumeric()
                || bytes[start - 1] == b'_'
                || bytes[start - 1] == b':');
        if !boundary {
            continue;
        }
        let rest = &code[start..];
        let (base, tail) = if let Some(t) = rest.strip_prefix("crate::") {
            (Vec::new(), t)
        } else if rest.starts_with("super::") {
            let mut base = here.clone();
            let mut t = rest;
            while let Some(next) = t.strip_prefix("super::") {
                base.pop();
                t = next;
            }
            (base, t)
        } else {
            continue;
        };
        expand(&base, tail, &mut found);
    }
    found
}

/// Paths of the use tree at the start of `s` below `base` (`a::b`, `a::{b, c::d}`, `{a, b}`).
fn expand(base: &ModPath, s: &str, out: &mut Vec<ModPath>) {
    let s = s.trim_start();
    if let Some(group) = s.strip_prefix('{') {
        let inner = &group[..block_len(s) - 2];
        for item in split_top(inner) {
            expand(base, item, out);
        }
        return;
    }
    let end = s
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    if end == 0 {
        out.push(base.clone());
        return;
    }
    let mut path = base.clone();
    path.push(s[..end].to_string());
    match s[end..].strip_prefix("::") {
        Some(t) => expand(&path, t, out),
        None => out.push(path),
    }
}

/// The comma-separated items of a use group, nested groups kept whole.
fn split_top(s: &str) -> Vec<&str> {
    let (mut items, mut depth, mut from) = (Vec::new(), 0, 0);
    for (i, c) in s.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                items.push(&s[from..i]);
                from = i + 1;
            }
            _ => {}
        }
    }
    items.push(&s[from..]);
    items.into_iter().filter(|t| !t.trim().is_empty()).collect()
}

/// Edges between sibling modules of the crate whose sources are in `src`.
fn module_edges(src: &Path) -> BTreeMap<ModPath, BTreeSet<ModPath>> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let mut code = BTreeMap::new();
    let mut test_modules = BTreeSet::new();
    for f in &files {
        let here = module_of(src, f);
        let (text, tests) = without_tests(&code_only(&std::fs::read_to_string(f).unwrap()));
        for t in tests {
            test_modules.insert([here.clone(), vec![t]].concat());
        }
        code.insert(here, text);
    }
    code.retain(|m, _| !test_modules.iter().any(|t| m.starts_with(t)));
    let known: BTreeSet<ModPath> = code.keys().cloned().collect();
    let mut edges: BTreeMap<ModPath, BTreeSet<ModPath>> = BTreeMap::new();
    for (here, text) in &code {
        for r in references(text, here) {
            let target = (0..=r.len())
                .rev()
                .map(|n| r[..n].to_vec())
                .find(|p| known.contains(p))
                .unwrap_or_default();
            let common = here.iter().zip(&target).take_while(|(a, b)| a == b).count();
            if common < here.len() && common < target.len() {
                let from = here[..=common].to_vec();
                let to = target[..=common].to_vec();
                edges.entry(from).or_default().insert(to);
            }
        }
    }
    edges
}

/// One cycle of the graph, if it has any (module paths joined by `::`).
fn find_cycle(edges: &BTreeMap<ModPath, BTreeSet<ModPath>>) -> Option<Vec<String>> {
    fn visit(
        n: &ModPath,
        edges: &BTreeMap<ModPath, BTreeSet<ModPath>>,
        stack: &mut Vec<ModPath>,
        done: &mut BTreeSet<ModPath>,
    ) -> Option<Vec<String>> {
        if let Some(at) = stack.iter().position(|m| m == n) {
            let mut cycle: Vec<String> = stack[at..].iter().map(|m| m.join("::")).collect();
            cycle.push(n.join("::"));
            return Some(cycle);
        }
        if !done.insert(n.clone()) {
            return None;
        }
        stack.push(n.clone());
        for next in edges.get(n).into_iter().flatten() {
            if let Some(c) = visit(next, edges, stack, done) {
                return Some(c);
            }
        }
        stack.pop();
        None
    }
    let mut done = BTreeSet::new();
    edges
        .keys()
        .find_map(|n| visit(n, edges, &mut Vec::new(), &mut done))
}

/// Writes `files` (path below `src`, text) into a fresh folder and returns its `src`.
fn synthetic(name: &str, files: &[(&str, &str)]) -> PathBuf {
    let root = std::env::temp_dir().join(format!("stride-modgraph-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    for (path, text) in files {
        let p = root.join("src").join(path);
        std::fs::create_dir_all(p.parent().unwrap()).unwrap();
        std::fs::write(p, text).unwrap();
    }
    root.join("src")
}

#[test]
fn the_check_finds_loops_and_ignores_tests_comments_and_structure() {
    let lib = "pub mod a;\npub mod b;\npub mod p;\n";
    let looped = synthetic(
        "loop",
        &[
            ("lib.rs", lib),
            ("a.rs", "use crate::{b::X, p};\npub struct Y;\n"),
            ("b.rs", "pub struct X;\nfn f(_: super::a::Y) {}\n"),
            ("p/mod.rs", "pub mod x;\npub mod y;\npub struct Z;\n"),
            ("p/x.rs", "use super::Z;\n"),
            ("p/y.rs", "use super::x;\n"),
        ],
    );
    assert_eq!(cycles(&module_edges(&looped)), ["a → b → a"]);
    let nested = synthetic(
        "nested",
        &[
            ("lib.rs", lib),
            ("a.rs", ""),
            ("b.rs", ""),
            ("p/mod.rs", "pub mod x;\npub mod y;\n"),
            ("p/x.rs", "use super::y::W;\npub struct V;\n"),
            (
                "p/y.rs",
                "pub struct W;\nconst _: Option<crate::p::x::V> = None;\n",
            ),
        ],
    );
    assert_eq!(
        find_cycle(&module_edges(&nested)).unwrap(),
        ["p::x", "p::y", "p::x"]
    );
    let clean = synthetic(
        "clean",
        &[
            ("lib.rs", lib),
            ("a.rs", "use crate::b::X;\n/// not [`crate::p`]\nconst S: &str = \"crate::p::Z\";\n"),
            ("b.rs", "pub struct X;\n#[cfg(test)]\nmod tests {\n    use crate::a::*;\n    fn f() { let _ = '{'; }\n}\n#[cfg(test)]\nmod more;\n"),
            ("b/more.rs", "use crate::a::S;\n"),
            ("p/mod.rs", "pub mod x;\npub struct Z;\n"),
            ("p/x.rs", "use super::Z;\nuse crate::a;\n"),
        ],
    );
    let edges = module_edges(&clean);
    assert!(cycles(&edges).is_empty(), "{edges:?}");
    assert_eq!(edges.len(), 2, "a → b and p → a: {edges:?}");
    for src in [looped, nested, clean] {
        std::fs::remove_dir_all(src.parent().unwrap()).unwrap();
    }
}

/// One cycle among the children of each module that has a cycle (module paths joined by
/// `::`), parents in path order.
fn cycles(edges: &BTreeMap<ModPath, BTreeSet<ModPath>>) -> Vec<String> {
    let mut by_parent: BTreeMap<ModPath, BTreeMap<ModPath, BTreeSet<ModPath>>> = BTreeMap::new();
    for (from, to) in edges {
        let parent = from[..from.len() - 1].to_vec();
        by_parent
            .entry(parent)
            .or_default()
            .insert(from.clone(), to.clone());
    }
    by_parent
        .values()
        .filter_map(find_cycle)
        .map(|c| c.join(" → "))
        .collect()
}

#[test]
fn no_crate_has_an_import_loop() {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(&crates)
        .unwrap()
        .map(|e| e.unwrap().path().join("src"))
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    assert!(dirs.len() > 5, "crates found: {dirs:?}");
    let loops: Vec<String> = dirs
        .iter()
        .filter_map(|src| {
            let name = src
                .parent()
                .unwrap()
                .file_name()
                .unwrap()
                .to_string_lossy()
                .into_owned();
            let found: Vec<String> = cycles(&module_edges(src))
                .into_iter()
                .map(|c| format!("crates/{name}: {c}"))
                .collect();
            (!found.is_empty()).then(|| found.join("\n"))
        })
        .collect();
    assert!(loops.is_empty(), "import loops:\n{}", loops.join("\n"));
}
