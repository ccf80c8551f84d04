//! Baked assets through the glTF-Transform CLI (installed from `integrations/gltf-transform`):
//! with pelt's config every command keeps the fur (the forward render matches the original's,
//! `pelt inspect` reports the same contract, fins and groups, and the output validates);
//! without the config, and after gltfpack, the result still renders, with a warning naming
//! what was lost. docs/pipelines.md records the same measurements.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::*;
use serde_json::Value;

/// The integration's folder.
fn integration() -> PathBuf {
    root().join("integrations/gltf-transform")
}

/// A program the integration's `npm ci` installed (skipped where it is not, unless
/// PELT_REQUIRE_GLTF_TRANSFORM is set, as CI does).
fn installed(bin: &str) -> Option<PathBuf> {
    let path = integration().join("node_modules/.bin").join(bin);
    tool_available(
        path.exists(),
        "PELT_REQUIRE_GLTF_TRANSFORM",
        bin,
        "npm ci --prefix integrations/gltf-transform",
    )
    .then_some(path)
}

/// Runs `gltf-transform COMMAND in out [--config pelt.config.mjs]`; returns its log.
fn transform(cli: &Path, command: &str, input: &Path, out: &Path, config: bool) -> String {
    let mut c = Command::new(cli);
    c.args([command, path_str(input), path_str(out)]);
    if config {
        c.arg("--config").arg(integration().join("pelt.config.mjs"));
    }
    let o = c.output().expect("run gltf-transform");
    let log = format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(o.status.success(), "gltf-transform {command}: {log}");
    log
}

fn path_str(p: &Path) -> &str {
    p.to_str().expect("UTF-8 path")
}

/// `pelt inspect --json` of the file's primitives: per primitive, its contract and topology
/// (the fin count left out where `same_fins` is false), and the fins' staleness.
fn contract(path: &Path, same_fins: bool) -> (Vec<Value>, Vec<Value>) {
    let o = pelt_ok(&["inspect", path_str(path), "--json"]);
    let v: Value = serde_json::from_slice(&o.stdout).expect("inspect JSON");
    let prims = v["primitive"].as_array().expect("primitives");
    let mut summary = Vec::new();
    let mut stale = Vec::new();
    for p in prims {
        let t = &p["topology"];
        let mut s = serde_json::json!({
            "contract": p["contract"],
            "normal_groups": t["normal_groups"],
            "ids_used": t["ids_used"],
        });
        if same_fins {
            s["fin_edges"] = t["fin_edges"].clone();
        }
        summary.push(s);
        stale.push(t["fins_stale"].clone());
    }
    (summary, stale)
}

/// A scene that fills the frame with the asset: the camera on its bounding sphere (from
/// `pelt inspect`'s bounds), a little above and to the side, a key and a fill light.
fn framed_scene(asset: &Path) -> Value {
    let o = pelt_ok(&["inspect", path_str(asset), "--json"]);
    let v: Value = serde_json::from_slice(&o.stdout).expect("inspect JSON");
    let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
    for p in v["primitive"].as_array().expect("primitives") {
        for k in 0..3 {
            lo[k] = lo[k].min(p["bounds"]["min"][k].as_f64().expect("min"));
            hi[k] = hi[k].max(p["bounds"]["max"][k].as_f64().expect("max"));
        }
    }
    let c: Vec<f64> = (0..3).map(|k| (lo[k] + hi[k]) / 2.0).collect();
    let r = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f64>().sqrt() / 2.0;
    let d = r / 20f64.to_radians().sin();
    serde_json::json!({
        "output": { "width": 160, "height": 90 },
        "camera": { "position": [c[0] + 0.35 * d, c[1] + 0.3 * d, c[2] + 0.88 * d],
                    "target": c, "fovYDeg": 40 },
        "objects": [{ "asset": asset, "material": { "kind": "fur" } }],
        "lights": [
            { "position": [c[0] + 2.0 * r, c[1] + 2.5 * r, c[2] + 3.0 * r],
              "color": [1, 1, 1], "intensity": 14.0 * r * r, "radius": 10.0 * r },
            { "position": [c[0] - 3.0 * r, c[1] + 1.0 * r, c[2] + 2.0 * r],
              "color": [0.6, 0.7, 1], "intensity": 5.0 * r * r, "radius": 10.0 * r }
        ]
    })
}

/// Renders `asset` in the frame `frame_of` fills (the original's, so every output is seen
/// from the same place).
fn render(dir: &Path, asset: &Path, frame_of: &Path, name: &str) -> (pelt_preview::Image, String) {
    let mut scene = framed_scene(frame_of);
    scene["objects"][0]["asset"] = Value::from(path_str(asset));
    render_warned(dir, name, &scene)
}

/// Each command, its FLIP limit against the original, and whether it keeps the triangles (so
/// the fin count must be the same).
const COMMANDS: &[(&str, f32, bool)] = &[
    ("copy", 0.01, true),
    ("prune", 0.01, true),
    ("dedup", 0.01, true),
    ("reorder", 0.01, true),
    ("weld", 0.03, true),
    ("quantize", 0.03, true),
    ("meshopt", 0.03, true),
    // optimize simplifies (a few triangles go), so its fins are recomputed and fewer.
    ("optimize", 0.03, false),
];

/// Every command with the config on `baked`: same picture within the limit, same contract.
fn round_trips(name: &str, baked: &Path) {
    let Some(cli) = installed("gltf-transform") else {
        return;
    };
    let dir = scratch(&format!("gltf-transform-{name}"));
    let (original, _) = render(&dir, baked, baked, "original");
    let (want_all, _) = contract(baked, true);
    let (want_shape, _) = contract(baked, false);
    let mut outputs = Vec::new();
    for &(command, limit, same_triangles) in COMMANDS {
        let out = dir.join(format!("{command}.glb"));
        transform(&cli, command, baked, &out, true);
        let (image, warned) = render(&dir, &out, baked, command);
        let f = flip_of(&original, &image);
        println!("{name} {command}: FLIP {f:.4}");
        assert!(f <= limit, "{name} {command}: FLIP {f:.4} > {limit}");
        // prune drops TANGENT (the material has no normal texture); pelt regenerates the
        // bake's frame and says so. Nothing else may be reported.
        let other: Vec<&str> = warned
            .lines()
            .filter(|l| l.contains("warning") && !l.contains("no TANGENT (a tool removed it)"))
            .collect();
        assert!(other.is_empty(), "{name} {command}: pelt warned: {other:?}");
        let (got, stale) = contract(&out, same_triangles);
        let want = if same_triangles {
            &want_all
        } else {
            &want_shape
        };
        assert_eq!(&got, want, "{name} {command}: inspect differs");
        assert!(
            stale.iter().all(Value::is_null),
            "{name} {command}: {stale:?}"
        );
        outputs.push(out);
    }
    let files: Vec<&Path> = outputs.iter().map(PathBuf::as_path).collect();
    validate_clean(&files);
    for f in &files {
        extension_schema::validate(f);
    }
}

#[test]
fn with_the_config_every_command_keeps_a_static_assets_fur() {
    let dir = scratch("gltf-transform-static-bake");
    let fur = ["--config", "fixtures/legacy/fur-small.json"];
    let baked = bake(&fixture("sphere.glb"), &dir, &fur);
    round_trips("static", &baked);
}

#[test]
fn with_the_config_every_command_keeps_a_skinned_assets_fur() {
    let dir = scratch("gltf-transform-skinned-bake");
    let fur = ["--config", "fixtures/legacy/fur-small.json"];
    let baked = bake(&fixture("creature.glb"), &dir, &fur);
    round_trips("skinned", &baked);
}

/// Negative control for the round trips: glTF-Transform without the config drops PELT_fur
/// (the contract inspect reports changes), and pelt still renders the result, exit 0, with a
/// warning naming what was lost.
#[test]
fn without_the_config_or_after_gltfpack_the_asset_renders_with_a_warning() {
    let (Some(cli), Some(gltfpack)) = (installed("gltf-transform"), installed("gltfpack")) else {
        return;
    };
    let dir = scratch("gltf-transform-unknown");
    let fur = ["--config", "fixtures/legacy/fur-small.json"];
    let baked = bake(&fixture("sphere.glb"), &dir.join("bake"), &fur);
    let plain = dir.join("plain.glb");
    let log = transform(&cli, "copy", &baked, &plain, false);
    assert!(log.contains("PELT_fur"), "{log}");
    assert_ne!(contract(&plain, true).0, contract(&baked, true).0);
    let (original, _) = render(&dir, &baked, &baked, "original");
    let (image, warned) = render(&dir, &plain, &baked, "plain");
    // The round trips' limits would catch it: without fins and manifest the fur differs.
    let f = flip_of(&original, &image);
    println!("without the config: FLIP {f:.4}");
    assert!(f > 0.01, "FLIP {f:.4}");
    assert!(
        warned.contains("has _FUR_COMB but no PELT_fur") && warned.contains("plain.glb"),
        "{warned}"
    );

    let packed = dir.join("packed.glb");
    let o = Command::new(&gltfpack)
        .args(["-i", path_str(&baked), "-o", path_str(&packed), "-kv"])
        .output()
        .expect("run gltfpack");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (_, warned) = render(&dir, &packed, &baked, "packed");
    assert!(
        warned.contains("no _FUR_COMB and no PELT_fur") && warned.contains("packed.glb"),
        "{warned}"
    );
    // Negative control: a painted source that was never baked (no sheen) draws without it.
    let (_, warned) = render(&dir, &fixture("sphere.glb"), &baked, "source");
    assert!(!warned.contains("no PELT_fur"), "{warned}");
}
