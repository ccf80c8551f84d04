//! What the distance maps are drawn from, the per-frame half of [`super::Maps`]: each face's
//! camera, every object's constants and the scene's lights (GPU Gems 3 §17.2.1), the
//! search's knobs (§17.2.2), and whether a frame has drawn the maps since these last
//! changed. Written every frame and uploaded only when they changed, so a camera move, an
//! L-buffer scale or a search knob leaves the maps as they are.
//!
//! Fur objects go into the maps as their shells (shells.wgsl's `fs_distance`), each face
//! a frame about the reference point (view space is world space moved to it, so one array
//! of lights per map serves its faces) and at most [`MAP_SHELLS`] thicker layers.

use std::sync::atomic::{AtomicBool, Ordering};

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

use crate::cube::face_view;
use crate::layout::{self, LayoutDesc};
use crate::plan::ScenePlan;
use crate::renderer::Renderer;
use crate::scene::{Sky, Technique};
use crate::uniforms::{FrameUniforms, LightUniforms, ObjectUniforms, UNIFORM_STRIDE};

/// Most distance maps (mirror and glass objects) in a scene.
pub const MAX_MAPS: usize = 64;
/// Most lights the maps are lit by (distance_map.wgsl's `MAX_MAP_LIGHTS`).
pub const MAX_MAP_LIGHTS: usize = 256;
/// Most shells a fur object draws into a distance map: fewer, thicker layers hold the same
/// fur (each layer's opacity is the strand model's over its thickness), as from a light.
pub const MAP_SHELLS: u32 = 8;

/// One face of one layer. Keep in sync with `Face` in shaders/distance_map.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct FaceUniforms {
    /// World to this face's clip space.
    pub view_proj: [[f32; 4]; 4],
    /// xyz: the reference point.
    pub reference: [f32; 4],
    /// rgb ambient; w specular power.
    pub ambient: [f32; 4],
    /// x layer, y light count, z the map's object (scene index), w face.
    pub ids: [u32; 4],
}

/// The search's knobs and the reference points. Keep in sync with `Reflect` in
/// shaders/reflect.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct ReflectUniforms {
    /// x linear steps, y secant steps, z layers, w most bounces.
    pub knobs: [u32; 4],
    /// x: min-max on (bit 0) and the map count (bits 8..); y technique (0 distance maps, 1
    /// environment map); z sky (0 background, 1 procedural, 2 cube map); w cube face size.
    pub flags: [u32; 4],
    /// rgb background, w the scene's radius.
    pub background: [f32; 4],
    /// x specular strength, y specular power, z light count.
    pub shading: [f32; 4],
    /// Each map's reference point, and the radius about it that holds the whole scene.
    pub maps: [[f32; 4]; MAX_MAPS],
    /// Each map's object: its bounds' centre and radius.
    pub objects: [[f32; 4]; MAX_MAPS],
}

/// One distance-map face's constants (dynamic offset; distance_map.wgsl).
pub const FACE_LAYOUT: LayoutDesc = LayoutDesc {
    label: "distance-map face",
    entries: &[layout::uniform(0, size_of::<FaceUniforms>(), true)],
};

/// The maps' inputs: uniforms and the draw list, with their last written bytes.
#[derive(Debug)]
pub struct MapInputs {
    faces: wgpu::Buffer,
    pub(super) faces_group: wgpu::BindGroup,
    objects: wgpu::Buffer,
    pub(super) objects_group: wgpu::BindGroup,
    pub(super) lights: wgpu::Buffer,
    pub(super) lights_group: wgpu::BindGroup,
    pub(super) params: wgpu::Buffer,
    fur_frames: wgpu::Buffer,
    /// Each face's frame for the fur's shells (dynamic offset, as `faces_group`).
    pub(super) fur_frames_group: wgpu::BindGroup,
    fur_lights: wgpu::Buffer,
    /// Each map's lights about its reference point (dynamic offset: the map × the array).
    pub(super) fur_lights_group: wgpu::BindGroup,
    /// What goes into the maps: (object slot, mesh index, scene index).
    pub(super) draws: Vec<(usize, usize, usize)>,
    /// The fur objects: (object slot, mesh index, scene index, shells drawn).
    pub(super) fur: Vec<(usize, usize, usize, u32)>,
    /// The maps hold the scene as last written (a frame has rendered them since).
    fresh: AtomicBool,
    /// The bytes the maps were last drawn from (faces, objects, lights, draws).
    drawn: Vec<u8>,
    /// The search's uniforms as last written.
    params_written: Vec<u8>,
}

impl MapInputs {
    /// Buffers for `faces` faces (maps × layers × 6) and `plan`'s objects, not yet written.
    pub fn new(r: &Renderer, plan: &ScenePlan, faces: u32) -> MapInputs {
        let stride = UNIFORM_STRIDE;
        let uniform = wgpu::BufferUsages::UNIFORM;
        let face_buf = r.buffer("faces", u64::from(faces) * stride, uniform);
        let n_objects = plan.objects.len().max(1) as u64;
        let objects = r.buffer("map objects", n_objects * stride, uniform);
        let light_bytes = MAX_MAP_LIGHTS * size_of::<LightUniforms>();
        let lights = r.buffer("map lights", light_bytes as u64, uniform);
        let params = r.buffer(
            "reflect params",
            size_of::<ReflectUniforms>() as u64,
            uniform,
        );
        let fur_frames = r.buffer("fur frames", u64::from(faces) * stride, uniform);
        let n_maps = plan.maps.len().max(1) as u64;
        let fur_lights = r.buffer("fur lights", n_maps * light_bytes as u64, uniform);
        MapInputs {
            fur_frames_group: r.group(
                "fur frames",
                &layout::FRAME,
                &[layout::sized(&fur_frames, size_of::<FrameUniforms>())],
            ),
            fur_lights_group: r.group(
                "fur lights",
                &layout::LIGHT_ARRAY,
                &[layout::sized(&fur_lights, light_bytes)],
            ),
            fur_frames,
            fur_lights,
            fur: Vec::new(),
            faces_group: r.group(
                "faces",
                &FACE_LAYOUT,
                &[layout::sized(&face_buf, size_of::<FaceUniforms>())],
            ),
            objects_group: r.group(
                "map objects",
                &layout::OBJECT,
                &[layout::sized(&objects, size_of::<ObjectUniforms>())],
            ),
            lights_group: r.group(
                "map lights",
                &layout::LIGHT_ARRAY,
                &[layout::sized(&lights, light_bytes)],
            ),
            faces: face_buf,
            objects,
            lights,
            params,
            draws: Vec::new(),
            fresh: AtomicBool::new(false),
            drawn: Vec::new(),
            params_written: Vec::new(),
        }
    }

    /// Whether a frame has rendered the maps since the scene was last written.
    pub fn fresh(&self) -> bool {
        self.fresh.load(Ordering::Relaxed)
    }

    /// Records that a submitted frame rendered the maps.
    pub fn mark_fresh(&self) {
        self.fresh.store(true, Ordering::Relaxed);
    }

    /// Writes the faces, objects, lights and knobs of `plan` for `views` map faces; when what
    /// the maps are drawn from changed, the next frame renders them again.
    pub fn write(&mut self, r: &Renderer, plan: &ScenePlan, views: usize) {
        let k = plan.reflections;
        let (centre, radius) = plan.extent;
        let lights: Vec<LightUniforms> = plan
            .lights
            .iter()
            .take(MAX_MAP_LIGHTS)
            // The maps are lit unshadowed.
            .map(|l| LightUniforms::new(&l.emitter, l.color, Mat4::IDENTITY, None))
            .collect();
        let stride = UNIFORM_STRIDE as usize;
        let mut faces = vec![0u8; views * stride];
        for (m, map) in plan.maps.iter().enumerate() {
            let (proj, _, _) = face_projection(plan, map.reference);
            let to_ref = Mat4::from_translation(-map.reference);
            for layer in 0..k.layers {
                for face in 0..6u32 {
                    let i = (m as u32 * k.layers + layer) * 6 + face;
                    let u = FaceUniforms {
                        view_proj: (proj * face_view(face) * to_ref).to_cols_array_2d(),
                        reference: map.reference.extend(0.0).into(),
                        ambient: plan
                            .ambient
                            .extend(crate::frame_data::SPECULAR_POWER)
                            .into(),
                        ids: [layer, lights.len() as u32, map.scene_index as u32, face],
                    };
                    let at = i as usize * stride;
                    faces[at..at + size_of::<FaceUniforms>()]
                        .copy_from_slice(bytemuck::bytes_of(&u));
                }
            }
        }
        let mut objects = vec![0u8; plan.objects.len() * stride];
        let mut draws = Vec::new();
        let mut fur = Vec::new();
        for (i, (o, _)) in plan.objects.iter().enumerate() {
            let u = if o.fur.is_some() {
                // The fur's own constants, as the view draws its shells.
                let mut u = crate::frame_data::object_uniform(o, 1.0);
                u.ids[0] = o.scene_index as u32;
                u.ids[1] = 0;
                u
            } else {
                ObjectUniforms {
                    model: o.model.to_cols_array_2d(),
                    normal_model: o.model.inverse().transpose().to_cols_array_2d(),
                    tint: o.color.extend(1.0).into(),
                    params: [1.0, crate::frame_data::SPECULAR_STRENGTH, 0.0, 0.0],
                    fur_base: [0.0; 4],
                    fur_tip: [0.0; 4],
                    fur_params: [0.0; 4],
                    fur_model: [0.0; 4],
                    ids: [o.scene_index as u32, 0, 0, 0],
                    optics: o.optics.encoded(),
                }
            };
            objects[i * stride..i * stride + size_of::<ObjectUniforms>()]
                .copy_from_slice(bytemuck::bytes_of(&u));
            match o.fur {
                _ if o.pattern != 0 => {}
                // Bald fur draws its skin alone (instance 0), as the view does.
                Some(f) => {
                    let n = if f.bald() {
                        0
                    } else {
                        f.shells.min(MAP_SHELLS)
                    };
                    fur.push((i, o.mesh, o.scene_index, n));
                }
                None => draws.push((i, o.mesh, o.scene_index)),
            }
        }
        let mut light_bytes = vec![0u8; MAX_MAP_LIGHTS * size_of::<LightUniforms>()];
        let lb: &[u8] = bytemuck::cast_slice(&lights);
        light_bytes[..lb.len()].copy_from_slice(lb);
        // What the maps are drawn from; a change (not a camera move, an L-buffer scale, a
        // search knob) makes them stale.
        // The wind bends the fur in the maps as it stood when they were drawn: its time
        // alone does not draw them again.
        let (wind, gust) = plan.wind;
        let drawn = [
            faces.as_slice(),
            &objects,
            &light_bytes,
            bytemuck::cast_slice(
                &draws
                    .iter()
                    .map(|&(i, m, s)| [i as u32, m as u32, s as u32])
                    .collect::<Vec<_>>(),
            ),
            bytemuck::cast_slice(
                &fur.iter()
                    .map(|&(i, m, s, n)| [i as u32, m as u32, s as u32, n])
                    .collect::<Vec<_>>(),
            ),
            bytemuck::cast_slice(&[wind[0], wind[1], wind[2], gust[0], gust[1]]),
        ]
        .concat();
        if drawn != self.drawn {
            if !fur.is_empty() {
                let (frames, lights) = fur_inputs(plan, views, lights.len());
                r.gpu.write_buffer(&self.fur_frames, 0, &frames);
                r.gpu.write_buffer(&self.fur_lights, 0, &lights);
            }
            self.fur = fur;
            r.gpu.write_buffer(&self.faces, 0, &faces);
            if !objects.is_empty() {
                r.gpu.write_buffer(&self.objects, 0, &objects);
            }
            r.gpu.write_buffer(&self.lights, 0, &light_bytes);
            self.draws = draws;
            self.drawn = drawn;
            self.fresh.store(false, Ordering::Relaxed);
        }
        let mut refs = [[0.0f32; 4]; MAX_MAPS];
        let mut bounds = [[0.0f32; 4]; MAX_MAPS];
        for ((slot, b), m) in refs.iter_mut().zip(bounds.iter_mut()).zip(&plan.maps) {
            let reach = (m.reference - centre).length() + radius;
            *slot = m.reference.extend(reach * 1.01).into();
            *b = m.centre.extend(m.radius).into();
        }
        let params = ReflectUniforms {
            knobs: [k.linear_steps, k.secant_steps, k.layers, k.max_depth],
            flags: [
                u32::from(k.min_max)
                    | u32::from(k.silhouettes) << 1
                    | (plan.maps.len() as u32) << 8,
                u32::from(k.technique == Technique::Envmap),
                match plan.sky {
                    Sky::None => 0,
                    Sky::Procedural => 1,
                    Sky::Cubemap(_) => 2,
                },
                k.cube_size,
            ],
            background: Vec3::from(pelt_scene::shading::BACKGROUND)
                .extend(radius.max(1e-3))
                .into(),
            shading: [
                crate::frame_data::SPECULAR_STRENGTH,
                crate::frame_data::SPECULAR_POWER,
                lights.len() as f32,
                0.0,
            ],
            maps: refs,
            objects: bounds,
        };
        if bytemuck::bytes_of(&params) != self.params_written.as_slice() {
            r.gpu
                .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
            self.params_written = bytemuck::bytes_of(&params).to_vec();
        }
    }
}

/// A cube face's projection (90°, square) about reference point `reference`, with its near
/// and far planes: the whole scene lies within. The maps' faces and the fur's frames share
/// it, so both pipelines of a face pass write comparable depths.
fn face_projection(plan: &ScenePlan, reference: Vec3) -> (Mat4, f32, f32) {
    let (centre, radius) = plan.extent;
    let reach = (reference - centre).length() + radius;
    let near = (radius * 1e-4).max(1e-5);
    let far = (reach * 2.0).max(1e-3);
    let proj = Mat4::perspective_rh(std::f32::consts::FRAC_PI_2, 1.0, near, far);
    (proj, near, far)
}

/// The fur's frames, one per map face (those of layers 0 and 1 unused: a fur object is never
/// a map's own), and each map's lights about its reference point, for `views` faces.
fn fur_inputs(plan: &ScenePlan, views: usize, light_count: usize) -> (Vec<u8>, Vec<u8>) {
    let k = plan.reflections;
    let stride = UNIFORM_STRIDE as usize;
    let light_bytes = MAX_MAP_LIGHTS * size_of::<LightUniforms>();
    let mut frames = vec![0u8; views * stride];
    let mut about = vec![0u8; plan.maps.len().max(1) * light_bytes];
    let size = k.cube_size as f32;
    for (m, map) in plan.maps.iter().enumerate() {
        let (proj, near, far) = face_projection(plan, map.reference);
        let to_ref = Mat4::from_translation(-map.reference);
        let moved: Vec<LightUniforms> = plan
            .lights
            .iter()
            .take(light_count)
            .map(|l| LightUniforms::new(&l.emitter, l.color, to_ref, None))
            .collect();
        let lb: &[u8] = bytemuck::cast_slice(&moved);
        about[m * light_bytes..m * light_bytes + lb.len()].copy_from_slice(lb);
        for layer in 2..k.layers {
            for face in 0..6u32 {
                let i = ((m as u32 * k.layers + layer) * 6 + face) as usize;
                let u = FrameUniforms {
                    view: to_ref.to_cols_array_2d(),
                    proj: (proj * face_view(face)).to_cols_array_2d(),
                    ambient: plan
                        .ambient
                        .extend(crate::frame_data::SPECULAR_POWER)
                        .into(),
                    target_size: [size, size, 1.0 / size, 1.0 / size],
                    lbuffer_size: [MAP_SHELLS as f32, 0.0, 0.0, 0.0],
                    proj_params: [1.0, 1.0, near, far],
                    flags: [layer, moved.len() as u32, map.scene_index as u32, face],
                    wind: plan.wind.0,
                    gust: plan.wind.1,
                };
                frames[i * stride..i * stride + size_of::<FrameUniforms>()]
                    .copy_from_slice(bytemuck::bytes_of(&u));
            }
        }
    }
    (frames, about)
}
