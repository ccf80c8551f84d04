//! How pelt stores topology in a `.glb`: normal-group IDs as a vertex attribute, and the fin
//! edges (Lengyel et al. 2001, as Frantzen's fins use them) as an accessor the primitive's
//! `PELT_fur` extension names ([`crate::extension`]). The format is written down in
//! `docs/format.md` and `docs/extension/PELT_fur/`; keep them in sync.
//!
//! - `_NORMAL_GROUP`: SCALAR unsigned short, not normalized, one 8-bit ID per vertex (0 = none).
//! - `PELT_fur.fins.accessor`: VEC2 UNSIGNED_INT records ([`FIN_RECORD_SIZE`] little-endian
//!   bytes: `c0 u32, c1 u32`, [`FinEdge`]), the corners (elements of the primitive's index
//!   list) where the edge starts in the windings of its two lowest faces; `c1 = 0xFFFFFFFF` on
//!   a boundary. A renderer gets the edge's vertices and both faces' normals through the index
//!   list ([`fin_geometry`]; `shaders/fin_records.wgsl` is the same decode in WGSL).
//! - `PELT_fur.computedFrom`: the triangle count and hash of the index list the records were
//!   computed from; records a tool left stale read as [`StoredFins::Stale`].
//! - The legacy form (`extras.pelt`, [`FORMAT_VERSION`] 2, records in a bufferView) still reads;
//!   version 1 (28-byte records) is refused by name.

use glam::Vec3;
use pelt_geom::fins::FinEdge;
use pelt_geom::topology::{NO_CORNER, next_corner, prev_corner};
use serde_json::{Map, Value, json};

use crate::accessor::{ComponentType, view_bytes};
use crate::document::{Document, PrimitiveRef, ViewData};
use crate::edit::NewAccessor;
use crate::error::Result;
use crate::extension::{EXTENSION, Form, computed_from, index_hash};

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

/// What a primitive's stored fin records are worth.
#[derive(Debug, Clone, PartialEq)]
pub enum StoredFins {
    /// Records that hold for the primitive's index list.
    Valid(Vec<FinEdge>),
    /// Records computed from another index list (a tool reordered, welded or simplified the
    /// triangles), or legacy records a tool left unreadable: why. A reader rebuilds the fins
    /// from the topology.
    Stale(String),
}

impl Document {
    /// Sets the primitive's `extensions.PELT_fur` to `fur`, with the fin records (when there
    /// are any) as a new accessor named by `fur.fins.accessor`, and `computedFrom` for the
    /// index list `indices` the primitive now has. Old records are detached (and pruned if
    /// nothing else uses them). Returns false, and changes nothing, when the primitive's
    /// `extensions` is not an object.
    pub fn set_topology(
        &mut self,
        r: PrimitiveRef,
        mut fur: Map<String, Value>,
        fins: Option<Vec<FinEdge>>,
        indices: &[u32],
    ) -> Result<bool> {
        if let Some(edges) = fins.filter(|e| !e.is_empty()) {
            let a = self.push_accessor(NewAccessor::records(fins_view(edges), 2));
            if let Some(f) = fur.get_mut("fins").and_then(Value::as_object_mut) {
                f.shift_remove("fromIndices");
                f.shift_remove("count");
                f.insert("accessor".into(), json!(a));
            }
        }
        fur.shift_remove("version");
        fur.insert("computedFrom".into(), computed_from(indices));
        self.set_fur_primitive(r, fur)
    }

    /// The fin edges stored for the primitive (None when it has none), checked against the
    /// primitive; stale records (see [`StoredFins`]) are an error naming why.
    pub fn read_fins(&self, r: PrimitiveRef) -> Result<Option<Vec<FinEdge>>> {
        match self.read_stored_fins(r)? {
            None => Ok(None),
            Some(StoredFins::Valid(e)) => Ok(Some(e)),
            Some(StoredFins::Stale(why)) => Err(self.invalid(
                format!("{} extensions.{EXTENSION}.fins", self.place(r)),
                why,
            )),
        }
    }

    /// The fin edges stored for the primitive (None when it has none).
    ///
    /// Extension form: records whose `computedFrom` (triangle count, index hash) no longer
    /// matches the index list are [`StoredFins::Stale`]; matching records are checked (the
    /// accessor must be VEC2 UNSIGNED_INT, every corner must name an element of the index
    /// list) and a failed check is an error. Legacy form (`extras.pelt`, no hash): records
    /// that fail the checks (a tool renumbered the bufferView they were in) are stale; format
    /// version 1 is refused with its version named.
    pub fn read_stored_fins(&self, r: PrimitiveRef) -> Result<Option<StoredFins>> {
        let Some((fur, form)) = self.fur_primitive(r)? else {
            return Ok(None);
        };
        let Some(fins) = fur.get("fins") else {
            return Ok(None);
        };
        let place = format!("{}.fins", self.fur_place(r, form));
        if form == Form::Legacy {
            self.check_format_version(r, fur)?;
            return Ok(Some(match self.legacy_fins(r, fins, &place) {
                Ok(e) => StoredFins::Valid(e),
                Err(e) => StoredFins::Stale(format!(
                    "the records do not fit the file any more ({}): a tool rewrote it",
                    e.message()
                )),
            }));
        }
        if let Some(why) = self.stale_reason(r, fur)? {
            return Ok(Some(StoredFins::Stale(why)));
        }
        let edges = match fins.get("fromIndices") {
            Some(derived) => {
                let count = fins
                    .get("count")
                    .and_then(Value::as_u64)
                    .ok_or_else(|| self.invalid(&place, "count is missing or not an integer"))?;
                let list = |part: &str| match derived.get(part) {
                    None => Ok(Vec::new()),
                    Some(a) => self.fin_accessor(a, &format!("{place}.fromIndices.{part}")),
                };
                self.derived_fins(r, (list("added")?, list("removed")?), count, &place)?
            }
            None => match fins.get("accessor") {
                Some(a) => self.fin_accessor(a, &format!("{place}.accessor"))?,
                None => Vec::new(),
            },
        };
        self.check_corners(r, edges, &place)
            .map(|e| Some(StoredFins::Valid(e)))
    }

    /// Why the extension's records no longer hold for the primitive's index list (None when
    /// `computedFrom` matches, or is absent).
    fn stale_reason(&self, r: PrimitiveRef, fur: &Map<String, Value>) -> Result<Option<String>> {
        let Some(from) = fur.get("computedFrom") else {
            return Ok(None);
        };
        let corners = self.corner_list(r)?;
        let (tris, hash) = ((corners.len() / 3) as u64, u64::from(index_hash(&corners)));
        let (want_tris, want_hash) = (
            from.get("triangles").and_then(Value::as_u64),
            from.get("indexHash").and_then(Value::as_u64),
        );
        Ok((want_tris != Some(tris) || want_hash != Some(hash)).then(|| {
            format!(
                "the fin records were computed from {} triangles (index hash {}), the primitive \
                 now has {tris} (hash {hash}): a tool reordered, welded or simplified the triangles",
                want_tris.map_or("?".into(), |t| t.to_string()),
                want_hash.map_or("?".into(), |h| h.to_string()),
            )
        }))
    }

    /// The primitive's index list (its vertices in order when it has no `indices`).
    pub fn corner_list(&self, r: PrimitiveRef) -> Result<Vec<u32>> {
        match self.primitive(r)?.get("indices").and_then(Value::as_u64) {
            Some(i) => crate::accessor::read_indices(
                self,
                i as usize,
                &format!("{} indices", self.place(r)),
            ),
            None => {
                let n = self.corner_count(r)?;
                let n = u32::try_from(n).map_err(|_| {
                    self.invalid(
                        self.place(r),
                        format!("{n} vertices do not fit 32-bit indices"),
                    )
                })?;
                Ok((0..n).collect())
            }
        }
    }

    /// Fin records from the accessor named by `a` (VEC2 UNSIGNED_INT, not normalized).
    fn fin_accessor(&self, a: &Value, place: &str) -> Result<Vec<FinEdge>> {
        let a = a
            .as_u64()
            .ok_or_else(|| self.invalid(place, "is not an accessor index"))?;
        let e = crate::accessor::read(self, a as usize, place)?;
        if e.components != 2 || e.component != ComponentType::U32 || e.normalized {
            return Err(self.invalid(
                place,
                format!(
                    "accessor {a} must be VEC2 UNSIGNED_INT (corner pairs), found {} {:?}{}",
                    e.ty,
                    e.component,
                    if e.normalized { " normalized" } else { "" }
                ),
            ));
        }
        Ok(decode_fins(&e.bytes))
    }

    /// Legacy records (`extras.pelt.fins`: a bufferView, or exceptions to the index list's
    /// edges), checked.
    fn legacy_fins(&self, r: PrimitiveRef, fins: &Value, place: &str) -> Result<Vec<FinEdge>> {
        let count = fins
            .get("count")
            .and_then(Value::as_u64)
            .ok_or_else(|| self.invalid(place, "count is missing or not an integer"))?;
        if let Some(stride) = fins.get("byteStride")
            && stride.as_u64() != Some(FIN_RECORD_SIZE as u64)
        {
            return Err(self.invalid(
                place,
                format!("byteStride is {stride}; version {FORMAT_VERSION} records are {FIN_RECORD_SIZE} bytes"),
            ));
        }
        if let Some(derived) = fins.get("fromIndices") {
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
            let edges = self.derived_fins(r, (list("added")?, list("removed")?), count, place)?;
            return self.check_corners(r, edges, place);
        }
        let Some(view) = fins.get("bufferView") else {
            return if count == 0 {
                Ok(Vec::new())
            } else {
                Err(self.invalid(
                    place,
                    format!("count is {count} but there is no bufferView"),
                ))
            };
        };
        let edges = self.fin_records(view, count, place)?;
        self.check_corners(r, edges, place)
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

    /// Fins stored as their difference from the index list's edges ([`crate::fin_predict`]):
    /// `(added, removed)` records, `count` fins in all.
    fn derived_fins(
        &self,
        r: PrimitiveRef,
        (added, removed): (Vec<FinEdge>, Vec<FinEdge>),
        count: u64,
        place: &str,
    ) -> Result<Vec<FinEdge>> {
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

    /// Sets the primitive's `extensions.PELT_fur` with its fins stored as their difference
    /// from the index list's edges: `added` and `removed` records ([`crate::fin_predict`]),
    /// `count` fins in all, for the index list `indices`.
    pub(crate) fn set_derived_fins(
        &mut self,
        r: PrimitiveRef,
        mut fur: Map<String, Value>,
        (count, added, removed): (usize, Vec<FinEdge>, Vec<FinEdge>),
        indices: &[u32],
    ) -> Result<bool> {
        let mut derived = Map::new();
        for (part, list) in [("added", added), ("removed", removed)] {
            if !list.is_empty() {
                let a = self.push_accessor(NewAccessor::records(fins_view(list), 2));
                derived.insert(part.into(), json!(a));
            }
        }
        if let Some(f) = fur.get_mut("fins").and_then(Value::as_object_mut) {
            f.shift_remove("accessor");
            f.insert("count".into(), json!(count));
            f.insert("fromIndices".into(), Value::Object(derived));
        }
        self.set_topology(r, fur, None, indices)
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

    /// Checks the legacy `extras.pelt.version`: only [`FORMAT_VERSION`] is read.
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
