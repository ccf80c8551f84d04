//! Every crate's layering, read from its source: no import circle spans more than one module
//! in any crate under `crates/*/src`. How the sources are read and where a path leads:
//! `tests/layering/mod.rs`. pelt-preview's own rule (its core names no feature) is in
//! `crates/pelt-preview/tests/layers.rs`, on the same reader.

mod layering;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use layering::{Crate, circles, crate_from_sources, describe, workspace_crates};

/// A synthetic crate from `(file under src/, text)` pairs.
fn synthetic(files: &[(&str, &str)]) -> Crate {
    let files: Vec<(PathBuf, String)> = files
        .iter()
        .map(|(p, t)| (PathBuf::from(p), (*t).to_owned()))
        .collect();
    crate_from_sources("synthetic", &files)
}

/// The circles of a crate, each as its sorted module names.
fn found(krate: &Crate) -> Vec<Vec<String>> {
    circles(&krate.graph())
        .into_iter()
        .map(|c| c.into_iter().collect())
        .collect()
}

/// `names` as owned strings.
fn names(names: &[&str]) -> Vec<String> {
    names.iter().map(|&n| n.to_owned()).collect()
}

#[test]
fn no_crate_has_an_import_circle() {
    let workspace = Path::new(env!("CARGO_MANIFEST_DIR"));
    let crates = workspace_crates(workspace);
    // Every crate folder is read, each with all of its files.
    let folders = std::fs::read_dir(workspace.join("crates"))
        .expect("crates/")
        .filter(|e| e.as_ref().is_ok_and(|e| e.path().join("src").is_dir()))
        .count();
    let libs = crates.iter().filter(|c| !c.name.contains("/bin/")).count();
    assert_eq!(libs, folders, "one crate read per folder");
    let modules: usize = crates.iter().map(|c| c.file_modules().len()).sum();
    assert!(modules > 150, "read {modules} modules");
    let mut report = Vec::new();
    for krate in &crates {
        let graph = krate.graph();
        for circle in circles(&graph) {
            report.push(format!("  {}: {}", krate.name, describe(&graph, &circle)));
        }
    }
    assert!(
        report.is_empty(),
        "{} import circle(s):\n{}",
        report.len(),
        report.join("\n")
    );
}

#[test]
fn the_reader_sees_subfolders_and_nested_groups() {
    let workspace = Path::new(env!("CARGO_MANIFEST_DIR"));
    let crates = workspace_crates(workspace);
    let preview = crates
        .iter()
        .find(|c| c.name == "pelt-preview")
        .expect("pelt-preview");
    let graph = preview.graph();
    // `features/reflect/` is read: a folder below a folder, with its `mod.rs`.
    assert!(
        graph.keys().any(|m| m.starts_with("features::reflect::")),
        "{:?}",
        graph.keys().collect::<Vec<_>>()
    );
    assert!(graph.contains_key("features::reflect"));
}

#[test]
fn a_circle_is_found_negative_control() {
    // a → b → c → a through plain paths; d names a but nothing names d.
    let k = synthetic(&[
        ("lib.rs", "mod a; mod b; mod c; mod d;"),
        ("a.rs", "use crate::b::X;"),
        ("b.rs", "use crate::c::Y; // crate::d"),
        ("c.rs", "fn f() { crate::a::g() }"),
        ("d.rs", "use crate::a;"),
    ]);
    assert_eq!(found(&k), vec![names(&["a", "b", "c"])]);
}

#[test]
fn a_circle_only_visible_through_a_nested_group_is_found() {
    // `e` names `f` only inside a group inside a group; `f` names `e` through `super`.
    let k = synthetic(&[
        ("lib.rs", "mod e; mod f; mod g;"),
        ("e.rs", "use crate::{g, f::{inner::{X, Y}, Z}};"),
        (
            "f.rs",
            "mod inner { pub struct X; pub struct Y; }\nuse super::{e::{self}};",
        ),
        ("g.rs", "pub fn g() {}"),
    ]);
    assert_eq!(found(&k), vec![names(&["e", "f"])]);
    // The first-level group alone names g, not f: without f's part there is no circle.
    let k = synthetic(&[
        ("lib.rs", "mod e; mod f; mod g;"),
        ("e.rs", "use crate::{g, h::{inner::{X}}};"),
        ("f.rs", "use super::e;"),
        ("g.rs", ""),
    ]);
    assert!(found(&k).is_empty(), "{:?}", found(&k));
}

#[test]
fn a_circle_in_a_subfolder_is_found() {
    // parts/mod.rs, parts/deep/mod.rs and parts/deep/leaf.rs: leaf → shallow → leaf.
    let k = synthetic(&[
        ("lib.rs", "pub mod parts;"),
        ("parts/mod.rs", "pub mod deep; pub mod shallow;"),
        ("parts/shallow.rs", "use self::super::deep::leaf::Leaf;"),
        ("parts/deep/mod.rs", "pub mod leaf;"),
        (
            "parts/deep/leaf.rs",
            "pub struct Leaf; use super::super::shallow as s;",
        ),
    ]);
    assert_eq!(
        found(&k),
        vec![names(&["parts::deep::leaf", "parts::shallow"])]
    );
}

#[test]
fn comments_strings_and_tests_name_no_module() {
    let k = synthetic(&[
        ("lib.rs", "mod a; mod b; #[cfg(test)] mod tests;"),
        ("a.rs", "use crate::b::X;"),
        (
            "b.rs",
            concat!(
                "//! Docs: [`crate::a::Y`] and crate::a.\n",
                "/// crate::a::Z\n",
                "/* crate::a /* nested crate::a */ */\n",
                "const S: &str = \"crate::a::f()\";\n",
                "const R: &str = r#\"use crate::a;\"#;\n",
                "const C: char = '{';\n",
                "fn f<'a>(x: &'a u8) {}\n",
                "#[cfg(test)]\nmod tests { use crate::a::Y; }\n",
                "#[cfg(test)]\nuse crate::a::W;\n",
            ),
        ),
        ("tests.rs", "use crate::b::X; use crate::a::Y;"),
    ]);
    assert!(found(&k).is_empty(), "{:?}", found(&k));
    assert!(!k.file_modules().contains("tests"));
    // The same text with one real use after the tests is a circle.
    let k = synthetic(&[
        ("lib.rs", "mod a; mod b;"),
        ("a.rs", "use crate::b::X;"),
        (
            "b.rs",
            "#[cfg(test)]\nmod tests { use crate::a::Y; }\nuse crate::a::W;",
        ),
    ]);
    assert_eq!(found(&k), vec![names(&["a", "b"])]);
}

#[test]
fn a_root_reexport_leads_to_the_owner() {
    // `crate::Skin` is `skin::Skin` re-exported at the root: naming it imports `skin`, not the
    // root, so `skin` importing the root's own `Error` makes no circle with `fur`…
    let k = synthetic(&[
        (
            "lib.rs",
            "mod fur; mod skin; pub use skin::Skin; pub struct Error;",
        ),
        ("fur.rs", "use crate::Skin; pub struct Fur;"),
        ("skin.rs", "pub struct Skin; use crate::Error;"),
    ]);
    let g = k.graph();
    assert!(g["fur"].contains_key("skin"), "{g:?}");
    assert!(!g["fur"].contains_key("lib"), "{g:?}");
    // …but the root re-exports `skin` and `skin` names the root's own item: that is a circle.
    assert_eq!(found(&k), vec![names(&["lib", "skin"])]);
    // A glob re-export leads to the owner too: `crate::Fur` is `fur`'s.
    let k = synthetic(&[
        ("lib.rs", "mod fur; mod skin; pub use fur::*;"),
        ("fur.rs", "pub struct Fur;"),
        ("skin.rs", "use crate::Fur;"),
    ]);
    let g = k.graph();
    assert!(g["skin"].contains_key("fur"), "{g:?}");
    assert!(found(&k).is_empty());
}

#[test]
fn the_circle_report_names_the_paths() {
    let k = synthetic(&[
        ("lib.rs", "mod a; mod b;"),
        ("a.rs", "use crate::b::X;"),
        ("b.rs", "fn f() { super::a::g(); }"),
    ]);
    let g = k.graph();
    let c: BTreeSet<String> = names(&["a", "b"]).into_iter().collect();
    let text = describe(&g, &c);
    assert!(text.contains("a -> b: crate::b::X"), "{text}");
    assert!(text.contains("b -> a: super::a::g"), "{text}");
}
