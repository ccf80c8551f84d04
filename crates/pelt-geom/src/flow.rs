//! A comb for meshes nobody painted: fur that flows along one object-space axis.
//!
//! Revie §2.4.1 stores the comb per vertex in tangent space so that it follows the surface as
//! the mesh deforms; the painted comb is an artist's direction field. For an unpainted mesh
//! this builds one an artist can predict: at every welded position the axis projected on the
//! surface (the tangent plane of the angle-weighted vertex normal), then smoothed over the
//! welded mesh by a few Jacobi steps (each position averages itself and its edge neighbours,
//! weighted by how well each projects, and is projected back on its tangent plane). Where the
//! axis is along the normal the projection vanishes and the neighbours fill it in; where a
//! whole region is singular (a pole facing the axis: any smooth tangent field on a closed
//! surface has such a point) a second axis, perpendicular to the first, is used.

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::normals::face_normals;
use crate::smooth::{Welded, corner_angle};

/// Below this length a projected direction has no usable direction.
const VANISHING: f64 = 1e-6;

/// The comb direction (unit, tangent to the surface) of every vertex of a triangle list:
/// `axis` projected on the surface and smoothed over the welded mesh `steps` times. Vertices
/// no triangle uses get the axis itself.
pub fn comb_flow(positions: &[Vec3], indices: &[u32], axis: Vec3, steps: u32) -> Vec<Vec3> {
    let welded = Welded::new(positions, indices);
    let normal = position_normals(positions, indices, &welded);
    let neighbours = neighbours(indices, &welded);
    let axis = axis.as_dvec3().normalize_or(DVec3::NEG_Z);
    let project = |p: usize, v: DVec3| v - normal[p] * normal[p].dot(v);
    let mut field: Vec<DVec3> = (0..welded.positions)
        .into_par_iter()
        .map(|p| project(p, axis))
        .collect();
    for _ in 0..steps {
        field = (0..welded.positions)
            .into_par_iter()
            .map(|p| {
                let around = &neighbours.1[neighbours.0[p] as usize..neighbours.0[p + 1] as usize];
                let sum = around.iter().fold(field[p], |s, &q| s + field[q as usize]);
                project(p, sum / (around.len() + 1) as f64)
            })
            .collect();
    }
    let second = if axis.x.abs() < 0.9 {
        DVec3::X
    } else {
        DVec3::Y
    };
    let second = (second - axis * axis.dot(second)).normalize();
    let unit: Vec<Vec3> = field
        .par_iter()
        .enumerate()
        .map(|(p, &d)| {
            let d = if d.length() > VANISHING {
                d
            } else {
                project(p, second)
            };
            d.normalize_or(axis).as_vec3()
        })
        .collect();
    let mut out = vec![axis.as_vec3(); positions.len()];
    for (c, &v) in indices.iter().enumerate() {
        out[v as usize] = unit[welded.corner_pid[c] as usize];
    }
    out
}

/// The angle-weighted average normal of every welded position (+Z where no face has area).
fn position_normals(positions: &[Vec3], indices: &[u32], welded: &Welded) -> Vec<DVec3> {
    let faces = face_normals(positions, indices);
    (0..welded.positions as u32)
        .into_par_iter()
        .map(|p| {
            let sum = welded.star(p).iter().fold(DVec3::ZERO, |s, &c| {
                let c = c as usize;
                faces[c / 3].map_or(s, |n| s + n * corner_angle(positions, indices, c))
            });
            sum.normalize_or(DVec3::Z)
        })
        .collect()
}

/// The distinct edge neighbours of every welded position, as (start per position, list).
fn neighbours(indices: &[u32], welded: &Welded) -> (Vec<u32>, Vec<u32>) {
    let lists: Vec<Vec<u32>> = (0..welded.positions as u32)
        .into_par_iter()
        .map(|p| {
            let mut around: Vec<u32> = welded
                .star(p)
                .iter()
                .flat_map(|&c| {
                    let base = c as usize - c as usize % 3;
                    (0..3).map(move |k| base + k)
                })
                .map(|d| welded.corner_pid[d])
                .filter(|&q| q != p)
                .collect();
            around.sort_unstable();
            around.dedup();
            around
        })
        .collect();
    let mut start = Vec::with_capacity(lists.len() + 1);
    let mut at = 0u32;
    for l in &lists {
        start.push(at);
        at += l.len() as u32;
    }
    start.push(at);
    debug_assert_eq!(indices.len() % 3, 0);
    (start, lists.concat())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A UV sphere (poles on ±Y), `rings` × `segs`, with a seam of duplicated vertices.
    fn sphere(rings: u32, segs: u32) -> (Vec<Vec3>, Vec<u32>) {
        let mut p = Vec::new();
        for r in 0..=rings {
            let th = std::f32::consts::PI * r as f32 / rings as f32;
            for s in 0..=segs {
                let ph = std::f32::consts::TAU * (s % segs) as f32 / segs as f32;
                p.push(Vec3::new(
                    th.sin() * ph.cos(),
                    th.cos(),
                    th.sin() * ph.sin(),
                ));
            }
        }
        let mut idx = Vec::new();
        let w = segs + 1;
        for r in 0..rings {
            for s in 0..segs {
                let (a, b) = (r * w + s, (r + 1) * w + s);
                idx.extend([a, a + 1, b, a + 1, b + 1, b]);
            }
        }
        (p, idx)
    }

    /// The angle-weighted normal of every vertex (the smooth normal with no crease).
    fn vertex_normals(p: &[Vec3], idx: &[u32]) -> Vec<Vec3> {
        let corners = crate::smooth::smooth_corner_normals(p, idx, std::f32::consts::PI);
        let mut n = vec![Vec3::ZERO; p.len()];
        for (c, &v) in idx.iter().enumerate() {
            n[v as usize] = corners[c];
        }
        n
    }

    #[test]
    fn flow_is_tangent_unit_and_follows_the_axis() {
        let (p, idx) = sphere(16, 32);
        let axis = Vec3::NEG_Z;
        let d = comb_flow(&p, &idx, axis, 4);
        let n = vertex_normals(&p, &idx);
        for (v, (&dir, &pos)) in d.iter().zip(&p).enumerate() {
            let n = n[v];
            assert!((dir.length() - 1.0).abs() < 1e-5, "vertex {v}: {dir}");
            assert!(
                dir.dot(n).abs() < 1e-5,
                "vertex {v}: {dir} not tangent to {n}"
            );
            // Away from the poles of the axis (±Z), the comb points along it.
            if n.z.abs() < 0.8 {
                assert!(dir.dot(axis) > 0.5, "vertex {v} at {pos}: {dir}");
            }
        }
        // Seam vertices (bit-equal positions) get one direction.
        let w = 33;
        for r in 0..=16usize {
            assert_eq!(d[r * w], d[r * w + 32], "ring {r}");
        }
    }

    #[test]
    fn the_pole_facing_the_axis_is_filled_from_its_neighbours() {
        // Axis along +Y: the poles have no projection; they must still get a unit tangent.
        let (p, idx) = sphere(8, 16);
        let d = comb_flow(&p, &idx, Vec3::Y, 2);
        let n = vertex_normals(&p, &idx);
        for (v, &dir) in d.iter().enumerate() {
            assert!((dir.length() - 1.0).abs() < 1e-5, "vertex {v}: {dir}");
            assert!(
                dir.dot(n[v]).abs() < 1e-5,
                "vertex {v}: {dir} not tangent to {}",
                n[v]
            );
        }
        // The pole itself (vertex 0) points along the second axis, projected.
        assert!(d[0].dot(Vec3::X).abs() > 0.99, "{}", d[0]);
    }
}
