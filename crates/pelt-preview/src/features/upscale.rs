//! Resampling one 2D view into a target of another size with bilinear filtering in linear
//! light (upscale.wgsl): `pelt view`'s frame budget scales a reduced-resolution frame up to
//! the window (the full-quality still frame is drawn straight into the window and never
//! passes through here).

use crate::feature::{Feature, Output};
use crate::layout::{self, FILTERABLE, LayoutDesc};
use crate::pass::Pass;
use crate::recipe::{Color, Recipe, Step};
use crate::renderer::{PipelineDesc, Renderer};
use crate::shaders::ShaderDesc;
use crate::targets::Target;

/// A frame to scale up and its sampler (upscale.wgsl).
pub const LAYOUT: LayoutDesc = LayoutDesc {
    label: "upscale source",
    entries: &[
        layout::texture(0, FILTERABLE, layout::D2),
        layout::sampler(1),
    ],
};

/// Bind-group slots of upscale.wgsl.
pub mod slot {
    /// The frame to scale and its sampler.
    pub const SOURCE: u32 = 0;
    /// The target's size.
    pub const SIZE: u32 = 1;
}

/// upscale.wgsl.
pub const SHADER: ShaderDesc = ShaderDesc::fullscreen("upscale.wgsl", "fs_main");

/// The upscale shader's pipeline.
pub fn pipeline() -> PipelineDesc {
    PipelineDesc::fullscreen(SHADER, vec![LAYOUT, layout::SIZE], None)
}

/// A reduced-resolution frame scaled up to a window (`pelt view`'s frame budget; drawn on request, never planned).
pub const PASS: Pass = Pass::new("upscale");

/// The upscale feature.
pub const FEATURE: Feature = Feature {
    pipelines: || vec![pipeline()],
    ..Feature::named("upscale")
};

/// What the pass reads: one source frame into one target size.
#[derive(Debug)]
pub struct Upscale {
    source: wgpu::BindGroup,
    size: wgpu::BindGroup,
}

impl Upscale {
    /// Reads `source` into targets of `size`.
    pub fn new(r: &Renderer, source: &Target, size: (u32, u32)) -> Upscale {
        Upscale::from_view(r, &source.view, size)
    }

    /// Reads the 2D view `source` into targets of `size`.
    pub fn from_view(r: &Renderer, source: &wgpu::TextureView, size: (u32, u32)) -> Upscale {
        let device = &r.gpu.device;
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("upscale"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            ..Default::default()
        });
        let (w, h) = (size.0 as f32, size.1 as f32);
        let buffer = r.gpu.buffer_init(
            "upscale size",
            bytemuck::cast_slice(&[w, h, 1.0 / w, 1.0 / h]),
            wgpu::BufferUsages::UNIFORM,
        );
        Upscale {
            source: r.group(
                "upscale source",
                &LAYOUT,
                &[
                    wgpu::BindingResource::TextureView(source),
                    wgpu::BindingResource::Sampler(&sampler),
                ],
            ),
            size: r.group("upscale size", &layout::SIZE, &[buffer.as_entire_binding()]),
        }
    }

    /// The pass drawing the source over `output`.
    pub fn pass<'a>(&'a self, output: Output<'a>) -> Recipe<'a> {
        self.pass_as(PASS, output)
    }

    /// [`Upscale::pass`] under another pass's name (a same-size copy: [`super::resolve`]).
    pub fn pass_as<'a>(&'a self, pass: Pass, output: Output<'a>) -> Recipe<'a> {
        let mut r = Recipe::new(
            pass,
            vec![Color {
                view: output.view,
                format: output.format,
                load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
            }],
            None,
        );
        r.pipeline(pipeline());
        r.bind(slot::SOURCE, &self.source, None);
        r.bind(slot::SIZE, &self.size, None);
        r.push(Step::Draw(0..3, 0..1));
        r
    }
}
