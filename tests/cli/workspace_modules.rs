//! No import cycles between the modules of a crate: module A using an item
//! of module B and B using one of A (directly or around a longer loop)
//! ties them into one unit that cannot be read, tested or moved apart.
//!
//! Every `.rs` file of a crate's `src` is a module (`mod.rs` and `lib.rs`
//! name their directory); `crate::`, `super::` and `self::` paths in its
//! code (not in its `#[cfg(test)]` module or its comments) are its imports,
//! resolved to the deepest module that exists. A module and its own
//! submodules are one unit (a parent declares and re-exports its children),
//! so only imports between modules where neither contains the other count.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

type Module = Vec<String>;

fn modules(src: &Path) -> BTreeMap<Module, PathBuf> {
    let mut out = BTreeMap::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let rel = path.strip_prefix(src).unwrap().with_extension("");
                let mut m: Module = rel
                    .components()
                    .map(|c| c.as_os_str().to_string_lossy().into_owned())
                    .collect();
                if matches!(m.last().map(String::as_str), Some("mod" | "lib" | "main")) {
                    m.pop();
                }
                out.insert(m, path);
            }
        }
    }
    out
}

/// The code of a file without comments and without its test module.
fn code(text: &str) -> String {
    let text = text.split("#[cfg(test)]").next().unwrap_or("");
    text.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// Every `crate::a::b`, `super::a` or `self::a` path, with `use` groups
/// (`crate::a::{b, c::d}`) expanded.
fn paths(code: &str) -> Vec<String> {
    let mut out = Vec::new();
    for start in ["crate::", "super::", "self::"] {
        let mut from = 0;
        while let Some(i) = code[from..].find(start) {
            let at = from + i;
            from = at + start.len();
            let before = code[..at].chars().last();
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
                continue;
            }
            // The path to its end, a use group spread over lines included.
            let tail = &code[at..];
            let tail = &tail[..tail.find(';').unwrap_or(tail.len()).min(4000)];
            let squeezed: String = tail.chars().filter(|c| !c.is_whitespace()).collect();
            let rest = squeezed.as_str();
            let end = rest
                .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':' || c == '{'))
                .unwrap_or(rest.len());
            let head = &rest[..end];
            match head.find('{') {
                None => out.push(head.to_string()),
                Some(brace) => {
                    // A use group: each item after the brace, to the first
                    // `,` or `}` at depth one (nested groups give their head).
                    let prefix = &rest[..brace];
                    let mut depth = 0;
                    let mut item = String::new();
                    for c in rest[brace..].chars() {
                        match c {
                            '{' => {
                                depth += 1;
                                if depth == 1 {
                                    continue;
                                }
                            }
                            '}' => {
                                depth -= 1;
                                if depth == 0 {
                                    out.push(format!("{prefix}{item}"));
                                    break;
                                }
                            }
                            ',' if depth == 1 => {
                                out.push(format!("{prefix}{item}"));
                                item.clear();
                                continue;
                            }
                            _ => {}
                        }
                        if depth >= 1 {
                            item.push(c);
                        }
                    }
                }
            }
        }
    }
    out
}

/// The deepest existing module a path from `module` names.
fn resolve(module: &Module, path: &str, all: &BTreeMap<Module, PathBuf>) -> Module {
    let mut segs = path.split("::").filter(|s| !s.is_empty()).peekable();
    let mut base: Module = match segs.next() {
        Some("crate") => Vec::new(),
        Some("self") => module.clone(),
        _ => {
            let mut b = module.clone();
            b.pop();
            while segs.peek() == Some(&"super") {
                segs.next();
                b.pop();
            }
            b
        }
    };
    for s in segs {
        let s = s.split(['{', '*']).next().unwrap_or("");
        let mut next = base.clone();
        next.push(s.to_string());
        if all.contains_key(&next) {
            base = next;
        } else {
            break;
        }
    }
    base
}

fn contains(outer: &Module, inner: &Module) -> bool {
    inner.starts_with(outer)
}

/// The cycles among a crate's modules, each as its modules' names.
fn cycles(src: &Path) -> Vec<Vec<String>> {
    let all = modules(src);
    let mut edges: BTreeMap<&Module, BTreeSet<Module>> = BTreeMap::new();
    for (m, file) in &all {
        let text = code(&std::fs::read_to_string(file).unwrap());
        let targets = edges.entry(m).or_default();
        for p in paths(&text) {
            let t = resolve(m, &p, &all);
            if !contains(&t, m) && !contains(m, &t) {
                targets.insert(t);
            }
        }
    }
    // Strongly connected components (Tarjan), those of two or more modules.
    struct Search<'a> {
        edges: &'a BTreeMap<&'a Module, BTreeSet<Module>>,
        index: BTreeMap<Module, usize>,
        low: BTreeMap<Module, usize>,
        stack: Vec<Module>,
        found: Vec<Vec<String>>,
    }
    fn visit(s: &mut Search<'_>, v: &Module) {
        let i = s.index.len();
        s.index.insert(v.clone(), i);
        s.low.insert(v.clone(), i);
        s.stack.push(v.clone());
        for w in s.edges.get(v).cloned().unwrap_or_default() {
            if !s.index.contains_key(&w) {
                visit(s, &w);
                let lw = s.low[&w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(lw);
            } else if s.stack.contains(&w) {
                let iw = s.index[&w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(iw);
            }
        }
        if s.low[v] == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                let done = &w == v;
                component.push(w.join("::"));
                if done {
                    break;
                }
            }
            if component.len() > 1 {
                s.found.push(component);
            }
        }
    }
    let mut s = Search {
        edges: &edges,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        found: Vec::new(),
    };
    for m in all.keys() {
        if !s.index.contains_key(m) {
            visit(&mut s, m);
        }
    }
    s.found
}

fn crates() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut out: Vec<PathBuf> = std::fs::read_dir(&root)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.join("src").is_dir())
        .collect();
    out.sort();
    out
}

#[test]
fn no_crate_has_an_import_cycle() {
    let crates = crates();
    assert!(crates.len() >= 7, "{crates:?}");
    for c in crates {
        let found = cycles(&c.join("src"));
        assert!(found.is_empty(), "{}: import cycles {found:?}", c.display());
    }
}

/// The check finds a cycle when there is one: two modules of a scratch
/// crate that use each other, and one around three modules.
#[test]
fn the_check_finds_cycles() {
    let dir = std::env::temp_dir().join(format!("floe-cycles-{}", std::process::id()));
    let src = dir.join("src");
    std::fs::create_dir_all(src.join("d")).unwrap();
    let write = |name: &str, text: &str| std::fs::write(src.join(name), text).unwrap();
    write("lib.rs", "mod a;\nmod b;\nmod c;\nmod d;\n");
    write("a.rs", "use crate::b::{B, X};\npub struct A;\n");
    write("b.rs", "use super::a::A;\npub struct B;\n");
    write("c.rs", "use crate::d::e::E;\n// use crate::a::A;\n");
    write("d/mod.rs", "pub mod e;\npub use e::E;\n");
    write(
        "d/e.rs",
        "use crate::{c, x};\npub struct E;\n#[cfg(test)]\nmod t { use crate::a; }\n",
    );
    let mut found = cycles(&src);
    std::fs::remove_dir_all(&dir).unwrap();
    found.iter_mut().for_each(|c| c.sort());
    found.sort();
    assert_eq!(
        found,
        vec![
            vec!["a".to_string(), "b".to_string()],
            vec!["c".to_string(), "d::e".to_string()]
        ]
    );
}
