//! Poses belong to objects, not to the asset cache. The cache shares one mesh between every
//! object that draws the same bytes, so the skinning passes must not write into it: each
//! object drawing a GPU-skinned mesh gets its own vertex, fur-vertex and fin buffers (the
//! index buffer, materials and fur textures stay shared) for the skinning feature
//! (`features::skin::GpuSkinned`, kept beside it by the scene's view) to write. Two objects
//! sharing one animated asset can then stand at two times of a clip in one frame. Created
//! with the scene's view ([`crate::SceneView`]), posed per frame by
//! [`crate::Preview::pose_object`].

use crate::asset::MeshData;
use crate::assets::{GpuFur, GpuMesh};
use crate::renderer::Renderer;

/// One object's posed copy of a skinned mesh.
#[derive(Debug)]
pub struct ObjectPose {
    /// The mesh as this object draws it: its own vertex, fur-vertex and fin buffers, the
    /// shared mesh's indices, materials and fur textures.
    pub mesh: GpuMesh,
}

impl ObjectPose {
    /// The posed copy of `shared` (the cache's upload of `m`) for one object, at the rest
    /// pose until the skinning feature poses it; `None` when `m` is not skinned on the GPU.
    pub fn new(r: &Renderer, shared: &GpuMesh, m: &MeshData) -> Option<Self> {
        m.skin.as_ref()?;
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
        let mesh = GpuMesh {
            vertices,
            indices: shared.indices.clone(),
            count: shared.count,
            parts: shared.parts.clone(),
            materials: shared.materials.clone(),
            fur,
            groups: shared.groups.clone(),
        };
        Some(ObjectPose { mesh })
    }
}
