//! A text overlay for `pelt view` (frame time, knobs, per-pass times) without a GUI toolkit:
//! lines of ASCII rasterized on the CPU with the public-domain 8×8 bitmap font of `font8x8`
//! into an R8 texture (uploaded only when the text changes), drawn by overlay.wgsl as a box
//! over the finished frame.

use crate::feature::{Feature, Output};
use crate::layout::{self, FILTERABLE, LayoutDesc};
use crate::pass::Pass;
use crate::recipe::{Color, Recipe, Step};
use crate::renderer::{PipelineDesc, Renderer};
use crate::shaders::ShaderDesc;

/// The overlay's text bitmap (overlay.wgsl).
pub const LAYOUT: LayoutDesc = LayoutDesc {
    label: "overlay text",
    entries: &[layout::texture(0, FILTERABLE, layout::D2)],
};

/// Bind-group slots of overlay.wgsl.
pub mod slot {
    /// The text bitmap.
    pub const TEXT: u32 = 0;
    /// Box corner and scale.
    pub const PARAMS: u32 = 1;
}

/// Font pixels of padding around the text.
const PAD: u32 = 4;

/// overlay.wgsl.
pub const SHADER: ShaderDesc = ShaderDesc::fullscreen("overlay.wgsl", "fs_main");

/// The overlay shader's pipeline.
pub fn pipeline() -> PipelineDesc {
    PipelineDesc::fullscreen(
        SHADER,
        vec![LAYOUT, layout::SIZE],
        Some(wgpu::BlendState::ALPHA_BLENDING),
    )
}

/// `pelt view`'s text overlay (drawn on request, never planned).
pub const PASS: Pass = Pass::new("overlay");

/// The overlay feature.
pub const FEATURE: Feature = Feature {
    pipelines: || vec![pipeline()],
    ..Feature::named("overlay")
};

/// `lines` rasterized: (width, height, one byte per pixel, 255 where the font has ink), with
/// [`PAD`] pixels around. Characters outside ASCII draw as `?`.
pub fn rasterize(lines: &[String]) -> (u32, u32, Vec<u8>) {
    let cols = lines.iter().map(|l| l.chars().count()).max().unwrap_or(0) as u32;
    let (w, h) = (cols * 8 + 2 * PAD, lines.len() as u32 * 10 + 2 * PAD);
    let mut px = vec![0u8; (w * h) as usize];
    for (row, line) in lines.iter().enumerate() {
        for (col, ch) in line.chars().enumerate() {
            let code = if ch.is_ascii() {
                ch as usize
            } else {
                '?' as usize
            };
            let glyph = font8x8::legacy::BASIC_LEGACY[code];
            for (gy, bits) in glyph.iter().enumerate() {
                for gx in 0..8 {
                    if bits & (1 << gx) != 0 {
                        let x = PAD + col as u32 * 8 + gx;
                        let y = PAD + row as u32 * 10 + gy as u32;
                        px[(y * w + x) as usize] = 255;
                    }
                }
            }
        }
    }
    (w, h, px)
}

/// The overlay's GPU state: the text texture (made again when the text changes) and its
/// placement.
#[derive(Debug)]
pub struct Overlay {
    text: Vec<String>,
    group: Option<wgpu::BindGroup>,
    params: wgpu::BindGroup,
}

impl Overlay {
    /// An empty overlay at the top-left corner, `scale` screen pixels per font pixel.
    pub fn new(r: &Renderer, scale: f32) -> Overlay {
        let buffer = r.gpu.buffer_init(
            "overlay params",
            bytemuck::cast_slice(&[8.0_f32, 8.0, scale, 0.0]),
            wgpu::BufferUsages::UNIFORM,
        );
        Overlay {
            text: Vec::new(),
            group: None,
            params: r.group(
                "overlay params",
                &layout::SIZE,
                &[buffer.as_entire_binding()],
            ),
        }
    }

    /// Shows `lines` (uploads only when they changed).
    pub fn set(&mut self, r: &Renderer, lines: Vec<String>) {
        if lines == self.text {
            return;
        }
        let (w, h, px) = rasterize(&lines);
        self.text = lines;
        if w == 0 || h == 0 {
            self.group = None;
            return;
        }
        let size = wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        };
        let texture = r.gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("overlay text"),
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        r.gpu.write_texture(
            texture.as_image_copy(),
            &px,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(w),
                rows_per_image: Some(h),
            },
            size,
        );
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        self.group = Some(r.group(
            "overlay text",
            &LAYOUT,
            &[wgpu::BindingResource::TextureView(&view)],
        ));
    }

    /// The pass drawing the text over `output` (None without text).
    pub fn pass<'a>(&'a self, output: Output<'a>) -> Option<Recipe<'a>> {
        let group = self.group.as_ref()?;
        let mut r = Recipe::new(
            PASS,
            vec![Color {
                view: output.view,
                format: output.format,
                load: wgpu::LoadOp::Load,
            }],
            None,
        );
        r.pipeline(pipeline());
        r.bind(slot::TEXT, group, None);
        r.bind(slot::PARAMS, &self.params, None);
        r.push(Step::Draw(0..3, 0..1));
        Some(r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_the_fonts_bits_with_padding() {
        let (w, h, px) = rasterize(&["A".into(), "b?".into()]);
        assert_eq!((w, h), (2 * 8 + 2 * PAD, 2 * 10 + 2 * PAD));
        let at = |x: u32, y: u32| px[(y * w + x) as usize] != 0;
        let a = font8x8::legacy::BASIC_LEGACY['A' as usize];
        for (gy, bits) in a.iter().enumerate() {
            for gx in 0..8u32 {
                assert_eq!(at(PAD + gx, PAD + gy as u32), bits & (1 << gx) != 0);
            }
        }
        // The padding and the gap between lines stay empty.
        assert!((0..w).all(|x| !at(x, 0) && !at(x, h - 1)));
        assert!((0..w).all(|x| !at(x, PAD + 8) && !at(x, PAD + 9)));
        // Outside ASCII: '?'.
        assert_eq!(rasterize(&["é".into()]).2, rasterize(&["?".into()]).2);
        assert_eq!(rasterize(&[]).0, 2 * PAD);
    }
}
