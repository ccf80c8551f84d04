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

use rayon::prelude::*;

use crate::topology::{NO_FACE, Topology};

/// One fin edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FinEdge {
    /// Vertices at the edge's two ends as `faces[0]` uses them, in its winding order.
    pub vertices: [u32; 2],
    /// The faces beside the edge; the second is [`NO_FACE`] on a boundary.
    pub faces: [u32; 2],
    /// Unit geometric normals of the two faces (counter-clockwise winding); zero for a
    /// missing second face.
    pub normals: [[f32; 3]; 2],
    /// Faces using the edge (1, 2, or more on a non-manifold edge).
    pub face_count: u32,
}

/// Builds the fin edges of `t`. `indices` are the output triangle indices (the vertices fins
/// refer to) and `furry(v)` says whether output vertex `v` has fur.
pub fn build(t: &Topology, indices: &[u32], furry: impl Fn(u32) -> bool + Sync) -> Vec<FinEdge> {
    let corner_at = |f: u32, p: u32| {
        let c = 3 * f as usize;
        (c..c + 3).find(|&k| t.corner_pid[k] == p).unwrap_or(c)
    };
    t.edges
        .par_iter()
        .with_min_len(4096)
        .filter_map(|e| {
            let c = e.corner as usize;
            let next = c - c % 3 + (c + 1) % 3;
            let first = [indices[c], indices[next]];
            let second = (e.faces[1] != NO_FACE)
                .then(|| [c, next].map(|k| indices[corner_at(e.faces[1], t.corner_pid[k])]));
            let fur = first
                .iter()
                .chain(second.iter().flatten())
                .any(|&v| furry(v));
            fur.then(|| FinEdge {
                vertices: first,
                faces: e.faces,
                normals: [
                    t.face_normal[e.faces[0] as usize],
                    t.face_normal
                        .get(e.faces[1] as usize)
                        .copied()
                        .unwrap_or([0.0; 3]),
                ],
                face_count: e.face_count,
            })
        })
        .collect()
}
