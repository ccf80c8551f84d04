//! Running a frame: the passes in order as recipes, their pipelines compiled, encoded,
//! submitted, the image read back; and timing whole frames (wall clock, after warm-up) and single passes (GPU timestamps where the back end's
//! are real time, Vulkan; wall time per separately submitted pass elsewhere, as on GL
//! llvmpipe whose timestamps are wrong).

use std::path::Path;
use std::time::Instant;

use crate::features::{self, Frame, MissingInput, registry};
use crate::plan::Pass;
use crate::recipe::Recipe;
use crate::renderer::{PipelineError, Renderer};
use crate::targets::Target;

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

/// Whether a frame renders the distance maps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Maps {
    /// Only when they are stale (the first frame, or the scene or its knobs changed): they
    /// depend on the scene, not on the camera.
    IfStale,
    /// Every frame (what a scene whose objects move would pay; the timing default).
    Always,
    /// Not in this frame (another view of the same frame renders them).
    Never,
}

/// The frame's passes in the plan's order, as recipes: each planned pass built by the
/// feature that registered it ([`features::registry::builder`]).
pub fn recipes<'a>(outer: &Frame<'a>, maps: Maps) -> Result<Vec<Recipe<'a>>, MissingInput> {
    let mut out = Vec::new();
    // Every pass before the resolve draws into the scene colour where the plan has one.
    let inner = &features::resolve::inner(outer)?;
    let fresh = match maps {
        Maps::IfStale => inner.maps.is_some_and(|m| m.fresh()),
        Maps::Always => false,
        Maps::Never => true,
    };
    for &p in &inner.plan.passes {
        let b = registry::builder(p).ok_or_else(|| MissingInput {
            pass: p.name(),
            what: "a feature that builds it (upscaling, mips and the overlay are drawn on request, never planned)".into(),
        })?;
        if b.maps && fresh {
            continue;
        }
        let f = match b.into {
            registry::DrawsInto::Scene => inner,
            registry::DrawsInto::Output => outer,
        };
        b.build.run(f, &mut out)?;
    }
    Ok(out)
}

/// Builds the frame's recipes and compiles the pipelines they use that are not cached yet.
fn prepared<'a>(r: &Renderer, f: &Frame<'a>, maps: Maps) -> Result<Vec<Recipe<'a>>, FrameError> {
    let recipes = recipes(f, maps)?;
    r.prepare(recipes.iter().flat_map(Recipe::keys))?;
    Ok(recipes)
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

/// Encodes and submits one whole frame.
fn submit_frame(r: &Renderer, recipes: &[Recipe<'_>]) -> Result<(), FrameError> {
    let mut enc = encoder(r);
    for p in recipes {
        p.encode(r, &mut enc, None)?;
    }
    r.gpu.queue.submit([enc.finish()]);
    Ok(())
}

/// Renders several views in one frame: every view's passes in one submission, then each
/// view's image read back (each frame must draw into its targets' own colour target).
pub fn render_many(r: &Renderer, frames: &[Frame<'_>]) -> Result<Vec<Image>, FrameError> {
    let scope = r.gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let mut all = Vec::new();
    for (i, f) in frames.iter().enumerate() {
        // The views share the scene's maps: the first renders them if they are stale.
        let maps = if i == 0 { Maps::IfStale } else { Maps::Never };
        all.extend(prepared(r, f, maps)?);
    }
    submit_frame(r, &all)?;
    if let Some(e) = pollster::block_on(scope.pop()) {
        return Err(FrameError::Device(e.to_string()));
    }
    if let Some(m) = frames.first().and_then(|f| f.maps) {
        m.mark_fresh();
    }
    frames
        .iter()
        .map(|f| {
            let target = f.targets.color.as_ref().ok_or_else(|| MissingInput {
                pass: "output",
                what: "a colour target of the view's own".into(),
            })?;
            read_back(r, &target.texture, f.plan.output)
        })
        .collect()
}

/// Renders one frame of `f` and submits it (into a window's surface, or the view's own
/// target), with device errors checked.
pub fn draw(r: &Renderer, f: &Frame<'_>) -> Result<(), FrameError> {
    let scope = r.gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let recipes = prepared(r, f, Maps::IfStale)?;
    submit_frame(r, &recipes)?;
    if let Some(e) = pollster::block_on(scope.pop()) {
        return Err(FrameError::Device(e.to_string()));
    }
    if let Some(m) = f.maps {
        m.mark_fresh();
    }
    if let Some(e) = r.gpu.take_error() {
        return Err(FrameError::Device(e));
    }
    Ok(())
}

/// Renders one frame into `target` (the view's own colour target) and reads it back.
pub fn render(r: &Renderer, f: &Frame<'_>, target: &Target) -> Result<Image, FrameError> {
    draw(r, f)?;
    read_back(r, &target.texture, f.plan.output)
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

impl Timings {
    /// Each pass as `name ms`, to `digits` decimals, comma-separated.
    pub fn passes_line(&self, digits: usize) -> String {
        let passes: Vec<String> = self
            .passes
            .iter()
            .map(|(p, ms)| format!("{} {ms:.digits$}", p.name()))
            .collect();
        passes.join(", ")
    }
}

/// `frame 3.20 ms (median of 15); passes (GPU timestamps): geometry 1.10 ms, …`.
impl std::fmt::Display for Timings {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let passes: Vec<String> = self
            .passes
            .iter()
            .map(|(p, ms)| format!("{} {ms:.2} ms", p.name()))
            .collect();
        write!(
            f,
            "frame {:.2} ms (median of {}); passes ({}): {}",
            self.frame_ms,
            self.frames,
            match self.clock {
                PassClock::Gpu => "GPU timestamps",
                PassClock::Wall => "wall time, each pass submitted alone",
            },
            passes.join(", ")
        )
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() { 0.0 } else { v[v.len() / 2] }
}

/// Times `frames` frames after `warmup` untimed ones (the distance maps are rendered in each).
pub fn time(
    r: &Renderer,
    f: &Frame<'_>,
    warmup: usize,
    frames: usize,
) -> Result<Timings, FrameError> {
    let device = &r.gpu.device;
    let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
    // Every timed frame renders the distance maps, as a scene whose objects move would.
    let recipes = prepared(r, f, Maps::Always)?;
    for _ in 0..warmup {
        submit_frame(r, &recipes)?;
        wait(r)?;
    }
    let mut whole = Vec::with_capacity(frames);
    for _ in 0..frames {
        let t = Instant::now();
        submit_frame(r, &recipes)?;
        wait(r)?;
        whole.push(t.elapsed().as_secs_f64() * 1e3);
    }
    let (per, clock) = if r.gpu.timestamps {
        (gpu_pass_times(r, &recipes, frames)?, PassClock::Gpu)
    } else {
        (wall_pass_times(r, &recipes, frames)?, PassClock::Wall)
    };
    if let Some(e) = pollster::block_on(scope.pop()) {
        return Err(FrameError::Device(e.to_string()));
    }
    // A pass of many recipes (a distance map's faces) is their sum.
    let mut passes: Vec<(Pass, f64)> = Vec::new();
    for (pass, ms) in recipes
        .iter()
        .map(|p| p.pass)
        .zip(per.into_iter().map(median))
    {
        match passes.iter_mut().find(|(p, _)| *p == pass) {
            Some((_, t)) => *t += ms,
            None => passes.push((pass, ms)),
        }
    }
    Ok(Timings {
        frame_ms: median(whole),
        passes,
        clock,
        frames,
    })
}

/// Each pass's time in each of `frames` frames from GPU timestamps (Vulkan).
fn gpu_pass_times(
    r: &Renderer,
    recipes: &[Recipe<'_>],
    frames: usize,
) -> Result<Vec<Vec<f64>>, FrameError> {
    let device = &r.gpu.device;
    let n = recipes.len() as u32 * 2;
    let set = device.create_query_set(&wgpu::QuerySetDescriptor {
        label: Some("pass times"),
        ty: wgpu::QueryType::Timestamp,
        count: n,
    });
    let bytes = u64::from(n) * 8;
    let buffer = |label, usage| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: bytes,
            usage,
            mapped_at_creation: false,
        })
    };
    let resolve = buffer(
        "timestamps",
        wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
    );
    let read = buffer(
        "timestamps read",
        wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
    );
    let period = f64::from(r.gpu.queue.get_timestamp_period());
    let mut per: Vec<Vec<f64>> = vec![Vec::with_capacity(frames); recipes.len()];
    for _ in 0..frames {
        let mut enc = encoder(r);
        for (i, p) in recipes.iter().enumerate() {
            let ts = Some(wgpu::RenderPassTimestampWrites {
                query_set: &set,
                beginning_of_pass_write_index: Some(2 * i as u32),
                end_of_pass_write_index: Some(2 * i as u32 + 1),
            });
            p.encode(r, &mut enc, ts)?;
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
    Ok(per)
}

/// Each pass's time in each of `frames` frames as wall time, each pass submitted and
/// waited for alone (GL, whose timestamps are wrong on llvmpipe).
fn wall_pass_times(
    r: &Renderer,
    recipes: &[Recipe<'_>],
    frames: usize,
) -> Result<Vec<Vec<f64>>, FrameError> {
    let mut per: Vec<Vec<f64>> = vec![Vec::with_capacity(frames); recipes.len()];
    for _ in 0..frames {
        for (i, p) in recipes.iter().enumerate() {
            let t = Instant::now();
            let mut enc = encoder(r);
            p.encode(r, &mut enc, None)?;
            r.gpu.queue.submit([enc.finish()]);
            wait(r)?;
            per[i].push(t.elapsed().as_secs_f64() * 1e3);
        }
    }
    Ok(per)
}

/// Draws the overlay's text over `output` (the window's surface) and submits it.
pub fn overlay(
    r: &Renderer,
    ov: &features::overlay::Overlay,
    output: features::Output<'_>,
) -> Result<(), FrameError> {
    let Some(recipe) = ov.pass(output) else {
        return Ok(());
    };
    r.prepare(recipe.keys())?;
    submit_frame(r, std::slice::from_ref(&recipe))
}

/// Scales `source`'s frame up into `output` (the window's surface) and submits it.
pub fn upscale(
    r: &Renderer,
    up: &features::upscale::Upscale,
    output: features::Output<'_>,
) -> Result<(), FrameError> {
    let recipe = up.pass(output);
    r.prepare(recipe.keys())?;
    submit_frame(r, std::slice::from_ref(&recipe))
}
