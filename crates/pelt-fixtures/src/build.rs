//! Shapes into glTF documents: POSITION (with bounds), NORMAL, TEXCOORD_0, COLOR_0 in a chosen
//! encoding, optional MikkTSpace TANGENT, one material, and a parent node with the mesh on a
//! child node (so tests can check that hierarchy and materials survive a bake).

use std::path::Path;

use pelt_geom::mikktspace;
use pelt_io::Document;
use pelt_io::edit::NewAccessor;
use serde_json::{Map, Value, json};

use crate::shapes::Shape;

/// How COLOR_0 is stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColorEncoding {
    /// VEC4 float.
    F32x4,
    /// VEC3 float (length 1).
    F32x3,
    /// VEC4 unsigned byte normalized.
    U8x4,
    /// VEC3 unsigned byte normalized (length 1).
    U8x3,
    /// VEC4 unsigned short normalized.
    U16x4,
}

/// What to put in the file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BuildOptions {
    /// COLOR_0 storage.
    pub colors: ColorEncoding,
    /// Write NORMAL.
    pub normals: bool,
    /// Write MikkTSpace TANGENT.
    pub tangents: bool,
}

impl Default for BuildOptions {
    fn default() -> Self {
        BuildOptions {
            colors: ColorEncoding::F32x4,
            normals: true,
            tangents: false,
        }
    }
}

/// The COLOR_0 accessor for `colors` in encoding `enc`.
pub fn color_accessor(colors: &[[f32; 4]], enc: ColorEncoding) -> NewAccessor {
    let q8 = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    let q16 = |v: f32| (v.clamp(0.0, 1.0) * 65535.0).round() as u16;
    match enc {
        ColorEncoding::F32x4 => NewAccessor::f32(colors),
        ColorEncoding::F32x3 => NewAccessor::f32(
            &colors
                .iter()
                .map(|c| [c[0], c[1], c[2]])
                .collect::<Vec<_>>(),
        ),
        ColorEncoding::U8x4 => {
            NewAccessor::u8_norm(&colors.iter().map(|c| c.map(q8)).collect::<Vec<_>>())
        }
        ColorEncoding::U8x3 => NewAccessor::u8_norm(
            &colors
                .iter()
                .map(|c| [q8(c[0]), q8(c[1]), q8(c[2])])
                .collect::<Vec<_>>(),
        ),
        ColorEncoding::U16x4 => {
            NewAccessor::u16_norm(&colors.iter().map(|c| c.map(q16)).collect::<Vec<_>>())
        }
    }
}

/// How the vertex attributes lie in the buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Layout {
    /// One bufferView per attribute, as Blender's glTF exporter writes them.
    #[default]
    Separate,
    /// One interleaved bufferView with a byteStride, as gltfpack and glTF-Transform write them.
    Interleaved,
}

/// Adds `shape` as a mesh (on a child node of a named parent) to `doc`.
pub fn add_shape(doc: &mut Document, shape: &Shape, opts: BuildOptions) {
    add_shape_laid_out(doc, shape, opts, Layout::Separate);
}

/// [`add_shape`] with the vertex attributes in `layout`.
pub fn add_shape_laid_out(doc: &mut Document, shape: &Shape, opts: BuildOptions, layout: Layout) {
    let mut list: Vec<(&str, NewAccessor)> = Vec::new();
    let pos: Vec<[f32; 3]> = shape.positions.iter().map(|p| p.to_array()).collect();
    let mut p = NewAccessor::f32(&pos);
    p.min_max = true;
    list.push(("POSITION", p));
    if opts.normals {
        let n: Vec<[f32; 3]> = shape.normals.iter().map(|p| p.to_array()).collect();
        list.push(("NORMAL", NewAccessor::f32(&n)));
    }
    let uv: Vec<[f32; 2]> = shape.uvs.iter().map(|p| p.to_array()).collect();
    list.push(("TEXCOORD_0", NewAccessor::f32(&uv)));
    if opts.tangents {
        // Per-corner MikkTSpace; the parametric shapes' corners of one vertex agree, so the
        // first corner of each vertex stands for it.
        let t = mikktspace::generate(&shape.positions, &shape.normals, &shape.uvs, &shape.indices);
        let mut per_vertex = vec![[1.0, 0.0, 0.0, 1.0]; shape.positions.len()];
        for (c, &v) in shape.indices.iter().enumerate().rev() {
            per_vertex[v as usize] = t.corners[c].to_array();
        }
        list.push(("TANGENT", NewAccessor::f32(&per_vertex)));
    }
    list.push(("COLOR_0", color_accessor(&shape.colors, opts.colors)));
    let mut attrs = Map::new();
    match layout {
        Layout::Separate => {
            for (name, a) in list {
                attrs.insert(name.into(), json!(doc.push_accessor(a)));
            }
        }
        Layout::Interleaved => {
            for (name, a) in push_interleaved(doc, &list, &pos) {
                attrs.insert(name.into(), json!(a));
            }
        }
    }
    let idx = doc.push_accessor(NewAccessor::indices(&shape.indices, shape.positions.len()));
    let mesh = doc.add_mesh_node(&shape.name, attrs, idx);
    decorate(doc, mesh, &shape.name);
}

/// The attributes (all with the same count) in one interleaved bufferView, each element
/// padded to 4 bytes; returns (name, accessor index) pairs. `pos` gives POSITION's bounds.
fn push_interleaved<'a>(
    doc: &mut Document,
    list: &[(&'a str, NewAccessor)],
    pos: &[[f32; 3]],
) -> Vec<(&'a str, usize)> {
    let count = pos.len();
    let sizes: Vec<usize> = list.iter().map(|(_, a)| a.element_size()).collect();
    let offsets: Vec<usize> = sizes
        .iter()
        .scan(0, |at, &s| {
            let o = *at;
            *at += s.next_multiple_of(4);
            Some(o)
        })
        .collect();
    let stride: usize = sizes.iter().map(|s| s.next_multiple_of(4)).sum();
    let mut bytes = vec![0u8; stride * count];
    for (((_, a), &size), &off) in list.iter().zip(&sizes).zip(&offsets) {
        for (i, e) in a.bytes.bytes().chunks_exact(size).enumerate() {
            bytes[i * stride + off..i * stride + off + size].copy_from_slice(e);
        }
    }
    let view = doc.push_view(bytes, Some(34962));
    if let Some(v) = doc
        .json
        .get_mut("bufferViews")
        .and_then(|v| v.get_mut(view))
        .and_then(Value::as_object_mut)
    {
        v.insert("byteStride".into(), json!(stride));
    }
    let bound = |f: fn(f32, f32) -> f32, init: f32| {
        pos.iter()
            .fold([init; 3], |m, p| std::array::from_fn(|k| f(m[k], p[k])))
    };
    list.iter()
        .zip(&offsets)
        .map(|((name, a), &off)| {
            let mut acc = json!({
                "bufferView": view,
                "byteOffset": off,
                "componentType": a.component.gl(),
                "count": count,
                "type": pelt_io::accessor::type_of(a.components),
            });
            if a.normalized {
                acc["normalized"] = json!(true);
            }
            if *name == "POSITION" {
                acc["min"] = json!(bound(f32::min, f32::INFINITY));
                acc["max"] = json!(bound(f32::max, f32::NEG_INFINITY));
            }
            (*name, doc.push_accessor_json(acc))
        })
        .collect()
}

/// Adds a material to the mesh's primitives and re-parents its node under a "root" node with
/// extras, as DCC exports look.
fn decorate(doc: &mut Document, mesh: usize, name: &str) {
    let materials = doc.json.entry("materials").or_insert_with(|| json!([]));
    let Some(materials) = materials.as_array_mut() else {
        return;
    };
    materials.push(json!({
        "name": format!("{name}-fur"),
        "pbrMetallicRoughness": {"baseColorFactor": [0.55, 0.4, 0.3, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.8},
        "extras": {"painted_with": "pelt-fixtures"}
    }));
    let material = materials.len() - 1;
    if let Some(prims) = doc
        .json
        .get_mut("meshes")
        .and_then(|m| m.get_mut(mesh))
        .and_then(|m| m.get_mut("primitives"))
        .and_then(Value::as_array_mut)
    {
        for p in prims {
            if let Some(p) = p.as_object_mut() {
                p.insert("material".into(), json!(material));
            }
        }
    }
    let Some(nodes) = doc.json.get_mut("nodes").and_then(Value::as_array_mut) else {
        return;
    };
    let child = nodes.len() - 1;
    nodes.push(json!({"name": format!("{name}-root"), "children": [child], "translation": [0.0, 0.5, 0.0], "extras": {"rig": "none"}}));
    let root = nodes.len() - 1;
    if let Some(scene) = doc
        .json
        .get_mut("scenes")
        .and_then(|s| s.get_mut(0))
        .and_then(|s| s.get_mut("nodes"))
        .and_then(Value::as_array_mut)
    {
        scene.retain(|n| n.as_u64() != Some(child as u64));
        scene.push(json!(root));
    }
}

/// A document holding one shape.
pub fn document(shape: &Shape, opts: BuildOptions) -> Document {
    document_laid_out(shape, opts, Layout::Separate)
}

/// [`document`] with the vertex attributes in `layout`.
pub fn document_laid_out(shape: &Shape, opts: BuildOptions, layout: Layout) -> Document {
    let mut doc = Document::empty(Path::new(&format!("{}.glb", shape.name)));
    add_shape_laid_out(&mut doc, shape, opts, layout);
    doc
}
