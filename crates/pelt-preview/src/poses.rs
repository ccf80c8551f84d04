//! Poses belong to objects, not to the asset cache. The cache shares one mesh between every
//! object that draws the same bytes, so the skinning passes must not write into it: each
//! object drawing a GPU-skinned mesh gets its own vertex, fur-vertex and fin buffers (the
//! index buffer, materials and fur textures stay shared), and its own skinning bindings that
//! write them. Two objects sharing one animated asset can then stand at two times of a clip
//! in one frame. Created with the scene's view ([`crate::SceneView`]), posed per frame by
//! [`crate::Preview::pose_object`].

use std::sync::Arc;

use crate::asset::MeshData;
use crate::assets::{GpuFur, GpuMesh};
use crate::features::skin::{GpuSkinned, SkinError, SkinTargets};
use crate::renderer::{PipelineError, Renderer};

/// One object's posed copy of a skinned mesh.
#[derive(Debug)]
pub struct ObjectPose {
    /// The mesh as this object draws it: its own vertex, fur-vertex and fin buffers, the
    /// shared mesh's indices, materials and fur textures.
    pub mesh: GpuMesh,
    skinned: GpuSkinned,
}

impl ObjectPose {
    /// The posed copy of `shared` (the cache's upload of `m`) for one object, at the rest
    /// pose until [`ObjectPose::pose`]; `None` when `m` is not skinned on the GPU. Fins that
    /// could not follow the skin are an error.
    pub fn new(r: &Renderer, shared: &GpuMesh, m: &MeshData) -> Result<Option<Self>, SkinError> {
        let Some(binding) = &m.skin else {
            return Ok(None);
        };
        let usage = wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE;
        let upload = |label: &str, bytes: &[u8]| r.gpu.buffer_init(label, bytes, usage);
        let vertices = upload("posed vertices", bytemuck::cast_slice(&m.vertices));
        let fur = match (&shared.fur, &m.fur) {
            (Some(f), Some(data)) => Some(GpuFur {
                vertices: upload("posed fur vertices", bytemuck::cast_slice(&data.vertices)),
                fins: f
                    .fins
                    .as_ref()
                    .map(|_| upload("posed fins", bytemuck::cast_slice(&data.fins))),
                fin_count: f.fin_count,
                textures: f.textures.clone(),
            }),
            _ => None,
        };
        let skinned = GpuSkinned::new(
            r,
            Arc::clone(binding),
            SkinTargets {
                vertices: &vertices,
                fur: fur.as_ref().map(|f| &f.vertices),
                fins: fur.as_ref().and_then(|f| {
                    f.fins
                        .as_ref()
                        .zip(m.fur.as_ref().map(|d| d.fins.as_slice()))
                }),
            },
        )?;
        let mesh = GpuMesh {
            vertices,
            indices: shared.indices.clone(),
            count: shared.count,
            parts: shared.parts.clone(),
            materials: shared.materials.clone(),
            fur,
            groups: shared.groups.clone(),
        };
        Ok(Some(ObjectPose { mesh, skinned }))
    }

    /// The rig this object is posed with.
    pub fn binding(&self) -> &pelt_scene::skin::SkinBinding {
        &self.skinned.binding
    }

    /// Skins this object's copy at `matrices` ([`pelt_scene::skin::SkinBinding::matrices`])
    /// and rebuilds its fins; submitted now, before the frames that draw it.
    pub fn pose(
        &self,
        r: &Renderer,
        matrices: &[pelt_scene::skin::RangeMatrices],
    ) -> Result<(), PipelineError> {
        self.skinned.pose(r, matrices)
    }
}
