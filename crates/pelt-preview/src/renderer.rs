//! The long-lived half of the preview (re_renderer's `Renderer` against its `DrawData`): the
//! device, bind group layouts, shader modules and a cache of render pipelines keyed by a
//! hashable descriptor. Pipelines are built on demand by [`Renderer::prepare`], so only the
//! passes a plan uses are ever compiled.

use std::cell::RefCell;
use std::collections::HashMap;

use crate::gpu::Gpu;
use crate::plan::{Mode, Pass, Plan};
use crate::scene::{FurBlend, Sky};
use crate::shaders::{Lighting, Shader};
use crate::uniforms::{
    FinInstance, FrameUniforms, FurVertex, LightUniforms, MAX_FORWARD_LIGHTS, ObjectUniforms,
    Vertex,
};

/// Linear light accumulation (RGB diffuse, A specular): 16-bit float, blendable everywhere.
pub const LBUFFER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// DSF buffer: 16-bit linear depth, 16-bit ID (integers: an ID in a float channel corrupts).
pub const DSF_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Uint;
/// Hardware depth for the geometry, material and forward passes.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The output image (lighting is linear; the target encodes sRGB).
pub const OUTPUT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// Revealage of weighted blended OIT: 16-bit float (8 bits band after a few layers).
pub const REVEAL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;
/// The cube-map sky's faces.
pub const SKY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// The heightfield (16-bit heights as half floats: filterable everywhere).
pub const HEIGHT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R16Float;
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

/// What makes one pipeline differ from another.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PipelineKey {
    /// The shader module and entry points.
    pub shader: Shader,
    /// How it blends.
    pub blend: Blend,
}

/// Bind group layouts shared by the passes.
#[derive(Debug)]
pub struct Layouts {
    /// group 0: the frame uniforms (dynamic offset: one slot per resolution).
    pub frame: wgpu::BindGroupLayout,
    /// group 1 of the object passes: one object's uniforms (dynamic offset).
    pub object: wgpu::BindGroupLayout,
    /// A float texture and the DSF texture (light pass group 1, material and fur group 2,
    /// obliteration group 0).
    pub textures: wgpu::BindGroupLayout,
    /// light pass group 2: one light (dynamic offset).
    pub light: wgpu::BindGroupLayout,
    /// forward group 2: every light.
    pub light_array: wgpu::BindGroupLayout,
    /// fur group 3: heightfield, fin texture, their samplers.
    pub fur: wgpu::BindGroupLayout,
    /// obliteration group 1: which IDs are outer shells.
    pub shell_table: wgpu::BindGroupLayout,
    /// composite group 0: accumulation and revealage.
    pub oit: wgpu::BindGroupLayout,
    /// cube sky group 1: the cube map and its sampler.
    pub sky: wgpu::BindGroupLayout,
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

fn texture_entry(binding: u32, sample_type: wgpu::TextureSampleType) -> wgpu::BindGroupLayoutEntry {
    texture_dim_entry(binding, sample_type, wgpu::TextureViewDimension::D2)
}

fn texture_dim_entry(
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

impl Layouts {
    fn new(device: &wgpu::Device) -> Layouts {
        let layout = |label: &str, entries: &[wgpu::BindGroupLayoutEntry]| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries,
            })
        };
        let unfilterable = wgpu::TextureSampleType::Float { filterable: false };
        let filterable = wgpu::TextureSampleType::Float { filterable: true };
        Layouts {
            frame: layout(
                "frame",
                &[uniform_entry(size_of::<FrameUniforms>() as u64, true)],
            ),
            object: layout(
                "object",
                &[uniform_entry(size_of::<ObjectUniforms>() as u64, true)],
            ),
            textures: layout(
                "textures",
                &[
                    texture_entry(0, unfilterable),
                    texture_entry(1, wgpu::TextureSampleType::Uint),
                ],
            ),
            light: layout(
                "light",
                &[uniform_entry(size_of::<LightUniforms>() as u64, true)],
            ),
            light_array: layout(
                "light array",
                &[uniform_entry(
                    (MAX_FORWARD_LIGHTS * size_of::<LightUniforms>()) as u64,
                    false,
                )],
            ),
            fur: layout(
                "fur textures",
                &[
                    texture_entry(0, filterable),
                    texture_entry(1, filterable),
                    sampler_entry(2),
                    sampler_entry(3),
                ],
            ),
            shell_table: layout("shell table", &[uniform_entry(SHELL_TABLE_BYTES, false)]),
            oit: layout(
                "oit",
                &[
                    texture_entry(0, unfilterable),
                    texture_entry(1, unfilterable),
                ],
            ),
            sky: layout(
                "sky",
                &[
                    texture_dim_entry(0, filterable, wgpu::TextureViewDimension::Cube),
                    sampler_entry(1),
                ],
            ),
        }
    }
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
}

const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 4] = wgpu::vertex_attr_array![
    0 => Float32x3, 1 => Float32x3, 2 => Float32x4, 3 => Uint32
];
const FUR_ATTRIBUTES: [wgpu::VertexAttribute; 3] = wgpu::vertex_attr_array![
    4 => Float32x4, 5 => Float32x2, 6 => Float32x4
];
const FIN_ATTRIBUTES: [wgpu::VertexAttribute; 10] = wgpu::vertex_attr_array![
    0 => Float32x3, 1 => Float32x3, 2 => Float32x3, 3 => Float32x3, 4 => Float32x4,
    5 => Float32x4, 6 => Float32x3, 7 => Float32x3, 8 => Float32x2, 9 => Uint32
];

impl Renderer {
    /// A renderer on `gpu`; nothing is compiled yet.
    pub fn new(gpu: Gpu) -> Renderer {
        let layouts = Layouts::new(&gpu.device);
        Renderer {
            gpu,
            layouts,
            modules: RefCell::new(HashMap::new()),
            pipelines: RefCell::new(HashMap::new()),
        }
    }

    /// The pipelines `plan` draws with.
    pub fn keys(plan: &Plan) -> Vec<PipelineKey> {
        let mut keys = Vec::new();
        let mut add = |shader, blend| {
            let k = PipelineKey { shader, blend };
            if !keys.contains(&k) {
                keys.push(k);
            }
        };
        let has_fins = plan
            .fur
            .iter()
            .any(|&k| plan.objects[k].fur.is_some_and(|f| f.fins));
        let wboit = plan.fur_blend == FurBlend::Wboit;
        let lighting = if plan.mode == Mode::Forward {
            Lighting::Forward
        } else {
            Lighting::Inferred
        };
        for p in &plan.passes {
            match p {
                Pass::Geometry => {
                    if !plan.opaque.is_empty() || !plan.alpha.is_empty() {
                        add(Shader::GBuffer, Blend::None);
                    }
                    if !plan.fur.is_empty() {
                        add(Shader::FurBase, Blend::None);
                        add(Shader::FurOuter, Blend::None);
                    }
                }
                Pass::Light => add(Shader::Light, Blend::None),
                Pass::Obliterate => add(Shader::Obliterate, Blend::None),
                Pass::Material | Pass::Forward => {
                    let shader = if *p == Pass::Forward {
                        Shader::Forward
                    } else {
                        Shader::Material
                    };
                    if !plan.opaque.is_empty() {
                        add(shader, Blend::None);
                    }
                    if !plan.alpha.is_empty() {
                        add(shader, Blend::Over);
                    }
                    if !plan.fur.is_empty() {
                        add(Shader::Shells(lighting), Blend::None);
                        if !wboit {
                            add(Shader::Shells(lighting), Blend::Over);
                            if has_fins {
                                add(Shader::Fins(lighting), Blend::Over);
                            }
                        }
                    }
                    match plan.sky {
                        Sky::None => {}
                        Sky::Procedural => add(Shader::SkyProcedural, Blend::None),
                        Sky::Cubemap(_) => add(Shader::SkyCube, Blend::None),
                    }
                }
                Pass::FurAccum => {
                    add(Shader::Shells(lighting), Blend::Wboit);
                    if has_fins {
                        add(Shader::Fins(lighting), Blend::Wboit);
                    }
                }
                Pass::Composite => add(Shader::Composite, Blend::Over),
            }
        }
        keys
    }

    /// Compiles whatever `plan` needs that is not cached yet; returns how many pipelines were
    /// built.
    pub fn prepare(&self, plan: &Plan) -> usize {
        let mut built = 0;
        for key in Self::keys(plan) {
            if !self.pipelines.borrow().contains_key(&key) {
                let p = self.build(key);
                self.pipelines.borrow_mut().insert(key, p);
                built += 1;
            }
        }
        built
    }

    /// A pipeline: from the cache, or built now (a pass needing one `prepare` did not
    /// foresee still works; it just compiles during the frame).
    pub fn pipeline(&self, key: PipelineKey) -> wgpu::RenderPipeline {
        if let Some(p) = self.pipelines.borrow().get(&key) {
            return p.clone();
        }
        let p = self.build(key);
        self.pipelines.borrow_mut().insert(key, p.clone());
        p
    }

    /// Pipelines built so far.
    pub fn cached(&self) -> usize {
        self.pipelines.borrow().len()
    }

    fn module(&self, shader: Shader) -> wgpu::ShaderModule {
        let device = &self.gpu.device;
        self.modules
            .borrow_mut()
            .entry(shader)
            .or_insert_with(|| {
                device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(&shader.module_name()),
                    source: wgpu::ShaderSource::Wgsl(shader.source().into()),
                })
            })
            .clone()
    }

    fn build(&self, key: PipelineKey) -> wgpu::RenderPipeline {
        let module = self.module(key.shader);
        let l = &self.layouts;
        let light_source = |lighting| match lighting {
            Lighting::Inferred => &l.textures,
            Lighting::Forward => &l.light_array,
        };
        let groups: Vec<Option<&wgpu::BindGroupLayout>> = match key.shader {
            Shader::GBuffer | Shader::FurBase | Shader::FurOuter => {
                vec![Some(&l.frame), Some(&l.object)]
            }
            Shader::Light => vec![Some(&l.frame), Some(&l.textures), Some(&l.light)],
            Shader::Material => vec![Some(&l.frame), Some(&l.object), Some(&l.textures)],
            Shader::Forward => vec![Some(&l.frame), Some(&l.object), Some(&l.light_array)],
            Shader::Shells(lt) | Shader::Fins(lt) => vec![
                Some(&l.frame),
                Some(&l.object),
                Some(light_source(lt)),
                Some(&l.fur),
            ],
            Shader::Obliterate => vec![Some(&l.textures), Some(&l.shell_table)],
            Shader::Composite => vec![Some(&l.oit)],
            Shader::SkyProcedural => vec![Some(&l.frame)],
            Shader::SkyCube => vec![Some(&l.frame), Some(&l.sky)],
        };
        let device = &self.gpu.device;
        let name = key.shader.module_name();
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(&name),
            bind_group_layouts: &groups,
            immediate_size: 0,
        });
        let per_vertex = |stride: usize, attributes| {
            Some(wgpu::VertexBufferLayout {
                array_stride: stride as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes,
            })
        };
        let vertex_buffers: Vec<Option<wgpu::VertexBufferLayout<'_>>> = match key.shader {
            Shader::GBuffer | Shader::Material | Shader::Forward => {
                vec![per_vertex(size_of::<Vertex>(), &VERTEX_ATTRIBUTES[..])]
            }
            Shader::FurBase | Shader::FurOuter | Shader::Shells(_) => vec![
                per_vertex(size_of::<Vertex>(), &VERTEX_ATTRIBUTES[..]),
                per_vertex(size_of::<FurVertex>(), &FUR_ATTRIBUTES[..]),
            ],
            Shader::Fins(_) => vec![Some(wgpu::VertexBufferLayout {
                array_stride: size_of::<FinInstance>() as u64,
                step_mode: wgpu::VertexStepMode::Instance,
                attributes: &FIN_ATTRIBUTES,
            })],
            _ => Vec::new(),
        };
        let color = |format, blend| {
            Some(wgpu::ColorTargetState {
                format,
                blend,
                write_mask: wgpu::ColorWrites::ALL,
            })
        };
        let additive = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::One,
            dst_factor: wgpu::BlendFactor::One,
            operation: wgpu::BlendOperation::Add,
        };
        let add_all = Some(wgpu::BlendState {
            color: additive,
            alpha: additive,
        });
        // Revealage: dst × (1 − src).
        let reveal = wgpu::BlendComponent {
            src_factor: wgpu::BlendFactor::Zero,
            dst_factor: wgpu::BlendFactor::OneMinusSrc,
            operation: wgpu::BlendOperation::Add,
        };
        let targets: Vec<Option<wgpu::ColorTargetState>> = match (key.shader, key.blend) {
            (Shader::GBuffer | Shader::FurBase | Shader::FurOuter, _) => {
                vec![color(self.gpu.normal_format, None), color(DSF_FORMAT, None)]
            }
            (Shader::Light, _) => vec![color(LBUFFER_FORMAT, add_all)],
            (Shader::Obliterate, _) => vec![color(LBUFFER_FORMAT, None), color(DSF_FORMAT, None)],
            (_, Blend::Wboit) => vec![
                color(self.gpu.accum_format, add_all),
                color(
                    REVEAL_FORMAT,
                    Some(wgpu::BlendState {
                        color: reveal,
                        alpha: reveal,
                    }),
                ),
            ],
            (_, Blend::Over) => vec![color(OUTPUT_FORMAT, Some(wgpu::BlendState::ALPHA_BLENDING))],
            (_, Blend::None) => vec![color(OUTPUT_FORMAT, None)],
        };
        let depth = |write: bool, compare| {
            Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(write),
                depth_compare: Some(compare),
                stencil: wgpu::StencilState::default(),
                bias: wgpu::DepthBiasState::default(),
            })
        };
        let depth_stencil = match (key.shader, key.blend) {
            (Shader::Light | Shader::Obliterate, _) => None,
            (Shader::Composite, _) => depth(false, wgpu::CompareFunction::Always),
            (Shader::SkyProcedural | Shader::SkyCube, _) => {
                depth(false, wgpu::CompareFunction::LessEqual)
            }
            (_, Blend::None) => depth(true, wgpu::CompareFunction::Less),
            _ => depth(false, wgpu::CompareFunction::LessEqual),
        };
        // Blended shells show only their outer side (the far side's shells stick out behind
        // the silhouette, where they would blend in the wrong order).
        let cull_mode = matches!(
            (key.shader, key.blend),
            (Shader::Shells(_), Blend::Over | Blend::Wboit)
        )
        .then_some(wgpu::Face::Back);
        let (vs, fs) = key.shader.entry_points(key.blend == Blend::Wboit);
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(&name),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some(vs),
                compilation_options: Default::default(),
                buffers: &vertex_buffers,
            },
            primitive: wgpu::PrimitiveState {
                cull_mode,
                ..Default::default()
            },
            depth_stencil,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some(fs),
                compilation_options: Default::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}
