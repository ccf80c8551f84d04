//! The long-lived half of the preview (re_renderer's `Renderer` against its `DrawData`): the
//! device, bind group layouts, shader modules and a cache of render pipelines keyed by a
//! hashable descriptor. Pipelines are built on demand by [`Renderer::prepare`], so only the
//! passes a plan uses are ever compiled.

use std::collections::HashMap;

use crate::gpu::Gpu;
use crate::plan::{Pass, Plan};
use crate::shaders::Shader;
use crate::uniforms::{FrameUniforms, LightUniforms, MAX_FORWARD_LIGHTS, ObjectUniforms, Vertex};

/// Linear light accumulation (RGB diffuse, A specular): 16-bit float, blendable everywhere.
pub const LBUFFER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// DSF buffer: 16-bit linear depth, 16-bit ID (integers: an ID in a float channel corrupts).
pub const DSF_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg16Uint;
/// Hardware depth for the geometry, material and forward passes.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The output image (lighting is linear; the target encodes sRGB).
pub const OUTPUT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// What makes one pipeline differ from another.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PipelineKey {
    /// The pass shader.
    pub shader: Shader,
    /// Alpha blending "over" (alpha objects in the material and forward passes).
    pub blend: bool,
}

/// Bind group layouts shared by the passes.
#[derive(Debug)]
pub struct Layouts {
    /// group 0: the frame uniforms (dynamic offset: one slot per resolution).
    pub frame: wgpu::BindGroupLayout,
    /// group 1 of geometry/material/forward: one object's uniforms (dynamic offset).
    pub object: wgpu::BindGroupLayout,
    /// light pass group 1, material pass group 2: a float texture and the DSF texture.
    pub textures: wgpu::BindGroupLayout,
    /// light pass group 2: one light (dynamic offset).
    pub light: wgpu::BindGroupLayout,
    /// forward pass group 2: every light.
    pub light_array: wgpu::BindGroupLayout,
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
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

impl Layouts {
    fn new(device: &wgpu::Device) -> Layouts {
        let layout = |label: &str, entries: &[wgpu::BindGroupLayoutEntry]| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries,
            })
        };
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
                    texture_entry(0, wgpu::TextureSampleType::Float { filterable: false }),
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
    modules: HashMap<Shader, wgpu::ShaderModule>,
    pipelines: HashMap<PipelineKey, wgpu::RenderPipeline>,
}

const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 4] = wgpu::vertex_attr_array![
    0 => Float32x3, 1 => Float32x3, 2 => Float32x4, 3 => Uint32
];

impl Renderer {
    /// A renderer on `gpu`; nothing is compiled yet.
    pub fn new(gpu: Gpu) -> Renderer {
        let layouts = Layouts::new(&gpu.device);
        Renderer {
            gpu,
            layouts,
            modules: HashMap::new(),
            pipelines: HashMap::new(),
        }
    }

    /// The pipelines `plan` draws with.
    pub fn keys(plan: &Plan) -> Vec<PipelineKey> {
        let mut keys = Vec::new();
        let has_alpha = !plan.alpha.is_empty();
        for p in &plan.passes {
            let shader = match p {
                Pass::Geometry => Shader::GBuffer,
                Pass::Light => Shader::Light,
                Pass::Material => Shader::Material,
                Pass::Forward => Shader::Forward,
            };
            let blendable = matches!(p, Pass::Material | Pass::Forward);
            if !blendable || !plan.opaque.is_empty() {
                keys.push(PipelineKey {
                    shader,
                    blend: false,
                });
            }
            if blendable && has_alpha {
                keys.push(PipelineKey {
                    shader,
                    blend: true,
                });
            }
        }
        keys
    }

    /// Compiles whatever `plan` needs that is not cached yet; returns how many pipelines were
    /// built.
    pub fn prepare(&mut self, plan: &Plan) -> usize {
        let mut built = 0;
        for key in Self::keys(plan) {
            if !self.pipelines.contains_key(&key) {
                let p = self.build(key);
                self.pipelines.insert(key, p);
                built += 1;
            }
        }
        built
    }

    /// A cached pipeline. Panics if [`Renderer::prepare`] did not build it (a bug in the
    /// pass list, not an input error).
    pub fn pipeline(&self, key: PipelineKey) -> &wgpu::RenderPipeline {
        #[expect(clippy::expect_used, reason = "prepare() builds every key a plan uses")]
        self.pipelines
            .get(&key)
            .expect("pipeline prepared for this plan")
    }

    /// Pipelines built so far.
    pub fn cached(&self) -> usize {
        self.pipelines.len()
    }

    fn module(&mut self, shader: Shader) -> wgpu::ShaderModule {
        let device = &self.gpu.device;
        self.modules
            .entry(shader)
            .or_insert_with(|| {
                device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(shader.file()),
                    source: wgpu::ShaderSource::Wgsl(shader.source().into()),
                })
            })
            .clone()
    }

    fn build(&mut self, key: PipelineKey) -> wgpu::RenderPipeline {
        let module = self.module(key.shader);
        let l = &self.layouts;
        let groups: Vec<Option<&wgpu::BindGroupLayout>> = match key.shader {
            Shader::GBuffer => vec![Some(&l.frame), Some(&l.object)],
            Shader::Light => vec![Some(&l.frame), Some(&l.textures), Some(&l.light)],
            Shader::Material => vec![Some(&l.frame), Some(&l.object), Some(&l.textures)],
            Shader::Forward => vec![Some(&l.frame), Some(&l.object), Some(&l.light_array)],
        };
        let device = &self.gpu.device;
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(key.shader.file()),
            bind_group_layouts: &groups,
            immediate_size: 0,
        });
        let vertex_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &VERTEX_ATTRIBUTES,
        })];
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
        let targets: Vec<Option<wgpu::ColorTargetState>> = match key.shader {
            Shader::GBuffer => vec![color(self.gpu.normal_format, None), color(DSF_FORMAT, None)],
            Shader::Light => vec![color(
                LBUFFER_FORMAT,
                Some(wgpu::BlendState {
                    color: additive,
                    alpha: additive,
                }),
            )],
            Shader::Material | Shader::Forward => vec![color(
                OUTPUT_FORMAT,
                key.blend.then_some(wgpu::BlendState::ALPHA_BLENDING),
            )],
        };
        let depth = (key.shader != Shader::Light).then(|| wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(!key.blend),
            depth_compare: Some(if key.blend {
                wgpu::CompareFunction::LessEqual
            } else {
                wgpu::CompareFunction::Less
            }),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        });
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(key.shader.file()),
            layout: Some(&layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_main"),
                compilation_options: Default::default(),
                buffers: if key.shader == Shader::Light {
                    &[]
                } else {
                    &vertex_buffers
                },
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: depth,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_main"),
                compilation_options: Default::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}
