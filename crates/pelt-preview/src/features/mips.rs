//! Mip chains of layered targets ([`crate::targets::LayeredTarget`]: cube faces and 2D
//! arrays): each level of each layer drawn from the level above by downsample.wgsl, whose
//! bilinear sample at a texel's centre is the 2×2 average above (box filter; in linear light
//! for sRGB formats). All levels of all layers go in one submission.

use crate::feature::{Feature, Output};
use crate::layout::{self, FILTERABLE, LayoutDesc};
use crate::pass::Pass;
use crate::recipe::{Color, Queries, Recipe, Step};
use crate::renderer::{PipelineDesc, Renderer};
use crate::shaders::ShaderDesc;
use crate::targets::LayeredTarget;

/// A 2D-array texture and its sampler: the level above (downsample.wgsl).
pub const LAYOUT: LayoutDesc = LayoutDesc {
    label: "array source",
    entries: &[
        layout::texture(0, FILTERABLE, layout::D2_ARRAY),
        layout::sampler(1),
    ],
};

/// Bind-group slots of downsample.wgsl.
pub mod slot {
    /// The level above, as a 2D array, and its sampler.
    pub const SOURCE: u32 = 0;
    /// 1 / the written level's size, and the layer.
    pub const PARAMS: u32 = 1;
}

/// downsample.wgsl.
pub const SHADER: ShaderDesc = ShaderDesc::fullscreen("downsample.wgsl", "fs_main");

/// The mips shader's pipeline.
pub fn pipeline() -> PipelineDesc {
    PipelineDesc::fullscreen(SHADER, vec![LAYOUT, layout::SIZE], None)
}

/// Mip levels of a layered target (drawn on request, never planned).
pub const PASS: Pass = Pass::new("mips");

/// The mips feature.
pub const FEATURE: Feature = Feature {
    pipelines: || vec![pipeline()],
    ..Feature::named("mips")
};

/// One level of one layer: its source group, its parameters and the view it writes.
struct Level {
    source: wgpu::BindGroup,
    params: wgpu::BindGroup,
    target: wgpu::TextureView,
}

fn level(r: &Renderer, t: &LayeredTarget, sampler: &wgpu::Sampler, layer: u32, mip: u32) -> Level {
    let above = t.texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        base_mip_level: mip - 1,
        mip_level_count: Some(1),
        array_layer_count: Some(t.layers),
        ..Default::default()
    });
    let (w, h) = t.mip_size(mip);
    let params = r.gpu.buffer_init(
        "downsample params",
        bytemuck::cast_slice(&[1.0 / w as f32, 1.0 / h as f32, layer as f32, 0.0]),
        wgpu::BufferUsages::UNIFORM,
    );
    Level {
        source: r.group(
            "downsample source",
            &LAYOUT,
            &[
                wgpu::BindingResource::TextureView(&above),
                wgpu::BindingResource::Sampler(sampler),
            ],
        ),
        params: r.group(
            "downsample params",
            &layout::SIZE,
            &[params.as_entire_binding()],
        ),
        target: t.layer(layer, mip),
    }
}

/// Fills mips 1.. of every layer of `t` from mip 0.
pub fn mip_chain(r: &Renderer, t: &LayeredTarget) -> Result<(), crate::FrameError> {
    let sampler = r.gpu.device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("downsample"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    });
    let mut enc = r
        .gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("mip chain"),
        });
    for mip in 1..t.mips {
        for layer in 0..t.layers {
            let l = level(r, t, &sampler, layer, mip);
            let out = Output {
                view: &l.target,
                format: t.format,
            };
            let mut recipe = Recipe::new(
                PASS,
                vec![Color {
                    view: out.view,
                    format: out.format,
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                }],
                None,
            );
            recipe.pipeline(pipeline());
            recipe.bind(slot::SOURCE, &l.source, None);
            recipe.bind(slot::PARAMS, &l.params, None);
            recipe.push(Step::Draw(0..3, 0..1));
            r.prepare(recipe.keys())?;
            recipe.encode(r, &mut enc, Queries::default())?;
        }
    }
    r.gpu.queue.submit([enc.finish()]);
    Ok(())
}
