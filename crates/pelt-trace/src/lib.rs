//! `pelt render --mode raytrace`: the ground truth the distance-map reflections (GPU Gems 3
//! ch. 17) are measured against. A CPU ray tracer over the same scene: the same triangles
//! (two-sided, with interpolated vertex normals), the same local lighting
//! ([`pelt_scene::shading`]: ambient, point lights, Blinn-Phong; a shadow ray toward each
//! light that casts shadows, `"shadows": true`, [`World::sees`]), colours, sky, and the same specular paths as the GPU's
//! Listing 17-5 loop ([`path`]): Schlick's Fresnel with F0, refraction with total internal
//! reflection, and the bounce limit. Where the GPU searches its distance maps for the next
//! hit, this traces the real triangles through a BVH (`obvhs`), so the difference between
//! the two images is the search alone. One ray per pixel centre (the rasterizer's sample);
//! rows run in parallel with rayon and the image is the same at any thread count.
//!
//! Left out: alpha objects (the rasterizer blends them over; here they are not hit) and fur,
//! whose base mesh is drawn in the fur's mean colour (as the distance maps hold it).

pub mod path;
pub mod strands;
pub mod world;

use glam::Vec3;
use rayon::prelude::*;

use pelt_scene::plan::{Optics, ScenePlan};
use pelt_scene::shading::srgb8;
use pelt_scene::view::View;

pub use path::Tracer;
pub use world::{SkyModel, World};

/// A traced image: 8-bit sRGB RGBA, rows top to bottom, and which pixels show a mirror or
/// glass object first.
#[derive(Debug, Clone, PartialEq)]
pub struct Traced {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Pixels.
    pub rgba: Vec<u8>,
    /// Per pixel: the camera ray's first hit is a mirror or glass object.
    pub reflective: Vec<bool>,
}

/// Traces the scene of `plan` seen through `view` at `size`; `max_depth` bounces.
pub fn render(world: &World, plan: &ScenePlan, view: &View, size: (u32, u32)) -> Traced {
    render_with(world, plan, view, size, &|_| {})
}

/// [`render`], calling `row_done` with the number of rows finished as each row finishes
/// (from the worker threads, in no set order).
pub fn render_with(
    world: &World,
    plan: &ScenePlan,
    view: &View,
    size: (u32, u32),
    row_done: &(dyn Fn(u32) + Sync),
) -> Traced {
    let finished = std::sync::atomic::AtomicU32::new(0);
    let tracer = Tracer {
        world,
        max_depth: plan.reflections.max_depth,
    };
    let (w, h) = size;
    let inv = view.view.inverse();
    let eye = inv.transform_point3(Vec3::ZERO);
    let rows: Vec<(Vec<u8>, Vec<bool>)> = (0..h)
        .into_par_iter()
        .map(|y| {
            let mut rgba = Vec::with_capacity(w as usize * 4);
            let mut mask = Vec::with_capacity(w as usize);
            for x in 0..w {
                let ndc_x = (x as f32 + 0.5) / w as f32 * 2.0 - 1.0;
                let ndc_y = 1.0 - (y as f32 + 0.5) / h as f32 * 2.0;
                let v = Vec3::new(ndc_x * view.tan_half[0], ndc_y * view.tan_half[1], -1.0);
                // Hits between the near and far planes (view depth, as the rasterizer clips).
                let len = v.length();
                let dir = inv.transform_vector3(v).normalize();
                let (c, hit) = tracer.camera_ray(eye, dir, view.near * len, view.far * len);
                rgba.extend(c.to_array().map(srgb8));
                rgba.push(255);
                mask.push(hit.is_some_and(|o| o != Optics::Diffuse));
            }
            row_done(finished.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1);
            (rgba, mask)
        })
        .collect();
    let mut out = Traced {
        width: w,
        height: h,
        rgba: Vec::with_capacity((w * h * 4) as usize),
        reflective: Vec::with_capacity((w * h) as usize),
    };
    for (r, m) in rows {
        out.rgba.extend(r);
        out.reflective.extend(m);
    }
    out
}

/// Traces `scene` (its objects' meshes are `meshes[mesh_of[i]]`) from its camera at its
/// output size; reads a cube-map sky's faces.
pub fn trace_scene(
    scene: &pelt_scene::Scene,
    meshes: &[pelt_scene::asset::MeshData],
    mesh_of: &[usize],
) -> Result<Traced, pelt_scene::sky::SkyError> {
    trace_scene_with(scene, meshes, mesh_of, &|_| {})
}

/// [`trace_scene`], calling `row_done` as each of the output's rows is finished
/// ([`render_with`]).
pub fn trace_scene_with(
    scene: &pelt_scene::Scene,
    meshes: &[pelt_scene::asset::MeshData],
    mesh_of: &[usize],
    row_done: &(dyn Fn(u32) + Sync),
) -> Result<Traced, pelt_scene::sky::SkyError> {
    let infos: Vec<pelt_scene::plan::MeshInfo> =
        meshes.iter().map(pelt_scene::plan::MeshInfo::of).collect();
    let plan = ScenePlan::new(scene, &infos, mesh_of, pelt_scene::Mode::Forward);
    let sky = match &scene.sky {
        pelt_scene::scene::Sky::None => SkyModel::Background,
        pelt_scene::scene::Sky::Procedural => SkyModel::Procedural,
        pelt_scene::scene::Sky::Cubemap(faces) => {
            SkyModel::cube(&pelt_scene::sky::load_cube(faces)?)
        }
    };
    let world = World::new(&plan, meshes, sky);
    let view = View::new(scene);
    Ok(render_with(
        &world,
        &plan,
        &view,
        (scene.output.width, scene.output.height),
        row_done,
    ))
}
