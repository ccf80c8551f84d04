//! Smooth normals for meshes that have none: per corner, the angle-weighted average of the
//! face normals around its welded position (Thürmer & Wüthrich's "normal vector computation by
//! angle"), taking only the faces whose normals lie within a crease angle of the corner's own
//! face (so hard edges stay hard; a crease angle of 0 gives flat normals, 180 smooths all).
//!
//! glTF 2.0 (§3.7.2.1) tells clients to shade a primitive without NORMAL flat. The bake uses
//! this instead when asked to grow fur on such a mesh (a generated comb): fur over facets
//! bends at every edge.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

// `face_normals` lives with the other normals; its old path here keeps working.
use crate::normals::DEGENERATE_FALLBACK;
pub use crate::normals::face_normals;
use crate::topology::stars;
use crate::weld::weld_positions;

/// The welded positions of a triangle list and the corners at each.
pub struct Welded {
    /// Welded position of every corner.
    pub corner_pid: Vec<u32>,
    /// Distinct positions.
    pub positions: usize,
    /// `star[star_start[p]..star_start[p + 1]]`: the corners at position `p`, ascending.
    pub star_start: Vec<u32>,
    /// Corners by position.
    pub star: Vec<u32>,
}

impl Welded {
    /// Welds bit-equal positions.
    pub fn new(positions: &[Vec3], indices: &[u32]) -> Welded {
        let (pid, n) = weld_positions(positions, 0.0);
        let corner_pid: Vec<u32> = indices.par_iter().map(|&v| pid[v as usize]).collect();
        let (star_start, star) = stars(&corner_pid, n);
        Welded {
            corner_pid,
            positions: n,
            star_start,
            star,
        }
    }

    /// The corners at position `p`.
    pub fn star(&self, p: u32) -> &[u32] {
        &self.star[self.star_start[p as usize] as usize..self.star_start[p as usize + 1] as usize]
    }
}

/// The angle of the triangle at corner `c` (radians; 0 for a degenerate triangle).
pub fn corner_angle(positions: &[Vec3], indices: &[u32], c: usize) -> f64 {
    let base = c - c % 3;
    let p = |k: usize| positions[indices[base + (c % 3 + k) % 3] as usize].as_dvec3();
    let (a, b) = (p(1) - p(0), p(2) - p(0));
    let (la, lb) = (a.length(), b.length());
    if la > 0.0 && lb > 0.0 && la.is_finite() && lb.is_finite() {
        (a.dot(b) / (la * lb)).clamp(-1.0, 1.0).acos()
    } else {
        0.0
    }
}

/// One unit normal per corner: the angle-weighted average of the normals of the faces at the
/// corner's welded position that lie within `crease` radians of its own face's normal. A
/// degenerate face's corners take the average of every face at their position.
pub fn smooth_corner_normals(positions: &[Vec3], indices: &[u32], crease: f32) -> Vec<Vec3> {
    let welded = Welded::new(positions, indices);
    let faces = face_normals(positions, indices);
    let angle: Vec<f64> = (0..indices.len())
        .into_par_iter()
        .map(|c| corner_angle(positions, indices, c))
        .collect();
    let cos_crease = f64::from(crease.clamp(0.0, std::f32::consts::PI)).cos();
    (0..indices.len())
        .into_par_iter()
        .map(|c| {
            let own = faces[c / 3];
            let mut sum = DVec3::ZERO;
            for &d in welded.star(welded.corner_pid[c]) {
                let Some(n) = faces[d as usize / 3] else {
                    continue;
                };
                // A face's own corner always counts: a crease of 0 (or rounding) keeps it.
                let within = match own {
                    Some(o) => d as usize / 3 == c / 3 || o.dot(n) >= cos_crease - 1e-12,
                    None => true,
                };
                if within {
                    sum += n * angle[d as usize];
                }
            }
            let len = sum.length();
            if len > 0.0 && len.is_finite() {
                (sum / len).as_vec3()
            } else {
                own.map_or(DEGENERATE_FALLBACK, |o| o.as_vec3())
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube's 12 triangles over 8 shared vertices (outward winding).
    fn cube() -> (Vec<Vec3>, Vec<u32>) {
        let p: Vec<Vec3> = (0..8)
            .map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32))
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let idx = quads
            .iter()
            .flat_map(|q| [q[0], q[1], q[2], q[0], q[2], q[3]])
            .collect();
        (p, idx)
    }

    #[test]
    fn crease_angle_keeps_a_cube_flat_and_smooths_it_when_wide() {
        let (p, idx) = cube();
        let flat = smooth_corner_normals(&p, &idx, 60f32.to_radians());
        let faces = face_normals(&p, &idx);
        for (c, n) in flat.iter().enumerate() {
            let f = faces[c / 3].unwrap().as_vec3();
            assert!(n.dot(f) > 1.0 - 1e-6, "corner {c}: {n} against face {f}");
        }
        let smooth = smooth_corner_normals(&p, &idx, std::f32::consts::PI);
        for (c, n) in smooth.iter().enumerate() {
            // At a cube corner the three faces meet at right angles, each with weight pi/2.
            let v = p[idx[c] as usize] - Vec3::splat(0.5);
            let expect = v.normalize();
            assert!((n.length() - 1.0).abs() < 1e-6);
            assert!(
                n.dot(expect) > 1.0 - 1e-6,
                "corner {c}: {n} against {expect}"
            );
        }
    }

    #[test]
    fn angle_weights_make_normals_independent_of_tessellation() {
        // A vertex between a large flat quad split in two and a slanted face: splitting a face
        // into more triangles around the vertex must not pull the normal toward it.
        let p = [
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(-1.0, 0.0, 1.0),
            Vec3::new(0.7, 0.7, 0.0),
        ];
        let one = smooth_corner_normals(&p, &[0, 1, 2, 0, 2, 3], std::f32::consts::PI);
        let two = smooth_corner_normals(&p, &[0, 1, 4, 0, 4, 2, 0, 2, 3], std::f32::consts::PI);
        assert!(
            one[0].dot(two[0]) > 1.0 - 1e-6,
            "{} against {}",
            one[0],
            two[0]
        );
    }
}
