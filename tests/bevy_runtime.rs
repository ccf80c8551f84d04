//! The Bevy plugin (`integrations/bevy_pelt`) against pelt's forward mode, both rendering the
//! demo's scene files at 320×180: the plugin's `render` example on lavapipe and `pelt render
//! --mode forward` with the same shell count. Whole-image FLIP and the fur's mean luminance;
//! a negative control (every shell opaque) fails the same threshold. The example is built by
//! `cargo build --release --manifest-path integrations/bevy_pelt/Cargo.toml --examples` (its
//! own workspace: Bevy is on wgpu 29); without it the tests skip, unless PELT_REQUIRE_BEVY is
//! set (CI sets it).

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::runtime;
use common::*;

fn example() -> PathBuf {
    root().join("integrations/bevy_pelt/target/release/examples/render")
}

fn bevy_ready() -> bool {
    tool_available(
        example().exists(),
        "PELT_REQUIRE_BEVY",
        "the bevy_pelt render example",
        "cargo build --release --manifest-path integrations/bevy_pelt/Cargo.toml --examples",
    )
}

/// `render SCENE -o OUT --size 320x180 EXTRA…` on Vulkan (lavapipe here), its output.
fn render(scene: &Path, out: &Path, extra: &[&str]) -> Output {
    Command::new(example())
        .arg(scene)
        .args(["-o", out.to_str().expect("UTF-8"), "--size", "320x180"])
        .args(extra)
        .env("WGPU_BACKEND", "vulkan")
        .env("RUST_LOG", "error")
        .output()
        .expect("run the render example")
}

fn bevy(scene: &Path, out: &Path, extra: &[&str]) {
    let o = render(scene, out, extra);
    let log = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "render {}: {log}", scene.display());
    assert!(!log.contains("ERROR"), "errors: {log}");
}

fn compare(scene: &Path, name: &str, args: &[&str], control: Option<&str>) -> (f32, f64) {
    runtime::compare(scene, name, "bevy", args, |out| {
        let mut e = args.to_vec();
        if let Some(c) = control {
            e.extend(["--control", c]);
        }
        bevy(scene, out, &e);
    })
}

fn demo_scenes() -> (PathBuf, PathBuf) {
    runtime::demo_scenes("bevy-demo")
}

#[test]
fn bevy_draws_the_demo_scenes_as_pelt_forward_does() {
    if !bevy_ready() {
        return;
    }
    let (creature, fox) = demo_scenes();
    let shells = ["--shells", "16"];
    let walk = ["--shells", "16", "--animation", "Walk", "--time", "0.35"];
    for (scene, name, args) in [
        (&creature, "creature", &shells[..]),
        (&fox, "fox", &walk[..]),
    ] {
        let (flip, ratio) = compare(scene, name, args, None);
        assert!(flip <= 0.05, "{name}: FLIP {flip} over 0.05");
        assert!(
            (ratio - 1.0).abs() <= 0.10,
            "{name}: fur luminance ratio {ratio}"
        );
        let control = format!("{name}-control");
        let (flip, _) = compare(scene, &control, args, Some("opaque-shells"));
        assert!(
            flip > 0.05,
            "{name}: the negative control (opaque shells) passes with FLIP {flip}"
        );
    }
}

/// One feature per scene, each with the negative control that leaves it out of Bevy's
/// picture (which must then fail the same threshold): wind (a strong one at 0.7 s), shadows
/// (the creature lifted over the ground under a point and a directional light that cast
/// them; in the same scene the fur casting by its coverage) and a textured fur asset (the
/// Fox's fur coloured by its base colour texture).
#[test]
fn each_feature_matches_and_its_negative_control_does_not() {
    if !bevy_ready() {
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
        (&shadows, "fur-shadow", &still[..], "no-fur-shadow", 0.044),
        (&fox, "textured", &walk[..], "no-texture", 0.05),
    ] {
        let (flip, _) = compare(scene, name, args, None);
        assert!(flip <= threshold, "{name}: FLIP {flip} over {threshold}");
        let (flip, _) = compare(scene, &format!("{name}-control"), args, Some(control));
        assert!(
            flip > threshold,
            "{name}: the negative control ({control}) passes with FLIP {flip}"
        );
    }
}

/// The Fox at two times of its Walk: each within FLIP 0.06 of pelt at that time, the two
/// frames differ, and the pose of the other time fails against pelt's (the fur follows the
/// skin).
#[test]
fn a_skinned_asset_follows_its_clip() {
    if !bevy_ready() {
        return;
    }
    let (_, fox) = demo_scenes();
    let dir = fox.parent().expect("folder").to_path_buf();
    let mut frames = Vec::new();
    for t in ["0.1", "0.6"] {
        let args = ["--shells", "16", "--animation", "Walk", "--time", t];
        let (flip, _) = compare(&fox, &format!("walk-{t}"), &args, None);
        assert!(flip <= 0.06, "Walk at {t}: FLIP {flip} over 0.06");
        frames.push(load_png(&dir.join(format!("walk-{t}-bevy.png"))));
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

/// `render SCENE --size SIZE --report EXTRA…`: each fur primitive's shell count and whether
/// the rule set it.
fn report(scene: &Path, size: &str, extra: &[&str]) -> serde_json::Value {
    let out = scene.with_file_name(format!("bevy-report-{size}.png"));
    let o = Command::new(example())
        .arg(scene)
        .args([
            "-o",
            out.to_str().expect("UTF-8"),
            "--size",
            size,
            "--report",
        ])
        .args(extra)
        .env("WGPU_BACKEND", "vulkan")
        .env("RUST_LOG", "error")
        .output()
        .expect("run the render example");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).expect("JSON")
}

/// The shells-by-screen-size rule: Bevy draws the count pelt plans (`--explain`) at every
/// size, the count falls as the fur shrinks on screen, a forced count is kept, and the two
/// pictures agree without `--shells`.
#[test]
fn the_shell_count_follows_the_fur_on_screen_as_in_pelt() {
    if !bevy_ready() {
        return;
    }
    let (creature, _) = demo_scenes();
    let mut counts = Vec::new();
    for size in ["160x90", "320x180", "1280x720"] {
        let r = report(&creature, size, &[]);
        let drawn = r["fur"][0]["shells"].as_u64().expect("a fur primitive");
        assert_eq!(r["fur"][0]["byScreenSize"], true);
        let planned = runtime::planned_shells(&creature, size);
        assert_eq!(
            drawn, planned,
            "{size}: Bevy draws {drawn} shells, pelt plans {planned}"
        );
        counts.push(drawn);
    }
    assert!(
        counts[0] < counts[1] && counts[1] < counts[2],
        "the count does not fall with size: {counts:?}"
    );
    let r = report(&creature, "160x90", &["--shells", "12"]);
    assert_eq!(
        (
            r["fur"][0]["shells"].as_u64(),
            r["fur"][0]["byScreenSize"].as_bool()
        ),
        (Some(12), Some(false))
    );
    let (flip, _) = compare(&creature, "rule", &[], None);
    assert!(flip <= 0.05, "by screen size: FLIP {flip}");
}

/// Bad input to the render example: a missing asset, a malformed scene file, a missing one
/// and a missing animation are errors naming the file and the place, exit 1, and no PNG.
#[test]
fn bad_scene_files_are_errors_naming_the_place_and_write_nothing() {
    if !bevy_ready() {
        return;
    }
    let (creature, fox) = demo_scenes();
    let missing_asset = runtime::variant(&creature, "bevy-bad-asset", |v| {
        v["objects"][0]["asset"] = "missing.glb".into();
    });
    let malformed = creature.with_file_name("bevy-bad-json.json");
    std::fs::write(&malformed, b"{\"objects\": [").expect("write");
    let absent = creature.with_file_name("bevy-absent.json");
    let cases: [(&Path, &[&str], &str); 4] = [
        (&missing_asset, &[], "objects[0].asset"),
        (&malformed, &[], "bevy-bad-json.json"),
        (&absent, &[], "bevy-absent.json"),
        (
            &fox,
            &["--animation", "Gallop"],
            "no animation \"Gallop\" (has Run, Survey, Walk)",
        ),
    ];
    for (scene, extra, want) in cases {
        let out = scene.with_file_name("bevy-bad.png");
        let o = render(scene, &out, extra);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{}: {err}", scene.display());
        assert!(err.contains(want), "{want} not in: {err}");
        assert!(!out.exists(), "{} was written", out.display());
    }
    let out = creature.with_file_name("bevy-good.png");
    bevy(&creature, &out, &[]);
    assert!(out.exists());
}

/// The fins (pelt's silhouette fins from the baked records, on with `"fins": true`): the
/// creature within a finer threshold than the whole-image floor (the fins hold a thin rim of
/// the picture), which Bevy without its fins fails; and the walking Fox's fins, skinned with
/// it, within the floor.
#[test]
fn the_fins_match_pelts() {
    if !bevy_ready() {
        return;
    }
    let (creature, fox) = demo_scenes();
    let fins = runtime::variant(&creature, "feature-fins", |v| {
        v["objects"][0]["material"]["fins"] = true.into();
    });
    let args = ["--shells", "16"];
    let draw = |extra: &'static [&'static str]| {
        let scene = fins.clone();
        move |out: &Path| bevy(&scene, out, &[&args[..], extra].concat())
    };
    let (flip, _) = runtime::compare(&fins, "fins", "bevy", &args, draw(&[]));
    assert!(flip <= 0.021, "fins: FLIP {flip} over 0.021");
    let (flip, _) = runtime::compare(
        &fins,
        "fins-control",
        "bevy",
        &args,
        draw(&["--fins", "off"]),
    );
    assert!(
        flip > 0.021,
        "without its fins Bevy passes with FLIP {flip}"
    );
    let walk = [
        "--shells",
        "16",
        "--fins",
        "on",
        "--animation",
        "Walk",
        "--time",
        "0.35",
    ];
    let (flip, _) = compare(&fox, "fins-walk", &walk, None);
    assert!(
        flip <= 0.05,
        "the walking Fox's fins: FLIP {flip} over 0.05"
    );
}
