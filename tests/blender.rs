//! The Blender add-on (`blender/pelt_fur`) in Debian's Blender, headless: `tests/blender/
//! scene.py` grooms a wavy grid with hair particles combed toward +X, runs
//! `bpy.ops.pelt.comb_from_hair` and `bpy.ops.pelt.export_baked` (and again with the groom
//! converted to a Curves hair object), exports a grid painted by
//! hand (byte colours, no flags) the same way, and makes a bake fail. Here the baked
//! `_FUR_COMB` is decoded through the baked frame (docs/bake.md) and compared with the hair
//! (its root segment laid on the surface) and with the paint (Listing 2.7).
//!
//! Without `blender` (Debian `blender python3-numpy`) the test is skipped, unless
//! `PELT_REQUIRE_BLENDER` is set (CI sets it and installs Blender).

mod common;

use std::collections::HashMap;
use std::path::Path;
use std::process::Command;

use common::*;
use glam::DVec3;
use serde_json::Value;

/// Floors for the groom: median and 95th-percentile angle (degrees) between the decoded comb
/// and the hair at vertices within one edge length of a root.
const HAIR_MEDIAN_DEG: f64 = 3.0;
const HAIR_P95_DEG: f64 = 10.0;
/// The painted comb: 8-bit paint comes back exact but for float rounding (radians).
const PAINTED_MAX_RAD: f64 = 1e-3;

fn vec3(v: &Value) -> DVec3 {
    let a = |i: usize| v[i].as_f64().expect("number");
    DVec3::new(a(0), a(1), a(2))
}

/// A JSON file `scene.py` wrote.
fn read_json(path: &Path) -> Value {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_slice(&bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Position key: the exporter writes Blender's coordinates as f32, the bake keeps them.
fn key(p: DVec3) -> [i64; 3] {
    [p.x, p.y, p.z].map(|c| (c * 1e4).round() as i64)
}

/// Per baked vertex, its decoded comb and the entry of `expected` at its position.
fn pairs<'e>(glb: &Path, expected: &'e Value) -> Vec<(DVec3, DVec3, &'e Value)> {
    let by_position: HashMap<[i64; 3], &Value> = expected["vertices"]
        .as_array()
        .expect("vertices")
        .iter()
        .map(|v| (key(vec3(&v["position"])), v))
        .collect();
    let baked = read_baked(glb, 0, 0);
    (0..baked.positions.len())
        .map(|v| {
            let p = baked.positions[v].as_dvec3();
            let e = by_position
                .get(&key(p))
                .unwrap_or_else(|| panic!("baked vertex {v} at {p} is no exported vertex"));
            let n = baked.normals[v].as_dvec3().normalize();
            (baked.object_comb(v), n, *e)
        })
        .collect()
}

fn percentile(sorted: &[f64], q: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

fn check_hair(out: &Path, name: &str) {
    let expected = read_json(&out.join(format!("{name}.json")));
    let near: Vec<_> = pairs(&out.join(format!("{name}.glb")), &expected)
        .into_iter()
        .filter(|(_, _, e)| e["near_root"].as_bool() == Some(true))
        .collect();
    // The hair laid on the surface (what the bake's Gram-Schmidt makes of it), against the comb.
    let angles_to = |hair_of: &dyn Fn(&Value) -> DVec3| {
        let mut a: Vec<f64> = near
            .iter()
            .map(|(comb, n, e)| {
                let hair = hair_of(e);
                angle(*comb, hair - *n * n.dot(hair)).to_degrees()
            })
            .collect();
        a.sort_by(f64::total_cmp);
        a
    };
    let angles = angles_to(&|e| vec3(&e["hair"]));
    // Negative control: the hair left in Blender's axes (what a bake without the add-on's
    // --comb-axes would compare with) is far off, so the floors below can fail.
    let unturned = angles_to(&|e| {
        let h = vec3(&e["hair"]);
        DVec3::new(h.x, -h.z, h.y)
    });
    assert!(
        percentile(&unturned, 0.5) > 2.0 * HAIR_MEDIAN_DEG,
        "the control is as close as the comb: median {:.2}°",
        percentile(&unturned, 0.5)
    );
    assert!(angles.len() > 100, "{} vertices near a root", angles.len());
    let (median, p95) = (percentile(&angles, 0.5), percentile(&angles, 0.95));
    eprintln!(
        "{name}: hair to comb over {} vertices near {} roots: median {median:.2}°, \
         p95 {p95:.2}°, max {:.2}°",
        angles.len(),
        expected["roots"],
        angles[angles.len() - 1]
    );
    assert!(median <= HAIR_MEDIAN_DEG, "median {median:.2}°");
    assert!(p95 <= HAIR_P95_DEG, "95th percentile {p95:.2}°");
}

fn check_painted(out: &Path) {
    let expected = read_json(&out.join("painted.json"));
    let mut worst: f64 = 0.0;
    let mut checked = 0;
    for (comb, n, e) in pairs(&out.join("painted.glb"), &expected) {
        let d = vec3(&e["painted"]);
        let g = d - n * n.dot(d);
        // Listing 2.7's defined cases (gray, along the normal) are the bake tests' business.
        if d.length() <= pelt_bake::comb::GRAY_EPSILON || g.length() <= 0.05 * d.length() {
            continue;
        }
        worst = worst.max(angle(comb, g));
        checked += 1;
    }
    eprintln!("painted comb over {checked} vertices: max {worst:.2e} rad");
    assert!(checked > 50, "{checked} painted vertices checked");
    assert!(
        worst <= PAINTED_MAX_RAD,
        "painted comb off by {worst:.2e} rad"
    );
}

fn check_failure(out: &Path) {
    let f = read_json(&out.join("failure.json"));
    let error = f["error"]
        .as_str()
        .expect("the failing export raised no error");
    // pelt's own message, naming the config and the place in it.
    assert!(
        error.contains("bad-config.json:1:"),
        "not pelt's message: {error}"
    );
    assert!(
        f["panel"]
            .as_str()
            .is_some_and(|p| p.contains("bad-config.json")),
        "the panel does not show the error: {f}"
    );
    assert_eq!(
        f["unchanged"], true,
        "a failed bake changed the earlier output"
    );
    assert_eq!(
        f["leftovers"],
        serde_json::json!([]),
        "temporary files left: {f}"
    );
    let missing = f["missing_pelt"].as_str().expect("no error without pelt");
    assert!(missing.contains("no-such-pelt"), "{missing}");
    let views = f["view_calls"].as_array().expect("view calls");
    assert_eq!(
        views.len(),
        1,
        "pelt view started {} times: {f}",
        views.len()
    );
    let call = views[0].as_str().expect("text");
    assert!(
        call.starts_with("view ") && call.ends_with("painted.glb"),
        "{call}"
    );
}

#[test]
fn blender_add_on_combs_from_hair_and_exports_baked() {
    let hint = "apt-get install blender python3-numpy";
    if !program_available("blender", "PELT_REQUIRE_BLENDER", hint) {
        return;
    }
    let dir = scratch("blender");
    copy_into(
        &root().join("blender/pelt_fur"),
        &dir.join("scripts/addons"),
    );
    let out = dir.join("out");
    std::fs::create_dir_all(&out).expect("mkdir");
    let run = Command::new("blender")
        .args([
            "-b",
            "--factory-startup",
            "--python-exit-code",
            "1",
            "--python",
        ])
        .arg(root().join("tests/blender/scene.py"))
        .arg("--")
        .arg(&out)
        .env("BLENDER_USER_SCRIPTS", dir.join("scripts"))
        .env("PELT", env!("CARGO_BIN_EXE_pelt"))
        .output()
        .expect("run blender");
    assert!(
        run.status.success(),
        "blender failed:\n{}\n{}",
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr)
    );
    validate_clean(&[
        &out.join("hair.glb"),
        &out.join("curves.glb"),
        &out.join("painted.glb"),
    ]);
    check_hair(&out, "hair");
    check_hair(&out, "curves");
    check_painted(&out);
    check_failure(&out);
    // pelt's warnings reach the panel.
    let plain = read_json(&out.join("plain.json"));
    let no_hair = plain["no_hair"]
        .as_str()
        .expect("comb_from_hair without hair raised nothing");
    assert!(no_hair.contains("plain: no hair"), "{no_hair}");
    let panel = plain["panel"].as_str().expect("panel text");
    assert!(
        panel.starts_with("baked 1 object(s)") && panel.contains("no COLOR_0"),
        "pelt's warning is not in the panel: {panel}"
    );
}
