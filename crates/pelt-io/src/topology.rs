//! How pelt stores topology in a `.glb`: normal-group IDs as a vertex attribute, and the fin
//! edges (Lengyel et al. 2001, as Frantzen's fins use them) in a bufferView described by the
//! primitive's `extras.pelt`. The format is written down in `docs/format.md`; keep the two in
//! sync.
//!
//! - `_NORMAL_GROUP`: SCALAR unsigned short, not normalized, one 8-bit ID per vertex (0 = none).
//! - `extras.pelt.version`: [`FORMAT_VERSION`] (2). Version 1 stored 28-byte fin records
//!   (vertices, faces, octahedral face normals, face count); this reader refuses it by name.
//! - `extras.pelt.fins`: `{ "bufferView", "count", "byteStride": 8, ... }`, records of
//!   [`FIN_RECORD_SIZE`] little-endian bytes: `c0 u32, c1 u32` ([`FinEdge`]), the corners
//!   (elements of the primitive's index list) where the edge starts in the windings of its two
//!   lowest faces; `c1 = 0xFFFFFFFF` on a boundary. A renderer gets the edge's vertices and both
//!   faces' normals through the index list ([`fin_geometry`]; `shaders/fin_record.wgsl` is the
//!   same decode in WGSL). A bufferView holds bytes only, so it needs no accessor (glTF forbids
//!   32-bit unsigned accessors outside indices) and validators accept it.

use glam::Vec3;
use pelt_geom::fins::FinEdge;
use pelt_geom::topology::{NO_CORNER, next_corner, prev_corner};
use serde_json::{Map, Value, json};

use crate::accessor::view_bytes;
use crate::document::{Document, PrimitiveRef, ViewData};
use crate::error::Result;

/// The attribute holding normal-group IDs.
pub const NORMAL_GROUP_ATTRIBUTE: &str = "_NORMAL_GROUP";

/// Bytes per fin record.
pub const FIN_RECORD_SIZE: usize = size_of::<FinEdge>();

/// Version of the `extras.pelt` layout: 2 since fin records became corner pairs.
pub const FORMAT_VERSION: u64 = 2;

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
                corner: w(0),
                second_corner: w(1),
            }
        })
        .collect()
}

/// Every bufferView reference in a primitive's `extras.pelt.fins` (the records, or the
/// exceptions of fins derived from the index list), visited mutably.
pub(crate) fn for_each_fin_view(fins: &mut Value, f: &mut impl FnMut(&mut Value)) {
    if let Some(v) = fins.get_mut("bufferView") {
        f(v);
    }
    if let Some(d) = fins.get_mut("fromIndices") {
        for part in ["added", "removed"] {
            if let Some(v) = d.get_mut(part).and_then(|p| p.get_mut("bufferView")) {
                f(v);
            }
        }
    }
}

/// What a renderer needs of one fin, decoded through the index list.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FinGeometry {
    /// The edge's vertices, in its first face's winding.
    pub vertices: [u32; 2],
    /// The two faces' geometric normals (counter-clockwise winding, unit; zero for a face with
    /// no area); the second is the first's on a boundary.
    pub face_normals: [Vec3; 2],
}

/// The unit geometric normal of the face holding corner `c` (counter-clockwise, as glTF
/// fronts faces), from the positions it is drawn with.
pub fn face_normal_at(c: u32, indices: &[u32], positions: &[Vec3]) -> Vec3 {
    let p = |k: u32| positions[indices[k as usize] as usize];
    let (a, b, d) = (p(c), p(next_corner(c)), p(prev_corner(c)));
    (b - a).cross(d - a).normalize_or_zero()
}

/// Decodes a fin record checked by [`Document::read_fins`] (corners in range of `indices`,
/// vertices in range of `positions`).
pub fn fin_geometry(e: &FinEdge, indices: &[u32], positions: &[Vec3]) -> FinGeometry {
    let n0 = face_normal_at(e.corner, indices, positions);
    let n1 = match e.second_face() {
        Some(_) => face_normal_at(e.second_corner, indices, positions),
        None => n0,
    };
    FinGeometry {
        vertices: [
            indices[e.corner as usize],
            indices[next_corner(e.corner) as usize],
        ],
        face_normals: [n0, n1],
    }
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
        if let Some(mut old) = self.pelt_extras(r)?.and_then(|p| p.get("fins")).cloned() {
            for_each_fin_view(&mut old, &mut |v| {
                if let Some(v) = v.as_u64() {
                    self.detached_views.push(v as usize);
                }
            });
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
    /// bytes (the bufferView must exist and hold exactly `count` records) and against the
    /// primitive (every corner names an element of its index list, or the end of a boundary).
    /// A file of another format version is refused with its version named.
    pub fn read_fins(&self, r: PrimitiveRef) -> Result<Option<Vec<FinEdge>>> {
        let place = format!("{} extras.pelt.fins", self.place(r));
        let Some(pelt) = self.pelt_extras(r)? else {
            return Ok(None);
        };
        let Some(fins) = pelt.get("fins") else {
            return Ok(None);
        };
        self.check_format_version(r, pelt)?;
        let count = fins
            .get("count")
            .and_then(Value::as_u64)
            .ok_or_else(|| self.invalid(&place, "count is missing or not an integer"))?;
        if let Some(stride) = fins.get("byteStride")
            && stride.as_u64() != Some(FIN_RECORD_SIZE as u64)
        {
            return Err(self.invalid(
                &place,
                format!("byteStride is {stride}; version {FORMAT_VERSION} records are {FIN_RECORD_SIZE} bytes"),
            ));
        }
        if let Some(derived) = fins.get("fromIndices") {
            let edges = self.derived_fins(r, derived, count, &place)?;
            return self.check_corners(r, edges, &place).map(Some);
        }
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
        let edges = self.fin_records(view, count, &place)?;
        self.check_corners(r, edges, &place).map(Some)
    }

    /// `count` records from bufferView `view`.
    fn fin_records(&self, view: &Value, count: u64, place: &str) -> Result<Vec<FinEdge>> {
        let view = view
            .as_u64()
            .ok_or_else(|| self.invalid(place, "bufferView is not an index"))?;
        let (bytes, _) = view_bytes(self, view as usize, place)?;
        if (bytes.len() as u64) != count.saturating_mul(FIN_RECORD_SIZE as u64) {
            return Err(self.invalid(
                place,
                format!(
                    "count {count} needs {} bytes of {FIN_RECORD_SIZE}-byte records, bufferView {view} holds {}",
                    count.saturating_mul(FIN_RECORD_SIZE as u64),
                    bytes.len()
                ),
            ));
        }
        Ok(decode_fins(bytes))
    }

    /// Fins stored as their difference from the index list's edges ([`crate::fin_predict`]).
    fn derived_fins(
        &self,
        r: PrimitiveRef,
        derived: &Value,
        count: u64,
        place: &str,
    ) -> Result<Vec<FinEdge>> {
        let list = |part: &str| -> Result<Vec<FinEdge>> {
            let lplace = format!("{place}.fromIndices.{part}");
            let Some(l) = derived.get(part) else {
                return Ok(Vec::new());
            };
            let n = l
                .get("count")
                .and_then(Value::as_u64)
                .ok_or_else(|| self.invalid(&lplace, "count is missing or not an integer"))?;
            let view = l
                .get("bufferView")
                .ok_or_else(|| self.invalid(&lplace, "bufferView is missing"))?;
            self.fin_records(view, n, &lplace)
        };
        let (added, removed) = (list("added")?, list("removed")?);
        let idx = self
            .primitive(r)?
            .get("indices")
            .and_then(Value::as_u64)
            .ok_or_else(|| self.invalid(place, "fromIndices needs the primitive's indices"))?;
        let indices = crate::accessor::read_indices(self, idx as usize, place)?;
        let edges =
            crate::fin_predict::apply(&crate::fin_predict::predict(&indices), &added, &removed)
                .ok_or_else(|| {
                    self.invalid(
                        format!("{place}.fromIndices.removed"),
                        "a removed record is not an edge of the index list",
                    )
                })?;
        if edges.len() as u64 != count {
            return Err(self.invalid(
                place,
                format!(
                    "count is {count}, the index list's edges and the exceptions give {}",
                    edges.len()
                ),
            ));
        }
        Ok(edges)
    }

    /// Sets the primitive's `extras.pelt` with its fins stored as their difference from the
    /// index list's edges: `added` and `removed` records ([`crate::fin_predict`]), `count`
    /// fins in all.
    pub(crate) fn set_derived_fins(
        &mut self,
        r: PrimitiveRef,
        mut pelt: Map<String, Value>,
        count: usize,
        added: Vec<FinEdge>,
        removed: Vec<FinEdge>,
    ) -> Result<bool> {
        let mut derived = Map::new();
        for (part, list) in [("added", added), ("removed", removed)] {
            if !list.is_empty() {
                let n = list.len();
                let view = self.push_view(fins_view(list), None);
                derived.insert(part.into(), json!({ "bufferView": view, "count": n }));
            }
        }
        if let Some(f) = pelt.get_mut("fins").and_then(Value::as_object_mut) {
            f.remove("bufferView");
            f.insert("count".into(), json!(count));
            f.insert("byteStride".into(), json!(FIN_RECORD_SIZE));
            f.insert("fromIndices".into(), Value::Object(derived));
        }
        self.set_pelt_extras(r, pelt, None)
    }

    /// Every corner of `edges` must name an element of the primitive's index list.
    fn check_corners(
        &self,
        r: PrimitiveRef,
        edges: Vec<FinEdge>,
        place: &str,
    ) -> Result<Vec<FinEdge>> {
        let corners = self.corner_count(r)?;
        // The corner's whole face must exist, so its next and previous corners do too.
        let out_of_range = |c: u32| u64::from(c) / 3 * 3 + 2 >= corners;
        if let Some((k, e)) = edges.iter().enumerate().find(|(_, e)| {
            out_of_range(e.corner)
                || (e.second_corner != NO_CORNER && out_of_range(e.second_corner))
        }) {
            return Err(self.invalid(
                format!("{place} record {k}"),
                format!(
                    "corners ({}, {}) are not both in the primitive's {} triangles",
                    e.corner,
                    e.second_corner,
                    corners / 3
                ),
            ));
        }
        Ok(edges)
    }

    /// Checks `extras.pelt.version`: only [`FORMAT_VERSION`] is read.
    fn check_format_version(&self, r: PrimitiveRef, pelt: &Map<String, Value>) -> Result<()> {
        let place = format!("{} extras.pelt.version", self.place(r));
        match pelt.get("version").and_then(Value::as_u64) {
            Some(FORMAT_VERSION) => Ok(()),
            Some(1) => Err(self.invalid(
                place,
                "format version 1 (28-byte fin records) is no longer read; this pelt reads \
                 version 2 (8-byte corner pairs): bake the source again",
            )),
            Some(v) => Err(self.invalid(
                place,
                format!("format version {v} is unknown; this pelt reads version {FORMAT_VERSION}"),
            )),
            None => Err(self.invalid(place, "missing or not an integer")),
        }
    }

    /// Elements of the primitive's index list (its vertex count when it has none).
    fn corner_count(&self, r: PrimitiveRef) -> Result<u64> {
        let prim = self.primitive(r)?;
        let accessor = match prim.get("indices").and_then(Value::as_u64) {
            Some(i) => Some(i),
            None => self.attribute(r, "POSITION")?.map(|i| i as u64),
        };
        Ok(accessor
            .and_then(|i| self.array("accessors").get(i as usize))
            .and_then(|a| a.get("count"))
            .and_then(Value::as_u64)
            .unwrap_or(0))
    }
}
