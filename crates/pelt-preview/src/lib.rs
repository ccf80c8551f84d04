//! pelt-preview: the preview renderer for baked assets, a wgpu implementation of inferred
//! lighting (Kircher & Lawrance 2009) with Revie's deferred fur, and deferred and forward
//! references. The CPU half (scene files, assets, plans, framing) is `pelt-scene`, re-exported
//! here under its module names.
//!
//! Three lifetimes, kept apart as in rerun's re_renderer:
//! - long-lived: [`Renderer`] (device, layouts and pipelines built from descriptors, keyed
//!   by them and the target formats) and [`assets::AssetCache`] (meshes, fur textures, skies:
//!   uploaded once, keyed by content, never written after);
//! - per view: [`targets::ViewTargets`], sized to the view and made for its output format;
//! - per frame: [`frame_data::FrameData`], the uniforms a camera and its knobs decide, written
//!   with `queue.write_buffer`, and each object's pose ([`poses::ObjectPose`]: its own copy
//!   of a GPU-skinned mesh's vertex buffers, written by the skinning passes).
//!
//! [`scene_view::SceneView`] holds one scene's share of each. Passes are built by the feature
//! modules ([`features`]) as [`recipe::Recipe`]s: the plan lists the passes, and
//! [`frame::recipes`] has the feature registered for each build it.

pub mod animate;
pub mod assets;
pub mod bench;
pub mod cube;
pub mod draw;
pub mod feature;
pub mod features;
pub mod frame;
pub mod frame_data;
pub mod glsl;
pub mod gpu;
pub mod gpu_material;
pub mod layout;
pub mod lighting;
pub mod owned;
pub mod pass;
pub mod poses;
pub mod progressive;
pub mod readback;
pub mod recipe;
pub mod renderer;
pub mod scene_state;
pub mod scene_view;
pub mod shaders;
pub mod shading;
pub mod targets;
pub mod uniforms;
pub mod work;

pub use pelt_scene::{
    asset, budget, debug, flags, framing, fur, knobs, orbit, plan, procedural, scene, sky, strands,
    view, wind,
};

use std::sync::Arc;

pub use features::registry::{explain, passes};
pub use frame::{FrameError, Image, PassClock, PassProfile, Timings};
pub use gpu::{Backend, Gpu, GpuError};
pub use pass::Pass;
pub use pelt_scene::{Mode, Plan, PlanError, Scene, SceneError};
pub use renderer::Renderer;
pub use scene_view::SceneView;

use asset::MeshData;
use assets::AssetCache;
use feature::Output;
use features::registry::{FEATURES, targets};
use features::skin::GpuSkinned;
use frame_data::FrameData;
use lighting::LightingInputs;
use owned::Owned;
use plan::{MeshInfo, ScenePlan};
use scene_state::{Prepared, SceneInputs};
use targets::{TargetSpec, ViewTargets};

/// Anything that stops a render.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// An object's asset failed to load.
    #[error(transparent)]
    Asset(#[from] asset::ObjectAssetError),
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
    /// A feature cannot make or follow its per-scene state (the distance maps on this
    /// adapter, the strand reference's strands or their traced shadows after a change of
    /// lights).
    #[error(transparent)]
    State(#[from] scene_state::StateError),
    /// A skinned asset's fins cannot follow its skin.
    #[error("{}: {source}", asset.as_ref().map_or("an asset".into(), |a| a.display().to_string()))]
    Skin {
        /// The asset (the first object that draws it).
        asset: Option<std::path::PathBuf>,
        /// Why.
        #[source]
        source: features::skin::SkinError,
    },
    /// A fur object's springs cannot follow its pose (the clip it was loaded at).
    #[error("objects[{object}]: {source}")]
    Springs {
        /// The scene object.
        object: usize,
        /// Why.
        #[source]
        source: PoseError,
    },
}

/// A skinned mesh could not be posed.
#[derive(Debug, thiserror::Error)]
pub enum PoseError {
    /// The clip does not exist (the error lists those that do).
    #[error(transparent)]
    Clip(#[from] pelt_io::IoError),
    /// The skinning pipelines could not be built.
    #[error(transparent)]
    Pipeline(#[from] renderer::PipelineError),
    /// The scene has no such object.
    #[error("objects[{object}] does not exist (the scene has {count} objects)")]
    NoObject {
        /// The index asked for.
        object: usize,
        /// How many objects the scene has.
        count: usize,
    },
}

impl From<draw::MissingInput> for RenderError {
    fn from(e: draw::MissingInput) -> Self {
        RenderError::Frame(FrameError::Missing(e))
    }
}

/// A scene's meshes on the GPU by mesh index, and each object's posed copy and its
/// skinning by scene index.
type Uploaded = (
    Vec<Option<Arc<assets::GpuMesh>>>,
    Vec<Option<poses::ObjectPose>>,
    Vec<Option<GpuSkinned>>,
);

/// Loads each distinct asset of `scene` once; returns the meshes and each object's index
/// into them.
pub fn load_meshes(scene: &Scene) -> Result<(Vec<MeshData>, Vec<usize>), RenderError> {
    Ok(asset::load_scene(scene)?)
}

/// Where a view's image goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ViewOutput {
    /// The colour format.
    pub format: wgpu::TextureFormat,
    /// The view renders into a texture of its own, read back as an [`Image`] (else into one
    /// the caller gives each frame: a window's surface).
    pub own_color: bool,
}

impl ViewOutput {
    /// A PNG: RGBA8 sRGB, read back.
    pub const IMAGE: ViewOutput = ViewOutput {
        format: renderer::OUTPUT_FORMAT,
        own_color: true,
    };
}

/// A renderer on one device with its asset cache, reusable across scenes and views.
#[derive(Debug)]
pub struct Preview {
    /// Pipelines and device.
    pub renderer: Renderer,
    /// GPU assets.
    pub assets: AssetCache,
}

impl Preview {
    /// Opens a device on `backend`.
    pub fn new(backend: Backend) -> Result<Preview, RenderError> {
        Ok(Preview::on(Gpu::new(backend)?))
    }

    /// A preview on an opened device (a window's).
    pub fn on(gpu: Gpu) -> Preview {
        Preview {
            renderer: Renderer::new(gpu, features::registry::shaders()),
            assets: AssetCache::default(),
        }
    }

    /// The adapter in words.
    pub fn adapter(&self) -> String {
        self.renderer.gpu.describe()
    }

    /// Loads `scene`'s assets and prepares it in `mode` for PNG output.
    pub fn prepare(&mut self, scene: &Scene, mode: Mode) -> Result<SceneView, RenderError> {
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
    ) -> Result<SceneView, RenderError> {
        self.prepare_view(scene, meshes, mesh_of, mode, ViewOutput::IMAGE)
    }

    /// Plans `scene` in `mode`, uploads what it draws (unless the cache has it), makes the
    /// view's targets for `output` and writes the first frame's uniforms.
    pub fn prepare_view(
        &mut self,
        scene: &Scene,
        meshes: &[MeshData],
        mesh_of: &[usize],
        mode: Mode,
        output: ViewOutput,
    ) -> Result<SceneView, RenderError> {
        let infos: Vec<MeshInfo> = meshes.iter().map(MeshInfo::of).collect();
        let scene_plan = ScenePlan::new(scene, &infos, mesh_of, mode);
        let plan = Plan::with_camera(&scene_plan, &view::View::new(scene))?;
        let (gpu_meshes, poses, skins) = self.upload_meshes(scene, meshes, mesh_of, &scene_plan)?;
        let sky = match &scene.sky {
            scene::Sky::Cubemap(faces) => {
                let cube = sky::load_cube(faces)?;
                Some(self.assets.sky(&self.renderer, &cube))
            }
            _ => None,
        };
        let mut owned = Owned::default();
        let inputs = SceneInputs {
            scene,
            plan: &scene_plan,
            sky: sky.as_deref(),
        };
        let mut prepared = Prepared {
            meshes,
            assets: &mut self.assets,
        };
        for s in FEATURES.iter().filter_map(|f| f.scene) {
            (s.make)(&self.renderer, &inputs, &mut prepared, &mut owned)?;
        }
        LightingInputs::gather(&self.renderer, FEATURES, &mut owned);
        let spec = TargetSpec::of(&plan, output.format, output.own_color, &targets());
        let mut data = FrameData::new(&self.renderer);
        data.write(&self.renderer, &plan);
        let sv = SceneView {
            infos,
            mesh_of: mesh_of.to_vec(),
            scene_plan,
            plan,
            meshes: gpu_meshes,
            poses,
            skins,
            sky,
            targets: ViewTargets::new(&self.renderer, spec, &targets()),
            data,
            extra: Vec::new(),
            owned,
        };
        self.assets.sweep();
        self.bend_loaded(&sv, scene)?;
        match self.renderer.gpu.take_error() {
            Some(e) => Err(FrameError::Device(e).into()),
            None => Ok(sv),
        }
    }

    /// Objects whose fur has a spring stand where their mesh was loaded (a CPU pose), but
    /// unbent: each is posed again there on the GPU, which bends its fur
    /// ([`poses::ObjectPose::bend`]), as every later pose does.
    fn bend_loaded(&self, sv: &SceneView, scene: &Scene) -> Result<(), RenderError> {
        for (object, o) in scene.objects.iter().enumerate() {
            let springy = sv
                .poses
                .get(object)
                .is_some_and(|p| p.as_ref().is_some_and(poses::ObjectPose::has_springs));
            let loaded = sv
                .skins
                .get(object)
                .and_then(|s| s.as_ref())
                .and_then(|s| s.binding.loaded.clone());
            if let (true, Some(at)) = (springy, loaded) {
                self.pose_object(sv, object, &at.animation, at.time, &o.asset)
                    .map_err(|source| RenderError::Springs { object, source })?;
            }
        }
        Ok(())
    }

    /// Every object's mesh on the GPU, seen or not (a camera move must not upload), by mesh
    /// index, with what the registered features draw of it (`Feature::uploads`); and each
    /// object's posed copy of a GPU-skinned mesh, by scene object.
    fn upload_meshes(
        &mut self,
        scene: &Scene,
        meshes: &[MeshData],
        mesh_of: &[usize],
        scene_plan: &ScenePlan,
    ) -> Result<Uploaded, RenderError> {
        let mut gpu_meshes: Vec<Option<Arc<assets::GpuMesh>>> = vec![None; meshes.len()];
        for (k, m) in meshes.iter().enumerate() {
            if scene_plan.objects.iter().any(|(o, _)| o.mesh == k) {
                let uploads = FEATURES
                    .iter()
                    .filter_map(|f| f.uploads)
                    .fold(assets::Uploads::default(), |u, of| {
                        u.with(of(scene_plan, k, m))
                    });
                gpu_meshes[k] = Some(self.assets.mesh(&self.renderer, m, uploads));
            }
        }
        let (mut object_poses, mut skins) = (Vec::new(), Vec::new());
        for (i, (o, &k)) in scene.objects.iter().zip(mesh_of).enumerate() {
            let spring = scene_plan
                .objects
                .iter()
                .find(|(p, _)| p.scene_index == i)
                .and_then(|(p, _)| p.fur)
                .and_then(|f| f.spring.map(|s| (s, f.length)));
            let pose = gpu_meshes[k].as_ref().and_then(|shared| {
                poses::ObjectPose::new(&self.renderer, shared, &meshes[k], spring)
            });
            let skin = match &pose {
                Some(p) => {
                    GpuSkinned::for_pose(&self.renderer, p, &meshes[k]).map_err(|source| {
                        RenderError::Skin {
                            asset: Some(o.asset.clone()),
                            source,
                        }
                    })?
                }
                None => None,
            };
            object_poses.push(pose);
            skins.push(skin);
        }
        Ok((gpu_meshes, object_poses, skins))
    }

    /// Knobs or size changed: a new scene plan and plan for `scene` (its camera included),
    /// new targets if they no longer fit, the uniforms written. Uploads no asset.
    pub fn update(
        &mut self,
        sv: &mut SceneView,
        scene: &Scene,
        mode: Mode,
    ) -> Result<(), RenderError> {
        sv.replan(scene, mode)?;
        let inputs = SceneInputs {
            scene,
            plan: &sv.scene_plan,
            sky: sv.sky.as_deref(),
        };
        for s in FEATURES.iter().filter_map(|f| f.scene) {
            (s.follow)(&self.renderer, &inputs, &mut sv.owned)?;
        }
        LightingInputs::gather(&self.renderer, FEATURES, &mut sv.owned);
        self.refresh(sv);
        Ok(())
    }

    /// The camera moved: only the camera-dependent plan and the uniforms change.
    pub fn look(&mut self, sv: &mut SceneView, camera: &scene::Camera) -> Result<(), RenderError> {
        sv.look(camera)?;
        self.refresh(sv);
        Ok(())
    }

    /// Shifts the view's projection by `(dx, dy)` output pixels from `base` (the view without
    /// jitter) and rewrites the uniforms: one sample of jittered supersampling.
    pub fn jitter(&self, sv: &mut SceneView, base: &view::View, (dx, dy): (f32, f32)) {
        let (w, h) = sv.plan.output;
        let shift = glam::Mat4::from_translation(glam::Vec3::new(
            2.0 * dx / w as f32,
            -2.0 * dy / h as f32,
            0.0,
        ));
        sv.plan.view = view::View {
            proj: shift * base.proj,
            ..*base
        };
        self.refresh(sv);
    }

    fn refresh(&self, sv: &mut SceneView) {
        let spec = sv.spec();
        if spec != sv.targets.spec {
            sv.targets = ViewTargets::new(&self.renderer, spec, &targets());
        }
        for e in &mut sv.extra {
            let spec = TargetSpec::of(&e.plan, e.targets.spec.color_format, true, &targets());
            if spec != e.targets.spec {
                e.targets = ViewTargets::new(&self.renderer, spec, &targets());
            }
        }
        let plans: Vec<&Plan> = std::iter::once(&sv.plan)
            .chain(sv.extra.iter().map(|e| &e.plan))
            .collect();
        sv.data.write_views(&self.renderer, &plans);
    }

    /// Adds a view of the same scene from `camera`, drawn in the same frame by
    /// [`Preview::render_views`] into targets of its own (PNG output), with uniform slots of
    /// its own; returns its index.
    pub fn add_view(
        &mut self,
        sv: &mut SceneView,
        camera: &scene::Camera,
    ) -> Result<usize, RenderError> {
        let (w, h) = sv.scene_plan.output;
        let size = scene::Size {
            width: w,
            height: h,
        };
        let plan = Plan::with_camera(&sv.scene_plan, &view::View::of(camera, size))?;
        let spec = TargetSpec::of(&plan, renderer::OUTPUT_FORMAT, true, &targets());
        sv.extra.push(scene_view::ExtraView {
            camera: *camera,
            plan,
            targets: ViewTargets::new(&self.renderer, spec, &targets()),
        });
        self.refresh(sv);
        Ok(sv.view_count() - 1)
    }

    /// Renders every view of `sv` in one frame (one submission) and reads each back.
    pub fn render_views(&self, sv: &SceneView) -> Result<Vec<Image>, RenderError> {
        let frames = (0..sv.view_count())
            .map(|v| sv.view_frame(v))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(frame::render_many(&self.renderer, &frames)?)
    }

    /// Renders one frame into the view's own target and reads it back.
    pub fn render(&self, sv: &SceneView) -> Result<Image, RenderError> {
        let f = sv.own_frame()?;
        let target = sv
            .targets
            .color
            .as_ref()
            .ok_or_else(|| features::MissingInput {
                pass: "output",
                what: "a colour target".into(),
            })?;
        Ok(frame::render(&self.renderer, &f, target)?)
    }

    /// Renders one frame into the view's own target and waits for the device (no readback).
    pub fn draw(&self, sv: &SceneView) -> Result<(), RenderError> {
        frame::draw(&self.renderer, &sv.own_frame()?)?;
        Ok(frame::wait(&self.renderer)?)
    }

    /// Poses every object of `sv` that draws a GPU-skinned mesh at `time` s of the clip
    /// `animation` (one skinning dispatch per skinned primitive, then the fins), before the
    /// frames that draw it. Returns how many objects were posed.
    pub fn pose(
        &self,
        sv: &SceneView,
        animation: &str,
        time: f32,
        path: &std::path::Path,
    ) -> Result<usize, PoseError> {
        let mut n = 0;
        for object in 0..sv.skins.len() {
            n += usize::from(self.pose_object(sv, object, animation, time, path)?);
        }
        Ok(n)
    }

    /// Poses scene object `object` alone at `time` s of `animation`: objects sharing one
    /// animated asset stand at their own times in one frame. Returns whether the object draws
    /// a GPU-skinned mesh (false: nothing to pose).
    pub fn pose_object(
        &self,
        sv: &SceneView,
        object: usize,
        animation: &str,
        time: f32,
        path: &std::path::Path,
    ) -> Result<bool, PoseError> {
        let skin = sv.skins.get(object).ok_or(PoseError::NoObject {
            object,
            count: sv.skins.len(),
        })?;
        let Some(skin) = skin else {
            return Ok(false);
        };
        let m = skin.binding.matrices(path, animation, time)?;
        if let Some(Some(p)) = sv.poses.get(object) {
            p.bend(&self.renderer, &skin.binding, path, (animation, time))?;
        }
        skin.pose(&self.renderer, &m)?;
        Ok(true)
    }

    /// Renders one frame into `view` (a window's surface texture, in the view's format).
    pub fn draw_into(&self, sv: &SceneView, view: &wgpu::TextureView) -> Result<(), RenderError> {
        let f = sv.frame(Output {
            view,
            format: sv.targets.spec.color_format,
        });
        Ok(frame::draw(&self.renderer, &f)?)
    }

    /// Times frames into the view's own target (see [`frame::time`]).
    pub fn time(
        &self,
        sv: &SceneView,
        warmup: usize,
        frames: usize,
    ) -> Result<Timings, RenderError> {
        Ok(frame::time(
            &self.renderer,
            &sv.own_frame()?,
            warmup,
            frames,
        )?)
    }

    /// Bytes written to GPU buffers and textures since the last call.
    pub fn take_uploaded(&self) -> u64 {
        self.renderer.gpu.take_uploaded()
    }
}
