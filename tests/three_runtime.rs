//! The three.js runtime (`integrations/three`) against pelt's forward mode, both rendering the
//! demo's scene files at 320×180 in this test run: `render.mjs` in headless Chromium (WebGL2
//! on SwiftShader) and `pelt render --mode forward` with the same shell count. Whole-image
//! FLIP and the fur's mean luminance; a negative control (every shell opaque) fails the same
//! threshold. Skipped where Chromium or the package's `npm ci` is missing, unless
//! PELT_REQUIRE_BROWSER is set (CI sets it).

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::runtime::{self, variant};
use common::*;

fn package() -> PathBuf {
    root().join("integrations/three")
}

fn browser_ready() -> bool {
    let installed = package().join("node_modules/puppeteer-core").exists()
        && package().join("node_modules/three").exists();
    let chromium =
        Path::new(&std::env::var("CHROMIUM").unwrap_or_else(|_| "/usr/bin/chromium".into()))
            .exists();
    tool_available(
        installed && chromium,
        "PELT_REQUIRE_BROWSER",
        "chromium and integrations/three's packages",
        "apt-get install chromium; npm ci --prefix integrations/three",
    )
}

/// `node render.mjs SCENE -o OUT --size 320x180 EXTRA…`, which must succeed without a
/// browser console error.
/// `node render.mjs SCENE -o OUT --size SIZE EXTRA…`, its output whatever its status.
fn render_mjs(scene: &Path, out: &Path, size: &str, extra: &[&str]) -> std::process::Output {
    Command::new("node")
        .arg(package().join("render.mjs"))
        .arg(scene)
        .args(["-o", out.to_str().expect("UTF-8"), "--size", size])
        .args(extra)
        .output()
        .expect("run node")
}

/// The three.js runtime as the shared checks run it: `render.mjs` in headless Chromium,
/// whose clean log has no browser console error.
struct Three;

impl runtime::Runtime for Three {
    fn name(&self) -> &'static str {
        "three"
    }

    fn run(&self, scene: &Path, out: &Path, size: &str, extra: &[&str]) -> std::process::Output {
        render_mjs(scene, out, size, extra)
    }

    fn check_log(&self, _scene: &Path, log: &str) {
        assert!(!log.contains("browser:"), "console errors: {log}");
    }
}

/// One comparison of the three.js runtime against pelt with the same flags, and the negative
/// control `control`, if any.
fn compare(scene: &Path, name: &str, args: &[&str], control: Option<&str>) -> (f32, f64) {
    runtime::compare_with(&Three, scene, name, args, control)
}

fn demo_scenes() -> (PathBuf, PathBuf) {
    runtime::demo_scenes("three-demo")
}

#[test]
fn three_draws_the_demo_scenes_as_pelt_forward_does() {
    if !browser_ready() {
        return;
    }
    let (creature, fox) = demo_scenes();
    runtime::check_demo_scenes(&Three, &creature, &fox);
}

#[test]
fn each_feature_matches_and_its_negative_control_does_not() {
    if !browser_ready() {
        return;
    }
    let (creature, fox) = demo_scenes();
    runtime::check_features(&Three, &creature, &fox);
}

#[test]
fn a_skinned_asset_follows_its_clip() {
    if !browser_ready() {
        return;
    }
    let (_, fox) = demo_scenes();
    runtime::check_clip(&Three, &fox);
}

/// `node test/NAME.mjs ARGS…` (a page driver of the package), its JSON result.
fn page(script: &str, args: &[&Path], extra: &[&str]) -> serde_json::Value {
    let o = Command::new("node")
        .arg(package().join("test").join(script))
        .args(args)
        .args(extra)
        .output()
        .expect("run node");
    assert!(
        o.status.success(),
        "{script}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    serde_json::from_slice(&o.stdout).expect("JSON result")
}

#[test]
fn the_stock_loader_without_the_plugin_shows_the_sheen_fallback() {
    if !browser_ready() {
        return;
    }
    let (_, fox) = demo_scenes();
    let demo = fox.parent().expect("folder");
    let r = page(
        "page.mjs",
        &[Path::new("stock"), &demo.join("fox.glb")],
        &[],
    );
    assert!(r.get("error").is_none(), "{}", r["error"]);
    assert_eq!(r["consoleErrors"], serde_json::json!([]), "console errors");
    assert_eq!(
        r["outside"],
        serde_json::json!([]),
        "requests off the machine"
    );
    assert!(
        r["sheenMaterials"].as_u64() >= Some(1),
        "no sheen drawn: {r}"
    );
    // Negative control: a file that is not a glTF is an error the page reports.
    let bad = demo.join("not-a-model.glb");
    std::fs::write(&bad, b"glTF\x02\0\0\0 truncated").expect("write");
    let r = page("page.mjs", &[Path::new("stock"), &bad], &[]);
    assert!(r.get("error").is_some(), "a truncated file loaded: {r}");
}

#[test]
fn the_viewer_shows_a_scene_file_and_a_dropped_asset_without_console_errors() {
    if !browser_ready() {
        return;
    }
    let (creature, _) = demo_scenes();
    let asset = creature.parent().expect("folder").join("fox.glb");
    let r = page("viewer.mjs", &[&creature, &asset], &[]);
    assert_eq!(
        r["consoleErrors"],
        serde_json::json!([]),
        "console errors: {r}"
    );
    assert_eq!(
        r["outside"],
        serde_json::json!([]),
        "requests off the machine"
    );
    assert_eq!(r["showing"], "fox.glb", "{r}");
    assert!(r["frames"].as_u64() > Some(4), "{r}");
}

#[test]
fn the_shell_count_follows_the_fur_on_screen_as_in_pelt() {
    if !browser_ready() {
        return;
    }
    let (creature, _) = demo_scenes();
    runtime::check_rule(&Three, &creature);
}

/// Bad input to `render.mjs`: a missing asset, a malformed scene file and a missing one are
/// errors naming the file and the place, exit 1, and no PNG.
#[test]
fn bad_scene_files_are_errors_naming_the_place_and_write_nothing() {
    if !browser_ready() {
        return;
    }
    let (creature, _) = demo_scenes();
    let missing_asset = variant(&creature, "bad-asset", |v| {
        v["objects"][0]["asset"] = "missing.glb".into();
    });
    let malformed = creature.with_file_name("bad-json.json");
    std::fs::write(&malformed, b"{\"objects\": [").expect("write");
    let absent = creature.with_file_name("absent.json");
    runtime::check_bad_input(
        &Three,
        &creature,
        &[
            (&missing_asset, &[], "objects[0]: missing.glb"),
            (&malformed, &[], "bad-json.json"),
            (&absent, &[], "absent.json: no such file"),
        ],
    );
}

/// gltfpack's output of the baked Fox (quantized, its texture coordinates moved by
/// KHR_texture_transform, the fur dropped) drawn opaque: the web runtime reads the transform
/// as pelt does. Negative control: the transform ignored.
#[test]
fn a_texture_transform_is_read_as_pelt_reads_it() {
    if !browser_ready() {
        return;
    }
    let gltfpack = root().join("integrations/gltf-transform/node_modules/.bin/gltfpack");
    if !tool_available(
        gltfpack.exists(),
        "PELT_REQUIRE_GLTF_TRANSFORM",
        "gltfpack",
        "npm ci --prefix integrations/gltf-transform",
    ) {
        return;
    }
    let (_, fox) = demo_scenes();
    let packed = fox.with_file_name("fox-packed.glb");
    let o = Command::new(&gltfpack)
        .arg("-i")
        .arg(fox.with_file_name("fox.glb"))
        .arg("-o")
        .arg(&packed)
        .output()
        .expect("run gltfpack");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let scene = variant(&fox, "fox-packed", |v| {
        v["objects"][0]["asset"] = "fox-packed.glb".into();
        v["objects"][0]["material"] = serde_json::json!({ "kind": "opaque" });
    });
    let walk = ["--animation", "Walk", "--time", "0.35"];
    let (flip, _) = compare(&scene, "uv-transform", &walk, None);
    assert!(flip <= 0.05, "KHR_texture_transform: FLIP {flip}");
    let (flip, _) = compare(
        &scene,
        "uv-transform-control",
        &walk,
        Some("no-uv-transform"),
    );
    assert!(flip > 0.05, "the transform ignored passes (FLIP {flip})");
}
