//! Procedural scenes for tests and benchmarks: grids of objects, N seeded random point
//! lights, and the inferred-lighting paper's two experiments rebuilt as scenes (Kircher &
//! Lawrance, §6: 101 objects with 81 omni lights at 1280×720; 122 lights with an 800×450
//! L-buffer against a full-resolution one).

use std::path::Path;

use glam::Vec3;
use pelt_fur::rng::SplitMix64;

use crate::scene::{Camera, FurSettings, Light, Material, Object, Scene, Size, Sky, Transform};

/// `count` copies of `asset` on a square grid in the XZ plane (row-major from −X −Z),
/// `spacing` apart, centred on the origin.
pub fn grid(asset: &Path, count: usize, spacing: f32, material: Material) -> Vec<Object> {
    let side = (count as f64).sqrt().ceil().max(1.0) as usize;
    let half = (side as f32 - 1.0) * spacing / 2.0;
    (0..count)
        .map(|i| Object {
            asset: asset.to_owned(),
            transform: Transform {
                translation: [
                    (i % side) as f32 * spacing - half,
                    0.0,
                    (i / side) as f32 * spacing - half,
                ],
                ..Transform::default()
            },
            material,
            color: [1.0; 3],
        })
        .collect()
}

/// `count` point lights uniformly in the box [lo, hi], radii uniform in `radius`, colours with
/// each component uniform in [0.3, 1]. Light i depends only on the seed and i.
pub fn random_lights(
    count: usize,
    seed: u64,
    lo: Vec3,
    hi: Vec3,
    radius: (f32, f32),
    intensity: f32,
) -> Vec<Light> {
    (0..count)
        .map(|i| {
            let mut s = SplitMix64::stream(seed, i as u64);
            let mut u = || s.unit() as f32;
            let position = lo + (hi - lo) * Vec3::new(u(), u(), u());
            let color = [0.3 + 0.7 * u(), 0.3 + 0.7 * u(), 0.3 + 0.7 * u()];
            Light::point(
                position.to_array(),
                radius.0 + (radius.1 - radius.0) * u(),
                intensity,
            )
            .with_color(color)
        })
        .collect()
}

/// A scene of `objects` copies of `asset` on a grid (spacing 2.5 units) and `lights` random
/// lights over it, looked at from above and in front, at `width` × `height`.
pub fn grid_scene(
    asset: &Path,
    objects: usize,
    lights: usize,
    seed: u64,
    width: u32,
    height: u32,
) -> Scene {
    let side = (objects as f64).sqrt().ceil().max(1.0) as f32;
    let extent = side * 2.5 / 2.0 + 1.0;
    Scene {
        output: Size { width, height },
        camera: Camera {
            position: [0.0, extent * 0.9, extent * 1.6],
            target: [0.0, 0.0, 0.0],
            ..Camera::default()
        },
        objects: grid(asset, objects, 2.5, Material::Opaque),
        lights: random_lights(
            lights,
            seed,
            Vec3::new(-extent, 0.3, -extent),
            Vec3::new(extent, 2.0, extent),
            (2.0, 4.0),
            1.0,
        ),
        ..Scene::default()
    }
}

/// The paper's first experiment: 101 objects, 81 omni lights, 1280 × 720 (inferred lighting
/// against forward rendering).
pub fn paper_objects_and_lights(asset: &Path) -> Scene {
    grid_scene(asset, 101, 81, 0x7065_6c74, 1280, 720)
}

/// The paper's second experiment: 122 lights at 1280 × 720, with the L-buffer at 800 × 450
/// (scale 0.625) and DSF; the comparison runs the same scene at scale 1 without DSF.
pub fn paper_lbuffer_scale(asset: &Path) -> Scene {
    Scene {
        lbuffer_scale: 0.625,
        dsf: true,
        ..grid_scene(asset, 64, 122, 0x7065_6c75, 1280, 720)
    }
}

/// The fur showcase (`pelt demo`, the fur tests and `render-bench --experiment fur`): `asset`
/// (a baked, furred asset whose bounds are `lo`..`hi`) as fur, standing on a ground quad
/// under a procedural sky, lit by a warm key, a cool fill and a rim light from behind; the
/// camera orbits the asset by `yaw_deg` (0 = from the front, +Z, slightly to the side).
pub fn fur_scene(asset: &Path, lo: Vec3, hi: Vec3, width: u32, height: u32, yaw_deg: f32) -> Scene {
    let center = (lo + hi) / 2.0;
    let radius = ((hi - lo).length() / 2.0).max(1e-3);
    let yaw = yaw_deg.to_radians();
    let (s, c) = yaw.sin_cos();
    let base = Vec3::new(0.45, 0.35, 1.0).normalize();
    let dir = Vec3::new(base.x * c + base.z * s, base.y, -base.x * s + base.z * c);
    let eye = center + dir * radius * 2.3;
    let ground = lo.y - 0.02 * radius;
    let light = |p, color, intensity| {
        crate::framing::light_around(center, radius, 9.0, p, color, intensity)
    };
    Scene {
        output: Size { width, height },
        camera: Camera {
            position: eye.to_array(),
            target: center.to_array(),
            up: [0.0, 1.0, 0.0],
            fov_y_deg: 40.0,
            near: radius * 0.2,
            far: radius * 12.0,
        },
        ambient: [0.05, 0.055, 0.065],
        sky: Sky::Procedural,
        objects: vec![
            Object {
                asset: asset.to_owned(),
                transform: Transform::default(),
                material: Material::Fur(FurSettings::default()),
                color: [1.0; 3],
            },
            Object {
                asset: "builtin:quad".into(),
                transform: Transform {
                    translation: [center.x, ground, center.z],
                    rotation: glam::Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2).to_array(),
                    scale: [radius * 5.0, radius * 5.0, 1.0],
                },
                material: Material::Opaque,
                color: [0.42, 0.40, 0.36],
            },
        ],
        lights: vec![
            light(Vec3::new(1.6, 1.8, 1.8), [1.0, 0.93, 0.82], 7.0),
            light(Vec3::new(-2.2, 0.6, 1.2), [0.55, 0.65, 1.0], 2.5),
            light(Vec3::new(-0.5, 1.4, -2.4), [1.0, 0.95, 0.9], 6.0),
        ],
        ..Scene::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_are_centred_and_spaced() {
        let objs = grid(Path::new("a.glb"), 9, 2.0, Material::Opaque);
        assert_eq!(objs.len(), 9);
        assert_eq!(objs[0].transform.translation, [-2.0, 0.0, -2.0]);
        assert_eq!(objs[4].transform.translation, [0.0, 0.0, 0.0]);
        assert_eq!(objs[8].transform.translation, [2.0, 0.0, 2.0]);
        // 101 objects: an 11 × 11 grid, partly filled, all distinct.
        let many = grid(Path::new("a.glb"), 101, 2.5, Material::Opaque);
        let mut spots: Vec<[i64; 2]> = many
            .iter()
            .map(|o| {
                [
                    (o.transform.translation[0] * 10.0) as i64,
                    (o.transform.translation[2] * 10.0) as i64,
                ]
            })
            .collect();
        spots.sort_unstable();
        spots.dedup();
        assert_eq!(spots.len(), 101);
    }

    #[test]
    fn random_lights_are_seeded_and_in_bounds() {
        let (lo, hi) = (Vec3::splat(-1.0), Vec3::splat(1.0));
        let a = random_lights(200, 5, lo, hi, (1.0, 2.0), 3.0);
        assert_eq!(a, random_lights(200, 5, lo, hi, (1.0, 2.0), 3.0));
        assert_eq!(a[..50], random_lights(50, 5, lo, hi, (1.0, 2.0), 3.0)[..]);
        assert_ne!(a, random_lights(200, 6, lo, hi, (1.0, 2.0), 3.0));
        for l in &a {
            assert!(
                l.emitter
                    .position()
                    .is_some_and(|p| p.cmpge(lo).all() && p.cmple(hi).all())
            );
            assert!(l.emitter.radius().is_some_and(|r| (1.0..=2.0).contains(&r)));
            assert!(l.color.iter().all(|c| (0.3..=1.0).contains(c)));
        }
        // Spread over the box, not bunched: the mean is near the centre.
        let mean = a.iter().filter_map(|l| l.emitter.position()).sum::<Vec3>() / a.len() as f32;
        assert!(mean.length() < 0.15, "{mean}");
    }

    #[test]
    fn the_papers_scenes_have_the_papers_counts_and_are_valid() {
        let a = paper_objects_and_lights(Path::new("creature.glb"));
        assert_eq!((a.objects.len(), a.lights.len()), (101, 81));
        assert_eq!((a.output.width, a.output.height), (1280, 720));
        let b = paper_lbuffer_scale(Path::new("creature.glb"));
        assert_eq!(b.lights.len(), 122);
        assert_eq!(b.lbuffer_size(), (800, 450));
        // Both survive a round trip through the scene format, checks included.
        for s in [a, b] {
            let text = serde_json::to_string(&s).expect("serialize");
            let back = Scene::parse(Path::new("gen.json"), &text).expect("valid scene");
            assert_eq!(back, s);
        }
    }
}
