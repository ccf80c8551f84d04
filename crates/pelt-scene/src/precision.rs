//! Depth precision said aloud: a camera whose far plane is so many times its near plane that
//! the depth buffer (32-bit float, standard depth) cannot separate surfaces a percent of the
//! far distance apart, and fur whose shells lie closer together than the depth buffer (or the
//! L-buffer's depth codes) can tell apart where the fur is, which z-fights into blotches.
//! Both are planning notes, naming the camera or the object, with the figures.

use glam::{Mat4, Vec3};

use crate::scene::Camera;

/// The spacing of depth values just below 1.0 in a 32-bit float (2⁻²⁴).
const DEPTH_ULP: f64 = 1.0 / 16_777_216.0;

/// The L-buffer's depth codes between the near and far planes (common.wgsl's DEPTH_STEPS).
const DEPTH_CODES: f64 = 65_534.0;

/// The spacing of 32-bit floats relative to their size (2⁻²³).
const POSITION_ULP: f64 = 1.0 / 8_388_608.0;

/// Shells closer together than this many float steps of the positions are named.
const POSITION_ULPS: f64 = 8.0;

/// A depth range whose resolution at the far plane is coarser than this share of its
/// distance is named.
pub const FAR_SHARE: f64 = 0.01;

/// The smallest distance the depth buffer separates at view depth `z` (standard depth,
/// d = f / (f − n) · (1 − n / z), so Δz = ulp · z² · (f − n) / (f · n)).
pub fn depth_resolution(camera: &Camera, z: f64) -> f64 {
    let (n, f) = (f64::from(camera.near), f64::from(camera.far));
    DEPTH_ULP * z * z * (f - n) / (f * n)
}

/// The camera's depth range, when it is too deep for its far plane.
pub fn range_note(camera: &Camera) -> Option<String> {
    let far = f64::from(camera.far);
    let at_far = depth_resolution(camera, far);
    (at_far > FAR_SHARE * far).then(|| {
        format!(
            "camera: near {} and far {} ({:.1e}:1): the depth buffer cannot separate surfaces \
             closer than {at_far:.3e} apart at the far plane ({:.0} % of its distance), so \
             surfaces there z-fight; raise near or lower far",
            camera.near,
            camera.far,
            far / f64::from(camera.near),
            100.0 * at_far / far
        )
    })
}

/// Object `o`'s fur, when its shells lie closer together than the depth buffer resolves
/// where it is (they z-fight into blotches), and object `o`, when the L-buffer's depth codes
/// are coarser than the object itself (inferred lighting cannot tell its near side from its
/// far side, and blurs its light across its edges). `bounds` are its asset-space bounds.
///
/// The codes are not held against the shells' spacing: measured on a 1 m furry sphere with
/// 4 cm fur, shells 2.5 mm apart, at 1.6 m with near 0.05, a far plane of 20 km (codes 0.3 m
/// apart) draws within FLIP 0.0063 of a far plane of 20 m; 2000 km (codes 30 m apart, past the
/// sphere's size) 0.096.
pub fn fur_note(camera: &Camera, o: &NotedObject, bounds: (Vec3, Vec3)) -> Option<String> {
    let (n, f) = (f64::from(camera.near), f64::from(camera.far));
    let (near, far) = (camera.near, camera.far);
    let (center, radius) = world_sphere(o.model, bounds);
    let eye = Vec3::from(camera.position);
    let nearest = (f64::from(eye.distance(center)) - f64::from(radius)).max(n);
    let codes = (f - n) / DEPTH_CODES;
    if let Some((fur_reach, shells)) = o.fur {
        let reach = f64::from(fur_reach * largest_scale(o.model));
        let spacing = reach / f64::from(shells.max(1));
        let buffer = depth_resolution(camera, nearest);
        // The f32 spacing of world positions as large as the object's or the eye's.
        let extent = (center.length() + radius).max(eye.length());
        let positions = f64::from(extent) * POSITION_ULP;
        if reach > 0.0 && spacing < POSITION_ULPS * positions {
            return Some(format!(
                "objects[{}]: its fur ({reach:.3e} long, {} shells {spacing:.3e} apart) is \
                 finer than 32-bit float positions resolve {extent:.3e} from the origin \
                 ({positions:.3e}), so its shells collapse into streaks; move the scene's \
                 origin near the fur, or draw it at a scale where the fur is coarser",
                o.scene_index, shells
            ));
        }
        if reach > 0.0 && spacing < buffer {
            return Some(format!(
                "objects[{}]: its fur ({reach:.3e} long, {} shells {spacing:.3e} apart) is \
                 finer than the depth buffer resolves where it is ({buffer:.3e} at \
                 {nearest:.3e} from the camera, near {near} and far {far}), so its shells may \
                 z-fight into blotches; bring near and far closer to the fur",
                o.scene_index, shells
            ));
        }
    }
    (codes > 2.0 * f64::from(radius)).then(|| {
        format!(
            "objects[{}]: the L-buffer's depth codes over near {near} to far {far} lie {codes:.3e} \
             apart, more than the object's size ({:.3e}), so inferred and deferred lighting \
             may blur its light across its edges; bring near and far closer to it",
            o.scene_index,
            2.0 * radius
        )
    })
}

/// What [`fur_note`] weighs of one planned object.
#[derive(Debug, Clone, Copy)]
pub struct NotedObject {
    /// Its index in the scene file.
    pub scene_index: usize,
    /// Asset to world.
    pub model: Mat4,
    /// Its fur's reach (asset units) and shell count, when it has fur.
    pub fur: Option<(f32, u32)>,
}

/// The largest axis scale of `m`.
fn largest_scale(m: Mat4) -> f32 {
    [m.x_axis, m.y_axis, m.z_axis]
        .iter()
        .map(|a| a.truncate().length())
        .fold(0.0, f32::max)
}

/// A sphere around asset-space box `bounds` once `m` places it.
fn world_sphere(m: Mat4, (lo, hi): (Vec3, Vec3)) -> (Vec3, f32) {
    let center = m.transform_point3((lo + hi) / 2.0);
    (center, (hi - lo).length() / 2.0 * largest_scale(m))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(near: f32, far: f32) -> Camera {
        Camera {
            near,
            far,
            ..Camera::default()
        }
    }

    #[test]
    fn a_deep_range_is_named_and_the_default_is_not() {
        assert_eq!(range_note(&Camera::default()), None);
        assert_eq!(range_note(&camera(0.01, 1000.0)), None);
        let note = range_note(&camera(1e-7, 1e7)).expect("1e14:1 is named");
        assert!(
            note.starts_with("camera: near 0.0000001 and far 10000000 (1.0e14:1)"),
            "{note}"
        );
    }

    #[test]
    fn the_resolution_grows_with_the_square_of_the_depth() {
        let c = camera(0.1, 100.0);
        let r1 = depth_resolution(&c, 1.0);
        assert!((depth_resolution(&c, 10.0) / r1 - 100.0).abs() < 1e-9);
        // 2⁻²⁴ · 1 · 99.9 / 10 at 1 m: about 6e-7.
        let want = DEPTH_ULP * 99.9 / 10.0;
        assert!((r1 / want - 1.0).abs() < 1e-6, "{r1} against {want}");
    }
}
