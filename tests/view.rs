//! `pelt view` end to end in a real window under Xvfb (`xvfb-run`, Debian `xvfb` and
//! `xauth`), on the back end `PELT_BACKEND` names (CI runs GL and Vulkan): the scripted mode's
//! screenshot equals `pelt render` of the same input, size, camera and knobs; after a scripted
//! orbit drawn under a tight frame budget, the still frame equals the full-quality render of
//! the final camera; strands mode refines a still frame toward the converged reference. Also
//! `pelt render --bench --orbit --json` (frame 0 uploads the asset,
//! later frames only uniforms) and a quiet successful render (no "error:" line).
//!
//! Without `xvfb-run` the window tests are skipped, unless `PELT_REQUIRE_XVFB` is set (CI sets
//! it, so there a missing Xvfb fails).

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::*;
use pelt_preview::Image;

fn backend() -> String {
    std::env::var("PELT_BACKEND").unwrap_or_else(|_| "auto".into())
}

/// Whether the window tests can run here.
fn have_xvfb() -> bool {
    let found = Command::new("xvfb-run")
        .arg("--help")
        .output()
        .is_ok_and(|o| o.status.success() || !o.stdout.is_empty());
    tool_available(
        found,
        "PELT_REQUIRE_XVFB",
        "xvfb-run",
        "apt-get install xvfb xauth",
    )
}

/// `pelt view ARGS` in a fresh X server.
fn view(args: &[&str]) -> Output {
    let b = backend();
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 640x480x24"])
        .arg(env!("CARGO_BIN_EXE_pelt"))
        .args(["view", "--backend", &b])
        .args(args)
        .current_dir(root())
        .output()
        .expect("run xvfb-run");
    assert!(
        out.status.success(),
        "pelt view {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn flip(reference: &Image, test: &Image) -> f32 {
    pelt_measure::Flip::new(reference, test)
        .expect("images of one size")
        .mean()
}

/// The fixture creature baked with fur (the demo's asset, smaller textures' config).
fn furry(dir: &Path) -> PathBuf {
    bake(
        &fixture("creature.glb"),
        dir,
        &["--config", fixture("fur.json").to_str().expect("utf8")],
    )
}

fn s(p: &Path) -> &str {
    p.to_str().expect("utf8")
}

/// `pelt view ARGS --screenshot DIR/NAME --size 192x128` (with `--play` when `play`): the
/// window's last frame and the log.
fn screenshot(dir: &Path, name: &str, args: &[&str], play: bool) -> (Image, String) {
    let shot = dir.join(name);
    let mut all = args.to_vec();
    all.extend(["--screenshot", s(&shot), "--size", "192x128"]);
    if play {
        all.push("--play");
    }
    let out = view(&all);
    (
        load_png(&shot),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `pelt render ASSET -o DIR/NAME --size 192x128 EXTRA` on the test's back end, read back.
fn render_png(dir: &Path, asset: &Path, name: &str, extra: &[&str]) -> Image {
    let path = dir.join(name);
    let b = backend();
    let mut args = vec![
        "render",
        "--backend",
        &b,
        s(asset),
        "-o",
        s(&path),
        "--size",
        "192x128",
    ];
    args.extend_from_slice(extra);
    pelt_ok(&args);
    load_png(&path)
}

#[test]
fn a_scripted_screenshot_equals_pelt_render() {
    if !have_xvfb() {
        return;
    }
    let dir = scratch("view-screenshot");
    let asset = furry(&dir);
    let shot = dir.join("view.png");
    let out = view(&[
        s(&asset),
        "--frames",
        "3",
        "--screenshot",
        s(&shot),
        "--size",
        "192x128",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.lines().any(|l| l.starts_with("error:")), "{err}");
    let render = |name: &str, extra: &[&str]| render_png(&dir, &asset, name, extra);
    let reference = render("render.png", &[]);
    let got = load_png(&shot);
    let f = flip(&reference, &got);
    eprintln!("view screenshot against pelt render: FLIP {f:.5} ({err})");
    assert!(f <= 0.01, "FLIP {f} > 0.01");
    // Negative control: the comparison sees a change of one knob. (Not the shell count: with
    // analytic coverage 2 shells already come within FLIP 0.006 of 16 on this small asset.)
    let other = render("render-binary.png", &["--fur-coverage", "binary"]);
    let g = flip(&other, &got);
    eprintln!("against binary coverage: FLIP {g:.5}");
    assert!(
        g > 0.01,
        "the check cannot tell binary coverage from analytic: {g}"
    );
}

#[test]
fn the_still_frame_after_a_budgeted_orbit_equals_the_full_quality_render() {
    if !have_xvfb() {
        return;
    }
    let dir = scratch("view-orbit");
    let asset = furry(&dir);
    let (w, h) = (192, 128);
    let shot = dir.join("still.png");
    // A 1 ms budget forces every moving frame down to the floors.
    let out = view(&[
        s(&asset),
        "--frames",
        "6",
        "--orbit",
        "15",
        "--budget-ms",
        "1",
        "--screenshot",
        s(&shot),
        "--size",
        "192x128",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.lines().filter(|l| l.contains("(moving: ")).count() >= 3,
        "the moving frames were drawn at reduced quality: {err}"
    );
    // The final camera: the default framing turned 5 × 15° about its target.
    let mesh = pelt_preview::asset::load(&asset).expect("asset");
    let mut scene = pelt_preview::framing::asset_scene(&asset, &mesh, w, h);
    let mut orbit = pelt_preview::orbit::Orbit::new(&scene.camera);
    for _ in 0..5 {
        orbit.rotate(15f32.to_radians(), 0.0);
    }
    scene.camera = orbit.camera();
    let scene_path = dir.join("final.json");
    std::fs::write(&scene_path, serde_json::to_string(&scene).expect("json")).expect("write");
    let reference = dir.join("final.png");
    let b = backend();
    pelt_ok(&[
        "render",
        "--backend",
        &b,
        s(&scene_path),
        "-o",
        s(&reference),
    ]);
    let f = flip(&load_png(&reference), &load_png(&shot));
    eprintln!("still frame after the orbit against the full-quality render: FLIP {f:.5}");
    assert!(f <= 0.005, "FLIP {f} > 0.005");
}

#[test]
fn an_orbit_bench_uploads_the_asset_once_then_only_uniforms() {
    let dir = scratch("view-bench");
    let asset = furry(&dir);
    let b = backend();
    let out = pelt_ok(&[
        "render",
        "--backend",
        &b,
        s(&asset),
        "--size",
        "160x90",
        "--bench",
        "5",
        "--orbit",
        "12",
        "--json",
        "-q",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    let frames = v["frames"].as_array().expect("frames");
    assert_eq!(frames.len(), 5);
    let bytes = |f: &serde_json::Value| f["upload_bytes"].as_u64().expect("upload_bytes");
    let file = std::fs::metadata(&asset).expect("asset").len();
    // Frame 0 uploads the mesh, fur vertices, fins and every mip of the fur textures: at
    // least half the file's bytes (the file also holds what the preview does not draw).
    let first = bytes(&frames[0]);
    assert!(first > file / 2, "frame 0: {first} of a {file}-byte asset");
    for (k, f) in frames.iter().enumerate().skip(1) {
        assert!(f["ms"].as_f64().is_some_and(|ms| ms > 0.0));
        let b = bytes(f);
        assert!(b > 0 && b <= 16 * 1024, "frame {k} uploaded {b} bytes");
    }
    // The profile: every pass with its time, encode time and counts; the furry asset's
    // geometry pass draws its body and outer shell.
    let profile = v["profile"]["profile"].as_array().expect("profile");
    let pass = |name: &str| {
        profile
            .iter()
            .find(|p| p["pass"] == name)
            .unwrap_or_else(|| panic!("no {name} in {profile:?}"))
    };
    assert_eq!(pass("geometry")["draws"], 2);
    assert!(pass("material")["triangles"].as_u64() > pass("geometry")["triangles"].as_u64());
    assert!(
        v["profile"]["encode_ms"]
            .as_f64()
            .is_some_and(|ms| ms > 0.0)
    );
}

#[test]
fn a_successful_render_prints_no_error_line_without_a_runtime_dir() {
    let dir = scratch("view-quiet");
    let out_png = dir.join("quiet.png");
    let b = backend();
    let out = Command::new(env!("CARGO_BIN_EXE_pelt"))
        .args(["render", "--backend", &b])
        .arg(fixture("torus.glb"))
        .arg("-o")
        .arg(&out_png)
        .args(["--size", "64x48"])
        .env_remove("XDG_RUNTIME_DIR")
        .output()
        .expect("run pelt");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        !err.lines().any(|l| l.trim_start().starts_with("error:")),
        "a successful render printed an error line: {err}"
    );
    // A real error still shows.
    let bad = Command::new(env!("CARGO_BIN_EXE_pelt"))
        .args(["render", "--backend", &b, "no-such.glb", "-o"])
        .arg(dir.join("never.png"))
        .env_remove("XDG_RUNTIME_DIR")
        .output()
        .expect("run pelt");
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("no-such.glb"));
}

#[test]
fn the_overlay_draws_text_over_the_window_and_nothing_else() {
    if !have_xvfb() {
        return;
    }
    let dir = scratch("view-overlay");
    let asset = furry(&dir);
    let shot = dir.join("overlay.png");
    let out = view(&[
        s(&asset),
        "--frames",
        "2",
        "--overlay",
        "--screenshot",
        s(&shot),
        "--size",
        "256x160",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    if !err.contains("the window's last frame") {
        // This surface cannot be read back (GL): the screenshot is rendered offscreen and
        // carries no overlay, so there is nothing to check here.
        eprintln!("skipped: the screenshot is not the window's frame ({err})");
        return;
    }
    let reference = dir.join("render.png");
    let b = backend();
    pelt_ok(&[
        "render",
        "--backend",
        &b,
        s(&asset),
        "-o",
        s(&reference),
        "--size",
        "256x160",
    ]);
    let (r, v) = (load_png(&reference), load_png(&shot));
    // Text: pure white pixels in the top-left box that the render does not have.
    let white = |i: &Image, x, y| i.pixel(x, y)[..3] == [255, 255, 255];
    let text = (8..250)
        .flat_map(|x| (8..40).map(move |y| (x, y)))
        .filter(|&(x, y)| white(&v, x, y) && !white(&r, x, y))
        .count();
    assert!(text > 100, "{text} text pixels in the overlay box");
    // Below the box the frame is the render's.
    let below = |i: &Image| i.rgba[(64 * 256 * 4) as usize..].to_vec();
    assert!(
        below(&v) == below(&r),
        "the overlay changed pixels outside its box"
    );
}

/// The Fox baked with a generated comb (its fur from the bake's default config).
fn fox(dir: &Path) -> PathBuf {
    bake(&fixture("fox/Fox.glb"), dir, &["--comb", "generate"])
}

#[test]
fn an_animated_asset_plays_in_the_window_and_a_paused_frame_equals_pelt_render() {
    if !have_xvfb() {
        return;
    }
    let dir = scratch("view-animation");
    let asset = fox(&dir);
    let b = backend();
    let shoot = |name: &str, time: &str, play: bool| {
        let args = [
            s(&asset),
            "--animation",
            "Walk",
            "--time",
            time,
            "--frames",
            "3",
        ];
        screenshot(&dir, name, &args, play)
    };
    let render = |name: &str, time: &str| {
        render_png(&dir, &asset, name, &["--animation", "Walk", "--time", time])
    };
    // Paused at 0.3667 s: the window's frame is pelt render's at that time.
    let (paused, log) = shoot("paused.png", "0.36666667", false);
    assert!(log.contains("Walk 0.37/0.71 s paused"), "{log}");
    let late = render("at-0.367.png", "0.36666667");
    let f = flip(&late, &paused);
    eprintln!("paused at 0.367 s against pelt render at 0.367 s: FLIP {f:.5}");
    assert!(f <= 0.002, "FLIP {f} > 0.002");
    // Playing from 0.3 s: three frames later the clip is at 0.367 s (framed at 0.3 s, where
    // it started, so closer to the render at 0.367 s than to the one at 0.3 s).
    let (played, log) = shoot("played.png", "0.3", true);
    assert!(log.contains("Walk 0.37/0.71 s playing"), "{log}");
    let early = render("at-0.3.png", "0.3");
    let (to_late, to_early) = (flip(&late, &played), flip(&early, &played));
    eprintln!("played to 0.367 s: FLIP {to_late:.5} against 0.367 s, {to_early:.5} against 0.3 s");
    assert!(to_late < to_early, "the clip did not advance");
    // Negative control: the check tells 0.3 s from 0.367 s (two frames of the walk).
    let g = flip(&early, &paused);
    eprintln!("0.3 s against 0.367 s: FLIP {g:.5}");
    assert!(g > 0.002, "0.3 s and 0.367 s look alike: {g}");
    // A clip the asset does not have is an error listing those it has.
    let out = Command::new("xvfb-run")
        .args(["-a"])
        .arg(env!("CARGO_BIN_EXE_pelt"))
        .args([
            "view",
            "--backend",
            &b,
            s(&asset),
            "--animation",
            "Trot",
            "--frames",
            "1",
        ])
        .output()
        .expect("run");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains("Survey, Walk, Run"),
        "{err}"
    );
}

#[test]
fn strands_mode_refines_a_still_frame_toward_the_converged_reference() {
    // `pelt view --mode strands` adds one jittered sample a frame while the camera is still:
    // after 48 frames its screenshot (the running mean) must lie far closer to the converged
    // strand reference (`pelt render --mode strands`) than after one, the single frame being
    // the negative control.
    if !have_xvfb() {
        return;
    }
    let dir = scratch("view-strands");
    let asset = furry(&dir);
    let shot = |frames: &str| {
        let path = dir.join(format!("strands-{frames}.png"));
        let out = view(&[
            s(&asset),
            "--mode",
            "strands",
            "--frames",
            frames,
            "--screenshot",
            s(&path),
            "--size",
            "192x128",
            "--quiet",
        ]);
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        (load_png(&path), err)
    };
    let reference = render_png(
        &dir,
        &asset,
        "strands-reference.png",
        &["--mode", "strands", "--target-flip", "0.01"],
    );
    let (one, _) = shot("1");
    let (many, err) = shot("48");
    let (f1, f48) = (flip(&reference, &one), flip(&reference, &many));
    eprintln!(
        "strands view against the converged reference: 1 frame FLIP {f1:.4}, 48 frames {f48:.4}"
    );
    assert!(
        f48 < 0.5 * f1,
        "48 frames ({f48:.4}) are not much closer than 1 ({f1:.4}): {err}"
    );
}

/// A scene with wind and no animation: its clock stands in for the timeline. A frame paused
/// at 0.4 s and one played from 0.3 s for three 1/30 s frames are `pelt render --time 0.4`,
/// byte for byte; the wind at 0 s draws otherwise (the check can fail).
#[test]
fn a_windy_scene_plays_in_the_window_and_a_paused_frame_equals_pelt_render() {
    if !have_xvfb() {
        return;
    }
    let dir = scratch("view-wind");
    let asset = furry(&dir);
    let mesh = pelt_preview::asset::load(&asset).expect("the baked creature");
    let mut scene = pelt_preview::framing::asset_scene(&asset, &mesh, 192, 128);
    scene.wind = Some(pelt_preview::wind::Wind {
        direction: glam::Vec3::X,
        strength: 1.5,
        gust_hz: 0.7,
        turbulence: 0.5,
    });
    let path = dir.join("windy.json");
    std::fs::write(&path, serde_json::to_string(&scene).expect("json")).expect("write");
    let shoot = |name: &str, time: &str, play: bool| {
        screenshot(
            &dir,
            name,
            &[s(&path), "--time", time, "--frames", "4"],
            play,
        )
    };
    let at = render_png(&dir, &path, "at-0.4.png", &["--time", "0.4"]);
    let (paused, log) = shoot("paused.png", "0.4", false);
    assert!(log.contains("wind 0.40 s paused"), "{log}");
    assert!(
        paused == at,
        "paused at 0.4 s is not pelt render --time 0.4"
    );
    let (played, log) = shoot("played.png", "0.3", true);
    assert!(log.contains("wind 0.40 s playing"), "{log}");
    assert!(
        played == at,
        "played to 0.4 s is not pelt render --time 0.4"
    );
    let early = render_png(&dir, &path, "at-0.png", &["--time", "0"]);
    assert!(early != at, "the wind at 0 s and at 0.4 s draw the same");
}

/// Fur springs on the walking Fox (`--spring`): the window paused at 0.3667 s draws `pelt
/// render --time 0.3667` byte for byte (both bend the fur on the GPU-skinned pose, from the
/// clip's periodic spring state); played there from 0.3 s, the springs move the fur as it
/// plays (the frame differs from the same play without them). That a time reached by playing
/// bends the fur exactly as one reached at once is `pelt_anim::spring`'s test.
#[test]
fn fur_springs_follow_the_clip_in_the_window_as_pelt_render_draws_them() {
    if !have_xvfb() {
        return;
    }
    let dir = scratch("view-springs");
    let asset = fox(&dir);
    let spring = ["--spring", "1500,25"];
    let shoot = |name: &str, time: &str, play: bool, extra: &[&str]| {
        let mut args = vec![
            s(&asset),
            "--animation",
            "Walk",
            "--time",
            time,
            "--frames",
            "3",
        ];
        args.extend_from_slice(extra);
        screenshot(&dir, name, &args, play)
    };
    let at = render_png(
        &dir,
        &asset,
        "at-0.367.png",
        &[
            "--animation",
            "Walk",
            "--time",
            "0.36666667",
            "--spring",
            "1500,25",
        ],
    );
    let (paused, log) = shoot("paused.png", "0.36666667", false, &spring);
    assert!(log.contains("Walk 0.37/0.71 s paused"), "{log}");
    assert!(
        paused == at,
        "paused at 0.367 s is not pelt render --time 0.367"
    );
    let (played, log) = shoot("played.png", "0.3", true, &spring);
    assert!(log.contains("Walk 0.37/0.71 s playing"), "{log}");
    let (rigid, _) = shoot("played-rigid.png", "0.3", true, &["--spring", "off"]);
    let (still, _) = shoot("played-none.png", "0.3", true, &[]);
    assert!(
        rigid == still,
        "--spring off is not the fur without a spring"
    );
    let g = flip(&still, &played);
    eprintln!("played to 0.367 s with the spring against without: FLIP {g:.5}");
    assert!(g > 0.005, "the spring changed nothing: {g}");
}
