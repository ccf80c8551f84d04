//! The wgpu device: any adapter, or one back end by name (`--backend vulkan|gl|auto`). On
//! machines without a GPU this is Mesa's CPU drivers: Vulkan on lavapipe, GL on llvmpipe.
//! Decides the few format and feature questions once: the normal buffer's 16-bit format and
//! whether GPU timestamps can be trusted (Vulkan yes; GL on llvmpipe reports them but its values
//! are wrong, so wall time is used there), and which of a pass's work the GPU can count
//! (fragment-shader invocations where the adapter has pipeline-statistics queries; samples
//! written where its occlusion queries count them, Vulkan).

use std::fmt;
use std::str::FromStr;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use wgpu::util::DeviceExt as _;

use crate::fur::Level;

/// Which wgpu back end to ask for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Backend {
    /// Whatever adapter wgpu prefers among the compiled-in back ends.
    #[default]
    Auto,
    /// Vulkan (lavapipe on a CPU-only machine).
    Vulkan,
    /// OpenGL / GLES through EGL (llvmpipe on a CPU-only machine).
    Gl,
}

impl FromStr for Backend {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "auto" | "any" => Ok(Backend::Auto),
            "vulkan" | "vk" => Ok(Backend::Vulkan),
            "gl" | "gles" | "opengl" => Ok(Backend::Gl),
            "metal" | "dx12" | "webgpu" => Err(format!(
                "back end {s:?} is not built into pelt (built in: vulkan, gl; or auto)"
            )),
            _ => Err(format!(
                "unknown back end {s:?} (expected vulkan, gl or auto)"
            )),
        }
    }
}

impl fmt::Display for Backend {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Backend::Auto => "auto",
            Backend::Vulkan => "vulkan",
            Backend::Gl => "gl",
        })
    }
}

/// A wgpu instance for `backend`, with the window system's display when there is a window
/// (wgpu's GL back end binds EGL to the display at instance creation).
fn instance(
    backend: Backend,
    display: Option<Box<dyn wgpu::wgt::WgpuHasDisplayHandle>>,
) -> wgpu::Instance {
    let mut desc = match display {
        Some(d) => wgpu::InstanceDescriptor::new_with_display_handle_from_env(d),
        None => wgpu::InstanceDescriptor::new_without_display_handle_from_env(),
    };
    desc.backends = backend.backends();
    wgpu::Instance::new(desc)
}

impl Backend {
    fn backends(self) -> wgpu::Backends {
        match self {
            Backend::Auto => wgpu::Backends::VULKAN | wgpu::Backends::GL,
            Backend::Vulkan => wgpu::Backends::VULKAN,
            Backend::Gl => wgpu::Backends::GL,
        }
    }
}

/// Why no device could be had.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No adapter of the requested back end.
    #[error(
        "no {backend} adapter found ({source}); on a machine without a GPU install Mesa's CPU drivers: \
         GL on llvmpipe comes with libegl-mesa0, Vulkan on lavapipe with mesa-vulkan-drivers"
    )]
    NoAdapter {
        /// What was asked for.
        backend: Backend,
        /// wgpu's reason.
        source: wgpu::RequestAdapterError,
    },
    /// The window's surface could not be made.
    #[error("the window's surface could not be created: {0}")]
    Surface(#[source] wgpu::CreateSurfaceError),
    /// The adapter refused the device.
    #[error("the adapter refused a device: {0}")]
    Device(#[from] wgpu::RequestDeviceError),
}

/// A device and what the renderer decided about it.
#[derive(Debug)]
pub struct Gpu {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The adapter it came from.
    pub adapter: wgpu::Adapter,
    /// The adapter's description.
    pub info: wgpu::AdapterInfo,
    /// The normal buffer's format: 16-bit unsigned normalized X/Y where the adapter can render
    /// to it, else 16-bit float.
    pub normal_format: wgpu::TextureFormat,
    /// GPU timestamp queries that track real time are available.
    pub timestamps: bool,
    /// Pipeline-statistics queries (fragment-shader invocations) are available.
    pub statistics: bool,
    /// Occlusion queries count samples (Vulkan); elsewhere wgpu's say only whether any
    /// sample passed (GL's ANY_SAMPLES_PASSED), which counts nothing.
    pub samples: bool,
    /// Weighted blended OIT accumulation: 32-bit float where the adapter blends it
    /// (`FLOAT32_BLENDABLE`), else 16-bit float with weights scaled so the sum cannot pass
    /// 65504 (see `draw::wboit_scale`).
    pub accum_format: wgpu::TextureFormat,
    /// Device errors wgpu reported outside an error scope (instead of its default panic).
    errors: Arc<Mutex<Vec<String>>>,
    /// Bytes written to GPU buffers and textures since the last [`Gpu::take_uploaded`].
    uploaded: AtomicU64,
}

/// A window the device must be able to present to (`pelt view`).
pub trait Window:
    wgpu::rwh::HasWindowHandle + wgpu::rwh::HasDisplayHandle + fmt::Debug + Send + Sync + 'static
{
}
impl<T> Window for T where
    T: wgpu::rwh::HasWindowHandle
        + wgpu::rwh::HasDisplayHandle
        + fmt::Debug
        + Send
        + Sync
        + 'static
{
}

impl Gpu {
    /// Opens a device on `backend` (headless).
    pub fn new(backend: Backend) -> Result<Gpu, GpuError> {
        let instance = instance(backend, None);
        Gpu::open(backend, &instance, None)
    }

    /// Opens a device on `backend` that can present to `window`, and the window's surface.
    pub fn for_window<W: Window>(
        backend: Backend,
        window: Arc<W>,
    ) -> Result<(Gpu, wgpu::Surface<'static>), GpuError> {
        let display: Box<dyn wgpu::wgt::WgpuHasDisplayHandle> = Box::new(Arc::clone(&window));
        let instance = instance(backend, Some(display));
        let surface = instance
            .create_surface(wgpu::SurfaceTarget::from(window))
            .map_err(GpuError::Surface)?;
        let gpu = Gpu::open(backend, &instance, Some(&surface))?;
        Ok((gpu, surface))
    }

    fn open(
        backend: Backend,
        instance: &wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<Gpu, GpuError> {
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: surface,
            apply_limit_buckets: false,
        }))
        .map_err(|source| GpuError::NoAdapter { backend, source })?;
        let info = adapter.get_info();
        let available = adapter.features();
        let mut features = wgpu::Features::empty();
        // Normals are stored as e * 0.5 + 0.5, so unorm, snorm or float all hold them.
        let renderable = |f: wgpu::TextureFormat| {
            adapter
                .get_texture_format_features(f)
                .allowed_usages
                .contains(
                    wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
                )
        };
        // Rendering to a 16-bit unorm format is an adapter-specific format feature.
        let norm16 = wgpu::Features::TEXTURE_FORMAT_16BIT_NORM
            | wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES;
        let normal_format =
            if available.contains(norm16) && renderable(wgpu::TextureFormat::Rg16Unorm) {
                features |= norm16;
                wgpu::TextureFormat::Rg16Unorm
            } else {
                wgpu::TextureFormat::Rg16Float
            };
        let accum_format = if available.contains(wgpu::Features::FLOAT32_BLENDABLE) {
            features |= wgpu::Features::FLOAT32_BLENDABLE;
            wgpu::TextureFormat::Rgba32Float
        } else {
            wgpu::TextureFormat::Rgba16Float
        };
        let timestamps = info.backend == wgpu::Backend::Vulkan
            && available.contains(wgpu::Features::TIMESTAMP_QUERY);
        if timestamps {
            features |= wgpu::Features::TIMESTAMP_QUERY;
        }
        let statistics = available.contains(wgpu::Features::PIPELINE_STATISTICS_QUERY);
        if statistics {
            features |= wgpu::Features::PIPELINE_STATISTICS_QUERY;
        }
        let samples = info.backend == wgpu::Backend::Vulkan;
        let (device, queue) =
            pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
                label: Some("pelt-preview"),
                required_features: features,
                required_limits: adapter.limits(),
                ..Default::default()
            }))?;
        let errors = Arc::new(Mutex::new(Vec::new()));
        let sink = Arc::clone(&errors);
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut v) = sink.lock() {
                v.push(e.to_string());
            }
        }));
        Ok(Gpu {
            adapter,
            errors,
            device,
            queue,
            info,
            normal_format,
            timestamps,
            statistics,
            samples,
            accum_format,
            uploaded: AtomicU64::new(0),
        })
    }

    /// Bytes written to GPU buffers and textures since the last call (every upload of the
    /// renderer goes through [`Gpu::write_buffer`], [`Gpu::buffer_init`] or
    /// [`Gpu::write_texture`]).
    pub fn take_uploaded(&self) -> u64 {
        self.uploaded.swap(0, Ordering::Relaxed)
    }

    fn count(&self, bytes: usize) {
        self.uploaded.fetch_add(bytes as u64, Ordering::Relaxed);
    }

    /// `queue.write_buffer`, counted.
    pub fn write_buffer(&self, buffer: &wgpu::Buffer, offset: u64, data: &[u8]) {
        self.count(data.len());
        self.queue.write_buffer(buffer, offset, data);
    }

    /// A buffer created holding `contents`, counted.
    pub fn buffer_init(
        &self,
        label: &str,
        contents: &[u8],
        usage: wgpu::BufferUsages,
    ) -> wgpu::Buffer {
        self.count(contents.len());
        self.device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage,
            })
    }

    /// `queue.write_texture`, counted.
    pub fn write_texture(
        &self,
        texture: wgpu::TexelCopyTextureInfo<'_>,
        data: &[u8],
        layout: wgpu::TexelCopyBufferLayout,
        size: wgpu::Extent3d,
    ) {
        self.count(data.len());
        self.queue.write_texture(texture, data, layout, size);
    }

    /// The first device error reported since the last call, if any.
    pub fn take_error(&self) -> Option<String> {
        let mut v = self.errors.lock().ok()?;
        let first = v.first().cloned();
        v.clear();
        first
    }

    /// `llvmpipe (LLVM 15.0.6, 256 bits) (Gl, Cpu)`.
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {:?}{})",
            self.info.name,
            self.info.backend,
            self.info.device_type,
            if self.info.driver_info.is_empty() {
                String::new()
            } else {
                format!(", {}", self.info.driver_info)
            }
        )
    }
}

/// A private runtime directory for this user when `XDG_RUNTIME_DIR` is unset, as Mesa's
/// Vulkan window-system code (through libwayland) expects one and otherwise prints "error:
/// XDG_RUNTIME_DIR is invalid or not set in the environment." on every device it opens.
/// Returns the directory to set, or None when the variable is set already or no private
/// directory could be made (then nothing changes: real errors are never hidden). The caller
/// sets the variable before any thread starts (see `pelt`'s `main`).
pub fn private_runtime_dir() -> Option<std::path::PathBuf> {
    use std::os::unix::fs::{DirBuilderExt as _, MetadataExt as _, PermissionsExt as _};
    if std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|v| !v.is_empty()) {
        return None;
    }
    // The process's user: the owner of /proc/self.
    let uid = std::fs::metadata("/proc/self").ok()?.uid();
    let dir = std::env::temp_dir().join(format!("pelt-runtime-{uid}"));
    let _ = std::fs::DirBuilder::new().mode(0o700).create(&dir);
    let m = std::fs::symlink_metadata(&dir).ok()?;
    let private = m.is_dir() && m.uid() == uid && m.permissions().mode() & 0o777 == 0o700;
    private.then_some(dir)
}

/// Most bytes of one level written before the queue is flushed: wgpu stages each
/// `write_texture` in a buffer of its own until the next submission, so a large level written
/// at once holds a second copy of itself (on a CPU driver, in system memory).
const WRITE_CHUNK: usize = 16 << 20;

impl Gpu {
    /// Writes `bytes`, the `height` rows of level `mip_level` of a 2D `texture`, top first;
    /// a level larger than [`WRITE_CHUNK`] goes in bands of rows, each submitted and waited
    /// for before the next is staged, so staging never holds more than one band.
    pub fn write_level(&self, texture: &wgpu::Texture, mip_level: u32, height: u32, bytes: &[u8]) {
        let row = (bytes.len() / height.max(1) as usize).max(1);
        let rows_per_band = (WRITE_CHUNK / row).max(1);
        let banded = bytes.len() > WRITE_CHUNK;
        let width = texture.width() >> mip_level;
        for (i, band) in bytes.chunks(rows_per_band * row).enumerate() {
            let rows = (band.len() / row) as u32;
            self.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture,
                    mip_level,
                    origin: wgpu::Origin3d {
                        x: 0,
                        y: (i * rows_per_band) as u32,
                        z: 0,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                band,
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(row as u32),
                    rows_per_image: Some(rows),
                },
                wgpu::Extent3d {
                    width: width.max(1),
                    height: rows,
                    depth_or_array_layers: 1,
                },
            );
            if banded {
                self.queue.submit([]);
                // Waiting only frees the band's staging buffer sooner; a device that stops
                // answering is reported by the frame that follows (take_error, readback).
                let _ = self.device.poll(wgpu::PollType::wait_indefinitely());
            }
        }
    }

    /// A 2D texture of `format` with `levels` (level 0 first), its view.
    pub fn upload_levels<T>(
        &self,
        label: &str,
        format: wgpu::TextureFormat,
        levels: &[Level<T>],
        level_bytes: impl Fn(&[T]) -> std::borrow::Cow<'_, [u8]>,
    ) -> wgpu::TextureView {
        let texture = self.texture_2d(
            label,
            format,
            (levels[0].width, levels[0].height),
            levels.len() as u32,
        );
        for (i, l) in levels.iter().enumerate() {
            // A level's bytes at once (RGBA8 texels are borrowed as they are, no copy).
            self.write_level(&texture, i as u32, l.height, &level_bytes(&l.texels));
        }
        texture.create_view(&wgpu::TextureViewDescriptor::default())
    }

    /// A sampled 2D texture of `format`, `size` texels at level 0 with `levels` levels, to be
    /// written ([`Gpu::write_level`]).
    pub fn texture_2d(
        &self,
        label: &str,
        format: wgpu::TextureFormat,
        size: (u32, u32),
        levels: u32,
    ) -> wgpu::Texture {
        self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: levels,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        })
    }
}
