//! Mesh topology for the inferred-lighting filter and silhouette fins: welded positions, the
//! faces around each position, unique edges with their faces, and normal groups.
//!
//! Normal groups follow Kircher & Lawrance, "Inferred Lighting", §3.1: the faces of a mesh are
//! the nodes of its dual graph; two faces are joined where they share a welded edge and the
//! normals at both ends of that edge agree on both sides within a tolerance; the connected
//! components are the groups. Positions are welded first (exactly, or within an epsilon), so
//! seams that only split UVs or other attributes neither cut groups nor duplicate edges. Where
//! three or more faces share an edge, every pair that meets the rule is joined.
//!
//! Degenerate triangles (zero area, or two corners welded into one position) have no normal and
//! cover no pixels. They are not faces of any edge (so they make no fins and are not counted as
//! boundary or non-manifold), but they still belong to a group, so that their vertices need no
//! split of their own: a degenerate triangle joins every proper triangle across its edges whose
//! normals meet the rule, and is a group of its own when none does.
//!
//! Edges are found per face through the faces around its corners, in parallel; each edge is
//! emitted once, by its lowest face, so the edge list is in order of (lowest face, corner) and
//! does not depend on the thread count.

use glam::Vec3;
use rayon::prelude::*;

use crate::normals::face_normal;
use crate::octahedral;
use crate::union_find::AtomicUnionFind;
use crate::weld::weld_positions;

/// "No face": the second face of a boundary edge.
pub const NO_FACE: u32 = u32::MAX;

/// The [`Topology::face_normal`] of a degenerate face (an octahedral code the encoder never
/// makes: both halves are -32768).
pub const DEGENERATE: u32 = 0x8000_8000;

/// One unique welded edge and the faces around it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Edge {
    /// The corner where the edge starts in its lowest face's winding (the edge runs from it to
    /// the next corner of that face, `corner / 3`).
    pub corner: u32,
    /// The second-lowest face using the edge, or [`NO_FACE`] on a boundary.
    pub second_face: u32,
    /// Number of faces using the edge: 1 on a boundary, 2 on a manifold edge, more otherwise.
    pub face_count: u32,
}

impl Edge {
    /// The lowest face using the edge.
    pub fn first_face(&self) -> u32 {
        self.corner / 3
    }

    /// The corner after `corner` in its face (where the edge ends).
    pub fn end_corner(&self) -> u32 {
        let c = self.corner;
        c - c % 3 + (c + 1) % 3
    }
}

/// What topology is built with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TopologyOptions {
    /// Positions closer than this weld (0: bit-equal positions only).
    pub weld_epsilon: f32,
    /// Two corner normals agree when the angle between them is at most this (radians).
    pub normal_tolerance: f32,
}

impl Default for TopologyOptions {
    fn default() -> Self {
        TopologyOptions {
            weld_epsilon: 0.0,
            normal_tolerance: DEFAULT_NORMAL_TOLERANCE_DEG.to_radians(),
        }
    }
}

/// The default normal tolerance, in degrees.
pub const DEFAULT_NORMAL_TOLERANCE_DEG: f32 = 0.1;

/// Topology of an indexed triangle mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Topology {
    /// Welded position id per vertex.
    pub position_id: Vec<u32>,
    /// Number of welded positions.
    pub positions: usize,
    /// Welded position id per corner.
    pub corner_pid: Vec<u32>,
    /// Corners at each welded position: those of position `p` are
    /// `star[star_start[p]..star_start[p + 1]]`, in corner order.
    star_start: Vec<u32>,
    /// Per corner around a position: [corner, position of the next corner of its face,
    /// position of the previous one].
    star: Vec<[u32; 3]>,
    /// Geometric normal per face (counter-clockwise winding), octahedral-encoded
    /// ([`crate::octahedral`]); [`DEGENERATE`] for a face with no area or collapsed by welding.
    pub face_normal: Vec<u32>,
    /// Unique edges of the proper faces, in order of (lowest face, corner).
    pub edges: Vec<Edge>,
    /// Normal group per face, numbered in order of each group's first face.
    pub face_group: Vec<u32>,
    /// Number of groups.
    pub groups: usize,
}

impl Topology {
    /// The welded positions at the ends of `e`, smaller first.
    pub fn ends(&self, e: &Edge) -> [u32; 2] {
        let (a, b) = (
            self.corner_pid[e.corner as usize],
            self.corner_pid[e.end_corner() as usize],
        );
        if a < b { [a, b] } else { [b, a] }
    }

    /// Edges with one face.
    pub fn boundary_edges(&self) -> usize {
        self.edges.iter().filter(|e| e.face_count == 1).count()
    }

    /// Edges with three or more faces.
    pub fn nonmanifold_edges(&self) -> usize {
        self.edges.iter().filter(|e| e.face_count > 2).count()
    }

    /// Whether face `f` is degenerate.
    pub fn is_degenerate(&self, f: u32) -> bool {
        self.face_normal[f as usize] == DEGENERATE
    }

    /// Number of degenerate faces.
    pub fn degenerate_faces(&self) -> usize {
        self.face_normal
            .iter()
            .filter(|&&n| n == DEGENERATE)
            .count()
    }

    /// The faces around welded position `p`, ascending (a face that collapses two corners into
    /// `p` appears twice).
    pub fn faces_at(&self, p: u32) -> impl Iterator<Item = u32> + '_ {
        let p = p as usize;
        self.star[self.star_start[p] as usize..self.star_start[p + 1] as usize]
            .iter()
            .map(|e| e[0] / 3)
    }
}

/// Faces handled by one parallel task.
const CHUNK: usize = 8192;

/// Two corner normals agree: bit-equal, or both non-zero within the angle whose cosine is
/// `cos_tol` (in f64, so tiny tolerances are not lost to rounding).
#[inline]
fn agree(n: Vec3, m: Vec3, cos_tol: f64) -> bool {
    if n == m {
        return true;
    }
    let (n, m) = (n.as_dvec3(), m.as_dvec3());
    let lens = (n.length_squared() * m.length_squared()).sqrt();
    lens > 0.0 && n.dot(m) >= cos_tol * lens
}

/// The normals the grouping rule compares.
#[derive(Debug, Clone, Copy)]
pub enum CornerNormals<'a> {
    /// One per vertex (corners of the same vertex agree without a look).
    Vertex(&'a [Vec3]),
    /// One per corner (index into `indices`).
    Corner(&'a [Vec3]),
}

/// Builds the topology of the triangles `indices` over `positions`.
pub fn build(
    positions: &[Vec3],
    indices: &[u32],
    normals: CornerNormals<'_>,
    opts: &TopologyOptions,
) -> Topology {
    let (position_id, n_pos) = weld_positions(positions, opts.weld_epsilon);
    let nf = indices.len() / 3;
    let corner_pid: Vec<u32> = indices
        .par_iter()
        .with_min_len(CHUNK)
        .map(|&v| position_id[v as usize])
        .collect();
    let pid = |c: usize| corner_pid[c];
    let face_normal: Vec<u32> = (0..nf)
        .into_par_iter()
        .with_min_len(CHUNK)
        .map(|f| {
            let [a, b, c] = [pid(3 * f), pid(3 * f + 1), pid(3 * f + 2)];
            let p = |k: usize| positions[indices[3 * f + k] as usize];
            if a == b || b == c || a == c {
                return DEGENERATE;
            }
            face_normal(p(0), p(1), p(2)).map_or(DEGENERATE, |n| octahedral::encode(n.as_vec3()))
        })
        .collect();
    let degenerate = |f: u32| face_normal[f as usize] == DEGENERATE;

    // Corners around each position (a counting sort by position, so corners ascend in each
    // run), with the positions of their neighbours in their face.
    let mut star_start = vec![0u32; n_pos + 1];
    for &p in &corner_pid {
        star_start[p as usize + 1] += 1;
    }
    for p in 0..n_pos {
        star_start[p + 1] += star_start[p];
    }
    let mut fill = star_start.clone();
    let mut star = vec![[0u32; 3]; corner_pid.len()];
    for (t, tri) in corner_pid.chunks_exact(3).enumerate() {
        for k in 0..3 {
            let slot = &mut fill[tri[k] as usize];
            star[*slot as usize] = [(3 * t + k) as u32, tri[(k + 1) % 3], tri[(k + 2) % 3]];
            *slot += 1;
        }
    }
    drop(fill);
    let star_at =
        |p: u32| &star[star_start[p as usize] as usize..star_start[p as usize + 1] as usize];
    let cos_tol = f64::from(opts.normal_tolerance.clamp(0.0, std::f32::consts::PI)).cos();
    let corners_agree = |c: usize, d: usize| match normals {
        CornerNormals::Vertex(n) => {
            let (v, w) = (indices[c] as usize, indices[d] as usize);
            v == w || agree(n[v], n[w], cos_tol)
        }
        CornerNormals::Corner(n) => agree(n[c], n[d], cos_tol),
    };
    // Two faces given by their corners at the edge's two ends.
    let same_group =
        |x: [usize; 2], y: [usize; 2]| corners_agree(x[0], y[0]) && corners_agree(x[1], y[1]);
    // The corner after / before corner d in its face.
    let next_of = |d: u32| (d - d % 3 + (d + 1) % 3) as usize;
    let prev_of = |d: u32| (d - d % 3 + (d + 2) % 3) as usize;

    // Edges, each emitted by its lowest face; faces joined across them as they are found.
    let sets = AtomicUnionFind::new(nf);
    let parts: Vec<Vec<Edge>> = (0..nf.div_ceil(CHUNK))
        .into_par_iter()
        .map(|task| {
            let mut edges = Vec::with_capacity(CHUNK * 3 / 2 + 16);
            // Faces on the edge, with their corners at its two ends.
            let mut around: Vec<(u32, [usize; 2])> = Vec::new();
            for f in (task * CHUNK..((task + 1) * CHUNK).min(nf)).map(|f| f as u32) {
                if degenerate(f) {
                    continue;
                }
                for k in 0..3 {
                    let c = 3 * f + k;
                    let (a, b) = (pid(c as usize), pid(next_of(c)));
                    around.clear();
                    around.push((f, [c as usize, next_of(c)]));
                    let mut owner = true;
                    for &[d, next, prev] in star_at(a) {
                        let g = d / 3;
                        if g == f || (next != b && prev != b) || degenerate(g) {
                            continue;
                        }
                        if g < f {
                            owner = false;
                            break;
                        }
                        let at_b = if next == b { next_of(d) } else { prev_of(d) };
                        around.push((g, [d as usize, at_b]));
                    }
                    if !owner {
                        continue;
                    }
                    for (i, &(x, cx)) in around.iter().enumerate() {
                        for &(y, cy) in &around[i + 1..] {
                            if same_group(cx, cy) {
                                sets.join(x, y);
                            }
                        }
                    }
                    edges.push(Edge {
                        corner: c,
                        second_face: around.get(1).map_or(NO_FACE, |&(g, _)| g),
                        face_count: around.len() as u32,
                    });
                }
            }
            edges
        })
        .collect();
    let edges = parts.concat();
    // Degenerate faces join proper neighbours across their edges by the same rule.
    for f in (0..nf as u32).filter(|&f| degenerate(f)) {
        for c in 3 * f..3 * f + 3 {
            let (a, b) = (pid(c as usize), pid(next_of(c)));
            if a == b {
                continue;
            }
            for &[d, next, prev] in star_at(a) {
                let g = d / 3;
                if (next != b && prev != b) || degenerate(g) {
                    continue;
                }
                let at_b = if next == b { next_of(d) } else { prev_of(d) };
                if same_group([c as usize, next_of(c)], [d as usize, at_b]) {
                    sets.join(f, g);
                }
            }
        }
    }
    let (face_group, groups) = sets.into_sequential().labels();
    Topology {
        position_id,
        positions: n_pos,
        corner_pid,
        star_start,
        star,
        face_normal,
        edges,
        face_group,
        groups,
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
        let t = build(
            &p,
            &i,
            CornerNormals::Vertex(&n),
            &TopologyOptions::default(),
        );
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
        let t = build(
            &p,
            &i,
            CornerNormals::Vertex(&n),
            &TopologyOptions::default(),
        );
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
        let t = build(
            &p,
            &i,
            CornerNormals::Vertex(&n),
            &TopologyOptions::default(),
        );
        assert_eq!(t.boundary_edges(), (2 * (w + h)) as usize);
        assert_eq!(t.groups, 1);
    }

    #[test]
    fn non_manifold_edges_join_only_the_pairs_that_agree() {
        // Three triangles on edge (0, 1): two share their normals there, the third does not.
        let p = vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(0.5, 1.0, 0.0),
            Vec3::new(0.5, -1.0, 0.0),
            Vec3::new(0.5, 0.0, 1.0),
        ];
        let i = vec![0, 1, 2, 1, 0, 3, 0, 1, 4];
        // Corner normals: faces 0 and 1 flat (+Z), face 2 tilted.
        let n: Vec<Vec3> = (0..9)
            .map(|c| if c < 6 { Vec3::Z } else { Vec3::Y })
            .collect();
        let t = build(
            &p,
            &i,
            CornerNormals::Corner(&n),
            &TopologyOptions::default(),
        );
        assert_eq!(t.nonmanifold_edges(), 1);
        let e = t.edges.iter().find(|e| e.face_count == 3).unwrap();
        assert_eq!((t.ends(e), e.first_face(), e.second_face), ([0, 1], 0, 1));
        assert_eq!(t.face_group, vec![0, 0, 1]);
        assert_eq!(t.boundary_edges(), 6);
    }

    #[test]
    fn degenerate_triangles_make_no_edges_but_join_a_neighbour() {
        // A quad of two triangles, a zero-area sliver on its diagonal, and an isolated collapsed
        // triangle.
        let p = vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::Y,
            Vec3::new(0.5, 0.5, 0.0),
            Vec3::new(5.0, 5.0, 0.0),
            Vec3::new(5.0, 5.0, 0.0),
            Vec3::new(6.0, 5.0, 0.0),
        ];
        let i = vec![0, 1, 2, 0, 2, 3, 0, 4, 2, 5, 6, 7];
        let n = vec![Vec3::Z; p.len()];
        let t = build(
            &p,
            &i,
            CornerNormals::Vertex(&n),
            &TopologyOptions::default(),
        );
        let degenerate: Vec<bool> = (0..4).map(|f| t.is_degenerate(f)).collect();
        assert_eq!(degenerate, vec![false, false, true, true]);
        // Only the quad's 5 edges: the sliver's edges and the collapsed face add nothing.
        assert_eq!(t.edges.len(), 5);
        assert_eq!(t.boundary_edges(), 4);
        assert_eq!(t.nonmanifold_edges(), 0);
        // The sliver lies on the quad's diagonal and joins it; the isolated collapsed triangle
        // is a group of its own.
        assert_eq!(t.face_group, vec![0, 0, 0, 1]);
        assert_eq!(t.groups, 2);
        // A collapsed triangle on an outer edge of the quad joins it too.
        let i2 = [&i[..], &[0, 1, 1]].concat();
        let t2 = build(
            &p,
            &i2,
            CornerNormals::Vertex(&n),
            &TopologyOptions::default(),
        );
        assert_eq!(t2.face_group[4], 0);
        assert_eq!(t2.edges.len(), 5);
    }

    #[test]
    fn tolerance_decides_between_nearly_equal_normals() {
        // Two triangles sharing an edge whose normals differ by 0.05 degrees on one side.
        let p = vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::ZERO,
            Vec3::X,
        ];
        let a = 0.05f32.to_radians();
        let tilted = Vec3::new(0.0, a.sin(), a.cos());
        let n = [Vec3::Z, Vec3::Z, Vec3::Z, Vec3::Z, tilted, Vec3::Z];
        let i = vec![0, 1, 2, 5, 4, 3];
        let opts = |deg: f32| TopologyOptions {
            normal_tolerance: deg.to_radians(),
            ..TopologyOptions::default()
        };
        assert_eq!(
            build(&p, &i, CornerNormals::Vertex(&n), &opts(0.1)).groups,
            1
        );
        assert_eq!(
            build(&p, &i, CornerNormals::Vertex(&n), &opts(0.01)).groups,
            2
        );
        assert_eq!(
            build(&p, &i, CornerNormals::Vertex(&n), &opts(0.0)).groups,
            2
        );
    }

    #[test]
    fn weld_epsilon_closes_a_seam_that_does_not_meet_exactly() {
        // Two triangles whose shared edge is off by 1e-5 on one side.
        let p = vec![
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::new(1.0, 1e-5, 0.0),
            Vec3::new(0.0, 1e-5, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
        ];
        let i = vec![0, 1, 2, 4, 5, 3];
        let n = [Vec3::Z; 6];
        let n = CornerNormals::Vertex(&n);
        let exact = build(&p, &i, n, &TopologyOptions::default());
        assert_eq!((exact.groups, exact.boundary_edges()), (2, 6));
        let welded = build(
            &p,
            &i,
            n,
            &TopologyOptions {
                weld_epsilon: 1e-4,
                ..TopologyOptions::default()
            },
        );
        assert_eq!((welded.groups, welded.boundary_edges()), (1, 4));
        assert_eq!(welded.positions, 4);
    }
}
