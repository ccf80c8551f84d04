//! Edge cases that once gave a wrong picture or a late error without a word, end to end:
//! output paths checked before the work (missing folders made, impossible paths refused at
//! once, nothing left behind), the material the bake adds drawn as the unbaked file is, and
//! node scales that collapse a mesh named at bake and at render time, mirroring nodes drawn
//! mirrored, precision notes where the picture blotches and only there. Each with a control
//! that shows the check can fail.

mod common;

use std::path::Path;
use std::time::{Duration, Instant};

use common::*;
use pelt_io::Document;
use serde_json::{Value, json};

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `fixtures/sphere.glb` changed by `edit`, written to `dir/name`.
fn sphere_with(
    dir: &Path,
    name: &str,
    edit: impl FnOnce(&mut serde_json::Map<String, Value>),
) -> std::path::PathBuf {
    let mut doc = Document::load(&fixture("sphere.glb")).expect("sphere");
    edit(&mut doc.json);
    let path = dir.join(name);
    write_input(&doc, &path);
    path
}

#[test]
fn a_bad_report_or_depfile_path_fails_before_the_bake_and_writes_nothing() {
    let dir = scratch("extremes-report-path");
    std::fs::write(dir.join("file"), b"not a folder").expect("write");
    let out = dir.join("out/sphere.glb");
    for flag in ["--report", "--depfile"] {
        let bad = dir.join("file/r.json");
        let started = Instant::now();
        let o = pelt(
            &[
                "bake",
                fixture("sphere.glb").to_str().unwrap_or_default(),
                "-o",
                out.to_str().unwrap_or_default(),
                flag,
                bad.to_str().unwrap_or_default(),
            ],
            &[],
        );
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{flag}: {e}");
        assert!(
            started.elapsed() < Duration::from_secs(5),
            "{flag}: not before the work"
        );
        assert!(
            e.contains("file/r.json") && e.contains("is a file, not a folder"),
            "{flag}: {e}"
        );
        // The OS error is said once, not repeated by every layer.
        assert_eq!(e.matches("file/r.json").count(), 1, "{flag}: {e}");
        assert!(!out.exists(), "{flag}: the .glb was written");
    }
    // Control: a report and a depfile in folders that do not exist yet are made and written.
    let report = dir.join("new/reports/r.json");
    let depfile = dir.join("new/deps/baked.d");
    pelt_ok(&[
        "bake",
        "-q",
        fixture("sphere.glb").to_str().unwrap_or_default(),
        "-o",
        out.to_str().unwrap_or_default(),
        "--report",
        report.to_str().unwrap_or_default(),
        "--depfile",
        depfile.to_str().unwrap_or_default(),
    ]);
    assert!(out.exists() && report.exists() && depfile.exists());
}

#[test]
fn a_render_checks_its_output_before_it_renders() {
    let dir = scratch("extremes-render-path");
    std::fs::write(dir.join("file"), b"not a folder").expect("write");
    let sphere = fixture("sphere.glb");
    let bad = dir.join("file/s.png");
    let o = pelt(
        &[
            "render",
            sphere.to_str().unwrap_or_default(),
            "-o",
            bad.to_str().unwrap_or_default(),
            "--size",
            "32x18",
        ],
        &[],
    );
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("file/s.png: cannot be written") && !e.contains("wrote"),
        "{e}"
    );
    // A missing folder is made, as `pelt bake` makes its output folders.
    let made = dir.join("missing/deeper/s.png");
    pelt_ok(&[
        "render",
        "-q",
        sphere.to_str().unwrap_or_default(),
        "-o",
        made.to_str().unwrap_or_default(),
        "--size",
        "32x18",
    ]);
    assert!(made.is_file());
    assert_eq!(
        files_under(&dir.join("missing")).len(),
        1,
        "a probe file was left behind"
    );
}

#[test]
fn a_node_scale_with_a_zero_axis_is_named_at_bake_and_render_time() {
    let dir = scratch("extremes-zero-scale");
    let flat = sphere_with(&dir, "flat.glb", |j| {
        j["nodes"][0]["scale"] = json!([1.0, 0.0, 1.0]);
    });
    let want = "nodes[0]: its scale [1.0, 0.0, 1.0] has a zero axis: the meshes under it are flattened to nothing";
    let o = pelt_ok(&[
        "bake",
        flat.to_str().unwrap_or_default(),
        "-o",
        dir.join("baked.glb").to_str().unwrap_or_default(),
    ]);
    assert!(stderr(&o).contains(want), "{}", stderr(&o));
    let o = pelt_ok(&[
        "render",
        flat.to_str().unwrap_or_default(),
        "-o",
        dir.join("flat.png").to_str().unwrap_or_default(),
        "--size",
        "32x18",
    ]);
    assert!(stderr(&o).contains(want), "{}", stderr(&o));
    // Control: a negative (mirroring) scale collapses nothing and says nothing.
    let mirrored = sphere_with(&dir, "mirrored.glb", |j| {
        j["nodes"][0]["scale"] = json!([1.0, -1.0, 1.0]);
    });
    let o = pelt_ok(&[
        "bake",
        mirrored.to_str().unwrap_or_default(),
        "-o",
        dir.join("mirrored-baked.glb").to_str().unwrap_or_default(),
    ]);
    assert!(!stderr(&o).contains("zero axis"), "{}", stderr(&o));
}

/// Writes `scene` to `dir/name.json`, renders it to `dir/name.png` and returns the image.
fn render_scene(dir: &Path, name: &str, scene: &Value) -> pelt_preview::Image {
    render_in(dir, name, scene, &[])
}

/// Renders `asset` drawn opaque (a one-object scene) at 160×90; returns the image.
fn render_opaque(dir: &Path, asset: &Path, name: &str) -> pelt_preview::Image {
    let scene = json!({
        "output": { "width": 160, "height": 90 },
        "camera": { "position": [0.0, 1.2, 4.5], "target": [0.0, 0.5, 0.0], "fovYDeg": 40 },
        "objects": [{ "asset": asset, "material": { "kind": "opaque" } }],
        "lights": [{ "position": [1.5, 2.0, 2.0], "color": [1, 1, 1], "intensity": 6, "radius": 8 }]
    });
    render_scene(dir, name, &scene)
}

#[test]
fn a_baked_asset_without_a_material_draws_opaque_as_it_did_unbaked() {
    let dir = scratch("extremes-opaque");
    let bare = sphere_with(&dir, "bare.glb", |j| {
        j.remove("materials");
        j["meshes"][0]["primitives"][0]
            .as_object_mut()
            .map(|p| p.remove("material"));
    });
    let baked = dir.join("baked.glb");
    pelt_ok(&[
        "bake",
        "-q",
        bare.to_str().unwrap_or_default(),
        "-o",
        baked.to_str().unwrap_or_default(),
        "--config",
        "fixtures/fur.json",
    ]);
    let doc = Document::load(&baked).expect("baked");
    let added = &doc.json["materials"][0];
    assert_eq!(added["name"], "pelt fur");
    assert_eq!(added["pbrMetallicRoughness"]["metallicFactor"], 0.0);
    let before = render_opaque(&dir, &bare, "bare");
    let after = render_opaque(&dir, &baked, "baked");
    let flip = |a: &pelt_preview::Image, b: &pelt_preview::Image| {
        pelt_measure::flip::Flip::new(a, b)
            .expect("same size")
            .mean()
    };
    let f = flip(&before, &after);
    println!("opaque, unbaked against baked: FLIP {f:.4}");
    assert!(f <= 0.05, "FLIP {f}");

    // Negative control: the material as earlier bakes wrote it (glTF's defaults: metal)
    // draws black, far from the unbaked picture; baking that file again mends it, saying so.
    let old = dir.join("old.glb");
    let mut doc = doc;
    doc.json["materials"][0]
        .as_object_mut()
        .map(|m| m.remove("pbrMetallicRoughness"));
    write_input(&doc, &old);
    let f_old = flip(&before, &render_opaque(&dir, &old, "old"));
    println!("opaque, unbaked against the old bake's metal: FLIP {f_old:.4}");
    assert!(f_old > 0.05, "the control passes: FLIP {f_old}");
    let rebaked = dir.join("rebaked.glb");
    let o = pelt_ok(&[
        "bake",
        old.to_str().unwrap_or_default(),
        "-o",
        rebaked.to_str().unwrap_or_default(),
        "--config",
        "fixtures/fur.json",
    ]);
    assert!(
        stderr(&o).contains("\"pelt fur\": an earlier bake added it with glTF's default factors"),
        "{}",
        stderr(&o)
    );
    let f_re = flip(&before, &render_opaque(&dir, &rebaked, "rebaked"));
    assert!(f_re <= 0.05, "re-baked: FLIP {f_re}");
    let doc = Document::load(&rebaked).expect("rebaked");
    assert_eq!(
        doc.array("materials").len(),
        1,
        "a second fur material was added"
    );
}

/// `pelt_fixtures`' unit sphere (under a root node at y = 0.5) with its positions scaled by
/// `by_positions` and its mesh node scaled by `by_node`, baked with `fixtures/fur.json`.
fn scaled_sphere(dir: &Path, name: &str, by_positions: f32, by_node: f32) -> std::path::PathBuf {
    baked_sphere(dir, name, by_positions, [by_node; 3])
}

/// [`scaled_sphere`] with the mesh node scaled by `node` per axis.
fn baked_sphere(dir: &Path, name: &str, by_positions: f32, node: [f32; 3]) -> std::path::PathBuf {
    let mut shape = pelt_fixtures::shapes::sphere(24, 48);
    for p in &mut shape.positions {
        *p *= by_positions;
    }
    let mut doc =
        pelt_fixtures::build::document(&shape, pelt_fixtures::build::BuildOptions::default());
    doc.json["nodes"][0]["scale"] = json!(node);
    let input = dir.join(format!("{name}-in.glb"));
    write_input(&doc, &input);
    let baked = dir.join(format!("{name}.glb"));
    pelt_ok(&[
        "bake",
        "-q",
        input.to_str().unwrap_or_default(),
        "-o",
        baked.to_str().unwrap_or_default(),
        "--config",
        "fixtures/fur.json",
    ]);
    baked
}

/// Renders `asset` as fur of `length` (mesh units) at 160×90, the camera framing a sphere of
/// radius `s` at y = 0.5; returns the image.
fn render_fur(dir: &Path, asset: &Path, name: &str, s: f32, length: f32) -> pelt_preview::Image {
    // pelt's lights fall off as 1 / (1 + d²), which no scale leaves alone: each light's
    // intensity is set for the same light at the sphere's centre at every scale.
    let at_centre = |d: f32, e: f32| e * (1.0 + d * d * s * s);
    let scene = json!({
        "output": { "width": 160, "height": 90 },
        "camera": {
            "position": [0.0, 0.5 + 0.9 * s, 3.2 * s], "target": [0.0, 0.5, 0.0], "fovYDeg": 40,
            "near": 0.2 * s, "far": 20.0 * s
        },
        "ambient": [0.05, 0.05, 0.05],
        "objects": [{ "asset": asset, "material": { "kind": "fur", "length": length } }],
        "lights": [
            { "position": [2.0 * s, 0.5 + 2.5 * s, 3.0 * s], "color": [1, 1, 1],
              "intensity": at_centre(4.39, 0.7), "radius": 10.0 * s },
            { "position": [-3.0 * s, 0.5 + s, 1.0 * s], "color": [0.5, 0.6, 1],
              "intensity": at_centre(3.32, 0.3), "radius": 10.0 * s }
        ]
    });
    render_scene(dir, name, &scene)
}

#[test]
fn fur_length_follows_node_scale_as_it_follows_positions() {
    let dir = scratch("extremes-node-scale");
    let length = 0.15; // mesh units: 15 % of the unit sphere's radius
    let mut pictures = Vec::new();
    for s in [1e-4f32, 0.01, 10.0, 1e6] {
        let by_positions = scaled_sphere(&dir, &format!("positions-{s}"), s, 1.0);
        let by_node = scaled_sphere(&dir, &format!("node-{s}"), 1.0, s);
        // The position-scaled copy's mesh unit is the world's; the node-scaled copy's fur,
        // given in its own mesh units, follows its node.
        let a = render_fur(
            &dir,
            &by_positions,
            &format!("positions-{s}"),
            s,
            length * s,
        );
        let b = render_fur(&dir, &by_node, &format!("node-{s}"), s, length);
        let f = pelt_measure::flip::Flip::new(&a, &b)
            .expect("same size")
            .mean();
        println!("node scale {s}: position-scaled against node-scaled FLIP {f:.4}");
        assert!(f <= 0.02, "node scale {s}: FLIP {f}");
        // Negative control: fur whose length ignores the node (applied in the asset's units,
        // as the preview once did) is far from the position-scaled picture.
        let wrong = render_fur(&dir, &by_node, &format!("node-ignored-{s}"), s, length / s);
        let g = pelt_measure::flip::Flip::new(&a, &wrong)
            .expect("same size")
            .mean();
        println!("node scale {s}: against fur ignoring the node FLIP {g:.4}");
        assert!(g > 0.02, "node scale {s}: the control passes: FLIP {g}");
        pictures.push(a);
    }
    // Across ten orders of magnitude the picture holds: the lights' falloff, 1 / (1 + d²) with
    // d in world units, is flat at the small scales and 1 / d² at the large ones, so the
    // pictures agree within each pair (nothing lost to precision at 1e-4 or 1e6).
    for (i, j, what) in [(0, 1, "1e-4 against 0.01"), (2, 3, "10 against 1e6")] {
        let f = pelt_measure::flip::Flip::new(&pictures[i], &pictures[j])
            .expect("same size")
            .mean();
        println!("scale {what}: FLIP {f:.4}");
        assert!(f <= 0.02, "scale {what}: FLIP {f}");
    }
    // Control: across the falloff's two regimes the measure sees the difference.
    let f = pelt_measure::flip::Flip::new(&pictures[1], &pictures[2])
        .expect("same size")
        .mean();
    println!("scale 0.01 against 10: FLIP {f:.4}");
    assert!(f > 0.02, "the control passes: FLIP {f}");
}

#[test]
fn a_missing_asset_is_named_with_its_scene_file_and_resolved_path() {
    let dir = scratch("extremes-missing-asset");
    let scene = dir.join("scene.json");
    std::fs::write(&scene, r#"{"objects": [{"asset": "sub/missing.glb"}]}"#).expect("scene");
    let o = pelt(
        &[
            "render",
            scene.to_str().unwrap_or_default(),
            "-o",
            dir.join("m.png").to_str().unwrap_or_default(),
        ],
        &[],
    );
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    let resolved = dir.join("sub/missing.glb");
    let want = format!(
        "pelt: {}: objects[0]: {}: read: ",
        scene.display(),
        resolved.display()
    );
    assert!(e.starts_with(&want), "{e}");
    assert!(!dir.join("m.png").exists());
    // A missing scene file: named once, its reason once.
    let missing = dir.join("missing.json");
    let png = dir.join("n.png");
    let o = pelt(
        &[
            "render",
            missing.to_str().unwrap_or_default(),
            "-o",
            png.to_str().unwrap_or_default(),
        ],
        &[],
    );
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.starts_with(&format!("pelt: {}: ", missing.display())),
        "{e}"
    );
    assert_eq!(e.matches("No such file or directory").count(), 1, "{e}");
    assert!(!png.exists());
}

#[test]
fn a_failed_bake_writes_no_depfile() {
    let dir = scratch("extremes-depfile-failed");
    let depfile = dir.join("baked.d");
    let o = pelt(
        &[
            "bake",
            dir.join("missing-folder/").to_str().unwrap_or_default(),
            "-o",
            dir.join("out/").to_str().unwrap_or_default(),
            "--depfile",
            depfile.to_str().unwrap_or_default(),
        ],
        &[],
    );
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("missing-folder"), "{}", stderr(&o));
    assert!(!depfile.exists(), "a depfile was written for a failed bake");
    // Control: the same command on an input that bakes writes it.
    pelt_ok(&[
        "bake",
        "-q",
        fixture("sphere.glb").to_str().unwrap_or_default(),
        "-o",
        dir.join("out/").to_str().unwrap_or_default(),
        "--depfile",
        depfile.to_str().unwrap_or_default(),
    ]);
    assert!(depfile.is_file());
}

/// A one-sphere scene at 160×90 looking at the top of `asset` (the unit sphere at y = 0.5,
/// furred), lit by `lights`, drawn in `mode`.
fn render_lit_sphere(
    dir: &Path,
    asset: &Path,
    name: &str,
    lights: Value,
    mode: &str,
) -> pelt_preview::Image {
    let scene = json!({
        "output": { "width": 160, "height": 90 },
        "camera": { "position": [0.0, 3.0, 2.5], "target": [0.0, 1.2, 0.0], "fovYDeg": 45, "near": 0.1, "far": 40 },
        "ambient": [0.03, 0.03, 0.03],
        "objects": [
            { "asset": "builtin:cube", "transform": { "translation": [0, -0.6, 0], "scale": [8, 0.2, 8] }, "color": [0.7, 0.7, 0.7] },
            { "asset": asset, "material": { "kind": "fur" } }
        ],
        "lights": lights
    });
    let strands = ["--mode", "strands", "--target-flip", "0.02"];
    let args: &[&str] = if mode == "strands" {
        &strands
    } else {
        &["--mode", mode]
    };
    render_in(dir, name, &scene, args)
}

/// A shadow-casting light at the centre of a furry sphere, just under its surface, on it and
/// among its strands: inferred lighting matches forward (the fur's L-buffer samples are lit
/// where the strand is and lifted along it, away from its surface, for the shadow lookup);
/// from inside, the fur is as dark as with no light at all, in the strand reference too.
#[test]
fn a_shadow_casting_light_inside_or_on_a_furry_surface_lights_inferred_as_forward() {
    let dir = scratch("extremes-light-inside");
    let sphere = scaled_sphere(&dir, "sphere", 1.0, 1.0);
    let light = |y: f32, shadows: bool| {
        json!([{ "position": [0.0, y, 0.0], "color": [1.0, 0.95, 0.85], "intensity": 3,
                 "radius": 10, "shadows": shadows }])
    };
    let dark = render_lit_sphere(&dir, &sphere, "unlit", json!([]), "forward");
    for (name, y, inside) in [
        ("centre", 0.5, true),
        ("under", 1.45, true),
        ("surface", 1.5, false),
        ("in-fur", 1.51, false),
    ] {
        let forward = render_lit_sphere(&dir, &sphere, name, light(y, true), "forward");
        let inferred = render_lit_sphere(&dir, &sphere, name, light(y, true), "inferred");
        let f = flip_of(&forward, &inferred);
        println!("light {name}: inferred against forward FLIP {f:.4}");
        assert!(f <= 0.06, "light {name}: inferred against forward FLIP {f}");
        if inside {
            for (mode, image) in [("forward", &forward), ("inferred", &inferred)] {
                let g = flip_of(&dark, image);
                println!("light {name}: {mode} against no light FLIP {g:.4}");
                assert!(g <= 0.01, "light {name}: {mode} lit from inside: FLIP {g}");
            }
        }
    }
    let strands = render_lit_sphere(&dir, &sphere, "centre", light(0.5, true), "strands");
    let g = flip_of(&dark, &strands);
    println!("light centre: strand reference against no light FLIP {g:.4}");
    assert!(g <= 0.01, "the strand reference lit from inside: FLIP {g}");
    // Negative control: the same light casting no shadows lights the fur from inside.
    for mode in ["forward", "inferred", "strands"] {
        let leak = render_lit_sphere(&dir, &sphere, "unshadowed", light(0.5, false), mode);
        let g = flip_of(&dark, &leak);
        println!("light centre, no shadows: {mode} against no light FLIP {g:.4}");
        assert!(g > 0.01, "the control passes in {mode}: FLIP {g}");
    }
}

/// The camera inside long fur (0.6 mesh units on the unit sphere, its tips up to 0.6 above
/// the skin; the camera 0.05 and 0.2 above it): inferred fur has no near-black pixel where
/// forward draws it lit (the shells of fur that holds the eye are lit forward: those above
/// the camera have no L-buffer sample), and both views stay within FLIP 0.05 of forward.
#[test]
fn inferred_fur_seen_from_inside_is_lit_where_forward_is() {
    let dir = scratch("extremes-inside-fur");
    let sphere = scaled_sphere(&dir, "sphere", 1.0, 1.0);
    let scene = |position: [f32; 3], target: [f32; 3], lights: Value| {
        json!({
            "output": { "width": 160, "height": 90 },
            "camera": { "position": position, "target": target, "fovYDeg": 60, "near": 0.01, "far": 40 },
            "ambient": [0.03, 0.03, 0.03],
            "objects": [
                { "asset": "builtin:cube", "transform": { "translation": [0, -0.6, 0], "scale": [8, 0.2, 8] }, "color": [0.7, 0.7, 0.7] },
                { "asset": sphere, "material": { "kind": "fur", "length": 0.6 } }
            ],
            "lights": lights
        })
    };
    let light = json!([{ "position": [1.5, 3.0, 1.0], "color": [1.0, 0.95, 0.85], "intensity": 6, "radius": 10 }]);
    for (name, position, target, floor) in [
        ("along", [0.0, 1.55, 0.0], [1.0, 1.0, 0.0], 0.05),
        ("down", [0.0, 1.7, 0.0], [0.0, 0.5, 1.0], 0.05),
    ] {
        let s = scene(position, target, light.clone());
        let forward = render_in(&dir, name, &s, &["--mode", "forward"]);
        let inferred = render_in(&dir, name, &s, &["--mode", "inferred"]);
        let black = near_black_where_lit(&forward, &inferred);
        let f = flip_of(&forward, &inferred);
        println!(
            "camera inside the fur, {name}: inferred against forward FLIP {f:.4}, {black} near-black pixels where forward is lit"
        );
        assert_eq!(black, 0, "{name}: inferred near black where forward is lit");
        assert!(f <= floor, "{name}: FLIP {f}");
        // Negative control: the counter finds the fur lit by the ambient term alone.
        let dark = scene(position, target, json!([]));
        let dark = render_in(&dir, &format!("{name}-dark"), &dark, &["--mode", "forward"]);
        let unlit = near_black_where_lit(&forward, &dark);
        assert!(
            unlit > 1000,
            "{name}: the control passes: {unlit} near-black pixels"
        );
    }
}

/// `image` mirrored left to right.
fn mirrored(image: &pelt_preview::Image) -> pelt_preview::Image {
    let mut out = image.clone();
    let w = image.width as usize;
    for (row_in, row_out) in image
        .rgba
        .chunks_exact(4 * w)
        .zip(out.rgba.chunks_exact_mut(4 * w))
    {
        for x in 0..w {
            row_out[4 * x..4 * x + 4].copy_from_slice(&row_in[4 * (w - 1 - x)..4 * (w - x)]);
        }
    }
    out
}

/// A mirroring node (scale x −1) turns its triangles clockwise (glTF: the determinant's sign
/// gives the winding): its fur, base and shells, draws as the mirror image of the unmirrored
/// sphere's, seen and lit from the mirror plane.
#[test]
fn a_mirroring_node_draws_its_fur_as_the_mirror_image() {
    let dir = scratch("extremes-mirroring-node");
    let plain = baked_sphere(&dir, "plain", 1.0, [1.0, 1.0, 1.0]);
    let flipped = baked_sphere(&dir, "flipped", 1.0, [-1.0, 1.0, 1.0]);
    let scene = |asset: &Path, light_x: f32| {
        json!({
            "output": { "width": 160, "height": 90 },
            "camera": { "position": [0.0, 1.4, 3.2], "target": [0.0, 0.5, 0.0], "fovYDeg": 40, "near": 0.2, "far": 20 },
            "ambient": [0.05, 0.05, 0.05],
            "objects": [{ "asset": asset, "material": { "kind": "fur" } }],
            "lights": [{ "position": [light_x, 3.0, 3.0], "color": [1, 1, 1], "intensity": 0.7, "radius": 10 }]
        })
    };
    for mode in ["forward", "inferred"] {
        let a = render_in(&dir, "plain", &scene(&plain, 0.0), &["--mode", mode]);
        let b = render_in(&dir, "flipped", &scene(&flipped, 0.0), &["--mode", mode]);
        let f = flip_of(&a, &mirrored(&b));
        println!("{mode}: the sphere against its mirror image mirrored back: FLIP {f:.4}");
        assert!(f <= 0.01, "{mode}: FLIP {f}");
        // Control: the mirror image under a light off the mirror plane is not the same picture.
        let c = render_in(
            &dir,
            "flipped-lit-aside",
            &scene(&flipped, 2.0),
            &["--mode", mode],
        );
        let g = flip_of(&a, &mirrored(&c));
        println!("{mode}: against the mirror image lit from one side: FLIP {g:.4}");
        assert!(g > 0.01, "{mode}: the control passes: FLIP {g}");
    }
}

/// Precision notes name the scenes that blotch and stay quiet for ordinary ones: an
/// ordinary camera over 4 cm fur says nothing; a far plane so deep that the L-buffer's depth
/// codes are coarser than the object, and fur finer than float positions resolve (4 cm fur on
/// a sphere 1000 km across, seen from up close), are each named.
#[test]
fn precision_notes_name_what_blotches_and_nothing_else() {
    let dir = scratch("extremes-precision-notes");
    let asset = scaled_sphere(&dir, "sphere", 1.0, 1.0);
    let notes = |name: &str, camera: Value, scale: f32| {
        let scene = json!({
            "output": { "width": 64, "height": 36 },
            "camera": camera,
            "objects": [{ "asset": asset, "transform": { "scale": [scale, scale, scale] },
                          "material": { "kind": "fur", "length": 0.04 / scale } }],
            "lights": [{ "position": [2.0 * scale, 3.0 * scale, 3.0 * scale], "color": [1, 1, 1], "intensity": 1, "radius": 10.0 * scale }]
        });
        let path = dir.join(format!("{name}.json"));
        std::fs::write(&path, scene.to_string()).expect("scene");
        let png = dir.join(format!("{name}.png"));
        let out = pelt_ok(&[
            "render",
            path.to_str().unwrap_or_default(),
            "-o",
            png.to_str().unwrap_or_default(),
        ]);
        let err = stderr(&out);
        println!("{name}: {err}");
        err.lines()
            .filter(|l| l.starts_with("pelt: note:"))
            .map(str::to_owned)
            .collect::<Vec<_>>()
    };
    let near = |far: f32| json!({ "position": [0.0, 1.4, 3.2], "target": [0.0, 0.5, 0.0], "near": 0.05, "far": far });
    assert_eq!(notes("ordinary", near(200.0), 1.0), Vec::<String>::new());
    assert_eq!(
        notes("far-20km", near(2e4), 1.0).len(),
        1,
        "the range note only"
    );
    let deep = notes("far-2000km", near(2e6), 1.0);
    assert!(
        deep.iter()
            .any(|n| n
                .contains("objects[0]: the L-buffer's depth codes over near 0.05 to far 2000000")),
        "{deep:?}"
    );
    let top = 0.5e6 + 1e6;
    let close = json!({ "position": [0.0, top + 0.6, 0.5], "target": [0.0, top, 0.0], "near": 0.05, "far": 100 });
    let planet = notes("planet", close, 1e6);
    assert!(
        planet.iter().any(|n| n.contains("objects[0]: its fur (4.000e-2 long, 16 shells 2.500e-3 apart) is finer than 32-bit float positions resolve")),
        "{planet:?}"
    );
}
