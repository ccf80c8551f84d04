//! The committed fixtures are exactly what the generator makes, and every baked fixture passes
//! the Khronos glTF-Validator with zero errors (CI sets PELT_REQUIRE_VALIDATOR=1 so a missing
//! validator fails there instead of skipping).

mod common;

use std::process::Command;

use common::*;

#[test]
fn generator_reproduces_the_committed_fixtures() {
    let dir = scratch("gen");
    pelt_fixtures::write_all(&dir).expect("generate fixtures");
    let mut compared = 0;
    for rel in ["sphere.glb", "torus.glb", "creature.glb"]
        .into_iter()
        .map(String::from)
        .chain(
            std::fs::read_dir(dir.join("edge"))
                .expect("edge dir")
                .flatten()
                .map(|e| format!("edge/{}", e.file_name().to_string_lossy())),
        )
        .chain(
            pelt_fixtures::obj::all()
                .into_iter()
                .map(|(rel, _)| format!("obj/{rel}")),
        )
    {
        let made = std::fs::read(dir.join(&rel)).expect("generated");
        let kept = std::fs::read(fixture(&rel))
            .unwrap_or_else(|_| panic!("fixtures/{rel} is not committed"));
        assert!(
            made == kept,
            "fixtures/{rel} differs from the generator's output: run `just fixtures`"
        );
        compared += 1;
    }
    assert!(compared >= 12, "only {compared} fixtures compared");
}

#[test]
fn every_baked_fixture_passes_the_khronos_validator() {
    let script = root().join("tools/validator/validate.mjs");
    let installed = root()
        .join("tools/validator/node_modules/gltf-validator")
        .exists();
    let node = Command::new("node")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    let hint = "npm ci --prefix tools/validator";
    if !tool_available(
        installed && node,
        "PELT_REQUIRE_VALIDATOR",
        "node or tools/validator/node_modules",
        hint,
    ) {
        return;
    }
    let dir = scratch("validate");
    let mut outputs = Vec::new();
    let mut inputs: Vec<String> = ["sphere.glb", "torus.glb", "creature.glb"]
        .map(String::from)
        .to_vec();
    inputs.extend(
        std::fs::read_dir(fixture("edge"))
            .expect("edge")
            .flatten()
            .map(|e| format!("edge/{}", e.file_name().to_string_lossy())),
    );
    inputs.extend(
        pelt_fixtures::obj::all()
            .into_iter()
            .filter(|(rel, _)| rel.ends_with(".obj"))
            .map(|(rel, _)| format!("obj/{rel}")),
    );
    let fur = fixture("fur.json");
    let variants = [
        &[][..],
        &["--tangents", "regenerate", "--quantize", "u8"][..],
        &["--config", fur.to_str().unwrap_or_default()][..],
    ];
    let mut bake_all = |rel: &str, first: &[&str]| {
        for extra in variants {
            let sub = dir.join(format!(
                "{}{}{}",
                rel.replace('/', "-"),
                first.len(),
                extra.len()
            ));
            std::fs::create_dir_all(&sub).expect("mkdir");
            let args: Vec<&str> = first.iter().chain(extra).copied().collect();
            outputs.push(bake(&fixture(rel), &sub, &args));
        }
    };
    for rel in &inputs {
        bake_all(rel, &[]);
    }
    // The Fox: skinned, textured, no COLOR_0 and no NORMAL; its comb is generated.
    bake_all("fox/Fox.glb", &["--comb", "generate"]);
    // The baked Fox posed mid-walk: a static mesh, skin and animations removed.
    let posed = dir.join("fox-walk.glb");
    let baked = outputs[outputs.len() - 3].clone();
    pelt_ok(&[
        "pose",
        baked.to_str().unwrap_or_default(),
        "--animation",
        "Walk",
        "--time",
        "0.4",
        "-o",
        posed.to_str().unwrap_or_default(),
    ]);
    outputs.push(posed);
    let out = Command::new("node")
        .arg(&script)
        .args(&outputs)
        .output()
        .expect("run validator");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "validator found errors:\n{text}");
    assert!(
        text.contains(&format!("{} passed, 0 failed", outputs.len())),
        "{text}"
    );
}
