//! A skinned test asset with a known answer: a cylinder (radius 0.25, from y = 0 to 2, comb
//! painted as a helix around it) bound to two joints, `root` at the origin and `bend` at y = 1.
//! Vertices below y = 0.8 follow `root` only, above y = 1.2 `bend` only, and between them the
//! weights blend linearly. The clip "Bend" turns `bend` from rest (t = 0) to 90° about +Z
//! (t = 1) with LINEAR keys; "BendStep" holds each key (STEP). With `root` at rest, `bend`'s
//! joint matrix at angle θ is T(0,1,0) · Rz(θ) · T(0,−1,0), so a vertex p with weight w on
//! `bend` lands at (1 − w) p + w (Rz(θ) (p − (0,1,0)) + (0,1,0)).

use glam::{Mat4, Quat, Vec2, Vec3};
use pelt_io::Document;
use pelt_io::edit::NewAccessor;
use serde_json::{Map, Value, json};

use crate::build::{BuildOptions, color_accessor};
use crate::shapes::Shape;

/// Cylinder radius.
pub const RADIUS: f32 = 0.25;
/// Where the blend between the joints starts and ends (y).
pub const BLEND: (f32, f32) = (0.8, 1.2);

/// The weight on `bend` of a vertex at height `y`.
pub fn bend_weight(y: f32) -> f32 {
    ((y - BLEND.0) / (BLEND.1 - BLEND.0)).clamp(0.0, 1.0)
}

/// The cylinder: `rings` rows up its height, `segs` around, seam vertices duplicated; normals
/// outward, comb painted along +Y.
pub fn cylinder(rings: u32, segs: u32) -> Shape {
    let mut s = Shape {
        name: "bent-cylinder".to_owned(),
        ..Shape::default()
    };
    for r in 0..=rings {
        for k in 0..=segs {
            let a = std::f32::consts::TAU * (k % segs) as f32 / segs as f32;
            let n = Vec3::new(a.cos(), 0.0, -a.sin());
            s.positions
                .push(n * RADIUS + Vec3::Y * (2.0 * r as f32 / rings as f32));
            s.normals.push(n);
            s.uvs
                .push(Vec2::new(k as f32 / segs as f32, r as f32 / rings as f32));
            // A helix: halfway between up the length and around it, painted as the linear
            // color (x, y, z) * 0.5 + 0.5, full length. Off the bend's plane, so the blended
            // part turns it in a way a rotation would not.
            let around = Vec3::new(-a.sin(), 0.0, -a.cos());
            let d = (Vec3::Y + around).normalize() * 0.5 + Vec3::splat(0.5);
            s.colors.push([d.x, d.y, d.z, 1.0]);
        }
    }
    for r in 0..rings {
        for k in 0..segs {
            let a = r * (segs + 1) + k;
            let b = a + segs + 1;
            s.indices.extend([a, a + 1, b, a + 1, b + 1, b]);
        }
    }
    s
}

/// The skinned cylinder document (32 rows, 16 around).
pub fn bent_cylinder() -> Document {
    let shape = cylinder(32, 16);
    let mut doc = Document::empty(std::path::Path::new("bent-cylinder.glb"));
    let mut attrs = Map::new();
    let pos: Vec<[f32; 3]> = shape.positions.iter().map(|p| p.to_array()).collect();
    let mut p = NewAccessor::f32(&pos);
    p.min_max = true;
    attrs.insert("POSITION".into(), json!(doc.push_accessor(p)));
    let n: Vec<[f32; 3]> = shape.normals.iter().map(|p| p.to_array()).collect();
    attrs.insert(
        "NORMAL".into(),
        json!(doc.push_accessor(NewAccessor::f32(&n))),
    );
    let uv: Vec<[f32; 2]> = shape.uvs.iter().map(|p| p.to_array()).collect();
    attrs.insert(
        "TEXCOORD_0".into(),
        json!(doc.push_accessor(NewAccessor::f32(&uv))),
    );
    let colors = color_accessor(&shape.colors, BuildOptions::default().colors);
    attrs.insert("COLOR_0".into(), json!(doc.push_accessor(colors)));
    let joints: Vec<[u16; 4]> = vec![[0, 1, 0, 0]; pos.len()];
    attrs.insert(
        "JOINTS_0".into(),
        json!(doc.push_accessor(NewAccessor::u16(&joints))),
    );
    let weights: Vec<[f32; 4]> = shape
        .positions
        .iter()
        .map(|p| {
            let w = bend_weight(p.y);
            [1.0 - w, w, 0.0, 0.0]
        })
        .collect();
    attrs.insert(
        "WEIGHTS_0".into(),
        json!(doc.push_accessor(NewAccessor::f32(&weights))),
    );
    let idx = doc.push_accessor(NewAccessor::indices(&shape.indices, pos.len()));
    let mesh_node = doc.add_mesh_node(&shape.name, attrs, idx);
    rig(&mut doc, mesh_node);
    doc
}

/// Joints, skin, material and the two clips.
fn rig(doc: &mut Document, mesh_node: usize) {
    let ibm = [Mat4::IDENTITY, Mat4::from_translation(Vec3::NEG_Y)];
    let ibm: Vec<f32> = ibm.iter().flat_map(|m| m.to_cols_array()).collect();
    let ibm = raw_accessor(doc, &ibm, "MAT4", 2, false);
    let times = raw_accessor(doc, &[0.0, 1.0], "SCALAR", 2, true);
    let q = Quat::from_rotation_z(std::f32::consts::FRAC_PI_2);
    let keys: Vec<f32> = [Quat::IDENTITY, q]
        .iter()
        .flat_map(|q| q.to_array())
        .collect();
    let keys = raw_accessor(doc, &keys, "VEC4", 2, false);
    let json = &mut doc.json;
    let nodes = json.entry("nodes").or_insert_with(|| json!([]));
    let Some(nodes) = nodes.as_array_mut() else {
        return;
    };
    let root = nodes.len();
    nodes.push(json!({"name": "root", "children": [root + 1]}));
    nodes.push(json!({"name": "bend", "translation": [0.0, 1.0, 0.0]}));
    if let Some(n) = nodes.get_mut(mesh_node).and_then(Value::as_object_mut) {
        n.insert("skin".into(), json!(0));
    }
    if let Some(scene) = json
        .get_mut("scenes")
        .and_then(|s| s.get_mut(0))
        .and_then(|s| s.get_mut("nodes"))
        .and_then(Value::as_array_mut)
    {
        scene.push(json!(root));
    }
    json.insert(
        "skins".into(),
        json!([{"name": "two-bones", "joints": [root, root + 1], "inverseBindMatrices": ibm}]),
    );
    let clip = |name: &str, interp: &str| {
        json!({"name": name,
            "samplers": [{"input": times, "output": keys, "interpolation": interp}],
            "channels": [{"sampler": 0, "target": {"node": root + 1, "path": "rotation"}}]})
    };
    json.insert(
        "animations".into(),
        json!([clip("Bend", "LINEAR"), clip("BendStep", "STEP")]),
    );
    json.insert(
        "materials".into(),
        json!([{"name": "fur", "pbrMetallicRoughness": {"baseColorFactor": [0.55, 0.4, 0.3, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.8}}]),
    );
    if let Some(p) = json
        .get_mut("meshes")
        .and_then(|m| m.get_mut(0))
        .and_then(|m| m.get_mut("primitives"))
        .and_then(|p| p.get_mut(0))
        .and_then(Value::as_object_mut)
    {
        p.insert("material".into(), json!(0));
    }
}

/// An accessor of floats (no bufferView target: animation and skin data); returns its index.
fn raw_accessor(doc: &mut Document, v: &[f32], ty: &str, count: usize, min_max: bool) -> usize {
    let bytes: Vec<u8> = v.iter().flat_map(|x| x.to_le_bytes()).collect();
    let view = doc.push_view(bytes, None);
    let mut a = json!({"bufferView": view, "componentType": 5126, "count": count, "type": ty});
    if min_max {
        let lo = v.iter().copied().fold(f32::INFINITY, f32::min);
        let hi = v.iter().copied().fold(f32::NEG_INFINITY, f32::max);
        a["min"] = json!([lo]);
        a["max"] = json!([hi]);
    }
    doc.push_accessor_json(a)
}
