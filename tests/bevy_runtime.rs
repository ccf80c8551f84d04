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
