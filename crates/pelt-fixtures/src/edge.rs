//! Small, hand-specified edge cases, each a document with one or two meshes. Comb colors are
//! chosen so a test can state the expected result exactly.

use std::path::Path;

use glam::{Vec2, Vec3};
use pelt_io::Document;
use pelt_io::edit::NewAccessor;
use serde_json::{Map, json};

use crate::build::{BuildOptions, ColorEncoding, add_shape};
use crate::paint;
use crate::shapes::{Shape, sphere};

/// A flat grid in the XY plane (normal +Z), `w`×`h` quads, UV = position / size.
fn plane(name: &str, w: u32, h: u32, color: impl Fn(Vec3) -> [f32; 4]) -> Shape {
    let mut s = Shape {
        name: name.to_owned(),
        ..Shape::default()
    };
    for y in 0..=h {
        for x in 0..=w {
            let p = Vec3::new(x as f32, y as f32, 0.0);
            s.positions.push(p);
            s.normals.push(Vec3::Z);
            s.uvs
                .push(Vec2::new(x as f32 / w as f32, 1.0 - y as f32 / h as f32));
            s.colors.push(color(p));
        }
    }
    for y in 0..h {
        for x in 0..w {
            let a = y * (w + 1) + x;
            let b = a + w + 1;
            s.indices.extend([a, a + 1, b, a + 1, b + 1, b]);
        }
    }
    s
}

fn doc_with(name: &str, shapes: &[(&Shape, BuildOptions)]) -> Document {
    let mut doc = Document::empty(Path::new(&format!("{name}.gltf")));
    for (s, o) in shapes {
        add_shape(&mut doc, s, *o);
    }
    doc
}

/// Comb +X everywhere.
fn comb_x(_: Vec3) -> [f32; 4] {
    paint(Vec3::X, 1.0)
}

/// A 4×1 strip whose U is mirrored at x = 2 (u = x/2, then (4 − x)/2): the vertices on the
/// mirror line are shared by faces of opposite UV orientation, so MikkTSpace must split them.
/// Comb +X everywhere.
pub fn mirrored_uv() -> Document {
    let mut s = plane("mirrored-uv", 4, 1, comb_x);
    for (p, uv) in s.positions.iter().zip(s.uvs.iter_mut()) {
        uv.x = if p.x <= 2.0 {
            p.x / 2.0
        } else {
            (4.0 - p.x) / 2.0
        };
    }
    doc_with("mirrored-uv", &[(&s, BuildOptions::default())])
}

/// A 3×3 grid plus degenerate triangles: two with coincident corners, one collinear, and a
/// proper triangle whose UVs have zero area.
pub fn degenerate() -> Document {
    let mut s = plane("degenerate", 3, 3, comb_x);
    s.indices.extend([0, 0, 1]); // coincident corners
    s.indices.extend([5, 6, 6]);
    s.indices.extend([0, 1, 2]); // collinear (y = 0 row)
    let n = s.positions.len() as u32;
    s.positions.extend([
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(1.0, 0.0, 1.0),
        Vec3::new(0.0, 1.0, 1.0),
    ]);
    s.normals.extend([Vec3::Z; 3]);
    s.uvs.extend([Vec2::new(0.5, 0.5); 3]); // zero UV area
    s.colors.extend([comb_x(Vec3::ZERO); 3]);
    s.indices.extend([n, n + 1, n + 2]);
    doc_with("degenerate", &[(&s, BuildOptions::default())])
}

/// A plane (normal +Z) whose comb is +Z (along the normal) in its left column, 1e-7 rad off the
/// normal in the middle column, gray in the right column, and +Y elsewhere.
pub fn comb_parallel() -> Document {
    let s = plane("comb-parallel", 3, 2, |p| {
        if p.y > 1.5 {
            paint(Vec3::Y, 0.8)
        } else if p.x < 0.5 {
            paint(Vec3::Z, 0.8)
        } else if p.x < 1.5 {
            paint(Vec3::new(1e-7, 0.0, 1.0).normalize(), 0.8)
        } else if p.x < 2.5 {
            [0.5, 0.5, 0.5, 0.8]
        } else {
            paint(Vec3::Y, 0.8)
        }
    });
    doc_with("comb-parallel", &[(&s, BuildOptions::default())])
}

/// A unit cube of 8 shared vertices without NORMAL: flat normals must be generated, which
/// splits every vertex into one per face (24).
pub fn no_normals() -> Document {
    let mut s = Shape {
        name: "no-normals".into(),
        ..Shape::default()
    };
    for i in 0..8u32 {
        let p = Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32)
            - Vec3::splat(0.5);
        s.positions.push(p);
        s.normals.push(p.normalize());
        s.uvs.push(Vec2::new(p.x + 0.5 + p.z * 0.25, p.y + 0.5));
        s.colors
            .push(paint(Vec3::new(0.2, -1.0, 0.1).normalize(), 1.0));
    }
    // Outward, counter-clockwise.
    s.indices = vec![
        0, 2, 1, 1, 2, 3, // -Z
        4, 5, 6, 5, 7, 6, // +Z
        0, 1, 4, 1, 5, 4, // -Y
        2, 6, 3, 3, 6, 7, // +Y
        0, 4, 2, 2, 4, 6, // -X
        1, 3, 5, 3, 7, 5, // +X
    ];
    doc_with(
        "no-normals",
        &[(
            &s,
            BuildOptions {
                normals: false,
                ..BuildOptions::default()
            },
        )],
    )
}

/// A small sphere whose COLOR_0 is VEC3 unsigned byte normalized (length 1 everywhere).
pub fn color_vec3_u8() -> Document {
    let mut s = sphere(8, 16);
    s.name = "color-vec3-u8".into();
    doc_with(
        "color-vec3-u8",
        &[(
            &s,
            BuildOptions {
                colors: ColorEncoding::U8x3,
                ..BuildOptions::default()
            },
        )],
    )
}

/// A small torus with VEC4 unsigned short colors and MikkTSpace tangents already present.
pub fn color_u16_with_tangents() -> Document {
    let mut s = crate::shapes::torus(6, 12);
    s.name = "color-u16-tangents".into();
    doc_with(
        "color-u16-tangents",
        &[(
            &s,
            BuildOptions {
                colors: ColorEncoding::U16x4,
                tangents: true,
                ..BuildOptions::default()
            },
        )],
    )
}

/// A plane whose COLOR_0 is sparse: a gray base with vertices 0, 5 and 7 overridden to +X.
pub fn sparse_color() -> Document {
    let s = plane("sparse-color", 3, 2, |_| [0.5, 0.5, 0.5, 1.0]);
    let mut doc = doc_with("sparse-color", &[(&s, BuildOptions::default())]);
    let base = doc.push_view(
        s.colors
            .iter()
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect::<Vec<u8>>(),
        None,
    );
    let idx = doc.push_view(
        [0u16, 5, 7, 0]
            .iter()
            .flat_map(|x| x.to_le_bytes())
            .collect::<Vec<u8>>(),
        None,
    );
    let vals = doc.push_view(
        [comb_x(Vec3::ZERO); 3]
            .iter()
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect::<Vec<u8>>(),
        None,
    );
    let acc = doc.push_accessor_json(json!({
        "bufferView": base, "componentType": 5126, "count": s.positions.len(), "type": "VEC4",
        "sparse": {"count": 3, "indices": {"bufferView": idx, "componentType": 5123}, "values": {"bufferView": vals}}
    }));
    let r = doc.primitives()[0];
    let _ = doc.set_attribute(r, "COLOR_0", acc);
    doc
}

/// A plane with one zero normal and one normal of length 3.
pub fn bad_normals() -> Document {
    let mut s = plane("bad-normals", 2, 2, comb_x);
    s.normals[4] = Vec3::ZERO;
    s.normals[1] = Vec3::Z * 3.0;
    doc_with("bad-normals", &[(&s, BuildOptions::default())])
}

/// A mesh with POINTS, LINES, LINE_LOOP and LINE_STRIP primitives (passed through with a
/// warning) beside a painted triangle primitive.
pub fn modes() -> Document {
    let s = plane("modes", 1, 1, comb_x);
    let mut doc = doc_with("modes", &[(&s, BuildOptions::default())]);
    let pos = doc
        .primitives()
        .first()
        .and_then(|r| doc.attribute(*r, "POSITION").ok().flatten())
        .unwrap_or(0);
    let lines = doc.push_accessor(NewAccessor::indices(&[0, 1, 1, 3], 4));
    let mut attrs = Map::new();
    attrs.insert("POSITION".into(), json!(pos));
    if let Some(prims) = doc
        .json
        .get_mut("meshes")
        .and_then(|m| m.get_mut(0))
        .and_then(|m| m.get_mut("primitives"))
        .and_then(serde_json::Value::as_array_mut)
    {
        prims.push(json!({"attributes": attrs.clone(), "indices": lines, "mode": 1}));
        prims.push(json!({"attributes": attrs.clone(), "mode": 0}));
        prims.push(json!({"attributes": attrs.clone(), "mode": 2}));
        prims.push(json!({"attributes": attrs, "indices": lines, "mode": 3}));
    }
    doc
}

/// Sets every primitive of mesh 0 to `mode`.
fn set_mode(doc: &mut Document, mode: u64) {
    let prims = doc
        .json
        .get_mut("meshes")
        .and_then(|m| m.get_mut(0))
        .and_then(|m| m.get_mut("primitives"))
        .and_then(serde_json::Value::as_array_mut);
    for p in prims.into_iter().flatten() {
        p["mode"] = json!(mode);
    }
}

/// The 4×3 plane drawn as one TRIANGLE_STRIP: each row top, bottom, top, … (counter-clockwise
/// from +Z like the list), rows joined by repeating their last and the next row's first index
/// (four degenerate triangles per join). Comb +X everywhere.
pub fn strip() -> Document {
    let (w, h) = (4, 3);
    let mut s = plane("strip", w, h, comb_x);
    s.indices.clear();
    for y in 0..h {
        let (bottom, top) = (y * (w + 1), (y + 1) * (w + 1));
        if y > 0 {
            s.indices.push(top);
        }
        for x in 0..=w {
            s.indices.extend([top + x, bottom + x]);
        }
        if y + 1 < h {
            s.indices.push(bottom + w);
        }
    }
    let mut doc = doc_with("strip", &[(&s, BuildOptions::default())]);
    set_mode(&mut doc, 5);
    doc
}

/// A 12-sided disc in the XY plane (normal +Z) drawn as one TRIANGLE_FAN around its centre,
/// counter-clockwise from +Z; comb pointing outward from the centre.
pub fn fan() -> Document {
    let mut s = Shape {
        name: "fan".to_owned(),
        ..Shape::default()
    };
    let n = 12;
    for k in 0..=n {
        let p = if k == 0 {
            Vec3::ZERO
        } else {
            let a = (k - 1) as f32 / n as f32 * std::f32::consts::TAU;
            Vec3::new(a.cos(), a.sin(), 0.0)
        };
        s.positions.push(p);
        s.normals.push(Vec3::Z);
        s.uvs.push(Vec2::new(0.5 + 0.5 * p.x, 0.5 - 0.5 * p.y));
        let out = if k == 0 { Vec3::X } else { p };
        s.colors.push(paint(out, 1.0));
    }
    s.indices = (0..=n).chain([1]).collect();
    let mut doc = doc_with("fan", &[(&s, BuildOptions::default())]);
    set_mode(&mut doc, 6);
    doc
}

/// A flat-shaded cube: 4 vertices per side with the side's normal, comb +X: six normal groups,
/// 18 unique edges.
fn flat_cube() -> Document {
    let mut s = Shape {
        name: "flat-cube".to_owned(),
        ..Shape::default()
    };
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let mut n = Vec3::ZERO;
            n[axis] = sign;
            let u = Vec3::from_array(std::array::from_fn(|k| f32::from(k == (axis + 1) % 3)));
            let v = n.cross(u);
            let base = s.positions.len() as u32;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                s.positions.push(n + u * a + v * b);
                s.normals.push(n);
                s.uvs.push(Vec2::new(0.5 + 0.5 * a, 0.5 + 0.5 * b));
                s.colors.push(paint(Vec3::X, 1.0));
            }
            s.indices
                .extend([base, base + 1, base + 2, base, base + 2, base + 3]);
        }
    }
    doc_with("flat-cube", &[(&s, BuildOptions::default())])
}

/// The two-ring hard-edged torus ([`crate::shapes::hard_torus`]).
fn hard_torus() -> Document {
    let s = crate::shapes::hard_torus(12, 24);
    doc_with("hard-torus", &[(&s, BuildOptions::default())])
}

/// Every edge case, by file stem.
pub fn all() -> Vec<(&'static str, Document)> {
    vec![
        ("flat-cube", flat_cube()),
        ("hard-torus", hard_torus()),
        ("mirrored-uv", mirrored_uv()),
        ("degenerate", degenerate()),
        ("comb-parallel", comb_parallel()),
        ("no-normals", no_normals()),
        ("color-vec3-u8", color_vec3_u8()),
        ("color-u16-tangents", color_u16_with_tangents()),
        ("sparse-color", sparse_color()),
        ("bad-normals", bad_normals()),
        ("modes", modes()),
        ("strip", strip()),
        ("fan", fan()),
    ]
}
