//! The long-lived half of the renderer (re_renderer's `Renderer`): the device and three
//! descriptor → handle caches (re_renderer's `get_or_create`): bind-group layouts, shader
//! modules and pipelines. The core knows no feature: a pipeline's key is the descriptor the
//! drawing code asked for ([`PipelineDesc`]: shader, layouts, vertex buffers, blends, depth,
//! constants) with the formats of the targets of the pass that draws it, read off the pass's
//! own attachments (see [`crate::recipe`]), so the cache cannot drift from the passes.
//! Pipelines are compiled before a frame is encoded, only those the frame uses; a frame never
//! compiles one while encoding.

use std::cell::{Cell, RefCell};
use std::collections::HashMap;

use crate::gpu::Gpu;
use crate::layout::LayoutDesc;
use crate::shaders::{Entry, ShaderDesc};

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

/// A render pipeline as a feature asks for it: its shader and how it is laid out. The
/// formats come from the pass that draws it ([`PipelineKey`]).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct PipelineDesc {
    /// The shader module and entry points.
    pub shader: ShaderDesc,
    /// Layouts, vertex buffers, blends, depth, culling, constants.
    pub spec: PipelineSpec,
}

impl PipelineDesc {
    /// The shader's override constant `name` as this pipeline sets it (`None`: the shader's
    /// default).
    pub fn constant(&self, name: &str) -> Option<f64> {
        self.spec
            .constants
            .iter()
            .find_map(|&(n, v)| (n == name).then_some(v))
    }

    /// The same pipeline with the override constant `name` set to `value` (`None`: the
    /// shader's default): one of its specializations.
    pub fn with_constant(mut self, name: &'static str, value: Option<f64>) -> PipelineDesc {
        self.spec.constants.retain(|(n, _)| *n != name);
        if let Some(v) = value {
            self.spec.constants.push((name, v));
        }
        self
    }

    /// A full-screen pass of `shader` (no vertex buffers, no depth) reading `groups` by slot,
    /// into one colour target blended by `blend`.
    pub fn fullscreen(
        shader: ShaderDesc,
        groups: Vec<LayoutDesc>,
        blend: Option<wgpu::BlendState>,
    ) -> PipelineDesc {
        PipelineDesc {
            shader,
            spec: PipelineSpec {
                groups,
                blends: vec![blend],
                ..PipelineSpec::default()
            },
        }
    }
}

/// What makes one pipeline differ from another: the descriptor and the formats of the
/// attachments of the pass that draws it.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct PipelineKey {
    /// What the feature asked for.
    pub desc: PipelineDesc,
    /// The formats of the pass's colour targets, in attachment order.
    pub colors: [Option<wgpu::TextureFormat>; MAX_COLOR_TARGETS],
    /// The pass's depth format.
    pub depth: Option<wgpu::TextureFormat>,
}

/// A compute pipeline: its shader and its bind-group layouts by slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ComputeDesc {
    /// The shader (a compute entry point).
    pub shader: ShaderDesc,
    /// Bind group layouts by slot.
    pub groups: &'static [LayoutDesc],
}

/// How a feature lays out one of its pipelines; the formats come from the key. Plain data,
/// so the shader test can check it against the WGSL without a device.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PipelineSpec {
    /// Bind group layouts by slot, slot 0 first (every slot up to the last present).
    pub groups: Vec<LayoutDesc>,
    /// Vertex buffers by slot.
    pub vertex_buffers: Vec<wgpu::VertexBufferLayout<'static>>,
    /// Blend of each colour target, in attachment order.
    pub blends: Vec<Option<wgpu::BlendState>>,
    /// Depth writes and test, when the pass has a depth target (none: test always, no
    /// writes).
    pub depth: Option<(bool, wgpu::CompareFunction)>,
    /// Faces culled.
    pub cull: Option<wgpu::Face>,
    /// The winding of front faces (clockwise for objects whose transform mirrors them).
    pub front_face: wgpu::FrontFace,
    /// Values of the module's `override` constants (by name).
    pub constants: Vec<(&'static str, f64)>,
    /// The channels each colour target keeps (None: all).
    pub writes: Option<wgpu::ColorWrites>,
}

// The constants are finite numbers (never NaN), so equality is total.
impl Eq for PipelineSpec {}

impl std::hash::Hash for PipelineSpec {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.groups.hash(state);
        self.vertex_buffers.hash(state);
        self.blends.hash(state);
        self.depth.hash(state);
        self.cull.hash(state);
        self.front_face.hash(state);
        self.writes.map(|w| w.bits()).hash(state);
        for (name, value) in &self.constants {
            name.hash(state);
            value.to_bits().hash(state);
        }
    }
}

/// Why a pipeline could not be made or found.
#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    /// The frame asked for a pipeline that was not compiled before encoding.
    #[error("pipeline {0} was not prepared before the frame was encoded")]
    NotPrepared(String),
    /// The shader module could not be composed (or, reloaded, does not validate).
    #[error(transparent)]
    Shader(#[from] crate::shaders::ShaderError),
    /// The pass's attachments do not fit the pipeline's layout.
    #[error("pipeline {module}: {message}")]
    Mismatch {
        /// The shader module.
        module: String,
        /// What does not fit.
        message: String,
    },
}

/// A composed module's key: its file and shader defs.
type ModuleKey = (&'static str, &'static [(&'static str, u32)]);

/// Device, layouts, modules and pipelines.
#[derive(Debug)]
pub struct Renderer {
    /// The device.
    pub gpu: Gpu,
    /// The shaders a reload validates.
    shaders: Vec<ShaderDesc>,
    layouts: RefCell<HashMap<LayoutDesc, wgpu::BindGroupLayout>>,
    modules: RefCell<HashMap<ModuleKey, wgpu::ShaderModule>>,
    pipelines: RefCell<HashMap<PipelineKey, wgpu::RenderPipeline>>,
    compute: RefCell<HashMap<ComputeDesc, wgpu::ComputePipeline>>,
    built: Cell<usize>,
    /// Shader files loaded from disk (`pelt view --shaders`), replacing the built-in ones.
    sources: RefCell<Option<Vec<(&'static str, String)>>>,
}

impl Renderer {
    /// A renderer on `gpu` drawing `shaders` (the registered features' shaders, which a
    /// shader reload validates); nothing is compiled yet.
    pub fn new(gpu: Gpu, shaders: Vec<ShaderDesc>) -> Renderer {
        Renderer {
            gpu,
            shaders,
            layouts: RefCell::new(HashMap::new()),
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
        let texts = crate::shaders::load_dir(dir, &self.shaders)?;
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
                self.pipelines.borrow_mut().insert(key.clone(), p);
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
            .ok_or_else(|| PipelineError::NotPrepared(key.desc.shader.module_name()))
    }

    /// The layout of `desc`, made on first use (descriptors with equal entries share one).
    pub fn layout(&self, desc: &LayoutDesc) -> wgpu::BindGroupLayout {
        self.layouts
            .borrow_mut()
            .entry(*desc)
            .or_insert_with(|| {
                self.gpu
                    .device
                    .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                        label: Some(desc.label),
                        entries: desc.entries,
                    })
            })
            .clone()
    }

    /// A buffer of `size` bytes for `usage`, writable from the CPU.
    pub fn buffer(&self, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
        self.gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: usage | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    /// A bind group of `desc` with one resource per binding, in binding order.
    pub fn group(
        &self,
        label: &str,
        desc: &LayoutDesc,
        resources: &[wgpu::BindingResource<'_>],
    ) -> wgpu::BindGroup {
        let entries: Vec<wgpu::BindGroupEntry<'_>> = desc
            .entries
            .iter()
            .zip(resources)
            .map(|(e, res)| wgpu::BindGroupEntry {
                binding: e.binding,
                resource: res.clone(),
            })
            .collect();
        self.gpu
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout: &self.layout(desc),
                entries: &entries,
            })
    }

    /// A bind group of the storage layout (compute passes): `read` at binding 0, `written`
    /// at binding 1.
    pub fn storage_group(&self, read: &wgpu::Buffer, written: &wgpu::Buffer) -> wgpu::BindGroup {
        self.group(
            "storage",
            &crate::layout::STORAGE,
            &[read.as_entire_binding(), written.as_entire_binding()],
        )
    }

    /// The compute pipeline of `desc`, compiled on first use.
    pub fn compute(&self, desc: &ComputeDesc) -> Result<wgpu::ComputePipeline, PipelineError> {
        if let Some(p) = self.compute.borrow().get(desc) {
            return Ok(p.clone());
        }
        let shader = desc.shader;
        let Entry::Compute(entry) = shader.entry else {
            return Err(PipelineError::Mismatch {
                module: shader.module_name(),
                message: "not a compute shader".into(),
            });
        };
        let layouts: Vec<wgpu::BindGroupLayout> =
            desc.groups.iter().map(|g| self.layout(g)).collect();
        let groups: Vec<Option<&wgpu::BindGroupLayout>> = layouts.iter().map(Some).collect();
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
            module: &self.module(shader)?,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        });
        self.compute.borrow_mut().insert(*desc, p.clone());
        self.built.set(self.built.get() + 1);
        Ok(p)
    }

    /// Pipelines compiled since the renderer was made.
    pub fn pipelines_built(&self) -> usize {
        self.built.get()
    }

    fn module(&self, shader: ShaderDesc) -> Result<wgpu::ShaderModule, PipelineError> {
        let key = (shader.file, shader.defs);
        if let Some(m) = self.modules.borrow().get(&key) {
            return Ok(m.clone());
        }
        let composed = match &*self.sources.borrow() {
            Some(texts) => shader.compose_with(|n| {
                texts
                    .iter()
                    .find(|(t, _)| *t == n)
                    .map_or("", |(_, s)| s.as_str())
            }),
            None => shader.compose(),
        }?;
        let module = self
            .gpu
            .device
            .create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(&shader.module_name()),
                source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(composed)),
            });
        self.modules.borrow_mut().insert(key, module.clone());
        Ok(module)
    }

    fn build(&self, key: &PipelineKey) -> Result<wgpu::RenderPipeline, PipelineError> {
        let PipelineDesc { shader, spec } = &key.desc;
        let mismatch = |message: String| PipelineError::Mismatch {
            module: shader.module_name(),
            message,
        };
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
                    write_mask: spec.writes.unwrap_or(wgpu::ColorWrites::ALL),
                })
            })
            .collect();
        let module = self.module(*shader)?;
        let device = &self.gpu.device;
        let name = shader.module_name();
        let layouts: Vec<wgpu::BindGroupLayout> =
            spec.groups.iter().map(|g| self.layout(g)).collect();
        let groups: Vec<Option<&wgpu::BindGroupLayout>> = layouts.iter().map(Some).collect();
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(&name),
            bind_group_layouts: &groups,
            immediate_size: 0,
        });
        let Entry::Render(vs, fs) = shader.entry else {
            return Err(mismatch("a compute shader in a render pass".into()));
        };
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
                    front_face: spec.front_face,
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
