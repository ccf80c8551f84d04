//! Wavefront OBJ import through `tobj`: triangulated, one glTF mesh (one primitive) and node per
//! OBJ object and material. Per-vertex colors written as `v x y z r g b` become COLOR_0 (VEC3
//! float, so comb length 1). OBJ's V axis points up, glTF's down: TEXCOORD_0 = (u, 1 - v).
//!
//! The text is read as peers read it ([`crate::text`]: UTF-8, UTF-16 with a byte-order mark,
//! other bytes decoded lossily with a warning). Every face, line and point index is checked
//! first, with its line number, against the vertices the file really holds (negative indices
//! count back from the last vertex read so far). `mtllib` files and their textures are read
//! relative to the OBJ and never outside its folder ([`crate::obj_material`]); what cannot be
//! read is a warning in [`Document::warnings`].

use std::path::Path;

use serde_json::{Map, Value, json};

use crate::document::Document;
use crate::edit::{NewAccessor, push_to};
use crate::error::{IoError, Result};
use crate::obj_material::{MaterialWriter, MtlReader};

/// Loads an OBJ file into a [`Document`].
pub fn load(path: &Path) -> Result<Document> {
    let bytes = std::fs::read(path).map_err(|source| IoError::Fs {
        path: path.to_owned(),
        action: "read",
        source,
    })?;
    from_bytes(path, &bytes)
}

/// Parses an OBJ held in memory; `path` names it in errors.
pub fn from_bytes(path: &Path, bytes: &[u8]) -> Result<Document> {
    let mut warnings = Vec::new();
    let text = crate::text::decode("", bytes, &mut warnings);
    let text = crate::obj_material::name_unnamed(&text, "usemtl", "", &mut warnings);
    let bytes = text.as_bytes();
    check_indices(path, bytes)?;
    let opts = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let mut cursor = std::io::Cursor::new(bytes);
    let mtl = MtlReader::new(path);
    let (models, materials) = tobj::load_obj_buf(&mut cursor, &opts, |name| mtl.load(name))
        .map_err(|e| IoError::invalid(path, "OBJ", format!("cannot load: {e}")))?;
    // The loader never fails, so tobj's material list is whatever loaded.
    let materials = materials.unwrap_or_default();
    let mut writer = MaterialWriter::new(&mtl, &materials);
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
        let attrs = push_attributes(&mut doc, mesh, n);
        let idx = doc.push_accessor(NewAccessor::indices(&mesh.indices, n));
        let mi = doc.add_mesh_node(&m.name, attrs, idx);
        if let Some(material) = mesh
            .material_id
            .and_then(|id| writer.material(&mut doc, id))
        {
            let r = crate::PrimitiveRef {
                mesh: mi,
                primitive: 0,
            };
            doc.set_primitive_material(r, material)?;
        }
    }
    warnings.extend(mtl.warnings.take());
    doc.warnings = warnings;
    for f in mtl.files.take() {
        if !doc.files_read.contains(&f) {
            doc.files_read.push(f);
        }
    }
    if doc.array("meshes").is_empty() {
        return Err(IoError::invalid(path, "OBJ", "no faces"));
    }
    Ok(doc)
}

/// The vertex attributes of an OBJ object's `n` vertices as accessors: POSITION (with its
/// bounds), and NORMAL, TEXCOORD_0 (V flipped to glTF's top-left origin) and COLOR_0 when
/// every vertex has them. Returns the primitive's `attributes`.
fn push_attributes(doc: &mut Document, mesh: &tobj::Mesh, n: usize) -> Map<String, Value> {
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
    attrs
}

/// Checks every `f`, `l` and `p` index of the file against the vertex data it really holds:
/// an integer other than 0, positive up to the file's count, negative back to the first
/// element read so far. Errors name the line.
fn check_indices(path: &Path, bytes: &[u8]) -> Result<()> {
    // Totals first: positive indices may refer to elements defined later in the file.
    let mut total = [0u64; 3];
    for line in bytes.split(|&b| b == b'\n') {
        if let Some(k) = element_kind(line) {
            total[k] += 1;
        }
    }
    let mut seen = [0u64; 3];
    for (n, line) in bytes.split(|&b| b == b'\n').enumerate() {
        if let Some(k) = element_kind(line) {
            seen[k] += 1;
            continue;
        }
        let text = std::str::from_utf8(line).map_err(|e| {
            IoError::invalid(
                path,
                format!("OBJ line {}", n + 1),
                format!(
                    "not UTF-8 text (byte 0x{:02X} at column {})",
                    line[e.valid_up_to()],
                    e.valid_up_to() + 1
                ),
            )
        })?;
        let mut words = text.split_whitespace();
        let element = match words.next() {
            Some("f") => "face",
            Some("l") => "line",
            Some("p") => "point",
            _ => continue,
        };
        for (v, word) in words.enumerate() {
            for (k, part) in word.split('/').enumerate().take(3) {
                if part.is_empty() && k > 0 {
                    continue;
                }
                let what = ["position", "texture coordinate", "normal"][k];
                let bad = |msg: String| {
                    IoError::invalid(
                        path,
                        format!("OBJ line {}", n + 1),
                        format!("{element} vertex {}: {msg}", v + 1),
                    )
                };
                let i: i64 = part
                    .parse()
                    .map_err(|_| bad(format!("{what} index {part:?} is not an integer")))?;
                let ok = match i {
                    0 => false,
                    i if i > 0 => i.unsigned_abs() <= total[k],
                    i => i.unsigned_abs() <= seen[k],
                };
                if !ok {
                    let msg = if i < 0 {
                        format!(
                            "{what} index {i} reaches before the first of the {} read so far",
                            seen[k]
                        )
                    } else {
                        format!(
                            "{what} index {i} is outside 1..={} (the file holds {} {what}s)",
                            total[k], total[k]
                        )
                    };
                    return Err(bad(msg));
                }
            }
        }
    }
    Ok(())
}

/// 0 for `v`, 1 for `vt`, 2 for `vn` lines.
fn element_kind(line: &[u8]) -> Option<usize> {
    let line = line.trim_ascii_start();
    let word_end = line.iter().position(u8::is_ascii_whitespace)?;
    match &line[..word_end] {
        b"v" => Some(0),
        b"vt" => Some(1),
        b"vn" => Some(2),
        _ => None,
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

    #[test]
    fn a_material_without_a_name_is_read_with_a_warning() {
        let dir = std::env::temp_dir().join(format!("pelt-obj-unnamed-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("mkdir");
        let path = dir.join("a.obj");
        std::fs::write(dir.join("m.mtl"), "newmtl\r\nKd 1 0 0\r\n").expect("write");
        std::fs::write(&path, format!("mtllib m.mtl\nusemtl \n{TRI}")).expect("write");
        let doc = load(&path).expect("an empty material name reads, as assimp reads it");
        assert_eq!(doc.warnings.len(), 2, "{:?}", doc.warnings);
        assert!(
            doc.warnings[0]
                .contains("line 2: usemtl without a name: read as the material \"unnamed\"")
                && doc.warnings[1].contains("mtllib \"m.mtl\" line 1: newmtl without a name"),
            "{:?}",
            doc.warnings
        );
        let materials = doc.array("materials");
        assert_eq!(materials.len(), 1);
        assert_eq!(
            materials[0]["pbrMetallicRoughness"]["baseColorFactor"],
            json!([1.0, 0.0, 0.0, 1.0]),
            "the unnamed material is the one the faces use"
        );
        // Control: a named material says nothing.
        std::fs::write(dir.join("m.mtl"), "newmtl red\nKd 1 0 0\n").expect("write");
        std::fs::write(&path, format!("mtllib m.mtl\nusemtl red\n{TRI}")).expect("write");
        assert!(load(&path).expect("loads").warnings.is_empty());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn missing_or_escaping_mtllibs_are_warnings() {
        let dir = std::env::temp_dir().join(format!("pelt-obj-mtl-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("mkdir");
        let path = dir.join("a.obj");
        let text = format!("mtllib missing.mtl\nmtllib ../../../etc/passwd\nusemtl x\n{TRI}");
        std::fs::write(&path, &text).expect("write");
        let doc = load(&path).expect("an OBJ whose materials are missing still loads");
        assert_eq!(doc.files_read, vec![path.clone()]);
        assert_eq!(doc.warnings.len(), 2, "{:?}", doc.warnings);
        assert!(
            doc.warnings[0].contains("mtllib \"missing.mtl\""),
            "{:?}",
            doc.warnings
        );
        assert!(
            doc.warnings[1].contains("leaves the OBJ's folder"),
            "{:?}",
            doc.warnings
        );
        assert!(doc.array("materials").is_empty());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn a_missing_obj_names_the_file() {
        let e = load(Path::new("no/such/file.obj")).expect_err("missing");
        let text = e.to_string();
        assert!(text.starts_with("no/such/file.obj: read:"), "{text}");
    }

    #[test]
    fn negative_indices_count_back_from_the_vertices_read_so_far() {
        let ok = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n";
        assert!(from_bytes(Path::new("n.obj"), ok.as_bytes()).is_ok());
        let e = from_bytes(
            Path::new("n.obj"),
            b"v 0 0 0\nf -1 -2 -3\nv 1 0 0\nv 0 1 0\n",
        )
        .expect_err("-2 before two vertices");
        assert!(
            e.to_string()
                .contains("OBJ line 2: face vertex 2: position index -2"),
            "{e}"
        );
    }
}
