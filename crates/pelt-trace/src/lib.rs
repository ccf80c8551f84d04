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
//! Fur objects are drawn as the strand reference's strands ([`fur`]: the same seeded strands,
//! capsules every ray meets, Kajiya-Kay lit) over their base mesh, so fur seen directly, in a
//! mirror or through glass has a truth. Left out: alpha objects (the rasterizer blends them
//! over; here they are not hit).

pub mod capsules;
pub mod fur;
pub mod path;
pub mod strand_set;
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

/// Camera rays per pixel, per axis, where the world traces fur: a strand is far thinner than
/// a pixel, so one ray at the pixel's centre would alias it (docs/mirrors.md states the
/// convergence against the strand reference).
pub const FUR_SAMPLES: u32 = 16;

/// Traces the scene of `plan` seen through `view` at `size`; `max_depth` bounces; one ray
/// per pixel centre, or [`FUR_SAMPLES`]² per pixel where the world traces fur.
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
    let samples = if world.traces_fur() { FUR_SAMPLES } else { 1 };
    render_sampled(world, plan, view, size, samples, row_done)
}

/// [`render_with`] with `samples`² camera rays per pixel on a regular grid (1: the pixel's
/// centre), averaged in linear light; a pixel is reflective where its centre's ray first
/// meets a mirror or glass.
pub fn render_sampled(
    world: &World,
    plan: &ScenePlan,
    view: &View,
    size: (u32, u32),
    samples: u32,
    row_done: &(dyn Fn(u32) + Sync),
) -> Traced {
    let finished = std::sync::atomic::AtomicU32::new(0);
    let tracer = Tracer {
        world,
        max_depth: plan.reflections.max_depth,
    };
    let (w, h) = size;
    let n = samples.max(1);
    let inv = view.view.inverse();
    let eye = inv.transform_point3(Vec3::ZERO);
    // The camera ray through framebuffer point (px, py): its direction and its depth range
    // (hits between the near and far planes, in view depth, as the rasterizer clips).
    let ray = |px: f32, py: f32| {
        let ndc_x = px / w as f32 * 2.0 - 1.0;
        let ndc_y = 1.0 - py / h as f32 * 2.0;
        let v = Vec3::new(ndc_x * view.tan_half[0], ndc_y * view.tan_half[1], -1.0);
        let len = v.length();
        (
            inv.transform_vector3(v).normalize(),
            view.near * len,
            view.far * len,
        )
    };
    let rows: Vec<(Vec<u8>, Vec<bool>)> = (0..h)
        .into_par_iter()
        .map(|y| {
            let mut rgba = Vec::with_capacity(w as usize * 4);
            let mut mask = Vec::with_capacity(w as usize);
            for x in 0..w {
                let (c, hit) = if n == 1 {
                    let (d, tmin, tmax) = ray(x as f32 + 0.5, y as f32 + 0.5);
                    tracer.camera_ray(eye, d, tmin, tmax)
                } else {
                    let mut sum = Vec3::ZERO;
                    for k in 0..n * n {
                        let (sx, sy) = ((k % n) as f32 + 0.5, (k / n) as f32 + 0.5);
                        let (d, tmin, tmax) =
                            ray(x as f32 + sx / n as f32, y as f32 + sy / n as f32);
                        sum += tracer.camera_ray(eye, d, tmin, tmax).0;
                    }
                    let (d, tmin, tmax) = ray(x as f32 + 0.5, y as f32 + 0.5);
                    let hit = world.hit(eye, d, tmin, tmax).map(|h| h.optics);
                    (sum / (n * n) as f32, hit)
                };
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

/// Why a scene cannot be traced.
#[derive(Debug, thiserror::Error)]
pub enum TraceError {
    /// A cube-map sky's faces cannot be read.
    #[error(transparent)]
    Sky(#[from] pelt_scene::sky::SkyError),
    /// A fur object's strands cannot be planted.
    #[error("objects[{object}]: its fur's strands cannot be traced: {source}")]
    Strands {
        /// The object's index in the scene file.
        object: usize,
        /// Why.
        #[source]
        source: pelt_scene::strands::StrandError,
    },
}

/// Traces `scene` (its objects' meshes are `meshes[mesh_of[i]]`) from its camera at its
/// output size, its fur objects as their strands; reads a cube-map sky's faces.
pub fn trace_scene(
    scene: &pelt_scene::Scene,
    meshes: &[pelt_scene::asset::MeshData],
    mesh_of: &[usize],
) -> Result<Traced, TraceError> {
    trace_scene_with(scene, meshes, mesh_of, &|_| {})
}

/// [`trace_scene`], calling `row_done` as each of the output's rows is finished
/// ([`render_with`]).
pub fn trace_scene_with(
    scene: &pelt_scene::Scene,
    meshes: &[pelt_scene::asset::MeshData],
    mesh_of: &[usize],
    row_done: &(dyn Fn(u32) + Sync),
) -> Result<Traced, TraceError> {
    trace_scene_sampled(scene, meshes, mesh_of, None, row_done)
}

/// [`trace_scene_with`] with `samples`² camera rays per pixel where the world traces fur
/// (None: [`FUR_SAMPLES`]).
pub fn trace_scene_sampled(
    scene: &pelt_scene::Scene,
    meshes: &[pelt_scene::asset::MeshData],
    mesh_of: &[usize],
    samples: Option<u32>,
    row_done: &(dyn Fn(u32) + Sync),
) -> Result<Traced, TraceError> {
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
    let world = World::with_fur(&plan, meshes, sky, &planted(&plan, meshes)?);
    let view = View::new(scene);
    let size = (scene.output.width, scene.output.height);
    Ok(match samples {
        Some(n) if world.traces_fur() => render_sampled(&world, &plan, &view, size, n, row_done),
        _ => render_with(&world, &plan, &view, size, row_done),
    })
}

/// The strands planted on each mesh a fur object of `plan` draws (by mesh; `None` for the
/// others), in the order `pelt_scene::strands::plant` plants them.
fn planted(
    plan: &ScenePlan,
    meshes: &[pelt_scene::asset::MeshData],
) -> Result<Vec<Option<Vec<pelt_scene::vertex::StrandRoot>>>, TraceError> {
    let mut out: Vec<Option<Vec<_>>> = vec![None; meshes.len()];
    for (o, _) in &plan.objects {
        if o.fur.is_none() || o.pattern != 0 || out[o.mesh].is_some() {
            continue;
        }
        let roots =
            pelt_scene::strands::plant(&meshes[o.mesh]).map_err(|source| TraceError::Strands {
                object: o.scene_index,
                source,
            })?;
        out[o.mesh] = Some(roots);
    }
    Ok(out)
}
