//! The systematic extremes suite on generated inputs: every comb extreme (zero, grey, along
//! the normal, into the surface, tangent, alpha 0 and 1, subnormal values) baked to the
//! result docs/bake.md gives it, with the warning where fur is lost; geometry extremes (one
//! triangle, duplicated and non-manifold triangles, mirrored UVs, no UVs, no normals,
//! degenerate triangles) baked with the painted comb kept; and the render extremes (1 and 256
//! shells, fur length 0 and 100 times the mesh, grazing views to 89°, the light count limits)
//! drawn inferred as forward draws them, or refused with the place named. Each check has a
//! control that shows it can fail.

mod common;

use std::path::{Path, PathBuf};

use common::*;
use glam::{DVec3, Vec2, Vec3};
use pelt_fixtures::build::{self, BuildOptions};
use pelt_fixtures::shapes::Shape;
use serde_json::{Value, json};

/// An n × n grid over [-1, 1]² in the XZ plane facing +Y, every vertex painted `color`.
fn plane(n: u32, color: [f32; 4]) -> Shape {
    let mut s = Shape {
        name: "plane".into(),
        ..Shape::default()
    };
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
            s.positions
                .push(Vec3::new(2.0 * u - 1.0, 0.0, 2.0 * v - 1.0));
            s.normals.push(Vec3::Y);
            s.uvs.push(Vec2::new(u, v));
            s.colors.push(color);
        }
    }
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            let b = a + n + 1;
            s.indices.extend([a, b, a + 1, a + 1, b, b + 1]);
        }
    }
    s
}

/// Writes `shape` (edited by `edit`) to `dir/name.glb` and bakes it to `dir/out/name.glb`
/// with `extra` arguments; returns (baked path, stderr).
fn bake_shape(
    dir: &Path,
    name: &str,
    shape: &Shape,
    extra: &[&str],
    edit: impl FnOnce(&mut serde_json::Map<String, Value>),
) -> (PathBuf, String) {
    let mut doc = build::document(shape, BuildOptions::default());
    edit(&mut doc.json);
    let input = dir.join(format!("{name}.glb"));
    write_input(&doc, &input);
    let out = dir.join("out").join(format!("{name}.glb"));
    let mut args = vec![
        "bake",
        input.to_str().unwrap_or_default(),
        "-o",
        out.to_str().unwrap_or_default(),
    ];
    args.extend_from_slice(extra);
    let o = pelt_ok(&args);
    (out, String::from_utf8_lossy(&o.stderr).into_owned())
}

/// The bake's warnings (the lines that say `warning`).
fn warnings(stderr: &str) -> Vec<&str> {
    stderr
        .lines()
        .filter(|l| l.trim_start().starts_with("warning:"))
        .collect()
}

/// Every comb extreme on a plane facing +Y (tangent +X from its U): what the baked
/// `_FUR_COMB` holds at every vertex, and the warning the bake prints, or none.
#[test]
fn every_comb_extreme_bakes_to_its_documented_result_and_warns_where_fur_is_lost() {
    let dir = scratch("extreme-combs");
    let tiny = f32::from_bits(1); // the smallest subnormal float
    let along = "16 of 16 vertices' combs lie along the normal or point straight into the surface";
    let bald_alpha = "no fur: every comb has alpha 0";
    let (x, z) = (DVec3::X, DVec3::Z);
    // (case, painted RGBA, expected object-space direction and length, expected warning)
    let cases = [
        ("zero", [0.0; 4], -(x + z), 0.0, Some(bald_alpha)),
        (
            "grey",
            [0.5, 0.5, 0.5, 1.0],
            x,
            0.0,
            Some("no fur: every comb is grey"),
        ),
        (
            "grey 8-bit",
            [0.5, 0.498, 0.502, 1.0],
            x,
            0.0,
            Some("no fur: every comb is grey"),
        ),
        (
            "along the normal",
            [0.5, 1.0, 0.5, 1.0],
            x,
            1.0,
            Some(along),
        ),
        (
            "into the surface",
            [0.5, 0.0, 0.5, 0.6],
            x,
            0.6,
            Some(along),
        ),
        ("tangent +X", [1.0, 0.5, 0.5, 1.0], x, 1.0, None),
        (
            "tangent -Z, half length",
            [0.5, 0.5, 0.0, 0.5],
            -z,
            0.5,
            None,
        ),
        (
            "alpha 0 with a direction",
            [1.0, 0.5, 0.5, 0.0],
            x,
            0.0,
            Some(bald_alpha),
        ),
        (
            "subnormal alpha",
            [1.0, 0.5, 0.5, tiny],
            x,
            0.0,
            Some(bald_alpha),
        ),
        ("subnormal direction", [tiny, 0.5, 0.5, 1.0], -x, 1.0, None),
    ];
    for (k, (case, color, direction, length, warning)) in cases.into_iter().enumerate() {
        let (out, stderr) = bake_shape(&dir, &format!("comb-{k}"), &plane(3, color), &[], |_| {});
        let baked = read_baked(&out, 0, 0);
        for (v, c) in baked.comb.iter().enumerate() {
            let off = angle(baked.object_comb(v), direction);
            assert!(
                off <= 1e-6 && c[3] == length,
                "{case}: vertex {v} baked {c:?}: {off} rad from {direction}, length {length}"
            );
        }
        let said = warnings(&stderr);
        match warning {
            Some(w) => assert!(
                said.len() == 1 && said[0].contains(w),
                "{case}: expected the warning {w:?}, the bake said {said:?}"
            ),
            None => assert!(said.is_empty(), "{case}: unexpected warnings {said:?}"),
        }
    }
    // Control: a mixed bald primitive names both causes, and one furred vertex silences it.
    let mut mixed = plane(3, [0.5, 0.5, 0.5, 1.0]);
    mixed.colors[0] = [1.0, 0.5, 0.5, 0.0];
    let (_, stderr) = bake_shape(&dir, "mixed", &mixed, &[], |_| {});
    assert!(
        stderr.contains("no fur: 15 combs are grey and the rest have alpha 0"),
        "{stderr}"
    );
    mixed.colors[0] = [1.0, 0.5, 0.5, 0.01];
    let (_, stderr) = bake_shape(&dir, "one-furred", &mixed, &[], |_| {});
    assert!(warnings(&stderr).is_empty(), "{stderr}");
}

/// The largest angle between the painted comb (after Gram-Schmidt) and the baked one decoded
/// through the baked tangent frame, over the vertices whose comb has a direction.
fn worst_comb_angle(out: &Path) -> f64 {
    let baked = read_baked(out, 0, 0);
    (0..baked.positions.len())
        .filter_map(|v| Some(angle(baked.object_comb(v), baked.expected_comb(v)?)))
        .fold(0.0, f64::max)
}

/// The painted comb of `fixtures`' creature field on a shape's own vertices, tilted off the
/// normal so that every vertex has a direction on the surface.
fn painted(shape: &mut Shape) {
    for (c, n) in shape.colors.iter_mut().zip(&shape.normals) {
        let d = (Vec3::new(0.3, -0.8, 0.5) - *n * 0.2).normalize();
        *c = [0.5 + 0.5 * d.x, 0.5 + 0.5 * d.y, 0.5 + 0.5 * d.z, 1.0];
    }
}

/// Geometry at its extremes bakes, keeps the painted comb within 1e-4 rad wherever the comb
/// has a direction on the surface, and says what it made up.
#[test]
fn geometry_extremes_bake_and_keep_the_painted_comb() {
    let dir = scratch("extreme-geometry");
    let mut sphere = pelt_fixtures::shapes::sphere(8, 16);
    painted(&mut sphere);
    // One triangle.
    let mut one = sphere.clone();
    one.indices.truncate(3 * 17);
    one.indices.drain(..3 * 16);
    // Every triangle twice (a duplicated export), and three triangles on one edge.
    let mut twice = sphere.clone();
    twice.indices.extend(sphere.indices.clone());
    let mut fan = plane(1, [1.0, 0.5, 0.8, 1.0]);
    let apex = fan.positions.len() as u32;
    fan.positions.push(Vec3::new(0.0, 1.0, 0.0));
    fan.normals.push(Vec3::Z);
    fan.uvs.push(Vec2::new(0.5, 1.0));
    fan.colors.push([1.0, 0.5, 0.5, 1.0]);
    fan.indices.extend([1, 2, apex]); // the diagonal (1, 2) now has three triangles
    // Mirrored UVs: the half at x < 0 reads its U backwards (tangent frames with w = -1).
    let mut mirrored = sphere.clone();
    for (uv, p) in mirrored.uvs.iter_mut().zip(&mirrored.positions) {
        if p.x < 0.0 {
            uv.x = 1.0 - uv.x;
        }
    }
    // Degenerate triangles among the good ones.
    let mut degenerate = sphere.clone();
    degenerate.indices.extend([0, 0, 0, 5, 6, 5, 20, 21, 20]);
    let no_uvs = "no TEXCOORD_0: the fur's strand textures are laid out by it";
    let no_normals = "no NORMAL";
    let cases: [(&str, &Shape, bool, bool, Option<&str>); 7] = [
        ("one triangle", &one, true, true, None),
        (
            "every triangle twice",
            &twice,
            true,
            true,
            Some("336 of 336 edges are shared by three or more triangles (non-manifold)"),
        ),
        (
            "three triangles on an edge",
            &fan,
            true,
            true,
            Some("1 of 7 edges are shared by three or more triangles (non-manifold)"),
        ),
        ("mirrored UVs", &mirrored, true, true, None),
        ("degenerate triangles", &degenerate, true, true, None),
        ("no UVs", &sphere, false, true, Some(no_uvs)),
        ("no normals", &sphere, true, false, Some(no_normals)),
    ];
    for (k, (case, shape, uvs, normals, warning)) in cases.into_iter().enumerate() {
        let (out, stderr) = bake_shape(&dir, &format!("geometry-{k}"), shape, &[], |j| {
            let attrs = &mut j["meshes"][0]["primitives"][0]["attributes"];
            let attrs = attrs.as_object_mut().expect("attributes");
            if !uvs {
                attrs.remove("TEXCOORD_0");
            }
            if !normals {
                attrs.remove("NORMAL");
            }
        });
        let worst = worst_comb_angle(&out);
        println!(
            "{case}: worst comb angle {worst:.2e} rad; {:?}",
            warnings(&stderr)
        );
        assert!(worst <= 1e-4, "{case}: comb off by {worst} rad");
        match warning {
            Some(w) => assert!(stderr.contains(w), "{case}: expected {w:?} in {stderr}"),
            None => assert!(warnings(&stderr).is_empty(), "{case}: {stderr}"),
        }
        assert!(!stderr.contains("NaN"), "{case}: {stderr}");
    }
    // Control: the comb check sees a comb decoded through the wrong frame (w flipped).
    let (out, _) = bake_shape(&dir, "control", &mirrored, &[], |_| {});
    let mut baked = read_baked(&out, 0, 0);
    for t in &mut baked.tangents {
        t.w = -t.w;
    }
    let off = (0..baked.positions.len())
        .filter_map(|v| Some(angle(baked.object_comb(v), baked.expected_comb(v)?)))
        .fold(0.0, f64::max);
    assert!(off > 0.1, "the control passes: {off}");
}

/// `fixtures/sphere.glb` baked with `fixtures/fur.json` into `dir`.
fn furry_sphere(dir: &Path) -> PathBuf {
    bake(
        &fixture("sphere.glb"),
        dir,
        &["--config", "fixtures/fur.json"],
    )
}

/// A 160×90 scene of `asset` as fur of `length` and `shells` seen from `eye` toward `target`,
/// lit by a white key light and a blue fill.
fn fur_scene(asset: &Path, material: Value, eye: [f32; 3], target: [f32; 3], far: f32) -> Value {
    json!({
        "output": { "width": 160, "height": 90 },
        "camera": { "position": eye, "target": target, "fovYDeg": 40, "near": 0.01, "far": far },
        "ambient": [0.05, 0.05, 0.05],
        "objects": [{ "asset": asset, "material": material }],
        "lights": [
            { "position": [2.0, 2.5, 3.0], "color": [1, 1, 1], "intensity": 6, "radius": 10 },
            { "position": [-3.0, 1.5, 1.0], "color": [0.5, 0.6, 1], "intensity": 2, "radius": 10 }
        ]
    })
}

/// Renders `scene` forward and inferred; asserts inferred is within `floor` of forward and
/// never near black where forward draws lit fur. Returns the forward picture.
fn inferred_as_forward(dir: &Path, name: &str, scene: &Value, floor: f32) -> pelt_preview::Image {
    let forward = render_in(dir, name, scene, &["--mode", "forward"]);
    let inferred = render_in(dir, name, scene, &["--mode", "inferred"]);
    let f = flip_of(&forward, &inferred);
    let black = near_black_where_lit(&forward, &inferred);
    println!("{name}: inferred against forward FLIP {f:.4}, {black} near-black pixels");
    assert!(f <= floor, "{name}: inferred against forward FLIP {f}");
    assert_eq!(black, 0, "{name}: inferred near black where forward is lit");
    forward
}

/// Writes `scene` to `dir/name.json` and runs `pelt render -q` on it to `dir/name-MODE.png`
/// in `mode`; returns the run, its stderr and the image's path.
fn render_cli(
    dir: &Path,
    name: &str,
    scene: &Value,
    mode: &str,
) -> (std::process::Output, String, PathBuf) {
    let path = dir.join(format!("{name}.json"));
    std::fs::write(&path, scene.to_string()).expect("scene");
    let png = dir.join(format!("{name}-{mode}.png"));
    let o = pelt(
        &[
            "render",
            "-q",
            path.to_str().unwrap_or_default(),
            "-o",
            png.to_str().unwrap_or_default(),
            "--mode",
            mode,
        ],
        &[],
    );
    let e = String::from_utf8_lossy(&o.stderr).into_owned();
    (o, e, png)
}

/// One and 256 shells, fur 0.15 and 100 times the unit sphere: inferred draws what forward
/// draws. Fur of length 0 is bald: its skin alone, as the strand reference draws it. Shell
/// counts past the range are refused, naming the place.
#[test]
fn shell_counts_and_fur_lengths_at_their_ends_draw_inferred_as_forward() {
    let dir = scratch("extreme-render");
    let sphere = furry_sphere(&dir);
    let near = ([0.0, 1.2, 4.5], 20.0);
    let far = ([0.0, 80.0, 420.0], 1000.0);
    let near_scene =
        |material: Value| fur_scene(&sphere, material, near.0, [0.0, 0.5, 0.0], near.1);
    for (shells, length, (eye, depth), floor) in [
        (1, 0.15, near, 0.05),
        (256, 0.15, near, 0.03),
        (1, 100.0, far, 0.01),
        (16, 100.0, far, 0.01),
        (256, 100.0, far, 0.01),
    ] {
        let material = json!({ "kind": "fur", "length": length, "shells": shells });
        let scene = fur_scene(&sphere, material, eye, [0.0, 0.5, 0.0], depth);
        inferred_as_forward(
            &dir,
            &format!("shells-{shells}-length-{length}"),
            &scene,
            floor,
        );
    }
    // Bald fur: the skin, in every mode, as the strand reference draws it.
    let bald = near_scene(json!({ "kind": "fur", "length": 0 }));
    let strands = render_in(&dir, "bald", &bald, &["--mode", "strands"]);
    for (mode, floor) in [("forward", 0.01), ("inferred", 0.05), ("deferred", 0.05)] {
        let f = flip_of(&render_in(&dir, "bald", &bald, &["--mode", mode]), &strands);
        println!("bald fur: {mode} against the strand reference FLIP {f:.4}");
        assert!(f <= floor, "bald fur, {mode}: FLIP {f}");
    }
    // Control: furred, the picture is another one.
    let furred = near_scene(json!({ "kind": "fur", "length": 0.15 }));
    let f = flip_of(
        &render_in(&dir, "furred", &furred, &["--mode", "forward"]),
        &strands,
    );
    assert!(f > 0.05, "the control passes: FLIP {f}");
    // Shell counts outside 1 to 256 are refused with their place; nothing is written.
    for shells in [0, 257] {
        let scene = near_scene(json!({ "kind": "fur", "shells": shells }));
        let (o, e, png) = render_cli(&dir, &format!("shells-{shells}"), &scene, "inferred");
        assert_eq!(o.status.code(), Some(2), "{e}");
        assert!(
            e.contains(&format!(
                "objects[0].material: shells must be 1 to 256, got {shells}"
            )),
            "{e}"
        );
        assert!(!png.exists(), "shells {shells}: an image was written");
    }
}

/// A furry plane seen from the side of its fur at 1° to 89° from its normal: inferred draws
/// what forward draws (within FLIP 0.06; head-on is the widest), with no dark pixels at its
/// ends.
#[test]
fn grazing_views_to_89_degrees_draw_inferred_as_forward() {
    let dir = scratch("extreme-grazing");
    let mut shape = plane(16, [0.5, 0.75, 0.0, 0.6]); // combed toward -Z, lifted
    shape.name = "slab".into();
    std::fs::create_dir_all(dir.join("in")).expect("in/");
    let input = dir.join("in").join("slab.glb");
    write_input(&build::document(&shape, BuildOptions::default()), &input);
    let slab = bake(&input, &dir, &["--config", "fixtures/fur.json"]);
    // The fixtures' root node lifts the mesh to y = 0.5.
    for degrees in [1.0f32, 60.0, 80.0, 85.0, 89.0] {
        let a = degrees.to_radians();
        let eye = [0.0, 0.5 + 3.0 * a.cos(), 3.0 * a.sin()];
        let material = json!({ "kind": "fur", "length": 0.15 });
        let scene = fur_scene(&slab, material, eye, [0.0, 0.5, 0.0], 50.0);
        inferred_as_forward(&dir, &format!("grazing-{degrees}"), &scene, 0.06);
    }
}

/// The light count limits: forward lights 256 lights in one pass and refuses more before
/// the GPU starts, naming the scene (inferred lights them all); past 8 shadow-casting lights
/// the rest light without shadows, with a note in every mode.
#[test]
fn light_count_limits_are_lit_or_named() {
    let dir = scratch("extreme-lights");
    let sphere = furry_sphere(&dir);
    let scene = |n: usize, shadows: usize| {
        let lights: Vec<Value> = (0..n)
            .map(|i| {
                let a = i as f32 * 2.399;
                json!({
                    "position": [3.0 * a.cos(), 1.5 + (i % 5) as f32 * 0.3, 3.0 * a.sin()],
                    "color": [1.0, 0.9, 0.8], "intensity": 24.0 / n as f32, "radius": 8,
                    "shadows": i < shadows
                })
            })
            .collect();
        let mut s = fur_scene(
            &sphere,
            json!({ "kind": "fur" }),
            [0.0, 1.2, 4.5],
            [0.0, 0.5, 0.0],
            20.0,
        );
        s["lights"] = json!(lights);
        s
    };
    inferred_as_forward(&dir, "lights-256", &scene(256, 0), 0.03);
    for (mode, code) in [
        ("forward", Some(1)),
        ("strands", Some(1)),
        ("inferred", Some(0)),
    ] {
        let (o, e, png) = render_cli(&dir, "lights-257", &scene(257, 0), mode);
        assert_eq!(o.status.code(), code, "{mode}: {e}");
        if code == Some(1) {
            assert!(
                e.contains("lights-257.json: lights: ")
                    && e.contains(&format!("{mode} mode takes at most 256 lights in one pass; the scene has 257 on screen")),
                "{mode}: {e}"
            );
            assert!(!png.exists(), "{mode}: an image was written");
        } else {
            assert!(png.exists(), "{mode}: no image");
        }
    }
    for mode in ["forward", "inferred", "strands"] {
        let (o, e, _) = render_cli(&dir, "shadows-9", &scene(9, 9), mode);
        assert_eq!(o.status.code(), Some(0), "{mode}: {e}");
        assert!(
            e.contains("lights[8]: at most 8 lights cast shadows; these light without"),
            "{mode}: {e}"
        );
    }
    // Control: eight shadow-casting lights say nothing.
    let (o, e, _) = render_cli(&dir, "shadows-8", &scene(8, 8), "inferred");
    assert!(o.status.success() && e.is_empty(), "{e}");
}
