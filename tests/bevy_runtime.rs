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

/// `render SCENE -o OUT --size SIZE EXTRA…` on Vulkan (lavapipe here), its output whatever
/// its status.
fn render(scene: &Path, out: &Path, size: &str, extra: &[&str]) -> Output {
    Command::new(example())
        .arg(scene)
        .args(["-o", out.to_str().expect("UTF-8"), "--size", size])
        .args(extra)
        .env("WGPU_BACKEND", "vulkan")
        .env("RUST_LOG", "error")
        .output()
        .expect("run the render example")
}

/// The Bevy plugin as the shared checks run it: the `render` example, whose clean log has
/// no error.
struct Bevy;

impl runtime::Runtime for Bevy {
    fn name(&self) -> &'static str {
        "bevy"
    }

    fn run(&self, scene: &Path, out: &Path, size: &str, extra: &[&str]) -> Output {
        render(scene, out, size, extra)
    }

    fn check_log(&self, _scene: &Path, log: &str) {
        assert!(!log.contains("ERROR"), "errors: {log}");
    }
}

fn bevy(scene: &Path, out: &Path, extra: &[&str]) {
    runtime::draw(&Bevy, scene, out, extra);
}

fn compare(scene: &Path, name: &str, args: &[&str], control: Option<&str>) -> (f32, f64) {
    runtime::compare_with(&Bevy, scene, name, args, control)
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
    runtime::check_demo_scenes(&Bevy, &creature, &fox);
}

#[test]
fn each_feature_matches_and_its_negative_control_does_not() {
    if !bevy_ready() {
        return;
    }
    let (creature, fox) = demo_scenes();
    runtime::check_features(&Bevy, &creature, &fox);
}

#[test]
fn a_skinned_asset_follows_its_clip() {
    if !bevy_ready() {
        return;
    }
    let (_, fox) = demo_scenes();
    runtime::check_clip(&Bevy, &fox);
}

#[test]
fn the_shell_count_follows_the_fur_on_screen_as_in_pelt() {
    if !bevy_ready() {
        return;
    }
    let (creature, _) = demo_scenes();
    runtime::check_rule(&Bevy, &creature);
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
    let gallop: &[&str] = &["--animation", "Gallop"];
    runtime::check_bad_input(
        &Bevy,
        &creature,
        &[
            (&missing_asset, &[], "objects[0].asset"),
            (&malformed, &[], "bevy-bad-json.json"),
            (&absent, &[], "bevy-absent.json"),
            (
                &fox,
                gallop,
                "no animation \"Gallop\" (has Run, Survey, Walk)",
            ),
        ],
    );
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
