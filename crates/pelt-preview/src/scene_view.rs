//! A scene on the GPU seen through one view: the three lifetimes of the renderer side by
//! side. The scene's meshes, fur and sky are shared GPU assets ([`crate::assets`], uploaded
//! once); the view's targets are its own ([`crate::targets`], made again when its size,
//! format or L-buffer scale changes); the frame's uniforms are written each frame
//! ([`crate::frame_data`]). The plan is split the same way: the [`ScenePlan`] changes with the
//! scene and its knobs, the [`Plan`] with the camera.

use std::sync::Arc;

use crate::assets::{GpuMesh, GpuSky};
use crate::draw::MissingInput;
use crate::feature::{Frame, Output};
use crate::features::registry::{FEATURES, targets};
use crate::features::skin::GpuSkinned;
use crate::frame_data::FrameData;
use crate::owned::Owned;
use crate::plan::{MeshInfo, Mode, Plan, ScenePlan};
use crate::poses::ObjectPose;
use crate::scene::{Camera, Scene};
use crate::targets::{TargetSpec, ViewTargets};
use crate::view::View;

/// Another camera on the same scene, drawn in the same frame into targets of its own, with
/// uniform slots of its own.
#[derive(Debug)]
pub struct ExtraView {
    /// Its camera.
    pub camera: Camera,
    /// Its plan.
    pub plan: Plan,
    /// Its targets (with a colour target of their own).
    pub targets: ViewTargets,
}

/// One scene, one view (and, for frames that draw several, extra views).
#[derive(Debug)]
pub struct SceneView {
    /// What each loaded mesh contributes to a plan.
    pub infos: Vec<MeshInfo>,
    /// Each scene object's mesh index.
    pub mesh_of: Vec<usize>,
    /// The camera-independent plan.
    pub scene_plan: ScenePlan,
    /// The current frame's plan.
    pub plan: Plan,
    /// The meshes on the GPU, by mesh index (None: no object draws it).
    pub meshes: Vec<Option<Arc<GpuMesh>>>,
    /// Each scene object's posed copy of its GPU-skinned mesh (None: not skinned).
    pub poses: Vec<Option<ObjectPose>>,
    /// The skinning that writes each posed copy, by scene object.
    pub skins: Vec<Option<GpuSkinned>>,
    /// The cube-map sky on the GPU.
    pub sky: Option<Arc<GpuSky>>,
    /// The view's targets.
    pub targets: ViewTargets,
    /// The frame's uniforms (view 0, then each extra view).
    pub data: FrameData,
    /// Views after the first, drawn in the same frame.
    pub extra: Vec<ExtraView>,
    /// State the scene's features own, read by every view (the mirror and glass objects'
    /// distance maps).
    pub owned: Owned,
}

impl SceneView {
    /// The frame, drawn into `output`.
    pub fn frame<'a>(&'a self, output: Output<'a>) -> Frame<'a> {
        Frame {
            plan: &self.plan,
            features: FEATURES,
            meshes: &self.meshes,
            poses: &self.poses,
            sky: self.sky.as_deref(),
            targets: &self.targets,
            data: &self.data,
            output,
            view: 0,
            scene: &self.owned,
        }
    }

    /// Views in the frame.
    pub fn view_count(&self) -> usize {
        1 + self.extra.len()
    }

    /// View `v`'s frame, drawn into its own colour target (view 0: [`SceneView::own_frame`]).
    pub fn view_frame(&self, v: usize) -> Result<Frame<'_>, MissingInput> {
        if v == 0 {
            return self.own_frame();
        }
        let e = self.extra.get(v - 1).ok_or_else(|| MissingInput {
            pass: "output",
            what: format!("view {v} (the frame has {})", self.view_count()),
        })?;
        let color = e.targets.color.as_ref().ok_or_else(|| MissingInput {
            pass: "output",
            what: format!("a colour target for view {v}"),
        })?;
        Ok(Frame {
            plan: &e.plan,
            features: FEATURES,
            meshes: &self.meshes,
            poses: &self.poses,
            sky: self.sky.as_deref(),
            targets: &e.targets,
            data: &self.data,
            output: Output {
                view: &color.view,
                format: color.format,
            },
            view: v,
            scene: &self.owned,
        })
    }

    /// The frame, drawn into the view's own colour target.
    pub fn own_frame(&self) -> Result<Frame<'_>, MissingInput> {
        let color = self.targets.color.as_ref().ok_or_else(|| MissingInput {
            pass: "output",
            what: "a colour target of the view's own (this view draws into a window)".into(),
        })?;
        Ok(self.frame(Output {
            view: &color.view,
            format: color.format,
        }))
    }

    /// The target spec the current plan needs.
    pub fn spec(&self) -> TargetSpec {
        TargetSpec::of(
            &self.plan,
            self.targets.spec.color_format,
            self.targets.spec.own_color,
            &targets(),
        )
    }

    /// A new scene plan for `scene` and `mode` (knobs changed), keeping the assets.
    pub fn replan(&mut self, scene: &Scene, mode: Mode) -> Result<(), crate::PlanError> {
        self.scene_plan = ScenePlan::new(scene, &self.infos, &self.mesh_of, mode);
        self.plan = Plan::with_camera(&self.scene_plan, &View::new(scene))?;
        for e in &mut self.extra {
            e.plan = Plan::with_camera(&self.scene_plan, &View::of(&e.camera, scene.output))?;
        }
        Ok(())
    }

    /// The current scene plan seen from `camera`.
    pub fn look(&mut self, camera: &Camera) -> Result<(), crate::PlanError> {
        let (w, h) = self.scene_plan.output;
        let size = crate::scene::Size {
            width: w,
            height: h,
        };
        self.plan = Plan::with_camera(&self.scene_plan, &View::of(camera, size))?;
        Ok(())
    }
}
