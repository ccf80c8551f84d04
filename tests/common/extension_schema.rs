//! The `PELT_fur` extension's JSON Schemas (docs/extension/PELT_fur/schema/), compiled with
//! `boon`, and the checks every file that carries the extension must pass.

use std::path::Path;

use pelt_io::Document;
use serde_json::Value;

use super::root;

/// A `PELT_fur` object and where it is (`meshes[0].primitives[0]`, `materials[1]`).
pub type Placed = (String, Value);

const SCHEMAS: &[&str] = &[
    "primitive.PELT_fur.schema.json",
    "primitive.PELT_fur.normalGroups.schema.json",
    "primitive.PELT_fur.fins.schema.json",
    "material.PELT_fur.schema.json",
    "material.PELT_fur.texture.schema.json",
    "material.PELT_fur.strands.schema.json",
];

/// The extension's schemas, compiled: (schemas, primitive schema, material schema).
pub fn schemas() -> (boon::Schemas, boon::SchemaIndex, boon::SchemaIndex) {
    let dir = root().join("docs/extension/PELT_fur/schema");
    let mut compiler = boon::Compiler::new();
    for name in SCHEMAS {
        let text = std::fs::read_to_string(dir.join(name)).expect("schema");
        let v: Value = serde_json::from_str(&text).expect("schema JSON");
        compiler
            .add_resource(&format!("https://pelt.invalid/schema/{name}"), v)
            .expect("add schema");
    }
    let mut schemas = boon::Schemas::new();
    let mut compile = |name: &str| {
        compiler
            .compile(&format!("https://pelt.invalid/schema/{name}"), &mut schemas)
            .unwrap_or_else(|e| panic!("{name}: {e}"))
    };
    let (p, m) = (
        compile("primitive.PELT_fur.schema.json"),
        compile("material.PELT_fur.schema.json"),
    );
    (schemas, p, m)
}

/// Every `PELT_fur` object of `doc` (primitives, then materials) with its place, and the
/// checks every output passes: listed in `extensionsUsed` only, no `extras.pelt` anywhere.
pub fn fur_objects(doc: &Document) -> (Vec<Placed>, Vec<Placed>) {
    let used = doc.array("extensionsUsed");
    assert!(used.iter().any(|e| e == "PELT_fur"), "{used:?}");
    assert!(
        !doc.array("extensionsRequired")
            .iter()
            .any(|e| e == "PELT_fur"),
        "PELT_fur must never be required"
    );
    let mut prims = Vec::new();
    for (m, mesh) in doc.array("meshes").iter().enumerate() {
        for (p, prim) in mesh["primitives"]
            .as_array()
            .into_iter()
            .flatten()
            .enumerate()
        {
            assert!(prim["extras"].get("pelt").is_none(), "{prim}");
            if let Some(e) = prim["extensions"].get("PELT_fur") {
                prims.push((format!("meshes[{m}].primitives[{p}]"), e.clone()));
            }
        }
    }
    let mut mats = Vec::new();
    for (k, mat) in doc.array("materials").iter().enumerate() {
        assert!(mat["extras"].get("pelt").is_none(), "{mat}");
        if let Some(e) = mat["extensions"].get("PELT_fur") {
            mats.push((format!("materials[{k}]"), e.clone()));
        }
    }
    (prims, mats)
}

/// Validates every `PELT_fur` object of the file at `path` against the schemas; returns how
/// many primitive and material objects there were.
pub fn validate(path: &Path) -> (usize, usize) {
    let (schemas, prim, mat) = schemas();
    let doc = Document::load(path).expect("load");
    let (prims, mats) = fur_objects(&doc);
    for (place, v) in &prims {
        if let Err(e) = schemas.validate(v, prim) {
            panic!("{}: {place}: {e}", path.display());
        }
    }
    for (place, v) in &mats {
        if let Err(e) = schemas.validate(v, mat) {
            panic!("{}: {place}: {e}", path.display());
        }
    }
    (prims.len(), mats.len())
}
