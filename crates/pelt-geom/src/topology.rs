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
//! Edges are found per welded position, in parallel: the faces around position `a` name every
//! edge from `a`, and each edge is emitted once, at its lower end, with the faces around it in
//! ascending order. So the edge list is in order of (lower end, higher end) and does not depend
//! on the thread count. Each face's sides are looked at twice (once per end), not once per
//! corner of every face around a position.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use rayon::prelude::*;

use crate::normals::face_normal;
use crate::union_find::AtomicUnionFind;
use crate::weld::weld_positions;

/// "No corner": the second corner of a boundary edge.
pub const NO_CORNER: u32 = u32::MAX;

/// The corner after `c` in its face.
#[inline]
pub fn next_corner(c: u32) -> u32 {
    c - c % 3 + (c + 1) % 3
}

/// The corner before `c` in its face.
#[inline]
pub fn prev_corner(c: u32) -> u32 {
    c - c % 3 + (c + 2) % 3
}

/// One unique welded edge, as the corners where it starts in the windings of its two lowest
/// faces. A corner `c` is element `c` of the index list: its face is `c / 3`, and the face's
/// edge from `c` runs to [`next_corner`]`(c)`. This is also the fin record a bake stores
/// (`docs/format.md`, format version 2), so the fins are this list, not a copy of it.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Pod, Zeroable)]
pub struct Edge {
    /// Where the edge starts in its lowest face's winding.
    pub corner: u32,
    /// Where it starts in the second-lowest face's winding ([`NO_CORNER`] on a boundary).
    /// On a consistently wound surface this face runs the edge the other way.
    pub second_corner: u32,
}

impl Edge {
    /// The lowest face using the edge.
    pub fn first_face(&self) -> u32 {
        self.corner / 3
    }

    /// The second-lowest face using the edge (None on a boundary).
    pub fn second_face(&self) -> Option<u32> {
        (self.second_corner != NO_CORNER).then_some(self.second_corner / 3)
    }

    /// The corner after `corner` in its face (where the edge ends).
    pub fn end_corner(&self) -> u32 {
        next_corner(self.corner)
    }

    /// Whether the edge has one face.
    pub fn is_boundary(&self) -> bool {
        self.second_corner == NO_CORNER
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
    /// `star[star_start[p]..star_start[p + 1]]`, ascending.
    star_start: Vec<u32>,
    /// Corners grouped by welded position (see `star_start`).
    star: Vec<u32>,
    /// Per face: no area, or two corners welded into one position.
    degenerate: Vec<bool>,
    /// Unique edges of the proper faces, in order of their ends' welded positions (lower,
    /// then higher).
    pub edges: Vec<Edge>,
    /// Edges with three or more faces.
    nonmanifold: usize,
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
        self.edges.iter().filter(|e| e.is_boundary()).count()
    }

    /// Edges with three or more faces (counted as they were found).
    pub fn nonmanifold_edges(&self) -> usize {
        self.nonmanifold
    }

    /// Whether face `f` is degenerate.
    pub fn is_degenerate(&self, f: u32) -> bool {
        self.degenerate[f as usize]
    }

    /// Number of degenerate faces.
    pub fn degenerate_faces(&self) -> usize {
        self.degenerate.iter().filter(|&&d| d).count()
    }

    /// The faces around welded position `p`, ascending (a face that collapses two corners into
    /// `p` appears twice).
    pub fn faces_at(&self, p: u32) -> impl Iterator<Item = u32> + '_ {
        let p = p as usize;
        self.star[self.star_start[p] as usize..self.star_start[p + 1] as usize]
            .iter()
            .map(|c| c / 3)
    }

    /// Takes the edge list out (for the fins, which are the same records), leaving it empty.
    pub fn take_edges(&mut self) -> Vec<Edge> {
        std::mem::take(&mut self.edges)
    }
}

/// Faces (or welded positions) handled by one parallel task.
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

/// The corners of each welded position, ascending: a counting sort of the corners by
/// position, in parallel over ranges of positions. Each task scans every corner (a cheap,
/// sequential read) but counts and places only those in its range, so it writes one
/// contiguous part of the output, and corners ascend within each position.
/// Returns (`star_start`, `star`).
pub(crate) fn stars(corner_pid: &[u32], n_pos: usize) -> (Vec<u32>, Vec<u32>) {
    let tasks = rayon::current_num_threads().clamp(1, 8);
    let span = n_pos.div_ceil(tasks).max(1);
    // count[p]: corners at p.
    let mut count = vec![0u32; n_pos];
    count.par_chunks_mut(span).enumerate().for_each(|(t, c)| {
        let lo = t * span;
        for &p in corner_pid {
            if let Some(n) = c.get_mut((p as usize).wrapping_sub(lo)) {
                *n += 1;
            }
        }
    });
    let mut star_start = Vec::with_capacity(n_pos + 1);
    let mut at = 0u32;
    for &n in &count {
        star_start.push(at);
        at += n;
    }
    star_start.push(at);
    drop(count);
    // Each task's part of the star, and its positions' next free slots (relative to it).
    let mut star = vec![0u32; corner_pid.len()];
    let mut parts = Vec::with_capacity(tasks);
    let mut rest = star.as_mut_slice();
    for t in 0..n_pos.div_ceil(span) {
        let (lo, hi) = (t * span, ((t + 1) * span).min(n_pos));
        let (part, tail) = rest.split_at_mut((star_start[hi] - star_start[lo]) as usize);
        parts.push((lo, part));
        rest = tail;
    }
    parts.into_par_iter().for_each(|(lo, part)| {
        let hi = (lo + span).min(n_pos);
        let base = star_start[lo];
        let mut next: Vec<u32> = star_start[lo..hi].iter().map(|&s| s - base).collect();
        for (c, &p) in corner_pid.iter().enumerate() {
            if let Some(slot) = next.get_mut((p as usize).wrapping_sub(lo)) {
                part[*slot as usize] = c as u32;
                *slot += 1;
            }
        }
    });
    (star_start, star)
}

/// One proper face's side of an edge from welded position `a` to a higher one `b`.
#[derive(Clone, Copy)]
struct Side {
    /// The other end's welded position.
    b: u32,
    /// The face.
    face: u32,
    /// Where the edge starts in the face's winding.
    start: u32,
    /// The face's corners at `a` and at `b`.
    ends: [u32; 2],
}

/// The sides of every edge from `a` to a higher position, by the faces around `a` (`star`,
/// ascending), sorted by the other end and then by face.
fn sides_at(
    a: u32,
    star: &[u32],
    pid: &impl Fn(u32) -> u32,
    is_degenerate: &impl Fn(u32) -> bool,
    out: &mut Vec<Side>,
) {
    out.clear();
    for &d in star {
        let face = d / 3;
        if is_degenerate(face) {
            continue;
        }
        let (next, prev) = (next_corner(d), prev_corner(d));
        // The face runs a to pid(next) from d, and pid(prev) to a from prev.
        for (at_b, start) in [(next, d), (prev, prev)] {
            let b = pid(at_b);
            if b > a {
                out.push(Side {
                    b,
                    face,
                    start,
                    ends: [d, at_b],
                });
            }
        }
    }
    // Faces already ascend (the star does); a stable sort by the other end keeps that.
    out.sort_by_key(|s| s.b);
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
        .with_min_len(crate::task_len(indices.len(), CHUNK))
        .map(|&v| position_id[v as usize])
        .collect();
    let degenerate = degenerate_faces(positions, indices, &corner_pid);
    let (star_start, star) = stars(&corner_pid, n_pos);
    let faces = Faces {
        indices,
        corner_pid: &corner_pid,
        star_start: &star_start,
        star: &star,
        degenerate: &degenerate,
        normals,
        cos_tol: f64::from(opts.normal_tolerance.clamp(0.0, std::f32::consts::PI)).cos(),
    };
    let sets = AtomicUnionFind::new(nf);
    let (edges, nonmanifold) = faces.edges(&sets, n_pos);
    faces.join_degenerate(&sets);
    let (face_group, groups) = sets.into_sequential().labels();
    Topology {
        position_id,
        positions: n_pos,
        corner_pid,
        star_start,
        star,
        degenerate,
        edges,
        nonmanifold,
        face_group,
        groups,
    }
}

/// Which faces are degenerate: two corners at one welded position, or no area.
fn degenerate_faces(positions: &[Vec3], indices: &[u32], corner_pid: &[u32]) -> Vec<bool> {
    let nf = indices.len() / 3;
    (0..nf)
        .into_par_iter()
        .with_min_len(crate::task_len(nf, CHUNK))
        .map(|f| {
            let [a, b, c] = [0, 1, 2].map(|k| corner_pid[3 * f + k]);
            let p = |k: usize| positions[indices[3 * f + k] as usize];
            a == b || b == c || a == c || face_normal(p(0), p(1), p(2)).is_none()
        })
        .collect()
}

/// The faces as the grouping rule sees them: welded corners, the stars of the welded
/// positions, which faces are degenerate, and the normals compared.
struct Faces<'a> {
    indices: &'a [u32],
    corner_pid: &'a [u32],
    star_start: &'a [u32],
    star: &'a [u32],
    degenerate: &'a [bool],
    normals: CornerNormals<'a>,
    /// The cosine of the normal tolerance.
    cos_tol: f64,
}

impl Faces<'_> {
    /// Corner `c`'s welded position.
    fn pid(&self, c: u32) -> u32 {
        self.corner_pid[c as usize]
    }

    /// The corners at welded position `p`.
    fn star_at(&self, p: u32) -> &[u32] {
        &self.star[self.star_start[p as usize] as usize..self.star_start[p as usize + 1] as usize]
    }

    /// Whether face `f` is degenerate.
    fn is_degenerate(&self, f: u32) -> bool {
        self.degenerate[f as usize]
    }

    /// Whether corners `c` and `d` have normals within the tolerance.
    fn corners_agree(&self, c: u32, d: u32) -> bool {
        match self.normals {
            CornerNormals::Vertex(n) => {
                let (v, w) = (
                    self.indices[c as usize] as usize,
                    self.indices[d as usize] as usize,
                );
                v == w || agree(n[v], n[w], self.cos_tol)
            }
            CornerNormals::Corner(n) => agree(n[c as usize], n[d as usize], self.cos_tol),
        }
    }

    /// Whether two faces, given by their corners at the edge's two ends, are one group.
    fn same_group(&self, x: [u32; 2], y: [u32; 2]) -> bool {
        self.corners_agree(x[0], y[0]) && self.corners_agree(x[1], y[1])
    }

    /// Face g's corner d sits at one end of the edge (a, b); its corner at b, if g uses the
    /// edge (and is proper).
    fn other_end(&self, d: u32, b: u32) -> Option<u32> {
        let (next, prev) = (next_corner(d), prev_corner(d));
        if self.pid(next) == b {
            Some(next)
        } else if self.pid(prev) == b {
            Some(prev)
        } else {
            None
        }
    }

    /// The edges step: every edge, each found at its lower welded position, with the count of
    /// non-manifold ones; the proper faces on each are joined in `sets` as the rule says.
    fn edges(&self, sets: &AtomicUnionFind, n_pos: usize) -> (Vec<Edge>, usize) {
        let chunk = crate::task_len(n_pos, CHUNK);
        let pid = |c: u32| self.pid(c);
        let is_degenerate = |f: u32| self.is_degenerate(f);
        let parts: Vec<(Vec<Edge>, usize)> = (0..n_pos.div_ceil(chunk))
            .into_par_iter()
            .map(|task| {
                let mut edges = Vec::with_capacity(chunk * 3 + 16);
                let mut nonmanifold = 0;
                let mut around: Vec<Side> = Vec::new();
                for a in (task * chunk..((task + 1) * chunk).min(n_pos)).map(|a| a as u32) {
                    sides_at(a, self.star_at(a), &pid, &is_degenerate, &mut around);
                    for run in around.chunk_by(|x, y| x.b == y.b) {
                        for (i, x) in run.iter().enumerate() {
                            for y in &run[i + 1..] {
                                if self.same_group(x.ends, y.ends) {
                                    sets.join(x.face, y.face);
                                }
                            }
                        }
                        nonmanifold += usize::from(run.len() > 2);
                        edges.push(Edge {
                            corner: run[0].start,
                            second_corner: run.get(1).map_or(NO_CORNER, |s| s.start),
                        });
                    }
                }
                (edges, nonmanifold)
            })
            .collect();
        let nonmanifold = parts.iter().map(|p| p.1).sum();
        (
            concat(parts.into_iter().map(|p| p.0).collect()),
            nonmanifold,
        )
    }

    /// Degenerate faces join proper neighbours across their edges by the same rule, in
    /// parallel like the edges (joins are atomic; the labels do not depend on their order).
    /// The faces on an edge (a, b) are in the stars of both ends: the smaller one is searched.
    /// Degenerate faces gather at high-valence positions (a UV sphere's poles), whose stars
    /// are long: searching from the pole made this step quadratic in the valence.
    fn join_degenerate(&self, sets: &AtomicUnionFind) {
        let nf = self.degenerate.len();
        let degenerate_faces = (0..nf as u32)
            .into_par_iter()
            .with_min_len(crate::task_len(nf, CHUNK))
            .filter(|&f| self.is_degenerate(f));
        degenerate_faces.for_each(|f| {
            for c in 3 * f..3 * f + 3 {
                let (a, b) = (self.pid(c), self.pid(next_corner(c)));
                if a == b {
                    continue;
                }
                let from_a = self.star_at(a).len() <= self.star_at(b).len();
                let (near, far) = if from_a { (a, b) } else { (b, a) };
                for &d in self.star_at(near) {
                    let g = d / 3;
                    if self.is_degenerate(g) {
                        continue;
                    }
                    let Some(e) = self.other_end(d, far) else {
                        continue;
                    };
                    let (at_a, at_b) = if from_a { (d, e) } else { (e, d) };
                    if self.same_group([c, next_corner(c)], [at_a, at_b]) {
                        sets.join(f, g);
                    }
                }
            }
        });
    }
}

/// The parts' edges in order, in one exact allocation filled in parallel.
fn concat(parts: Vec<Vec<Edge>>) -> Vec<Edge> {
    let total = parts.iter().map(Vec::len).sum();
    let mut out = bytemuck::zeroed_vec::<Edge>(total);
    let mut slots = Vec::with_capacity(parts.len());
    let mut rest = out.as_mut_slice();
    for p in &parts {
        let (slot, tail) = rest.split_at_mut(p.len());
        slots.push(slot);
        rest = tail;
    }
    parts
        .par_iter()
        .zip(slots)
        .for_each(|(p, slot)| slot.copy_from_slice(p));
    out
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
        let e = t.edges.iter().find(|e| t.ends(e) == [0, 1]).unwrap();
        // The two lowest faces: face 0 runs 0 to 1 from its corner 0; face 1 runs 1 to 0 from
        // its corner 3.
        assert_eq!(
            (e.first_face(), e.second_face(), e.corner, e.second_corner),
            (0, Some(1), 0, 3)
        );
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
    fn a_sliver_at_a_pole_joins_by_the_same_rule_searched_from_either_end() {
        // A fan of 8 triangles around a pole P, and a zero-area sliver (P, R, M) on the fan's
        // edge P-R, M halfway along it. R's star (3 corners) is smaller than P's (9), so the
        // sliver's edge is searched from R: the sliver's corners must still be paired with
        // the fan face's corners at the same ends (P with P, R with R).
        let ring = |k: usize| {
            let a = k as f32 * std::f32::consts::TAU / 8.0;
            Vec3::new(a.cos(), a.sin(), 0.0)
        };
        let mut p: Vec<Vec3> = (0..8).map(ring).collect();
        p.push(Vec3::ZERO); // 8: P
        p.push(ring(0)); // 9: the sliver's own vertex at R
        p.push(ring(0) * 0.5); // 10: M
        let mut i: Vec<u32> = (0..8u32).flat_map(|k| [8, k, (k + 1) % 8]).collect();
        i.extend([8, 9, 10]);
        // P's normal and the ring's differ, so pairing P with R would not agree.
        let mut n = vec![Vec3::X; p.len()];
        n[8] = Vec3::Z;
        let groups = |n: &[Vec3]| {
            let t = build(
                &p,
                &i,
                CornerNormals::Vertex(n),
                &TopologyOptions::default(),
            );
            assert!(t.is_degenerate(8) && !t.is_degenerate(0));
            (t.face_group[8] == t.face_group[0], t.groups)
        };
        assert_eq!(groups(&n), (true, 1));
        // The sliver's vertex at R turned away: no longer the same group.
        n[9] = -Vec3::X;
        assert_eq!(groups(&n), (false, 2));
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
