//! The vertex records the preview draws from, built on the CPU by asset loading and read by
//! the renderer's vertex stages. Keep in sync with `VertexIn` in shaders/common.wgsl, `FurIn`
//! in shaders/fur_common.wgsl and `FinIn` in shaders/fins.wgsl (the shader-validation test
//! checks each pipeline's vertex-buffer layout against its entry point's inputs).

use bytemuck::{Pod, Zeroable};

/// One vertex. Keep in sync with `VertexIn` in shaders/common.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Vertex {
    /// Position in the asset's space.
    pub position: [f32; 3],
    /// Normal in the asset's space.
    pub normal: [f32; 3],
    /// Linear base colour and alpha (the primitive's material factor).
    pub albedo: [f32; 4],
    /// Normal-group ID (`_NORMAL_GROUP`, 0 when absent).
    pub group: u32,
    /// The TEXCOORD set the primitive's material samples (0, 0 when absent).
    pub uv: [f32; 2],
}

/// The per-vertex fur attributes (vertex buffer 1 of the fur pipelines). Keep in sync with
/// `FurIn` in shaders/fur_common.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct FurVertex {
    /// TANGENT in the asset's space (w = handedness).
    pub tangent: [f32; 4],
    /// TEXCOORD_0.
    pub uv: [f32; 2],
    /// `_FUR_COMB`: tangent-space comb direction, w = length (0 = no fur).
    pub comb: [f32; 4],
    /// xyz: the springs' bend of the comb in the asset's space, added to the combed direction
    /// (`crate::springs`): zero at rest and wherever no spring moves the fur. w: the length
    /// scale, the asset's units per mesh unit across the surface at this vertex (its node
    /// transforms' scale along the normal; 1 without a scaling node), which the fur length
    /// and the comb length, both in mesh units, are multiplied by.
    pub bend: [f32; 4],
}

impl FurVertex {
    /// A vertex without fur.
    pub const NONE: FurVertex = FurVertex {
        tangent: [1.0, 0.0, 0.0, 1.0],
        uv: [0.0; 2],
        comb: [1.0, 0.0, 0.0, 0.0],
        bend: [0.0, 0.0, 0.0, 1.0],
    };

    /// The comb length in the asset's units per unit of fur length: the baked length (0..1)
    /// times the length scale (shaders/fur_common.wgsl's `comb_length`).
    pub fn comb_length(&self) -> f32 {
        self.comb[3] * self.bend[3]
    }
}

/// One fin edge, expanded for the fin quads (an instanced vertex buffer). Keep in sync with
/// `FinIn` in shaders/fins.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct FinInstance {
    /// Position of the edge's first vertex.
    pub p0: [f32; 3],
    /// Position of the second.
    pub p1: [f32; 3],
    /// Vertex normal at the first.
    pub n0: [f32; 3],
    /// Vertex normal at the second.
    pub n1: [f32; 3],
    /// Object-space comb direction and length at the first.
    pub c0: [f32; 4],
    /// At the second.
    pub c1: [f32; 4],
    /// Geometric normal of the first face beside the edge.
    pub f0: [f32; 3],
    /// Of the second (the first again on a boundary edge).
    pub f1: [f32; 3],
    /// x: the fin texture's horizontal offset; y: the edge's length in UV units.
    pub u: [f32; 2],
    /// Normal group of the first vertex.
    pub group: u32,
    /// Linear base colour under the edge's midpoint: the vertex albedo times the material's
    /// base colour texture (the fur's colour when it comes from the texture).
    pub albedo: [f32; 3],
}

/// The most lights the forward reference takes in one pass (`MAX_FORWARD_LIGHTS` in
/// shaders/forward.wgsl).
pub const MAX_FORWARD_LIGHTS: usize = 256;

/// One explicit strand of the strand reference (an instance of shaders/strands.wgsl, whose
/// vertex stage builds its segments). Keep in sync with `StrandIn` in shaders/strands.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct StrandRoot {
    /// Root position in the asset's space; w = height, a fraction of the fur length.
    pub root: [f32; 4],
    /// Surface normal at the root; w = comb length (`_FUR_COMB`'s w).
    pub normal: [f32; 4],
    /// Object-space comb direction at the root; w = radius in the asset's units.
    pub comb: [f32; 4],
    /// Lean in the asset's units per unit of height (the model's lean through the UV
    /// mapping); w = the strand's tint value.
    pub lean: [f32; 4],
    /// Linear base colour at the root.
    pub albedo: [f32; 4],
}
