//! The default scene for `pelt render ASSET.glb`: the camera framing the asset's bounding
//! sphere from the front, slightly above and to the side, with a key, a fill and a rim light
//! sized to the asset (or the asset's own lights, where it places some), and a little ambient. An asset with baked fur is drawn as fur (its
//! manifest's look) under the procedural sky.

use std::path::Path;

use glam::Vec3;

use crate::asset::MeshData;
use crate::scene::{Camera, FurSettings, Light, Material, Object, Scene, Size, Sky, Transform};

/// A scene showing `asset` (whose mesh is `mesh`) at `width` × `height`.
pub fn asset_scene(asset: &Path, mesh: &MeshData, width: u32, height: u32) -> Scene {
    let (lo, hi) = mesh.bounds();
    let center = (lo + hi) / 2.0;
    let fur_length = mesh.fur.as_ref().map_or(0.0, |f| {
        let scale = f.vertices.iter().map(|v| v.bend[3]).fold(0.0, f32::max);
        f.look.length * scale
    });
    let radius = ((hi - lo).length() / 2.0 + fur_length).max(1e-3);
    let fov_y_deg = 40.0_f32;
    let aspect = width as f32 / height as f32;
    // Distance at which the bounding sphere fits the narrower field of view, with a margin.
    let half = (fov_y_deg.to_radians() / 2.0).tan();
    let fit = half.min(half * aspect);
    let distance = radius / fit.atan().sin() * 1.1;
    let dir = Vec3::new(0.35, 0.3, 1.0).normalize();
    let eye = center + dir * distance;
    let light =
        |offset, color, intensity| light_around(center, radius, 8.0, offset, color, intensity);
    Scene {
        output: Size { width, height },
        camera: Camera {
            position: eye.to_array(),
            target: center.to_array(),
            up: [0.0, 1.0, 0.0],
            fov_y_deg,
            near: (distance - radius * 1.5).max(distance * 0.01),
            far: distance + radius * 4.0,
        },
        ambient: [0.04; 3],
        objects: vec![Object {
            asset: asset.to_owned(),
            transform: Transform::default(),
            material: if mesh.fur.is_some() {
                Material::Fur(FurSettings::default())
            } else {
                Material::Opaque
            },
            color: if mesh.fur.is_some() {
                [1.0; 3]
            } else {
                [0.8; 3]
            },
        }],
        sky: if mesh.fur.is_some() {
            Sky::Procedural
        } else {
            Sky::None
        },
        // An asset that places its own lights (KHR_lights_punctual) is lit by them alone:
        // the scene's plan adds them.
        lights: if mesh.lights.is_empty() {
            vec![
                light(Vec3::new(1.5, 2.0, 2.5), [1.0, 0.95, 0.85], 6.0),
                light(Vec3::new(-2.5, 0.5, 1.5), [0.55, 0.65, 1.0], 2.5),
                light(Vec3::new(0.0, 1.5, -3.0), [1.0, 1.0, 1.0], 4.0),
            ]
        } else {
            Vec::new()
        },
        ..Scene::default()
    }
}

/// A point light at `center + offset · radius` that reaches `reach` radii, with its
/// intensity scaled by radius² so the asset is lit the same at any size.
pub fn light_around(
    center: Vec3,
    radius: f32,
    reach: f32,
    offset: Vec3,
    color: [f32; 3],
    intensity: f32,
) -> Light {
    Light::point(
        (center + offset * radius).to_array(),
        radius * reach,
        intensity * radius * radius,
    )
    .with_color(color)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::asset::builtin;
    use crate::view::View;

    #[test]
    fn the_asset_fills_the_frame_and_every_light_reaches_it() {
        for scale in [0.01_f32, 1.0, 300.0] {
            let mut m = builtin("sphere").expect("sphere");
            for v in &mut m.vertices {
                v.position =
                    (Vec3::from(v.position) * scale + Vec3::new(5.0, -2.0, 1.0) * scale).into();
            }
            let s = asset_scene(Path::new("a.glb"), &m, 200, 100);
            Scene::parse(
                Path::new("gen.json"),
                &serde_json::to_string(&s).expect("json"),
            )
            .expect("valid");
            let v = View::new(&s);
            let (lo, hi) = m.bounds();
            let (vlo, vhi) = v.view_box(glam::Mat4::IDENTITY, lo, hi);
            let r = v.screen_rect(vlo, vhi, (200, 100)).expect("on screen");
            // Fits inside, and fills a good part of the height.
            assert!(r[1] < 30 && r[3] > 70, "scale {scale}: {r:?}");
            assert!(
                vhi.z < -s.camera.near && vlo.z > -s.camera.far,
                "scale {scale}: inside the depth range"
            );
            for l in &s.lights {
                let p = l.emitter.position().expect("a point light");
                let d = (p - (lo + hi) / 2.0).length();
                assert!(
                    d < l.emitter.radius().expect("a point light") * 0.6,
                    "light reaches the asset"
                );
            }
        }
    }
}
