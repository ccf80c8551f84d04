//! The camera of a scene and what the CPU decides from it before any pass runs: view and
//! projection matrices (right-handed view space, camera looking down −Z, as Kircher &
//! Lawrance's eq. 1 assumes), each light's screen-space scissor rectangle (Kircher & Lawrance
//! §2.2: a light is drawn only over the pixels its sphere can reach), and screen rectangles of
//! object bounds for assigning alpha stipple patterns (§4).

use glam::{Mat4, Vec3, Vec4Swizzles};

use crate::scene::{Camera, Scene, Size};

/// Matrices and frustum numbers for one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// World to view.
    pub view: Mat4,
    /// View to clip (depth 0..1).
    pub proj: Mat4,
    /// tan of half the horizontal and vertical fields of view.
    pub tan_half: [f32; 2],
    /// Near and far plane distances.
    pub near: f32,
    /// Far plane distance.
    pub far: f32,
}

impl View {
    /// The scene's camera at the output's aspect ratio.
    pub fn new(scene: &Scene) -> View {
        View::of(&scene.camera, scene.output)
    }

    /// `camera` at the aspect ratio of `output`.
    pub fn of(camera: &Camera, output: Size) -> View {
        let c = camera;
        let aspect = output.width as f32 / output.height as f32;
        let fov = c.fov_y_deg.to_radians();
        let view = Mat4::look_at_rh(c.position.into(), c.target.into(), c.up.into());
        let proj = Mat4::perspective_rh(fov, aspect, c.near, c.far);
        let ty = (fov / 2.0).tan();
        View {
            view,
            proj,
            tan_half: [ty * aspect, ty],
            near: c.near,
            far: c.far,
        }
    }

    /// Pixel rectangle `[x0, y0, x1, y1)` of a target `size` covering the view-space box
    /// `[lo, hi]`, or None when the box is entirely behind the near plane, beyond the far
    /// plane or off screen. A box crossing the near plane covers the whole target.
    pub fn screen_rect(&self, lo: Vec3, hi: Vec3, size: (u32, u32)) -> Option<[u32; 4]> {
        if hi.z > -self.near && lo.z > -self.near || hi.z < -self.far {
            return None;
        }
        let (w, h) = (size.0 as f32, size.1 as f32);
        let [x0, y0, x1, y1] = if hi.z > -self.near {
            [0.0, 0.0, w, h]
        } else {
            let (mut nx0, mut ny0, mut nx1, mut ny1) = (f32::MAX, f32::MAX, f32::MIN, f32::MIN);
            for p in box_corners(lo, hi) {
                let nx = p.x / (-p.z * self.tan_half[0]);
                let ny = p.y / (-p.z * self.tan_half[1]);
                (nx0, ny0, nx1, ny1) = (nx0.min(nx), ny0.min(ny), nx1.max(nx), ny1.max(ny));
            }
            [
                ((nx0 * 0.5 + 0.5) * w).floor(),
                ((0.5 - ny1 * 0.5) * h).floor(),
                ((nx1 * 0.5 + 0.5) * w).ceil(),
                ((0.5 - ny0 * 0.5) * h).ceil(),
            ]
        };
        let r = [
            x0.clamp(0.0, w),
            y0.clamp(0.0, h),
            x1.clamp(0.0, w),
            y1.clamp(0.0, h),
        ]
        .map(|v| v as u32);
        (r[2] > r[0] && r[3] > r[1]).then_some(r)
    }

    /// The scissor rectangle of a point light (world position, radius) on a target of `size`.
    pub fn light_rect(&self, position: Vec3, radius: f32, size: (u32, u32)) -> Option<[u32; 4]> {
        let c = (self.view * position.extend(1.0)).xyz();
        self.screen_rect(c - Vec3::splat(radius), c + Vec3::splat(radius), size)
    }

    /// View-space axis-aligned box of a world-space box under `model`.
    pub fn view_box(&self, model: Mat4, lo: Vec3, hi: Vec3) -> (Vec3, Vec3) {
        let m = self.view * model;
        box_corners(lo, hi)
            .into_iter()
            .map(|p| m.transform_point3(p))
            .fold((Vec3::MAX, Vec3::MIN), |(a, b), q| (a.min(q), b.max(q)))
    }

    /// Whether the eye, or any point of its near plane's rectangle, may lie within the
    /// asset-space box [lo, hi] placed by `model` (conservative: the box is widened by the
    /// near rectangle's reach, measured in the model's smallest axis scale).
    pub fn holds_eye(&self, model: Mat4, lo: Vec3, hi: Vec3) -> bool {
        let m = self.view * model;
        if m.determinant().abs() < f32::MIN_POSITIVE {
            return false;
        }
        let eye = m.inverse().transform_point3(Vec3::ZERO);
        let smallest = [m.x_axis, m.y_axis, m.z_axis]
            .iter()
            .map(|a| a.truncate().length())
            .fold(f32::INFINITY, f32::min);
        let reach = self.near * (1.0 + self.tan_half[0] + self.tan_half[1]) / smallest;
        eye.cmpge(lo - reach).all() && eye.cmple(hi + reach).all()
    }
}

/// The eight corners of the box [lo, hi].
fn box_corners(lo: Vec3, hi: Vec3) -> [Vec3; 8] {
    std::array::from_fn(|k| {
        Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// Stipple patterns (1..=3) for alpha objects given as (screen rectangle, view depth), in the
/// same order. Objects are taken nearest first; each takes the lowest pattern that no
/// overlapping object already holds (Kircher & Lawrance §4 assign them "dynamically based on
/// the depth of the objects"). Returns the patterns and how many objects found all three
/// taken (they share one with an overlapping object, so where both cover a pixel only the
/// nearer one's lighting samples survive).
pub fn assign_stipple(objects: &[(Option<[u32; 4]>, f32)]) -> (Vec<u32>, usize) {
    let mut order: Vec<usize> = (0..objects.len()).collect();
    order.sort_by(|&a, &b| objects[a].1.total_cmp(&objects[b].1).then(a.cmp(&b)));
    let overlap =
        |a: [u32; 4], b: [u32; 4]| a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3];
    let mut pattern = vec![0u32; objects.len()];
    let mut crowded = 0;
    for (k, &i) in order.iter().enumerate() {
        let mut taken = [false; 4];
        if let Some(ri) = objects[i].0 {
            for &j in &order[..k] {
                if objects[j].0.is_some_and(|rj| overlap(ri, rj)) {
                    taken[pattern[j] as usize] = true;
                }
            }
        }
        pattern[i] = match (1..=3).find(|&p| !taken[p as usize]) {
            Some(p) => p,
            None => {
                crowded += 1;
                // Share with the farthest layer: the one that matters least.
                3
            }
        };
    }
    (pattern, crowded)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn view() -> View {
        let scene = Scene::default();
        View::new(&scene)
    }

    #[test]
    fn the_eye_is_held_by_a_box_it_or_its_near_plane_lies_in() {
        let v = view();
        let eye = v.view.inverse().transform_point3(Vec3::ZERO);
        let unit = (Vec3::splat(-1.0), Vec3::splat(1.0));
        let at =
            |p: Vec3, scale: f32| Mat4::from_translation(p) * Mat4::from_scale(Vec3::splat(scale));
        assert!(v.holds_eye(at(eye, 1.0), unit.0, unit.1));
        assert!(v.holds_eye(at(eye + Vec3::X * 1.5, 2.0), unit.0, unit.1));
        // Just past the box, within the near plane's reach: held; well past it: not.
        let near = v.near * (1.0 + v.tan_half[0] + v.tan_half[1]);
        assert!(v.holds_eye(at(eye + Vec3::X * (1.0 + 0.5 * near), 1.0), unit.0, unit.1));
        assert!(!v.holds_eye(at(eye + Vec3::X * (1.0 + 2.0 * near), 1.0), unit.0, unit.1));
        assert!(!v.holds_eye(at(eye + Vec3::Y * 3.0, 1.0), unit.0, unit.1));
        // A collapsed box holds nothing.
        assert!(!v.holds_eye(at(eye, 0.0), unit.0, unit.1));
    }

    #[test]
    fn light_rects_hold_every_lit_pixel_and_cull_what_cannot_show() {
        let v = view();
        let size = (320, 180);
        let inv = v.view.inverse();
        // Sample points on spheres in front of the camera: each projects inside its rectangle.
        for (k, (c, r)) in [
            (Vec3::new(0.0, 0.0, -3.0), 0.5),
            (Vec3::new(1.0, 0.4, -2.0), 0.8),
            (Vec3::new(-2.5, -1.0, -5.0), 1.5),
        ]
        .into_iter()
        .enumerate()
        {
            let world = inv.transform_point3(c);
            let rect = v.light_rect(world, r, size).expect("visible");
            for i in 0..200 {
                let a = i as f32 * 2.399;
                let z = 1.0 - 2.0 * (i as f32 + 0.5) / 200.0;
                let s = (1.0 - z * z).sqrt();
                let p = c + r * Vec3::new(s * a.cos(), s * a.sin(), z);
                let clip = v.proj * p.extend(1.0);
                let ndc = clip.xyz() / clip.w;
                let px = (ndc.x * 0.5 + 0.5) * size.0 as f32;
                let py = (0.5 - ndc.y * 0.5) * size.1 as f32;
                if (0.0..size.0 as f32).contains(&px) && (0.0..size.1 as f32).contains(&py) {
                    assert!(
                        px >= rect[0] as f32
                            && px <= rect[2] as f32
                            && py >= rect[1] as f32
                            && py <= rect[3] as f32,
                        "sphere {k}: ({px}, {py}) outside {rect:?}"
                    );
                }
            }
            // And the rectangle is not the whole screen for a small far light.
            if k == 0 {
                assert!((rect[2] - rect[0]) < size.0 / 2, "{rect:?}");
            }
        }
        // Behind the camera, off to the side, or beyond far: culled.
        assert_eq!(
            v.light_rect(inv.transform_point3(Vec3::new(0.0, 0.0, 2.0)), 1.0, size),
            None
        );
        assert_eq!(
            v.light_rect(inv.transform_point3(Vec3::new(50.0, 0.0, -3.0)), 1.0, size),
            None
        );
        assert_eq!(
            v.light_rect(inv.transform_point3(Vec3::new(0.0, 0.0, -500.0)), 1.0, size),
            None
        );
        // Around the eye: the whole screen.
        assert_eq!(
            v.light_rect(inv.transform_point3(Vec3::ZERO), 1.0, size),
            Some([0, 0, 320, 180])
        );
    }

    #[test]
    fn stipple_patterns_differ_where_alpha_objects_overlap() {
        let r = |x: u32| Some([x, 0, x + 10, 10]);
        // Three overlapping: three patterns, nearest gets 1.
        let (p, crowded) = assign_stipple(&[(r(0), 3.0), (r(5), 1.0), (r(2), 2.0)]);
        assert_eq!((p, crowded), (vec![3, 1, 2], 0));
        // Disjoint objects reuse pattern 1.
        let (p, _) = assign_stipple(&[(r(0), 1.0), (r(100), 2.0), (r(200), 3.0)]);
        assert_eq!(p, vec![1, 1, 1]);
        // A fourth overlapping layer has none left.
        let (p, crowded) = assign_stipple(&[(r(0), 1.0), (r(1), 2.0), (r(2), 3.0), (r(3), 4.0)]);
        assert_eq!((p, crowded), (vec![1, 2, 3, 3], 1));
    }
}
