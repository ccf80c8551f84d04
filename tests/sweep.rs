//! `pelt sweep` and `pelt render --mode strands` as a user runs them: the demo's scene
//! (written by `pelt demo`) swept over shells and the L-buffer scale against the converged
//! strand reference and full-resolution deferred; bad knobs as usage errors; a strand
//! reference that cannot converge in the samples allowed writes nothing.
//! `PELT_BACKEND=gl|vulkan` picks the back end.

mod common;

use std::path::Path;

use common::{pelt, scratch};

fn backend() -> String {
    std::env::var("PELT_BACKEND").unwrap_or_else(|_| "auto".into())
}

fn read_png(path: &Path) -> (u32, u32, Vec<u8>) {
    let bytes = std::fs::read(path).expect("png written");
    let mut d = png::Decoder::new(std::io::Cursor::new(bytes));
    d.set_transformations(png::Transformations::EXPAND);
    let mut r = d.read_info().expect("valid png");
    let mut buf = vec![0; r.output_buffer_size().expect("size")];
    let info = r.next_frame(&mut buf).expect("frame");
    buf.truncate(info.buffer_size());
    let rgba = match info.color_type {
        png::ColorType::Rgb => buf
            .chunks_exact(3)
            .flat_map(|p| [p[0], p[1], p[2], 255])
            .collect(),
        _ => buf,
    };
    (info.width, info.height, rgba)
}

/// The demo's scene at 160×90, baked and written by `pelt demo` into `dir`.
fn demo_scene(dir: &Path) -> std::path::PathBuf {
    let b = backend();
    let d = dir.to_str().expect("utf8");
    let out = pelt(
        &[
            "demo",
            "-o",
            d,
            "--backend",
            &b,
            "--size",
            "160x90",
            "--frames",
            "1",
            "-q",
        ],
        &[],
    );
    assert!(
        out.status.success(),
        "pelt demo: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    dir.join("scene.json")
}

#[test]
fn the_demo_scene_sweep_measures_shells_against_the_strand_reference() {
    let dir = scratch("sweep-demo");
    let scene = demo_scene(&dir);
    let out_dir = dir.join("sweep");
    let b = backend();
    let out = pelt(
        &[
            "sweep",
            scene.to_str().expect("utf8"),
            "--knob",
            "shells=4,16,64",
            "--knob",
            "lbuffer-scale=0.5,1",
            "--frames",
            "2",
            "--warmup",
            "1",
            // At 160×90 the halves reach 0.005 near 4096 samples; room for one more doubling.
            "--max-samples",
            "8192",
            "--backend",
            &b,
            "-o",
            out_dir.to_str().expect("utf8"),
        ],
        &[],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "pelt sweep: {stderr}");
    eprintln!("{stderr}");

    // sweep.csv: a row per setting, with time and error.
    let csv = std::fs::read_to_string(out_dir.join("sweep.csv")).expect("sweep.csv");
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    assert_eq!(header[..4], ["knob", "value", "ms", "error"]);
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 5, "{csv}");
    let error = |knob: &str, value: &str| -> f64 {
        let r = rows
            .iter()
            .find(|r| r[0] == knob && r[1] == value)
            .unwrap_or_else(|| panic!("a row for {knob}={value}: {csv}"));
        let (ms, e): (f64, f64) = (r[2].parse().expect("ms"), r[3].parse().expect("error"));
        // FLIP's mean is of per-pixel errors from 0 to 1.
        assert!(ms > 0.0 && (0.0..=1.0).contains(&e), "{r:?}");
        e
    };
    let (e4, e16, e64) = (
        error("shells", "4"),
        error("shells", "16"),
        error("shells", "64"),
    );
    assert!(
        e4 > e64,
        "against the strand reference 64 shells must beat 4: {e4} vs {e64}"
    );
    eprintln!("shells 4/16/64 against strands: {e4:.4} {e16:.4} {e64:.4}");
    // The shells are another renderer than the strands: their error cannot vanish.
    assert!(e64 > 0.01, "shells against strands: {e64}");
    // At full scale the inferred L-buffer is the deferred frame up to rounding (about 1e-4);
    // at half scale its lighting is upsampled, and differs visibly (about 0.018).
    let (full, half) = (error("lbuffer-scale", "1"), error("lbuffer-scale", "0.5"));
    assert!(full < 1e-3, "full-scale L-buffer against deferred: {full}");
    assert!(
        half > 5e-3 && half > 10.0 * full,
        "half-scale L-buffer against deferred: {half} (full scale {full})"
    );
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .unwrap_or_else(|| panic!("a {name} column: {csv}"))
    };
    let (against, image, heat, lum) = (
        col("reference"),
        col("image"),
        col("heat"),
        col("fur_luminance"),
    );
    for r in &rows {
        let want = if r[0] == "shells" {
            "strands"
        } else {
            "deferred"
        };
        assert_eq!(r[against], want, "{r:?}");
        assert!(out_dir.join(r[image]).is_file() && out_dir.join(r[heat]).is_file());
        if r[0] == "shells" {
            // The shells are as bright as the strands they stand for (within 10 %).
            let ratio: f64 = r[lum].parse().expect("fur luminance");
            assert!((0.9..=1.1).contains(&ratio), "fur luminance {ratio}: {r:?}");
        }
    }

    // sweep.json: the same rows, the reference's convergence, the adapter.
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out_dir.join("sweep.json")).expect("sweep.json"),
    )
    .expect("valid json");
    assert_eq!(json["rows"].as_array().map(Vec::len), Some(5));
    assert_eq!(json["reference"]["kind"], "strands");
    let half = json["reference"]["half_vs_half_flip"]
        .as_f64()
        .expect("half-vs-half figure");
    assert!(half <= 0.005, "{half}");
    assert!(json["reference"]["samples"].as_u64().expect("samples") >= 16);
    assert!(!json["adapter"].as_str().expect("adapter").is_empty());

    // sweep.png: drawn, with the Pareto front in red and dark text and axes.
    let (w, h, px) = read_png(&out_dir.join("sweep.png"));
    let pixels = (w * h) as usize;
    let red = px
        .chunks_exact(4)
        .filter(|p| p[0] > 200 && p[1] < 60 && p[2] < 60)
        .count();
    let dark = px
        .chunks_exact(4)
        .filter(|p| p[0] < 80 && p[1] < 80 && p[2] < 80)
        .count();
    assert!(red > 50, "{red} Pareto-front pixels");
    assert!(
        dark > pixels / 500,
        "{dark} text and axis pixels of {pixels}"
    );
    let (cw, ch, _) = read_png(&out_dir.join("contact.png"));
    assert!(cw > 0 && ch > 0);
    assert!(out_dir.join("reference-strands.png").is_file());
    assert!(out_dir.join("sweep.md").is_file());
    assert!(!out_dir.join(".sweep-partial").exists());
}

/// The spot stage's shadow knobs against the ray tracer: a larger perspective map draws the
/// spot light's shadow closer to the truth (the coarsest map is the negative control).
#[test]
fn the_sweep_measures_a_spot_lights_shadow_knobs_against_the_ray_tracer() {
    let dir = scratch("sweep-spot");
    let out_dir = dir.join("out");
    let scene = common::fixture("scenes/spot.json");
    let out = pelt(
        &[
            "sweep",
            scene.to_str().expect("utf8"),
            "--knob",
            "shadow-size=64,1024",
            "--knob",
            "pcf=1,2",
            "--size",
            "192x108",
            "--frames",
            "1",
            "--warmup",
            "0",
            "--backend",
            &backend(),
            "-q",
            "-o",
            out_dir.to_str().expect("utf8"),
        ],
        &[],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out_dir.join("sweep.json")).expect("sweep.json"),
    )
    .expect("valid json");
    assert_eq!(json["reference"]["kind"], "raytrace");
    let flip = |knob: &str, value: &str| -> f64 {
        json["rows"]
            .as_array()
            .expect("rows")
            .iter()
            .find(|r| r["knob"] == knob && r["value"] == value)
            .and_then(|r| r["error"].as_f64())
            .unwrap_or_else(|| panic!("{knob}={value} in {json}"))
    };
    let (coarse, fine) = (flip("shadow-size", "64"), flip("shadow-size", "1024"));
    assert!(
        fine < coarse * 0.8,
        "shadow-size 1024: {fine}, 64: {coarse}"
    );
    assert!(fine <= 0.03 && flip("pcf", "2") <= 0.03, "{json}");
}

#[test]
fn bad_knobs_are_usage_errors_naming_the_knob_and_its_range() {
    let dir = scratch("sweep-bad");
    let out_dir = dir.join("out");
    let o = out_dir.to_str().expect("utf8");
    let asset = common::fixture("creature.glb");
    let a = asset.to_str().expect("utf8");
    let b = backend();
    let cases: [(&[&str], &str); 7] = [
        (
            &["--knob", "shells=0"],
            "knob shells: \"0\" is not allowed (auto (by screen size) or 1 to 256)",
        ),
        (
            &["--knob", "lbuffer-scale=2"],
            "knob lbuffer-scale: \"2\" is not allowed (0.1 to 1)",
        ),
        (
            &["--knob", "hairs=4"],
            "unknown knob \"hairs\" (knobs: shells, fins,",
        ),
        (&["--knob", "shells"], "expected NAME=V1,V2,..."),
        (
            &["--knob", "linear-steps=4"],
            "knob linear-steps: the scene has no mirror or glass object",
        ),
        (
            &["--knob", "pcf=2"],
            "knob pcf: the scene has no light that casts shadows",
        ),
        (
            &["--knob", "shadow-size=100"],
            "knob shadow-size: \"100\" is not allowed (a power of two from 16 to 4096)",
        ),
    ];
    for (extra, want) in cases {
        let mut args = vec!["sweep", a, "-o", o, "--backend", &b];
        args.extend_from_slice(extra);
        let out = pelt(&args, &[]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{extra:?}: {stderr}");
        assert!(stderr.contains(want), "{extra:?}: {stderr}");
        assert!(!out_dir.exists(), "{extra:?} wrote output");
    }
}

/// `pelt render` of the showcase in strands mode at 64×36, allowed 2 samples per pixel toward
/// an unreachable target, with `extra` flags; returns the exit code, standard error and
/// whether the PNG was written.
fn unconverged_strands(name: &str, extra: &[&str]) -> (Option<i32>, String, bool) {
    let dir = scratch(name);
    let png = dir.join("strands.png");
    let b = backend();
    let scene = common::fixture("scenes/showcase.json");
    let mut args = vec![
        "render",
        scene.to_str().expect("utf8"),
        "--mode",
        "strands",
        "--size",
        "64x36",
        "--max-samples",
        "2",
        "--target-flip",
        "0.0001",
        "--backend",
        &b,
        "-o",
        png.to_str().expect("utf8"),
    ];
    args.extend_from_slice(extra);
    let out = pelt(&args, &[]);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    (out.status.code(), stderr, png.exists())
}

#[test]
fn a_strand_reference_that_cannot_converge_writes_nothing() {
    let (code, stderr, written) = unconverged_strands("strands-unconverged", &[]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("did not converge"), "{stderr}");
    assert!(!written);
    // It said where it stood from the start: what it will do, then its first frame (a line
    // each, standard error not being a terminal here).
    assert!(
        stderr.contains("strand reference: 64×36, up to 2 samples per pixel"),
        "{stderr}"
    );
    assert!(
        ["1", "4", "9", "16"]
            .iter()
            .any(|spp| stderr.contains(&format!("strand reference: {spp} spp, "))),
        "{stderr}"
    );
}

#[test]
fn quiet_strands_say_nothing_but_the_error() {
    let (code, stderr, written) = unconverged_strands("strands-quiet", &["-q"]);
    assert_eq!(code, Some(1), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.contains("did not converge"), "{stderr}");
    assert!(!written);
}

/// A scene of the fixture sphere baked with fur, in `dir`.
fn furred_sphere_scene(dir: &Path) -> std::path::PathBuf {
    let baked = dir.join("sphere.glb");
    common::pelt_ok(&[
        "bake",
        "-q",
        "fixtures/sphere.glb",
        "-o",
        baked.to_str().expect("utf8"),
        "--config",
        "fixtures/fur.json",
    ]);
    let scene = dir.join("scene.json");
    let text = r#"{
        "camera": { "position": [0, 1.2, 4.5], "target": [0, 0.5, 0] },
        "objects": [{ "asset": "sphere.glb", "material": { "kind": "fur" } }],
        "lights": [{ "position": [1.5, 2, 2], "color": [1, 1, 1], "intensity": 6, "radius": 8 }]
    }"#;
    std::fs::write(&scene, text).expect("scene");
    scene
}

/// Starts `pelt sweep` on a furred sphere into `out`, waits for its staging folder, sends
/// `signal` and returns the exit status.
fn interrupted_sweep(out: &Path, signal: &str) -> std::process::ExitStatus {
    let b = backend();
    let scene = furred_sphere_scene(out.parent().expect("a parent"));
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_pelt"))
        .arg("sweep")
        .arg(&scene)
        .args(["--size", "64x36", "--knob"])
        .args([
            "shells=4,8",
            "--frames",
            "1",
            "--warmup",
            "0",
            "--backend",
            &b,
            "-q",
            "-o",
        ])
        .arg(out)
        .current_dir(common::root())
        .spawn()
        .expect("start pelt sweep");
    let staging = out.join(".sweep-partial");
    let started = std::time::Instant::now();
    while !staging.join("images").is_dir() {
        assert!(
            started.elapsed() < std::time::Duration::from_secs(120),
            "no staging folder"
        );
        assert!(
            child.try_wait().expect("poll").is_none(),
            "the sweep ended first"
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let kill = std::process::Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .expect("kill");
    assert!(kill.success());
    child.wait().expect("wait")
}

#[test]
fn an_interrupted_sweep_leaves_nothing_behind() {
    let dir = scratch("sweep-interrupted");
    let out = dir.join("sweep");
    let status = interrupted_sweep(&out, "-INT");
    assert_eq!(status.code(), Some(130), "{status:?}");
    assert!(
        !out.exists(),
        "left behind: {:?}",
        common::files_under(&out)
    );
    // Negative control: killed outright (no handler runs), the staging folder stays; the
    // check above would have seen it.
    let status = interrupted_sweep(&out, "-KILL");
    assert_eq!(status.code(), None);
    assert!(out.join(".sweep-partial").is_dir());
}
