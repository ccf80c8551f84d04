//! The renderer's layering, read from its source: the core (device, layouts, pipelines,
//! targets, assets, frame inputs) imports no feature. Only the crate's top (the frame driver,
//! the scene's view, progressive refinement, the crate root) knows the feature registry. The
//! sources are read by the workspace's reader (`tests/layering/mod.rs`, every module under
//! `src/` and its subfolders, nested `use` groups resolved); the workspace's `tests/layers.rs`
//! checks that no import circle spans two modules here or in any other crate.

#[path = "../../../tests/layering/mod.rs"]
mod layering;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use layering::{Graph, crate_from_dir, crate_from_sources};

/// Modules above the features: they may import them.
const TOP: &[&str] = &[
    "lib",
    "frame",
    "scene_view",
    "progressive",
    "animate",
    "bench",
];

/// Each core module's imports of features (`features`, `features::…`), by module.
fn core_imports_of_features(graph: &Graph) -> BTreeMap<&str, BTreeSet<&str>> {
    let mut out = BTreeMap::new();
    for (m, to) in graph {
        if m.starts_with("features") || TOP.contains(&m.as_str()) {
            continue;
        }
        let f: BTreeSet<&str> = to
            .keys()
            .filter(|t| t.starts_with("features"))
            .map(String::as_str)
            .collect();
        if !f.is_empty() {
            out.insert(m.as_str(), f);
        }
    }
    out
}

#[test]
fn the_core_imports_no_feature() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let krate = crate_from_dir("pelt-preview", &src);
    let graph = krate.graph();
    assert!(graph.len() > 30, "found {} modules", graph.len());
    let found = core_imports_of_features(&graph);
    assert!(
        found.is_empty(),
        "core modules importing features: {found:?}"
    );
    // The check sees imports: the frame driver does import the registry's features, and a
    // feature folder's modules are read (features/reflect/).
    assert!(graph["frame"].keys().any(|t| t.starts_with("features")));
    assert!(graph.keys().any(|m| m.starts_with("features::reflect::")));
}

#[test]
fn a_core_module_naming_a_feature_is_found_negative_control() {
    let files: Vec<(PathBuf, String)> = [
        ("lib.rs", "mod frame; mod draw; mod targets; mod features;"),
        ("frame.rs", "use crate::features::fur::Fur;"),
        // Only through a nested group, and from a file in a subfolder.
        (
            "draw.rs",
            "use crate::{targets, features::{reflect::{inputs::{MapInputs}}}};",
        ),
        (
            "targets.rs",
            "// crate::features::fur\nconst S: &str = \"crate::features\";",
        ),
        ("features/mod.rs", "pub mod fur; pub mod reflect;"),
        ("features/fur.rs", "use crate::draw;"),
        ("features/reflect/mod.rs", "pub mod inputs;"),
        ("features/reflect/inputs.rs", "pub struct MapInputs;"),
    ]
    .iter()
    .map(|(p, t)| (PathBuf::from(p), (*t).to_owned()))
    .collect();
    let graph = crate_from_sources("synthetic", &files).graph();
    let found = core_imports_of_features(&graph);
    let want: BTreeMap<&str, BTreeSet<&str>> =
        [("draw", BTreeSet::from(["features::reflect::inputs"]))].into();
    assert_eq!(found, want);
}
