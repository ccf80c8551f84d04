//! Mesh topology for the inferred-lighting filter and silhouette fins (issue 3, first step):
//! welded positions, unique edges with their faces, and normal groups.
//!
//! Normal groups follow Kircher & Lawrance, "Inferred Lighting", §3.1: the faces of a mesh are
//! the nodes of its dual graph; two faces are joined where they share a (welded) edge and the
//! normals at both ends of that edge agree on both sides within a tolerance; the connected
//! components are the groups. Seams that only split UVs or other attributes therefore neither
//! cut groups nor duplicate edges. Where three or more faces share an edge, every pair that
//! meets the rule is joined. Degenerate triangles are ordinary nodes: their vertex normals
//! decide, as for any face.

use glam::Vec3;
use rayon::prelude::*;

use crate::weld::{key_bits, weld};

/// One unique welded edge and the faces around it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Edge {
    /// Welded position ids of the two ends, smaller first.
    pub ends: [u32; 2],
    /// Faces using the edge, ascending.
    pub faces: Vec<u32>,
}

/// Topology of an indexed triangle mesh.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Topology {
    /// Welded position id per vertex.
    pub position_id: Vec<u32>,
    /// Number of welded positions.
    pub positions: usize,
    /// Unique edges, ordered by their ends.
    pub edges: Vec<Edge>,
    /// Normal group per face, numbered in order of each group's first face.
    pub face_group: Vec<u32>,
    /// Number of groups.
    pub groups: usize,
}

impl Topology {
    /// Edges with one face.
    pub fn boundary_edges(&self) -> usize {
        self.edges.iter().filter(|e| e.faces.len() == 1).count()
    }

    /// Edges with three or more faces.
    pub fn nonmanifold_edges(&self) -> usize {
        self.edges.iter().filter(|e| e.faces.len() > 2).count()
    }
}

/// Union-find with path halving; the root of a set is its smallest member.
struct Sets(Vec<u32>);

impl Sets {
    fn find(&mut self, mut x: u32) -> u32 {
        while self.0[x as usize] != x {
            let p = self.0[x as usize];
            self.0[x as usize] = self.0[p as usize];
            x = p;
        }
        x
    }

    fn join(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
        self.0[hi as usize] = lo;
    }
}

/// Builds the topology. `normals` are per vertex; two corner normals agree when the angle
/// between them is at most `normal_tolerance` radians.
pub fn build(
    positions: &[Vec3],
    normals: &[Vec3],
    indices: &[u32],
    normal_tolerance: f32,
) -> Topology {
    let (position_id, n_pos) = weld(positions.len(), |v| positions[v].to_array().map(key_bits));
    let nf = indices.len() / 3;
    let pid = |c: usize| position_id[indices[c] as usize];

    // Every face edge keyed by its welded ends; sorting gathers the faces of each edge.
    let mut half: Vec<(u64, u32)> = (0..3 * nf)
        .into_par_iter()
        .with_min_len(4096)
        .filter_map(|c| {
            let f = c / 3;
            let (a, b) = (pid(c), pid(3 * f + (c + 1) % 3));
            (a != b).then(|| {
                let (lo, hi) = if a < b { (a, b) } else { (b, a) };
                ((u64::from(lo) << 32) | u64::from(hi), c as u32)
            })
        })
        .collect();
    half.par_sort_unstable();

    let cos_tol = normal_tolerance.cos();
    let agree = |c: usize, d: usize| {
        let (n, m) = (normals[indices[c] as usize], normals[indices[d] as usize]);
        n.dot(m) >= cos_tol * n.length() * m.length()
    };
    // The corner of face f at welded position p.
    let corner_at = |f: usize, p: u32| (3 * f..3 * f + 3).find(|&c| pid(c) == p);

    let mut sets = Sets((0..nf as u32).collect());
    let mut edges = Vec::new();
    for run in half.chunk_by(|a, b| a.0 == b.0) {
        let ends = [(run[0].0 >> 32) as u32, run[0].0 as u32];
        let mut faces: Vec<u32> = run.iter().map(|&(_, c)| c / 3).collect();
        faces.dedup();
        for (i, &f) in faces.iter().enumerate() {
            for &g in &faces[i + 1..] {
                let same = ends.iter().all(|&p| {
                    match (corner_at(f as usize, p), corner_at(g as usize, p)) {
                        (Some(c), Some(d)) => agree(c, d),
                        _ => false,
                    }
                });
                if same {
                    sets.join(f, g);
                }
            }
        }
        edges.push(Edge { ends, faces });
    }

    // Groups numbered by first face.
    let mut face_group = vec![u32::MAX; nf];
    let mut root_group = vec![u32::MAX; nf];
    let mut groups = 0u32;
    for f in 0..nf as u32 {
        let r = sets.find(f) as usize;
        if root_group[r] == u32::MAX {
            root_group[r] = groups;
            groups += 1;
        }
        face_group[f as usize] = root_group[r];
    }
    Topology {
        position_id,
        positions: n_pos,
        edges,
        face_group,
        groups: groups as usize,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat-shaded cube: 4 vertices per face, each with the face's normal.
    fn cube() -> (Vec<Vec3>, Vec<Vec3>, Vec<u32>) {
        let (mut p, mut n, mut i) = (vec![], vec![], vec![]);
        for axis in 0..3 {
            for sign in [-1.0f32, 1.0] {
                let mut normal = Vec3::ZERO;
                normal[axis] = sign;
                let (u, v) = (
                    Vec3::from_array(std::array::from_fn(|k| f32::from(k == (axis + 1) % 3))),
                    Vec3::from_array(std::array::from_fn(|k| f32::from(k == (axis + 2) % 3))),
                );
                let base = p.len() as u32;
                for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                    p.push(normal + u * a + v * b);
                    n.push(normal);
                }
                i.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
            }
        }
        (p, n, i)
    }

    #[test]
    fn flat_cube_has_six_groups_and_closed_edges() {
        let (p, n, i) = cube();
        let t = build(&p, &n, &i, 0.01);
        assert_eq!(t.groups, 6);
        assert_eq!(t.positions, 8);
        // Closed manifold: every edge has two faces, 3F/2 edges.
        assert_eq!(t.edges.len(), 3 * 12 / 2);
        assert_eq!(t.boundary_edges(), 0);
        assert_eq!(t.nonmanifold_edges(), 0);
    }

    #[test]
    fn smooth_normals_make_one_group_across_a_uv_seam() {
        // The cube again, but with normals pointing out of the center: duplicated positions
        // (seams) with equal normals weld, so everything is one group.
        let (p, _, i) = cube();
        let n: Vec<Vec3> = p.iter().map(|v| v.normalize()).collect();
        let t = build(&p, &n, &i, 0.01);
        assert_eq!(t.groups, 1);
        assert_eq!(t.edges.len(), 18);
    }

    #[test]
    fn open_grid_counts_its_boundary() {
        let (w, h) = (5u32, 3u32);
        let p: Vec<Vec3> = (0..=h)
            .flat_map(|y| (0..=w).map(move |x| Vec3::new(x as f32, y as f32, 0.0)))
            .collect();
        let n = vec![Vec3::Z; p.len()];
        let mut i = vec![];
        for y in 0..h {
            for x in 0..w {
                let a = y * (w + 1) + x;
                let b = a + w + 1;
                i.extend([a, a + 1, b, a + 1, b + 1, b]);
            }
        }
        let t = build(&p, &n, &i, 0.01);
        assert_eq!(t.boundary_edges(), (2 * (w + h)) as usize);
        assert_eq!(t.groups, 1);
    }
}
