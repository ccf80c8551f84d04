//! Fin edges: the edge list silhouette fins are drawn from (Lengyel et al. 2001; Frantzen's
//! shells-and-fins renderer). A renderer without geometry shaders draws one instanced quad per
//! edge and fades it in by how close the edge is to the silhouette, which it judges from the
//! normals of the two faces beside the edge.
//!
//! A fin is stored as its edge's two corners ([`Edge`]: where the edge starts in the winding of
//! each of its two lowest faces), 8 bytes. Through the index list those give the edge's two
//! vertices and both faces' three vertices, so a renderer computes the face normals from the
//! positions it draws with: skinned or morphed positions give the deformed normals, with
//! nothing baked going stale.
//!
//! Every unique welded edge of the proper faces is a fin edge (a UV seam is one edge, not two),
//! except where no vertex of its faces at its two ends has fur (comb length 0): those edges
//! would draw nothing. Boundary edges have no second corner; non-manifold edges (three or more
//! faces) keep their two lowest faces.

use rayon::prelude::*;

pub use crate::topology::Edge as FinEdge;
use crate::topology::{Edge, next_corner};

/// Which vertices have fur.
#[derive(Clone, Copy)]
pub enum Fur<'a> {
    /// Every vertex (every edge becomes a fin).
    Everywhere,
    /// Comb length per output vertex; a vertex has fur where it is above 0.
    Lengths(&'a [f32]),
}

/// The fin edges among `edges` (a topology's edge list, taken with
/// [`crate::topology::Topology::take_edges`]), in edge order, reusing its memory. `indices`
/// are the output triangle indices (the vertices corners refer to); `fur` says which of those
/// vertices have fur.
pub fn build(mut edges: Vec<Edge>, indices: &[u32], fur: Fur<'_>) -> Vec<FinEdge> {
    let lengths = match fur {
        Fur::Everywhere => return edges,
        Fur::Lengths(l) => l,
    };
    let furry = |c: u32| {
        lengths
            .get(indices[c as usize] as usize)
            .is_some_and(|&l| l > 0.0)
    };
    let keep = |e: &Edge| {
        let second = e.second_face().map(|_| e.second_corner);
        [Some(e.corner), second]
            .into_iter()
            .flatten()
            .any(|c| furry(c) || furry(next_corner(c)))
    };
    // Mark in parallel, then compact in place (no second allocation).
    let marks: Vec<bool> = edges.par_iter().with_min_len(16384).map(keep).collect();
    let mut k = 0;
    edges.retain(|_| {
        k += 1;
        marks[k - 1]
    });
    edges
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::topology::NO_CORNER;

    #[test]
    fn bare_edges_are_left_out_and_kept_ones_keep_their_order() {
        // Two triangles (0 1 2) and (2 1 3) sharing edge 1-2; fur only at vertex 3.
        let indices = [0, 1, 2, 2, 1, 3];
        let edges = vec![
            Edge {
                corner: 0,
                second_corner: NO_CORNER,
            },
            Edge {
                corner: 1,
                second_corner: 3,
            },
            Edge {
                corner: 2,
                second_corner: NO_CORNER,
            },
            Edge {
                corner: 4,
                second_corner: NO_CORNER,
            },
            Edge {
                corner: 5,
                second_corner: NO_CORNER,
            },
        ];
        let lengths = [0.0, 0.0, 0.0, 0.5];
        let fins = build(edges.clone(), &indices, Fur::Lengths(&lengths));
        // Only the edges with vertex 3 at an end are kept: the shared edge 1-2 has no fur at its
        // ends in either face, though its second face has fur at its third corner.
        assert_eq!(fins, vec![edges[3], edges[4]]);
        assert_eq!(build(edges.clone(), &indices, Fur::Everywhere), edges);
    }
}
