//! `pelt pose` on the skinned cylinder of `pelt_fixtures::skinned` (two joints, weights that
//! blend between y = 0.8 and 1.2, the clip "Bend" turning the upper joint 90° about +Z):
//! positions against the closed form, the comb carried by the skin, the rest pose, bad input.

mod common;

use std::path::{Path, PathBuf};

use common::*;
use glam::{Mat3, Quat, Vec3};
use pelt_fixtures::skinned;

/// The cylinder, baked (painted comb, groups and fins).
fn baked_cylinder(dir: &Path) -> PathBuf {
    let src = dir.join("src");
    std::fs::create_dir_all(&src).expect("mkdir");
    let src = src.join("bent-cylinder.glb");
    write_input(&skinned::bent_cylinder(), &src);
    bake(&src, dir, &[])
}

fn pose(input: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "pose",
        input.to_str().unwrap_or_default(),
        "-o",
        out.to_str().unwrap_or_default(),
    ];
    args.extend_from_slice(extra);
    pelt(&args, &[])
}

/// WEIGHTS_0's weight on joint 1 per vertex of the baked file.
fn bend_weights(path: &Path) -> Vec<f32> {
    let doc = pelt_io::Document::load(path).expect("load");
    let r = pelt_io::PrimitiveRef {
        mesh: 0,
        primitive: 0,
    };
    let a = doc
        .attribute(r, "WEIGHTS_0")
        .expect("attr")
        .expect("WEIGHTS_0");
    pelt_io::accessor::read_vec::<4>(&doc, a, "WEIGHTS_0")
        .expect("weights")
        .iter()
        .map(|w| w[1])
        .collect()
}

/// Where the closed form puts a rest position with weight `w` on the bend joint at angle θ.
fn expected(p: Vec3, w: f32, theta: f32) -> Vec3 {
    let pivot = Vec3::Y;
    let turned = Quat::from_rotation_z(theta) * (p - pivot) + pivot;
    p * (1.0 - w) + turned * w
}

#[test]
fn posed_positions_and_comb_follow_the_skin() {
    let dir = scratch("pose");
    let rest_path = baked_cylinder(&dir);
    let rest = read_baked(&rest_path, 0, 0);
    let w = bend_weights(&rest_path);
    let extent = 2.0f32;
    for (time, theta) in [(1.0f32, 90f32.to_radians()), (0.5, 45f32.to_radians())] {
        let out = dir.join(format!("posed-{time}.glb"));
        let o = pose(
            &rest_path,
            &out,
            &["--animation", "Bend", "--time", &time.to_string()],
        );
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let posed = read_baked(&out, 0, 0);
        assert_eq!(posed.positions.len(), rest.positions.len());
        let mut worst_blend = 0f64;
        for (v, &wv) in w.iter().enumerate() {
            let e = expected(rest.positions[v], wv, theta);
            let d = (posed.positions[v] - e).length();
            assert!(
                d < 1e-5 * extent,
                "t {time} vertex {v}: {} against {e}",
                posed.positions[v]
            );
            // The comb in object space, rebuilt from the posed frame, against the rest comb
            // carried by the blended skin matrix (its 3×3: (1 − w) I + w Rz(θ)).
            let m = Mat3::IDENTITY * (1.0 - wv) + Mat3::from_rotation_z(theta) * wv;
            let carried = (m.as_dmat3() * rest.object_comb(v)).normalize();
            let got = posed.object_comb(v).normalize();
            let angle = angle(carried, got);
            if wv == 0.0 || wv == 1.0 {
                assert!(angle < 1e-5, "t {time} vertex {v} (rigid): {angle} rad");
            } else {
                worst_blend = worst_blend.max(angle);
            }
        }
        // Where weights blend, the matrix (1 − w) I + w Rz(θ) is no rotation: at w = 1/2 it
        // is Rz(θ/2) times a scale of c = cos(θ/2) in the bend's plane (1 across it), and
        // the posed frame (T by the matrix, N by its cofactor, B = N × T) differs from the
        // matrix applied to the comb by at most the largest turn that scale gives a
        // direction, atan(1/√c) − atan(√c): 9.88° at 90°, 2.27° at 45° (measured 9.74° and
        // 2.27° on this helix comb).
        let c = f64::from(theta / 2.0).cos();
        let bound = (1.0 / c.sqrt()).atan() - c.sqrt().atan() + 1e-4;
        assert!(
            worst_blend <= bound,
            "t {time}: {worst_blend} rad against {bound}"
        );
        assert!(
            worst_blend > bound / 2.0,
            "t {time}: the blend was not exercised"
        );
    }
}

#[test]
fn step_keys_hold_and_times_clamp() {
    let dir = scratch("pose-step");
    let rest_path = baked_cylinder(&dir);
    let rest = read_baked(&rest_path, 0, 0);
    let w = bend_weights(&rest_path);
    for (clip, time, theta) in [
        ("BendStep", "0.99", 0.0f32),
        ("BendStep", "1", 90f32.to_radians()),
        ("Bend", "-3", 0.0),
        ("Bend", "7", 90f32.to_radians()),
    ] {
        let out = dir.join(format!("{clip}-{time}.glb"));
        let o = pose(&rest_path, &out, &["--animation", clip, "--time", time]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let posed = read_baked(&out, 0, 0);
        for (v, &wv) in w.iter().enumerate() {
            let e = expected(rest.positions[v], wv, theta);
            assert!(
                (posed.positions[v] - e).length() < 2e-5,
                "{clip} at {time}, vertex {v}"
            );
        }
    }
}

#[test]
fn the_posed_file_is_static_and_keeps_the_baked_topology() {
    let dir = scratch("pose-static");
    let rest_path = baked_cylinder(&dir);
    let out = dir.join("posed.glb");
    let o = pose(&rest_path, &out, &["--animation", "Bend", "--time", "1"]);
    assert!(o.status.success());
    let doc = pelt_io::Document::load(&out).expect("load");
    assert!(doc.array("skins").is_empty() && doc.array("animations").is_empty());
    let r = pelt_io::PrimitiveRef {
        mesh: 0,
        primitive: 0,
    };
    for gone in ["JOINTS_0", "WEIGHTS_0"] {
        assert_eq!(doc.attribute(r, gone).expect("attr"), None, "{gone}");
    }
    let before = pelt_io::Document::load(&rest_path).expect("load");
    let fins = |d: &pelt_io::Document| d.read_fins(r).expect("fins");
    assert_eq!(fins(&doc), fins(&before), "fin records changed");
    // The rest pose (no clip) gives the rest positions back.
    let still = dir.join("still.glb");
    assert!(pose(&rest_path, &still, &[]).status.success());
    let (a, b) = (read_baked(&rest_path, 0, 0), read_baked(&still, 0, 0));
    for (p, q) in a.positions.iter().zip(&b.positions) {
        assert!((*p - *q).length() < 1e-6);
    }
}

#[test]
fn bad_rigs_are_named_errors_with_no_output() {
    let dir = scratch("pose-bad");
    let rest_path = baked_cylinder(&dir);
    let doc = pelt_io::Document::load(&rest_path).expect("load");
    // (what, mutation of the JSON, expected words in the error)
    type Edit = fn(&mut serde_json::Map<String, serde_json::Value>);
    let cases: [(&str, Edit, &str); 4] = [
        (
            "joint outside the scene",
            |j| {
                j["nodes"]
                    .as_array_mut()
                    .expect("nodes")
                    .push(serde_json::json!({"name": "stray"}));
                let n = j["nodes"].as_array().map_or(0, Vec::len) - 1;
                j["skins"][0]["joints"][1] = serde_json::json!(n);
            },
            "skins[0].joints[1]: node",
        ),
        (
            "inverse bind matrices of the wrong type",
            |j| {
                j["skins"][0]["inverseBindMatrices"] =
                    j["animations"][0]["samplers"][0]["output"].clone();
            },
            "expected Mat4 of F32",
        ),
        (
            "two parents",
            |j| {
                j["nodes"][0]["children"] = serde_json::json!([2]);
            },
            "already a child",
        ),
        (
            "too few joints for JOINTS_0",
            |j| {
                j["skins"][0]["joints"] = serde_json::json!([j["skins"][0]["joints"][0]]);
                j["skins"][0]
                    .as_object_mut()
                    .expect("skin")
                    .remove("inverseBindMatrices");
            },
            "names joint 1, but the skin has 1 joints",
        ),
    ];
    for (what, edit, words) in cases {
        let mut d = doc.clone();
        edit(&mut d.json);
        let input = dir.join(format!("{}.glb", what.replace(' ', "-")));
        write_input(&d, &input);
        let out = dir.join("out.glb");
        let o = pose(&input, &out, &["--animation", "Bend", "--time", "1"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{what}: {err}");
        assert!(
            err.contains(words) && err.contains(input.to_str().unwrap_or("?")),
            "{what}: {err}"
        );
        assert!(!err.contains("panicked"), "{what}: {err}");
        assert!(!out.exists(), "{what}: output written");
    }
    // A name that does not exist lists those that do.
    let o = pose(&rest_path, &dir.join("x.glb"), &["--animation", "Trot"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains(r#"no animation named "Trot": the file has "Bend", "BendStep""#),
        "{err}"
    );
}

#[test]
fn nan_keys_and_unnormalized_weights() {
    let dir = scratch("pose-nan");
    let rest_path = baked_cylinder(&dir);
    let doc = pelt_io::Document::load(&rest_path).expect("load");
    // NaN in the rotation keys: an error naming the sampler's output.
    let mut d = doc.clone();
    let out_acc = d.json["animations"][0]["samplers"][0]["output"]
        .as_u64()
        .expect("output") as usize;
    poke_f32(&mut d, out_acc, 5, f32::NAN);
    let input = dir.join("nan.glb");
    write_input(&d, &input);
    let o = pose(
        &input,
        &dir.join("out.glb"),
        &["--animation", "Bend", "--time", "1"],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("animations[0].samplers[0].output: value 5 is NaN"),
        "{err}"
    );
    // A singular inverse bind matrix (the second joint's scaled to zero).
    let mut d = doc.clone();
    let ibm = d.json["skins"][0]["inverseBindMatrices"]
        .as_u64()
        .expect("ibm") as usize;
    for k in 16..32 {
        poke_f32(&mut d, ibm, k, 0.0);
    }
    let input = dir.join("singular.glb");
    write_input(&d, &input);
    let o = pose(&input, &dir.join("out.glb"), &["--animation", "Bend"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("skins[0].inverseBindMatrices[1]: singular"),
        "{err}"
    );
    // Weights summing to 2 everywhere: normalized (same pose), counted in a warning.
    let mut d = doc.clone();
    let r = pelt_io::PrimitiveRef {
        mesh: 0,
        primitive: 0,
    };
    let wa = d.attribute(r, "WEIGHTS_0").expect("attr").expect("weights");
    let n = d.array("accessors")[wa]["count"].as_u64().unwrap_or(0) as usize;
    let w = pelt_io::accessor::read_vec::<4>(&d, wa, "w").expect("w");
    for (v, w) in w.iter().enumerate() {
        for (k, x) in w.iter().enumerate() {
            poke_f32(&mut d, wa, 4 * v + k, x * 2.0);
        }
    }
    let input = dir.join("heavy.glb");
    write_input(&d, &input);
    let heavy = dir.join("heavy-posed.glb");
    let o = pose(&input, &heavy, &["--animation", "Bend", "--time", "1"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains(&format!("{n} vertices had weights that do not sum to 1")),
        "{err}"
    );
    let normal = dir.join("normal-posed.glb");
    assert!(
        pose(&rest_path, &normal, &["--animation", "Bend", "--time", "1"])
            .status
            .success()
    );
    let (a, b) = (read_baked(&heavy, 0, 0), read_baked(&normal, 0, 0));
    for (p, q) in a.positions.iter().zip(&b.positions) {
        assert!((*p - *q).length() < 1e-6);
    }
}

/// Overwrites float `k` of accessor `a` (tightly packed, in buffer 0).
fn poke_f32(d: &mut pelt_io::Document, a: usize, k: usize, value: f32) {
    let acc = &d.array("accessors")[a];
    let view = acc["bufferView"].as_u64().expect("view") as usize;
    let off = acc["byteOffset"].as_u64().unwrap_or(0) as usize;
    let v = &d.array("bufferViews")[view];
    let stride = v["byteStride"].as_u64().unwrap_or(0) as usize;
    assert_eq!(stride, 0, "packed views only");
    let at = v["byteOffset"].as_u64().unwrap_or(0) as usize + off + 4 * k;
    d.buffers[0][at..at + 4].copy_from_slice(&value.to_le_bytes());
}
