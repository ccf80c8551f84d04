//! OBJ files as peers read them (`fixtures/obj/`, written by pelt-fixtures): materials and
//! their textures carried into the glTF, missing or empty `.mtl` files and text that is not
//! UTF-8 as warnings, UTF-16 with a byte-order mark decoded.

mod common;

use std::path::Path;

use common::*;
use serde_json::Value;

fn bake_obj(name: &str, dir: &Path) -> (std::path::PathBuf, Value) {
    let out = dir.join(format!("{name}.glb"));
    let input = fixture(&format!("obj/{name}.obj"));
    let report = bake_report(&[
        input.to_str().unwrap_or_default(),
        "-o",
        out.to_str().unwrap_or_default(),
    ]);
    (out, report)
}

fn warnings(report: &Value) -> Vec<String> {
    report["warnings"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|w| w.as_str().map(str::to_owned))
        .collect()
}

#[test]
fn mtl_materials_and_textures_become_gltf_materials() {
    let dir = scratch("obj-textured");
    let (out, report) = bake_obj("textured", &dir);
    assert!(warnings(&report).is_empty(), "{report}");
    let doc = pelt_io::Document::load(&out).expect("load");
    let materials = doc.array("materials");
    assert_eq!(materials.len(), 2, "one per material the faces use");
    let fur = &materials[0];
    assert_eq!(fur["name"], "fur");
    let pbr = &fur["pbrMetallicRoughness"];
    // Under map_Kd the factor is white (the texture is the colour); Ns 250 → roughness 0.5.
    assert_eq!(
        pbr["baseColorFactor"],
        serde_json::json!([1.0, 1.0, 1.0, 1.0])
    );
    assert_eq!(pbr["roughnessFactor"], 0.5);
    assert_eq!(fur["normalTexture"]["scale"], 0.5, "map_Bump -bm 0.5");
    let image_of = |info: &Value| {
        let t = info["index"].as_u64().expect("texture") as usize;
        let i = doc.array("textures")[t]["source"].as_u64().expect("image") as usize;
        doc.image_bytes(i).expect("bytes").to_vec()
    };
    let read = |rel: &str| std::fs::read(fixture(rel)).expect("fixture");
    assert!(image_of(&pbr["baseColorTexture"]) == read("obj/tex/albedo.png"));
    assert!(image_of(&fur["normalTexture"]) == read("obj/tex/normal.png"));
    let skin = &materials[1];
    assert_eq!(skin["name"], "skin");
    assert_eq!(skin["alphaMode"], "BLEND");
    assert_eq!(skin["pbrMetallicRoughness"]["roughnessFactor"], 0.25, "Pr");
    let factor = skin["pbrMetallicRoughness"]["baseColorFactor"]
        .as_array()
        .expect("factor");
    assert!((factor[0].as_f64().unwrap_or(0.0) - 0.9).abs() < 1e-6 && factor[3] == 0.5);
    // Each primitive points at its material.
    let used: Vec<u64> = (0..2)
        .map(|m| {
            doc.json["meshes"][m]["primitives"][0]["material"]
                .as_u64()
                .expect("material")
        })
        .collect();
    assert_eq!(used, [0, 1]);
    // The depfile names the .mtl and both images.
    let dep = dir.join("t.d");
    pelt_ok(&[
        "bake",
        "-q",
        fixture("obj/textured.obj").to_str().unwrap_or_default(),
        "-o",
        dir.join("t.glb").to_str().unwrap_or_default(),
        "--depfile",
        dep.to_str().unwrap_or_default(),
    ]);
    let text = std::fs::read_to_string(&dep).expect("depfile");
    for f in ["textured.mtl", "tex/albedo.png", "tex/normal.png"] {
        assert!(text.contains(f), "{f} missing from {text}");
    }
    validate_clean(&[&out]);
}

/// The textured OBJ renders with its checker; the same grid without its .mtl does not (the
/// negative control).
#[test]
fn a_textured_obj_renders_its_texture() {
    let dir = scratch("obj-render");
    let count = |name: &str| {
        let png = dir.join(format!("{name}.png"));
        pelt_ok(&[
            "render",
            fixture(&format!("obj/{name}.obj"))
                .to_str()
                .unwrap_or_default(),
            "-o",
            png.to_str().unwrap_or_default(),
            "--size",
            "96x72",
        ]);
        let img = load_png(&png);
        let px = img.rgba.chunks(4);
        let red = px
            .clone()
            .filter(|p| p[0] as u32 > 2 * p[2] as u32 && p[0] > 60)
            .count();
        let blue = px
            .filter(|p| p[2] as u32 > 2 * p[0] as u32 && p[2] > 60)
            .count();
        (red, blue)
    };
    let (red, blue) = count("textured");
    assert!(
        red > 20 && blue > 20,
        "checker: {red} red, {blue} blue pixels"
    );
    let (red, blue) = count("missing-mtl");
    assert!(
        red < 5 && blue < 5,
        "untextured: {red} red, {blue} blue pixels"
    );
}

#[test]
fn a_missing_or_empty_mtl_is_a_warning() {
    let dir = scratch("obj-mtl");
    for (name, needle) in [
        ("missing-mtl", "mtllib \"not-here.mtl\""),
        ("empty-mtl", "mtllib \"empty.mtl\" holds no materials"),
    ] {
        let (out, report) = bake_obj(name, &dir);
        let w = warnings(&report);
        assert!(w.iter().any(|w| w.contains(needle)), "{name}: {w:?}");
        assert!(
            w.iter().all(|w| !w.contains("/fixtures/")),
            "no paths: {w:?}"
        );
        let doc = pelt_io::Document::load(&out).expect("load");
        assert!(doc.array("materials").is_empty(), "{name}");
        assert_eq!(report["primitives_baked"], 1, "{name}");
    }
}

#[test]
fn latin1_and_utf16_text_is_decoded() {
    let dir = scratch("obj-text");
    let (out, report) = bake_obj("latin1", &dir);
    let w = warnings(&report);
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(
        w[0].starts_with("line 1: not UTF-8 (byte 0xE9 at column 60)"),
        "{w:?}"
    );
    assert!(
        w[1].starts_with("latin1.mtl line 1: not UTF-8 (byte 0xE9"),
        "{w:?}"
    );
    let doc = pelt_io::Document::load(&out).expect("load");
    // The name decodes the same way in both files, so the face keeps its material.
    assert_eq!(doc.array("materials")[0]["name"], "caf\u{FFFD}");
    assert_eq!(doc.json["meshes"][0]["primitives"][0]["material"], 0);

    let (utf16, report) = bake_obj("utf16", &dir);
    assert!(warnings(&report).is_empty(), "{report}");
    let (plain, _) = bake_obj("missing-mtl", &dir);
    let (a, b) = (read_baked(&utf16, 0, 0), read_baked(&plain, 0, 0));
    assert_eq!(a.positions, b.positions);
    assert_eq!(a.indices, b.indices);
    assert_eq!(a.comb, b.comb);
    validate_clean(&[&out, &utf16]);
}

#[test]
fn a_texture_past_max_texture_is_drawn_smaller_with_a_warning() {
    let dir = scratch("obj-max-texture");
    let png = dir.join("small.png");
    let o = pelt_ok(&[
        "render",
        fixture("obj/textured.obj").to_str().unwrap_or_default(),
        "-o",
        png.to_str().unwrap_or_default(),
        "--size",
        "96x72",
        "--max-texture",
        "1",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("images[0]: 8×8 is larger than the 1 texture limit: drawn at 1×1"),
        "{err}"
    );
    // The 8×8 checker averaged to one texel: purple, no red or blue square left (the full
    // texture draws both: a_textured_obj_renders_its_texture).
    let img = load_png(&png);
    let px = img.rgba.chunks(4);
    let pure = |p: &[u8], a: usize, b: usize| p[a] as u32 > 2 * p[b] as u32 && p[a] > 60;
    let red = px.clone().filter(|p| pure(p, 0, 2)).count();
    let blue = px.clone().filter(|p| pure(p, 2, 0)).count();
    let purple = px
        .filter(|p| p[0] > 60 && p[2] > 60 && p[0].abs_diff(p[2]) < 40 && p[1] < p[0] / 2)
        .count();
    assert!(
        red < 5 && blue < 5 && purple > 20,
        "{red} red, {blue} blue, {purple} purple"
    );
}
