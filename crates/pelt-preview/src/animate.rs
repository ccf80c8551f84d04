//! An animated asset following its clock, with the skinning path chosen in one place: a mesh
//! the GPU can skin (`MeshData::skin`, attached by `asset::skinned` when the asset has
//! joints and NORMAL and no morph targets) keeps its upload and is skinned again on the GPU
//! for each pose (`features::skin`, Revie's fur drawn from the posed vertices); any other
//! mesh is posed on the CPU (`asset::posed`, the skinning `pelt pose` writes) and uploaded
//! again. `pelt render --frames`, `pelt demo` and `pelt view` all go through [`follow`].

use std::path::Path;

use pelt_io::Document;
use pelt_scene::asset::{self, AssetError, MeshData, PoseAt};

use crate::{Image, Mode, PoseError, Preview, RenderError, Scene, SceneView};

/// Why an animated asset could not be drawn at a pose.
#[derive(Debug, thiserror::Error)]
pub enum AnimateError {
    /// Skinning on the GPU failed (an unknown clip, a pipeline).
    #[error(transparent)]
    Pose(#[from] PoseError),
    /// Posing on the CPU failed.
    #[error(transparent)]
    Asset(#[from] AssetError),
    /// Preparing or drawing a frame failed.
    #[error(transparent)]
    Render(#[from] RenderError),
}

/// What the caller does after [`follow`].
#[derive(Debug)]
pub enum Followed {
    /// The GPU skinned every object of the views to the pose: draw them as they are. Views
    /// prepared later start at the loaded pose and need [`follow`] again.
    Skinned,
    /// The mesh cannot be skinned on the GPU: here it is posed on the CPU; prepare the views
    /// again from it.
    Upload(Box<MeshData>),
}

/// Brings the animated `mesh` (loaded from `doc`, at `path`) to `pose` in `views`.
pub fn follow(
    preview: &Preview,
    views: &[&SceneView],
    (mesh, doc, path): (&MeshData, &Document, &Path),
    pose: &PoseAt,
) -> Result<Followed, AnimateError> {
    if mesh.skin.is_none() {
        return Ok(Followed::Upload(Box::new(asset::posed(doc, pose)?)));
    }
    for sv in views {
        preview.pose(sv, &pose.animation, pose.time, path)?;
    }
    Ok(Followed::Skinned)
}

/// A scene whose mesh 0 is the animated asset at `path` (its rest document `doc`), loaded
/// at `poses[0]`, drawn at each of `poses`: prepared once when the GPU skins it, once per
/// later pose otherwise.
pub struct Clip<'a> {
    /// The scene; its camera stays where it is.
    pub scene: &'a Scene,
    /// The scene's meshes, mesh 0 loaded at the first pose.
    pub meshes: &'a [MeshData],
    /// Each object's mesh.
    pub mesh_of: &'a [usize],
    /// The animated asset's rest document and its path.
    pub doc: &'a Document,
    /// Where it was loaded from (the GPU skinning reads its clips there).
    pub path: &'a Path,
    /// The render mode.
    pub mode: Mode,
}

impl Clip<'_> {
    /// One image per pose, in order.
    pub fn frames(
        &self,
        preview: &mut Preview,
        poses: &[PoseAt],
    ) -> Result<Vec<Image>, AnimateError> {
        let mut meshes = self.meshes.to_vec();
        let mut view = preview.prepare_loaded(self.scene, &meshes, self.mesh_of, self.mode)?;
        let mut images = Vec::with_capacity(poses.len());
        for (i, pose) in poses.iter().enumerate() {
            // The first frame is drawn as loaded unless the GPU skins it: every frame of a
            // sheet then comes from one skinning path.
            if i > 0 || meshes[0].skin.is_some() {
                let asset = (&meshes[0], self.doc, self.path);
                if let Followed::Upload(m) = follow(preview, &[&view], asset, pose)? {
                    meshes[0] = *m;
                    view = preview.prepare_loaded(self.scene, &meshes, self.mesh_of, self.mode)?;
                }
            }
            // The wind blows at the frame's time.
            if self.scene.wind.is_some() {
                let mut at = self.scene.clone();
                at.time = pose.time;
                preview.update(&mut view, &at, self.mode)?;
            }
            images.push(preview.render(&view)?);
        }
        Ok(images)
    }
}

/// The time range (first key, last key) of clip `animation` of `doc`, checked against the rig.
pub fn clip_range(doc: &Document, animation: &str) -> Result<(f32, f32), pelt_io::IoError> {
    let rig = pelt_anim::Rig::load(doc)?;
    rig.clip(doc, animation).map(|c| (c.start, c.end))
}

/// `frames` moments spread evenly over `[start, end)` of `animation` (the last key is not
/// repeated: a cycle's end is its start).
pub fn spread(animation: &str, (start, end): (f32, f32), frames: u32) -> Vec<PoseAt> {
    (0..frames)
        .map(|i| PoseAt {
            animation: animation.to_owned(),
            time: start + (end - start) * i as f32 / frames.max(1) as f32,
        })
        .collect()
}
