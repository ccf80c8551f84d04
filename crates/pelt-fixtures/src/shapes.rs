//! Parametric painted shapes: a grid of (rings+1)×(segs+1) vertices over (u, v) ∈ \[0, 1\]², with
//! a duplicated seam column (same position, U = 0 and U = 1) as exporters write it. Seam
//! vertices copy their twin's position and normal bit for bit (and so do the pole rows of a
//! sphere), as an exporter splitting a vertex along a UV seam does.

use glam::{Vec2, Vec3};

use crate::{comb_field, paint};

/// A painted triangle mesh in plain arrays.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Shape {
    /// Mesh name.
    pub name: String,
    /// Positions.
    pub positions: Vec<Vec3>,
    /// Unit normals.
    pub normals: Vec<Vec3>,
    /// UVs.
    pub uvs: Vec<Vec2>,
    /// RGBA comb colors (linear floats).
    pub colors: Vec<[f32; 4]>,
    /// Triangle indices.
    pub indices: Vec<u32>,
}

/// Builds a shape from a parametric surface `f(u, v) -> position`, periodic in u (and in v when
/// `closed_v`); normals by central differences (falling back to `fallback(u, v)` where the
/// surface pinches, as at poles).
fn parametric(
    name: &str,
    rings: u32,
    segs: u32,
    closed_v: bool,
    f: impl Fn(f32, f32) -> Vec3,
    fallback: impl Fn(f32, f32) -> Vec3,
) -> Shape {
    let mut s = Shape {
        name: name.to_owned(),
        ..Shape::default()
    };
    let h = 1e-3;
    for r in 0..=rings {
        for k in 0..=segs {
            let (u, v) = (k as f32 / segs as f32, r as f32 / rings as f32);
            // Seam twins are evaluated where their first copy is, so they match exactly.
            let (u, v) = (
                if k == segs { 0.0 } else { u },
                if closed_v && r == rings { 0.0 } else { v },
            );
            let p = f(u, v);
            let du = f(u + h, v) - f(u - h, v);
            let dv = f(u, (v + h).min(1.0)) - f(u, (v - h).max(0.0));
            let n = dv
                .cross(du)
                .try_normalize()
                .unwrap_or_else(|| fallback(u, v).normalize());
            let (d, len) = comb_field(p, n);
            s.positions.push(p);
            s.normals.push(n);
            s.uvs
                .push(Vec2::new(k as f32 / segs as f32, r as f32 / rings as f32));
            s.colors.push(paint(d, len));
        }
    }
    grid_indices(&mut s.indices, 0, rings, segs);
    s
}

/// Two triangles per cell of a `rings` × `segs` grid of (segs + 1)-wide rows starting at
/// vertex `base`.
fn grid_indices(out: &mut Vec<u32>, base: u32, rings: u32, segs: u32) {
    for r in 0..rings {
        for k in 0..segs {
            let a = base + r * (segs + 1) + k;
            let b = a + segs + 1;
            out.extend([a, b, a + 1, a + 1, b, b + 1]);
        }
    }
}

fn spherical(u: f32, v: f32) -> Vec3 {
    let (th, ph) = (v * std::f32::consts::PI, u * std::f32::consts::TAU);
    // Exactly on the axis at the poles (sin(π) in f32 is not 0).
    let s = if v <= 0.0 || v >= 1.0 { 0.0 } else { th.sin() };
    Vec3::new(s * ph.cos(), th.cos(), -s * ph.sin())
}

/// Unit UV sphere (pole rows hold degenerate triangles, as real UV spheres do).
pub fn sphere(rings: u32, segs: u32) -> Shape {
    parametric("sphere", rings, segs, false, spherical, spherical)
}

/// Torus with major radius 1 and minor radius 0.35 (seams in both U and V), its normals and
/// counter-clockwise faces pointing out of the tube (V runs down the outer equator).
pub fn torus(rings: u32, segs: u32) -> Shape {
    let f = |u: f32, v: f32| {
        let (a, b) = (u * std::f32::consts::TAU, v * std::f32::consts::TAU);
        let r = 1.0 + 0.35 * b.cos();
        Vec3::new(r * a.cos(), -0.35 * b.sin(), -r * a.sin())
    };
    parametric("torus", rings, segs, true, f, spherical)
}

/// A torus whose tube has two rings of hard edges (its outer and inner equators): the upper
/// and lower halves are separate vertex grids with normals tilted up and down, so the two
/// rings have the same positions but different normals on each side. Two normal groups.
pub fn hard_torus(rings: u32, segs: u32) -> Shape {
    let tau = std::f32::consts::TAU;
    let f = |u: f32, v: f32| {
        let (a, b) = (u * tau, v * tau);
        let r = 1.0 + 0.35 * b.cos();
        Vec3::new(r * a.cos(), 0.35 * b.sin(), -r * a.sin())
    };
    let mut s = Shape {
        name: "hard-torus".to_owned(),
        ..Shape::default()
    };
    let half = rings / 2;
    for (lo, tilt) in [(0, 0.6f32), (half, -0.6)] {
        let base = s.positions.len() as u32;
        for r in lo..=lo + half {
            for k in 0..=segs {
                // Shared rings and the U seam use the same (u, v), so positions match exactly.
                let u = if k == segs {
                    0.0
                } else {
                    k as f32 / segs as f32
                };
                let v = if r == rings {
                    0.0
                } else {
                    r as f32 / rings as f32
                };
                let p = f(u, v);
                let (a, b) = (u * tau, v * tau);
                let smooth = Vec3::new(b.cos() * a.cos(), b.sin(), -b.cos() * a.sin());
                let n = (smooth + Vec3::Y * tilt).normalize();
                let (d, len) = comb_field(p, n);
                s.positions.push(p);
                s.normals.push(n);
                s.uvs
                    .push(Vec2::new(k as f32 / segs as f32, r as f32 / rings as f32));
                s.colors.push(paint(d, len));
            }
        }
        grid_indices(&mut s.indices, base, half, segs);
    }
    s
}

/// A blobby four-legged creature: an ellipsoid body with a head, four legs and a tail made of
/// smooth radial bumps.
pub fn creature(rings: u32, segs: u32) -> Shape {
    let bumps: [(Vec3, f32, f32); 7] = [
        (Vec3::new(1.0, 0.35, 0.0), 0.55, 0.25),  // head
        (Vec3::new(0.55, -0.8, 0.45), 0.7, 0.12), // legs
        (Vec3::new(0.55, -0.8, -0.45), 0.7, 0.12),
        (Vec3::new(-0.55, -0.8, 0.45), 0.7, 0.12),
        (Vec3::new(-0.55, -0.8, -0.45), 0.7, 0.12),
        (Vec3::new(-1.0, 0.3, 0.0), 0.6, 0.06),  // tail
        (Vec3::new(0.9, 0.75, 0.25), 0.3, 0.05), // ear
    ];
    let f = move |u: f32, v: f32| {
        let d = spherical(u, v);
        let mut r = 1.0;
        for (dir, height, width) in bumps {
            let c = d.dot(dir.normalize());
            r += height * (-(1.0 - c) / width).exp();
        }
        d * r * Vec3::new(1.3, 0.8, 0.7)
    };
    parametric("creature", rings, segs, false, f, spherical)
}
