//! The contracts every feature's passes share: the error a pass reports when an input is
//! missing, the named vertex-buffer and bind-group slots of the object passes (Kircher &
//! Lawrance §2's G-buffer, material and forward passes, Revie's shells and fins), their vertex
//! layouts and blends. Part of the renderer's core: features import it; it imports no
//! feature.

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
    /// The strand reference's shadow bits beside its roots.
    pub const TRACED: u32 = 1;
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

const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 5] = wgpu::vertex_attr_array![
    0 => Float32x3, 1 => Float32x3, 2 => Float32x4, 3 => Uint32, 7 => Float32x2
];
const FUR_ATTRIBUTES: [wgpu::VertexAttribute; 4] = wgpu::vertex_attr_array![
    4 => Float32x4, 5 => Float32x2, 6 => Float32x4, 8 => Float32x4
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
        Blend::Wboit => wboit_blends(),
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

/// Blends of the two OIT targets (McGuire & Bavoil): additive accumulation, revealage
/// dst × (1 − src).
pub fn wboit_blends() -> Vec<Option<wgpu::BlendState>> {
    let reveal = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Zero,
        dst_factor: wgpu::BlendFactor::OneMinusSrc,
        operation: wgpu::BlendOperation::Add,
    };
    vec![
        Some(ADD),
        Some(wgpu::BlendState {
            color: reveal,
            alpha: reveal,
        }),
    ]
}
