//! Progressive refinement: a view rendered again and again with its projection jittered
//! within the pixel (the R2 sequence), every sample averaged in linear light, so that an
//! image with sub-pixel detail (the explicit strands of `Mode::Strands`) converges while the
//! camera is still. `pelt view --mode strands` shows the running mean and restarts on any
//! change; the strand reference (pelt-measure) uses the same jitter. The mean lives on the
//! CPU (f64 sums, so thousands of samples lose nothing) and is uploaded once per sample into
//! an sRGB texture the upscale pass copies to the window.

use crate::draw::MissingInput;
use crate::feature::Output;
use crate::features::upscale::Upscale;
use crate::frame::FrameError;
use crate::view::View;
use crate::{Image, Preview, RenderError, Renderer, SceneView};
use pelt_scene::shading::{linear_of_srgb8, srgb8};

/// The R2 sequence (Roberts 2018) in [-0.5, 0.5)²: sample `i`'s offset within the pixel.
/// Its even and odd terms are each low-discrepancy, so both halves cover the pixel.
pub fn jitter(i: u32) -> (f32, f32) {
    const A1: f64 = 0.754_877_666_246_692_7;
    const A2: f64 = 0.569_840_290_998_053_3;
    let n = f64::from(i);
    let f = |a: f64| ((0.5 + n * a).fract() - 0.5) as f32;
    (f(A1), f(A2))
}

/// A running mean of jittered frames of one view, and the texture that shows it.
#[derive(Debug)]
pub struct Progressive {
    size: (u32, u32),
    sum: Vec<[f64; 3]>,
    samples: u32,
    /// The view without jitter, taken at the first sample after a restart.
    base: Option<View>,
    linear: [f32; 256],
    texture: wgpu::Texture,
    upscale: Upscale,
}

impl Progressive {
    /// An empty mean for frames of `size`, shown into targets of `output` size.
    pub fn new(r: &Renderer, size: (u32, u32), output: (u32, u32)) -> Progressive {
        let texture = r.gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("progressive mean"),
            size: wgpu::Extent3d {
                width: size.0.max(1),
                height: size.1.max(1),
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8UnormSrgb,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        Progressive {
            size,
            sum: vec![[0.0; 3]; (size.0 * size.1) as usize],
            samples: 0,
            base: None,
            linear: std::array::from_fn(|i| linear_of_srgb8(i as u8)),
            upscale: Upscale::from_view(r, &view, output),
            texture,
        }
    }

    /// The frame size it averages.
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// Samples per pixel so far.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Forgets every sample (the camera, the scene or the window changed). `sv` keeps
    /// whatever jitter it has until the next [`Progressive::step`] or [`Progressive::stop`].
    pub fn restart(&mut self) {
        self.sum.iter_mut().for_each(|s| *s = [0.0; 3]);
        self.samples = 0;
        self.base = None;
    }

    /// Renders one more sample of `sv` (its own colour target, of this mean's size), adds
    /// it and uploads the new mean.
    pub fn step(&mut self, preview: &Preview, sv: &mut SceneView) -> Result<(), RenderError> {
        if sv.plan.output != self.size {
            return Err(MissingInput {
                pass: "progressive",
                what: format!(
                    "a {}×{} view (got {}×{})",
                    self.size.0, self.size.1, sv.plan.output.0, sv.plan.output.1
                ),
            }
            .into());
        }
        let base = *self.base.get_or_insert(sv.plan.view);
        preview.jitter(sv, &base, jitter(self.samples));
        let img = preview.render(sv)?;
        for (acc, p) in self.sum.iter_mut().zip(img.rgba.chunks_exact(4)) {
            for c in 0..3 {
                acc[c] += f64::from(self.linear[p[c] as usize]);
            }
        }
        self.samples += 1;
        self.upload(&preview.renderer);
        Ok(())
    }

    /// Puts `sv`'s projection back without jitter.
    pub fn stop(&self, preview: &Preview, sv: &mut SceneView) {
        if let Some(base) = &self.base {
            preview.jitter(sv, base, (0.0, 0.0));
        }
    }

    /// The mean so far as an image (black before the first sample).
    pub fn image(&self) -> Image {
        let n = f64::from(self.samples.max(1));
        let rgba = self
            .sum
            .iter()
            .flat_map(|s| {
                let [r, g, b] = s.map(|v| srgb8((v / n) as f32));
                [r, g, b, 255]
            })
            .collect();
        Image {
            width: self.size.0,
            height: self.size.1,
            rgba,
        }
    }

    fn upload(&self, r: &Renderer) {
        let img = self.image();
        r.gpu.queue.write_texture(
            self.texture.as_image_copy(),
            &img.rgba,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(4 * self.size.0),
                rows_per_image: None,
            },
            wgpu::Extent3d {
                width: self.size.0,
                height: self.size.1,
                depth_or_array_layers: 1,
            },
        );
    }

    /// Draws the mean into `output` (the window's texture).
    pub fn show(&self, r: &Renderer, output: Output<'_>) -> Result<(), FrameError> {
        crate::frame::upscale(r, &self.upscale, output)
    }
}
