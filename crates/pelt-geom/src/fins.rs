//! Fin edges: the edge list silhouette fins are drawn from (Lengyel et al. 2001; Frantzen's
//! shells-and-fins renderer). A renderer without geometry shaders draws one instanced quad per
//! edge and fades it in by how close the edge is to the silhouette, which it judges from the
//! normals of the two faces beside the edge; so each edge carries its two end vertices, its two
//! faces and their normals, and nothing has to be derived at load time.
//!
//! Every unique welded edge of the proper faces is a fin edge (a UV seam is one edge, not two),
//! except where no vertex of its faces at its two ends has fur (comb length 0): those edges
//! would draw nothing. Boundary edges (one face) have no second face; non-manifold edges (three
//! or more faces) keep their two lowest faces and their face count.
//!
//! [`FinEdge`] is also the stored record (28 bytes, little-endian in files).

use bytemuck::{Pod, Zeroable};
use rayon::prelude::*;

use crate::topology::{Edge, NO_FACE, Topology};

/// One fin edge; the layout is the file's record (keep in sync with `docs/format.md`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Pod, Zeroable)]
pub struct FinEdge {
    /// Vertices at the edge's two ends as `faces[0]` uses them, in its winding order.
    pub vertices: [u32; 2],
    /// The faces beside the edge (the two lowest); the second is [`NO_FACE`] on a boundary.
    pub faces: [u32; 2],
    /// The two faces' geometric normals (counter-clockwise winding), octahedral-encoded
    /// ([`crate::octahedral`]); 0 for a missing second face.
    pub normals: [u32; 2],
    /// Faces using the edge (1, 2, or more on a non-manifold edge).
    pub face_count: u32,
}

/// Edges handled by one parallel task.
const CHUNK: usize = 16384;

/// Which vertices have fur.
#[derive(Clone, Copy)]
pub enum Fur<'a> {
    /// Every vertex (every edge becomes a fin).
    Everywhere,
    /// Comb length per output vertex; a vertex has fur where it is above 0.
    Lengths(&'a [f32]),
}

/// Builds the fin edges of `t`, in edge order. `indices` are the output triangle indices (the
/// vertices fins refer to); `fur` says which of those vertices have fur.
pub fn build(t: &Topology, indices: &[u32], fur: Fur<'_>) -> Vec<FinEdge> {
    let corner_at = |f: u32, p: u32| {
        let c = 3 * f as usize;
        (c..c + 3).find(|&k| t.corner_pid[k] == p).unwrap_or(c)
    };
    // The vertices of the edge's ends in its first face and, if any, its second.
    let ends = |e: &Edge| {
        let (c, next) = (e.corner as usize, e.end_corner() as usize);
        let first = [indices[c], indices[next]];
        let second = (e.second_face != NO_FACE)
            .then(|| [c, next].map(|k| indices[corner_at(e.second_face, t.corner_pid[k])]));
        (first, second)
    };
    let record = |e: &Edge| FinEdge {
        vertices: ends(e).0,
        faces: [e.first_face(), e.second_face],
        normals: [
            t.face_normal[e.first_face() as usize],
            if e.second_face == NO_FACE {
                0
            } else {
                t.face_normal[e.second_face as usize]
            },
        ],
        face_count: e.face_count,
    };
    let lengths = match fur {
        Fur::Everywhere => return t.edges.par_iter().with_min_len(CHUNK).map(record).collect(),
        Fur::Lengths(l) => l,
    };
    let keep = |e: &&Edge| {
        let (first, second) = ends(e);
        let furry = |v: &u32| lengths.get(*v as usize).is_some_and(|&l| l > 0.0);
        first.iter().chain(second.iter().flatten()).any(furry)
    };
    // Count per chunk, then write each chunk's fins into its own part of one exact allocation.
    let chunks: Vec<&[Edge]> = t.edges.chunks(CHUNK).collect();
    let counts: Vec<usize> = chunks
        .par_iter()
        .map(|ch| ch.iter().filter(keep).count())
        .collect();
    let mut out = vec![FinEdge::zeroed(); counts.iter().sum()];
    let mut parts = Vec::with_capacity(chunks.len());
    let mut rest = out.as_mut_slice();
    for &n in &counts {
        let (part, tail) = rest.split_at_mut(n);
        parts.push(part);
        rest = tail;
    }
    chunks.par_iter().zip(parts).for_each(|(ch, part)| {
        for (slot, e) in part.iter_mut().zip(ch.iter().filter(keep)) {
            *slot = record(e);
        }
    });
    out
}
