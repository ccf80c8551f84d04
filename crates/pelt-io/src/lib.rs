//! pelt-io: reading and writing the files pelt bakes.
//!
//! - [`document`]: a glTF 2.0 asset as its JSON (kept whole, key order included) plus its
//!   buffers, loaded from `.gltf` (external files, data URIs) or `.glb`, with every reference
//!   checked against the real bytes before use.
//! - [`accessor`]: typed reads of accessors (every component type, normalization, strides,
//!   sparse) and the encodings pelt writes.
//! - [`edit`]: the changes a bake makes: new accessors, replaced attributes, re-indexed
//!   primitives.
//! - [`glb`]: the self-contained `.glb` writer (all buffers and images in one BIN chunk),
//!   streamed and written atomically.
//! - [`meshopt`]: `EXT_meshopt_compression`/`KHR_meshopt_compression` views decoded at load.
//! - [`pack`]: compressed output (`EXT_meshopt_compression`): vertex-cache order, quantized
//!   attributes through the extension's filters, a compressed stream per bufferView;
//!   [`pack_codec`] wraps meshoptimizer's encoders.
//! - [`mesh`]: one primitive as a [`pelt_geom::Mesh`], every float attribute checked finite.
//! - [`prune`]: removing the accessors and bufferViews a bake left unused.
//! - [`prune_textures`]: removing textures and images a re-bake replaces.
//! - [`extension`]: the `PELT_fur` glTF extension, the one home of its names and layouts (and
//!   the legacy `extras.pelt` form it replaced).
//! - [`topology`]: how normal-group IDs and fin edges are stored (`_NORMAL_GROUP`, the fin
//!   records' accessor, stale-record detection).
//! - [`fin_predict`]: fin records derived from the index list (compressed output stores only
//!   the exceptions).
//! - [`triangles`]: strips and fans as triangle lists.
//! - [`texture`]: images, samplers, textures and material extensions a bake adds (fur textures).
//! - [`typed`]: the `gltf` crate's typed view (skins, animations, materials) over the same
//!   buffers, with pelt-io's bounds check before its readers run.
//! - [`picture`]: texture images decoded with the `image` crate (bounded), a material's
//!   texture slot through `gltf`, bilinear lookups with the sampler's wrap modes.
//! - [`picture_bounded`]: images larger than a texture limit halved while they decode.
//! - [`text`]: OBJ and MTL text in any encoding peers read (UTF-8, UTF-16 with a BOM, lossy).
//! - [`validate`]: the whole document checked against the glTF schema and the validator's
//!   rules before a bake writes it.
//! - [`obj`]: Wavefront OBJ (with `v x y z r g b` colors) into the same document model.

pub mod accessor;
pub mod contract;
pub mod document;
pub mod edit;
pub mod error;
pub mod extension;
pub mod fin_predict;
pub mod glb;
pub mod mesh;
pub mod meshopt;
pub mod nodes;
pub mod obj;
pub mod obj_material;
pub mod pack;
pub mod pack_codec;
mod pack_order;
mod pack_quantize;
pub mod picture;
pub mod picture_bounded;
pub mod prune;
pub mod prune_textures;
pub mod text;
pub mod texture;
pub mod topology;
pub mod triangles;
pub mod typed;
pub mod validate;

pub use document::{Buffer, Document, PrimitiveRef, ViewData};
pub use error::IoError;

/// Loads any supported input: `.obj` by its extension, otherwise `.gltf`/`.glb` (told apart
/// by their magic bytes).
pub fn load(path: &std::path::Path) -> Result<Document, IoError> {
    if is_obj(path) {
        obj::load(path)
    } else {
        Document::load(path)
    }
}

/// [`load`] for bytes already in memory; `path` names them in errors and anchors the relative
/// URIs of a `.gltf` (which are read from disk).
pub fn load_bytes(path: &std::path::Path, bytes: Vec<u8>) -> Result<Document, IoError> {
    if is_obj(path) {
        obj::from_bytes(path, &bytes)
    } else {
        Document::from_bytes(path, bytes)
    }
}

/// Whether `path` is read as Wavefront OBJ (by its extension). OBJ states no facing
/// convention, so a renderer draws its faces from both sides.
pub fn is_obj(path: &std::path::Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"))
}
