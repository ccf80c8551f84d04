//! Poses belong to objects, not to the asset cache. The cache shares one mesh between every
//! object that draws the same bytes, so the skinning passes must not write into it: each
//! object drawing a GPU-skinned mesh gets its own vertex, fur-vertex and fin buffers (the
//! index buffer, materials and fur textures stay shared) for the skinning feature
//! (`features::skin::GpuSkinned`, kept beside it by the scene's view) to write. Two objects
//! sharing one animated asset can then stand at two times of a clip in one frame. Created
//! with the scene's view ([`crate::SceneView`]), posed per frame by
//! [`crate::Preview::pose_object`]. An object whose fur has a spring also keeps its springs
//! here (`pelt_scene::springs`: the clip's periodic state and a playhead), and each pose writes
//! their bends into its fur vertices.

use std::sync::{Arc, Mutex};

use pelt_anim::spring::Spring;
use pelt_scene::skin::SkinBinding;
use pelt_scene::springs::FurSprings;

use crate::asset::MeshData;
use crate::assets::{GpuFur, GpuMesh};
use crate::renderer::Renderer;
use crate::uniforms::FurVertex;

/// One object's posed copy of a skinned mesh.
#[derive(Debug)]
pub struct ObjectPose {
    /// The mesh as this object draws it: its own vertex, fur-vertex and fin buffers, the
    /// shared mesh's indices, materials and fur textures.
    pub mesh: GpuMesh,
    springs: Option<PoseSprings>,
}

/// An object's fur springs: the fur records as loaded (the bends are written over them, the
/// skinning pass then writes the tangents), the settings, and the springs of the clip last
/// played.
#[derive(Debug)]
struct PoseSprings {
    rest: Vec<FurVertex>,
    spring: Spring,
    length: f32,
    playing: Mutex<Option<FurSprings>>,
}

impl ObjectPose {
    /// The posed copy of `shared` (the cache's upload of `m`) for one object, at the rest
    /// pose until the skinning feature poses it, with `spring` moving fur of `length` asset
    /// units; `None` when `m` is not skinned on the GPU.
    pub fn new(
        r: &Renderer,
        shared: &GpuMesh,
        m: &MeshData,
        spring: Option<(Spring, f32)>,
    ) -> Option<Self> {
        m.skin.as_ref()?;
        let usage = wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE;
        let upload = |label: &str, bytes: &[u8]| r.gpu.buffer_init(label, bytes, usage);
        let vertices = upload("posed vertices", bytemuck::cast_slice(&m.vertices));
        let fur = match (&shared.fur, &m.fur) {
            (Some(f), Some(data)) => Some(GpuFur {
                // Written again by the springs' bends (`ObjectPose::bend`).
                vertices: r.gpu.buffer_init(
                    "posed fur vertices",
                    bytemuck::cast_slice(&data.vertices),
                    usage | wgpu::BufferUsages::COPY_DST,
                ),
                fins: f
                    .fins
                    .as_ref()
                    .map(|_| upload("posed fins", bytemuck::cast_slice(&data.fins))),
                fin_count: f.fin_count,
                textures: f.textures.clone(),
            }),
            _ => None,
        };
        let mesh = GpuMesh {
            vertices,
            indices: shared.indices.clone(),
            count: shared.count,
            parts: shared.parts.clone(),
            materials: shared.materials.clone(),
            fur,
            groups: shared.groups.clone(),
        };
        let springs = match (spring, &m.fur, &mesh.fur) {
            (Some((spring, length)), Some(data), Some(_)) if !spring.rigid() => Some(PoseSprings {
                rest: data.vertices.clone(),
                spring,
                length,
                playing: Mutex::new(None),
            }),
            _ => None,
        };
        Some(ObjectPose { mesh, springs })
    }

    /// Whether the object's fur has springs (its bends follow each pose).
    pub fn has_springs(&self) -> bool {
        self.springs.is_some()
    }

    /// Writes the springs' bends at `time` s of clip `animation` into the fur vertices (when
    /// the object's fur has a spring); submitted before the skinning pass, which then writes
    /// the skinned tangents into the same records. A clip other than the last one played
    /// starts its springs afresh.
    pub fn bend(
        &self,
        r: &Renderer,
        binding: &Arc<SkinBinding>,
        path: &std::path::Path,
        (animation, time): (&str, f32),
    ) -> Result<(), pelt_io::IoError> {
        let (Some(s), Some(fur)) = (&self.springs, &self.mesh.fur) else {
            return Ok(());
        };
        let mut playing = s
            .playing
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let springs = match playing.take() {
            Some(p) if p.plays(animation) => p,
            _ => FurSprings::new(binding, path, animation, s.spring, (s.length, s.rest.len()))?,
        };
        let springs = playing.insert(springs);
        let bends = springs.bends(time, &s.rest);
        let records: Vec<FurVertex> = s
            .rest
            .iter()
            .zip(&bends)
            .map(|(v, b)| FurVertex { bend: *b, ..*v })
            .collect();
        r.gpu
            .queue
            .write_buffer(&fur.vertices, 0, bytemuck::cast_slice(&records));
        Ok(())
    }
}
