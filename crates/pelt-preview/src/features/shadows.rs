//! Shadows, as Kircher & Lawrance's title promises: a cube of distances about each
//! shadow-casting point light (shadow_map.wgsl), read where lights are applied (shadows.wgsl):
//! in the light pass, one lookup per L-buffer pixel, so opaque surfaces and every stippled
//! alpha layer receive shadows (§4: "any lighting/shadow algorithm that is one to one in terms
//! of L-buffer pixels"), and in the forward pass per pixel, the same way.
//!
//! Like the distance maps, the cubes depend on the scene, not on the camera: [`ShadowCubes`]
//! is made with the scene view and drawn again only when a caster, a light or a pose moved.
//! Every opaque object of the scene casts (mirrors and glass too, as the ray tracer's shadow
//! rays see them); alpha layers do not. Fur casts by its coverage besides, through the deep
//! opacity maps, which draw into the same layers after the cubes ([`crate::lighting`]'s
//! shadow layers). The cubes and how to read them are lighting inputs (binding 0 and 1).

use std::sync::atomic::{AtomicBool, Ordering};

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

use crate::cube::face_view;
use crate::draw::{MissingInput, vertex_layout, vertex_slot};
use crate::feature::{Build, Cached, Feature, Frame, KnobDesc, LightingInput, PassDesc, Resource};
use crate::layout::{self, LayoutDesc};
use crate::lighting::{self, LightFrame, SHADOW_READ_SIZE, ShadowLayers, binding, layers_kept};
use crate::owned::Owned;
use crate::pass::Pass;
use crate::plan::{MAX_SHADOW_LIGHTS, Plan, ScenePlan};
use crate::recipe::{Color, Depth, Recipe, Step};
use crate::renderer::{DEPTH_FORMAT, PipelineDesc, PipelineSpec, Renderer};
use crate::scene_state::SceneState;
use crate::shaders::ShaderDesc;
use crate::targets::{LayeredTarget, Target};
use crate::uniforms::{ObjectUniforms, UNIFORM_STRIDE};
use pelt_scene::knobs::spec;
use pelt_scene::light::LightKind;
use pelt_scene::shading::Emitter;

/// Bind-group slots of shadow_map.wgsl.
pub mod slot {
    /// The face being drawn (dynamic offset).
    pub const FACE: u32 = 0;
    /// One caster's constants (dynamic offset).
    pub const OBJECT: u32 = 1;
}

/// Format of the cubes: the distance from the light in world units to the nearest opaque
/// surface (xy) and to the nearest fur (zw, [`super::opacity`]), each as a half float and its
/// half-float remainder (GL renders to no 32-bit float format).
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// What a texel that sees no surface holds: farther than any receiver.
const NOTHING: f64 = 3.0e38;

/// One face of one light's cube, or a directional light's map. Keep in sync with
/// `ShadowFace` in shaders/shadow_map.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct ShadowFace {
    /// World to this face's clip space.
    pub view_proj: [[f32; 4]; 4],
    /// A cube's face: xyz the light's world position, w its radius. A light's one map: w = 0.
    pub light: [f32; 4],
    /// A light's one map: the distance from its near plane along its axis is
    /// dot(xyz, world) + w.
    pub plane: [f32; 4],
}

/// One face's constants (dynamic offset; shadow_map.wgsl).
pub const FACE_LAYOUT: LayoutDesc = LayoutDesc {
    label: "shadow face",
    entries: &[layout::uniform(0, size_of::<ShadowFace>(), true)],
};

/// A light's one map (where it has one instead of a cube: a directional light's orthographic
/// map, a spot light's perspective one) as shadows.wgsl reads it. Keep in sync with
/// `LightMap` in shaders/lighting_inputs.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct LightMap {
    /// World to the map, projectively: q.xy / q.w its texture coordinates, q.z the distance
    /// from its near plane along its axis, q.w the depth its texels grow with (1 in an
    /// orthographic map).
    pub to_map: [[f32; 4]; 4],
    /// x: the world size of one texel at q.w = 1 (0: the slot's light has a cube); yzw:
    /// unused.
    pub texel: [f32; 4],
}

/// How the cubes are read (the lighting input [`binding::SHADOW_READ`]). Keep in sync with
/// `ShadowRead` in shaders/lighting_inputs.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct ShadowRead {
    /// x: the PCF side (texels); yzw: unused.
    pub pcf: [u32; 4],
    /// Each slot's map where its light has one (zero for a cube's slot).
    pub maps: [LightMap; MAX_SHADOW_LIGHTS],
}

const _: () = assert!(size_of::<ShadowRead>() == SHADOW_READ_SIZE);

/// shadow_map.wgsl.
pub const SHADER: ShaderDesc = ShaderDesc::render("shadow_map.wgsl");

/// The casters' pipeline: both sides drawn (a closed mesh's back faces are its shadow's
/// nearest surface from inside the light's reach too), nearest distance kept by depth.
pub fn pipeline() -> PipelineDesc {
    PipelineDesc {
        shader: SHADER,
        spec: PipelineSpec {
            groups: vec![FACE_LAYOUT, layout::OBJECT],
            vertex_buffers: vec![vertex_layout()],
            blends: vec![None],
            depth: Some((true, wgpu::CompareFunction::Less)),
            ..PipelineSpec::default()
        },
    }
}

/// The shadows' feature.
pub const FEATURE: Feature = Feature {
    knobs: &[KnobDesc::of(&spec::SHADOW_SIZE), KnobDesc::of(&spec::PCF)],
    pipelines: || vec![pipeline()],
    scene: Some(SceneState {
        make: |r, s, _, owned| {
            ShadowCubes::new(r, s.plan).publish(owned);
            Ok(())
        },
        follow: |r, s, owned| {
            let changed = match owned.get_mut::<ShadowCubes>() {
                Some(c) if c.fits(s.plan) => c.write(r, s.plan),
                _ => {
                    ShadowCubes::new(r, s.plan).publish(owned);
                    false
                }
            };
            if changed {
                ShadowCubes::frames_into(owned);
            }
            Ok(())
        },
    }),
    lighting: &[
        LightingInput {
            binding: binding::SHADOW_MAPS,
            what: "the shadow maps",
            resource: |o| {
                let c = o.get::<ShadowCubes>()?;
                Some((Resource::Texture(&c.cubes.sampled), c.id))
            },
        },
        LightingInput {
            binding: binding::SHADOW_READ,
            what: "how to read the shadow maps",
            resource: |o| {
                let c = o.get::<ShadowCubes>()?;
                Some((Resource::Buffer(&c.params), c.id))
            },
        },
    ],
    passes: &[PassDesc {
        cached: Some(CACHED),
        ..PassDesc::new(
            PASS,
            Build::Many(passes),
            |plan| !plan.shadow_lights.is_empty() && !plan.mode.is_debug(),
            explain,
        )
    }],
    ..Feature::named("shadows")
};

/// The shadow pass: a map about each light that casts shadows.
pub const PASS: Pass = Pass::new("shadow-maps");

/// The shadow pass in words.
fn explain(plan: &Plan) -> String {
    let what: Vec<String> = LightKind::ALL
        .into_iter()
        .filter_map(|kind| {
            let n = plan.shadow_lights.iter().filter(|&&k| k == kind).count();
            (n > 0).then(|| format!("{n} {}", map_words(kind)))
        })
        .collect();
    format!(
        "{} of {size}²: distance to the nearest opaque surface; lights and forward shading compare {pcf}×{pcf} texels (PCF)",
        what.join(", "),
        size = plan.shadow_maps.size,
        pcf = plan.shadow_maps.pcf
    )
}

/// The cubes outlive the frame: drawn again only when a light or a caster moved, any
/// caster is posed (its vertices change each frame), or what another feature draws into
/// the same layers changed ([`layers_kept`]).
const CACHED: Cached = Cached {
    fresh: layers_kept,
    drawn: |f| {
        if let Some(l) = f.scene.get::<ShadowLayers>() {
            l.fresh.store(true, Ordering::Relaxed);
        }
    },
};

/// The shadow cubes of one scene and their casters.
#[derive(Debug)]
pub struct ShadowCubes {
    /// Their identity ([`lighting::next_id`]): the lighting inputs and the shadow layers
    /// follow a new one.
    pub id: u64,
    /// Lights with a cube.
    pub slots: u32,
    /// Each face's side in texels.
    pub size: u32,
    /// The cubes: six layers per light (a light with one map draws it into the first).
    pub cubes: LayeredTarget,
    /// The layers drawn: (layer, its view); a layer's face constants are at its index.
    views: Vec<(u32, wgpu::TextureView)>,
    /// Each drawn layer's light frame, as last written.
    frames: Vec<LightFrame>,
    depth: Target,
    faces: wgpu::Buffer,
    faces_group: wgpu::BindGroup,
    params: wgpu::Buffer,
    objects: wgpu::Buffer,
    objects_group: wgpu::BindGroup,
    capacity: usize,
    /// What the cubes hold: (object slot, mesh index, scene index).
    draws: Vec<(usize, usize, usize)>,
    drawn: Vec<u8>,
    /// How the cubes are read, as last written.
    read_written: Option<ShadowRead>,
}

impl ShadowCubes {
    /// The cubes of `plan`'s shadow-casting lights, written.
    pub fn new(r: &Renderer, plan: &ScenePlan) -> ShadowCubes {
        let slots = plan.shadow_lights().count() as u32;
        let size = plan.shadow_maps.size;
        let side = if slots > 0 { size } else { 1 };
        let layers = slots.max(1) * 6;
        let cubes = LayeredTarget::new(r, "shadow cubes", (side, side), layers, 1, FORMAT);
        let views = plan
            .shadow_lights()
            .enumerate()
            .flat_map(|(slot, l)| (0..layers_of(&l.emitter)).map(move |f| slot as u32 * 6 + f))
            .map(|i| (i, cubes.layer(i, 0)))
            .collect();
        let depth = Target::new(&r.gpu.device, "shadow depth", (side, side), DEPTH_FORMAT);
        let faces = r.buffer(
            "shadow faces",
            u64::from(layers) * UNIFORM_STRIDE,
            wgpu::BufferUsages::UNIFORM,
        );
        let capacity = plan.objects.len().max(1);
        let objects = r.buffer(
            "shadow casters",
            capacity as u64 * UNIFORM_STRIDE,
            wgpu::BufferUsages::UNIFORM,
        );
        let params = r.buffer(
            "shadow read",
            size_of::<ShadowRead>() as u64,
            wgpu::BufferUsages::UNIFORM,
        );
        let mut c = ShadowCubes {
            id: lighting::next_id(),
            slots,
            size,
            faces_group: r.group(
                "shadow faces",
                &FACE_LAYOUT,
                &[layout::sized(&faces, size_of::<ShadowFace>())],
            ),
            objects_group: r.group(
                "shadow casters",
                &layout::OBJECT,
                &[layout::sized(&objects, size_of::<ObjectUniforms>())],
            ),
            params,
            cubes,
            views,
            frames: Vec::new(),
            depth,
            faces,
            objects,
            capacity,
            draws: Vec::new(),
            drawn: Vec::new(),
            read_written: None,
        };
        c.write(r, plan);
        c
    }

    /// Keeps these cubes in `owned` with the shadow layers they publish.
    fn publish(self, owned: &mut Owned) {
        owned.insert(ShadowLayers {
            id: self.id,
            size: self.size,
            count: self.cubes.layers,
            sampled: self.cubes.sampled.clone(),
            drawn: Vec::new(),
            fresh: AtomicBool::new(false),
        });
        owned.insert(self);
        Self::frames_into(owned);
    }

    /// Gives the published shadow layers the cubes' light frames, as last written, and has
    /// the next frame draw them again.
    fn frames_into(owned: &mut Owned) {
        let Some(c) = owned.get::<ShadowCubes>() else {
            return;
        };
        let drawn: Vec<(wgpu::TextureView, LightFrame)> = c
            .views
            .iter()
            .zip(&c.frames)
            .map(|((_, v), f)| (v.clone(), *f))
            .collect();
        if let Some(l) = owned.get_mut::<ShadowLayers>() {
            l.drawn = drawn;
            l.fresh.store(false, Ordering::Relaxed);
        }
    }

    /// Whether these cubes fit `plan`'s shadow-casting lights (their kinds) and objects.
    pub fn fits(&self, plan: &ScenePlan) -> bool {
        self.slots == plan.shadow_lights().count() as u32
            && self.views.len() == Self::layers_drawn(plan)
            && self.size == plan.shadow_maps.size
            && plan.objects.len() <= self.capacity
    }

    /// How many layers `plan`'s shadow-casting lights draw: six per point light, one per
    /// light with one map.
    fn layers_drawn(plan: &ScenePlan) -> usize {
        plan.shadow_lights()
            .map(|l| layers_of(&l.emitter) as usize)
            .sum()
    }

    /// Each drawn layer's face and light frame, and each slot's one map, for `plan`'s lights.
    fn fitted(&self, plan: &ScenePlan) -> (Vec<ShadowFace>, Vec<LightFrame>, [LightMap; 8]) {
        let mut faces = Vec::with_capacity(self.views.len());
        let mut frames = Vec::with_capacity(self.views.len());
        let mut maps = [LightMap::zeroed(); MAX_SHADOW_LIGHTS];
        for (slot, l) in plan.shadow_lights().enumerate() {
            let mut put = |(u, light): (ShadowFace, LightFrame)| {
                frames.push(LightFrame {
                    layer: self.views[faces.len()].0,
                    ..light
                });
                faces.push(u);
            };
            match l.emitter {
                Emitter::Point { position, radius } => {
                    cube_faces(position, radius).into_iter().for_each(&mut put);
                }
                Emitter::Directional { direction } => {
                    let (face, map) = sun_map(direction, plan, self.size);
                    put(face);
                    maps[slot] = map;
                }
                Emitter::Spot {
                    position,
                    direction,
                    radius,
                    outer,
                    ..
                } if outer <= SPOT_MAP_MAX => {
                    let (face, map) = spot_map(position, direction, radius, outer, self.size);
                    put(face);
                    maps[slot] = map;
                }
                Emitter::Spot {
                    position, radius, ..
                } => {
                    cube_faces(position, radius).into_iter().for_each(&mut put);
                }
            }
        }
        (faces, frames, maps)
    }

    /// Writes the faces and casters of `plan` (which the cubes fit); returns whether they
    /// changed (the next frame draws them again).
    pub fn write(&mut self, r: &Renderer, plan: &ScenePlan) -> bool {
        let stride = UNIFORM_STRIDE as usize;
        let (fitted, frames, maps) = self.fitted(plan);
        let mut faces = vec![0u8; self.views.len() * stride];
        for (k, u) in fitted.iter().enumerate() {
            faces[k * stride..k * stride + size_of::<ShadowFace>()]
                .copy_from_slice(bytemuck::bytes_of(u));
        }
        let mut objects = vec![0u8; plan.objects.len() * stride];
        let mut draws = Vec::new();
        for (i, (o, _)) in plan.objects.iter().enumerate() {
            let u = ObjectUniforms {
                model: o.model.to_cols_array_2d(),
                ..ObjectUniforms::zeroed()
            };
            objects[i * stride..i * stride + size_of::<ObjectUniforms>()]
                .copy_from_slice(bytemuck::bytes_of(&u));
            if o.pattern == 0 {
                draws.push((i, o.mesh, o.scene_index));
            }
        }
        let ids: Vec<[u32; 3]> = draws
            .iter()
            .map(|&(i, m, s)| [i as u32, m as u32, s as u32])
            .collect();
        let read = ShadowRead {
            pcf: [plan.shadow_maps.pcf, 0, 0, 0],
            maps,
        };
        if self.read_written != Some(read) {
            r.gpu
                .write_buffer(&self.params, 0, bytemuck::bytes_of(&read));
            self.read_written = Some(read);
        }
        let drawn = [faces.as_slice(), &objects, bytemuck::cast_slice(&ids)].concat();
        if drawn == self.drawn {
            return false;
        }
        if !faces.is_empty() {
            r.gpu.write_buffer(&self.faces, 0, &faces);
        }
        if !objects.is_empty() {
            r.gpu.write_buffer(&self.objects, 0, &objects);
        }
        self.frames = frames;
        self.draws = draws;
        self.drawn = drawn;
        true
    }
}

/// The layers a casting light draws: a point light's six cube faces, a directional light's
/// one orthographic map.
fn layers_of(emitter: &Emitter) -> u32 {
    match *emitter {
        Emitter::Point { .. } => 6,
        Emitter::Directional { .. } => 1,
        Emitter::Spot { outer, .. } => {
            if outer <= SPOT_MAP_MAX {
                1
            } else {
                6
            }
        }
    }
}

/// An up vector for a view along unit `direction`: +y, or +z where the view is nearly
/// vertical.
fn up_for(direction: Vec3) -> Vec3 {
    if direction.y.abs() < 0.99 {
        Vec3::Y
    } else {
        Vec3::Z
    }
}

/// The widest spot light (its outer half-angle, radians) drawn into one perspective map;
/// a wider one draws a cube, as a point light does (one map's texels would stretch too far
/// toward its rim).
const SPOT_MAP_MAX: f32 = std::f32::consts::FRAC_PI_3;

/// A spot light's map of `size` texels a side: a perspective view down its axis `direction`
/// from `position`, its field of view the cone's `outer` half-angle and half a texel more,
/// reaching `radius`. It stores the distance along the axis (q.z = q.w: a texel at depth d
/// spans d times the map's texel at depth 1).
fn spot_map(
    position: Vec3,
    direction: Vec3,
    radius: f32,
    outer: f32,
    size: u32,
) -> ((ShadowFace, LightFrame), LightMap) {
    let up = up_for(direction);
    let view = Mat4::look_to_rh(position, direction, up);
    let t = outer.tan() * (1.0 + 1.0 / size as f32);
    let near = (radius * 1e-4).max(1e-6);
    let proj = Mat4::perspective_rh(2.0 * t.atan(), 1.0, near, radius);
    // View space (looking down −z) to (u·w, v·w, depth, depth), depth = −z.
    let to_map = Mat4::from_cols(
        glam::Vec4::new(0.5 / t, 0.0, 0.0, 0.0),
        glam::Vec4::new(0.0, -0.5 / t, 0.0, 0.0),
        glam::Vec4::new(-0.5, -0.5, -1.0, -1.0),
        glam::Vec4::ZERO,
    ) * view;
    let face = ShadowFace {
        view_proj: (proj * view).to_cols_array_2d(),
        light: [0.0; 4],
        plane: direction.extend(-direction.dot(position)).into(),
    };
    let map = LightMap {
        to_map: to_map.to_cols_array_2d(),
        texel: [2.0 * t / size as f32, 0.0, 0.0, 0.0],
    };
    let frame = LightFrame {
        view,
        proj,
        near: 0.0,
        layer: 0,
        along_axis: true,
    };
    ((face, frame), map)
}

/// What `--explain` calls the maps of a kind of light.
fn map_words(kind: LightKind) -> &'static str {
    match kind {
        LightKind::Point => "point light(s) × 6 cube faces",
        LightKind::Directional => "directional light(s) × 1 orthographic map (fitted to the scene)",
        LightKind::Spot => {
            "spot light(s) × 1 perspective map (fitted to the cone; a cube beyond a 60° half-angle)"
        }
    }
}

/// The six faces of a point light's cube, each with its light frame (layer unset).
fn cube_faces(position: Vec3, radius: f32) -> [(ShadowFace, LightFrame); 6] {
    let near = (radius * 1e-4).max(1e-6);
    let proj = Mat4::perspective_rh(std::f32::consts::FRAC_PI_2, 1.0, near, radius);
    let to_light = Mat4::from_translation(-position);
    std::array::from_fn(|face| {
        let view = face_view(face as u32) * to_light;
        let u = ShadowFace {
            view_proj: (proj * view).to_cols_array_2d(),
            light: position.extend(radius).into(),
            plane: [0.0; 4],
        };
        let layer = 0;
        (
            u,
            LightFrame {
                view,
                proj,
                near,
                layer,
                along_axis: false,
            },
        )
    })
}

/// A directional light's map (travelling along unit `direction`) of `size` texels a side:
/// an orthographic view along it, fitted to the world bounds of every object of `plan`
/// (casters and receivers), square texels, with a margin of a hundredth of the scene.
fn sun_map(direction: Vec3, plan: &ScenePlan, size: u32) -> ((ShadowFace, LightFrame), LightMap) {
    let up = up_for(direction);
    let view = Mat4::look_to_rh(Vec3::ZERO, direction, up);
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for (o, (blo, bhi)) in &plan.objects {
        for c in 0..8 {
            let corner = Vec3::select(
                glam::BVec3::new(c & 1 != 0, c & 2 != 0, c & 4 != 0),
                *bhi,
                *blo,
            );
            let v = view.transform_point3(o.model.transform_point3(corner));
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    if !(lo.is_finite() && hi.is_finite()) {
        (lo, hi) = (Vec3::splat(-1.0), Vec3::ONE);
    }
    let span = (hi - lo).max_element().max(1e-6);
    let margin = 0.01 * span;
    let half = 0.5 * (hi.x - lo.x).max(hi.y - lo.y) + margin;
    let (cx, cy) = (0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y));
    // View space looks down −z: the nearest to the light has the largest z.
    let (near, far) = (-(hi.z + margin), -(lo.z - margin));
    let proj = Mat4::orthographic_rh(cx - half, cx + half, cy - half, cy + half, near, far);
    // View space to (u, v, distance past the near plane).
    let to_map = Mat4::from_cols(
        glam::Vec4::new(0.5 / half, 0.0, 0.0, 0.0),
        glam::Vec4::new(0.0, -0.5 / half, 0.0, 0.0),
        glam::Vec4::new(0.0, 0.0, -1.0, 0.0),
        glam::Vec4::new(0.5 - 0.5 * cx / half, 0.5 + 0.5 * cy / half, -near, 1.0),
    ) * view;
    let face = ShadowFace {
        view_proj: (proj * view).to_cols_array_2d(),
        light: [0.0; 4],
        plane: direction.extend(-near).into(),
    };
    let sun = LightMap {
        to_map: to_map.to_cols_array_2d(),
        texel: [2.0 * half / size as f32, 0.0, 0.0, 0.0],
    };
    let layer = 0;
    (
        (
            face,
            LightFrame {
                view,
                proj,
                near,
                layer,
                along_axis: true,
            },
        ),
        sun,
    )
}

/// The view's shadow cubes, or the error `pass` reports without them.
fn cubes<'a>(f: &Frame<'a>, pass: &'static str) -> Result<&'a ShadowCubes, MissingInput> {
    f.scene.need(pass, "the scene's shadow cubes")
}

/// The shadow pass: every face of every light's cube, each a render pass.
pub fn passes<'a>(f: &Frame<'a>) -> Result<Vec<Recipe<'a>>, MissingInput> {
    let name = PASS.name();
    let c = cubes(f, name)?;
    let mut out = Vec::new();
    for (i, (_, view)) in c.views.iter().enumerate() {
        let mut r = Recipe::new(
            PASS,
            vec![Color {
                view,
                format: FORMAT,
                load: wgpu::LoadOp::Clear(wgpu::Color {
                    r: NOTHING,
                    g: 0.0,
                    b: 0.0,
                    a: 0.0,
                }),
            }],
            Some(Depth {
                view: &c.depth.view,
                format: DEPTH_FORMAT,
                load: wgpu::LoadOp::Clear(1.0),
            }),
        );
        r.pipeline(pipeline());
        r.bind(
            slot::FACE,
            &c.faces_group,
            Some(i as u32 * UNIFORM_STRIDE as u32),
        );
        for &(k, mesh, scene_index) in &c.draws {
            let g = f.object_mesh(name, scene_index, mesh)?;
            r.bind(
                slot::OBJECT,
                &c.objects_group,
                Some(k as u32 * UNIFORM_STRIDE as u32),
            );
            r.push(Step::Vertices(vertex_slot::MESH, &g.vertices));
            r.push(Step::Indices(&g.indices));
            r.push(Step::DrawIndexed(0..g.count, 0..1));
        }
        out.push(r);
    }
    Ok(out)
}
