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

fn three(scene: &Path, out: &Path, extra: &[&str]) {
    let o = render_mjs(scene, out, "320x180", extra);
    let log = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "render.mjs {}: {log}", scene.display());
    assert!(!log.contains("browser:"), "console errors: {log}");
}

/// One comparison of the three.js runtime against pelt (`render.mjs` with `extra_three` and
/// the negative control `control`, if any).
fn compare(
    scene: &Path,
    name: &str,
    extra_pelt: &[&str],
    extra_three: &[&str],
    control: Option<&str>,
) -> (f32, f64) {
    runtime::compare(scene, name, "three", extra_pelt, |out| {
        let mut e = extra_three.to_vec();
        if let Some(c) = control {
            e.extend(["--control", c]);
        }
        three(scene, out, &e);
    })
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
    let shells = ["--shells", "16"];
    let walk = ["--shells", "16", "--animation", "Walk", "--time", "0.35"];
    for (scene, name, args) in [
        (&creature, "creature", &shells[..]),
        (&fox, "fox", &walk[..]),
    ] {
        let (flip, ratio) = compare(scene, name, args, args, None);
        assert!(flip <= 0.05, "{name}: FLIP {flip} over 0.05");
        assert!(
            (ratio - 1.0).abs() <= 0.10,
            "{name}: fur luminance ratio {ratio}"
        );
        let (flip, _) = compare(
            scene,
            &format!("{name}-control"),
            args,
            args,
            Some("opaque-shells"),
        );
        assert!(
            flip > 0.05,
            "{name}: the negative control (opaque shells) passes with FLIP {flip}"
        );
    }
}

/// One feature per scene, each with the negative control that leaves it out of the web
/// image (which must then fail the same threshold): wind (a strong one at 0.7 s), shadows
/// (the creature lifted over the ground under a point and a directional light that cast
/// them; and in the same scene the fur casting by its coverage) and a textured fur asset (the Fox's fur coloured by its base colour texture).
#[test]
fn each_feature_matches_and_its_negative_control_does_not() {
    if !browser_ready() {
        return;
    }
    let (creature, fox) = demo_scenes();
    let (wind, shadows) = runtime::feature_scenes(&creature);
    let windy = ["--shells", "16", "--time", "0.7"];
    let still = ["--shells", "16"];
    let walk = ["--shells", "16", "--animation", "Walk", "--time", "0.35"];
    for (scene, name, args, control, threshold) in [
        (&wind, "wind", &windy[..], "no-wind", 0.05),
        (&shadows, "shadows", &still[..], "no-shadows", 0.05),
        // The fur casting by its coverage (hashed through its layers) rather than as its
        // base mesh: a finer threshold for a finer feature.
        (&shadows, "fur-shadow", &still[..], "no-fur-shadow", 0.044),
        (&fox, "textured", &walk[..], "no-texture", 0.05),
    ] {
        let (flip, _) = compare(scene, name, args, args, None);
        assert!(flip <= threshold, "{name}: FLIP {flip} over {threshold}");
        let (flip, _) = compare(scene, &format!("{name}-control"), args, args, Some(control));
        assert!(
            flip > threshold,
            "{name}: the negative control ({control}) passes with FLIP {flip}"
        );
    }
}

#[test]
fn a_skinned_asset_follows_its_clip() {
    if !browser_ready() {
        return;
    }
    let (_, fox) = demo_scenes();
    let dir = fox.parent().expect("folder").to_path_buf();
    let mut frames = Vec::new();
    for t in ["0.1", "0.6"] {
        let args = ["--shells", "16", "--animation", "Walk", "--time", t];
        let (flip, _) = compare(&fox, &format!("walk-{t}"), &args, &args, None);
        assert!(flip <= 0.06, "Walk at {t}: FLIP {flip} over 0.06");
        frames.push(load_png(&dir.join(format!("walk-{t}-three.png"))));
    }
    let moved = flip_of(&frames[0], &frames[1]);
    assert!(
        moved > 0.01,
        "the two times drew the same frame (FLIP {moved})"
    );
    // Negative control: the web pose of the other time fails the same threshold against
    // pelt's (a runtime whose fur did not follow the clip would).
    let pelt = load_png(&dir.join("walk-0.1-pelt.png"));
    let wrong = flip_of(&pelt, &frames[1]);
    assert!(
        wrong > 0.06,
        "the pose at 0.6 s passes against 0.1 s (FLIP {wrong})"
    );
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

/// `render.mjs SCENE --size SIZE --report EXTRA…`: each fur mesh's shell count and whether
/// the rule set it.
fn report(scene: &Path, size: &str, extra: &[&str]) -> serde_json::Value {
    let out = scene.with_file_name(format!("report-{size}.png"));
    let o = render_mjs(scene, &out, size, &[&["--report"][..], extra].concat());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).expect("JSON")
}

/// The shells-by-screen-size rule: the web runtime draws the count pelt plans (`--explain`)
/// at every size, the count falls as the fur shrinks on screen, a forced count is kept, and
/// the two images agree without `--shells`.
#[test]
fn the_shell_count_follows_the_fur_on_screen_as_in_pelt() {
    if !browser_ready() {
        return;
    }
    let (creature, _) = demo_scenes();
    let mut counts = Vec::new();
    for size in ["160x90", "320x180", "1280x720"] {
        let r = report(&creature, size, &[]);
        let web = r["fur"][0]["shells"].as_u64().expect("a fur mesh");
        assert_eq!(r["fur"][0]["byScreenSize"], true);
        let planned = runtime::planned_shells(&creature, size);
        assert_eq!(
            web, planned,
            "{size}: three draws {web} shells, pelt plans {planned}"
        );
        counts.push(web);
    }
    assert!(
        counts[0] < counts[1] && counts[1] < counts[2],
        "the count does not fall with size: {counts:?}"
    );
    // Forced, the count stays (the negative control of the rule).
    let r = report(&creature, "160x90", &["--shells", "12"]);
    assert_eq!(
        (
            r["fur"][0]["shells"].as_u64(),
            r["fur"][0]["byScreenSize"].as_bool()
        ),
        (Some(12), Some(false))
    );
    let (flip, _) = compare(&creature, "rule", &[], &[], None);
    assert!(flip <= 0.05, "by screen size: FLIP {flip}");
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
    for (scene, want) in [
        (&missing_asset, "objects[0]: missing.glb"),
        (&malformed, "bad-json.json"),
        (&absent, "absent.json: no such file"),
    ] {
        let out = scene.with_extension("png");
        let o = render_mjs(scene, &out, "64x36", &[]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{}: {err}", scene.display());
        assert!(err.contains(want), "{want} not in: {err}");
        assert!(!out.exists(), "{} was written", out.display());
    }
    // Negative control: the good scene writes its PNG.
    let out = creature.with_file_name("good.png");
    three(&creature, &out, &[]);
    assert!(out.exists());
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
    let (flip, _) = compare(&scene, "uv-transform", &walk, &walk, None);
    assert!(flip <= 0.05, "KHR_texture_transform: FLIP {flip}");
    let (flip, _) = compare(
        &scene,
        "uv-transform-control",
        &walk,
        &walk,
        Some("no-uv-transform"),
    );
    assert!(flip > 0.05, "the transform ignored passes (FLIP {flip})");
}
