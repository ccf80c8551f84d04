//! What the runtime tests share (tests/three_runtime.rs, tests/bevy_runtime.rs): the demo's
//! scene files, `pelt render --mode forward` at 320×180, and one comparison of a runtime's
//! picture against pelt's: whole-image FLIP and the fur's mean luminance, the fur's pixels
//! being where pelt's picture changes without the fur object.

use std::path::{Path, PathBuf};
use std::process::Command;

use super::{flip_of, load_png, pelt_ok, scratch};

/// The demo's scene files (the creature's, and the Fox's without its springs), made once for
/// the tests of a binary, in scratch folder `name`.
pub fn demo_scenes(name: &str) -> (PathBuf, PathBuf) {
    static DEMO: std::sync::OnceLock<(PathBuf, PathBuf)> = std::sync::OnceLock::new();
    DEMO.get_or_init(|| make_demo(&scratch(name))).clone()
}

fn make_demo(dir: &Path) -> (PathBuf, PathBuf) {
    let o = Command::new(env!("CARGO_BIN_EXE_pelt"))
        .arg("demo")
        .current_dir(dir)
        .output()
        .expect("pelt demo");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let demo = dir.join("out/demo");
    let mut fox: serde_json::Value =
        serde_json::from_slice(&std::fs::read(demo.join("fox.json")).expect("fox.json"))
            .expect("JSON");
    for o in fox["objects"].as_array_mut().expect("objects") {
        if let Some(m) = o["material"].as_object_mut() {
            m.remove("spring");
        }
    }
    let fox_path = demo.join("fox-still.json");
    std::fs::write(&fox_path, serde_json::to_vec_pretty(&fox).expect("JSON")).expect("write");
    (demo.join("scene.json"), fox_path)
}

/// `pelt render SCENE --mode forward --size 320x180 -o OUT EXTRA…`.
pub fn forward(scene: &Path, out: &Path, extra: &[&str]) {
    let mut args = vec![
        "render",
        scene.to_str().expect("UTF-8"),
        "--mode",
        "forward",
        "--size",
        "320x180",
        "-o",
        out.to_str().expect("UTF-8"),
        "-q",
    ];
    args.extend_from_slice(extra);
    pelt_ok(&args);
}

/// Mean luminance (8-bit sRGB values, Rec. 709 weights) of `img` where `mask` is set.
pub fn luminance(img: &pelt_preview::Image, mask: &[bool]) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for (p, _) in img.rgba.chunks_exact(4).zip(mask).filter(|(_, m)| **m) {
        sum += 0.2126 * f64::from(p[0]) + 0.7152 * f64::from(p[1]) + 0.0722 * f64::from(p[2]);
        n += 1;
    }
    sum / n.max(1) as f64
}

/// One comparison: pelt's picture of `scene` (`NAME-pelt.png`) against the runtime's
/// (`NAME-RUNTIME.png`, which `draw` writes): FLIP and the fur's luminance ratio
/// (runtime / pelt).
pub fn compare(
    scene: &Path,
    name: &str,
    runtime: &str,
    extra_pelt: &[&str],
    draw: impl FnOnce(&Path),
) -> (f32, f64) {
    let dir = scene.parent().expect("folder");
    let (p, t) = (
        dir.join(format!("{name}-pelt.png")),
        dir.join(format!("{name}-{runtime}.png")),
    );
    forward(scene, &p, extra_pelt);
    draw(&t);
    let (a, b) = (load_png(&p), load_png(&t));
    let flip = flip_of(&a, &b);
    let mut bare: serde_json::Value =
        serde_json::from_slice(&std::fs::read(scene).expect("scene")).expect("JSON");
    bare["objects"].as_array_mut().expect("objects").remove(0);
    let bare_path = dir.join(format!("{name}-bare.json"));
    std::fs::write(&bare_path, serde_json::to_vec(&bare).expect("JSON")).expect("write");
    let bp = dir.join(format!("{name}-bare.png"));
    forward(&bare_path, &bp, extra_pelt);
    let c = load_png(&bp);
    let mask: Vec<bool> = a
        .rgba
        .chunks_exact(4)
        .zip(c.rgba.chunks_exact(4))
        .map(|(x, y)| (0..3).any(|k| x[k].abs_diff(y[k]) > 8))
        .collect();
    let ratio = luminance(&b, &mask) / luminance(&a, &mask);
    eprintln!(
        "{name}: FLIP {flip:.4}, fur luminance {runtime}/pelt {ratio:.3} over {} px",
        mask.iter().filter(|m| **m).count()
    );
    (flip, ratio)
}

/// `scene` (JSON) with `edit` applied, written beside it as `name.json`.
pub fn variant(scene: &Path, name: &str, edit: impl FnOnce(&mut serde_json::Value)) -> PathBuf {
    let mut v: serde_json::Value =
        serde_json::from_slice(&std::fs::read(scene).expect("scene")).expect("JSON");
    edit(&mut v);
    let path = scene.with_file_name(format!("{name}.json"));
    std::fs::write(&path, serde_json::to_vec_pretty(&v).expect("JSON")).expect("write");
    path
}

/// The feature scenes of the runtime tests, beside `creature`: wind (a strong one), and
/// shadows (the creature lifted over the ground under a point and a directional light that
/// cast them).
pub fn feature_scenes(creature: &Path) -> (PathBuf, PathBuf) {
    let wind = variant(creature, "feature-wind", |v| {
        v["wind"] = serde_json::json!({
            "direction": [1.0, 0.0, 0.3], "strength": 2.0, "gustHz": 0.8, "turbulence": 0.5
        });
    });
    let shadows = variant(creature, "feature-shadows", |v| {
        v["lights"][0]["shadows"] = true.into();
        v["objects"][0]["transform"]["translation"] = serde_json::json!([0.0, 0.35, 0.0]);
        v["lights"]
            .as_array_mut()
            .expect("lights")
            .push(serde_json::json!({
                "kind": "directional", "direction": [-0.4, -1.0, -0.3],
                "color": [1.0, 0.95, 0.9], "intensity": 1.2, "shadows": true
            }));
    });
    (wind, shadows)
}

/// The shells pelt plans for the first fur object of `scene` at `size` (`--explain`).
pub fn planned_shells(scene: &Path, size: &str) -> u64 {
    let explain = pelt_ok(&[
        "render",
        scene.to_str().expect("UTF-8"),
        "--explain",
        "--size",
        size,
    ]);
    let text = String::from_utf8_lossy(&explain.stdout);
    text.split("base + ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no shell count in {text}"))
}
