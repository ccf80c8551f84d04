//! End-to-end tests of `pelt bake` on the bundled fixtures: the comb round trip, the edge cases,
//! preservation of what pelt does not touch, determinism, and errors.

mod common;

use common::*;
use glam::{DVec3, Vec3};
use serde_json::Value;

/// Max angle between the decoded comb and the Gram-Schmidt'd input over a fixture.
fn max_round_trip_error(fixture_name: &str, extra: &[&str]) -> f64 {
    let dir = scratch("roundtrip");
    let out = bake(&fixture(fixture_name), &dir, extra);
    let b = read_baked(&out, 0, 0);
    let mut worst = 0f64;
    let mut checked = 0;
    for v in 0..b.positions.len() {
        if let Some(want) = b.expected_comb(v) {
            worst = worst.max(angle(b.object_comb(v), want));
            checked += 1;
        }
    }
    assert!(
        checked > b.positions.len() / 2,
        "too few combed vertices checked ({checked})"
    );
    worst
}

#[test]
fn float_comb_round_trips_within_1e_4_rad() {
    for f in [
        "creature.glb",
        "sphere.glb",
        "torus.glb",
        "edge/color-u16-tangents.gltf",
    ] {
        let e = max_round_trip_error(f, &[]);
        println!("{f}: float max error {e:.3e} rad");
        assert!(e < 1e-4, "{f}: {e} rad");
        let e = max_round_trip_error(f, &["--tangents", "regenerate"]);
        assert!(e < 1e-4, "{f} regenerated: {e} rad");
    }
}

#[test]
fn quantized_comb_stays_within_the_readme_bounds() {
    // Half a quantization step per component bounds the angle by √3/65535 (2.64e-5 rad) and
    // √3/255 (6.79e-3 rad); the README states these and the measured 2.60e-5 and 6.64e-3.
    let e16 = max_round_trip_error("creature.glb", &["--quantize", "u16"]);
    let e8 = max_round_trip_error("creature.glb", &["--quantize", "u8"]);
    println!("u16 max error {e16:.3e} rad, u8 max error {e8:.3e} rad");
    assert!(e16 <= 3f64.sqrt() / 65535.0 + 1e-7, "u16: {e16}");
    assert!(e8 <= 3f64.sqrt() / 255.0 + 1e-7, "u8: {e8}");
    assert!(e8 > e16);
}

#[test]
fn comb_is_tangential_and_unit() {
    let dir = scratch("unit");
    let b = read_baked(&bake(&fixture("creature.glb"), &dir, &[]), 0, 0);
    for c in &b.comb {
        let len = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
        assert!((len - 1.0).abs() < 1e-5, "{c:?}");
        assert!(c[2].abs() < 1e-5, "z = {}", c[2]);
        assert!((0.0..=1.0).contains(&c[3]));
    }
    for t in &b.tangents {
        assert!(t.w == 1.0 || t.w == -1.0);
    }
}

#[test]
fn mirrored_uvs_split_the_seam_and_keep_the_comb() {
    let dir = scratch("mirror");
    let out = bake(
        &fixture("edge/mirrored-uv.gltf"),
        &dir,
        &["--report", dir.join("r.json").to_str().unwrap_or_default()],
    );
    let b = read_baked(&out, 0, 0);
    let report: Value =
        serde_json::from_slice(&std::fs::read(dir.join("r.json")).unwrap_or_default())
            .unwrap_or_default();
    let prim = &report["inputs"][0]["primitives"][0];
    assert_eq!(prim["split_vertices"], 2, "{prim}");
    assert!(b.tangents.iter().any(|t| t.w == 1.0) && b.tangents.iter().any(|t| t.w == -1.0));
    for v in 0..b.positions.len() {
        assert!(angle(b.object_comb(v), DVec3::X) < 1e-6, "vertex {v}");
    }
}

#[test]
fn a_split_leaves_no_unused_accessors_or_views() {
    let dir = scratch("prune");
    let rep = dir.join("r.json");
    let out = bake(
        &fixture("edge/mirrored-uv.gltf"),
        &dir,
        &["--report", rep.to_str().unwrap_or_default()],
    );
    let report: Value =
        serde_json::from_slice(&std::fs::read(&rep).unwrap_or_default()).unwrap_or_default();
    assert!(
        report["inputs"][0]["removed_accessors"].as_u64() > Some(0),
        "{report}"
    );
    let doc = pelt_io::Document::load(&out).expect("load output");
    let mut used = vec![false; doc.array("accessors").len()];
    for m in doc.array("meshes") {
        for p in m["primitives"].as_array().into_iter().flatten() {
            let attrs = p["attributes"].as_object().into_iter().flatten();
            for a in attrs.map(|(_, v)| v).chain(p.get("indices")) {
                used[a.as_u64().expect("index") as usize] = true;
            }
        }
    }
    assert!(used.iter().all(|&u| u), "unused accessors: {used:?}");
    let mut views = vec![false; doc.array("bufferViews").len()];
    for a in doc.array("accessors") {
        views[a["bufferView"].as_u64().expect("view") as usize] = true;
    }
    // Fin records live in a bufferView of their own, referred to from extras.pelt.
    for m in doc.array("meshes") {
        for p in m["primitives"].as_array().into_iter().flatten() {
            if let Some(v) = p["extras"]["pelt"]["fins"]["bufferView"].as_u64() {
                views[v as usize] = true;
            }
        }
    }
    assert!(views.iter().all(|&u| u), "unused views: {views:?}");
}

#[test]
fn comb_along_the_normal_and_gray_have_defined_results() {
    let dir = scratch("parallel");
    let rep = dir.join("r.json");
    let out = bake(
        &fixture("edge/comb-parallel.gltf"),
        &dir,
        &["--report", rep.to_str().unwrap_or_default()],
    );
    let b = read_baked(&out, 0, 0);
    let report: Value =
        serde_json::from_slice(&std::fs::read(&rep).unwrap_or_default()).unwrap_or_default();
    let prim = &report["inputs"][0]["primitives"][0];
    // Grid 4 wide, 3 tall; top row +Y. Rows 0-1: x=0 along N, x=1 1e-7 rad off, x=2 gray.
    assert_eq!(prim["parallel_combs"], 4, "{prim}");
    assert_eq!(prim["gray_combs"], 2, "{prim}");
    for (v, c) in b.comb.iter().enumerate() {
        assert!(c.iter().all(|x| x.is_finite()));
        let x = v % 4;
        let y = v / 4;
        if y < 2 && x < 2 {
            assert_eq!(
                *c,
                [1.0, 0.0, 0.0, 0.8],
                "vertex {v}: tangent fallback, length kept"
            );
        } else if y < 2 && x == 2 {
            assert_eq!(c[3], 0.0, "vertex {v}: gray gives length 0");
        } else {
            assert!(angle(b.object_comb(v), DVec3::Y) < 1e-6);
        }
    }
}

#[test]
fn missing_normals_become_flat_and_split() {
    let dir = scratch("flat");
    let rep = dir.join("r.json");
    let out = bake(
        &fixture("edge/no-normals.gltf"),
        &dir,
        &[
            "--report",
            rep.to_str().unwrap_or_default(),
            "--crease-angle",
            "0",
        ],
    );
    let b = read_baked(&out, 0, 0);
    assert_eq!(b.positions.len(), 24, "8 corners × 3 faces each");
    for tri in b.indices.chunks(3) {
        let p = |k: usize| b.positions[tri[k] as usize].as_dvec3();
        let flat = (p(1) - p(0)).cross(p(2) - p(0)).normalize();
        for &v in tri {
            assert!((b.normals[v as usize].as_dvec3() - flat).length() < 1e-6);
        }
    }
    let report: Value =
        serde_json::from_slice(&std::fs::read(&rep).unwrap_or_default()).unwrap_or_default();
    assert_eq!(report["inputs"][0]["primitives"][0]["flat_normals"], true);
}

#[test]
fn missing_normals_are_smooth_within_the_crease_angle() {
    // The cube without NORMAL: its edges are 90° creases, so at the default 60° every corner
    // keeps its face's normal; at 180° the three faces at a corner average to the diagonal.
    for (crease, smooth) in [("60", false), ("180", true)] {
        let dir = scratch(&format!("smooth-{crease}"));
        let rep = dir.join("r.json");
        let out = bake(
            &fixture("edge/no-normals.gltf"),
            &dir,
            &[
                "--report",
                rep.to_str().unwrap_or_default(),
                "--crease-angle",
                crease,
            ],
        );
        let b = read_baked(&out, 0, 0);
        let (lo, hi) = b.positions.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), &p| (lo.min(p), hi.max(p)),
        );
        let centre = (lo + hi) / 2.0;
        for tri in b.indices.chunks(3) {
            let p = |k: usize| b.positions[tri[k] as usize].as_dvec3();
            let flat = (p(1) - p(0)).cross(p(2) - p(0)).normalize().as_vec3();
            for &v in tri {
                let n = b.normals[v as usize];
                let expect = if smooth {
                    (b.positions[v as usize] - centre).normalize()
                } else {
                    flat
                };
                assert!(
                    (n - expect).length() < 1e-5,
                    "crease {crease}: {n} against {expect}"
                );
            }
        }
        let report: Value =
            serde_json::from_slice(&std::fs::read(&rep).unwrap_or_default()).unwrap_or_default();
        let prim = &report["inputs"][0]["primitives"][0];
        assert_eq!(prim["smooth_normals"], true, "{prim}");
        assert_eq!(prim["flat_normals"], false, "{prim}");
        let warnings = report["inputs"][0]["warnings"].to_string();
        assert!(warnings.contains("smooth normals generated"), "{warnings}");
    }
}

#[test]
fn bad_normals_are_repaired_and_counted() {
    let dir = scratch("badn");
    let rep = dir.join("r.json");
    let out = bake(
        &fixture("edge/bad-normals.gltf"),
        &dir,
        &["--report", rep.to_str().unwrap_or_default()],
    );
    let report: Value =
        serde_json::from_slice(&std::fs::read(&rep).unwrap_or_default()).unwrap_or_default();
    let prim = &report["inputs"][0]["primitives"][0];
    assert_eq!(
        (
            prim["zero_normals"].as_u64(),
            prim["renormalized_normals"].as_u64()
        ),
        (Some(1), Some(1)),
        "{prim}"
    );
    let b = read_baked(&out, 0, 0);
    assert!(b.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-6));
}

#[test]
fn degenerate_triangles_are_counted_and_harmless() {
    let dir = scratch("degen");
    let rep = dir.join("r.json");
    let out = bake(
        &fixture("edge/degenerate.gltf"),
        &dir,
        &["--report", rep.to_str().unwrap_or_default()],
    );
    let report: Value =
        serde_json::from_slice(&std::fs::read(&rep).unwrap_or_default()).unwrap_or_default();
    let prim = &report["inputs"][0]["primitives"][0];
    assert_eq!(prim["degenerate_triangles"], 3, "{prim}");
    // The zero-UV-area triangle, and the collinear one (its derivatives vanish too).
    assert_eq!(prim["degenerate_uv_triangles"], 2, "{prim}");
    let b = read_baked(&out, 0, 0);
    assert!(b.comb.iter().flatten().all(|x| x.is_finite()));
    assert!(
        b.tangents
            .iter()
            .all(|t| (t.truncate().length() - 1.0).abs() < 1e-5)
    );
}

#[test]
fn every_color_encoding_is_read() {
    // VEC3 u8: length 1 everywhere.
    let dir = scratch("enc");
    let b = read_baked(&bake(&fixture("edge/color-vec3-u8.gltf"), &dir, &[]), 0, 0);
    assert!(b.comb.iter().all(|c| c[3] == 1.0));
    // Sparse: vertices 0, 5, 7 combed +X, the rest gray (length 0).
    let b = read_baked(&bake(&fixture("edge/sparse-color.gltf"), &dir, &[]), 0, 0);
    for (v, c) in b.comb.iter().enumerate() {
        if [0, 5, 7].contains(&v) {
            assert!(
                angle(b.object_comb(v), DVec3::X) < 1e-6 && c[3] == 1.0,
                "vertex {v}"
            );
        } else {
            assert_eq!(c[3], 0.0, "vertex {v}");
        }
    }
}

#[test]
fn obj_with_vertex_colors_bakes() {
    let dir = scratch("obj");
    let b = read_baked(&bake(&fixture("edge/painted.obj"), &dir, &[]), 0, 0);
    assert!(
        b.comb
            .iter()
            .all(|c| c[3] == 1.0 && c.iter().all(|x| x.is_finite()))
    );
    assert!(b.positions.len() >= 5);
}

#[test]
fn non_triangle_primitives_are_skipped_with_a_warning() {
    let dir = scratch("modes");
    let out = pelt_ok(&[
        "bake",
        "fixtures/edge/modes.gltf",
        "-o",
        dir.join("m.glb").to_str().unwrap_or_default(),
        "--report",
        "-",
    ]);
    let report: Value = serde_json::from_slice(&out.stdout).unwrap_or_default();
    let prims = &report["inputs"][0]["primitives"];
    assert_eq!(prims[0]["status"], "baked");
    assert!(
        prims[1]["status"].as_str().unwrap_or("").contains("mode 1"),
        "{prims}"
    );
    assert!(
        report["inputs"][0]["warnings"][0]
            .as_str()
            .unwrap_or("")
            .contains("primitives[1]")
    );
}

#[test]
fn untouched_parts_are_preserved() {
    let dir = scratch("preserve");
    let input = fixture("creature.glb");
    let out = bake(&input, &dir, &["--tangents", "regenerate"]);
    let a = pelt_io::Document::load(&input).expect("input");
    let b = pelt_io::Document::load(&out).expect("output");
    for key in ["asset", "scene", "scenes", "nodes", "materials"] {
        assert_eq!(a.json.get(key), b.json.get(key), "{key} changed");
    }
    let (pa, pb) = (
        &a.json["meshes"][0]["primitives"][0],
        &b.json["meshes"][0]["primitives"][0],
    );
    assert_eq!(pa["material"], pb["material"]);
    let ba = read_attr(&a, "COLOR_0");
    let bb = read_attr(&b, "COLOR_0");
    assert_eq!(ba, bb, "COLOR_0 changed");
    assert_eq!(read_attr(&a, "TEXCOORD_0"), read_attr(&b, "TEXCOORD_0"));
}

fn read_attr(doc: &pelt_io::Document, name: &str) -> Vec<u8> {
    let r = pelt_io::PrimitiveRef {
        mesh: 0,
        primitive: 0,
    };
    let i = doc.attribute(r, name).expect("attr").expect("present");
    pelt_io::accessor::read(doc, i, name)
        .expect("read")
        .bytes
        .into_owned()
}

#[test]
fn output_is_byte_identical_across_runs_and_thread_counts() {
    let dir = scratch("det");
    let mut outs = Vec::new();
    for threads in ["1", "2", "8"] {
        let o = dir.join(format!("t{threads}.glb"));
        let r = pelt(
            &[
                "bake",
                "-q",
                "fixtures/torus.glb",
                "-o",
                o.to_str().unwrap_or_default(),
                "--tangents",
                "regenerate",
                "--jobs",
                threads,
            ],
            &[],
        );
        assert!(r.status.success());
        outs.push(std::fs::read(&o).unwrap_or_default());
    }
    assert!(!outs[0].is_empty());
    assert!(outs.iter().all(|o| *o == outs[0]));
    let text = String::from_utf8_lossy(&outs[0]);
    assert!(
        !text.contains(dir.to_str().unwrap_or("?")),
        "absolute path inside output"
    );
}

#[test]
fn nan_is_an_error_naming_file_place_and_vertex() {
    let dir = scratch("nan");
    // Take the degenerate fixture and poison one normal.
    let mut doc = pelt_io::Document::load(&fixture("edge/mirrored-uv.gltf")).expect("load");
    let r = pelt_io::PrimitiveRef {
        mesh: 0,
        primitive: 0,
    };
    let i = doc.attribute(r, "NORMAL").expect("a").expect("normal");
    let view = doc.json["accessors"][i]["bufferView"].as_u64().unwrap_or(0) as usize;
    let off = doc.json["bufferViews"][view]["byteOffset"]
        .as_u64()
        .unwrap_or(0) as usize;
    doc.buffers[0][off + 12 * 3 + 4..off + 12 * 3 + 8].copy_from_slice(&f32::NAN.to_le_bytes());
    let bad = dir.join("nan.glb");
    pelt_io::glb::write_glb(&doc, &bad).expect("write");
    let out_path = dir.join("out.glb");
    let out = pelt(
        &[
            "bake",
            bad.to_str().unwrap_or_default(),
            "-o",
            out_path.to_str().unwrap_or_default(),
        ],
        &[],
    );
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    for part in [
        "nan.glb",
        "meshes[0]",
        "primitives[0]",
        "NORMAL",
        "vertex 3",
        "NaN",
    ] {
        assert!(err.contains(part), "{part:?} missing from: {err}");
    }
    assert!(!out_path.exists(), "partial output written");
}

#[test]
fn usage_errors_exit_2_and_failures_exit_1() {
    assert_eq!(pelt(&["bake"], &[]).status.code(), Some(2));
    assert_eq!(
        pelt(&["bake", "x.glb", "-o", "y.glb", "--quantize", "u4"], &[])
            .status
            .code(),
        Some(2)
    );
    assert_eq!(
        pelt(&["bake", "fixtures/torus.glb", "-o", "y.gltf"], &[])
            .status
            .code(),
        Some(2)
    );
    assert_eq!(
        pelt(
            &[
                "bake",
                "fixtures/torus.glb",
                "-o",
                "y.glb",
                "--comb-axes",
                "x,x,y"
            ],
            &[]
        )
        .status
        .code(),
        Some(2)
    );
    let dir = scratch("fail");
    let out = pelt(
        &[
            "bake",
            "fixtures/torus.glb",
            "fixtures/missing.glb",
            "-o",
            dir.to_str().unwrap_or_default(),
        ],
        &[],
    );
    assert_eq!(out.status.code(), Some(1));
    assert!(
        dir.join("torus.glb").exists(),
        "one failing input must not stop the others"
    );
    assert!(!dir.join("missing.glb").exists());
    assert!(String::from_utf8_lossy(&out.stderr).contains("missing.glb"));
}

#[test]
fn help_shows_examples() {
    let out = pelt_ok(&["bake", "--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("Examples:") && text.contains("--comb-axes x,z,-y"),
        "{text}"
    );
}

#[test]
fn comb_axes_remap_a_z_up_comb() {
    // Painted +Z in a Z-up tool is "up" = +Y in glTF; x,z,-y maps (x, y, z) → (x, z, -y).
    let dir = scratch("axes");
    let plain = read_baked(&bake(&fixture("edge/mirrored-uv.gltf"), &dir, &[]), 0, 0);
    let dir2 = scratch("axes2");
    let mapped = read_baked(
        &bake(
            &fixture("edge/mirrored-uv.gltf"),
            &dir2,
            &["--comb-axes", "y,x,z"],
        ),
        0,
        0,
    );
    // Painted +X; with y,x,z the direction becomes +Y, which is tangential on this +Z plane.
    for v in 0..plain.positions.len() {
        assert!(angle(plain.object_comb(v), DVec3::X) < 1e-6);
        assert!(angle(mapped.object_comb(v), DVec3::Y) < 1e-6);
    }
}

#[test]
fn inspect_reports_attributes_and_comb() {
    let dir = scratch("inspect");
    let out = bake(&fixture("torus.glb"), &dir, &["--quantize", "u16"]);
    let r = pelt_ok(&["inspect", out.to_str().unwrap_or_default(), "--json"]);
    let v: Value = serde_json::from_slice(&r.stdout).unwrap_or_default();
    let p = &v["primitive"][0];
    assert_eq!(
        p["attributes"]["_FUR_COMB"]["encoding"],
        "VEC4 unsigned short normalized"
    );
    assert_eq!(p["comb"]["count"], p["vertices"]);
    assert!(p["comb"]["max_abs_z"].as_f64().unwrap_or(1.0) < 1e-3);
    let text = pelt_ok(&["inspect", out.to_str().unwrap_or_default()]);
    assert!(String::from_utf8_lossy(&text.stdout).contains("_FUR_COMB"));
}

#[test]
fn generated_comb_is_the_axis_projected_on_the_surface() {
    // The sphere fixture (COLOR_0 painted, ignored here) baked with a comb generated toward
    // -Z, no smoothing, half length: in object space (T, B, N from the baked frame) the comb
    // is the axis projected on the tangent plane, wherever the axis is not along the normal.
    let dir = scratch("gen-comb");
    let config = dir.join("comb.json");
    std::fs::write(
        &config,
        r#"{"comb": {"source": "generate", "length": 0.5, "smoothing": 0}}"#,
    )
    .expect("config");
    let rep = dir.join("r.json");
    let out = bake(
        &fixture("sphere.glb"),
        &dir,
        &[
            "--config",
            config.to_str().unwrap_or_default(),
            "--report",
            rep.to_str().unwrap_or_default(),
        ],
    );
    let b = read_baked(&out, 0, 0);
    let axis = Vec3::NEG_Z;
    let mut checked = 0;
    for v in 0..b.positions.len() {
        let n = b.normals[v];
        assert!(
            (b.comb[v][3] - 0.5).abs() < 1e-6,
            "vertex {v}: length {}",
            b.comb[v][3]
        );
        let object = b.object_comb(v).as_vec3();
        if n.dot(axis).abs() > 0.9 {
            continue;
        }
        let expect = (axis - n * n.dot(axis)).normalize();
        assert!(
            object.normalize().dot(expect) > 0.995,
            "vertex {v}: comb {object} against {expect}"
        );
        checked += 1;
    }
    assert!(
        checked > b.positions.len() / 2,
        "only {checked} vertices checked"
    );
    let report: Value =
        serde_json::from_slice(&std::fs::read(&rep).unwrap_or_default()).unwrap_or_default();
    assert_eq!(report["options"]["comb"], "generate:0,0,-1");
    assert_eq!(report["inputs"][0]["primitives"][0]["generated_comb"], true);
    let warnings = report["inputs"][0]["warnings"].to_string();
    assert!(warnings.contains("COLOR_0 not read"), "{warnings}");
}

#[test]
fn the_fox_bakes_with_a_generated_comb_and_keeps_its_skin() {
    // No COLOR_0 and no NORMAL: painted, it gets nothing; generated, every vertex is combed
    // and JOINTS_0/WEIGHTS_0 follow the vertex split.
    let dir = scratch("fox");
    let plain = pelt(
        &[
            "bake",
            fixture("fox/Fox.glb").to_str().unwrap_or_default(),
            "-o",
            dir.join("plain.glb").to_str().unwrap_or_default(),
        ],
        &[],
    );
    let err = String::from_utf8_lossy(&plain.stderr).to_string()
        + &String::from_utf8_lossy(&plain.stdout);
    assert!(err.contains("--comb generate"), "{err}");
    let out = bake(&fixture("fox/Fox.glb"), &dir, &["--comb", "generate"]);
    let b = read_baked(&out, 0, 0);
    assert_eq!(b.indices.len(), 576 * 3);
    assert!(b.comb.iter().all(|c| c[3] == 1.0));
    let doc = pelt_io::Document::load(&out).expect("load");
    let r = pelt_io::PrimitiveRef {
        mesh: 0,
        primitive: 0,
    };
    for name in [
        "JOINTS_0",
        "WEIGHTS_0",
        "TEXCOORD_0",
        "NORMAL",
        "TANGENT",
        "_FUR_COMB",
    ] {
        let a = doc
            .attribute(r, name)
            .expect("attribute")
            .unwrap_or_else(|| panic!("{name} missing"));
        let count = doc.array("accessors")[a]["count"].as_u64();
        assert_eq!(count, Some(b.positions.len() as u64), "{name}");
    }
}

#[test]
fn generated_comb_length_follows_a_texture_channel() {
    // The sphere fixture given a base colour texture whose red channel steps 0, 85, 170, 255
    // across u (4×1 texels, REPEAT): baked with lengthTexture baseColor.r, every vertex's comb
    // length is 0.8 × the bilinear red value at its UV.
    let dir = scratch("len-tex");
    let mut doc = pelt_io::Document::load(&fixture("sphere.glb")).expect("load");
    let reds = [0u8, 85, 170, 255];
    let mut png_bytes = Vec::new();
    {
        let mut e = png::Encoder::new(&mut png_bytes, 4, 1);
        e.set_color(png::ColorType::Rgba);
        e.set_depth(png::BitDepth::Eight);
        let mut w = e.write_header().expect("header");
        let px: Vec<u8> = reds.iter().flat_map(|&r| [r, 10, 20, 255]).collect();
        w.write_image_data(&px).expect("data");
    }
    let image = doc.push_image(png_bytes, "image/png", "steps");
    let sampler = doc.push_sampler(9729, 9729, 10497, 10497);
    let texture = doc.push_texture(image, sampler, "steps");
    doc.json["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] =
        serde_json::json!({"index": texture});
    let input = dir.join("textured.glb");
    pelt_io::glb::write_glb(&doc, &input).expect("write");
    let config = dir.join("c.json");
    std::fs::write(
        &config,
        r#"{"comb": {"source": "generate", "length": 0.8,
            "lengthTexture": {"texture": "baseColor", "channel": "r"}}}"#,
    )
    .expect("config");
    let out_dir = dir.join("out");
    let out = bake(
        &input,
        &out_dir,
        &["--config", config.to_str().unwrap_or_default()],
    );
    let b = read_baked(&out, 0, 0);
    let m = pelt_io::mesh::read_primitive(
        &pelt_io::Document::load(&out).expect("load"),
        pelt_io::PrimitiveRef {
            mesh: 0,
            primitive: 0,
        },
    )
    .expect("read");
    let uvs = m.mesh.uvs.expect("uvs");
    let red = |k: i64| f32::from(reds[k.rem_euclid(4) as usize]) / 255.0;
    let mut seen = [false; 2];
    for (v, uv) in uvs.iter().enumerate() {
        let x = f64::from(uv.x) * 4.0 - 0.5;
        let (x0, f) = (x.floor(), (x - x.floor()) as f32);
        let expect = 0.8 * (red(x0 as i64) * (1.0 - f) + red(x0 as i64 + 1) * f);
        let got = b.comb[v][3];
        assert!(
            (got - expect).abs() < 1e-5,
            "vertex {v} at u {}: {got} against {expect}",
            uv.x
        );
        seen[usize::from(expect > 0.4)] = true;
    }
    assert_eq!(seen, [true, true], "both short and long fur sampled");
}
