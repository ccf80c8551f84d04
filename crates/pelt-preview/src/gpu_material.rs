//! Materials on the GPU: a mesh's base colour, normal and metallic-roughness textures
//! ([`pelt_scene::material`]) uploaded with their full mip chains, the glTF sampler's wrap
//! modes, and the factors, as one bind group of the Material layout (read by the G-buffer for
//! normal maps and by the material and forward passes for colour and specular). A slot the
//! material leaves empty binds a 1×1 neutral texture (white; the flat normal), so every
//! shader reads the same layout. The base colour view and sampler also go into the fur's
//! group (the asset cache), where shells take the colour under each strand.

use pelt_io::picture::{Rgba8, WrappingMode};
use pelt_scene::fur::Level;
use pelt_scene::material::{Material, Texture, mip_count, next_level};

use crate::layout::{D2, FILTERABLE, LayoutDesc, sampler, texture, uniform};
use crate::renderer::Renderer;
use crate::uniforms::MaterialUniforms;

/// One material's textures (base colour, normal, metallic-roughness), their samplers and
/// its factors (`material` in common.wgsl).
pub const LAYOUT: LayoutDesc = LayoutDesc {
    label: "material",
    entries: &[
        texture(0, FILTERABLE, D2),
        texture(1, FILTERABLE, D2),
        texture(2, FILTERABLE, D2),
        sampler(3),
        sampler(4),
        sampler(5),
        uniform(6, size_of::<MaterialUniforms>(), false),
    ],
};

/// sRGB base colour.
pub const BASE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// Linear data (normals, metallic-roughness).
pub const DATA_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// One material on the GPU.
#[derive(Debug, Clone)]
pub struct GpuMaterial {
    /// The Material-layout group.
    pub group: wgpu::BindGroup,
    /// Whether it has any texture: objects drawn with it use the pipelines whose shader
    /// samples them; the others read the neutral texels' values without sampling
    /// ([`TEXTURED`]).
    pub textured: bool,
    /// glTF's `doubleSided`: opaque draws of a single-sided material cull its back faces.
    pub double_sided: bool,
    /// The base colour texture (or the white texel).
    pub base_view: wgpu::TextureView,
    /// Its sampler.
    pub base_sampler: wgpu::Sampler,
}

fn address(w: WrappingMode) -> wgpu::AddressMode {
    match w {
        WrappingMode::ClampToEdge => wgpu::AddressMode::ClampToEdge,
        WrappingMode::MirroredRepeat => wgpu::AddressMode::MirrorRepeat,
        WrappingMode::Repeat => wgpu::AddressMode::Repeat,
    }
}

/// `image` and its full mip chain as a texture of `format` (sRGB averaging for
/// [`BASE_FORMAT`]), halved first where it is larger than the device's 2D texture limit
/// (an asset loaded with a larger `--max-texture` than the device takes). Levels are made
/// and written one at a time from the one above, so besides the image and the texture the
/// upload holds one level below it (a quarter of the image) and one staging band.
fn upload_image(
    r: &Renderer,
    label: &str,
    format: wgpu::TextureFormat,
    image: &Rgba8,
) -> wgpu::TextureView {
    let max = r.gpu.device.limits().max_texture_dimension_2d;
    let k = pelt_io::picture_bounded::halvings(image.width, image.height, max);
    let halved = (k > 1).then(|| pelt_io::picture_bounded::halve(image, k));
    let base = halved.as_ref().unwrap_or(image);
    let count = mip_count(base.width, base.height);
    let texture = r
        .gpu
        .texture_2d(label, format, (base.width, base.height), count);
    let mut below: Option<Rgba8> = None;
    for level in 0..count {
        let l = below.as_ref().unwrap_or(base);
        r.gpu.write_level(&texture, level, l.height, &l.pixels);
        if level + 1 < count {
            below = Some(next_level(l, format == BASE_FORMAT));
        }
    }
    texture.create_view(&wgpu::TextureViewDescriptor::default())
}

/// The override constant of the shaders that read a material (gbuffer.wgsl, material.wgsl,
/// forward.wgsl): true (their default) samples the material's textures, false reads the
/// neutral texels' values below without a fetch. Keep in sync with those shaders.
pub const TEXTURED: &str = "TEXTURED";

/// `desc` specialized for materials without textures ([`TEXTURED`] false).
pub fn untextured(desc: crate::renderer::PipelineDesc) -> crate::renderer::PipelineDesc {
    desc.with_constant(TEXTURED, Some(0.0))
}

/// `lit`'s pipelines for both kinds of material: as they are (textured) and
/// [`untextured`].
pub fn with_untextured(
    lit: impl IntoIterator<Item = crate::renderer::PipelineDesc>,
) -> Vec<crate::renderer::PipelineDesc> {
    lit.into_iter()
        .flat_map(|d| [d.clone(), untextured(d)])
        .collect()
}

/// A texture slot's view and sampler: the material's texture, or the 1×1 `neutral` texel.
fn slot(
    r: &Renderer,
    label: &str,
    t: Option<&Texture>,
    format: wgpu::TextureFormat,
    neutral: [u8; 4],
) -> (wgpu::TextureView, wgpu::Sampler) {
    let (view, wrap) = match t {
        Some(t) => (upload_image(r, label, format, &t.image), t.wrap),
        None => (
            r.gpu.upload_levels(
                label,
                format,
                &[Level {
                    width: 1,
                    height: 1,
                    texels: vec![neutral],
                }],
                |l| bytemuck::cast_slice(l).into(),
            ),
            [WrappingMode::Repeat; 2],
        ),
    };
    let sampler = r.gpu.device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some(label),
        address_mode_u: address(wrap[0]),
        address_mode_v: address(wrap[1]),
        address_mode_w: wgpu::AddressMode::Repeat,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        mipmap_filter: wgpu::MipmapFilterMode::Linear,
        anisotropy_clamp: 1,
        ..Default::default()
    });
    (view, sampler)
}

/// The factors of `m` as the shaders read them.
pub fn uniforms(m: &Material) -> MaterialUniforms {
    MaterialUniforms {
        factors: [m.normal_scale, m.metallic, m.roughness, 0.0],
        flags: [
            u32::from(m.normal.is_some()),
            u32::from(m.base_color.is_some()),
            u32::from(m.metallic_roughness.is_some()),
            0,
        ],
    }
}

/// Uploads `m`.
pub fn upload(r: &Renderer, m: &Material) -> GpuMaterial {
    let (base_view, base_sampler) = slot(
        r,
        "base colour",
        m.base_color.as_ref(),
        BASE_FORMAT,
        [255; 4],
    );
    let (normal_view, normal_sampler) = slot(
        r,
        "normal texture",
        m.normal.as_ref(),
        DATA_FORMAT,
        [128, 128, 255, 255],
    );
    let (mr_view, mr_sampler) = slot(
        r,
        "metallic-roughness",
        m.metallic_roughness.as_ref(),
        DATA_FORMAT,
        [255; 4],
    );
    let factors = r.gpu.buffer_init(
        "material factors",
        bytemuck::bytes_of(&uniforms(m)),
        wgpu::BufferUsages::UNIFORM,
    );
    let view = wgpu::BindingResource::TextureView;
    let sampler = wgpu::BindingResource::Sampler;
    let resources = [
        view(&base_view),
        view(&normal_view),
        view(&mr_view),
        sampler(&base_sampler),
        sampler(&normal_sampler),
        sampler(&mr_sampler),
        factors.as_entire_binding(),
    ];
    let group = r.group("material", &LAYOUT, &resources);
    GpuMaterial {
        group,
        textured: m.textured(),
        double_sided: m.double_sided,
        base_view,
        base_sampler,
    }
}
