//! The renderer's layering, read from its source: no import circle spans more than one module,
//! and the core (device, layouts, pipelines, targets, assets, frame inputs) imports no
//! feature. Only the crate's top (the frame driver, the scene's view, progressive refinement,
//! the crate root) knows the feature registry.

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

/// Modules above the features: they may import them.
const TOP: &[&str] = &[
    "lib",
    "frame",
    "scene_view",
    "progressive",
    "animate",
    "bench",
];

/// Each module's source (comments and tests removed), by path (`features::fur`).
fn sources() -> BTreeMap<String, String> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut out = BTreeMap::new();
    for (dir, prefix) in [(src.clone(), ""), (src.join("features"), "features::")] {
        for e in std::fs::read_dir(&dir).expect("src") {
            let path = e.expect("entry").path();
            if path.extension().is_none_or(|x| x != "rs") {
                continue;
            }
            let stem = path.file_stem().and_then(|s| s.to_str()).expect("name");
            let name = match (prefix, stem) {
                ("features::", "mod") => "features".to_owned(),
                _ => format!("{prefix}{stem}"),
            };
            let text = std::fs::read_to_string(&path).expect("read");
            out.insert(name, strip(&text));
        }
    }
    out
}

/// `text` without its tests and line comments.
fn strip(text: &str) -> String {
    let code = text.split("#[cfg(test)]").next().unwrap_or("");
    code.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

/// Which modules each module names (`crate::x`, `crate::features::y`, `super::y`).
fn edges(mods: &BTreeMap<String, String>) -> BTreeMap<String, BTreeSet<String>> {
    let mut out = BTreeMap::new();
    for (m, text) in mods {
        let mut to = BTreeSet::new();
        let parent = if m.starts_with("features::") {
            "features::"
        } else {
            ""
        };
        for (marker, base) in [("crate::", ""), ("super::", parent)] {
            for piece in text.split(marker).skip(1) {
                for path in paths(piece) {
                    let parts: Vec<&str> = path.split("::").filter(|p| !p.is_empty()).collect();
                    // The longest known module the path starts with.
                    for n in (1..=parts.len().min(2)).rev() {
                        let cand = format!("{base}{}", parts[..n].join("::"));
                        if mods.contains_key(&cand) {
                            if &cand != m {
                                to.insert(cand);
                            }
                            break;
                        }
                    }
                }
            }
        }
        out.insert(m.clone(), to);
    }
    out
}

/// The paths `piece` (the text after `crate::` or `super::`) names: `a::b`, or each of
/// `a::{b, c::d}`.
fn paths(piece: &str) -> Vec<String> {
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == ':';
    let head: String = piece.chars().take_while(|&c| ident(c)).collect();
    let rest = &piece[head.len()..];
    match rest.strip_prefix('{') {
        Some(group) => group
            .split('}')
            .next()
            .unwrap_or("")
            .split(',')
            .map(|item| {
                let item: String = item.trim().chars().take_while(|&c| ident(c)).collect();
                format!("{head}{item}")
            })
            .collect(),
        None => vec![head],
    }
}

/// The strongly connected components with more than one module.
fn circles(edges: &BTreeMap<String, BTreeSet<String>>) -> Vec<BTreeSet<String>> {
    let reach = |from: &String| {
        let mut seen = BTreeSet::new();
        let mut stack = vec![from.clone()];
        while let Some(m) = stack.pop() {
            for n in edges.get(&m).into_iter().flatten() {
                if seen.insert(n.clone()) {
                    stack.push(n.clone());
                }
            }
        }
        seen
    };
    let reached: BTreeMap<&String, BTreeSet<String>> =
        edges.keys().map(|m| (m, reach(m))).collect();
    let mut out: Vec<BTreeSet<String>> = Vec::new();
    for (m, r) in &reached {
        let comp: BTreeSet<String> = r
            .iter()
            .filter(|n| reached.get(n).is_some_and(|back| back.contains(*m)))
            .cloned()
            .collect();
        if comp.len() > 1 && !out.contains(&comp) {
            out.push(comp);
        }
    }
    out
}

#[test]
fn no_import_circle_spans_more_than_one_module() {
    let mods = sources();
    assert!(mods.len() > 30, "found {} modules", mods.len());
    let found = circles(&edges(&mods));
    assert!(found.is_empty(), "import circles: {found:?}");
}

#[test]
fn the_core_imports_no_feature() {
    let mods = sources();
    let e = edges(&mods);
    for (m, to) in &e {
        if m.starts_with("features") || TOP.contains(&m.as_str()) {
            continue;
        }
        let f: Vec<&String> = to.iter().filter(|t| t.starts_with("features")).collect();
        assert!(f.is_empty(), "the core module {m} imports {f:?}");
    }
    // The check sees imports: the frame driver does import the registry's features.
    assert!(e["frame"].iter().any(|t| t.starts_with("features")));
}

#[test]
fn a_circle_is_found_negative_control() {
    let mut mods = BTreeMap::new();
    mods.insert("a".to_owned(), "use crate::b::X;".to_owned());
    mods.insert("b".to_owned(), strip("use crate::c::Y; // crate::a"));
    mods.insert("c".to_owned(), strip("fn f() { crate::a::g() }"));
    mods.insert("d".to_owned(), "use crate::a;".to_owned());
    // Grouped imports name each module: e → f, f → e.
    mods.insert("e".to_owned(), "use crate::{d, f::Z};".to_owned());
    mods.insert("f".to_owned(), "use super::{e};".to_owned());
    let found = circles(&edges(&mods));
    assert_eq!(found.len(), 2, "{found:?}");
    assert!(found.iter().any(|c| c.len() == 3), "{found:?}");
    // A comment names no module.
    mods.insert("c".to_owned(), strip("// crate::a::g()"));
    mods.remove("f");
    assert!(circles(&edges(&mods)).is_empty());
}
