//! No cycles between the crate's modules: read every file under `src/`, find the modules each
//! one names (`crate::a::b`, `super::c`, `use crate::{d, e}`) outside comments and tests, and
//! fail on any loop among them. A module may use its parent or its children freely (a parent
//! declares its children and re-exports them); a loop through siblings or cousins is a tangle
//! (two modules that each need the other should share a third that both can use).

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

type Module = Vec<String>;

/// Every module of `src/`, by path, with its source.
fn modules() -> BTreeMap<Module, String> {
    fn walk(dir: &Path, prefix: &[String], out: &mut BTreeMap<Module, String>) {
        for entry in std::fs::read_dir(dir).unwrap().flatten() {
            let path = entry.path();
            let name = path.file_stem().unwrap().to_string_lossy().into_owned();
            if path.is_dir() {
                walk(&path, &[prefix, &[name]].concat(), out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let module = if matches!(name.as_str(), "mod" | "lib" | "main") {
                    prefix.to_vec()
                } else {
                    [prefix, &[name]].concat()
                };
                out.insert(module, std::fs::read_to_string(&path).unwrap());
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src"), &[], &mut out);
    out
}

/// `source` without its tests and its comment lines.
fn code(source: &str) -> String {
    let source = source.split("#[cfg(test)]").next().unwrap_or("");
    source.lines().filter(|l| !l.trim_start().starts_with("//")).collect::<Vec<_>>().join("\n")
}

/// The paths `code` names from the crate's root or its parent: each as the segments after
/// `crate` or `super`, with whether it starts at `super`. A brace group is read one level deep.
fn paths(code: &str) -> Vec<(bool, Vec<String>)> {
    let ident = |s: &str| s.chars().take_while(|c| c.is_alphanumeric() || *c == '_').count();
    let mut out = Vec::new();
    for (start, from_super) in [("crate::", false), ("super::", true)] {
        let mut rest = code;
        while let Some(at) = rest.find(start) {
            let before = rest[..at].chars().last();
            rest = &rest[at + start.len()..];
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
                continue;
            }
            if let Some(group) = rest.strip_prefix('{') {
                let end = group.find('}').unwrap_or(group.len());
                for item in group[..end].split(',') {
                    let segments: Vec<String> = item.trim().split("::").map(|s| s[..ident(s)].to_string()).collect();
                    out.push((from_super, segments.into_iter().filter(|s| !s.is_empty()).collect()));
                }
                continue;
            }
            let mut segments = Vec::new();
            let mut tail = rest;
            loop {
                let n = ident(tail);
                if n == 0 {
                    break;
                }
                segments.push(tail[..n].to_string());
                match tail[n..].strip_prefix("::") {
                    Some(next) => tail = next,
                    None => break,
                }
            }
            out.push((from_super, segments));
        }
    }
    out
}

/// The modules each module uses, parents and children left out.
fn graph() -> BTreeMap<Module, BTreeSet<Module>> {
    let all = modules();
    let resolve = |path: Vec<String>| (1..=path.len()).rev().map(|n| path[..n].to_vec()).find(|m| all.contains_key(m));
    let mut graph = BTreeMap::new();
    for (module, source) in &all {
        // `super` from a/b.rs, or from a/b/mod.rs, is a.
        let parent: Module = module[..module.len().saturating_sub(1)].to_vec();
        let mut uses = BTreeSet::new();
        for (from_super, segments) in paths(&code(source)) {
            let base = if from_super { parent.clone() } else { Vec::new() };
            if let Some(target) = resolve([base, segments].concat()) {
                let related = target.starts_with(module) || module.starts_with(&target);
                if !related {
                    uses.insert(target);
                }
            }
        }
        graph.insert(module.clone(), uses);
    }
    graph
}

/// The loops of `graph`: its strongly connected parts of more than one module (Tarjan).
fn loops(graph: &BTreeMap<Module, BTreeSet<Module>>) -> Vec<Vec<Module>> {
    struct State<'a> {
        graph: &'a BTreeMap<Module, BTreeSet<Module>>,
        index: BTreeMap<&'a Module, (usize, usize)>,
        stack: Vec<&'a Module>,
        next: usize,
        found: Vec<Vec<Module>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a Module) {
        s.index.insert(v, (s.next, s.next));
        s.next += 1;
        s.stack.push(v);
        for w in s.graph.get(v).into_iter().flatten() {
            if !s.index.contains_key(w) {
                visit(s, w);
                let low = s.index[w].1.min(s.index[v].1);
                s.index.get_mut(v).unwrap().1 = low;
            } else if s.stack.contains(&w) {
                let low = s.index[w].0.min(s.index[v].1);
                s.index.get_mut(v).unwrap().1 = low;
            }
        }
        if s.index[v].0 == s.index[v].1 {
            let at = s.stack.iter().position(|m| *m == v).unwrap();
            let part: Vec<Module> = s.stack.drain(at..).cloned().collect();
            if part.len() > 1 {
                s.found.push(part);
            }
        }
    }
    let mut s = State { graph, index: BTreeMap::new(), stack: Vec::new(), next: 0, found: Vec::new() };
    for v in graph.keys() {
        if !s.index.contains_key(v) {
            visit(&mut s, v);
        }
    }
    s.found
}

#[test]
fn no_module_needs_another_that_needs_it_back() {
    let graph = graph();
    assert!(graph.len() > 50, "found only {} modules under src/", graph.len());
    let found: Vec<String> =
        loops(&graph).iter().map(|part| part.iter().map(|m| m.join("::")).collect::<Vec<_>>().join(" ⇄ ")).collect();
    assert!(found.is_empty(), "module cycles:\n{}", found.join("\n"));
}

#[test]
fn paths_are_read_from_code_and_loops_are_found() {
    let source = "use crate::a::b;\nuse super::{c, d::e};\n// crate::commented\nlet x = crate::f::g(1);";
    let found = paths(&code(source));
    let s = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    assert!(found.contains(&(false, s(&["a", "b"]))));
    assert!(found.contains(&(true, s(&["c"]))));
    assert!(found.contains(&(true, s(&["d", "e"]))));
    assert!(found.contains(&(false, s(&["f", "g"]))));
    assert!(!found.iter().any(|(_, p)| p.contains(&"commented".to_string())));
    let m = |v: &str| vec![v.to_string()];
    let mut g = BTreeMap::new();
    g.insert(m("a"), BTreeSet::from([m("b")]));
    g.insert(m("b"), BTreeSet::from([m("c")]));
    g.insert(m("c"), BTreeSet::from([m("a")]));
    g.insert(m("d"), BTreeSet::from([m("a")]));
    assert_eq!(loops(&g).len(), 1);
    assert_eq!(loops(&g)[0].len(), 3);
    g.insert(m("c"), BTreeSet::new());
    assert!(loops(&g).is_empty());
}

/// `graph` seen from the crate's root: each top-level module (a folder or a file under `src/`)
/// with the other top-level modules anything inside it uses.
fn top_level(graph: &BTreeMap<Module, BTreeSet<Module>>) -> BTreeMap<Module, BTreeSet<Module>> {
    let top = |m: &Module| m.first().map(|s| vec![s.clone()]);
    let mut out: BTreeMap<Module, BTreeSet<Module>> = BTreeMap::new();
    for (module, uses) in graph {
        let Some(from) = top(module) else { continue };
        let entry = out.entry(from.clone()).or_default();
        entry.extend(uses.iter().filter_map(top).filter(|to| *to != from));
    }
    out
}

#[test]
fn no_top_level_module_needs_another_that_needs_it_back() {
    let graph = top_level(&graph());
    assert!(graph.len() > 10, "found only {} top-level modules under src/", graph.len());
    let found: Vec<String> =
        loops(&graph).iter().map(|part| part.iter().map(|m| m.join("::")).collect::<Vec<_>>().join(" ⇄ ")).collect();
    assert!(found.is_empty(), "top-level module cycles:\n{}", found.join("\n"));
}
