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

/// A runtime drawing pelt's scene files: how to run it, and what a clean run's log is.
pub trait Runtime {
    /// Its name in the pictures' file names (`NAME-RUNTIME.png`).
    fn name(&self) -> &'static str;
    /// Draws `scene` to `out` at `size` with `extra` flags: its output whatever its status.
    fn run(&self, scene: &Path, out: &Path, size: &str, extra: &[&str]) -> std::process::Output;
    /// Panics unless `log` (a successful run's stderr) is clean.
    fn check_log(&self, scene: &Path, log: &str);
}

/// `rt` draws `scene` at 320×180, which must succeed with a clean log.
pub fn draw(rt: &dyn Runtime, scene: &Path, out: &Path, extra: &[&str]) {
    let o = rt.run(scene, out, "320x180", extra);
    let log = String::from_utf8_lossy(&o.stderr);
    assert!(
        o.status.success(),
        "{} {}: {log}",
        rt.name(),
        scene.display()
    );
    rt.check_log(scene, &log);
}

/// One comparison of `rt` against pelt with the same flags, and the negative control
/// `control` (`--control NAME`) on the runtime's side, if any.
pub fn compare_with(
    rt: &dyn Runtime,
    scene: &Path,
    name: &str,
    args: &[&str],
    control: Option<&str>,
) -> (f32, f64) {
    compare(scene, name, rt.name(), args, |out| {
        let mut e = args.to_vec();
        if let Some(c) = control {
            e.extend(["--control", c]);
        }
        draw(rt, scene, out, &e);
    })
}

/// The demo's creature, and its Fox at Walk 0.35 s, within FLIP 0.05 of pelt with 16 shells
/// and their fur's luminance within 10 %; every shell opaque fails the same threshold.
pub fn check_demo_scenes(rt: &dyn Runtime, creature: &Path, fox: &Path) {
    let shells = ["--shells", "16"];
    let walk = ["--shells", "16", "--animation", "Walk", "--time", "0.35"];
    for (scene, name, args) in [(creature, "creature", &shells[..]), (fox, "fox", &walk[..])] {
        let (flip, ratio) = compare_with(rt, scene, name, args, None);
        assert!(flip <= 0.05, "{name}: FLIP {flip} over 0.05");
        assert!(
            (ratio - 1.0).abs() <= 0.10,
            "{name}: fur luminance ratio {ratio}"
        );
        let control = format!("{name}-control");
        let (flip, _) = compare_with(rt, scene, &control, args, Some("opaque-shells"));
        assert!(
            flip > 0.05,
            "{name}: the negative control (opaque shells) passes with FLIP {flip}"
        );
    }
}

/// One feature per scene, each with the negative control that leaves it out of the runtime's
/// picture (which must then fail the same threshold): wind (a strong one at 0.7 s), shadows
/// (the creature lifted over the ground under a point and a directional light that cast
/// them; in the same scene the fur casting by its coverage, a finer threshold for a finer
/// feature) and a textured fur asset (the Fox's fur coloured by its base colour texture).
pub fn check_features(rt: &dyn Runtime, creature: &Path, fox: &Path) {
    let (wind, shadows) = feature_scenes(creature);
    let windy = ["--shells", "16", "--time", "0.7"];
    let still = ["--shells", "16"];
    let walk = ["--shells", "16", "--animation", "Walk", "--time", "0.35"];
    for (scene, name, args, control, threshold) in [
        (wind.as_path(), "wind", &windy[..], "no-wind", 0.05),
        (shadows.as_path(), "shadows", &still[..], "no-shadows", 0.05),
        (
            shadows.as_path(),
            "fur-shadow",
            &still[..],
            "no-fur-shadow",
            0.044,
        ),
        (fox, "textured", &walk[..], "no-texture", 0.05),
    ] {
        let (flip, _) = compare_with(rt, scene, name, args, None);
        assert!(flip <= threshold, "{name}: FLIP {flip} over {threshold}");
        let (flip, _) = compare_with(rt, scene, &format!("{name}-control"), args, Some(control));
        assert!(
            flip > threshold,
            "{name}: the negative control ({control}) passes with FLIP {flip}"
        );
    }
}

/// The Fox at two times of its Walk: each within FLIP 0.06 of pelt at that time, the two
/// frames differ, and the runtime's pose of the other time fails against pelt's (the fur
/// follows the skin).
pub fn check_clip(rt: &dyn Runtime, fox: &Path) {
    let dir = fox.parent().expect("folder").to_path_buf();
    let mut frames = Vec::new();
    for t in ["0.1", "0.6"] {
        let args = ["--shells", "16", "--animation", "Walk", "--time", t];
        let (flip, _) = compare_with(rt, fox, &format!("walk-{t}"), &args, None);
        assert!(flip <= 0.06, "Walk at {t}: FLIP {flip} over 0.06");
        frames.push(load_png(&dir.join(format!("walk-{t}-{}.png", rt.name()))));
    }
    let moved = flip_of(&frames[0], &frames[1]);
    assert!(
        moved > 0.01,
        "the two times drew the same frame (FLIP {moved})"
    );
    let pelt = load_png(&dir.join("walk-0.1-pelt.png"));
    let wrong = flip_of(&pelt, &frames[1]);
    assert!(
        wrong > 0.06,
        "the pose at 0.6 s passes against 0.1 s (FLIP {wrong})"
    );
}

/// The runtime's `--report` of `scene` at `size`: each fur mesh's shell count and whether
/// the rule set it.
pub fn report(rt: &dyn Runtime, scene: &Path, size: &str, extra: &[&str]) -> serde_json::Value {
    let out = scene.with_file_name(format!("{}-report-{size}.png", rt.name()));
    let o = rt.run(scene, &out, size, &[&["--report"][..], extra].concat());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).expect("JSON")
}

/// The shells-by-screen-size rule: the runtime draws the count pelt plans (`--explain`) at
/// every size, the count falls as the fur shrinks on screen, a forced count is kept, and the
/// two pictures agree without `--shells`.
pub fn check_rule(rt: &dyn Runtime, creature: &Path) {
    let mut counts = Vec::new();
    for size in ["160x90", "320x180", "1280x720"] {
        let r = report(rt, creature, size, &[]);
        let drawn = r["fur"][0]["shells"].as_u64().expect("a fur mesh");
        assert_eq!(r["fur"][0]["byScreenSize"], true);
        let planned = planned_shells(creature, size);
        assert_eq!(
            drawn,
            planned,
            "{size}: {} draws {drawn} shells, pelt plans {planned}",
            rt.name()
        );
        counts.push(drawn);
    }
    assert!(
        counts[0] < counts[1] && counts[1] < counts[2],
        "the count does not fall with size: {counts:?}"
    );
    let r = report(rt, creature, "160x90", &["--shells", "12"]);
    assert_eq!(
        (
            r["fur"][0]["shells"].as_u64(),
            r["fur"][0]["byScreenSize"].as_bool()
        ),
        (Some(12), Some(false))
    );
    let (flip, _) = compare_with(rt, creature, "rule", &[], None);
    assert!(flip <= 0.05, "by screen size: FLIP {flip}");
}

/// Bad input: each `(scene, extra flags, what the error must name)` exits 1 with that in its
/// message and writes no PNG; the good scene writes its PNG (the negative control).
pub fn check_bad_input(rt: &dyn Runtime, good: &Path, cases: &[(&Path, &[&str], &str)]) {
    for (scene, extra, want) in cases {
        let out = scene.with_file_name(format!("{}-bad.png", rt.name()));
        let o = rt.run(scene, &out, "64x36", extra);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{}: {err}", scene.display());
        assert!(err.contains(want), "{want} not in: {err}");
        assert!(!out.exists(), "{} was written", out.display());
    }
    let out = good.with_file_name(format!("{}-good.png", rt.name()));
    draw(rt, good, &out, &[]);
    assert!(out.exists());
}
