//! Per-frame state: the uniforms a frame's cameras, lights and knobs decide (frame constants
//! per view and resolution, one slot per object and per light of each view, each view's
//! forward light array, the obliteration's shell table), in buffers made once and written with
//! `queue.write_buffer`. Several views of one scene share the buffers, each at its own slots
//! (view-major), so they are drawn in one frame.
//! Only bytes that changed since the last frame are written, so a still camera uploads
//! nothing and an orbit uploads a few hundred bytes; a buffer grows (and its bind group is
//! made again) only when a scene has more objects or lights than it holds.

use glam::Mat4;

use crate::layout::{self, LayoutDesc, SHELL_TABLE_BYTES};
use crate::plan::{Plan, PlannedLight, PlannedObject};
use crate::renderer::Renderer;
use crate::scene::{FurCoverage, FurLighting};
use crate::uniforms::{
    FrameUniforms, LightUniforms, MAX_FORWARD_LIGHTS, ObjectUniforms, UNIFORM_STRIDE,
};

pub use pelt_scene::shading::{SPECULAR_POWER, SPECULAR_STRENGTH};
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

/// Which frame constants a pass binds: its view's at L-buffer or at output resolution.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Res {
    /// The geometry and light passes.
    Lbuffer,
    /// Every output-resolution pass.
    Output,
}

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

/// One uniform buffer, its bind group and the bytes last written to it.
#[derive(Debug)]
struct Uniform {
    label: &'static str,
    buffer: wgpu::Buffer,
    group: wgpu::BindGroup,
    layout: LayoutDesc,
    /// Bytes of one binding (the element the shader sees).
    binding: u64,
    written: Vec<u8>,
}

impl Uniform {
    fn new(
        r: &Renderer,
        label: &'static str,
        layout: LayoutDesc,
        binding: u64,
        capacity: u64,
    ) -> Uniform {
        let buffer = r.gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: capacity.max(binding),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let group = r.group(
            label,
            &layout,
            &[wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                buffer: &buffer,
                offset: 0,
                size: wgpu::BufferSize::new(binding),
            })],
        );
        Uniform {
            label,
            buffer,
            group,
            layout,
            binding,
            written: Vec::new(),
        }
    }

    /// Writes `bytes`, growing the buffer first if they do not fit, and only the 256-byte
    /// blocks that differ from what the buffer holds.
    fn write(&mut self, r: &Renderer, bytes: &[u8]) {
        if bytes.len() as u64 > self.buffer.size() {
            let grown = (bytes.len() as u64).next_power_of_two();
            *self = Uniform::new(r, self.label, self.layout, self.binding, grown);
        }
        let block = UNIFORM_STRIDE as usize;
        let mut at = 0;
        while at < bytes.len() {
            let end = (at + block).min(bytes.len());
            if self.written.get(at..end) != Some(&bytes[at..end]) {
                // Runs of changed blocks go in one write.
                let mut stop = end;
                while stop < bytes.len() {
                    let next = (stop + block).min(bytes.len());
                    if self.written.get(stop..next) == Some(&bytes[stop..next]) {
                        break;
                    }
                    stop = next;
                }
                r.gpu
                    .write_buffer(&self.buffer, at as u64, &bytes[at..stop]);
                at = stop;
            } else {
                at = end;
            }
        }
        self.written.clear();
        self.written.extend_from_slice(bytes);
    }
}

/// The uniforms of one frame.
#[derive(Debug)]
pub struct FrameData {
    frame: Uniform,
    objects: Uniform,
    lights: Uniform,
    light_array: Uniform,
    shell_table: Uniform,
    /// Object slots per view.
    object_stride: usize,
    /// Light slots per view.
    light_stride: usize,
}

/// Bytes of one view's forward light array.
const LIGHT_ARRAY_BYTES: usize = MAX_FORWARD_LIGHTS * size_of::<LightUniforms>();

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
        wind: plan.wind.0,
        gust: plan.wind.1,
    }
}

/// The shell table's flag (obliterate.wgsl, light.wgsl): the G-buffer texels of this object
/// ID hold a strand tangent, lit with Kajiya-Kay. Keep in sync with `STRAND_LIT` in
/// shaders/common.wgsl.
pub const STRAND_LIT: u32 = 1 << 16;

fn light_uniforms(view: Mat4, l: &PlannedLight) -> LightUniforms {
    LightUniforms::new(&l.emitter, l.color, view, l.shadow)
}

fn object_uniforms(plan: &Plan, oit_scale: f32) -> Vec<ObjectUniforms> {
    plan.objects
        .iter()
        .map(|o| object_uniform(o, oit_scale))
        .collect()
}

/// One object's constants (`oit_scale`: the WBOIT weight scale).
pub fn object_uniform(o: &PlannedObject, oit_scale: f32) -> ObjectUniforms {
    let f = o.fur;
    ObjectUniforms {
        model: o.model.to_cols_array_2d(),
        normal_model: o.model.inverse().transpose().to_cols_array_2d(),
        tint: o.color.extend(1.0).into(),
        params: [
            o.opacity,
            SPECULAR_STRENGTH,
            o.map.unwrap_or(0) as f32,
            f.map_or(0.0, |f| f32::from(u8::from(f.color_from_texture))),
        ],
        fur_base: f.map_or([0.0; 4], |f| f.base_color.extend(f.length).into()),
        fur_tip: f.map_or([0.0; 4], |f| f.tip_color.extend(f.uv_scale).into()),
        fur_params: [RIM_STRENGTH, RIM_FALLOFF, STRAND_FADE, oit_scale],
        fur_model: f.map_or([0.0; 4], |f| {
            [
                f.medium[0],
                f.medium[1],
                f32::from(u8::from(f.coverage == FurCoverage::Binary)),
                f32::from(u8::from(f.lighting == FurLighting::Revie)),
            ]
        }),
        ids: [
            o.id,
            o.pattern,
            f.map_or(0, |f| f.shell_id),
            f.map_or(0, |f| f.shells),
        ],
        optics: o.optics.encoded(),
    }
}

impl FrameData {
    /// Empty buffers for a frame of a few objects and lights (they grow when needed).
    pub fn new(r: &Renderer) -> FrameData {
        let slot = |n: u64| n * UNIFORM_STRIDE;
        let light_array = LIGHT_ARRAY_BYTES as u64;
        FrameData {
            frame: Uniform::new(
                r,
                "frame",
                layout::FRAME,
                size_of::<FrameUniforms>() as u64,
                slot(2),
            ),
            objects: Uniform::new(
                r,
                "objects",
                layout::OBJECT,
                size_of::<ObjectUniforms>() as u64,
                slot(8),
            ),
            lights: Uniform::new(
                r,
                "lights",
                layout::LIGHT,
                size_of::<LightUniforms>() as u64,
                slot(8),
            ),
            light_array: Uniform::new(
                r,
                "light array",
                layout::LIGHT_ARRAY,
                light_array,
                light_array,
            ),
            shell_table: Uniform::new(
                r,
                "shell table",
                layout::SHELL_TABLE,
                SHELL_TABLE_BYTES as u64,
                SHELL_TABLE_BYTES as u64,
            ),
            object_stride: 1,
            light_stride: 1,
        }
    }

    /// Writes what `plan` decided (camera, objects, lights, knobs) as view 0.
    pub fn write(&mut self, r: &Renderer, plan: &Plan) {
        self.write_views(r, &[plan]);
    }

    /// Writes each view's plan at its slots (view v: frame slots 2v and 2v + 1, objects and
    /// lights from v × their stride, light array v).
    pub fn write_views(&mut self, r: &Renderer, plans: &[&Plan]) {
        self.object_stride = plans
            .iter()
            .map(|p| p.objects.len())
            .max()
            .unwrap_or(0)
            .max(1);
        self.light_stride = plans
            .iter()
            .map(|p| p.lights.len())
            .max()
            .unwrap_or(0)
            .max(1);
        let mut frames = Vec::with_capacity(2 * plans.len());
        let mut objects = Vec::new();
        let mut lights = Vec::new();
        let mut array =
            vec![<LightUniforms as bytemuck::Zeroable>::zeroed(); MAX_FORWARD_LIGHTS * plans.len()];
        let zero = <ObjectUniforms as bytemuck::Zeroable>::zeroed();
        for (v, plan) in plans.iter().enumerate() {
            let lsize = plan.lbuffer.unwrap_or((1, 1));
            frames.push(frame_uniforms(plan, lsize, lsize));
            frames.push(frame_uniforms(plan, plan.output, lsize));
            let layers: u32 = plan
                .objects
                .iter()
                .filter_map(|o| o.fur)
                .map(|f| f.shells + FIN_LAYERS)
                .sum();
            let mut o = object_uniforms(plan, wboit_scale(r.gpu.accum_format, layers));
            o.resize(self.object_stride, zero);
            objects.extend(o);
            let mut l: Vec<LightUniforms> = plan
                .lights
                .iter()
                .map(|x| light_uniforms(plan.view.view, x))
                .collect();
            for (a, x) in array[v * MAX_FORWARD_LIGHTS..].iter_mut().zip(&l) {
                *a = *x;
            }
            l.resize(
                self.light_stride,
                <LightUniforms as bytemuck::Zeroable>::zeroed(),
            );
            lights.extend(l);
        }
        self.frame.write(r, &strided(&frames));
        self.objects.write(r, &strided(&objects));
        self.lights.write(r, &strided(&lights));
        self.light_array.write(r, bytemuck::cast_slice(&array));
        let mut table = [0u32; 256];
        for o in plans.iter().flat_map(|p| &p.objects) {
            if let Some(f) = o.fur {
                let strands = if f.lighting == FurLighting::KajiyaKay {
                    STRAND_LIT
                } else {
                    0
                };
                table[(f.shell_id & 255) as usize] = (o.id & 255) | strands;
                table[(o.id & 255) as usize] |= strands;
            }
        }
        self.shell_table.write(r, bytemuck::cast_slice(&table));
    }

    /// Dynamic offset of view `view`'s frame constants at `res`.
    pub fn frame_offset(&self, view: usize, res: Res) -> u32 {
        let slot = 2 * view + usize::from(res == Res::Output);
        (slot as u64 * UNIFORM_STRIDE) as u32
    }

    /// Dynamic offset of object `k`'s uniforms in view `view`.
    pub fn object_offset(&self, view: usize, k: usize) -> u32 {
        ((view * self.object_stride + k) as u64 * UNIFORM_STRIDE) as u32
    }

    /// Dynamic offset of light `i`'s uniforms in view `view`.
    pub fn light_offset(&self, view: usize, i: usize) -> u32 {
        ((view * self.light_stride + i) as u64 * UNIFORM_STRIDE) as u32
    }

    /// Dynamic offset of view `view`'s forward light array.
    pub fn light_array_offset(&self, view: usize) -> u32 {
        (view * LIGHT_ARRAY_BYTES) as u32
    }

    /// Frame constants (dynamic offset [`FrameData::frame_offset`]).
    pub fn frame(&self) -> &wgpu::BindGroup {
        &self.frame.group
    }

    /// Object uniforms (dynamic offset [`FrameData::object_offset`]).
    pub fn objects(&self) -> &wgpu::BindGroup {
        &self.objects.group
    }

    /// One light per slot (light pass).
    pub fn lights(&self) -> &wgpu::BindGroup {
        &self.lights.group
    }

    /// Every light (forward).
    pub fn light_array(&self) -> &wgpu::BindGroup {
        &self.light_array.group
    }

    /// Which IDs are outer shells.
    pub fn shell_table(&self) -> &wgpu::BindGroup {
        &self.shell_table.group
    }
}
