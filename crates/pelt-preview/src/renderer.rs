//! The long-lived half of the renderer (re_renderer's `Renderer`): the device, the bind-group
//! layouts, shader modules and a cache of render pipelines. A pipeline's key is what the
//! drawing code asked for: the shader, the blend, and the formats of the targets of the pass
//! that draws it, read off the pass's own attachments (see [`crate::recipe`]), so the cache
//! cannot drift from the passes. Each feature module says how its shaders' pipelines are
//! laid out ([`crate::features::spec`]). Pipelines are compiled before a frame is encoded,
//! only those the frame uses; a frame never compiles one while encoding.

use std::cell::{Cell, RefCell};
use std::collections::HashMap;

use crate::gpu::Gpu;
use crate::shaders::Shader;
use crate::uniforms::{
    FrameUniforms, LightUniforms, MAX_FORWARD_LIGHTS, MaterialUniforms, ObjectUniforms,
};

/// Linear light accumulation (RGB diffuse, A specular): 16-bit float, blendable everywhere.
pub const LBUFFER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// DSF buffer: 16-bit linear depth, 16-bit ID (integers: an ID in a float channel corrupts).
pub const DSF_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Uint;
/// Hardware depth for the geometry, material and forward passes.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The PNG output (lighting is linear; the target encodes sRGB). A window renders to its
/// surface's format instead: pipeline keys carry the format.
pub const OUTPUT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// The linear colour frames that blend fur layers draw into before the resolve pass
/// ([`crate::features::resolve`]).
pub const SCENE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Revealage of weighted blended OIT: 16-bit float (8 bits band after a few layers).
pub const REVEAL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;
/// The cube-map sky's faces.
pub const SKY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// The heightfield (16-bit heights as half floats: filterable everywhere).
pub const HEIGHT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;
/// The fur density's two textures (pelt_fur::density, four bins each; half floats filter).
pub const DENSITY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// The fin texture (linear data: height, tint, coverage).
pub const FIN_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// How a pipeline writes its colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Blend {
    /// Replace, with depth writes.
    None,
    /// Straight alpha "over", depth test without writes.
    Over,
    /// Weighted blended OIT: additive accumulation and multiplicative revealage.
    Wboit,
}

/// Most colour targets a pass writes.
pub const MAX_COLOR_TARGETS: usize = 2;

/// What makes one pipeline differ from another.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PipelineKey {
    /// The shader module and entry points.
    pub shader: Shader,
    /// How it blends.
    pub blend: Blend,
    /// The formats of the pass's colour targets, in attachment order.
    pub colors: [Option<wgpu::TextureFormat>; MAX_COLOR_TARGETS],
    /// The pass's depth format.
    pub depth: Option<wgpu::TextureFormat>,
}

/// Bind group layouts shared by the passes. Which slot each takes in a pass is named in the
/// feature modules (`slot` constants), never by a bare number.
#[derive(Debug)]
pub struct Layouts {
    /// The frame uniforms (dynamic offset: one slot per view and resolution).
    pub frame: wgpu::BindGroupLayout,
    /// One object's uniforms (dynamic offset).
    pub object: wgpu::BindGroupLayout,
    /// A float texture and the DSF texture (G-buffer or L-buffer reads).
    pub textures: wgpu::BindGroupLayout,
    /// One light (dynamic offset).
    pub light: wgpu::BindGroupLayout,
    /// Every light (forward; dynamic offset: one array per view).
    pub light_array: wgpu::BindGroupLayout,
    /// Heightfield, fin texture, their samplers.
    pub fur: wgpu::BindGroupLayout,
    /// Which IDs are outer shells (obliteration).
    pub shell_table: wgpu::BindGroupLayout,
    /// Accumulation and revealage (OIT composite).
    pub oit: wgpu::BindGroupLayout,
    /// The cube map and its sampler.
    pub sky: wgpu::BindGroupLayout,
    /// A frame to scale up and its sampler.
    pub upscale_source: wgpu::BindGroupLayout,
    /// The target's size (w, h, 1/w, 1/h).
    pub upscale_size: wgpu::BindGroupLayout,
    /// A compute pass's storage buffers: binding 0 read, binding 1 read and written.
    pub storage: wgpu::BindGroupLayout,
    /// A 2D-array texture and its sampler (mip generation).
    pub array_source: wgpu::BindGroupLayout,
    /// The overlay's text bitmap.
    pub text: wgpu::BindGroupLayout,
    /// One distance-map face's constants (dynamic offset).
    pub face: wgpu::BindGroupLayout,
    /// The previous distance-map layer (depth peeling).
    pub peel: wgpu::BindGroupLayout,
    /// Distance maps, their ranges and the search's knobs (reflect.wgsl).
    pub reflect_maps: wgpu::BindGroupLayout,
    /// Distance maps and their ranges, written (minmax.wgsl).
    pub minmax: wgpu::BindGroupLayout,
    /// One material's textures, samplers and factors.
    pub material: wgpu::BindGroupLayout,
}

fn uniform_entry(size: u64, dynamic: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding: 0,
        visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: dynamic,
            min_binding_size: wgpu::BufferSize::new(size),
        },
        count: None,
    }
}

fn texture_entry(
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

fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
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

fn sampler_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
        count: None,
    }
}

/// Bytes of the obliteration pass's ID table (`array<vec4<u32>, 64>`).
pub const SHELL_TABLE_BYTES: u64 = 1024;

/// A bind group layout by name: what a pipeline spec lists, slot by slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LayoutId {
    /// [`Layouts::frame`].
    Frame,
    /// [`Layouts::object`].
    Object,
    /// [`Layouts::textures`].
    Textures,
    /// [`Layouts::light`].
    Light,
    /// [`Layouts::light_array`].
    LightArray,
    /// [`Layouts::fur`].
    Fur,
    /// [`Layouts::shell_table`].
    ShellTable,
    /// [`Layouts::oit`].
    Oit,
    /// [`Layouts::sky`].
    Sky,
    /// [`Layouts::upscale_source`].
    UpscaleSource,
    /// [`Layouts::upscale_size`].
    UpscaleSize,
    /// [`Layouts::storage`].
    Storage,
    /// [`Layouts::array_source`].
    ArraySource,
    /// [`Layouts::text`].
    Text,
    /// [`Layouts::face`].
    Face,
    /// [`Layouts::peel`].
    Peel,
    /// [`Layouts::reflect_maps`].
    ReflectMaps,
    /// [`Layouts::minmax`].
    MinMax,
    /// [`Layouts::material`].
    Material,
}

impl LayoutId {
    /// Every layout.
    pub const ALL: [LayoutId; 19] = [
        LayoutId::Frame,
        LayoutId::Object,
        LayoutId::Textures,
        LayoutId::Light,
        LayoutId::LightArray,
        LayoutId::Fur,
        LayoutId::ShellTable,
        LayoutId::Oit,
        LayoutId::Sky,
        LayoutId::UpscaleSource,
        LayoutId::UpscaleSize,
        LayoutId::Storage,
        LayoutId::ArraySource,
        LayoutId::Text,
        LayoutId::Face,
        LayoutId::Peel,
        LayoutId::ReflectMaps,
        LayoutId::MinMax,
        LayoutId::Material,
    ];

    /// The layout's entries (plain data: the shader test checks them against the WGSL).
    pub fn entries(self) -> Vec<wgpu::BindGroupLayoutEntry> {
        let d2 = wgpu::TextureViewDimension::D2;
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let filterable = wgpu::TextureSampleType::Float { filterable: true };
        let array = wgpu::TextureViewDimension::D2Array;
        let size = |n: usize| n as u64;
        match self {
            LayoutId::Frame => vec![uniform_entry(size(size_of::<FrameUniforms>()), true)],
            LayoutId::Object => vec![uniform_entry(size(size_of::<ObjectUniforms>()), true)],
            LayoutId::Textures => vec![
                texture_entry(0, unfilterable, d2),
                texture_entry(1, wgpu::TextureSampleType::Uint, d2),
            ],
            LayoutId::Light => vec![uniform_entry(size(size_of::<LightUniforms>()), true)],
            LayoutId::LightArray => vec![uniform_entry(
                size(MAX_FORWARD_LIGHTS * size_of::<LightUniforms>()),
                true,
            )],
            LayoutId::Fur => vec![
                texture_entry(0, filterable, d2),
                texture_entry(1, filterable, d2),
                sampler_entry(2),
                sampler_entry(3),
                texture_entry(4, filterable, d2),
                sampler_entry(5),
                texture_entry(6, filterable, d2),
                texture_entry(7, filterable, d2),
            ],
            LayoutId::Material => vec![
                texture_entry(0, filterable, d2),
                texture_entry(1, filterable, d2),
                texture_entry(2, filterable, d2),
                sampler_entry(3),
                sampler_entry(4),
                sampler_entry(5),
                wgpu::BindGroupLayoutEntry {
                    binding: 6,
                    ..uniform_entry(size(size_of::<MaterialUniforms>()), false)
                },
            ],
            LayoutId::ShellTable => vec![uniform_entry(SHELL_TABLE_BYTES, false)],
            LayoutId::Oit => vec![
                texture_entry(0, unfilterable, d2),
                texture_entry(1, unfilterable, d2),
            ],
            LayoutId::Sky => vec![
                texture_entry(0, filterable, wgpu::TextureViewDimension::Cube),
                sampler_entry(1),
            ],
            LayoutId::UpscaleSource => vec![texture_entry(0, filterable, d2), sampler_entry(1)],
            LayoutId::UpscaleSize => vec![uniform_entry(16, false)],
            LayoutId::Storage => vec![storage_entry(0, true), storage_entry(1, false)],
            LayoutId::Text => vec![texture_entry(0, filterable, d2)],
            LayoutId::Face => vec![uniform_entry(
                size(size_of::<crate::features::reflect::FaceUniforms>()),
                true,
            )],
            LayoutId::Peel => vec![texture_entry(0, unfilterable, array)],
            LayoutId::ReflectMaps => vec![
                texture_entry(0, unfilterable, array),
                texture_entry(1, unfilterable, array),
                wgpu::BindGroupLayoutEntry {
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ..storage_entry(2, true)
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 3,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ..uniform_entry(
                        size(size_of::<crate::features::reflect::ReflectUniforms>()),
                        false,
                    )
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 4,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ..uniform_entry(
                        size(crate::features::reflect::MAX_MAP_LIGHTS * size_of::<LightUniforms>()),
                        false,
                    )
                },
            ],
            LayoutId::MinMax => vec![
                wgpu::BindGroupLayoutEntry {
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ..texture_entry(0, unfilterable, array)
                },
                storage_entry(1, false),
            ],
            LayoutId::ArraySource => vec![
                texture_entry(0, filterable, wgpu::TextureViewDimension::D2Array),
                sampler_entry(1),
            ],
        }
    }
}

impl Layouts {
    fn new(device: &wgpu::Device) -> Layouts {
        let layout = |id: LayoutId| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(&format!("{id:?}")),
                entries: &id.entries(),
            })
        };
        Layouts {
            frame: layout(LayoutId::Frame),
            object: layout(LayoutId::Object),
            textures: layout(LayoutId::Textures),
            light: layout(LayoutId::Light),
            light_array: layout(LayoutId::LightArray),
            fur: layout(LayoutId::Fur),
            shell_table: layout(LayoutId::ShellTable),
            oit: layout(LayoutId::Oit),
            sky: layout(LayoutId::Sky),
            upscale_source: layout(LayoutId::UpscaleSource),
            upscale_size: layout(LayoutId::UpscaleSize),
            storage: layout(LayoutId::Storage),
            array_source: layout(LayoutId::ArraySource),
            text: layout(LayoutId::Text),
            face: layout(LayoutId::Face),
            peel: layout(LayoutId::Peel),
            reflect_maps: layout(LayoutId::ReflectMaps),
            minmax: layout(LayoutId::MinMax),
            material: layout(LayoutId::Material),
        }
    }

    /// The layout named `id`.
    pub fn get(&self, id: LayoutId) -> &wgpu::BindGroupLayout {
        match id {
            LayoutId::Frame => &self.frame,
            LayoutId::Object => &self.object,
            LayoutId::Textures => &self.textures,
            LayoutId::Light => &self.light,
            LayoutId::LightArray => &self.light_array,
            LayoutId::Fur => &self.fur,
            LayoutId::ShellTable => &self.shell_table,
            LayoutId::Oit => &self.oit,
            LayoutId::Sky => &self.sky,
            LayoutId::UpscaleSource => &self.upscale_source,
            LayoutId::UpscaleSize => &self.upscale_size,
            LayoutId::Storage => &self.storage,
            LayoutId::ArraySource => &self.array_source,
            LayoutId::Text => &self.text,
            LayoutId::Face => &self.face,
            LayoutId::Peel => &self.peel,
            LayoutId::ReflectMaps => &self.reflect_maps,
            LayoutId::MinMax => &self.minmax,
            LayoutId::Material => &self.material,
        }
    }
}

/// How a feature lays out one of its pipelines; the formats come from the key. Plain data,
/// so the shader test can check it against the WGSL without a device.
#[derive(Debug, Default)]
pub struct PipelineSpec {
    /// Bind group layouts by slot, slot 0 first (every slot up to the last present).
    pub groups: Vec<LayoutId>,
    /// Vertex buffers by slot.
    pub vertex_buffers: Vec<wgpu::VertexBufferLayout<'static>>,
    /// Blend of each colour target, in attachment order.
    pub blends: Vec<Option<wgpu::BlendState>>,
    /// Depth writes and test, when the pass has a depth target (none: test always, no
    /// writes).
    pub depth: Option<(bool, wgpu::CompareFunction)>,
    /// Faces culled.
    pub cull: Option<wgpu::Face>,
    /// Values of the module's `override` constants (by name).
    pub constants: Vec<(&'static str, f64)>,
}

/// Why a pipeline could not be made or found.
#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    /// The frame asked for a pipeline that was not compiled before encoding.
    #[error("pipeline {0:?} was not prepared before the frame was encoded")]
    NotPrepared(PipelineKey),
    /// The pass's attachments do not fit the pipeline's layout.
    #[error("pipeline {key:?}: {message}")]
    Mismatch {
        /// The key.
        key: PipelineKey,
        /// What does not fit.
        message: String,
    },
}

/// Device, layouts, modules and pipelines.
#[derive(Debug)]
pub struct Renderer {
    /// The device.
    pub gpu: Gpu,
    /// Bind group layouts.
    pub layouts: Layouts,
    modules: RefCell<HashMap<Shader, wgpu::ShaderModule>>,
    pipelines: RefCell<HashMap<PipelineKey, wgpu::RenderPipeline>>,
    compute: RefCell<HashMap<Shader, wgpu::ComputePipeline>>,
    built: Cell<usize>,
    /// Shader files loaded from disk (`pelt view --shaders`), replacing the built-in ones.
    sources: RefCell<Option<Vec<(&'static str, String)>>>,
}

impl Renderer {
    /// A renderer on `gpu`; nothing is compiled yet.
    pub fn new(gpu: Gpu) -> Renderer {
        let layouts = Layouts::new(&gpu.device);
        Renderer {
            gpu,
            layouts,
            modules: RefCell::new(HashMap::new()),
            pipelines: RefCell::new(HashMap::new()),
            compute: RefCell::new(HashMap::new()),
            built: Cell::new(0),
            sources: RefCell::new(None),
        }
    }

    /// Reads every shader file from `dir` and validates every module; when all are valid,
    /// they replace the current ones and every pipeline is rebuilt on the frame that next
    /// draws it. On an error nothing changes (the last good pipelines stay).
    pub fn load_shaders(&self, dir: &std::path::Path) -> Result<(), crate::shaders::ShaderError> {
        let texts = crate::shaders::load_dir(dir)?;
        *self.sources.borrow_mut() = Some(texts);
        self.modules.borrow_mut().clear();
        self.pipelines.borrow_mut().clear();
        self.compute.borrow_mut().clear();
        Ok(())
    }

    /// Compiles every pipeline of `keys` that is not cached yet; returns how many it built.
    pub fn prepare<'k>(
        &self,
        keys: impl IntoIterator<Item = &'k PipelineKey>,
    ) -> Result<usize, PipelineError> {
        let mut n = 0;
        for key in keys {
            if !self.pipelines.borrow().contains_key(key) {
                let p = self.build(key)?;
                self.pipelines.borrow_mut().insert(*key, p);
                self.built.set(self.built.get() + 1);
                n += 1;
            }
        }
        Ok(n)
    }

    /// A prepared pipeline.
    pub fn pipeline(&self, key: &PipelineKey) -> Result<wgpu::RenderPipeline, PipelineError> {
        self.pipelines
            .borrow()
            .get(key)
            .cloned()
            .ok_or(PipelineError::NotPrepared(*key))
    }

    /// A bind group of the Storage layout (compute passes): `read` at binding 0, `written`
    /// at binding 1.
    pub fn storage_group(&self, read: &wgpu::Buffer, written: &wgpu::Buffer) -> wgpu::BindGroup {
        self.gpu
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("storage"),
                layout: &self.layouts.storage,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: read.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: written.as_entire_binding(),
                    },
                ],
            })
    }

    /// The compute pipeline of `shader` (a compute module), compiled on first use.
    pub fn compute(&self, shader: Shader) -> Result<wgpu::ComputePipeline, PipelineError> {
        if let Some(p) = self.compute.borrow().get(&shader) {
            return Ok(p.clone());
        }
        let key = PipelineKey {
            shader,
            blend: Blend::None,
            colors: [None; MAX_COLOR_TARGETS],
            depth: None,
        };
        if !shader.is_compute() {
            return Err(PipelineError::Mismatch {
                key,
                message: "not a compute shader".into(),
            });
        }
        let spec = crate::features::spec(&key);
        let groups: Vec<Option<&wgpu::BindGroupLayout>> = spec
            .groups
            .iter()
            .map(|&g| Some(self.layouts.get(g)))
            .collect();
        let device = &self.gpu.device;
        let name = shader.module_name();
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(&name),
            bind_group_layouts: &groups,
            immediate_size: 0,
        });
        let p = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(&name),
            layout: Some(&layout),
            module: &self.module(shader),
            entry_point: Some(shader.entry_points().0),
            compilation_options: Default::default(),
            cache: None,
        });
        self.compute.borrow_mut().insert(shader, p.clone());
        self.built.set(self.built.get() + 1);
        Ok(p)
    }

    /// Pipelines compiled since the renderer was made.
    pub fn pipelines_built(&self) -> usize {
        self.built.get()
    }

    fn module(&self, shader: Shader) -> wgpu::ShaderModule {
        let device = &self.gpu.device;
        let source = match &*self.sources.borrow() {
            Some(texts) => shader.source_with(|n| {
                texts
                    .iter()
                    .find(|(t, _)| *t == n)
                    .map_or("", |(_, s)| s.as_str())
            }),
            None => shader.source(),
        };
        self.modules
            .borrow_mut()
            .entry(shader)
            .or_insert_with(|| {
                device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(&shader.module_name()),
                    source: wgpu::ShaderSource::Wgsl(source.into()),
                })
            })
            .clone()
    }

    fn build(&self, key: &PipelineKey) -> Result<wgpu::RenderPipeline, PipelineError> {
        let spec = crate::features::spec(key);
        let mismatch = |message: String| PipelineError::Mismatch { key: *key, message };
        let formats: Vec<wgpu::TextureFormat> = key.colors.iter().flatten().copied().collect();
        if formats.len() != spec.blends.len() {
            return Err(mismatch(format!(
                "the pass has {} colour targets, the shader writes {}",
                formats.len(),
                spec.blends.len()
            )));
        }
        let depth_stencil = match (key.depth, spec.depth) {
            (None, None) => None,
            (None, Some(_)) => return Err(mismatch("the shader needs a depth target".into())),
            (Some(format), d) => {
                let (write, compare) = d.unwrap_or((false, wgpu::CompareFunction::Always));
                Some(wgpu::DepthStencilState {
                    format,
                    depth_write_enabled: Some(write),
                    depth_compare: Some(compare),
                    stencil: wgpu::StencilState::default(),
                    bias: wgpu::DepthBiasState::default(),
                })
            }
        };
        let targets: Vec<Option<wgpu::ColorTargetState>> = formats
            .iter()
            .zip(&spec.blends)
            .map(|(&format, &blend)| {
                Some(wgpu::ColorTargetState {
                    format,
                    blend,
                    write_mask: wgpu::ColorWrites::ALL,
                })
            })
            .collect();
        let module = self.module(key.shader);
        let device = &self.gpu.device;
        let name = key.shader.module_name();
        let groups: Vec<Option<&wgpu::BindGroupLayout>> = spec
            .groups
            .iter()
            .map(|&g| Some(self.layouts.get(g)))
            .collect();
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(&name),
            bind_group_layouts: &groups,
            immediate_size: 0,
        });
        let (vs, fs) = key.shader.entry_points();
        let options = wgpu::PipelineCompilationOptions {
            constants: &spec.constants,
            ..Default::default()
        };
        let buffers: Vec<Option<wgpu::VertexBufferLayout<'_>>> =
            spec.vertex_buffers.iter().cloned().map(Some).collect();
        Ok(
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(&name),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some(vs),
                    compilation_options: options.clone(),
                    buffers: &buffers,
                },
                primitive: wgpu::PrimitiveState {
                    cull_mode: spec.cull,
                    ..Default::default()
                },
                depth_stencil,
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fs),
                    compilation_options: options,
                    targets: &targets,
                }),
                multiview_mask: None,
                cache: None,
            }),
        )
    }
}
