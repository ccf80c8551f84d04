//! How pelt stores topology in a `.glb`: normal-group IDs as a vertex attribute, and the fin
//! edges (Lengyel et al. 2001, as Frantzen's fins use them) in a bufferView described by the
//! primitive's `extras.pelt`. The format is written down in `docs/format.md`; keep the two in
//! sync.
//!
//! - `_NORMAL_GROUP`: SCALAR unsigned short, not normalized, one 8-bit ID per vertex (0 = none).
//! - `extras.pelt.fins`: `{ "bufferView", "count", "byteStride": 28, ... }`, records of
//!   [`FIN_RECORD_SIZE`] little-endian bytes: `v0 u32, v1 u32, f0 u32, f1 u32, n0 u32, n1 u32,
//!   faceCount u32` ([`FinEdge`]), where n0 and n1 are the face normals in octahedral encoding
//!   ([`pelt_geom::octahedral`]: two snorm16, x in the low half; WGSL's `unpack2x16snorm`). A
//!   boundary edge has `f1 = 0xFFFFFFFF` and `n1 = 0`. A bufferView holds bytes only, so it needs no accessor (glTF forbids 32-bit
//!   unsigned accessors outside indices) and validators accept it.

use pelt_geom::fins::FinEdge;
use serde_json::{Map, Value, json};

use crate::accessor::view_bytes;
use crate::document::{Document, PrimitiveRef, ViewData};
use crate::error::Result;

/// The attribute holding normal-group IDs.
pub const NORMAL_GROUP_ATTRIBUTE: &str = "_NORMAL_GROUP";

/// Bytes per fin record.
pub const FIN_RECORD_SIZE: usize = size_of::<FinEdge>();

/// Version of the `extras.pelt` layout.
pub const FORMAT_VERSION: u64 = 1;

/// The fin records as a bufferView's data: the edges' own memory, as little-endian words.
pub fn fins_view(edges: Vec<FinEdge>) -> ViewData {
    let mut words: Vec<u32> = bytemuck::allocation::cast_vec(edges);
    if cfg!(target_endian = "big") {
        words.iter_mut().for_each(|w| *w = w.to_le());
    }
    ViewData::Words(words)
}

/// Decodes little-endian fin records.
pub fn decode_fins(bytes: &[u8]) -> Vec<FinEdge> {
    bytes
        .chunks_exact(FIN_RECORD_SIZE)
        .map(|r| {
            let w =
                |k: usize| u32::from_le_bytes([r[4 * k], r[4 * k + 1], r[4 * k + 2], r[4 * k + 3]]);
            FinEdge {
                vertices: [w(0), w(1)],
                faces: [w(2), w(3)],
                normals: [w(4), w(5)],
                face_count: w(6),
            }
        })
        .collect()
}

impl Document {
    /// The primitive's `extras.pelt`, if any.
    pub fn pelt_extras(&self, r: PrimitiveRef) -> Result<Option<&Map<String, Value>>> {
        Ok(self
            .primitive(r)?
            .get("extras")
            .and_then(|e| e.get("pelt"))
            .and_then(Value::as_object))
    }

    /// Sets the primitive's `extras.pelt` (keeping any other extras), with the fin records as
    /// a new bufferView referenced from `pelt.fins.bufferView` when there are any. A previous
    /// fin bufferView is detached (and pruned if nothing else uses it). Returns false, and
    /// changes nothing, when the primitive's `extras` exists but is not an object.
    pub fn set_pelt_extras(
        &mut self,
        r: PrimitiveRef,
        mut pelt: Map<String, Value>,
        fins: Option<ViewData>,
    ) -> Result<bool> {
        let extras_ok = self
            .primitive(r)?
            .get("extras")
            .is_none_or(Value::is_object);
        if !extras_ok {
            return Ok(false);
        }
        if let Some(old) = self
            .pelt_extras(r)?
            .and_then(|p| p.get("fins"))
            .and_then(|f| f.get("bufferView"))
            .and_then(Value::as_u64)
        {
            self.detached_views.push(old as usize);
        }
        if let Some(data) = fins.filter(|d| !d.bytes().is_empty()) {
            let view = self.push_view(data, None);
            if let Some(f) = pelt.get_mut("fins").and_then(Value::as_object_mut) {
                f.insert("bufferView".into(), json!(view));
                f.insert("byteStride".into(), json!(FIN_RECORD_SIZE));
            }
        }
        let prim = self.primitive_checked(r)?;
        let extras = prim.entry("extras").or_insert_with(|| json!({}));
        if let Some(e) = extras.as_object_mut() {
            e.insert("pelt".into(), Value::Object(pelt));
        }
        Ok(true)
    }

    /// The fin edges stored for the primitive (None when it has none), checked against the
    /// bytes: the bufferView must exist and hold exactly `count` records.
    pub fn read_fins(&self, r: PrimitiveRef) -> Result<Option<Vec<FinEdge>>> {
        let place = format!("{} extras.pelt.fins", self.place(r));
        let Some(fins) = self.pelt_extras(r)?.and_then(|p| p.get("fins")) else {
            return Ok(None);
        };
        let count = fins
            .get("count")
            .and_then(Value::as_u64)
            .ok_or_else(|| self.invalid(&place, "count is missing or not an integer"))?;
        let Some(view) = fins.get("bufferView") else {
            return if count == 0 {
                Ok(Some(Vec::new()))
            } else {
                Err(self.invalid(
                    &place,
                    format!("count is {count} but there is no bufferView"),
                ))
            };
        };
        let view = view
            .as_u64()
            .ok_or_else(|| self.invalid(&place, "bufferView is not an index"))?;
        let (bytes, _) = view_bytes(self, view as usize, &place)?;
        if (bytes.len() as u64) != count.saturating_mul(FIN_RECORD_SIZE as u64) {
            return Err(self.invalid(
                &place,
                format!(
                    "count {count} needs {} bytes of {FIN_RECORD_SIZE}-byte records, bufferView {view} holds {}",
                    count.saturating_mul(FIN_RECORD_SIZE as u64),
                    bytes.len()
                ),
            ));
        }
        Ok(Some(decode_fins(bytes)))
    }
}
