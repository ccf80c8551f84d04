//! Bind-group layouts as descriptors (re_renderer's `BindGroupLayoutDesc`): plain, const data
//! that a feature declares beside the shader that reads it. The renderer turns a descriptor
//! into a `wgpu::BindGroupLayout` once, through a cache keyed by its entries
//! ([`crate::Renderer::layout`]), so no layout is named in the renderer core and two
//! descriptors with the same entries share one layout. The shader-validation test checks
//! every pipeline's descriptors against the WGSL bindings.
//!
//! The layouts here are the ones several features read: the per-frame uniforms (frame,
//! object, lights, the forward light array, the outer-shell table), a view target with its DSF buffer, a target's size and a compute
//! pass's storage pair.

use crate::uniforms::{FrameUniforms, LightUniforms, MAX_FORWARD_LIGHTS, ObjectUniforms};

/// One bind-group layout: a label (for debuggers) and its entries, binding by binding.
#[derive(Debug, Clone, Copy)]
pub struct LayoutDesc {
    /// A name for debuggers and errors.
    pub label: &'static str,
    /// The entries.
    pub entries: &'static [wgpu::BindGroupLayoutEntry],
}

/// The cache key: the entries alone (equal entries make interchangeable layouts).
impl PartialEq for LayoutDesc {
    fn eq(&self, other: &Self) -> bool {
        self.entries == other.entries
    }
}

impl Eq for LayoutDesc {}

impl std::hash::Hash for LayoutDesc {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.entries.hash(state);
    }
}

/// A uniform buffer of `size` bytes at `binding`, seen by vertex and fragment stages.
pub const fn uniform(binding: u32, size: usize, dynamic: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: dynamic,
            min_binding_size: wgpu::BufferSize::new(size as u64),
        },
        count: None,
    }
}

/// A texture at `binding`, seen by the fragment stage.
pub const fn texture(
    binding: u32,
    sample_type: wgpu::TextureSampleType,
    view_dimension: wgpu::TextureViewDimension,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension,
            multisampled: false,
        },
        count: None,
    }
}

/// A storage buffer at `binding`, seen by the compute stage.
pub const fn storage(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

/// A filtering sampler at `binding`, seen by the fragment stage.
pub const fn sampler(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
        count: None,
    }
}

/// `entry` seen by `stages` instead.
pub const fn seen_by(
    stages: wgpu::ShaderStages,
    entry: wgpu::BindGroupLayoutEntry,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        visibility: stages,
        ..entry
    }
}

/// 2D float textures that are read texel by texel (not filtered).
pub const UNFILTERABLE: wgpu::TextureSampleType =
    wgpu::TextureSampleType::Float { filterable: false };
/// 2D float textures that are filtered.
pub const FILTERABLE: wgpu::TextureSampleType = wgpu::TextureSampleType::Float { filterable: true };
/// A 2D view.
pub const D2: wgpu::TextureViewDimension = wgpu::TextureViewDimension::D2;
/// A 2D-array view.
pub const D2_ARRAY: wgpu::TextureViewDimension = wgpu::TextureViewDimension::D2Array;

/// The frame uniforms (dynamic offset: one slot per view and resolution).
pub const FRAME: LayoutDesc = LayoutDesc {
    label: "frame",
    entries: &[uniform(0, size_of::<FrameUniforms>(), true)],
};

/// One object's uniforms (dynamic offset).
pub const OBJECT: LayoutDesc = LayoutDesc {
    label: "object",
    entries: &[uniform(0, size_of::<ObjectUniforms>(), true)],
};

/// One light (dynamic offset).
pub const LIGHT: LayoutDesc = LayoutDesc {
    label: "light",
    entries: &[uniform(0, size_of::<LightUniforms>(), true)],
};

/// Bytes of the table of which IDs are outer fur shells (`array<vec4<u32>, 64>`).
pub const SHELL_TABLE_BYTES: usize = 1024;

/// Which IDs are outer fur shells (the lights skip them; obliteration replaces them).
pub const SHELL_TABLE: LayoutDesc = LayoutDesc {
    label: "shell table",
    entries: &[uniform(0, SHELL_TABLE_BYTES, false)],
};

/// Every light of a view (forward lighting; dynamic offset: one array per view).
pub const LIGHT_ARRAY: LayoutDesc = LayoutDesc {
    label: "light array",
    entries: &[uniform(
        0,
        MAX_FORWARD_LIGHTS * size_of::<LightUniforms>(),
        true,
    )],
};

/// A float target read texel by texel and the DSF buffer beside it (G-buffer or L-buffer).
pub const TEXTURES: LayoutDesc = LayoutDesc {
    label: "target and dsf",
    entries: &[
        texture(0, UNFILTERABLE, D2),
        texture(1, wgpu::TextureSampleType::Uint, D2),
    ],
};

/// A target's size (w, h, 1/w, 1/h).
pub const SIZE: LayoutDesc = LayoutDesc {
    label: "size",
    entries: &[uniform(0, 16, false)],
};

/// An asset's fur textures (fur_common.wgsl), bound by the asset cache at upload: heightfield,
/// fin texture, their samplers, the base colour and its sampler, and the density's two
/// textures.
pub const FUR_TEXTURES: LayoutDesc = LayoutDesc {
    label: "fur textures",
    entries: &[
        texture(0, FILTERABLE, D2),
        texture(1, FILTERABLE, D2),
        sampler(2),
        sampler(3),
        texture(4, FILTERABLE, D2),
        sampler(5),
        texture(6, FILTERABLE, D2),
        texture(7, FILTERABLE, D2),
    ],
};

/// A cube-map sky and its sampler (sky.wgsl's `fs_cube`), bound by the asset cache at upload.
pub const SKY_CUBE: LayoutDesc = LayoutDesc {
    label: "sky cube",
    entries: &[
        texture(0, FILTERABLE, wgpu::TextureViewDimension::Cube),
        sampler(1),
    ],
};

/// A compute pass's storage buffers: binding 0 read, binding 1 read and written.
pub const STORAGE: LayoutDesc = LayoutDesc {
    label: "storage",
    entries: &[storage(0, true), storage(1, false)],
};

/// A bind-group entry of the first `size` bytes of `buffer` (a dynamic-offset uniform binds one
/// record of a buffer of many).
pub fn sized(buffer: &wgpu::Buffer, size: usize) -> wgpu::BindingResource<'_> {
    wgpu::BindingResource::Buffer(wgpu::BufferBinding {
        buffer,
        offset: 0,
        size: wgpu::BufferSize::new(size as u64),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn descriptors_with_equal_entries_are_one_key() {
        let renamed = LayoutDesc {
            label: "another name",
            ..FRAME
        };
        assert_eq!(renamed, FRAME);
        assert_ne!(FRAME, OBJECT);
        let mut set = std::collections::HashSet::new();
        set.insert(FRAME);
        assert!(set.contains(&renamed));
        assert!(!set.contains(&OBJECT));
    }
}
