//! Reading the device's results back to the CPU, part of the renderer's core: waiting for
//! submitted work, mapped buffer and texture copies, and the 8-bit sRGB [`Image`] a frame is
//! read back as (saved as PNG); the errors the device reports while rendering.

use std::path::Path;
use std::time::Instant;

use crate::draw::MissingInput;
use crate::renderer::{PipelineError, Renderer};

/// Errors from the device while rendering.
#[derive(Debug, thiserror::Error)]
pub enum FrameError {
    /// wgpu reported a validation or out-of-memory error.
    #[error("the GPU device reported an error: {0}")]
    Device(String),
    /// Reading the image back failed.
    #[error("reading the image back failed: {0}")]
    Readback(String),
    /// A planned pass lacks a target or resource.
    #[error(transparent)]
    Missing(#[from] MissingInput),
    /// A pipeline could not be made.
    #[error(transparent)]
    Pipeline(#[from] PipelineError),
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
    /// Tiles of one size laid out `cols` to a row, left to right, top to bottom (black where a
    /// row is short). Empty when there are no tiles.
    pub fn contact_sheet(tiles: &[Image], cols: u32) -> Image {
        let (tw, th) = tiles.first().map_or((0, 0), |t| (t.width, t.height));
        let cols = cols.clamp(1, tiles.len().max(1) as u32);
        let rows = (tiles.len() as u32).div_ceil(cols);
        let mut sheet = Image {
            width: tw * cols,
            height: th * rows,
            rgba: vec![0; (tw * cols * th * rows * 4) as usize],
        };
        for (k, tile) in tiles.iter().enumerate() {
            let (x, y) = ((k as u32 % cols) * tw, (k as u32 / cols) * th);
            for row in 0..tile.height.min(th) {
                let src = (row * tile.width * 4) as usize;
                let dst = (((y + row) * sheet.width + x) * 4) as usize;
                let n = (tile.width.min(tw) * 4) as usize;
                sheet.rgba[dst..dst + n].copy_from_slice(&tile.rgba[src..src + n]);
            }
        }
        sheet
    }

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

/// How long a frame may take before the device counts as hung.
const FRAME_LIMIT: std::time::Duration = std::time::Duration::from_secs(600);

/// Waits for the submitted work. wgpu's GL back end gives up on a fence after a few seconds
/// even when asked to wait indefinitely, which a heavy frame on llvmpipe can take; such
/// timeouts are waited out again, up to [`FRAME_LIMIT`].
pub fn wait(r: &Renderer) -> Result<(), FrameError> {
    let start = Instant::now();
    loop {
        match r.gpu.device.poll(wgpu::PollType::wait_indefinitely()) {
            Ok(_) => return Ok(()),
            Err(wgpu::PollError::Timeout) if start.elapsed() < FRAME_LIMIT => {}
            Err(e) => return Err(FrameError::Device(e.to_string())),
        }
    }
}

/// A buffer of `bytes` that queries resolve into, and the mappable buffer it is copied to.
pub fn query_buffers(r: &Renderer, label: &str, bytes: u64) -> (wgpu::Buffer, wgpu::Buffer) {
    let buffer = |suffix: &str, usage| {
        r.gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(&format!("{label}{suffix}")),
            size: bytes,
            usage,
            mapped_at_creation: false,
        })
    };
    (
        buffer(
            "",
            wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
        ),
        buffer(
            " read",
            wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        ),
    )
}

/// Maps a `MAP_READ` buffer whose copy was submitted, waiting for the device.
pub fn map_read(r: &Renderer, buffer: &wgpu::Buffer) -> Result<wgpu::BufferView, FrameError> {
    let fail = |e: &dyn std::fmt::Display| FrameError::Readback(e.to_string());
    let (tx, rx) = std::sync::mpsc::channel();
    buffer.slice(..).map_async(wgpu::MapMode::Read, move |res| {
        let _ = tx.send(res);
    });
    wait(r)?;
    rx.recv().map_err(|e| fail(&e))?.map_err(|e| fail(&e))?;
    buffer.slice(..).get_mapped_range().map_err(|e| fail(&e))
}

/// The bytes of `buffer` (a buffer with `COPY_SRC` usage), through a mapped copy.
pub fn read_buffer(r: &Renderer, buffer: &wgpu::Buffer) -> Result<Vec<u8>, FrameError> {
    let staging = r.gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("read buffer"),
        size: buffer.size(),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut enc = encoder(r);
    enc.copy_buffer_to_buffer(buffer, 0, &staging, 0, buffer.size());
    r.gpu.queue.submit([enc.finish()]);
    let bytes = map_read(r, &staging)?.to_vec();
    staging.unmap();
    Ok(bytes)
}

/// Copies a 4-byte-per-texel texture (RGBA8, Rg16Uint, …) to the CPU, rows top to bottom,
/// removing the 256-byte row padding.
pub fn read_back(
    r: &Renderer,
    texture: &wgpu::Texture,
    size: (u32, u32),
) -> Result<Image, FrameError> {
    read_back_layer(r, texture, 0, 0, size)
}

/// [`read_back`] of one layer and mip level (`size` is that level's).
pub fn read_back_layer(
    r: &Renderer,
    texture: &wgpu::Texture,
    layer: u32,
    mip: u32,
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
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: mip,
            origin: wgpu::Origin3d {
                x: 0,
                y: 0,
                z: layer,
            },
            aspect: wgpu::TextureAspect::All,
        },
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

/// A command encoder for one frame's (or one read-back's) work.
pub fn encoder(r: &Renderer) -> wgpu::CommandEncoder {
    r.gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("frame"),
        })
}
