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
//! opacity maps drawn with the cubes ([`super::opacity`]).

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

use super::opacity::{self, LightFrame, OpacityMaps};
use crate::cube::face_view;
use crate::draw::{MissingInput, vertex_layout, vertex_slot};
use crate::feature::{Build, Cached, Feature, Frame, KnobDesc, PassDesc, Reference};
use crate::layout::{self, D2_ARRAY, LayoutDesc, UNFILTERABLE, seen_by};
use crate::pass::Pass;
use crate::plan::{MAX_SHADOW_LIGHTS, Plan, ScenePlan};
use crate::recipe::{Color, Depth, Recipe, Step};
use crate::renderer::{DEPTH_FORMAT, PipelineDesc, PipelineSpec, Renderer};
use crate::scene_state::SceneState;
use crate::shaders::ShaderDesc;
use crate::targets::{LayeredTarget, Target};
use crate::uniforms::{ObjectUniforms, UNIFORM_STRIDE};
use pelt_scene::shading::Emitter;

/// Bind-group slots of shadow_map.wgsl.
pub mod slot {
    /// The face being drawn (dynamic offset).
    pub const FACE: u32 = 0;
    /// One caster's constants (dynamic offset).
    pub const OBJECT: u32 = 1;
    /// light.wgsl and forward.wgsl: the cubes (shadows.wgsl's `@group(4)`).
    pub const CUBES: u32 = 4;
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
    /// A point light: xyz its world position, w its radius. A directional light: w = 0.
    pub light: [f32; 4],
    /// A directional light: the distance from its map's near plane is dot(xyz, world) + w.
    pub plane: [f32; 4],
}

/// One face's constants (dynamic offset; shadow_map.wgsl).
pub const FACE_LAYOUT: LayoutDesc = LayoutDesc {
    label: "shadow face",
    entries: &[layout::uniform(0, size_of::<ShadowFace>(), true)],
};

/// A directional light's map as shadows.wgsl reads it. Keep in sync with `SunMap` in
/// shaders/shadows.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct SunMap {
    /// World to the map: xy its texture coordinates, z the distance from its near plane.
    pub to_map: [[f32; 4]; 4],
    /// x: the world size of one texel; yzw: unused.
    pub texel: [f32; 4],
}

/// How the cubes are read. Keep in sync with `ShadowRead` in shaders/shadows.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct ShadowRead {
    /// x: the PCF side (texels); yzw: unused.
    pub pcf: [u32; 4],
    /// The deep opacity layers' boundaries (world units past the nearest fur) and w their
    /// count (0: fur casts no coverage; [`opacity::boundaries`]).
    pub layers: [f32; 4],
    /// Each slot's map when its light is directional (zero for a point light's slot).
    pub suns: [SunMap; MAX_SHADOW_LIGHTS],
}

/// The cubes and how to read them, as the light and forward passes do (shadows.wgsl).
pub const LAYOUT: LayoutDesc = LayoutDesc {
    label: "shadow cubes",
    entries: &[
        seen_by(
            wgpu::ShaderStages::FRAGMENT,
            layout::texture(0, UNFILTERABLE, D2_ARRAY),
        ),
        seen_by(
            wgpu::ShaderStages::FRAGMENT,
            layout::uniform(1, size_of::<ShadowRead>(), false),
        ),
        seen_by(
            wgpu::ShaderStages::FRAGMENT,
            layout::texture(2, UNFILTERABLE, D2_ARRAY),
        ),
    ],
};

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
    knobs: &[
        KnobDesc::new(
            "shadow-size",
            "a power of two from 16 to 4096",
            "the scene's (512)",
            Reference::RayTracer,
        ),
        KnobDesc::new("pcf", "1 to 8", "the scene's (2)", Reference::RayTracer),
        KnobDesc::new(
            "opacity-layers",
            "0 to 3",
            "the scene's (3)",
            Reference::Strands,
        ),
    ],
    pipelines: || [vec![pipeline()], opacity::pipelines()].concat(),
    scene: Some(SceneState {
        make: |r, s, _, owned| {
            owned.insert(ShadowCubes::new(r, s.plan));
            Ok(())
        },
        follow: |r, s, owned| {
            match owned.get_mut::<ShadowCubes>() {
                Some(c) if c.fits(s.plan) => c.write(r, s.plan),
                _ => owned.insert(ShadowCubes::new(r, s.plan)),
            }
            Ok(())
        },
    }),
    passes: &[PassDesc {
        cached: Some(CACHED),
        ..PassDesc::new(
            PASS,
            Build::Many(passes),
            |plan| plan.shadow_lights != (0, 0) && !plan.mode.is_debug(),
            explain,
        )
    }],
    ..Feature::named("shadows")
};

/// The shadow pass: a map about each light that casts shadows.
pub const PASS: Pass = Pass::new("shadow-maps");

/// The shadow pass in words.
fn explain(plan: &Plan) -> String {
    let (points, suns) = plan.shadow_lights;
    let mut what = Vec::new();
    if points > 0 {
        what.push(format!("{points} point light(s) × 6 cube faces"));
    }
    if suns > 0 {
        what.push(format!(
            "{suns} directional light(s) × 1 orthographic map (fitted to the scene)"
        ));
    }
    let mut s = format!(
        "{} of {size}²: distance to the nearest opaque surface; lights and forward shading compare {pcf}×{pcf} texels (PCF)",
        what.join(", "),
        size = plan.shadow_maps.size,
        pcf = plan.shadow_maps.pcf
    );
    let layers = plan.shadow_maps.opacity_layers;
    if layers > 0 && !plan.fur_casters.is_empty() {
        s += &format!(
            "; the fur from each: its nearest distance, then {layers} deep opacity layer(s) of its shells' optical depth (Yuksel & Keyser 2008), which fur and everything behind it read"
        );
        let off = plan.fur_casters.len() - plan.fur.len();
        if off > 0 {
            s += &format!(" ({off} fur object(s) off screen cast too)");
        }
    }
    s
}

/// The cubes outlive the frame: drawn again only when a light or a caster moved, any
/// caster is posed (its vertices change each frame), or the fur the view draws changed.
const CACHED: Cached = Cached {
    fresh: |f| {
        f.scene
            .get::<ShadowCubes>()
            .is_some_and(|c| c.fresh() && c.fur_drawn.load(Ordering::Relaxed) == c.fur_key(f))
            && f.poses.iter().all(Option::is_none)
    },
    drawn: |f| {
        if let Some(c) = f.scene.get::<ShadowCubes>() {
            c.fresh.store(true, Ordering::Relaxed);
            c.fur_drawn.store(c.fur_key(f), Ordering::Relaxed);
        }
    },
};

/// The shadow cubes of one scene, their casters and the group that reads them.
#[derive(Debug)]
pub struct ShadowCubes {
    /// Lights with a cube.
    pub slots: u32,
    /// Each face's side in texels.
    pub size: u32,
    /// The cubes: six layers per light (a directional light draws its map into the first).
    pub cubes: LayeredTarget,
    /// The layers drawn: (layer, its view); a layer's face constants are at its index.
    views: Vec<(u32, wgpu::TextureView)>,
    depth: Target,
    faces: wgpu::Buffer,
    faces_group: wgpu::BindGroup,
    params: wgpu::Buffer,
    objects: wgpu::Buffer,
    objects_group: wgpu::BindGroup,
    capacity: usize,
    /// What the cubes hold: (object slot, mesh index, scene index).
    draws: Vec<(usize, usize, usize)>,
    /// The cubes as shadows.wgsl reads them (a 1×1 stand-in without shadow-casting lights).
    pub read: wgpu::BindGroup,
    /// The fur's deep opacity maps beside the cubes.
    pub opacity: OpacityMaps,
    fresh: AtomicBool,
    /// Which fur the opacity maps hold ([`ShadowCubes::fur_key`]).
    fur_drawn: AtomicU64,
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
        let drawn: Vec<u32> = plan
            .shadow_lights()
            .enumerate()
            .flat_map(|(slot, l)| (0..layers_of(&l.emitter)).map(move |f| slot as u32 * 6 + f))
            .collect();
        let views = drawn.iter().map(|&i| (i, cubes.layer(i, 0))).collect();
        let opacity = OpacityMaps::new(r, plan.fur_casts(), &cubes, &drawn);
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
            read: r.group(
                "shadow cubes",
                &LAYOUT,
                &[
                    wgpu::BindingResource::TextureView(&cubes.sampled),
                    params.as_entire_binding(),
                    wgpu::BindingResource::TextureView(&opacity.layers.sampled),
                ],
            ),
            opacity,
            params,
            cubes,
            views,
            depth,
            faces,
            objects,
            capacity,
            draws: Vec::new(),
            fresh: AtomicBool::new(false),
            fur_drawn: AtomicU64::new(0),
            drawn: Vec::new(),
            read_written: None,
        };
        c.write(r, plan);
        c
    }

    /// Whether these cubes fit `plan`'s shadow-casting lights (their kinds) and objects.
    pub fn fits(&self, plan: &ScenePlan) -> bool {
        self.slots == plan.shadow_lights().count() as u32
            && self.views.len() == Self::layers_drawn(plan)
            && self.size == plan.shadow_maps.size
            && plan.objects.len() <= self.capacity
            && self.opacity.on == plan.fur_casts()
    }

    /// What fur view `f` draws into the opacity maps (each object's scene index, shells,
    /// coverage, length and strand medium), hashed; 0 without them.
    fn fur_key(&self, f: &Frame<'_>) -> u64 {
        if !self.opacity.on {
            return 0;
        }
        let mut h = std::hash::DefaultHasher::new();
        for &k in &f.plan.fur_casters {
            let o = &f.plan.objects[k];
            let fur = o.fur.map(|p| {
                (
                    p.shells,
                    p.coverage == pelt_scene::scene::FurCoverage::Binary,
                    p.length.to_bits(),
                    p.medium.map(f32::to_bits),
                )
            });
            std::hash::Hash::hash(&(o.scene_index, fur), &mut h);
        }
        std::hash::Hasher::finish(&h) | 1
    }

    /// How many layers `plan`'s shadow-casting lights draw: six per point light, one per
    /// directional light.
    fn layers_drawn(plan: &ScenePlan) -> usize {
        plan.shadow_lights()
            .map(|l| layers_of(&l.emitter) as usize)
            .sum()
    }

    /// Whether a frame has drawn the cubes since their lights and casters last changed.
    pub fn fresh(&self) -> bool {
        self.fresh.load(Ordering::Relaxed)
    }

    /// Writes the faces and casters of `plan` (which the cubes fit); a change makes the next
    /// frame draw them again.
    pub fn write(&mut self, r: &Renderer, plan: &ScenePlan) {
        let stride = UNIFORM_STRIDE as usize;
        let mut faces = vec![0u8; self.views.len() * stride];
        let mut frames = vec![0u8; self.views.len() * stride];
        let mut suns = [SunMap::zeroed(); MAX_SHADOW_LIGHTS];
        let n = if self.opacity.on {
            plan.shadow_maps.opacity_layers
        } else {
            0
        };
        let (sum, layers) = opacity::boundaries(n, plan.fur_depth());
        let mut k = 0;
        for (slot, l) in plan.shadow_lights().enumerate() {
            let mut put = |(u, light): (ShadowFace, LightFrame)| {
                let at = k * stride;
                faces[at..at + size_of::<ShadowFace>()].copy_from_slice(bytemuck::bytes_of(&u));
                let lf = LightFrame {
                    layer: self.views[k].0,
                    ..light
                };
                let fu = lf.uniforms(self.size, sum, plan);
                frames[at..at + size_of_val(&fu)].copy_from_slice(bytemuck::bytes_of(&fu));
                k += 1;
            };
            match l.emitter {
                Emitter::Point { position, radius } => {
                    for u in cube_faces(position, radius) {
                        put(u);
                    }
                }
                Emitter::Directional { direction } => {
                    let (face, sun) = sun_map(direction, plan, self.size);
                    put(face);
                    suns[slot] = sun;
                }
            }
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
            layers,
            suns,
        };
        if self.read_written != Some(read) {
            r.gpu
                .write_buffer(&self.params, 0, bytemuck::bytes_of(&read));
            self.read_written = Some(read);
        }
        let drawn = [
            faces.as_slice(),
            &frames,
            &objects,
            bytemuck::cast_slice(&ids),
        ]
        .concat();
        if drawn != self.drawn {
            if !faces.is_empty() {
                r.gpu.write_buffer(&self.faces, 0, &faces);
            }
            self.opacity.write(r, &frames);
            if !objects.is_empty() {
                r.gpu.write_buffer(&self.objects, 0, &objects);
            }
            self.draws = draws;
            self.drawn = drawn;
            self.fresh.store(false, Ordering::Relaxed);
        }
    }
}

/// The layers a casting light draws: a point light's six cube faces, a directional light's
/// one orthographic map.
fn layers_of(emitter: &Emitter) -> u32 {
    match emitter {
        Emitter::Point { .. } => 6,
        Emitter::Directional { .. } => 1,
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
            },
        )
    })
}

/// A directional light's map (travelling along unit `direction`) of `size` texels a side:
/// an orthographic view along it, fitted to the world bounds of every object of `plan`
/// (casters and receivers), square texels, with a margin of a hundredth of the scene.
fn sun_map(direction: Vec3, plan: &ScenePlan, size: u32) -> ((ShadowFace, LightFrame), SunMap) {
    let up = if direction.y.abs() < 0.99 {
        Vec3::Y
    } else {
        Vec3::Z
    };
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
    let sun = SunMap {
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
            },
        ),
        sun,
    )
}

/// light.wgsl's and forward.wgsl's override: whether any light of the view casts shadows.
pub const SHADOWS: &str = "SHADOWS";

/// light.wgsl's and forward.wgsl's override: whether the fur casts by its coverage too.
pub const FUR_SHADOWS: &str = "FUR_SHADOWS";

/// `desc` for views without a shadow-casting light: the lookup compiled out.
pub fn unshadowed(desc: PipelineDesc) -> PipelineDesc {
    desc.with_constant(SHADOWS, Some(0.0))
        .with_constant(FUR_SHADOWS, Some(0.0))
}

/// `desc` for views whose fur casts no coverage: the opacity layers' lookup compiled out.
pub fn without_fur(desc: PipelineDesc) -> PipelineDesc {
    desc.with_constant(FUR_SHADOWS, Some(0.0))
}

/// `descs` and their [`without_fur`] and [`unshadowed`] variants.
pub fn with_unshadowed(descs: Vec<PipelineDesc>) -> Vec<PipelineDesc> {
    descs
        .into_iter()
        .flat_map(|d| [d.clone(), without_fur(d.clone()), unshadowed(d)])
        .collect()
}

/// Whether any light of the view casts shadows.
pub fn any(f: &Frame<'_>) -> bool {
    f.plan.lights.iter().any(|l| l.shadow.is_some())
}

/// Whether the view's fur casts by its coverage (its scene's cubes have opacity layers).
pub fn fur_casts(f: &Frame<'_>) -> bool {
    f.scene.get::<ShadowCubes>().is_some_and(|c| c.opacity.on)
}

/// `desc` as the view needs it: [`unshadowed`] unless a light of the view casts shadows,
/// [`without_fur`] unless its fur casts too.
pub fn for_view(f: &Frame<'_>, desc: PipelineDesc) -> PipelineDesc {
    match (any(f), fur_casts(f)) {
        (false, _) => unshadowed(desc),
        (true, false) => without_fur(desc),
        (true, true) => desc,
    }
}

/// Binds the view's cubes at [`slot::CUBES`] for a pass that reads them.
pub fn bind<'a>(f: &Frame<'a>, r: &mut Recipe<'a>, pass: Pass) -> Result<(), MissingInput> {
    let c = cubes(f, pass.name())?;
    r.bind(slot::CUBES, &c.read, None);
    Ok(())
}

/// The view's shadow cubes, or the error `pass` reports without them.
pub fn cubes<'a>(f: &Frame<'a>, pass: &'static str) -> Result<&'a ShadowCubes, MissingInput> {
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
        if c.opacity.on {
            out.extend(c.opacity.passes(f, PASS, i, view, &c.depth.view)?);
        }
    }
    Ok(out)
}
