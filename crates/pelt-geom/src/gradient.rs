//! A fast tangent frame for meshes whose tangents only carry the comb: per vertex, the sum of
//! the UV gradients (dP/du, Lengyel 2001) of the faces around it. No welding, no neighbour
//! search, no groups, no per-corner arrays and no vertex splits: one pass over the faces.
//!
//! Why it is enough there: the bake expresses each comb in its vertex's frame and writes that
//! frame's tangent, and every reader decodes the comb with the frame it reads (Revie §2.4.1,
//! `frame.rs`), so the object-space comb comes back whatever the frame, as long as it is
//! defined and stored. Only a normal map needs the frame its baker used, which glTF names as
//! MikkTSpace ([`crate::mikktspace`], bit-identical to the reference): the bake uses that where
//! a primitive's material has a normal texture.
//!
//! Mirrored UVs: each face adds its unit `s = dP/du · (UV signed area)` (MikkTSpace's first-order
//! derivative before its sign correction), which points the same way on both sides of a mirror
//! seam, so the halves add up instead of cancelling. w is the sign most faces at the vertex
//! have; the tangent is the sum times w, so on unmirrored faces it is dP/du, as MikkTSpace's.
//!
//! The sum runs in face order on one thread: the result is the same bits at any thread count.

use glam::{Vec2, Vec3, Vec4};

/// Per-vertex tangents and what was met on the way.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GradientTangents {
    /// One per vertex: xyz the (unnormalized, unprojected) gradient sum, w = +1 or -1. Zero
    /// xyz where no face with usable UVs touches the vertex; the frame (`frame::Frame::new`)
    /// projects, normalizes and replaces those by a perpendicular of the normal.
    pub vertices: Vec<Vec4>,
    /// Proper triangles whose UVs have zero area or derivatives (they add nothing).
    pub degenerate_uv_triangles: usize,
}

/// Below this (relative to the UV edge lengths) a face's UV area counts as zero.
const UV_AREA_EPSILON: f32 = 1e-12;

/// The gradient tangents of an indexed triangle list. `indices.len()` must be a multiple of
/// three with every index below `positions.len()` (and `uvs.len()`, when given). Without UVs
/// every tangent is zero (the frame's perpendicular applies).
pub fn generate(positions: &[Vec3], uvs: Option<&[Vec2]>, indices: &[u32]) -> GradientTangents {
    let mut sums = vec![Vec4::ZERO; positions.len()];
    let Some(uvs) = uvs else {
        return finish(sums, 0);
    };
    let mut degenerate_uv = 0;
    for t in indices.chunks_exact(3) {
        let [a, b, c] = [t[0] as usize, t[1] as usize, t[2] as usize];
        let Some(s) = face_gradient(
            [positions[a], positions[b], positions[c]],
            [uvs[a], uvs[b], uvs[c]],
        ) else {
            let (pa, pb, pc) = (positions[a], positions[b], positions[c]);
            if pa != pb && pb != pc && pc != pa {
                degenerate_uv += 1;
            }
            continue;
        };
        for v in [a, b, c] {
            sums[v] += s;
        }
    }
    finish(sums, degenerate_uv)
}

/// The face's unit `s` (xyz) and orientation vote (w = ±1), or None where the triangle or its
/// UVs are degenerate.
#[inline]
fn face_gradient(p: [Vec3; 3], uv: [Vec2; 3]) -> Option<Vec4> {
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
    let area = d1.x * d2.y - d1.y * d2.x;
    let scale = d1.length_squared().max(d2.length_squared());
    // False for NaN too.
    let usable = area.is_finite() && area.abs() > UV_AREA_EPSILON * scale;
    if !usable {
        return None;
    }
    let s = (e1 * d2.y - e2 * d1.y).try_normalize()?;
    Some(s.extend(if area > 0.0 { 1.0 } else { -1.0 }))
}

/// Turns the sums into tangents: w = the majority sign (ties: +1), xyz = sum · w.
fn finish(mut sums: Vec<Vec4>, degenerate_uv_triangles: usize) -> GradientTangents {
    for t in &mut sums {
        let w = if t.w < 0.0 { -1.0 } else { 1.0 };
        *t = (t.truncate() * w).extend(w);
    }
    GradientTangents {
        vertices: sums,
        degenerate_uv_triangles,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit quad in the xy plane with UVs (x, y), optionally mirrored in u on its right half.
    fn strip(mirror: bool) -> (Vec<Vec3>, Vec<Vec2>, Vec<u32>) {
        let xs = [0.0f32, 1.0, 2.0];
        let mut p = Vec::new();
        let mut uv = Vec::new();
        for y in [0.0f32, 1.0] {
            for &x in &xs {
                p.push(Vec3::new(x, y, 0.0));
                let u = if mirror && x > 1.0 { 2.0 - x } else { x };
                uv.push(Vec2::new(u, y));
            }
        }
        let idx = vec![0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4];
        (p, uv, idx)
    }

    #[test]
    fn tangents_follow_u_with_right_handedness() {
        let (p, uv, idx) = strip(false);
        let t = generate(&p, Some(&uv), &idx);
        for v in &t.vertices {
            assert!(v.x > 0.0 && v.y.abs() < 1e-6 && v.z.abs() < 1e-6, "{v}");
            assert_eq!(v.w, 1.0);
        }
        assert_eq!(t.degenerate_uv_triangles, 0);
    }

    #[test]
    fn a_mirror_seam_adds_up_instead_of_cancelling() {
        let (p, uv, idx) = strip(true);
        let t = generate(&p, Some(&uv), &idx);
        // The seam column (x = 1): three faces each, of both kinds; their s agree, so the
        // sum is as long as three unit vectors (it would be one if they cancelled).
        for v in [1usize, 4] {
            let s = t.vertices[v].truncate();
            assert!((s.x.abs() - 3.0).abs() < 1e-5 && s.y.abs() < 1e-6, "{s}");
        }
        // The mirrored side: dP/du points to -x there, with w = -1.
        for v in [2usize, 5] {
            assert!(t.vertices[v].x < 0.0, "{}", t.vertices[v]);
            assert_eq!(t.vertices[v].w, -1.0);
        }
    }

    #[test]
    fn degenerate_uvs_and_missing_uvs_give_zero() {
        let (p, mut uv, idx) = strip(false);
        let none = generate(&p, None, &idx);
        assert!(none.vertices.iter().all(|v| v.truncate() == Vec3::ZERO));
        uv.iter_mut().for_each(|u| *u = Vec2::ZERO);
        let flat = generate(&p, Some(&uv), &idx);
        assert_eq!(flat.degenerate_uv_triangles, 4);
        assert!(flat.vertices.iter().all(|v| v.truncate() == Vec3::ZERO));
    }
}
