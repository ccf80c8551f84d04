//! Triangle and vertex order for compressed output: a primitive whose accessors are its own
//! is put in vertex-cache order (meshoptimizer's `optimizeVertexCache`) and its vertices in
//! first-use order (`optimizeVertexFetchRemap`, unused vertices dropped), which is what the
//! index and vertex codecs compress best. The index codec may rotate a triangle's corners
//! (winding kept), so the primitive is given the indices a reader will decode, and its fin
//! records ([`crate::topology`]: corners of the index list) follow both the new triangle order
//! and the rotations, each with its lower face first, sorted, and stored as their difference
//! from the index list's edges ([`crate::fin_predict`]) where that is smaller.

use pelt_geom::fins::FinEdge;
use pelt_geom::topology::NO_CORNER;
use serde_json::{Value, json};

use crate::accessor;
use crate::document::{Document, PrimitiveRef};
use crate::edit::NewAccessor;
use crate::error::Result;
use crate::fin_predict::{NO_RECORD, by_first_corner, diff, lower_first, predict};
use crate::pack_codec::{encode_triangles, fetch_remap};

/// A triangle's corners rotated to the least of its three rotations (winding kept; a
/// triangle that repeats a vertex has one answer too), and the rotation (the corner that now
/// comes first).
fn canonical(t: &[u32]) -> ([u32; 3], u32) {
    (0..3u32)
        .map(|r| {
            let r_ = r as usize;
            ([t[r_], t[(r_ + 1) % 3], t[(r_ + 2) % 3]], r)
        })
        .min()
        .unwrap_or(([0; 3], 0))
}

/// For each corner of `old`, its corner in `new`, which holds the same triangles (in the same
/// vertex numbering) in another order, each possibly rotated. None if they are not the same
/// triangles. The triangles of `new` are bucketed by their smallest vertex (a counting sort),
/// so matching is linear.
pub(crate) fn corner_map(old: &[u32], new: &[u32]) -> Option<Vec<u32>> {
    if old.len() != new.len() || !old.len().is_multiple_of(3) {
        return None;
    }
    let vertices = new.iter().chain(old).max().map_or(0, |&m| m as usize + 1);
    let nt = new.len() / 3;
    let mut start = vec![0u32; vertices + 1];
    let keys: Vec<([u32; 3], u32)> = new.chunks_exact(3).map(canonical).collect();
    for (k, _) in &keys {
        start[k[0] as usize + 1] += 1;
    }
    for v in 0..vertices {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut bucket = vec![0u32; nt];
    for (t, (k, _)) in keys.iter().enumerate() {
        let at = &mut fill[k[0] as usize];
        bucket[*at as usize] = t as u32;
        *at += 1;
    }
    // A triangle of `new` is used once (duplicate triangles pair up in order).
    let mut taken = vec![false; nt];
    let mut map = vec![0u32; old.len()];
    for (ta, tri) in old.chunks_exact(3).enumerate() {
        let (ka, ra) = canonical(tri);
        let range = start[ka[0] as usize] as usize..start[ka[0] as usize + 1] as usize;
        let tb = bucket[range]
            .iter()
            .copied()
            .find(|&tb| !taken[tb as usize] && keys[tb as usize].0 == ka)?;
        taken[tb as usize] = true;
        let rb = keys[tb as usize].1;
        for k in 0..3u32 {
            map[3 * ta + k as usize] = 3 * tb + (k + 3 - ra + rb) % 3;
        }
    }
    Some(map)
}

/// Fin records through a corner map, each with its lower face first, sorted.
fn remap_fins(edges: &[FinEdge], map: &[u32]) -> Option<Vec<FinEdge>> {
    let at = |c: u32| map.get(c as usize).copied();
    let mut out = edges
        .iter()
        .map(|e| {
            Some(lower_first(FinEdge {
                corner: at(e.corner)?,
                second_corner: if e.second_corner == NO_CORNER {
                    NO_CORNER
                } else {
                    at(e.second_corner)?
                },
            }))
        })
        .collect::<Option<Vec<_>>>()?;
    // A corner starts one edge of its face, so records are placed by first corner (linear);
    // a list that repeats one (not a bake's) is sorted instead.
    let mut second = vec![NO_RECORD; map.len()];
    for e in &out {
        let s = &mut second[e.corner as usize];
        if *s != NO_RECORD {
            out.sort_unstable_by_key(|e| (e.corner, e.second_corner));
            return Some(out);
        }
        *s = e.second_corner;
    }
    Some(by_first_corner(&second))
}

/// The new order of a primitive: (new vertex → old vertex, indices in new vertices).
fn cache_order(indices: &[u32], vertex_count: usize) -> Option<(Vec<u32>, Vec<u32>)> {
    // meshoptimizer asserts that indices are in range: check first.
    if indices.iter().any(|&i| i as usize >= vertex_count) {
        return None;
    }
    let ordered = meshopt::optimize_vertex_cache(indices, vertex_count);
    let remap = fetch_remap(&ordered, vertex_count)?;
    let used = remap.iter().filter(|&&n| n != u32::MAX).count();
    let mut map = vec![0u32; used];
    for (old, &new) in remap.iter().enumerate() {
        if new != u32::MAX {
            map[new as usize] = old as u32;
        }
    }
    let ordered = ordered.iter().map(|&i| remap[i as usize]).collect();
    Some((map, ordered))
}

impl Document {
    /// Puts triangle primitive `r` in the codecs' order (see the module documentation);
    /// `own` says its accessors are used nowhere else (otherwise only the index codec's
    /// rotations apply). Returns whether the vertices were reordered.
    pub(crate) fn order_for_codec(&mut self, r: PrimitiveRef, own: bool) -> Result<bool> {
        let place = self.place(r);
        let prim = self.primitive(r)?;
        let (Some(idx), Some(pos)) = (
            prim.get("indices").and_then(Value::as_u64),
            prim.get("attributes")
                .and_then(|a| a.get("POSITION"))
                .and_then(Value::as_u64),
        ) else {
            return Ok(false);
        };
        let indices = accessor::read_indices(self, idx as usize, &format!("{place} indices"))?;
        let n = accessor::read_any(self, pos as usize, &format!("{place} POSITION"))?.count;
        if !indices.len().is_multiple_of(3) || indices.is_empty() {
            return Ok(false);
        }
        // Indices past the vertex count are the bake's to refuse, not reordered here.
        let (map, ordered) = match own.then(|| cache_order(&indices, n)).flatten() {
            Some((map, ordered)) => (Some(map), ordered),
            None => (None, indices.clone()),
        };
        let vertices = map.as_ref().map_or(n, Vec::len);
        let Some((_, decoded)) = encode_triangles(&ordered, vertices) else {
            return Ok(false);
        };
        let fins = self.read_fins(r)?;
        let fur = self.fur_primitive(r)?.map(|(f, _)| f.clone());
        if let (Some(fur), None) = (&fur, fins.as_ref().filter(|e| !e.is_empty())) {
            // No records to move, but `computedFrom` must describe the new index list.
            self.set_topology(r, fur.clone(), None, &decoded)?;
        }
        if let Some(edges) = fins.filter(|e| !e.is_empty()) {
            // The old triangles in the new vertex numbering, to match against the decoded.
            let renumbered: Vec<u32> = match &map {
                Some(m) => {
                    let mut inverse = vec![0u32; n];
                    for (new, &old) in m.iter().enumerate() {
                        inverse[old as usize] = new as u32;
                    }
                    indices.iter().map(|&i| inverse[i as usize]).collect()
                }
                None => indices,
            };
            let (edges, predicted) = rayon::join(
                || corner_map(&renumbered, &decoded).and_then(|cm| remap_fins(&edges, &cm)),
                || predict(&decoded),
            );
            let edges = edges.ok_or_else(|| {
                self.invalid(&place, "the index codec changed the triangles (internal)")
            })?;
            let fur = fur.unwrap_or_default();
            // Stored as their difference from the index list's edges where that is smaller.
            let (added, removed) = diff(&edges, &predicted);
            if added.len() + removed.len() < edges.len() {
                self.set_derived_fins(r, fur, (edges.len(), added, removed), &decoded)?;
            } else {
                self.set_topology(r, fur, Some(edges), &decoded)?;
            }
        }
        match &map {
            Some(m) => self.remap_primitive(r, m, &decoded, &[])?,
            None => {
                let a = self.push_accessor(NewAccessor::indices(&decoded, n));
                self.primitive_checked(r)?
                    .insert("indices".into(), json!(a));
                self.detach_accessors([idx as usize]);
            }
        }
        Ok(map.is_some())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corners_follow_reordered_and_rotated_triangles() {
        let old = [0, 1, 2, 2, 1, 3, 5, 4, 3];
        // Triangle 2 first (rotated once), then 0 (as it was), then 1 (rotated twice).
        let new = [4, 3, 5, 0, 1, 2, 3, 2, 1];
        let map = corner_map(&old, &new).expect("same triangles");
        for (c, &m) in map.iter().enumerate() {
            assert_eq!(old[c], new[m as usize], "corner {c} → {m}");
            // The next corner of the same face follows it.
            let next = |x: usize| x / 3 * 3 + (x + 1) % 3;
            assert_eq!(old[next(c)], new[next(m as usize)]);
        }
        assert_eq!(
            corner_map(&old, &[0, 1, 2, 2, 3, 1, 5, 4, 3]),
            None,
            "winding"
        );
        // A triangle that repeats a vertex matches itself rotated.
        let map = corner_map(&[7, 7, 8], &[7, 8, 7]).expect("same triangle");
        assert_eq!(map, [2, 0, 1]);
    }

    #[test]
    fn cache_order_keeps_every_triangle_and_drops_unused_vertices() {
        let indices = [4, 0, 2, 2, 0, 5];
        let (map, ordered) = cache_order(&indices, 6).expect("indices in range");
        assert_eq!(map.len(), 4, "vertices 1 and 3 unused");
        let back: Vec<u32> = ordered.iter().map(|&i| map[i as usize]).collect();
        assert!(corner_map(&indices, &back).is_some(), "{back:?}");
    }
}
