//! GPU-visible structs. Keep in sync with `shaders/common.wgsl` (Frame, Object, Light,
//! VertexIn): same field order, same sizes, 16-byte aligned.

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};
use pelt_scene::shading::Emitter;

pub use pelt_scene::vertex::{FinInstance, FurVertex, MAX_FORWARD_LIGHTS, StrandRoot, Vertex};

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
    /// The wind: xyz its world direction × strength (all zero: none), w the scene's time (s).
    pub wind: [f32; 4],
    /// The wind's x gust frequency (Hz), y turbulence (0 to 1); zw unused.
    pub gust: [f32; 4],
}

/// One material's factors. Keep in sync with `MaterialParams` in shaders/common.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct MaterialUniforms {
    /// x: `normalTexture.scale`; y: `metallicFactor`; z: `roughnessFactor`; w: unused.
    pub factors: [f32; 4],
    /// x: the material has a normal texture (1) or not (0); y: a base colour texture; z: a
    /// metallic-roughness texture; w: unused.
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
    /// x opacity; y specular strength; z the distance map; w fur colour from the base colour
    /// texture (1) or not (0).
    pub params: [f32; 4],
    /// Fur: rgb root colour (linear, times the object's colour), w fur length.
    pub fur_base: [f32; 4],
    /// Fur: rgb tip colour, w heightfield UV scale.
    pub fur_tip: [f32; 4],
    /// Fur: x rim strength, y rim falloff (Listing 2.3), z strand fade width (in shell depth),
    /// w WBOIT weight scale.
    pub fur_params: [f32; 4],
    /// Fur: the strand model as a medium: x κ = Σ 2r / Σ π r² (per tile width), y mean strand
    /// diameter (tile widths), z coverage (0 analytic, 1 binary heightfield), w deferred fur
    /// lighting (0 Kajiya-Kay, 1 Revie's normals).
    pub fur_model: [f32; 4],
    /// x object ID (1..255); y stipple pattern (0 opaque, 1..3); z the fur's outer-shell ID;
    /// w shell count.
    pub ids: [u32; 4],
    /// rgb F0 (mirror) or tint (glass); a: −1 mirror, 0 diffuse, the IOR for glass
    /// (GPU Gems 3 Listing 17-5's sign convention).
    pub optics: [f32; 4],
}

/// One light. Keep in sync with `Light` in shaders/common.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct LightUniforms {
    /// A point or spot light's position and radius; a directional light's unit direction
    /// toward it and 0 ([`LightUniforms::new`]).
    pub position_radius: [f32; 4],
    /// rgb colour × intensity; w intensity × luminance(colour).
    pub color: [f32; 4],
    /// x: the light's shadow-cube slot + 1 (0: it casts none); yzw unused.
    pub shadow: [u32; 4],
    /// A spot light's cone (`Emitter::cone`); (0, 0, 0, 1) for the other kinds.
    pub cone: [f32; 4],
}

impl LightUniforms {
    /// `emitter` of linear `color` × intensity in the space `to_space` maps world space to
    /// (a rigid transform), with its shadow-map slot.
    pub fn new(emitter: &Emitter, color: Vec3, to_space: Mat4, shadow: Option<u32>) -> Self {
        let position_radius = emitter.packed(to_space);
        let lum = color.dot(Vec3::new(0.2126, 0.7152, 0.0722));
        LightUniforms {
            position_radius: position_radius.into(),
            color: color.extend(lum).into(),
            shadow: [shadow.map_or(0, |s| s + 1), 0, 0, 0],
            cone: emitter.cone(to_space).into(),
        }
    }
}

/// Uniform buffer offsets are multiples of this (wgpu's default limit).
pub const UNIFORM_STRIDE: u64 = 256;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_match_the_wgsl_layouts() {
        // WGSL: Frame = 2 mat4 + 7 vec4 = 240; Object = 2 mat4 + 8 vec4 = 256; Light = 4 vec4 = 64.
        assert_eq!(size_of::<FrameUniforms>(), 240);
        assert_eq!(size_of::<ObjectUniforms>(), 256);
        assert_eq!(size_of::<FurVertex>(), 56);
        assert_eq!(size_of::<FinInstance>(), 128);
        assert_eq!(size_of::<LightUniforms>(), 64);
        assert_eq!(size_of::<Vertex>(), 52);
        assert_eq!(size_of::<MaterialUniforms>(), 32);
        assert!(size_of::<ObjectUniforms>() as u64 <= UNIFORM_STRIDE);
        // Within WebGL2's and wgpu's downlevel limit on a uniform binding (16 KiB).
        assert_eq!(MAX_FORWARD_LIGHTS * size_of::<LightUniforms>(), 16384);
    }
}
