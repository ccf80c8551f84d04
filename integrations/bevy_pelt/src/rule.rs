//! Per frame: the shells drawn by screen size (`pelt_fur::shells::ShellRule`, the rule the
//! bake writes as `shellRule`: one shell per pixel of projected fur length, at least its
//! `min`, at most the manifest's `shells`), measured from the main camera with pelt's
//! `pelt_scene::footprint::fur_pixels`; and the wind, copied into the fur materials.

use bevy::mesh::skinning::{SkinnedMesh, SkinnedMeshInverseBindposes};
use bevy::prelude::*;

use crate::attach::FurAttached;
use crate::fins::FinMaterial;
use crate::material::FurMaterial;
use crate::settings::FurWind;

type Glam30Mat4 = glam30::Mat4;

fn to30(m: Mat4) -> Glam30Mat4 {
    Glam30Mat4::from_cols_array(&m.to_cols_array())
}

/// The camera the rule measures from: the active camera of highest order.
fn main_camera<'a>(
    cameras: impl Iterator<Item = (&'a Camera, &'a GlobalTransform, &'a Projection)>,
) -> Option<(&'a Camera, &'a GlobalTransform, &'a Projection)> {
    cameras
        .filter(|(c, _, _)| c.is_active)
        .max_by_key(|(c, _, _)| c.order)
}

/// The longest the fur can project to, in pixels of the camera's viewport.
fn fur_pixels(
    cam: (&Camera, &GlobalTransform, &Projection),
    model: Mat4,
    bounds: (Vec3, Vec3),
    length: f32,
) -> Option<f32> {
    let (camera, eye, projection) = cam;
    let size = camera.physical_viewport_size()?;
    let reach = length;
    match projection {
        Projection::Perspective(p) => {
            let tan_y = (p.fov * 0.5).tan();
            let view = pelt_scene::view::View {
                view: to30(eye.to_matrix().inverse()),
                proj: Glam30Mat4::IDENTITY,
                tan_half: [tan_y * p.aspect_ratio, tan_y],
                near: p.near,
                far: p.far,
            };
            // The box grown by the fur's length, its nearest view depth (as pelt's planner).
            let grow = |v: Vec3| glam30::Vec3::from_array(v.to_array());
            let (lo, hi) = (grow(bounds.0 - length), grow(bounds.1 + length));
            let (_, vhi) = view.view_box(to30(model), lo, hi);
            Some(pelt_scene::footprint::fur_pixels(
                &view,
                (size.x, size.y),
                to30(model),
                -vhi.z,
                reach,
            ))
        }
        Projection::Orthographic(o) => {
            let stretch = pelt_scene::footprint::max_stretch(to30(model));
            Some(reach * stretch * size.y as f32 / o.area.height().max(1e-12))
        }
        Projection::Custom(_) => None,
    }
}

/// What places a mesh's vertices in the world: its transform, or for a skinned mesh its
/// first joint's (the skeleton's root, bind pose undone).
fn model_of(
    gt: &GlobalTransform,
    skinned: Option<&SkinnedMesh>,
    joints: &Query<&GlobalTransform>,
    inverse: &Assets<SkinnedMeshInverseBindposes>,
) -> Mat4 {
    let posed = skinned.and_then(|s| {
        let j = joints.get(*s.joints.first()?).ok()?;
        let ib = inverse.get(&s.inverse_bindposes)?.first().copied()?;
        Some(j.to_matrix() * ib)
    });
    posed.unwrap_or_else(|| gt.to_matrix())
}

/// Sets each fur's shell count by the rule, hiding the shells above it.
pub(crate) fn apply_rule(
    cameras: Query<(&Camera, &GlobalTransform, &Projection)>,
    mut furs: Query<(&mut FurAttached, &GlobalTransform, Option<&SkinnedMesh>)>,
    joints: Query<&GlobalTransform>,
    inverse: Res<Assets<SkinnedMeshInverseBindposes>>,
    mut materials: ResMut<Assets<FurMaterial>>,
    mut visibility: Query<&mut Visibility>,
) {
    let Some(cam) = main_camera(cameras.iter()) else {
        return;
    };
    for (mut fur, gt, skinned) in &mut furs {
        let Some(rule) = fur.rule else { continue };
        let model = model_of(gt, skinned, &joints, &inverse);
        let Some(pixels) = fur_pixels(cam, model, fur.bounds, fur.length) else {
            continue;
        };
        let n = rule.shells(f64::from(pixels), fur.max);
        if n == fur.drawn {
            continue;
        }
        fur.drawn = n;
        for (i, (e, h)) in fur.shells.iter().enumerate() {
            if let Ok(mut v) = visibility.get_mut(*e) {
                *v = if (i as u32) < n {
                    Visibility::Inherited
                } else {
                    Visibility::Hidden
                };
            }
            if let Some(mut m) = materials.get_mut(h) {
                m.extension.fur.shell.y = n as f32;
            }
        }
        if let Some(mut m) = materials.get_mut(&fur.base) {
            m.extension.fur.shell.y = n as f32;
        }
    }
}

/// Copies the wind into every fur material when it changes, and each frame while it blows on
/// the app's clock.
pub(crate) fn apply_wind(
    mut fin_materials: ResMut<Assets<FinMaterial>>,
    wind: Res<FurWind>,
    time: Res<Time>,
    furs: Query<Ref<FurAttached>>,
    mut materials: ResMut<Assets<FurMaterial>>,
    mut last: Local<Option<(Vec4, Vec4)>>,
) {
    let (w, g) = wind.vectors(time.elapsed_secs());
    let fresh = furs.iter().any(|f| f.is_added());
    if *last == Some((w, g)) && !fresh {
        return;
    }
    *last = Some((w, g));
    for fur in &furs {
        for h in std::iter::once(&fur.base).chain(fur.shells.iter().map(|(_, h)| h)) {
            if let Some(mut m) = materials.get_mut(h) {
                m.extension.fur.wind = w;
                m.extension.fur.gust = g;
            }
        }
        if let Some((_, h)) = &fur.fins
            && let Some(mut m) = fin_materials.get_mut(h)
        {
            m.extension.fin.wind = w;
            m.extension.fin.gust = g;
        }
    }
}
