//! One module per feature of the renderer. Each owns its shaders' pipeline layouts
//! ([`spec`] dispatches to them) and builds its passes, or its part of shared passes, as
//! [`Recipe`]s from a frame's inputs:
//!
//! - [`geometry`]: opaque geometry into the G-buffer (Kircher & Lawrance §2.1);
//! - [`lights`]: scissored point lights into the L-buffer (§2.2);
//! - [`material`]: the material pass with DSF (§2.3, §3), which draws what the other features
//!   put at output resolution;
//! - [`alpha`]: stippled alpha (§4);
//! - [`fur`]: Revie's deferred fur: base and outer shell in the G-buffer, stipple
//!   obliteration, shells and fins;
//! - [`wboit`]: weighted blended OIT accumulation and composite (McGuire & Bavoil);
//! - [`sky`]: procedural and cube-map skies;
//! - [`forward`]: the forward reference;
//! - [`upscale`]: a reduced-resolution frame scaled up to a window (`pelt view`);
//! - [`resolve`]: the half-float scene colour the fur's layers blend into, to the output;
//! - [`mips`]: mip chains of layered targets (cube faces, arrays);
//! - [`overlay`]: `pelt view`'s text overlay;
//! - [`reflect`]: mirrors and glass from layered distance maps (GPU Gems 3 ch. 17);
//! - [`strands`]: explicit strands, the converged fur reference;
//! - [`skin`]: the skinning compute pass (glTF linear blend skinning) into storage buffers;
//! - [`debug`]: the debug views (normal groups, the decoded comb).
//!
//! Each module declares its shaders, bind-group layouts and pipelines as descriptors and one
//! [`registry::Feature`], listed in [`registry::FEATURES`].

pub mod alpha;
pub mod debug;
pub mod forward;
pub mod fur;
pub mod geometry;
pub mod lights;
pub mod material;
pub mod mips;
pub mod overlay;
pub mod reflect;
pub mod registry;
pub mod resolve;
pub mod skin;
pub mod sky;
pub mod strands;
pub mod upscale;
pub mod wboit;

use std::sync::Arc;

use crate::assets::{GpuMesh, GpuSky, GpuStrands};
use crate::frame_data::{FrameData, Res};
use crate::plan::Plan;
use crate::poses::ObjectPose;
use crate::recipe::{Recipe, Step};
use crate::targets::ViewTargets;
use crate::uniforms::{FurVertex, Vertex};

/// Vertex-buffer slots of the passes that draw meshes: the index of each buffer in the
/// pipelines' `PipelineSpec::vertex_buffers` (whose layouts the shader-validation test checks
/// against the shaders' `VertexIn` and `FurIn`); keep the two in step.
pub mod vertex_slot {
    /// The mesh's vertex records (`Vertex`).
    pub const MESH: u32 = 0;
    /// The fur vertex records (`FurVertex`) beside the mesh's.
    pub const FUR: u32 = 1;
    /// The instance records of a pass that draws instances alone (fins, strand roots).
    pub const INSTANCES: u32 = 0;
}

/// Bind-group slots of the passes that draw objects (G-buffer, material, forward, shells,
/// fins). Keep in sync with the `@group` numbers of those shaders (checked by the
/// shader-validation test).
pub mod slot {
    /// Frame constants.
    pub const FRAME: u32 = 0;
    /// One object's constants.
    pub const OBJECT: u32 = 1;
    /// How the object is lit: the L-buffer and DSF buffer, or the forward light array.
    pub const LIGHTING: u32 = 2;
    /// The fur's heightfield and fin texture.
    pub const FUR: u32 = 3;
    /// The material's textures and factors in the material and forward passes.
    pub const MATERIAL: u32 = 3;
    /// The material's textures and factors in the G-buffer pass (its normal map).
    pub const GBUFFER_MATERIAL: u32 = 2;
}

/// A planned pass lacks something it needs.
#[derive(Debug, thiserror::Error)]
#[error("the {pass} pass needs {what}, which this frame does not have")]
pub struct MissingInput {
    /// The pass.
    pub pass: &'static str,
    /// What is missing.
    pub what: String,
}

/// The output colour a frame renders into.
#[derive(Debug, Clone, Copy)]
pub struct Output<'a> {
    /// The view (a window's surface texture, or the view's own colour target).
    pub view: &'a wgpu::TextureView,
    /// Its format.
    pub format: wgpu::TextureFormat,
}

/// Everything one frame of one view draws from.
#[derive(Debug, Clone, Copy)]
pub struct Frame<'a> {
    /// The CPU decisions.
    pub plan: &'a Plan,
    /// The meshes, by the plan's mesh index (None: not uploaded, no object uses it).
    pub meshes: &'a [Option<Arc<GpuMesh>>],
    /// Each scene object's posed copy of its mesh, by scene index (None: not skinned).
    pub poses: &'a [Option<ObjectPose>],
    /// The cube-map sky, when the scene has one.
    pub sky: Option<&'a GpuSky>,
    /// The view's targets.
    pub targets: &'a ViewTargets,
    /// The frame's uniforms.
    pub data: &'a FrameData,
    /// Where the image goes.
    pub output: Output<'a>,
    /// Which view of the frame's uniforms this is (0 for a single view).
    pub view: usize,
    /// The scene's distance maps, when it has mirrors or glass.
    pub maps: Option<&'a reflect::Maps>,
    /// Explicit strands by mesh index (the strand reference; empty in other modes).
    pub strands: &'a [Option<Arc<GpuStrands>>],
}

impl<'a> Frame<'a> {
    /// Object `k`'s mesh (its own posed copy where it has one).
    pub fn mesh(&self, pass: &'static str, k: usize) -> Result<&'a GpuMesh, MissingInput> {
        let o = &self.plan.objects[k];
        self.object_mesh(pass, o.scene_index, o.mesh)
    }

    /// The mesh scene object `scene_index` draws: its posed copy where it has one, else the
    /// shared mesh `mesh`.
    pub fn object_mesh(
        &self,
        pass: &'static str,
        scene_index: usize,
        mesh: usize,
    ) -> Result<&'a GpuMesh, MissingInput> {
        if let Some(Some(p)) = self.poses.get(scene_index) {
            return Ok(&p.mesh);
        }
        self.meshes
            .get(mesh)
            .and_then(|m| m.as_deref())
            .ok_or_else(|| MissingInput {
                pass,
                what: format!("the mesh of objects[{scene_index}] on the GPU"),
            })
    }

    /// Binds object `k`'s uniforms.
    pub fn bind_object(&self, recipe: &mut Recipe<'a>, k: usize) {
        recipe.bind(
            slot::OBJECT,
            self.data.objects(),
            Some(self.data.object_offset(self.view, k)),
        );
    }

    /// Binds this view's frame constants at `res` (at the object passes' frame slot).
    pub fn bind_frame(&self, recipe: &mut Recipe<'a>, res: Res) {
        recipe.bind(
            slot::FRAME,
            self.data.frame(),
            Some(self.data.frame_offset(self.view, res)),
        );
    }

    /// Draws each object of `order` with the current pipeline, part by part, binding each
    /// part's material at `material` where the shader reads one (None: it reads none).
    pub fn draw_objects(
        &self,
        recipe: &mut Recipe<'a>,
        pass: &'static str,
        material: Option<u32>,
        order: &[usize],
    ) -> Result<(), MissingInput> {
        for &k in order {
            let mesh = self.mesh(pass, k)?;
            self.bind_object(recipe, k);
            recipe.push(Step::Vertices(vertex_slot::MESH, &mesh.vertices));
            recipe.push(Step::Indices(&mesh.indices));
            match material {
                Some(at) => {
                    for p in &mesh.parts {
                        recipe.bind(at, &mesh.materials[p.material].group, None);
                        recipe.push(Step::DrawIndexed(p.indices.clone(), 0..1));
                    }
                }
                None => recipe.push(Step::DrawIndexed(0..mesh.count, 0..1)),
            }
        }
        Ok(())
    }
}

const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 5] = wgpu::vertex_attr_array![
    0 => Float32x3, 1 => Float32x3, 2 => Float32x4, 3 => Uint32, 7 => Float32x2
];
const FUR_ATTRIBUTES: [wgpu::VertexAttribute; 3] = wgpu::vertex_attr_array![
    4 => Float32x4, 5 => Float32x2, 6 => Float32x4
];

/// Vertex buffer 0 of the object passes: [`Vertex`] (`VertexIn` in common.wgsl).
pub fn vertex_layout() -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: size_of::<Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &VERTEX_ATTRIBUTES,
    }
}

/// Vertex buffer 1 of the fur passes: [`FurVertex`] (`FurIn` in fur_common.wgsl).
pub fn fur_vertex_layout() -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: size_of::<FurVertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &FUR_ATTRIBUTES,
    }
}

/// Additive blending (light accumulation, OIT sums).
pub const ADD: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
};

/// Colour blend of an object shader drawn with `blend` into one target (`None`: replace;
/// `Over`: straight alpha; `Wboit`: accumulation and revealage).
pub fn object_blends(blend: crate::renderer::Blend) -> Vec<Option<wgpu::BlendState>> {
    use crate::renderer::Blend;
    match blend {
        Blend::None => vec![None],
        Blend::Over => vec![Some(wgpu::BlendState::ALPHA_BLENDING)],
        Blend::Wboit => wboit::blends(),
    }
}

/// Depth state of an object shader drawn with `blend`: opaque writes and tests "less",
/// blended layers test "less or equal" without writing.
pub fn object_depth(blend: crate::renderer::Blend) -> Option<(bool, wgpu::CompareFunction)> {
    match blend {
        crate::renderer::Blend::None => Some((true, wgpu::CompareFunction::Less)),
        _ => Some((false, wgpu::CompareFunction::LessEqual)),
    }
}
