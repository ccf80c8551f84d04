//! The whole input document checked before a bake writes it, so that no output is ever invalid
//! for a fault pelt passed through: the glTF 2.0 schema as the `gltf` crate checks it (types,
//! required properties, enum values, every index in range), then the rules of the Khronos
//! validator that the schema alone does not state, for every part of the file:
//!
//! - `extensions` are objects of objects, every extension used is declared in
//!   `extensionsUsed`, `extensionsRequired` is part of it, neither lists a name twice;
//! - nodes form a forest (one parent at most, no loops, scenes list roots);
//! - arrays are not empty (outside `extras` and extension data), `asset.minVersion` is not
//!   above `asset.version`, a node has a matrix or TRS, not both, rotations are unit
//!   quaternions, material factors lie in [0, 1], mesh `weights` match the morph targets;
//! - attribute semantics: indexed ones (`TEXCOORD_n`, `COLOR_n`, `JOINTS_n`, `WEIGHTS_n`)
//!   numbered from 0 without gaps, each in a format glTF allows for it, all of one count;
//!   `normalized` only on byte and short accessors;
//! - accessor data: floats finite, float colours in [0, 1], normals and tangents unit length,
//!   indices inside the vertices, animation inputs increasing;
//! - bufferViews: indices or vertex data as the target says, a byteStride where several vertex
//!   attributes share one.
//!
//! A fault is refused with the JSON path and the rule ([`IoError::Invalid`]). One is repaired
//! instead, where the fix is unambiguous: declared `min`/`max` that do not match the data are
//! replaced by the data's (each repair is returned as a warning).

use serde_json::{Map, Value};

use crate::accessor::{self, ComponentType};
use crate::document::Document;
use crate::error::{IoError, Result};

/// Checks `doc` (see the module documentation); returns the repairs made, as warnings.
///
/// With `triangles_read`, the caller has read every triangle primitive through
/// [`crate::mesh::read_primitive`], which checks their floats and indices as it decodes them;
/// those accessors are not read a second time.
pub fn check(doc: &mut Document, triangles_read: bool) -> Result<Vec<String>> {
    let mut repairs = position_bounds(doc)?;
    crate::typed::document(doc)?;
    let mut path = String::new();
    walk(doc, &Value::Object(doc.json.clone()), &mut path, false)?;
    extensions_declared(doc)?;
    asset_and_nodes(doc)?;
    node_forest(doc)?;
    materials(doc)?;
    meshes(doc)?;
    accessor_data(doc, triangles_read)?;
    buffer_view_use(doc)?;
    attribute_values(doc)?;
    animations(doc)?;
    repairs.extend(repair_bounds(doc)?);
    repairs.extend(image_types(doc)?);
    repairs.extend(crate::nodes::collapsed(doc));
    Ok(repairs)
}

/// POSITION accessors without `min`/`max` (which glTF requires) get the data's.
fn position_bounds(doc: &mut Document) -> Result<Vec<String>> {
    let mut missing: Vec<usize> = Vec::new();
    for mesh in doc.array("meshes") {
        let prims = mesh.get("primitives").and_then(Value::as_array);
        for prim in prims.into_iter().flatten() {
            let pos = prim.get("attributes").and_then(|a| a.get("POSITION"));
            if let Some(i) = pos.and_then(Value::as_u64).map(|i| i as usize)
                && doc
                    .array("accessors")
                    .get(i)
                    .is_some_and(|a| a.get("min").is_none() || a.get("max").is_none())
                && !missing.contains(&i)
            {
                missing.push(i);
            }
        }
    }
    let mut repairs = Vec::new();
    for a in missing {
        let place = format!("accessors[{a}]");
        let Some((lo, hi, float)) = bounds(doc, a, &place)? else {
            continue;
        };
        set_bounds(doc, a, &lo, &hi, float);
        repairs.push(format!(
            "{place}: POSITION had no min/max; the data's were added"
        ));
    }
    Ok(repairs)
}

/// Per-component minima and maxima, and whether they are floats.
type Bounds = (Vec<f64>, Vec<f64>, bool);

/// Per-component (min, max) of accessor `a` and whether it holds floats; None when empty.
fn bounds(doc: &Document, a: usize, place: &str) -> Result<Option<Bounds>> {
    let e = accessor::read_any(doc, a, place)?;
    let comps = e.components.max(1);
    if e.count == 0 {
        return Ok(None);
    }
    let mut lo = vec![f64::INFINITY; comps];
    let mut hi = vec![f64::NEG_INFINITY; comps];
    if e.component == ComponentType::F32 {
        // Floats straight from their bytes, one element at a time (the common, large case).
        let mut lo32 = vec![f32::INFINITY; comps];
        let mut hi32 = vec![f32::NEG_INFINITY; comps];
        for el in e.bytes.chunks_exact(4 * comps) {
            for (k, c) in el.chunks_exact(4).enumerate() {
                let v = f32::from_le_bytes([c[0], c[1], c[2], c[3]]);
                lo32[k] = lo32[k].min(v);
                hi32[k] = hi32[k].max(v);
            }
        }
        lo = lo32.into_iter().map(f64::from).collect();
        hi = hi32.into_iter().map(f64::from).collect();
    } else {
        for i in 0..e.count * comps {
            let v = accessor::raw(e.component, &e.bytes, i);
            lo[i % comps] = lo[i % comps].min(v);
            hi[i % comps] = hi[i % comps].max(v);
        }
    }
    Ok(Some((lo, hi, e.component == ComponentType::F32)))
}

fn set_bounds(doc: &mut Document, a: usize, lo: &[f64], hi: &[f64], float: bool) {
    let num = |v: f64| {
        if float {
            serde_json::json!(v)
        } else {
            serde_json::json!(v as i64)
        }
    };
    if let Some(obj) = doc
        .json
        .get_mut("accessors")
        .and_then(|x| x.get_mut(a))
        .and_then(Value::as_object_mut)
    {
        obj.insert(
            "min".into(),
            Value::Array(lo.iter().map(|&v| num(v)).collect()),
        );
        obj.insert(
            "max".into(),
            Value::Array(hi.iter().map(|&v| num(v)).collect()),
        );
    }
}

/// An error at JSON pointer `place` (`/meshes/0/name`), written as pelt names places
/// (`meshes[0].name`).
fn err(doc: &Document, place: &str, rule: &str) -> IoError {
    let mut out = String::new();
    for part in place.trim_start_matches('/').split('/') {
        if part.parse::<usize>().is_ok() {
            out.push_str(&format!("[{part}]"));
        } else {
            if !out.is_empty() {
                out.push('.');
            }
            out.push_str(part);
        }
    }
    doc.invalid(out, rule.to_owned())
}

/// Every `extensions` is an object of objects; no empty arrays outside extras and extension
/// data.
fn walk(doc: &Document, v: &Value, path: &mut String, opaque: bool) -> Result<()> {
    match v {
        Value::Object(o) => {
            for (k, child) in o {
                let len = path.len();
                path.push('/');
                path.push_str(k);
                if k == "extensions" && !opaque {
                    let Some(exts) = child.as_object() else {
                        return Err(err(doc, path, "extensions must be a JSON object"));
                    };
                    for (name, data) in exts {
                        if !data.is_object() {
                            return Err(err(
                                doc,
                                &format!("{path}/{name}"),
                                "an extension's data must be a JSON object",
                            ));
                        }
                    }
                }
                let inner = opaque || k == "extras" || k == "extensions";
                walk(doc, child, path, inner)?;
                path.truncate(len);
            }
        }
        Value::Array(a) => {
            if a.is_empty() && !opaque {
                return Err(err(doc, path, "an array must not be empty"));
            }
            for (i, child) in a.iter().enumerate() {
                let len = path.len();
                path.push_str(&format!("/{i}"));
                walk(doc, child, path, opaque)?;
                path.truncate(len);
            }
        }
        _ => {}
    }
    Ok(())
}

/// The names of every `extensions` object in the document (outside extras).
fn used_extensions(v: &Value, out: &mut Vec<String>) {
    match v {
        Value::Object(o) => {
            for (k, child) in o {
                if k == "extras" {
                    continue;
                }
                if k == "extensions"
                    && let Some(exts) = child.as_object()
                {
                    out.extend(exts.keys().cloned());
                }
                used_extensions(child, out);
            }
        }
        Value::Array(a) => a.iter().for_each(|c| used_extensions(c, out)),
        _ => {}
    }
}

fn extensions_declared(doc: &Document) -> Result<()> {
    let names = |key: &str| -> Result<Vec<String>> {
        let list: Vec<String> = doc
            .array(key)
            .iter()
            .filter_map(|v| v.as_str().map(str::to_owned))
            .collect();
        for (i, n) in list.iter().enumerate() {
            if list[..i].contains(n) {
                return Err(err(
                    doc,
                    &format!("{key}/{i}"),
                    "an extension is listed twice",
                ));
            }
        }
        Ok(list)
    };
    let declared = names("extensionsUsed")?;
    for (i, r) in names("extensionsRequired")?.iter().enumerate() {
        if !declared.contains(r) {
            return Err(err(
                doc,
                &format!("extensionsRequired/{i}"),
                &format!("{r} is required but not in extensionsUsed"),
            ));
        }
    }
    let mut used = Vec::new();
    used_extensions(&Value::Object(doc.json.clone()), &mut used);
    if let Some(u) = used.iter().find(|u| !declared.contains(u)) {
        return Err(err(
            doc,
            "extensionsUsed",
            &format!("the extension {u} is used but not declared in extensionsUsed"),
        ));
    }
    Ok(())
}

fn version(v: &str) -> Option<(u64, u64)> {
    let (a, b) = v.split_once('.')?;
    Some((a.parse().ok()?, b.parse().ok()?))
}

fn asset_and_nodes(doc: &Document) -> Result<()> {
    let asset = doc.json.get("asset");
    let get = |k: &str| asset.and_then(|a| a.get(k)).and_then(Value::as_str);
    if let (Some(min), Some(v)) = (get("minVersion"), get("version"))
        && version(min).zip(version(v)).is_some_and(|(m, v)| m > v)
    {
        return Err(err(
            doc,
            "asset/minVersion",
            &format!("minVersion {min} is above version {v}"),
        ));
    }
    for (i, n) in doc.array("nodes").iter().enumerate() {
        let trs = ["translation", "rotation", "scale"]
            .iter()
            .any(|k| n.get(k).is_some());
        if n.get("matrix").is_some() && trs {
            return Err(err(
                doc,
                &format!("nodes/{i}/matrix"),
                "a node has either a matrix or translation/rotation/scale, not both",
            ));
        }
        if let Some(q) = n.get("rotation").and_then(Value::as_array) {
            let q: Vec<f64> = q.iter().filter_map(Value::as_f64).collect();
            let len = q.iter().map(|c| c * c).sum::<f64>().sqrt();
            if q.iter().any(|c| c.abs() > 1.0) || (len - 1.0).abs() > 5e-4 {
                return Err(err(
                    doc,
                    &format!("nodes/{i}/rotation"),
                    &format!("the rotation is not a unit quaternion (length {len})"),
                ));
            }
        }
    }
    Ok(())
}

/// Nodes form a forest: at most one parent each, no loops, and a scene lists roots only.
fn node_forest(doc: &Document) -> Result<()> {
    let nodes = doc.array("nodes");
    let mut parent: Vec<Option<usize>> = vec![None; nodes.len()];
    for (i, n) in nodes.iter().enumerate() {
        let children = n.get("children").and_then(Value::as_array);
        for c in children.into_iter().flatten().filter_map(Value::as_u64) {
            let c = c as usize;
            match parent.get_mut(c) {
                Some(Some(p)) => {
                    return Err(err(
                        doc,
                        &format!("nodes/{i}/children"),
                        &format!("node {c} is already a child of node {p}"),
                    ));
                }
                Some(slot) => *slot = Some(i),
                None => {}
            }
        }
    }
    for start in 0..nodes.len() {
        let (mut at, mut steps) = (start, 0);
        while let Some(p) = parent[at] {
            at = p;
            steps += 1;
            if at == start || steps > nodes.len() {
                return Err(err(
                    doc,
                    &format!("nodes/{start}"),
                    "the node is part of a loop of children",
                ));
            }
        }
    }
    for (s, scene) in doc.array("scenes").iter().enumerate() {
        let roots = scene.get("nodes").and_then(Value::as_array);
        for (k, n) in roots.into_iter().flatten().enumerate() {
            if let Some(p) = n
                .as_u64()
                .and_then(|n| parent.get(n as usize).copied().flatten())
            {
                return Err(err(
                    doc,
                    &format!("scenes/{s}/nodes/{k}"),
                    &format!("a scene lists root nodes only, and this one is a child of node {p}"),
                ));
            }
        }
    }
    Ok(())
}

fn materials(doc: &Document) -> Result<()> {
    for (i, m) in doc.array("materials").iter().enumerate() {
        let pbr = m.get("pbrMetallicRoughness");
        let factors: [(&str, Option<&Value>); 5] = [
            ("emissiveFactor", m.get("emissiveFactor")),
            (
                "pbrMetallicRoughness/baseColorFactor",
                pbr.and_then(|p| p.get("baseColorFactor")),
            ),
            (
                "pbrMetallicRoughness/metallicFactor",
                pbr.and_then(|p| p.get("metallicFactor")),
            ),
            (
                "pbrMetallicRoughness/roughnessFactor",
                pbr.and_then(|p| p.get("roughnessFactor")),
            ),
            (
                "occlusionTexture/strength",
                m.get("occlusionTexture").and_then(|t| t.get("strength")),
            ),
        ];
        for (key, v) in factors {
            let values: Vec<f64> = match v {
                Some(Value::Array(a)) => a.iter().filter_map(Value::as_f64).collect(),
                Some(v) => v.as_f64().into_iter().collect(),
                None => Vec::new(),
            };
            if let Some(bad) = values.iter().find(|x| !(0.0..=1.0).contains(*x)) {
                return Err(err(
                    doc,
                    &format!("materials/{i}/{key}"),
                    &format!("{bad} is outside [0, 1]"),
                ));
            }
        }
    }
    Ok(())
}

/// Formats glTF allows per attribute semantic: (types, float, normalized u8/u16, plain
/// u8/u16).
fn formats(semantic: &str, quantized: bool) -> Option<(&'static [&'static str], bool, bool, bool)> {
    let base = semantic.split('_').next().unwrap_or(semantic);
    let q = quantized;
    Some(match base {
        "POSITION" => (&["VEC3"], true, q, q),
        "NORMAL" => (&["VEC3"], true, q, false),
        "TANGENT" => (&["VEC4"], true, q, false),
        "TEXCOORD" => (&["VEC2"], true, true, q),
        "COLOR" => (&["VEC3", "VEC4"], true, true, false),
        "JOINTS" => (&["VEC4"], false, false, true),
        "WEIGHTS" => (&["VEC4"], true, true, false),
        _ => return None,
    })
}

fn accessor_format_ok(a: &Value, semantic: &str, quantized: bool) -> bool {
    let Some((types, float, norm, plain)) = formats(semantic, quantized) else {
        return true;
    };
    let ty = a.get("type").and_then(Value::as_str).unwrap_or("");
    let normalized = a
        .get("normalized")
        .and_then(Value::as_bool)
        .unwrap_or(false);
    let ct = a.get("componentType").and_then(Value::as_u64).unwrap_or(0);
    let small_int = matches!(ct, 5121 | 5123) || (quantized && matches!(ct, 5120 | 5122));
    types.contains(&ty)
        && match ct {
            5126 => float && !normalized,
            _ if small_int => (normalized && norm) || (!normalized && plain),
            _ => false,
        }
}

fn meshes(doc: &Document) -> Result<()> {
    let quantized = doc
        .array("extensionsUsed")
        .iter()
        .any(|e| e == "KHR_mesh_quantization");
    let accessors = doc.array("accessors");
    for (a, acc) in accessors.iter().enumerate() {
        let ct = acc
            .get("componentType")
            .and_then(Value::as_u64)
            .unwrap_or(0);
        if acc.get("normalized").and_then(Value::as_bool) == Some(true)
            && !matches!(ct, 5120..=5123)
        {
            return Err(err(
                doc,
                &format!("accessors/{a}/normalized"),
                "only byte and short accessors can be normalized",
            ));
        }
    }
    for (m, mesh) in doc.array("meshes").iter().enumerate() {
        let prims = mesh.get("primitives").and_then(Value::as_array);
        let mut targets = None;
        for (p, prim) in prims.into_iter().flatten().enumerate() {
            let place = format!("meshes/{m}/primitives/{p}/attributes");
            let attrs = prim.get("attributes").and_then(Value::as_object);
            let attrs = attrs.cloned().unwrap_or_default();
            semantics(doc, &attrs, &place, quantized)?;
            texcoords_bound(doc, prim, &format!("meshes/{m}/primitives/{p}"))?;
            let t = prim
                .get("targets")
                .and_then(Value::as_array)
                .map_or(0, Vec::len);
            if targets.is_some_and(|n| n != t) {
                return Err(err(
                    doc,
                    &format!("meshes/{m}/primitives/{p}/targets"),
                    "every primitive of a mesh must have the same number of morph targets",
                ));
            }
            targets = Some(t);
        }
        if let Some(w) = mesh.get("weights").and_then(Value::as_array)
            && Some(w.len()) != targets
        {
            return Err(err(
                doc,
                &format!("meshes/{m}/weights"),
                &format!(
                    "{} weights for {} morph targets",
                    w.len(),
                    targets.unwrap_or(0)
                ),
            ));
        }
    }
    Ok(())
}

/// Every texture a material binds names a TEXCOORD_n the primitive has.
fn texcoords_bound(doc: &Document, prim: &Value, place: &str) -> Result<()> {
    fn sets(v: &Value, out: &mut Vec<(String, u64)>, key: &str) {
        match v {
            Value::Object(o) => {
                for (k, child) in o {
                    if k.ends_with("Texture") && child.get("index").is_some() {
                        let set = child.get("texCoord").and_then(Value::as_u64).unwrap_or(0);
                        out.push((format!("{key}/{k}"), set));
                    } else if k != "extras" {
                        sets(child, out, &format!("{key}/{k}"));
                    }
                }
            }
            Value::Array(a) => a.iter().for_each(|c| sets(c, out, key)),
            _ => {}
        }
    }
    let Some(m) = prim.get("material").and_then(Value::as_u64) else {
        return Ok(());
    };
    let Some(material) = doc.array("materials").get(m as usize) else {
        return Ok(());
    };
    let mut bound = Vec::new();
    sets(material, &mut bound, &format!("materials/{m}"));
    let attrs = prim.get("attributes");
    for (texture, set) in bound {
        if attrs
            .and_then(|a| a.get(format!("TEXCOORD_{set}")))
            .is_none()
        {
            return Err(err(
                doc,
                &format!("{place}/material"),
                &format!("{texture} reads TEXCOORD_{set}, which the primitive does not have"),
            ));
        }
    }
    Ok(())
}

/// Image `mimeType`s glTF allows (with the extensions that add WebP and KTX2), and declared
/// types that differ from the bytes' own corrected (a repair).
fn image_types(doc: &mut Document) -> Result<Vec<String>> {
    let used = |e: &str| doc.array("extensionsUsed").iter().any(|x| x == e);
    let mut allowed = vec!["image/png", "image/jpeg"];
    if used("EXT_texture_webp") {
        allowed.push("image/webp");
    }
    if used("KHR_texture_basisu") {
        allowed.push("image/ktx2");
    }
    let mut repairs = Vec::new();
    for i in 0..doc.array("images").len() {
        let declared = doc.array("images")[i]
            .get("mimeType")
            .and_then(Value::as_str)
            .map(str::to_owned);
        let in_view = doc.array("images")[i].get("bufferView").is_some();
        let actual = if in_view || doc.uri_images.get(i).is_some_and(Option::is_some) {
            crate::document::mime_from_bytes(doc.image_bytes(i)?)
        } else {
            None
        };
        if let Some(actual) = &actual
            && declared.as_ref().is_some_and(|d| d != actual)
            && allowed.contains(&actual.as_str())
        {
            if let Some(img) = doc
                .json
                .get_mut("images")
                .and_then(|x| x.get_mut(i))
                .and_then(Value::as_object_mut)
            {
                img.insert("mimeType".into(), Value::String(actual.clone()));
            }
            repairs.push(format!(
                "images[{i}]: declared {} but holds {actual}; mimeType corrected",
                declared.unwrap_or_default()
            ));
            continue;
        }
        if let Some(d) = declared.filter(|d| !allowed.contains(&d.as_str())) {
            return Err(err(
                doc,
                &format!("images/{i}/mimeType"),
                &format!(
                    "{d} is not an image type glTF allows here ({})",
                    allowed.join(", ")
                ),
            ));
        }
    }
    Ok(repairs)
}

fn semantics(
    doc: &Document,
    attrs: &Map<String, Value>,
    place: &str,
    quantized: bool,
) -> Result<()> {
    let accessors = doc.array("accessors");
    let mut count = None;
    for (name, v) in attrs {
        let Some(acc) = v.as_u64().and_then(|i| accessors.get(i as usize)) else {
            continue;
        };
        if !name.starts_with('_') && !accessor_format_ok(acc, name, quantized) {
            return Err(err(
                doc,
                &format!("{place}/{name}"),
                "the accessor's type or component type is not one glTF allows for this \
                 attribute",
            ));
        }
        let c = acc.get("count").and_then(Value::as_u64);
        if count.is_some_and(|n| Some(n) != c) {
            return Err(err(
                doc,
                &format!("{place}/{name}"),
                "all attributes of a primitive must have the same count",
            ));
        }
        count = count.or(c);
    }
    for set in ["TEXCOORD", "COLOR", "JOINTS", "WEIGHTS"] {
        let mut n: Vec<u64> = attrs
            .keys()
            .filter_map(|k| k.strip_prefix(set)?.strip_prefix('_')?.parse().ok())
            .collect();
        n.sort_unstable();
        if n.iter().enumerate().any(|(i, &k)| k != i as u64) {
            return Err(err(
                doc,
                place,
                &format!("{set}_n attributes must be numbered from 0 without gaps (found {n:?})"),
            ));
        }
    }
    let sets = |s: &str| attrs.keys().filter(|k| k.starts_with(s)).count();
    if sets("JOINTS_") != sets("WEIGHTS_") {
        return Err(err(doc, place, "JOINTS_n and WEIGHTS_n must come in pairs"));
    }
    Ok(())
}

/// Floats finite in every accessor; indices inside their primitive's vertices.
fn accessor_data(doc: &Document, triangles_read: bool) -> Result<()> {
    let read = if triangles_read {
        triangle_accessors(doc)
    } else {
        vec![false; doc.array("accessors").len()]
    };
    for (a, acc) in doc.array("accessors").iter().enumerate() {
        if acc.get("componentType").and_then(Value::as_u64) != Some(5126)
            || doc.detached.contains(&a)
            || read.get(a).copied().unwrap_or(false)
        {
            continue;
        }
        let e = accessor::read_any(doc, a, &format!("accessors[{a}]"))?;
        let finite = |c: &[u8]| f32::from_le_bytes([c[0], c[1], c[2], c[3]]).is_finite();
        if let Some(i) = e.bytes.chunks_exact(4).position(|c| !finite(c)) {
            return Err(err(
                doc,
                &format!("accessors/{a}"),
                &format!(
                    "element {} holds a non-finite float",
                    i / e.components.max(1)
                ),
            ));
        }
    }
    for (m, mesh) in doc.array("meshes").iter().enumerate() {
        let prims = mesh.get("primitives").and_then(Value::as_array);
        for (p, prim) in prims.into_iter().flatten().enumerate() {
            let mode = prim.get("mode").and_then(Value::as_u64).unwrap_or(4);
            if triangles_read && crate::triangles::is_triangles(mode) {
                continue;
            }
            let (Some(i), Some(pos)) = (
                prim.get("indices").and_then(Value::as_u64),
                prim.get("attributes")
                    .and_then(|a| a.get("POSITION"))
                    .and_then(Value::as_u64),
            ) else {
                continue;
            };
            let place = format!("meshes/{m}/primitives/{p}/indices");
            let vertices = doc.array("accessors")[pos as usize]["count"]
                .as_u64()
                .unwrap_or(0);
            let indices = accessor::read_indices(doc, i as usize, &place)?;
            if let Some(bad) = indices.iter().find(|&&x| u64::from(x) >= vertices) {
                return Err(err(
                    doc,
                    &place,
                    &format!("index {bad} is past the {vertices} vertices"),
                ));
            }
        }
    }
    Ok(())
}

/// The accessors triangle primitives use (attributes and morph targets).
fn triangle_accessors(doc: &Document) -> Vec<bool> {
    let mut used = vec![false; doc.array("accessors").len()];
    for mesh in doc.array("meshes") {
        let prims = mesh.get("primitives").and_then(Value::as_array);
        for prim in prims.into_iter().flatten() {
            let mode = prim.get("mode").and_then(Value::as_u64).unwrap_or(4);
            if !crate::triangles::is_triangles(mode) {
                continue;
            }
            let targets = prim.get("targets").and_then(Value::as_array);
            let sets = prim
                .get("attributes")
                .into_iter()
                .chain(targets.into_iter().flatten());
            for set in sets.filter_map(Value::as_object) {
                for v in set.values().filter_map(Value::as_u64) {
                    if let Some(u) = used.get_mut(v as usize) {
                        *u = true;
                    }
                }
            }
        }
    }
    used
}

/// Every attribute and index accessor of every primitive (morph targets included), with
/// whether it holds indices.
fn primitive_accessors(doc: &Document) -> Vec<(String, usize, bool)> {
    let mut out = Vec::new();
    for (m, mesh) in doc.array("meshes").iter().enumerate() {
        let prims = mesh.get("primitives").and_then(Value::as_array);
        for (p, prim) in prims.into_iter().flatten().enumerate() {
            let place = format!("meshes/{m}/primitives/{p}");
            if let Some(i) = prim.get("indices").and_then(Value::as_u64) {
                out.push((format!("{place}/indices"), i as usize, true));
            }
            let targets = prim.get("targets").and_then(Value::as_array);
            let sets = prim
                .get("attributes")
                .map(|a| (format!("{place}/attributes"), a))
                .into_iter()
                .chain(
                    targets
                        .into_iter()
                        .flatten()
                        .enumerate()
                        .map(|(t, a)| (format!("{place}/targets/{t}"), a)),
                );
            for (set_place, set) in sets {
                for (name, v) in set.as_object().into_iter().flatten() {
                    if let Some(a) = v.as_u64() {
                        out.push((format!("{set_place}/{name}"), a as usize, false));
                    }
                }
            }
        }
    }
    out
}

/// A bufferView holds indices or vertex attributes, not both, as its target says; one shared
/// by several vertex attributes states its byteStride.
fn buffer_view_use(doc: &Document) -> Result<()> {
    let accessors = doc.array("accessors");
    let views = doc.array("bufferViews");
    // view → (first user, used for indices, distinct vertex accessors)
    let mut uses: std::collections::BTreeMap<usize, (String, bool, Vec<usize>)> =
        std::collections::BTreeMap::new();
    for (place, a, index) in primitive_accessors(doc) {
        let Some(v) = accessors
            .get(a)
            .and_then(|acc| acc.get("bufferView"))
            .and_then(Value::as_u64)
        else {
            continue;
        };
        let v = v as usize;
        let target = views
            .get(v)
            .and_then(|x| x.get("target"))
            .and_then(Value::as_u64);
        let wrong = match target {
            Some(34963) => !index,
            Some(34962) => index,
            _ => false,
        };
        if wrong {
            return Err(err(
                doc,
                &place,
                &format!("reads bufferViews[{v}], whose target is for the other kind of data"),
            ));
        }
        let entry = uses
            .entry(v)
            .or_insert_with(|| (place.clone(), index, Vec::new()));
        if entry.1 != index {
            return Err(err(
                doc,
                &place,
                &format!(
                    "reads bufferViews[{v}] as {}, which {} reads as {}",
                    if index { "indices" } else { "vertex data" },
                    entry.0.replace('/', "."),
                    if entry.1 { "indices" } else { "vertex data" }
                ),
            ));
        }
        if !index && !entry.2.contains(&a) {
            entry.2.push(a);
        }
    }
    for (v, (place, _, vertex)) in uses {
        let stride = views.get(v).and_then(|x| x.get("byteStride"));
        if vertex.len() > 1 && stride.is_none() {
            return Err(err(
                doc,
                &place,
                &format!(
                    "bufferViews[{v}] holds {} vertex attributes but states no byteStride",
                    vertex.len()
                ),
            ));
        }
    }
    Ok(())
}

/// Float COLOR_n values lie in [0, 1]; float NORMAL and TANGENT vectors are unit length
/// (and TANGENT's w is ±1); morph targets' displacements are left alone.
fn attribute_values(doc: &Document) -> Result<()> {
    use rayon::prelude::*;
    let accessors = doc.array("accessors");
    let mut jobs: Vec<(String, usize, u8)> = Vec::new();
    for (place, a, index) in primitive_accessors(doc) {
        // Morph targets hold displacements: neither unit nor within [0, 1].
        if place.contains("/targets/") {
            continue;
        }
        let name = place.rsplit('/').next().unwrap_or("");
        let kind = if name.starts_with("COLOR_") {
            0
        } else if name == "NORMAL" {
            1
        } else if name == "TANGENT" {
            2
        } else {
            continue;
        };
        let acc = accessors.get(a);
        let float = acc
            .and_then(|x| x.get("componentType"))
            .and_then(Value::as_u64)
            == Some(5126);
        if index || !float || jobs.iter().any(|j| j.1 == a) || doc.detached.contains(&a) {
            continue;
        }
        jobs.push((place, a, kind));
    }
    // One accessor per task; the first fault in document order is the one reported.
    let faults: Vec<Result<Option<String>>> = jobs
        .par_iter()
        .map(|(place, a, kind)| values_fault(doc, *a, place, *kind))
        .collect();
    for ((place, _, _), fault) in jobs.iter().zip(faults) {
        if let Some(why) = fault? {
            return Err(err(doc, place, &why));
        }
    }
    Ok(())
}

/// The first element of accessor `a` outside its range: kind 0 colours in [0, 1], 1 unit
/// normals, 2 unit tangents with w = ±1.
fn values_fault(doc: &Document, a: usize, place: &str, kind: u8) -> Result<Option<String>> {
    let e = accessor::read_any(doc, a, place)?;
    let comps = e.components.max(1);
    let f = |c: &[u8]| f32::from_le_bytes([c[0], c[1], c[2], c[3]]);
    if kind == 0 {
        let out = e
            .bytes
            .chunks_exact(4)
            .position(|c| !(0.0..=1.0).contains(&f(c)));
        return Ok(out.map(|k| {
            format!(
                "element {} holds {}, outside [0, 1] (glTF colours are clamped)",
                k / comps,
                f(&e.bytes[4 * k..4 * k + 4])
            )
        }));
    }
    if comps < 3 {
        return Ok(None);
    }
    Ok(e.bytes
        .chunks_exact(4 * comps)
        .enumerate()
        .find_map(|(i, el)| {
            let [x, y, z] = [0, 4, 8].map(|o| f(&el[o..o + 4]));
            let len2 = x * x + y * y + z * z;
            let w_bad = kind == 2 && comps == 4 && f(&el[12..16]).abs() != 1.0;
            // |len - 1| <= 5e-4 is |len² - 1| <= about 1e-3.
            ((len2 - 1.0).abs() > 1e-3 || !len2.is_finite() || w_bad).then(|| {
                format!(
                    "element {i} has length {}{}; glTF requires unit vectors{}",
                    len2.sqrt(),
                    if w_bad { " or w not ±1" } else { "" },
                    if kind == 2 {
                        " (bake with --tangents regenerate)"
                    } else {
                        ""
                    }
                )
            })
        }))
}

/// Animation sampler inputs strictly increasing.
fn animations(doc: &Document) -> Result<()> {
    for (a, anim) in doc.array("animations").iter().enumerate() {
        let samplers = anim.get("samplers").and_then(Value::as_array);
        for (s, sampler) in samplers.into_iter().flatten().enumerate() {
            let Some(input) = sampler.get("input").and_then(Value::as_u64) else {
                continue;
            };
            let place = format!("animations/{a}/samplers/{s}/input");
            let e = accessor::read_any(doc, input as usize, &place)?;
            let times: Vec<f32> = (0..e.count)
                .map(|i| e.component_f32(i * e.components))
                .collect();
            if times.windows(2).any(|w| w[1] <= w[0]) {
                return Err(err(
                    doc,
                    &place,
                    "animation input times must increase strictly",
                ));
            }
        }
    }
    Ok(())
}

/// Declared `min`/`max` that differ from the data are replaced by the data's.
fn repair_bounds(doc: &mut Document) -> Result<Vec<String>> {
    let mut repairs = Vec::new();
    for a in 0..doc.array("accessors").len() {
        let acc = &doc.array("accessors")[a];
        if doc.detached.contains(&a) || (acc.get("min").is_none() && acc.get("max").is_none()) {
            continue;
        }
        let place = format!("accessors[{a}]");
        let Some((lo, hi, float)) = bounds(doc, a, &place)? else {
            continue;
        };
        let same = |declared: Option<&Value>, actual: &[f64]| {
            declared.and_then(Value::as_array).is_some_and(|d| {
                d.len() == actual.len()
                    && d.iter().zip(actual).all(|(d, &x)| {
                        d.as_f64()
                            .is_some_and(|d| if float { d as f32 == x as f32 } else { d == x })
                    })
            })
        };
        if same(acc.get("min"), &lo) && same(acc.get("max"), &hi) {
            continue;
        }
        set_bounds(doc, a, &lo, &hi, float);
        repairs.push(format!(
            "{place}: the declared min/max did not match the data; replaced by the data's"
        ));
    }
    Ok(repairs)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::edit::NewAccessor;
    use serde_json::json;

    /// One triangle whose NORMAL is `base` and whose one morph target's NORMAL is `target`.
    fn morphed(base: [f32; 3], target: [f32; 3]) -> Document {
        let mut doc = Document::empty(std::path::Path::new("m.glb"));
        let mut p = NewAccessor::f32(&[[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        p.min_max = true;
        let p = doc.push_accessor(p);
        let n = doc.push_accessor(NewAccessor::f32(&[base, [0.0, 0.0, 1.0], [0.0, 0.0, 1.0]]));
        let mut d = NewAccessor::f32(&[[0.0f32, 0.0, 0.1]; 3]);
        d.min_max = true;
        let d = doc.push_accessor(d);
        let t = doc.push_accessor(NewAccessor::f32(&[target; 3]));
        let i = doc.push_accessor(NewAccessor::indices(&[0, 1, 2], 3));
        let mut attrs = Map::new();
        attrs.insert("POSITION".into(), json!(p));
        attrs.insert("NORMAL".into(), json!(n));
        let mesh = doc.add_mesh_node("m", attrs, i);
        doc.json["meshes"][mesh]["primitives"][0]["targets"] =
            json!([{ "POSITION": d, "NORMAL": t }]);
        doc
    }

    #[test]
    fn morph_target_normals_are_displacements_and_base_normals_unit() {
        let mut ok = morphed([0.0, 0.0, 1.0], [0.0; 3]);
        check(&mut ok, false).expect("a zero displacement is a displacement");
        let mut bad = morphed([0.0; 3], [0.0; 3]);
        let e = check(&mut bad, false)
            .expect_err("a zero base normal")
            .to_string();
        assert!(
            e.contains("attributes.NORMAL: element 0 has length 0; glTF requires unit vectors"),
            "{e}"
        );
    }
}
