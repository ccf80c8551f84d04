//! Wavefront OBJ import through `tobj`: triangulated, one glTF mesh (one primitive) and node per
//! OBJ object. Per-vertex colors written as `v x y z r g b` become COLOR_0 (VEC3 float, so comb
//! length 1). OBJ's V axis points up, glTF's down: TEXCOORD_0 = (u, 1 - v).

use std::path::Path;

use serde_json::{Map, Value, json};

use crate::document::Document;
use crate::edit::{NewAccessor, push_to};
use crate::error::{IoError, Result};

/// Loads an OBJ file into a [`Document`].
pub fn load(path: &Path) -> Result<Document> {
    let opts = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, _materials) = tobj::load_obj(path, &opts)
        .map_err(|e| IoError::invalid(path, "OBJ", format!("cannot load: {e}")))?;
    let mut doc = Document::empty(path);
    for (i, m) in models.iter().enumerate() {
        let mesh = &m.mesh;
        let place = format!("OBJ object {i} {:?}", m.name);
        let n = mesh.positions.len() / 3;
        if n == 0 || mesh.indices.is_empty() {
            continue;
        }
        if let Some(&bad) = mesh.indices.iter().find(|&&x| x as usize >= n) {
            return Err(IoError::invalid(
                path,
                place,
                format!("face index {bad} is past the {n} vertices"),
            ));
        }
        let pos: Vec<[f32; 3]> = mesh
            .positions
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2]])
            .collect();
        let mut attrs = Map::new();
        let mut p = NewAccessor::f32(&pos);
        p.min_max = true;
        attrs.insert("POSITION".into(), json!(doc.push_accessor(p)));
        if mesh.normals.len() == 3 * n {
            let v: Vec<[f32; 3]> = mesh
                .normals
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]])
                .collect();
            attrs.insert(
                "NORMAL".into(),
                json!(doc.push_accessor(NewAccessor::f32(&v))),
            );
        }
        if mesh.texcoords.len() == 2 * n {
            let v: Vec<[f32; 2]> = mesh
                .texcoords
                .chunks_exact(2)
                .map(|c| [c[0], 1.0 - c[1]])
                .collect();
            attrs.insert(
                "TEXCOORD_0".into(),
                json!(doc.push_accessor(NewAccessor::f32(&v))),
            );
        }
        if mesh.vertex_color.len() == 3 * n {
            let v: Vec<[f32; 3]> = mesh
                .vertex_color
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]])
                .collect();
            attrs.insert(
                "COLOR_0".into(),
                json!(doc.push_accessor(NewAccessor::f32(&v))),
            );
        }
        let idx = doc.push_accessor(NewAccessor::indices(&mesh.indices, n));
        doc.add_mesh_node(&m.name, attrs, idx);
    }
    if doc.array("meshes").is_empty() {
        return Err(IoError::invalid(path, "OBJ", "no faces"));
    }
    Ok(doc)
}

impl Document {
    /// An empty glTF 2.0 document with one scene, for assets built in memory.
    pub fn empty(path: &Path) -> Document {
        let mut json = Map::new();
        json.insert(
            "asset".into(),
            json!({"version": "2.0", "generator": "pelt"}),
        );
        json.insert("scene".into(), json!(0));
        json.insert("scenes".into(), json!([{"nodes": []}]));
        Document::from_parts(path, json, Vec::new())
    }

    /// Adds a mesh with one triangle primitive, and a node for it in scene 0.
    pub fn add_mesh_node(
        &mut self,
        name: &str,
        attributes: Map<String, Value>,
        indices: usize,
    ) -> usize {
        let mut prim = Map::new();
        prim.insert("attributes".into(), Value::Object(attributes));
        prim.insert("indices".into(), json!(indices));
        let mut mesh = Map::new();
        if !name.is_empty() {
            mesh.insert("name".into(), json!(name));
        }
        mesh.insert("primitives".into(), json!([Value::Object(prim)]));
        let mi = push_to(&mut self.json, "meshes", Value::Object(mesh));
        let mut node = Map::new();
        if !name.is_empty() {
            node.insert("name".into(), json!(name));
        }
        node.insert("mesh".into(), json!(mi));
        let ni = push_to(&mut self.json, "nodes", Value::Object(node));
        if let Some(nodes) = self
            .json
            .get_mut("scenes")
            .and_then(|s| s.get_mut(0))
            .and_then(|s| s.get_mut("nodes"))
            .and_then(Value::as_array_mut)
        {
            nodes.push(json!(ni));
        }
        mi
    }
}
