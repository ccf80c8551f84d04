//! Per-corner unit normals for the bake.
//!
//! glTF 2.0 (§3.7.2.1): "When normals are not specified, client implementations MUST calculate
//! flat normals". pelt does so, and also repairs what files get wrong: a zero normal takes the
//! flat normal of the face using it, a non-unit normal is renormalized. All arithmetic is in f64
//! with the edge vectors scaled to unit size first, so coordinates from 1e-20 to 1e20, and
//! subnormal ones, give the same direction as coordinates near 1.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

/// A normal whose length is off by more than this is counted as non-unit.
pub const UNIT_TOLERANCE: f64 = 1e-3;

/// The normal a degenerate face gets when no vertex of it touches a proper face.
pub const DEGENERATE_FALLBACK: Vec3 = Vec3::Z;

/// What happened while computing normals, for the report.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NormalStats {
    /// The source had no NORMAL: every corner got its face's flat normal.
    pub generated_flat: bool,
    /// Vertices whose normal was zero (or too short to normalize) and was replaced by flat normals.
    pub zero_replaced: usize,
    /// Vertices whose normal length was off by more than [`UNIT_TOLERANCE`] and was renormalized.
    pub renormalized: usize,
    /// Triangles with zero area (coincident or collinear corners).
    pub degenerate_triangles: usize,
}

impl NormalStats {
    /// True when the normals pelt uses differ from those stored, so NORMAL must be written.
    pub fn rewrites_normals(&self) -> bool {
        self.generated_flat || self.zero_replaced > 0 || self.renormalized > 0
    }
}

/// Unit normal of a triangle in f64, or `None` when it has no area. From f32 inputs nothing in
/// f64 can overflow or underflow (differences stay below 2^129, and the smallest non-zero f32
/// difference, 2^-149, raised to the fourth power is still far above f64's smallest normal),
/// so no scaling is needed for any coordinates, subnormal ones included.
pub fn face_normal(p0: Vec3, p1: Vec3, p2: Vec3) -> Option<DVec3> {
    let a = p1.as_dvec3() - p0.as_dvec3();
    let b = p2.as_dvec3() - p0.as_dvec3();
    let c = a.cross(b);
    let len_sq = c.length_squared();
    (len_sq > 0.0 && len_sq.is_finite()).then(|| c / len_sq.sqrt())
}

/// Unit normal (f64) of every face, `None` where it has no area.
pub fn face_normals(positions: &[Vec3], indices: &[u32]) -> Vec<Option<DVec3>> {
    indices
        .par_chunks_exact(3)
        .map(|t| {
            face_normal(
                positions[t[0] as usize],
                positions[t[1] as usize],
                positions[t[2] as usize],
            )
        })
        .collect()
}

/// Unit length in f64, or `None` when the vector is too short to have a direction.
pub fn normalize_f64(v: Vec3) -> Option<DVec3> {
    let d = v.as_dvec3();
    let scale = d.abs().max_element();
    if !(scale > 0.0 && scale.is_finite()) {
        return None;
    }
    let s = d / scale;
    let len = s.length();
    (len > 0.0).then(|| s / len)
}

/// One unit normal per triangle corner (`indices.len()` of them), with what was repaired.
pub fn corner_normals(
    positions: &[Vec3],
    normals: Option<&[Vec3]>,
    indices: &[u32],
) -> (Vec<Vec3>, NormalStats) {
    let mut stats = NormalStats {
        generated_flat: normals.is_none(),
        ..NormalStats::default()
    };
    let faces: Vec<Option<DVec3>> = face_normals(positions, indices);
    stats.degenerate_triangles = faces.iter().filter(|f| f.is_none()).count();

    // Per vertex: its normalized stored normal, or None when it needs a flat one.
    let stored: Option<Vec<Option<Vec3>>> = normals.map(|ns| {
        ns.iter()
            .map(|&n| match normalize_f64(n) {
                Some(u) => {
                    if (n.as_dvec3().length() - 1.0).abs() > UNIT_TOLERANCE {
                        stats.renormalized += 1;
                    }
                    Some(u.as_vec3())
                }
                None => {
                    stats.zero_replaced += 1;
                    None
                }
            })
            .collect()
    });

    // A degenerate face borrows, per vertex, the flat normal of the first proper face using it.
    let mut vertex_face = vec![None::<Vec3>; positions.len()];
    for (tri, f) in indices.chunks_exact(3).zip(&faces) {
        if let Some(f) = f {
            for &v in tri {
                vertex_face[v as usize].get_or_insert(f.as_vec3());
            }
        }
    }

    let mut out = Vec::with_capacity(indices.len());
    for (tri, f) in indices.chunks_exact(3).zip(&faces) {
        for &v in tri {
            let v = v as usize;
            let kept = stored.as_ref().and_then(|s| s[v]);
            out.push(kept.unwrap_or_else(|| match f {
                Some(f) => f.as_vec3(),
                None => vertex_face[v].unwrap_or(DEGENERATE_FALLBACK),
            }));
        }
    }
    (out, stats)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_normals_follow_winding() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let (n, s) = corner_normals(&p, None, &[0, 1, 2]);
        assert!(s.generated_flat);
        assert!(n.iter().all(|&n| n == Vec3::Z));
        let (n, _) = corner_normals(&p, None, &[0, 2, 1]);
        assert!(n.iter().all(|&n| n == -Vec3::Z));
    }

    #[test]
    fn extreme_scales_give_the_same_normal() {
        for s in [1e-20_f32, 1e-40, 1e20, 3e38] {
            let n = face_normal(Vec3::ZERO, Vec3::X * s, Vec3::new(0.0, s, 0.0)).unwrap();
            assert!((n - DVec3::Z).length() < 1e-12, "scale {s}: {n}");
        }
    }

    #[test]
    fn zero_and_long_normals_are_repaired_and_counted() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let ns = [Vec3::ZERO, Vec3::Z * 3.0, Vec3::Z];
        let (n, s) = corner_normals(&p, Some(&ns), &[0, 1, 2]);
        assert_eq!((s.zero_replaced, s.renormalized), (1, 1));
        assert!(s.rewrites_normals());
        assert!(n.iter().all(|&n| (n - Vec3::Z).length() < 1e-7));
    }

    #[test]
    fn degenerate_face_borrows_a_neighbour_normal() {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::X * 2.0];
        // Face 1 is collinear (0, 1, 3 on the x axis).
        let (n, s) = corner_normals(&p, None, &[0, 1, 2, 0, 1, 3]);
        assert_eq!(s.degenerate_triangles, 1);
        assert_eq!(n[3], Vec3::Z);
        assert_eq!(n[5], DEGENERATE_FALLBACK);
    }
}
