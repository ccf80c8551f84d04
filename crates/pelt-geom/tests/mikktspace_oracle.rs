//! pelt's MikkTSpace against `bevy_mikktspace` (a faithful port of the reference C code) as the
//! oracle: the tangents must match bit for bit on manifold meshes, including UV seams, mirrored
//! UVs, degenerate triangles, zero-area UVs and w = -1 frames.

use glam::{Vec2, Vec3};
use pelt_geom::mikktspace;
use proptest::prelude::*;

struct Oracle<'a> {
    p: &'a [Vec3],
    n: &'a [Vec3],
    t: &'a [Vec2],
    i: &'a [u32],
    out: Vec<[f32; 4]>,
}

impl bevy_mikktspace::Geometry for Oracle<'_> {
    fn num_faces(&self) -> usize {
        self.i.len() / 3
    }
    fn num_vertices_of_face(&self, _: usize) -> usize {
        3
    }
    fn position(&self, f: usize, v: usize) -> [f32; 3] {
        self.p[self.i[f * 3 + v] as usize].to_array()
    }
    fn normal(&self, f: usize, v: usize) -> [f32; 3] {
        self.n[self.i[f * 3 + v] as usize].to_array()
    }
    fn tex_coord(&self, f: usize, v: usize) -> [f32; 2] {
        self.t[self.i[f * 3 + v] as usize].to_array()
    }
    fn set_tangent(&mut self, ts: Option<bevy_mikktspace::TangentSpace>, f: usize, v: usize) {
        self.out[f * 3 + v] = ts.unwrap_or_default().tangent_encoded();
    }
}

fn oracle(p: &[Vec3], n: &[Vec3], t: &[Vec2], i: &[u32]) -> Vec<[f32; 4]> {
    let mut o = Oracle {
        p,
        n,
        t,
        i,
        out: vec![[0.0; 4]; i.len()],
    };
    bevy_mikktspace::generate_tangents(&mut o).expect("oracle never fails");
    o.out
}

fn assert_matches(p: &[Vec3], n: &[Vec3], t: &[Vec2], i: &[u32]) -> mikktspace::Tangents {
    let ours = mikktspace::generate(p, n, t, i);
    let theirs = oracle(p, n, t, i);
    for (c, (a, b)) in ours.corners.iter().zip(&theirs).enumerate() {
        assert_eq!(
            a.to_array().map(f32::to_bits),
            b.map(f32::to_bits),
            "corner {c}: pelt {a:?}, oracle {b:?}"
        );
    }
    assert_eq!(ours.corners.len(), theirs.len());
    ours
}

/// A UV sphere with a seam column (duplicated positions, different UVs) and pole fans.
fn uv_sphere(rings: u32, segs: u32) -> (Vec<Vec3>, Vec<Vec3>, Vec<Vec2>, Vec<u32>) {
    let (mut p, mut t, mut i) = (vec![], vec![], vec![]);
    for r in 0..=rings {
        for s in 0..=segs {
            let (v, u) = (r as f32 / rings as f32, s as f32 / segs as f32);
            let (th, ph) = (v * std::f32::consts::PI, u * std::f32::consts::TAU);
            p.push(Vec3::new(
                th.sin() * ph.cos(),
                th.cos(),
                th.sin() * ph.sin(),
            ));
            t.push(Vec2::new(u, v));
        }
    }
    for r in 0..rings {
        for s in 0..segs {
            let a = r * (segs + 1) + s;
            let b = a + segs + 1;
            i.extend([a, a + 1, b, a + 1, b + 1, b]);
        }
    }
    let n = p.iter().map(|p| p.normalize()).collect();
    (p, n, t, i)
}

/// A bumpy grid; the left half has mirrored U (orientation-reversing UVs).
fn mirrored_grid(w: u32, h: u32, jitter: &[f32]) -> (Vec<Vec3>, Vec<Vec3>, Vec<Vec2>, Vec<u32>) {
    let (mut p, mut n, mut t, mut i) = (vec![], vec![], vec![], vec![]);
    let half = w / 2;
    for y in 0..=h {
        // Seam: two vertex columns at x = half, one per UV side.
        for x in 0..=w + 1 {
            let gx = if x > half { x - 1 } else { x };
            let k = (y * (w + 2) + x) as usize;
            let z = jitter.get(k % jitter.len().max(1)).copied().unwrap_or(0.0);
            p.push(Vec3::new(gx as f32, y as f32, z));
            n.push(Vec3::new(-z * 0.3, 0.2, 1.0).normalize());
            let u = gx as f32 / w as f32;
            let u = if x <= half { 1.0 - u } else { u };
            t.push(Vec2::new(u, y as f32 / h as f32));
        }
    }
    for y in 0..h {
        for x in 0..=w {
            if x == half {
                continue;
            }
            let a = y * (w + 2) + x;
            let b = a + w + 2;
            i.extend([a, a + 1, b, a + 1, b + 1, b]);
        }
    }
    (p, n, t, i)
}

#[test]
fn sphere_with_seam_and_poles_matches() {
    let (p, n, t, i) = uv_sphere(12, 24);
    let out = assert_matches(&p, &n, &t, &i);
    // The pole rows have coincident corners.
    assert!(out.stats.degenerate_triangles > 0);
}

#[test]
fn mirrored_uvs_match_and_carry_both_signs() {
    let (p, n, t, i) = mirrored_grid(8, 5, &[0.0, 0.1, -0.2, 0.05, 0.3]);
    let out = assert_matches(&p, &n, &t, &i);
    let signs: std::collections::BTreeSet<i32> = out.corners.iter().map(|c| c[3] as i32).collect();
    assert_eq!(signs, [-1, 1].into_iter().collect());
    assert!(out.corners.iter().all(|c| c[3] == 1.0 || c[3] == -1.0));
}

#[test]
fn degenerate_uvs_and_triangles_match() {
    let (p, n, mut t, mut i) = mirrored_grid(6, 4, &[0.0]);
    // Collapse the UVs of a few vertices (zero-area UV triangles) and add a sliver triangle.
    for v in [3usize, 4, 12, 13] {
        t[v] = t[2];
    }
    i.extend([0, 0, 1]);
    i.extend([5, 6, 5]);
    let out = assert_matches(&p, &n, &t, &i);
    assert!(out.stats.degenerate_uv_triangles > 0);
    assert_eq!(out.stats.degenerate_triangles, 2);
}

#[test]
fn isolated_bad_triangle_gets_the_reference_default() {
    let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let n = [Vec3::Z; 3];
    let t = [Vec2::ZERO; 3];
    let out = assert_matches(&p, &n, &t, &[0, 1, 2]);
    assert_eq!(out.stats.default_corners, 3);
    assert_eq!(out.corners[0].to_array(), [1.0, 0.0, 0.0, -1.0]);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn random_bumpy_grids_match(
        w in 2u32..9, h in 1u32..6,
        jitter in prop::collection::vec(-1.0f32..1.0, 1..40),
        uv_noise in prop::collection::vec(-0.3f32..0.3, 1..40),
        collapse in prop::collection::vec(0usize..200, 0..4),
    ) {
        let (p, n, mut t, i) = mirrored_grid(w, h, &jitter);
        for (k, uv) in t.iter_mut().enumerate() {
            uv.y += uv_noise[k % uv_noise.len()];
        }
        for c in collapse {
            let v = c % t.len();
            t[v] = t[0];
        }
        assert_matches(&p, &n, &t, &i);
    }
}

#[test]
fn large_mesh_matches_across_parallel_blocks_and_ordered_vertices() {
    // 20 000+ welded vertices: many parallel blocks of vertices, a mirrored seam, and a few
    // faces without usable UVs scattered over it (their vertices take the ordered walk).
    let jitter: Vec<f32> = (0..97)
        .map(|k| ((k * 37 % 23) as f32 - 11.0) * 0.05)
        .collect();
    let (p, n, mut t, i) = mirrored_grid(160, 130, &jitter);
    for v in (500..t.len()).step_by(1777) {
        t[v + 1] = t[v];
        t[v + 162] = t[v];
    }
    let out = assert_matches(&p, &n, &t, &i);
    assert!(p.len() > 20_000);
    assert!(out.stats.degenerate_uv_triangles > 0);
}
