//! The `PELT_fur` extension (docs/extension/PELT_fur/): every bake writes it (never
//! `extras.pelt`), its objects validate against the extension's JSON Schemas, records a tool
//! left stale are detected and rebuilt, files that lost parts of it render with a warning,
//! files of the earlier `extras.pelt` form re-bake to it, and fur materials carry a sheen
//! fallback that pelt's own renderer ignores.

mod common;

use std::path::Path;

use common::extension_schema::{schemas, validate as validate_against_schemas};
use common::*;
use pelt_io::Document;
use serde_json::{Value, json};

#[test]
fn every_bake_writes_pelt_fur_that_validates_against_its_schemas() {
    let dir = scratch("extension-schemas");
    let fur = ["--config", "fixtures/legacy/fur-small.json"];
    let sphere = bake(&fixture("sphere.glb"), &dir.join("sphere"), &fur);
    let packed = bake(&fixture("torus.glb"), &dir.join("packed"), &["--compress"]);
    let skinned = bake(&fixture("creature.glb"), &dir.join("skinned"), &fur);
    let groups = bake(
        &fixture("sphere.glb"),
        &dir.join("groups"),
        &["--topology", "groups"],
    );
    for (path, prims, mats) in [
        (&sphere, 1, 1),
        (&packed, 1, 0),
        (&skinned, 1, 1),
        (&groups, 1, 0),
    ] {
        let (p, m) = validate_against_schemas(path);
        assert!(p >= prims && m >= mats, "{}: {p} {m}", path.display());
    }
    validate_clean(&[&sphere, &packed, &skinned, &groups]);
    // The fins are an accessor of corner pairs, in a bufferView with no target.
    let doc = Document::load(&sphere).expect("load");
    let prim = &doc.json["meshes"][0]["primitives"][0];
    let a = prim["extensions"]["PELT_fur"]["fins"]["accessor"]
        .as_u64()
        .expect("fins accessor") as usize;
    let acc = &doc.json["accessors"][a];
    assert_eq!(
        (acc["type"].as_str(), acc["componentType"].as_u64()),
        (Some("VEC2"), Some(5125))
    );
    let view = &doc.json["bufferViews"][acc["bufferView"].as_u64().expect("view") as usize];
    assert!(
        view.get("target").is_none() && view.get("byteStride").is_none(),
        "{view}"
    );
    // Defaults are left out; values that differ are written.
    let groups_of = |path: &Path| {
        let d = Document::load(path).expect("load");
        d.json["meshes"][0]["primitives"][0]["extensions"]["PELT_fur"]["normalGroups"].clone()
    };
    let keys = |v: &Value| v.as_object().map(|o| o.keys().cloned().collect::<Vec<_>>());
    assert_eq!(
        keys(&groups_of(&sphere)),
        Some(vec!["groups".into(), "idsUsed".into()])
    );
    let tuned = bake(
        &fixture("sphere.glb"),
        &dir.join("tuned"),
        &["--normal-tolerance", "30", "--weld-epsilon", "0.001"],
    );
    let g = groups_of(&tuned);
    assert_eq!(
        (g["normalToleranceDeg"].as_f64(), g["weldEpsilon"].as_f64()),
        (Some(30.0), Some(0.001)),
        "{g}"
    );
    validate_against_schemas(&tuned);
    // Negative controls: the schemas refuse what a reader could not use.
    let (schemas, p, m) = schemas();
    let ok = prim["extensions"]["PELT_fur"].clone();
    assert!(schemas.validate(&ok, p).is_ok());
    for bad in [
        json!({ "computedFrom": null }),
        json!({ "computedFrom": { "triangles": 3, "indexHash": "abc" } }),
        json!({ "fins": { "accessor": 1, "fromIndices": {}, "count": 0 } }),
        json!({ "unknown": 1 }),
    ] {
        let mut v = ok.clone();
        for (k, x) in bad.as_object().expect("object") {
            v[k] = x.clone();
        }
        assert!(schemas.validate(&v, p).is_err(), "accepted {v}");
    }
    let mat = doc.json["materials"][0]["extensions"]["PELT_fur"].clone();
    assert!(schemas.validate(&mat, m).is_ok());
    let mut no_tex = mat.clone();
    no_tex.as_object_mut().expect("object").remove("finTexture");
    assert!(schemas.validate(&no_tex, m).is_err());
}

/// A copy of `from` whose first primitive's triangles are rotated by one (the last triangle
/// first), as a tool that reorders triangles for the vertex cache leaves it; `keep_hash`:
/// whether `computedFrom` stays (false: removed, as an old reader would not look at it).
fn reorder_triangles(from: &Path, to: &Path, keep_hash: bool) {
    let mut doc = Document::load(from).expect("load");
    let r = pelt_io::PrimitiveRef {
        mesh: 0,
        primitive: 0,
    };
    let mut idx = doc.corner_list(r).expect("indices");
    idx.rotate_right(3);
    let n = doc.json["accessors"][doc.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
        .as_u64()
        .expect("POSITION") as usize]["count"]
        .as_u64()
        .expect("count") as usize;
    let a = doc.push_accessor(pelt_io::edit::NewAccessor::indices(&idx, n));
    doc.json["meshes"][0]["primitives"][0]["indices"] = json!(a);
    if !keep_hash {
        let e = doc.json["meshes"][0]["primitives"][0]["extensions"]["PELT_fur"]
            .as_object_mut()
            .expect("PELT_fur");
        e.remove("computedFrom");
    }
    write_input(&doc, to);
}

/// How many fin records of the primitive are not an edge of its triangles as drawn: the
/// edge from `c0` and the edge from `c1` must join the same two positions.
fn misread_records(path: &Path) -> usize {
    let doc = Document::load(path).expect("load");
    let r = pelt_io::PrimitiveRef {
        mesh: 0,
        primitive: 0,
    };
    let fins = doc.read_fins(r).expect("read").expect("fins");
    let idx = doc.corner_list(r).expect("indices");
    let pos = pelt_io::accessor::read_vec::<3>(
        &doc,
        doc.attribute(r, "POSITION")
            .expect("attr")
            .expect("POSITION"),
        "POSITION",
    )
    .expect("positions");
    let next = |c: u32| c - c % 3 + (c + 1) % 3;
    let p = |c: u32| pos[idx[c as usize] as usize];
    fins.iter()
        .filter(|e| e.second_corner != u32::MAX)
        .filter(|e| {
            let (a, b) = (p(e.corner), p(next(e.corner)));
            let (c, d) = (p(e.second_corner), p(next(e.second_corner)));
            !((a == d && b == c) || (a == c && b == d))
        })
        .count()
}

fn sphere_scene(asset: &Path) -> Value {
    json!({
        "output": { "width": 160, "height": 90 },
        "camera": { "position": [0.0, 1.4, 3.6], "target": [0.0, 0.5, 0.0], "fovYDeg": 40 },
        "objects": [{ "asset": asset, "material": { "kind": "fur", "length": 0.15 } }],
        "lights": [{ "position": [2.0, 2.5, 3.0], "color": [1, 1, 1], "intensity": 6, "radius": 10 }]
    })
}

#[test]
fn stale_fin_records_are_detected_and_rebuilt() {
    let dir = scratch("extension-stale");
    let baked = bake(
        &fixture("sphere.glb"),
        &dir,
        &["--config", "fixtures/legacy/fur-small.json"],
    );
    let stale = dir.join("reordered.glb");
    reorder_triangles(&baked, &stale, true);
    // inspect names the stale records and why.
    let info: Value = serde_json::from_slice(
        &pelt_ok(&["inspect", "--json", stale.to_str().unwrap_or_default()]).stdout,
    )
    .expect("inspect JSON");
    let t = &info["primitive"][0]["topology"];
    assert!(
        t["fins_stale"]
            .as_str()
            .is_some_and(|w| w.contains("reordered")),
        "{t}"
    );
    assert_eq!(
        info["primitive"][0]["contract"]["fins"],
        "stale (rebuilt at load)"
    );
    // The renderer rebuilds the fins, says so, and draws what the fresh bake draws.
    let (fresh, _) = render_warned(&dir, "fresh", &sphere_scene(&baked));
    let (rebuilt, warned) = render_warned(&dir, "rebuilt", &sphere_scene(&stale));
    assert!(
        warned.contains("reordered.glb") && warned.contains("rebuilt from the triangles"),
        "{warned}"
    );
    let f = flip_of(&fresh, &rebuilt);
    println!("fins rebuilt at load against the bake's: FLIP {f:.4}");
    assert!(f <= 0.01, "FLIP {f}");
    // Negative control: without computedFrom (an old reader's view) the same records read
    // as valid, and many are not edges of the triangles any more.
    let blind = dir.join("blind.glb");
    reorder_triangles(&baked, &blind, false);
    assert_eq!(misread_records(&baked), 0);
    let wrong = misread_records(&blind);
    println!("records misread without the hash: {wrong}");
    assert!(wrong > 100, "{wrong}");
}

#[test]
fn files_that_lost_part_of_the_contract_render_with_a_warning() {
    let dir = scratch("extension-lost");
    let baked = bake(
        &fixture("sphere.glb"),
        &dir,
        &["--config", "fixtures/legacy/fur-small.json"],
    );
    let edit = |name: &str, f: &dyn Fn(&mut Document)| {
        let mut doc = Document::load(&baked).expect("load");
        f(&mut doc);
        let out = dir.join(format!("{name}.glb"));
        write_input(&doc, &out);
        out
    };
    // A tool that does not know PELT_fur drops it and keeps the `_` attributes.
    let no_ext = edit("no-extension", &|d| {
        d.json["meshes"][0]["primitives"][0]["extensions"]
            .as_object_mut()
            .expect("exts")
            .remove("PELT_fur");
        d.json["materials"][0]["extensions"]
            .as_object_mut()
            .expect("exts")
            .remove("PELT_fur");
    });
    // One that keeps the extension but drops the attribute.
    let no_comb = edit("no-comb", &|d| {
        d.json["meshes"][0]["primitives"][0]["attributes"]
            .as_object_mut()
            .expect("attrs")
            .remove("_FUR_COMB");
    });
    for (path, needle) in [
        (&no_ext, "has _FUR_COMB but no PELT_fur"),
        (&no_comb, "carries PELT_fur but no _FUR_COMB"),
    ] {
        let (_, warned) = render_warned(&dir, "lost", &sphere_scene(path));
        assert!(
            warned.contains(&path.display().to_string()) && warned.contains(needle),
            "{warned}"
        );
        let o = pelt_ok(&["inspect", path.to_str().unwrap_or_default()]);
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(text.contains("contract"), "{text}");
    }
    // Control: the intact file warns of neither.
    let (_, warned) = render_warned(&dir, "intact", &sphere_scene(&baked));
    assert!(!warned.contains("PELT_fur"), "{warned}");
}

#[test]
fn an_extras_form_file_rebakes_to_the_extension() {
    let dir = scratch("extension-legacy");
    let fur = ["--config", "fixtures/legacy/fur-small.json"];
    let rebaked = bake(&fixture("legacy/sphere-extras.glb"), &dir.join("re"), &fur);
    let fresh = bake(&fixture("sphere.glb"), &dir.join("fresh"), &fur);
    let (p, m) = validate_against_schemas(&rebaked);
    assert_eq!((p, m), (1, 1));
    let count = |path: &Path, key: &str| Document::load(path).expect("load").array(key).len();
    for key in ["images", "textures", "accessors", "bufferViews"] {
        assert_eq!(count(&rebaked, key), count(&fresh, key), "{key}");
    }
    validate_clean(&[&rebaked]);
}

#[test]
fn fur_materials_carry_a_sheen_fallback_pelt_ignores() {
    let dir = scratch("extension-sheen");
    let baked = bake(
        &fixture("sphere.glb"),
        &dir,
        &["--config", "fixtures/legacy/fur-small.json"],
    );
    let doc = Document::load(&baked).expect("load");
    let sheen = &doc.json["materials"][0]["extensions"]["KHR_materials_sheen"];
    let color: Vec<f64> = sheen["sheenColorFactor"]
        .as_array()
        .expect("colour")
        .iter()
        .filter_map(Value::as_f64)
        .collect();
    let rough = sheen["sheenRoughnessFactor"].as_f64().expect("roughness");
    println!("sheen {color:?} roughness {rough}");
    assert_eq!(color.len(), 3);
    assert!(color.iter().all(|c| (0.0..=1.0).contains(c)) && color.iter().any(|&c| c > 0.05));
    // The tips are lighter than the roots: the sheen leans to the tip colour.
    assert!(color[0] > 0.2, "{color:?}");
    assert!((0.3..=1.0).contains(&rough), "{rough}");
    assert!(
        doc.array("extensionsUsed")
            .iter()
            .any(|e| e == "KHR_materials_sheen")
    );
    // pelt draws fur, not the sheen: the picture without it is the same.
    let mut bare = doc.clone();
    bare.json["materials"][0]["extensions"]
        .as_object_mut()
        .expect("exts")
        .remove("KHR_materials_sheen");
    let without = dir.join("without-sheen.glb");
    write_input(&bare, &without);
    let (a, _) = render_warned(&dir, "with", &sphere_scene(&baked));
    let (b, _) = render_warned(&dir, "without", &sphere_scene(&without));
    assert_eq!(flip_of(&a, &b), 0.0);
}
