//! GPU-visible structs. Keep in sync with `shaders/common.wgsl` (Frame, Object, Light,
//! VertexIn): same field order, same sizes, 16-byte aligned.

use bytemuck::{Pod, Zeroable};

/// Per-frame constants. Keep in sync with `Frame` in shaders/common.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct FrameUniforms {
    /// World to view.
    pub view: [[f32; 4]; 4],
    /// View to clip.
    pub proj: [[f32; 4]; 4],
    /// rgb ambient; w specular power.
    pub ambient: [f32; 4],
    /// The pass's target: w, h, 1/w, 1/h.
    pub target_size: [f32; 4],
    /// The L-buffer: w, h, 1/w, 1/h.
    pub lbuffer_size: [f32; 4],
    /// tan(fov_x/2), tan(fov_y/2), near, far.
    pub proj_params: [f32; 4],
    /// x DSF on; y forward light count; z DSF depth threshold floor in quantisation steps;
    /// w the frame has an L-buffer.
    pub flags: [u32; 4],
}

/// Per-object constants. Keep in sync with `Object` in shaders/common.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct ObjectUniforms {
    /// Object to world.
    pub model: [[f32; 4]; 4],
    /// Inverse transpose of `model`.
    pub normal_model: [[f32; 4]; 4],
    /// rgb colour multiplied into the vertex albedo.
    pub tint: [f32; 4],
    /// x opacity; y specular strength.
    pub params: [f32; 4],
    /// x object ID (1..255); y stipple pattern (0 opaque, 1..3).
    pub ids: [u32; 4],
}

/// One point light. Keep in sync with `Light` in shaders/common.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct LightUniforms {
    /// View-space position and radius.
    pub position_radius: [f32; 4],
    /// rgb colour × intensity; w intensity × luminance(colour).
    pub color: [f32; 4],
}

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
}

/// The most lights the forward reference takes in one pass (`MAX_FORWARD_LIGHTS` in
/// shaders/forward.wgsl).
pub const MAX_FORWARD_LIGHTS: usize = 256;

/// Uniform buffer offsets are multiples of this (wgpu's default limit).
pub const UNIFORM_STRIDE: u64 = 256;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_match_the_wgsl_layouts() {
        // WGSL: Frame = 2 mat4 + 5 vec4 = 208; Object = 2 mat4 + 3 vec4 = 176; Light = 32.
        assert_eq!(size_of::<FrameUniforms>(), 208);
        assert_eq!(size_of::<ObjectUniforms>(), 176);
        assert_eq!(size_of::<LightUniforms>(), 32);
        assert_eq!(size_of::<Vertex>(), 44);
        assert!(size_of::<ObjectUniforms>() as u64 <= UNIFORM_STRIDE);
        assert_eq!(MAX_FORWARD_LIGHTS * size_of::<LightUniforms>(), 8192);
    }
}
