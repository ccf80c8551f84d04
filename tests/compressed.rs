//! Compressed input: gltfpack's `EXT_meshopt_compression` output (`fixtures/compressed/`,
//! see its README) bakes like the file it was made from, and a compressed view that lies is a
//! clear refusal naming the view, with nothing written.

mod common;

use common::*;
use serde_json::Value;

#[test]
fn meshopt_compressed_inputs_bake_to_plain_valid_files() {
    let dir = scratch("meshopt");
    let plain = bake_report(&[
        fixture("creature.glb").to_str().unwrap_or_default(),
        "-o",
        dir.join("plain.glb").to_str().unwrap_or_default(),
    ]);
    let out = dir.join("creature.glb");
    let packed = bake_report(&[
        fixture("compressed/creature-gltfpack-cc.glb")
            .to_str()
            .unwrap_or_default(),
        "-o",
        out.to_str().unwrap_or_default(),
    ]);
    // gltfpack keeps every vertex and triangle of the grid (it reorders them).
    for key in ["vertices", "triangles"] {
        assert_eq!(packed[key], plain[key], "{key}");
    }
    let doc = pelt_io::Document::load(&out).expect("load");
    let text = serde_json::to_string(&doc.json).unwrap_or_default();
    assert!(!text.contains("meshopt"), "the output is plain glTF");
    assert!(doc.array("buffers").len() == 1);
    // The decoded octahedral normals are unit vectors and the comb decodes on the surface.
    let b = read_baked(&out, 0, 0);
    for n in &b.normals {
        assert!((n.length() - 1.0).abs() < 1e-3, "{n}");
    }
    assert!(
        b.comb.iter().all(|c| c[2].abs() < 1e-3),
        "tangent-space combs lie in the plane"
    );
    let fox = dir.join("fox.glb");
    bake_report(&[
        fixture("compressed/fox-gltfpack-cc.glb")
            .to_str()
            .unwrap_or_default(),
        "-o",
        fox.to_str().unwrap_or_default(),
        "--comb",
        "generate",
    ]);
    // The quaternion-filtered animation still poses: pelt pose reads it.
    pelt_ok(&[
        "pose",
        fox.to_str().unwrap_or_default(),
        "--animation",
        "Walk",
        "--time",
        "0.4",
        "-o",
        dir.join("fox-walk.glb").to_str().unwrap_or_default(),
    ]);
    validate_clean_errors(&[&out, &fox, &dir.join("fox-walk.glb")]);
}

/// Runs the validator where installed; errors fail (gltfpack's node layout draws warnings).
fn validate_clean_errors(files: &[&std::path::Path]) {
    let installed = root()
        .join("tools/validator/node_modules/gltf-validator")
        .exists();
    if !tool_available(
        installed,
        "PELT_REQUIRE_VALIDATOR",
        "the glTF validator",
        "npm ci --prefix tools/validator",
    ) {
        return;
    }
    let o = std::process::Command::new("node")
        .arg(root().join("tools/validator/validate.mjs"))
        .args(files)
        .output()
        .expect("node");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stdout));
}

#[test]
fn a_compressed_view_that_lies_is_refused_naming_it() {
    let dir = scratch("meshopt-bad");
    let src = fixture("compressed/creature-gltfpack-cc.glb");
    let bytes = std::fs::read(&src).expect("fixture");
    let edit = |f: &dyn Fn(&mut Value)| -> Vec<u8> {
        let (json, _) = pelt_fixtures::mutate::glb_chunks(&bytes).expect("glb");
        let mut j: Value = serde_json::from_slice(&bytes[json.clone()]).expect("json");
        f(&mut j);
        let rest = &bytes[json.end..];
        pelt_fixtures::mutate::assemble_glb(&serde_json::to_vec(&j).expect("json"), rest)
    };
    let ext = |j: &mut Value, k: &str, v: Value| {
        j["bufferViews"][0]["extensions"]["EXT_meshopt_compression"][k] = v;
    };
    for (name, bad, needle) in [
        (
            "count",
            edit(&|j| ext(j, "count", Value::from(9_000_000))),
            "count × byteStride = ",
        ),
        (
            "fallback",
            edit(&|j| ext(j, "buffer", Value::from(1))),
            "a fallback buffer holds none",
        ),
        (
            "garbage",
            edit(&|j| ext(j, "byteLength", Value::from(16))),
            "cannot be decoded",
        ),
        (
            "mode",
            edit(&|j| ext(j, "mode", Value::from("POINTS"))),
            "unknown mode",
        ),
    ] {
        let input = dir.join(format!("{name}.glb"));
        std::fs::write(&input, bad).expect("write");
        let out = dir.join(format!("{name}-out.glb"));
        let o = pelt(
            &[
                "bake",
                input.to_str().unwrap_or_default(),
                "-o",
                out.to_str().unwrap_or_default(),
            ],
            &[],
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{name}: {err}");
        assert!(
            err.contains("bufferViews[0].extensions.EXT_meshopt_compression")
                && err.contains(needle),
            "{name}: {err}"
        );
        assert!(!out.exists(), "{name}: nothing written");
    }
}
