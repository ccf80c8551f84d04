//! The per-scene half of the preview (re_renderer's `DrawData` against its `Renderer`): meshes
//! in vertex and index buffers (with their fur vertices, fin instances and fur textures),
//! uniform buffers for the frame, every object and every light, their bind groups, and the
//! render targets each pass writes (G-buffer, L-buffer, its obliterated composition copy, the
//! OIT accumulation, output). Built once per scene and plan; frames reuse it.

use glam::{Mat4, Vec3, Vec4Swizzles};
use wgpu::util::DeviceExt;

use crate::asset::MeshData;
use crate::fur::{FurData, Level};
use crate::plan::Plan;
use crate::renderer::{
    DEPTH_FORMAT, DSF_FORMAT, FIN_FORMAT, HEIGHT_FORMAT, LBUFFER_FORMAT, OUTPUT_FORMAT,
    REVEAL_FORMAT, Renderer, SHELL_TABLE_BYTES, SKY_FORMAT,
};
use crate::uniforms::{
    FrameUniforms, LightUniforms, MAX_FORWARD_LIGHTS, ObjectUniforms, UNIFORM_STRIDE,
};

/// Specular strength of every material (no per-asset specular yet).
pub const SPECULAR_STRENGTH: f32 = 0.25;
/// Blinn-Phong exponent for every light.
pub const SPECULAR_POWER: f32 = 32.0;
/// DSF depth threshold floor, in 16-bit depth quantisation steps.
pub const DEPTH_THRESHOLD_STEPS: u32 = 3;
/// Rim bend strength of the outer shell's normals (Revie Listing 2.3, `glowStrength`).
pub const RIM_STRENGTH: f32 = 0.8;
/// Rim falloff (Listing 2.3, `glowFalloff`).
pub const RIM_FALLOFF: f32 = 2.0;
/// Width (in normalized shell depth) over which a strand fades out below its height.
pub const STRAND_FADE: f32 = 0.15;
/// Fin layers assumed to overlap a pixel on top of the shells, for the OIT weight bound.
pub const FIN_LAYERS: u32 = 8;

/// The factor on every WBOIT weight: 1 with a 32-bit float accumulation; with a 16-bit one,
/// small enough that `layers` layers at the largest weight (3e3, McGuire & Bavoil eq. 7) sum
/// below 60 000 (f16 saturates at 65 504). A common factor cancels in the weighted average,
/// so only the 1e-2 floor's place in f16's range moves.
pub fn wboit_scale(accum: wgpu::TextureFormat, layers: u32) -> f32 {
    if accum == wgpu::TextureFormat::Rgba32Float {
        1.0
    } else {
        (60_000.0 / (3e3 * layers.max(1) as f32)).min(1.0)
    }
}

/// One mesh on the GPU.
#[derive(Debug)]
pub struct GpuMesh {
    /// Vertices.
    pub vertices: wgpu::Buffer,
    /// Triangle indices.
    pub indices: wgpu::Buffer,
    /// Index count.
    pub count: u32,
    /// Its fur, when a fur object uses it.
    pub fur: Option<GpuFur>,
}

/// A mesh's fur on the GPU.
#[derive(Debug)]
pub struct GpuFur {
    /// Fur vertices (vertex buffer 1 of the fur pipelines).
    pub vertices: wgpu::Buffer,
    /// Fin instances.
    pub fins: Option<wgpu::Buffer>,
    /// Fin count.
    pub fin_count: u32,
    /// Heightfield, fin texture and samplers.
    pub textures: wgpu::BindGroup,
}

/// The obliteration pass's output: the L-buffer and DSF buffer with the outer-shell stipple
/// texels replaced (Revie §2.4.4).
#[derive(Debug)]
pub struct Composition {
    /// Light.
    pub light: Target,
    /// Depth code and ID.
    pub dsf: Target,
    /// Size (the L-buffer's).
    pub size: (u32, u32),
}

/// Weighted blended OIT targets.
#[derive(Debug)]
pub struct Oit {
    /// Σ colour·α·w, Σ α·w.
    pub accum: Target,
    /// Π (1 − α).
    pub reveal: Target,
    /// Both, for the composite pass.
    pub read: wgpu::BindGroup,
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
    /// The original L-buffer and DSF buffer (1×1 stand-ins without one): the light the fur
    /// reads at root and tip.
    pub lbuffer_read: wgpu::BindGroup,
    /// The obliteration pass's composition copy, when the frame has fur and an L-buffer.
    pub composition: Option<Composition>,
    /// What the material pass reads: the composition copy when there is one, else
    /// `lbuffer_read`'s textures.
    pub material_read: wgpu::BindGroup,
    /// Which object IDs are fur outer shells (obliteration).
    pub shell_table: Option<wgpu::BindGroup>,
    /// Weighted blended OIT targets (fur with `--fur-blend wboit`).
    pub oit: Option<Oit>,
    /// The cube-map sky.
    pub sky: Option<wgpu::BindGroup>,
    /// Output.
    pub output: Output,
}

/// Six decoded cube faces (+X, −X, +Y, −Y, +Z, −Z), RGBA8 sRGB, `size` × `size` each.
#[derive(Debug, Clone)]
pub struct CubeImages {
    /// Side length.
    pub size: u32,
    /// Faces, rows top to bottom.
    pub faces: Vec<Vec<u8>>,
}

/// f32 to IEEE half-float bits (round to nearest even), for the heightfield texture.
pub fn f16_bits(v: f32) -> u16 {
    let x = v.to_bits();
    let sign = ((x >> 16) & 0x8000) as u16;
    let exp = ((x >> 23) & 0xff) as i32;
    let man = x & 0x7f_ffff;
    if exp == 0xff {
        return sign | 0x7c00 | if man != 0 { 0x200 } else { 0 };
    }
    let e = exp - 127 + 15;
    if e >= 0x1f {
        return sign | 0x7c00;
    }
    if e <= 0 {
        if e < -10 {
            return sign;
        }
        let m = man | 0x80_0000;
        let shift = (14 - e) as u32;
        let half = 1u32 << (shift - 1);
        let mut r = m >> shift;
        let rest = m & ((1 << shift) - 1);
        if rest > half || (rest == half && r & 1 == 1) {
            r += 1;
        }
        return sign | r as u16;
    }
    let mut r = ((e as u32) << 10) | (man >> 13);
    let rest = man & 0x1fff;
    if rest > 0x1000 || (rest == 0x1000 && r & 1 == 1) {
        r += 1;
    }
    sign | r as u16
}

fn upload_levels<T>(
    r: &Renderer,
    label: &str,
    format: wgpu::TextureFormat,
    levels: &[Level<T>],
    texel_bytes: impl Fn(&T) -> Vec<u8>,
) -> wgpu::TextureView {
    let device = &r.gpu.device;
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: levels[0].width,
            height: levels[0].height,
            depth_or_array_layers: 1,
        },
        mip_level_count: levels.len() as u32,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (i, l) in levels.iter().enumerate() {
        let bytes: Vec<u8> = l.texels.iter().flat_map(&texel_bytes).collect();
        let bpp = bytes.len() as u32 / (l.width * l.height).max(1);
        r.gpu.queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: i as u32,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            &bytes,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(l.width * bpp),
                rows_per_image: Some(l.height),
            },
            wgpu::Extent3d {
                width: l.width,
                height: l.height,
                depth_or_array_layers: 1,
            },
        );
    }
    texture.create_view(&wgpu::TextureViewDescriptor::default())
}

fn gpu_fur(r: &Renderer, fur: &FurData) -> GpuFur {
    let device = &r.gpu.device;
    let height = upload_levels(r, "heightfield", HEIGHT_FORMAT, &fur.heightfield, |&h| {
        f16_bits(f32::from(h) / 65535.0).to_le_bytes().to_vec()
    });
    let fin = upload_levels(r, "fin texture", FIN_FORMAT, &fur.fin, |t| t.to_vec());
    let sampler = |v_mode| {
        device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("fur"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: v_mode,
            address_mode_w: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        })
    };
    let repeat = sampler(wgpu::AddressMode::Repeat);
    let fin_sampler = sampler(wgpu::AddressMode::ClampToEdge);
    let textures = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("fur textures"),
        layout: &r.layouts.fur,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&height),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::TextureView(&fin),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: wgpu::BindingResource::Sampler(&repeat),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: wgpu::BindingResource::Sampler(&fin_sampler),
            },
        ],
    });
    GpuFur {
        vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("fur vertices"),
            contents: bytemuck::cast_slice(&fur.vertices),
            usage: wgpu::BufferUsages::VERTEX,
        }),
        fins: (!fur.fins.is_empty()).then(|| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("fins"),
                contents: bytemuck::cast_slice(&fur.fins),
                usage: wgpu::BufferUsages::VERTEX,
            })
        }),
        fin_count: fur.fins.len() as u32,
        textures,
    }
}

fn sky_group(r: &Renderer, cube: &CubeImages) -> wgpu::BindGroup {
    let device = &r.gpu.device;
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some("sky"),
        size: wgpu::Extent3d {
            width: cube.size,
            height: cube.size,
            depth_or_array_layers: 6,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: SKY_FORMAT,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    for (i, face) in cube.faces.iter().enumerate() {
        r.gpu.queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &texture,
                mip_level: 0,
                origin: wgpu::Origin3d {
                    x: 0,
                    y: 0,
                    z: i as u32,
                },
                aspect: wgpu::TextureAspect::All,
            },
            face,
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(cube.size * 4),
                rows_per_image: Some(cube.size),
            },
            wgpu::Extent3d {
                width: cube.size,
                height: cube.size,
                depth_or_array_layers: 1,
            },
        );
    }
    let view = texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::Cube),
        ..Default::default()
    });
    let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some("sky"),
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    });
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("sky"),
        layout: &r.layouts.sky,
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(&view),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: wgpu::BindingResource::Sampler(&sampler),
            },
        ],
    })
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
    pub fn new(
        r: &Renderer,
        plan: Plan,
        meshes: &[MeshData],
        cube: Option<&CubeImages>,
    ) -> DrawData {
        let device = &r.gpu.device;
        let l = &r.layouts;
        let furred: Vec<usize> = plan.fur.iter().map(|&k| plan.objects[k].mesh).collect();
        let gpu_meshes = meshes
            .iter()
            .enumerate()
            .map(|(i, m)| GpuMesh {
                fur: m
                    .fur
                    .as_ref()
                    .filter(|_| furred.contains(&i))
                    .map(|f| gpu_fur(r, f)),
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
        let layers: u32 = plan
            .objects
            .iter()
            .filter_map(|o| o.fur)
            .map(|f| f.shells + FIN_LAYERS)
            .sum();
        let oit_scale = wboit_scale(r.gpu.accum_format, layers);
        let objects: Vec<ObjectUniforms> = plan
            .objects
            .iter()
            .map(|o| {
                let f = o.fur;
                ObjectUniforms {
                    model: o.model.to_cols_array_2d(),
                    normal_model: o.model.inverse().transpose().to_cols_array_2d(),
                    tint: o.color.extend(1.0).into(),
                    params: [o.opacity, SPECULAR_STRENGTH, 0.0, 0.0],
                    fur_base: f.map_or([0.0; 4], |f| f.base_color.extend(f.length).into()),
                    fur_tip: f.map_or([0.0; 4], |f| f.tip_color.extend(f.uv_scale).into()),
                    fur_params: [RIM_STRENGTH, RIM_FALLOFF, STRAND_FADE, oit_scale],
                    ids: [
                        o.id,
                        o.pattern,
                        f.map_or(0, |f| f.shell_id),
                        f.map_or(0, |f| f.shells),
                    ],
                }
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
                wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
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
        // The obliteration pass: its composition copy, and which IDs are outer shells.
        let has_fur = !plan.fur.is_empty();
        let composition = plan.lbuffer.filter(|_| has_fur).map(|s| Composition {
            light: tex("composition", s, LBUFFER_FORMAT),
            dsf: tex("composition dsf", s, DSF_FORMAT),
            size: s,
        });
        let material_read = match &composition {
            Some(c) => pair(&c.light.view, &c.dsf.view),
            None => lbuffer_read.clone(),
        };
        let shell_table = has_fur.then(|| {
            let mut table = [0u32; 256];
            for o in &plan.objects {
                if let Some(f) = o.fur {
                    table[(f.shell_id & 255) as usize] = o.id;
                }
            }
            let buf = uniform("shell table", bytemuck::cast_slice(&table));
            debug_assert_eq!(buf.size(), SHELL_TABLE_BYTES);
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("shell table"),
                layout: &l.shell_table,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: buf.as_entire_binding(),
                }],
            })
        });
        let oit = (has_fur && plan.passes.contains(&crate::plan::Pass::FurAccum)).then(|| {
            let accum = tex("oit accum", plan.output, r.gpu.accum_format);
            let reveal = tex("oit reveal", plan.output, REVEAL_FORMAT);
            let read = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("oit"),
                layout: &l.oit,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(&accum.view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::TextureView(&reveal.view),
                    },
                ],
            });
            Oit {
                accum,
                reveal,
                read,
            }
        });
        let sky = cube.map(|c| sky_group(r, c));
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
            composition,
            material_read,
            shell_table,
            oit,
            sky,
            output,
        }
    }

    /// Dynamic offset of object `k`'s uniforms.
    pub fn object_offset(k: usize) -> u32 {
        (k as u64 * UNIFORM_STRIDE) as u32
    }
}
