//! The per-scene half of the preview (re_renderer's `DrawData` against its `Renderer`): meshes
//! in vertex and index buffers, uniform buffers for the frame, every object and every light,
//! their bind groups, and the render targets each pass writes (G-buffer, L-buffer, output).
//! Built once per scene and plan; frames reuse it.

use glam::{Mat4, Vec3, Vec4Swizzles};
use wgpu::util::DeviceExt;

use crate::asset::MeshData;
use crate::plan::Plan;
use crate::renderer::{DEPTH_FORMAT, DSF_FORMAT, LBUFFER_FORMAT, OUTPUT_FORMAT, Renderer};
use crate::uniforms::{
    FrameUniforms, LightUniforms, MAX_FORWARD_LIGHTS, ObjectUniforms, UNIFORM_STRIDE,
};

/// Specular strength of every material (no per-asset specular yet).
pub const SPECULAR_STRENGTH: f32 = 0.25;
/// Blinn-Phong exponent for every light.
pub const SPECULAR_POWER: f32 = 32.0;
/// DSF depth threshold floor, in 16-bit depth quantisation steps.
pub const DEPTH_THRESHOLD_STEPS: u32 = 3;

/// One mesh on the GPU.
#[derive(Debug)]
pub struct GpuMesh {
    /// Vertices.
    pub vertices: wgpu::Buffer,
    /// Triangle indices.
    pub indices: wgpu::Buffer,
    /// Index count.
    pub count: u32,
}

/// A texture and its default view.
#[derive(Debug)]
pub struct Target {
    /// The texture.
    pub texture: wgpu::Texture,
    /// Its view.
    pub view: wgpu::TextureView,
}

impl Target {
    fn new(
        device: &wgpu::Device,
        label: &str,
        size: (u32, u32),
        format: wgpu::TextureFormat,
        usage: wgpu::TextureUsages,
    ) -> Target {
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some(label),
            size: wgpu::Extent3d {
                width: size.0,
                height: size.1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        Target { texture, view }
    }
}

/// The geometry pass's outputs (Kircher & Lawrance §2.1).
#[derive(Debug)]
pub struct GBuffer {
    /// View normals, X/Y after eq. 1.
    pub normals: Target,
    /// Linear depth code and DSF ID.
    pub dsf: Target,
    /// Hardware depth.
    pub depth: Target,
    /// Size.
    pub size: (u32, u32),
}

/// The light pass's output: RGB diffuse, A specular intensity (§2.2).
#[derive(Debug)]
pub struct LBuffer {
    /// The light accumulation.
    pub light: Target,
    /// Size.
    pub size: (u32, u32),
}

/// The final image and its depth.
#[derive(Debug)]
pub struct Output {
    /// sRGB colour.
    pub color: Target,
    /// Depth.
    pub depth: Target,
    /// Size.
    pub size: (u32, u32),
}

/// Per-scene GPU data.
#[derive(Debug)]
pub struct DrawData {
    /// The plan it was built for.
    pub plan: Plan,
    /// Meshes, indexed by `PlannedObject::mesh`.
    pub meshes: Vec<GpuMesh>,
    /// Frame uniforms: slot 0 at L-buffer resolution, slot 1 at output resolution.
    pub frame: wgpu::BindGroup,
    /// Object uniforms, one slot per planned object.
    pub objects: wgpu::BindGroup,
    /// Light uniforms, one slot per planned light (light pass).
    pub light: wgpu::BindGroup,
    /// Every light in one array (forward pass).
    pub light_array: wgpu::BindGroup,
    /// G-buffer (absent without an L-buffer).
    pub gbuffer: Option<GBuffer>,
    /// L-buffer (absent without one).
    pub lbuffer: Option<LBuffer>,
    /// The textures the light pass reads (normals, DSF).
    pub gbuffer_read: Option<wgpu::BindGroup>,
    /// The textures the material pass reads (L-buffer, DSF; 1×1 stand-ins without one).
    pub lbuffer_read: wgpu::BindGroup,
    /// Output.
    pub output: Output,
}

fn frame_uniforms(plan: &Plan, target: (u32, u32), lbuffer: (u32, u32)) -> FrameUniforms {
    let v = &plan.view;
    let size = |s: (u32, u32)| [s.0 as f32, s.1 as f32, 1.0 / s.0 as f32, 1.0 / s.1 as f32];
    FrameUniforms {
        view: v.view.to_cols_array_2d(),
        proj: v.proj.to_cols_array_2d(),
        ambient: plan.ambient.extend(SPECULAR_POWER).into(),
        target_size: size(target),
        lbuffer_size: size(lbuffer),
        proj_params: [v.tan_half[0], v.tan_half[1], v.near, v.far],
        flags: [
            u32::from(plan.dsf),
            plan.lights.len().min(MAX_FORWARD_LIGHTS) as u32,
            DEPTH_THRESHOLD_STEPS,
            u32::from(plan.lbuffer.is_some()),
        ],
    }
}

fn light_uniforms(view: Mat4, l: &crate::plan::PlannedLight) -> LightUniforms {
    let p = (view * l.position.extend(1.0)).xyz();
    let lum = l.color.dot(Vec3::new(0.2126, 0.7152, 0.0722));
    LightUniforms {
        position_radius: p.extend(l.radius).into(),
        color: l.color.extend(lum).into(),
    }
}

/// `items` laid out one per [`UNIFORM_STRIDE`] bytes.
fn strided<T: bytemuck::Pod>(items: &[T]) -> Vec<u8> {
    let mut bytes = vec![0u8; items.len().max(1) * UNIFORM_STRIDE as usize];
    for (i, it) in items.iter().enumerate() {
        let b = bytemuck::bytes_of(it);
        let at = i * UNIFORM_STRIDE as usize;
        bytes[at..at + b.len()].copy_from_slice(b);
    }
    bytes
}

impl DrawData {
    /// Uploads `meshes` and the plan's uniforms and creates the targets.
    pub fn new(r: &Renderer, plan: Plan, meshes: &[MeshData]) -> DrawData {
        let device = &r.gpu.device;
        let l = &r.layouts;
        let gpu_meshes = meshes
            .iter()
            .map(|m| GpuMesh {
                vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("vertices"),
                    contents: bytemuck::cast_slice(&m.vertices),
                    usage: wgpu::BufferUsages::VERTEX,
                }),
                indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("indices"),
                    contents: bytemuck::cast_slice(&m.indices),
                    usage: wgpu::BufferUsages::INDEX,
                }),
                count: m.indices.len() as u32,
            })
            .collect();
        let lsize = plan.lbuffer.unwrap_or((1, 1));
        let frames = [
            frame_uniforms(&plan, lsize, lsize),
            frame_uniforms(&plan, plan.output, lsize),
        ];
        let objects: Vec<ObjectUniforms> = plan
            .objects
            .iter()
            .map(|o| ObjectUniforms {
                model: o.model.to_cols_array_2d(),
                normal_model: o.model.inverse().transpose().to_cols_array_2d(),
                tint: o.color.extend(1.0).into(),
                params: [o.opacity, SPECULAR_STRENGTH, 0.0, 0.0],
                ids: [o.id, o.pattern, 0, 0],
            })
            .collect();
        let lights: Vec<LightUniforms> = plan
            .lights
            .iter()
            .map(|x| light_uniforms(plan.view.view, x))
            .collect();
        let mut array = vec![<LightUniforms as bytemuck::Zeroable>::zeroed(); MAX_FORWARD_LIGHTS];
        for (a, x) in array.iter_mut().zip(&lights) {
            *a = *x;
        }
        let uniform = |label: &str, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::UNIFORM,
            })
        };
        let bind = |layout: &wgpu::BindGroupLayout, buffer: &wgpu::Buffer, size: usize| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer,
                        offset: 0,
                        size: wgpu::BufferSize::new(size as u64),
                    }),
                }],
            })
        };
        let frame_buf = uniform("frame", &strided(&frames));
        let object_buf = uniform("objects", &strided(&objects));
        let light_buf = uniform("lights", &strided(&lights));
        let array_buf = uniform("light array", bytemuck::cast_slice(&array));

        let tex = |label, size, format| {
            Target::new(
                device,
                label,
                size,
                format,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            )
        };
        let gbuffer = plan.lbuffer.map(|s| GBuffer {
            normals: tex("normals", s, r.gpu.normal_format),
            dsf: tex("dsf", s, DSF_FORMAT),
            depth: tex("gbuffer depth", s, DEPTH_FORMAT),
            size: s,
        });
        let lbuffer = plan.lbuffer.map(|s| LBuffer {
            light: tex("lbuffer", s, LBUFFER_FORMAT),
            size: s,
        });
        let pair = |a: &wgpu::TextureView, b: &wgpu::TextureView| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &l.textures,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(a),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(b),
                    },
                ],
            })
        };
        let gbuffer_read = gbuffer.as_ref().map(|g| pair(&g.normals.view, &g.dsf.view));
        let lbuffer_read = match (&lbuffer, &gbuffer) {
            (Some(lb), Some(g)) => pair(&lb.light.view, &g.dsf.view),
            _ => {
                // Stand-ins the material shader never reads (flags.w = 0: ambient only).
                let a = tex("no lbuffer", (1, 1), LBUFFER_FORMAT);
                let b = tex("no dsf", (1, 1), DSF_FORMAT);
                pair(&a.view, &b.view)
            }
        };
        let output = Output {
            color: Target::new(
                device,
                "output",
                plan.output,
                OUTPUT_FORMAT,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
            ),
            depth: tex("output depth", plan.output, DEPTH_FORMAT),
            size: plan.output,
        };
        DrawData {
            frame: bind(&l.frame, &frame_buf, size_of::<FrameUniforms>()),
            objects: bind(&l.object, &object_buf, size_of::<ObjectUniforms>()),
            light: bind(&l.light, &light_buf, size_of::<LightUniforms>()),
            light_array: bind(
                &l.light_array,
                &array_buf,
                array.len() * size_of::<LightUniforms>(),
            ),
            plan,
            meshes: gpu_meshes,
            gbuffer,
            lbuffer,
            gbuffer_read,
            lbuffer_read,
            output,
        }
    }

    /// Dynamic offset of object `k`'s uniforms.
    pub fn object_offset(k: usize) -> u32 {
        (k as u64 * UNIFORM_STRIDE) as u32
    }
}
