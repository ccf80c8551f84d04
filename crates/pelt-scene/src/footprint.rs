//! How fine a pixel can get on a fur object: the CPU half of the shells' choice between the
//! statistical medium and the strand-resolving heightfield taps (shells.wgsl,
//! `layer_alpha`). A shell fragment reads single strands only where its pixel's footprint
//! is under 0.75 mean strand diameters (tile widths); the resolving code costs every shell
//! fragment on drivers that run both sides of a branch (llvmpipe runs a fragment shader's
//! lanes in lockstep under masks), so the renderer compiles it only into the pipeline of
//! objects that may show such a pixel. This module bounds, per object and camera, the
//! smallest footprint any of its pixels can have, from the sparsest texel density of its mesh.

use crate::asset::MeshData;
use crate::view::View;
use glam::{Mat3, Mat4, Vec2, Vec3};

/// The shells resolve single strands where a pixel is under this many strand diameters
/// (the upper end of the shader's `smoothstep(0.5 d, RESOLVED_BELOW d, footprint)`; the
/// renderer sets shells.wgsl's override of that name from this constant).
pub const RESOLVED_BELOW: f32 = 0.75;

/// Headroom of the bound: a skinned pose squeezes triangles, shells over concave skin are
/// smaller than the skin, and a screen-space derivative is a finite difference. An object
/// is given the resolving pipeline when its finest pixel is under `SAFETY × RESOLVED_BELOW`
/// diameters.
pub const SAFETY: f32 = 2.0;

/// The sparsest texel density of `mesh`'s fur: the smallest √(UV area / surface area) over
/// its furred triangles (TEXCOORD_0 units per asset unit), where the heightfield is
/// stretched most and a pixel spans the least of a tile; infinite without fur. Triangles
/// without surface area or without UV area are skipped (they cover no pixel, or map the
/// whole triangle to one texel). One stretched triangle is enough to give the object the
/// resolving pipeline when it is near: that costs time, never accuracy.
pub fn texel_density(mesh: &MeshData) -> f32 {
    let Some(fur) = &mesh.fur else {
        return f32::INFINITY;
    };
    let mut finest = f32::INFINITY;
    for t in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| i as usize);
        let (Some(fa), Some(fb), Some(fc)) = (
            fur.vertices.get(a),
            fur.vertices.get(b),
            fur.vertices.get(c),
        ) else {
            continue;
        };
        if fa.comb[3] <= 0.0 && fb.comb[3] <= 0.0 && fc.comb[3] <= 0.0 {
            continue;
        }
        let p = |i: usize| Vec3::from(mesh.vertices[i].position);
        let uv = [fa.uv, fb.uv, fc.uv].map(Vec2::from);
        if let Some(d) = triangle_density([p(a), p(b), p(c)], uv) {
            finest = finest.min(d);
        }
    }
    finest
}

/// √(UV area / surface area) of one triangle, `None` when it has no surface area.
pub fn triangle_density(p: [Vec3; 3], uv: [Vec2; 3]) -> Option<f32> {
    let area = (p[1] - p[0]).cross(p[2] - p[0]).length();
    let uv_area = (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]).abs();
    (area > 0.0 && area.is_finite() && uv_area > 0.0 && uv_area.is_finite())
        .then(|| (uv_area / area).sqrt())
}

/// The largest factor by which `model` stretches a length: σ_max of its linear part,
/// bounded above by the largest row sum of |MᵀM| (exact for rotations times scales).
pub fn max_stretch(model: Mat4) -> f32 {
    let m = Mat3::from_mat4(model);
    let g = m.transpose() * m;
    let rows = [g.row(0), g.row(1), g.row(2)];
    rows.iter()
        .map(|r| r.abs().element_sum())
        .fold(0.0f32, f32::max)
        .sqrt()
}

/// The smallest footprint, in heightfield tile widths, that any pixel of an object can have:
/// the nearest view depth `near_depth` of its (fur-inflated) bounds, one pixel's angle at
/// `output`'s height, shrunk to the narrowest footprint off the axis (a pixel at angle α
/// covers z·θ·√cos α across the ray), through `model`'s largest stretch, the mesh's sparsest
/// `texel_density` and the fur's `uv_scale`.
pub fn finest_footprint(
    view: &View,
    output: (u32, u32),
    model: Mat4,
    near_depth: f32,
    texel_density: f32,
    uv_scale: f32,
) -> f32 {
    let z = near_depth.max(view.near);
    let pixel = 2.0 * view.tan_half[1] / output.1.max(1) as f32;
    let [tx, ty] = view.tan_half;
    let cos_corner = 1.0 / (1.0 + tx * tx + ty * ty).sqrt();
    let stretch = max_stretch(model).max(f32::MIN_POSITIVE);
    z * pixel * cos_corner.sqrt() / stretch * texel_density * uv_scale.abs()
}

/// The longest the fur can project to on screen, in output pixels: `reach` (its length in
/// the asset's units) through `model`'s largest stretch, at the nearest view depth
/// `near_depth` of the object's fur-inflated bounds (the near plane where the eye is inside
/// them), at `output`'s height. What the shells-by-screen-size rule reads
/// (`pelt_fur::shells`; integrations/three computes the same from its bounding sphere).
pub fn fur_pixels(
    view: &View,
    output: (u32, u32),
    model: Mat4,
    near_depth: f32,
    reach: f32,
) -> f32 {
    let z = near_depth.max(view.near);
    let focal = output.1.max(1) as f32 / (2.0 * view.tan_half[1]);
    reach * max_stretch(model) * focal / z
}

/// Whether an object whose finest footprint is `footprint` (tile widths), with strands of
/// mean diameter `diameter` (tile widths), may show a pixel that resolves single strands.
pub fn resolves_strands(footprint: f32, diameter: f32) -> bool {
    diameter > 0.0 && footprint.is_finite() && footprint < SAFETY * RESOLVED_BELOW * diameter
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Camera, Size};

    #[test]
    fn max_stretch_of_a_rotated_uniform_scale_is_the_scale() {
        let m = Mat4::from_scale_rotation_translation(
            Vec3::splat(2.5),
            glam::Quat::from_rotation_y(0.7) * glam::Quat::from_rotation_x(0.3),
            Vec3::new(1.0, 2.0, 3.0),
        );
        assert!((max_stretch(m) - 2.5).abs() < 1e-4, "{}", max_stretch(m));
        let s = Mat4::from_scale(Vec3::new(1.0, 4.0, 2.0));
        assert!((max_stretch(s) - 4.0).abs() < 1e-5);
    }

    #[test]
    fn a_nearer_camera_or_a_larger_output_makes_the_footprint_finer() {
        let camera = Camera::default();
        let view = View::of(
            &camera,
            Size {
                width: 320,
                height: 180,
            },
        );
        let at =
            |z: f32, h: u32| finest_footprint(&view, (h * 16 / 9, h), Mat4::IDENTITY, z, 1.0, 8.0);
        assert!(at(1.0, 180) < at(2.0, 180));
        assert!(at(1.0, 720) < at(1.0, 180));
        // Four times the rows, a quarter of the footprint.
        assert!((at(1.0, 180) / at(1.0, 720) - 4.0).abs() < 1e-4);
        // Behind the near plane (the camera inside the bounds): the near plane's footprint.
        assert_eq!(at(-3.0, 180), at(view.near, 180));
        assert!(resolves_strands(at(view.near, 180), 0.006));
        assert!(!resolves_strands(at(1e4, 180), 0.006));
        assert!(
            !resolves_strands(0.0, 0.0),
            "no strands, nothing to resolve"
        );
    }

    /// The bound against the truth: every on-screen triangle of a textured sphere, under
    /// cameras near and far, on and off the axis, with scaled and rotated models, has a
    /// pixel footprint (√(its tile area / its screen area in pixels)) no finer than
    /// `finest_footprint` says any pixel of the object can have.
    #[test]
    fn no_triangle_on_screen_is_finer_than_the_bound() {
        let mesh = crate::asset::builtin("sphere").expect("sphere");
        let tri = |t: &[u32]| {
            let v = t.iter().map(|&i| &mesh.vertices[i as usize]);
            // The sphere's own grid (49 vertices a ring, the seam's twice): no wrap, a
            // density that grows towards the poles.
            let (p, uv): (Vec<Vec3>, Vec<Vec2>) = t
                .iter()
                .zip(v)
                .map(|(&i, v)| {
                    let (ring, seg) = (i / 49, i % 49);
                    (
                        Vec3::from(v.position),
                        Vec2::new(seg as f32 / 48.0, ring as f32 / 24.0),
                    )
                })
                .unzip();
            ([p[0], p[1], p[2]], [uv[0], uv[1], uv[2]])
        };
        let density = mesh
            .indices
            .chunks_exact(3)
            .filter_map(|t| {
                let (p, uv) = tri(t);
                triangle_density(p, uv)
            })
            .fold(f32::INFINITY, f32::min);
        assert!(
            density.is_finite() && density > 0.0,
            "the sphere is textured"
        );
        let (lo, hi) = mesh.bounds();
        let output = (320u32, 180u32);
        let uv_scale = 6.0;
        let mut checked = 0;
        let mut tightest = f32::INFINITY;
        for (k, eye) in [
            [0.0, 0.0, 1.6],
            [0.3, 1.2, 1.1],
            [4.0, 1.0, 6.0],
            [-1.9, -0.4, 0.6],
        ]
        .into_iter()
        .enumerate()
        {
            for fov in [20.0, 60.0, 110.0] {
                let camera = Camera {
                    position: eye,
                    target: [0.4 * k as f32 - 0.5, 0.1, 0.0],
                    fov_y_deg: fov,
                    near: 0.05,
                    ..Camera::default()
                };
                let view = View::of(
                    &camera,
                    Size {
                        width: output.0,
                        height: output.1,
                    },
                );
                let model = Mat4::from_scale_rotation_translation(
                    Vec3::new(0.8, 1.1, 0.9),
                    glam::Quat::from_rotation_z(0.4 * k as f32),
                    Vec3::ZERO,
                );
                let (_, vhi) = view.view_box(model, lo, hi);
                let bound = finest_footprint(&view, output, model, -vhi.z, density, uv_scale);
                let clip = view.proj * view.view * model;
                for t in mesh.indices.chunks_exact(3) {
                    let (p, uv) = tri(t);
                    let c = p.map(|q| clip * q.extend(1.0));
                    if c.iter().any(|c| c.w < camera.near) {
                        continue;
                    }
                    let s = c.map(|c| {
                        Vec2::new(
                            (c.x / c.w * 0.5 + 0.5) * output.0 as f32,
                            (c.y / c.w * 0.5 + 0.5) * output.1 as f32,
                        )
                    });
                    let on_screen = s.iter().any(|s| {
                        (0.0..output.0 as f32).contains(&s.x)
                            && (0.0..output.1 as f32).contains(&s.y)
                    });
                    let pixels = 0.5 * (s[1] - s[0]).perp_dot(s[2] - s[0]).abs();
                    let tiles =
                        0.5 * (uv[1] - uv[0]).perp_dot(uv[2] - uv[0]).abs() * uv_scale * uv_scale;
                    if !on_screen || pixels < 1e-3 || tiles <= 0.0 {
                        continue;
                    }
                    let footprint = (tiles / pixels).sqrt();
                    tightest = tightest.min(footprint / bound);
                    checked += 1;
                    assert!(
                        footprint >= bound,
                        "camera {k}, fov {fov}: a triangle at {footprint} tile widths a pixel, under the bound {bound}"
                    );
                }
            }
        }
        eprintln!("{checked} triangles; the tightest is {tightest:.3}× the bound");
        assert!(checked > 1000, "{checked}");
        // A bound far below every pixel would send every object to the costly pipeline.
        assert!(tightest < 2.0, "the bound is loose: {tightest}");
    }
}
