//! pelt-preview: the preview renderer for baked assets, a headless wgpu implementation of
//! inferred lighting (Kircher & Lawrance 2009) with deferred and forward references.
//!
//! - [`scene`], [`procedural`], [`framing`]: what is rendered: scene files, generated scenes,
//!   the default scene around one asset;
//! - [`asset`]: glTF/OBJ (and built-in shapes) into vertex lists with normal-group IDs;
//! - [`plan`], [`view`]: CPU decisions per frame: mode, passes, culling, scissor rectangles,
//!   object IDs, stipple patterns, draw order (`--explain`);
//! - [`gpu`], [`renderer`], [`draw`], [`passes`], [`frame`]: the device, long-lived pipelines,
//!   per-scene buffers and targets, the passes, and running/timing frames;
//! - [`shaders`], [`uniforms`]: WGSL sources (top-level `shaders/`) and the structs they share;
//! - [`fur`]: an asset's baked fur (comb, fins, textures, manifest) for Revie's deferred fur;
//!   [`sky`]: the cube-map sky's images.

pub mod asset;
pub mod draw;
pub mod frame;
pub mod framing;
pub mod fur;
pub mod gpu;
pub mod passes;
pub mod plan;
pub mod procedural;
pub mod renderer;
pub mod scene;
pub mod shaders;
pub mod sky;
pub mod uniforms;
pub mod view;

use std::path::PathBuf;

pub use frame::{FrameError, Image, PassClock, Timings};
pub use gpu::{Backend, Gpu, GpuError};
pub use plan::{Mode, Plan, PlanError};
pub use scene::{Scene, SceneError};

use asset::{AssetError, MeshData};
use draw::DrawData;
use renderer::Renderer;

/// Anything that stops a render.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// An object's asset failed to load.
    #[error("objects[{object}] ({}): {source}", path.display())]
    Asset {
        /// Object index in the scene.
        object: usize,
        /// Its asset path.
        path: PathBuf,
        /// Why.
        source: AssetError,
    },
    /// The plan cannot run.
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// The cube-map sky could not be read.
    #[error(transparent)]
    Sky(#[from] sky::SkyError),
    /// No device.
    #[error(transparent)]
    Gpu(#[from] GpuError),
    /// The device failed during the frame.
    #[error(transparent)]
    Frame(#[from] FrameError),
}

/// Loads each distinct asset of `scene` once; returns the meshes and each object's index
/// into them. Objects are tinted by their scene colour in the shader, not here.
pub fn load_meshes(scene: &Scene) -> Result<(Vec<MeshData>, Vec<usize>), RenderError> {
    let mut paths: Vec<&std::path::Path> = Vec::new();
    let mut meshes = Vec::new();
    let mut of = Vec::with_capacity(scene.objects.len());
    for (i, o) in scene.objects.iter().enumerate() {
        match paths.iter().position(|p| *p == o.asset.as_path()) {
            Some(k) => of.push(k),
            None => {
                let m = asset::load(&o.asset).map_err(|source| RenderError::Asset {
                    object: i,
                    path: o.asset.clone(),
                    source,
                })?;
                paths.push(&o.asset);
                of.push(meshes.len());
                meshes.push(m);
            }
        }
    }
    Ok((meshes, of))
}

/// A renderer on one device, reusable across scenes.
#[derive(Debug)]
pub struct Preview {
    /// Pipelines and device.
    pub renderer: Renderer,
}

impl Preview {
    /// Opens a device on `backend`.
    pub fn new(backend: Backend) -> Result<Preview, RenderError> {
        Ok(Preview {
            renderer: Renderer::new(Gpu::new(backend)?),
        })
    }

    /// The adapter in words.
    pub fn adapter(&self) -> String {
        self.renderer.gpu.describe()
    }

    /// Plans `scene` in `mode`, builds the pipelines the plan needs and uploads the scene.
    pub fn prepare(&mut self, scene: &Scene, mode: Mode) -> Result<DrawData, RenderError> {
        let (meshes, of) = load_meshes(scene)?;
        self.prepare_loaded(scene, &meshes, &of, mode)
    }

    /// [`Preview::prepare`] with the meshes already loaded.
    pub fn prepare_loaded(
        &mut self,
        scene: &Scene,
        meshes: &[MeshData],
        mesh_of: &[usize],
        mode: Mode,
    ) -> Result<DrawData, RenderError> {
        let plan = Plan::new(scene, meshes, mesh_of, mode)?;
        let cube = match &scene.sky {
            scene::Sky::Cubemap(faces) => Some(sky::load_cube(faces)?),
            _ => None,
        };
        self.renderer.prepare(&plan);
        let d = DrawData::new(&self.renderer, plan, meshes, cube.as_ref());
        match self.renderer.gpu.take_error() {
            Some(e) => Err(FrameError::Device(e).into()),
            None => Ok(d),
        }
    }

    /// Renders one frame.
    pub fn render(&self, d: &DrawData) -> Result<Image, RenderError> {
        Ok(frame::render(&self.renderer, d)?)
    }

    /// Times frames (see [`frame::time`]).
    pub fn time(&self, d: &DrawData, warmup: usize, frames: usize) -> Result<Timings, RenderError> {
        Ok(frame::time(&self.renderer, d, warmup, frames)?)
    }
}
