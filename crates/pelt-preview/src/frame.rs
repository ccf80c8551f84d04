//! Running a plan: encode the passes in order, submit, read the image back; and timing whole
//! frames (wall clock, after warm-up) and single passes (GPU timestamps where the back end's
//! are real time, Vulkan; wall time per separately submitted pass elsewhere, as on GL
//! llvmpipe whose timestamps are wrong).

use std::path::Path;
use std::time::Instant;

use crate::draw::DrawData;
use crate::passes::{
    Timestamps, composite_pass, forward_pass, fur_accum_pass, geometry_pass, light_pass,
    material_pass, obliterate_pass,
};
use crate::plan::Pass;
use crate::renderer::Renderer;

/// Errors from the device while rendering.
#[derive(Debug, thiserror::Error)]
pub enum FrameError {
    /// wgpu reported a validation or out-of-memory error.
    #[error("the GPU device reported an error: {0}")]
    Device(String),
    /// Reading the image back failed.
    #[error("reading the image back failed: {0}")]
    Readback(String),
    /// Writing the PNG failed.
    #[error("{path}: {message}")]
    Write {
        /// The file.
        path: String,
        /// What failed.
        message: String,
    },
}

/// An 8-bit sRGB RGBA image.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Rows top to bottom, 4 bytes per pixel.
    pub rgba: Vec<u8>,
}

impl Image {
    /// Pixel (x, y).
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = ((y * self.width + x) * 4) as usize;
        [
            self.rgba[i],
            self.rgba[i + 1],
            self.rgba[i + 2],
            self.rgba[i + 3],
        ]
    }

    /// PNG bytes (deterministic: no timestamps or text chunks).
    pub fn png(&self) -> Vec<u8> {
        let mut out = Vec::new();
        {
            let mut enc = png::Encoder::new(&mut out, self.width, self.height);
            enc.set_color(png::ColorType::Rgba);
            enc.set_depth(png::BitDepth::Eight);
            #[expect(
                clippy::expect_used,
                reason = "encoding into a Vec cannot fail for a well-sized image"
            )]
            let mut w = enc.write_header().expect("png header");
            #[expect(
                clippy::expect_used,
                reason = "the buffer holds exactly width × height pixels"
            )]
            w.write_image_data(&self.rgba).expect("png data");
        }
        out
    }

    /// Writes the PNG atomically (nothing is left behind on failure).
    pub fn save(&self, path: &Path) -> Result<(), FrameError> {
        pelt_io::glb::write_atomic(path, &self.png()).map_err(|e| FrameError::Write {
            path: path.display().to_string(),
            message: e.to_string(),
        })
    }
}

fn encode_pass(
    r: &Renderer,
    d: &DrawData,
    pass: Pass,
    enc: &mut wgpu::CommandEncoder,
    ts: Timestamps<'_>,
) {
    match pass {
        Pass::Geometry => {
            if let Some(g) = &d.gbuffer {
                geometry_pass(enc, r, d, g, ts);
            }
        }
        Pass::Light => {
            if let (Some(g), Some(l)) = (&d.gbuffer, &d.lbuffer) {
                light_pass(enc, r, d, g, l, ts);
            }
        }
        Pass::Material => material_pass(enc, r, d, &d.output, ts),
        Pass::Forward => forward_pass(enc, r, d, &d.output, ts),
        Pass::Obliterate => {
            if let Some(c) = &d.composition {
                obliterate_pass(enc, r, d, c, ts);
            }
        }
        Pass::FurAccum => {
            if let Some(o) = &d.oit {
                fur_accum_pass(enc, r, d, o, ts);
            }
        }
        Pass::Composite => {
            if let Some(o) = &d.oit {
                composite_pass(enc, r, d, o, &d.output, ts);
            }
        }
    }
}

fn encoder(r: &Renderer) -> wgpu::CommandEncoder {
    r.gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("frame"),
        })
}

/// How long a frame may take before the device counts as hung.
const FRAME_LIMIT: std::time::Duration = std::time::Duration::from_secs(600);

/// Waits for the submitted work. wgpu's GL back end gives up on a fence after a few seconds
/// even when asked to wait indefinitely, which a heavy frame on llvmpipe can take; such
/// timeouts are waited out again, up to [`FRAME_LIMIT`].
fn wait(r: &Renderer) -> Result<(), FrameError> {
    let start = Instant::now();
    loop {
        match r.gpu.device.poll(wgpu::PollType::wait_indefinitely()) {
            Ok(_) => return Ok(()),
            Err(wgpu::PollError::Timeout) if start.elapsed() < FRAME_LIMIT => {}
            Err(e) => return Err(FrameError::Device(e.to_string())),
        }
    }
}

/// Encodes and submits one whole frame.
fn submit_frame(r: &Renderer, d: &DrawData) {
    let mut enc = encoder(r);
    for &p in &d.plan.passes {
        encode_pass(r, d, p, &mut enc, None);
    }
    r.gpu.queue.submit([enc.finish()]);
}

/// Renders one frame and reads it back.
pub fn render(r: &Renderer, d: &DrawData) -> Result<Image, FrameError> {
    let device = &r.gpu.device;
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    submit_frame(r, d);
    let image = read_back(r, &d.output.color.texture, d.output.size)?;
    if let Some(e) = pollster::block_on(scope.pop()) {
        return Err(FrameError::Device(e.to_string()));
    }
    if let Some(e) = r.gpu.take_error() {
        return Err(FrameError::Device(e));
    }
    Ok(image)
}

/// Maps a `MAP_READ` buffer whose copy was submitted, waiting for the device.
fn map_read(r: &Renderer, buffer: &wgpu::Buffer) -> Result<wgpu::BufferView, FrameError> {
    let fail = |e: &dyn std::fmt::Display| FrameError::Readback(e.to_string());
    let (tx, rx) = std::sync::mpsc::channel();
    buffer.slice(..).map_async(wgpu::MapMode::Read, move |res| {
        let _ = tx.send(res);
    });
    wait(r)?;
    rx.recv().map_err(|e| fail(&e))?.map_err(|e| fail(&e))?;
    buffer.slice(..).get_mapped_range().map_err(|e| fail(&e))
}

/// Copies a 4-byte-per-texel texture (RGBA8, Rg16Uint, …) to the CPU, rows top to bottom,
/// removing the 256-byte row padding.
pub fn read_back(
    r: &Renderer,
    texture: &wgpu::Texture,
    (w, h): (u32, u32),
) -> Result<Image, FrameError> {
    let device = &r.gpu.device;
    let row = w * 4;
    let padded =
        row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: u64::from(padded) * u64::from(h),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut enc = encoder(r);
    enc.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(padded),
                rows_per_image: Some(h),
            },
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
    r.gpu.queue.submit([enc.finish()]);
    let mapped = map_read(r, &buffer)?;
    let mut rgba = Vec::with_capacity((row * h) as usize);
    for y in 0..h as usize {
        let start = y * padded as usize;
        rgba.extend_from_slice(&mapped[start..start + row as usize]);
    }
    drop(mapped);
    buffer.unmap();
    Ok(Image {
        width: w,
        height: h,
        rgba,
    })
}

/// How pass times were measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PassClock {
    /// GPU timestamp queries (Vulkan).
    Gpu,
    /// Wall time around each pass submitted and waited for on its own.
    Wall,
}

/// Medians over timed frames, in milliseconds.
#[derive(Debug, Clone, PartialEq)]
pub struct Timings {
    /// Whole frames: encode, submit, wait.
    pub frame_ms: f64,
    /// Each pass.
    pub passes: Vec<(Pass, f64)>,
    /// How the pass times were taken.
    pub clock: PassClock,
    /// Frames timed (after warm-up).
    pub frames: usize,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() { 0.0 } else { v[v.len() / 2] }
}

/// Times `frames` frames after `warmup` untimed ones.
pub fn time(
    r: &Renderer,
    d: &DrawData,
    warmup: usize,
    frames: usize,
) -> Result<Timings, FrameError> {
    let device = &r.gpu.device;
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    for _ in 0..warmup {
        submit_frame(r, d);
        wait(r)?;
    }
    let mut whole = Vec::with_capacity(frames);
    for _ in 0..frames {
        let t = Instant::now();
        submit_frame(r, d);
        wait(r)?;
        whole.push(t.elapsed().as_secs_f64() * 1e3);
    }
    let passes = &d.plan.passes;
    let mut per: Vec<Vec<f64>> = vec![Vec::with_capacity(frames); passes.len()];
    let clock = if r.gpu.timestamps {
        let n = passes.len() as u32 * 2;
        let set = device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("pass times"),
            ty: wgpu::QueryType::Timestamp,
            count: n,
        });
        let bytes = u64::from(n) * 8;
        let resolve = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamps"),
            size: bytes,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let read = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("timestamps read"),
            size: bytes,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let period = f64::from(r.gpu.queue.get_timestamp_period());
        for _ in 0..frames {
            let mut enc = encoder(r);
            for (i, &p) in passes.iter().enumerate() {
                let ts = Some(wgpu::RenderPassTimestampWrites {
                    query_set: &set,
                    beginning_of_pass_write_index: Some(2 * i as u32),
                    end_of_pass_write_index: Some(2 * i as u32 + 1),
                });
                encode_pass(r, d, p, &mut enc, ts);
            }
            enc.resolve_query_set(&set, 0..n, &resolve, 0);
            enc.copy_buffer_to_buffer(&resolve, 0, &read, 0, bytes);
            r.gpu.queue.submit([enc.finish()]);
            {
                let m = map_read(r, &read)?;
                let t: &[u64] = bytemuck::cast_slice(&m);
                for (i, v) in per.iter_mut().enumerate() {
                    v.push(t[2 * i + 1].saturating_sub(t[2 * i]) as f64 * period / 1e6);
                }
            }
            read.unmap();
        }
        PassClock::Gpu
    } else {
        for _ in 0..frames {
            for (i, &p) in passes.iter().enumerate() {
                let t = Instant::now();
                let mut enc = encoder(r);
                encode_pass(r, d, p, &mut enc, None);
                r.gpu.queue.submit([enc.finish()]);
                wait(r)?;
                per[i].push(t.elapsed().as_secs_f64() * 1e3);
            }
        }
        PassClock::Wall
    };
    if let Some(e) = pollster::block_on(scope.pop()) {
        return Err(FrameError::Device(e.to_string()));
    }
    Ok(Timings {
        frame_ms: median(whole),
        passes: passes
            .iter()
            .copied()
            .zip(per.into_iter().map(median))
            .collect(),
        clock,
        frames,
    })
}
