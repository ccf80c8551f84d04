//! The mirrors-and-glass experiment (GPU Gems 3 ch. 17 measured): a scene rendered through
//! its distance maps at given knobs, timed on the adapter, and compared by FLIP with the CPU
//! ray tracer's image of the same scene, over the whole image and over the pixels where a
//! mirror or glass object is seen first. The reflection shading's own time is the material
//! (or forward) pass with the reflections on, less the same pass with them off.

use std::time::Instant;

use pelt_preview::Pass;
use pelt_preview::asset::MeshData;
use pelt_preview::features::{forward, material, reflect};
use pelt_preview::scene::{Reflections, Technique};
use pelt_preview::{Image, Mode, Preview, RenderError, Scene};

use crate::flip::{Flip, SizeMismatch};

/// What can stop an experiment.
#[derive(Debug, thiserror::Error)]
pub enum MeasureError {
    /// Rendering failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// The ray tracer could not read the sky or plant a fur object's strands.
    #[error(transparent)]
    Trace(#[from] pelt_trace::TraceError),
    /// The images differ in size.
    #[error(transparent)]
    Size(#[from] SizeMismatch),
    /// The reference was traced with another bounce limit.
    #[error("the reference has {reference} bounces, the run {run}")]
    Depth {
        /// The reference's.
        reference: u32,
        /// The run's.
        run: u32,
    },
}

/// The ray tracer's image of a scene: the reference.
#[derive(Debug, Clone)]
pub struct Reference {
    /// The image.
    pub image: Image,
    /// Pixels whose camera ray first meets a mirror or glass object.
    pub mask: Vec<bool>,
    /// Its time (wall clock, every core).
    pub ms: f64,
    /// The bounce limit it was traced with (a run must use the same).
    pub max_depth: u32,
}

/// Traces the reference of `scene` with at most `max_depth` bounces.
pub fn reference(
    scene: &Scene,
    meshes: &[MeshData],
    mesh_of: &[usize],
    max_depth: u32,
) -> Result<Reference, MeasureError> {
    let mut scene = scene.clone();
    scene.reflections.max_depth = max_depth;
    let t = Instant::now();
    let traced = pelt_trace::trace_scene(&scene, meshes, mesh_of)?;
    let ms = t.elapsed().as_secs_f64() * 1e3;
    Ok(Reference {
        image: Image {
            width: traced.width,
            height: traced.height,
            rgba: traced.rgba,
        },
        mask: traced.reflective,
        ms,
        max_depth,
    })
}

/// One setting's render, times and errors.
#[derive(Debug, Clone)]
pub struct Run {
    /// The knobs.
    pub knobs: Reflections,
    /// The image.
    pub image: Image,
    /// Its FLIP against the reference.
    pub flip: Flip,
    /// FLIP mean over the whole image.
    pub error: f32,
    /// FLIP mean over the mirror and glass pixels.
    pub error_reflective: f32,
    /// Median frame time (ms).
    pub frame_ms: f64,
    /// The distance maps' pass (ms; None when the frame has none).
    pub maps_ms: Option<f64>,
    /// The min-max pass (ms; None when the frame has none).
    pub minmax_ms: Option<f64>,
    /// The material (or forward) pass (ms).
    pub shade_ms: f64,
}

/// The time of `pass` in `t` (the frame's timings sum a pass's recipes), if it ran.
fn pass_ms(t: &pelt_preview::Timings, pass: Pass) -> Option<f64> {
    t.passes.iter().find(|(p, _)| *p == pass).map(|(_, ms)| *ms)
}

/// Renders `scene` with `knobs` in `mode`, times `frames` frames after `warmup`, and
/// compares the image with `reference`.
#[expect(
    clippy::too_many_arguments,
    reason = "an experiment's inputs, each used once"
)]
pub fn run(
    preview: &mut Preview,
    scene: &Scene,
    meshes: &[MeshData],
    mesh_of: &[usize],
    mode: Mode,
    knobs: Reflections,
    reference: &Reference,
    (warmup, frames): (usize, usize),
) -> Result<Run, MeasureError> {
    if knobs.max_depth != reference.max_depth {
        return Err(MeasureError::Depth {
            reference: reference.max_depth,
            run: knobs.max_depth,
        });
    }
    let mut s = scene.clone();
    s.reflections = knobs;
    let view = preview.prepare_loaded(&s, meshes, mesh_of, mode)?;
    let image = preview.render(&view)?;
    let t = preview.time(&view, warmup, frames)?;
    let shade = if mode == Mode::Forward {
        forward::PASS
    } else {
        material::PASS
    };
    let flip = Flip::new(&reference.image, &image)?;
    Ok(Run {
        knobs,
        error: flip.mean(),
        error_reflective: flip.masked_mean(&reference.mask),
        flip,
        image,
        frame_ms: t.frame_ms,
        maps_ms: pass_ms(&t, reflect::MAPS),
        minmax_ms: pass_ms(&t, reflect::MIN_MAX),
        shade_ms: pass_ms(&t, shade).unwrap_or(0.0),
    })
}

/// The material (or forward) pass's time with the reflections off: what the shading pass
/// costs without mirrors and glass, subtracted to get the reflection shading's own time.
pub fn shade_without(
    preview: &mut Preview,
    scene: &Scene,
    meshes: &[MeshData],
    mesh_of: &[usize],
    mode: Mode,
    (warmup, frames): (usize, usize),
) -> Result<f64, MeasureError> {
    let mut s = scene.clone();
    s.reflections.technique = Technique::Off;
    let view = preview.prepare_loaded(&s, meshes, mesh_of, mode)?;
    let t = preview.time(&view, warmup, frames)?;
    Ok(pass_ms(
        &t,
        if mode == Mode::Forward {
            forward::PASS
        } else {
            material::PASS
        },
    )
    .unwrap_or(0.0))
}
