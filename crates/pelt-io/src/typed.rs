//! The `gltf` crate's typed view of a [`Document`]: skins, animations, nodes, materials and
//! textures are read through `gltf::Document` and its accessor readers, over the buffers the
//! document already holds (no second load, no copy).
//!
//! pelt-io keeps the JSON and the bytes (it edits and writes them); this module only lends
//! them to `gltf`. Before one of `gltf`'s readers walks an accessor, [`check`] runs pelt-io's
//! own bounds check on it: `gltf` 1.4's readers slice without checking `count` against the
//! bufferView and unwrap sparse values, so a malformed file could make them panic, and pelt
//! answers bad input with an error naming the place, never a panic.

use serde_json::Value;

use crate::Document;
use crate::accessor;
use crate::error::{IoError, Result};

/// The typed document of `doc` (validated by `gltf`: every index in range, required fields
/// present). A validation failure is an error naming the first place `gltf` reports.
pub fn document(doc: &Document) -> Result<gltf::Document> {
    position_indices(doc)?;
    let mut json = doc.json.clone();
    // A document built in memory (an OBJ) keeps its data in new bufferViews on buffer 0,
    // which the writer declares; declare it here too.
    if doc.buffers.is_empty() && !doc.new_views.is_empty() && !json.contains_key("buffers") {
        json.insert("buffers".into(), serde_json::json!([{ "byteLength": 1 }]));
    }
    // pelt decides which required extensions it reads (pelt-io refuses the ones it cannot);
    // `gltf` would refuse every one its own features do not cover.
    json.remove("extensionsRequired");
    let root: gltf::json::Root =
        serde_path_to_error::deserialize(Value::Object(json)).map_err(|e| {
            let path = e.path().to_string();
            doc.invalid(
                if path == "." { "JSON".to_owned() } else { path },
                format!("does not follow the glTF 2.0 schema: {}", e.into_inner()),
            )
        })?;
    gltf::Document::from_json(root).map_err(|e| match e {
        gltf::Error::Validation(list) => {
            let n = list.len();
            let (path, error) = &list[0];
            let more = if n > 1 {
                format!(" (and {} more)", n - 1)
            } else {
                String::new()
            };
            doc.invalid(path.as_str(), format!("{error}{more}"))
        }
        other => doc.invalid("JSON", other.to_string()),
    })
}

/// Every primitive's POSITION names an accessor that exists: `gltf` 1.4's validation indexes
/// the accessor list with it unchecked.
fn position_indices(doc: &Document) -> Result<()> {
    let n = doc.array("accessors").len() as u64;
    for (m, mesh) in doc.array("meshes").iter().enumerate() {
        let prims = mesh.get("primitives").and_then(Value::as_array);
        for (p, prim) in prims.into_iter().flatten().enumerate() {
            let pos = prim.get("attributes").and_then(|a| a.get("POSITION"));
            if let Some(i) = pos.and_then(Value::as_u64).filter(|&i| i >= n) {
                return Err(doc.invalid(
                    format!("meshes[{m}].primitives[{p}].attributes.POSITION"),
                    format!("accessor {i} does not exist (the file has {n})"),
                ));
            }
        }
    }
    Ok(())
}

/// The buffer data `gltf`'s readers ask for.
pub fn buffers<'d>(doc: &'d Document) -> impl Fn(gltf::Buffer<'_>) -> Option<&'d [u8]> + Clone {
    move |b| doc.buffers.get(b.index()).map(|d| &d[..])
}

/// Checks accessor `a` against the real bytes (bounds, strides, sparse parts) before a `gltf`
/// reader walks it; `place` names it in the error.
pub fn check(doc: &Document, a: &gltf::Accessor<'_>, place: &str) -> Result<()> {
    accessor::read_any(doc, a.index(), place).map(|_| ())
}

/// [`check`], and that the accessor holds `dims` elements of one of `types`: `gltf`'s readers
/// assume the element size their caller expects (a mismatch trips a debug assertion in them,
/// or reads the wrong bytes in a release build).
pub fn check_kind(
    doc: &Document,
    a: &gltf::Accessor<'_>,
    place: &str,
    dims: gltf::accessor::Dimensions,
    types: &[gltf::accessor::DataType],
) -> Result<()> {
    check(doc, a, place)?;
    if a.dimensions() != dims || !types.contains(&a.data_type()) {
        return Err(doc.invalid(
            format!("{place} (accessor {})", a.index()),
            format!(
                "is {:?} of {:?}; expected {dims:?} of {}",
                a.dimensions(),
                a.data_type(),
                types
                    .iter()
                    .map(|t| format!("{t:?}"))
                    .collect::<Vec<_>>()
                    .join(" or ")
            ),
        ));
    }
    Ok(())
}

/// An error at `place` of `doc`.
pub fn invalid(doc: &Document, place: impl Into<String>, message: impl Into<String>) -> IoError {
    doc.invalid(place, message)
}
