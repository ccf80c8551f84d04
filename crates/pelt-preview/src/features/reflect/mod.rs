//! Mirrors and glass from layered distance maps (GPU Gems 3 ch. 17, Umenhoffer, Patow and
//! Szirmay-Kalos). Per mirror or glass object, a cube map from its reference point with
//! `layers` layers (§17.2.1: its front faces, its back faces, and depth-peeled layers of the
//! rest of the scene), each texel holding material and radiance (Listing 17-5's convention)
//! and normal and distance (distance_map.wgsl); each layer's minimum and maximum distance in
//! a compute pass (Figure 17-4, minmax.wgsl); then the objects themselves drawn in the
//! material (or forward) pass by reflect.wgsl, which traces each pixel's reflection and
//! refraction paths through the maps (§17.2.2, §17.3).
//!
//! The maps depend on the scene and the knobs, not on the camera: [`Maps`] is made with the
//! scene view (every object of the scene is drawn into them, on screen or not, lit by every
//! light), and made again when the knobs change its textures.

pub use crate::cube::face_view;

use super::lights;
use crate::draw::{MissingInput, fur_vertex_layout, vertex_layout};
use crate::feature::{
    Build, Cached, DrawDesc, Feature, Frame, KnobDesc, PassDesc, Phase, Shared, Sides,
};
use crate::knobs::spec;
use crate::layout::{self, D2_ARRAY, LayoutDesc, UNFILTERABLE, seen_by};
use crate::owned::Owned;
use crate::pass::Pass;
use crate::plan::{Plan, ScenePlan};
use crate::recipe::{Color, Depth, Recipe, Step};
use crate::renderer::{Blend, ComputeDesc, DEPTH_FORMAT, PipelineDesc, PipelineSpec, Renderer};
use crate::scene::Technique;
use crate::scene_state::{SceneInputs, SceneState, StateError};
use crate::shaders::{Entry, ShaderDesc};
use crate::targets::{LayeredTarget, Target};
use crate::uniforms::{LightUniforms, UNIFORM_STRIDE};

mod inputs;
pub use inputs::{
    FACE_LAYOUT, FaceUniforms, MAP_SHELLS, MAX_MAP_LIGHTS, MAX_MAPS, MapInputs, ReflectUniforms,
};

/// Bind-group slots of distance_map.wgsl.
pub mod slot {
    /// The face being drawn (dynamic offset).
    pub const FACE: u32 = 0;
    /// One object's constants (dynamic offset).
    pub const OBJECT: u32 = 1;
    /// Every light of the scene, world space.
    pub const LIGHTS: u32 = 2;
    /// The previous layer's distances (depth peeling).
    pub const PEEL: u32 = 3;
    /// shells.wgsl's `fs_distance`: the map's lights about its reference point.
    pub const FUR_LIGHTS: u32 = 2;
    /// shells.wgsl's `fs_distance`: the previous layer's distances.
    pub const FUR_PEEL: u32 = 4;
    /// reflect.wgsl: the maps, their ranges and the knobs.
    pub const MAPS: u32 = 2;
    /// reflect.wgsl: the cube-map sky.
    pub const SKY: u32 = 3;
    /// minmax.wgsl: the distances and the ranges.
    pub const RANGES: u32 = 0;
}

/// Format of the material target.
pub const MATERIAL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Format of the normal and distance target: an octahedral normal and the distance as an f16
/// and its f16 remainder (about 22 bits, for the secant search), renderable on every back end
/// (GL cannot render to Rgba32Float) at half its memory.
pub const GEOMETRY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// What the maps' textures depend on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MapSpec {
    /// Maps.
    pub maps: u32,
    /// Layers per map.
    pub layers: u32,
    /// Face size.
    pub cube: u32,
}

/// Distance maps this adapter cannot make.
#[derive(Debug, thiserror::Error)]
pub enum MapError {
    /// The cube faces are larger than the adapter's textures can be.
    #[error("reflections.cubeSize: {size} is above this adapter's texture limit of {limit}")]
    CubeTooLarge {
        /// Asked for.
        size: u32,
        /// The adapter's `max_texture_dimension_2d`.
        limit: u32,
    },
    /// More mirror and glass objects than the search's uniforms hold.
    #[error("at most {MAX_MAPS} mirror and glass objects have distance maps; the scene has {0}")]
    TooMany(usize),
}

/// The distance maps of one scene and everything that draws and reads them: the targets
/// (sized by [`MapSpec`], made again when it changes), the bind groups that read them, and
/// the inputs they are drawn from ([`MapInputs`], written each frame, with their freshness).
#[derive(Debug)]
pub struct Maps {
    /// What the textures were made for.
    pub spec: MapSpec,
    /// Material and radiance, every (map, layer, face).
    pub material: LayeredTarget,
    /// Normal and distance.
    pub geometry: LayeredTarget,
    depth: Target,
    peel: LayeredTarget,
    views: Vec<(wgpu::TextureView, wgpu::TextureView)>,
    /// Each layer's (min, max) distance.
    pub ranges: wgpu::Buffer,
    read: wgpu::BindGroup,
    minmax: wgpu::BindGroup,
    peel_read: wgpu::BindGroup,
    sky: wgpu::BindGroup,
    /// What the maps are drawn from.
    pub inputs: MapInputs,
}

/// A 1×1 cube for the sky slot of scenes without a cube-map sky.
fn no_sky(r: &Renderer) -> wgpu::BindGroup {
    let tex = LayeredTarget::new(r, "no sky", (1, 1), 6, 1, wgpu::TextureFormat::Rgba8Unorm);
    let view = tex.texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::Cube),
        array_layer_count: Some(6),
        ..Default::default()
    });
    let sampler = r
        .gpu
        .device
        .create_sampler(&wgpu::SamplerDescriptor::default());
    r.group(
        "no sky",
        &super::sky::LAYOUT,
        &[
            wgpu::BindingResource::TextureView(&view),
            wgpu::BindingResource::Sampler(&sampler),
        ],
    )
}

/// The previous distance-map layer (depth peeling; distance_map.wgsl).
pub const PEEL_LAYOUT: LayoutDesc = LayoutDesc {
    label: "peel",
    entries: &[layout::texture(0, UNFILTERABLE, D2_ARRAY)],
};

/// Distance maps, their ranges, the search's knobs and the maps' lights (reflect.wgsl).
pub const MAPS_LAYOUT: LayoutDesc = LayoutDesc {
    label: "distance maps",
    entries: &[
        layout::texture(0, UNFILTERABLE, D2_ARRAY),
        layout::texture(1, UNFILTERABLE, D2_ARRAY),
        seen_by(wgpu::ShaderStages::FRAGMENT, layout::storage(2, true)),
        seen_by(
            wgpu::ShaderStages::FRAGMENT,
            layout::uniform(3, size_of::<ReflectUniforms>(), false),
        ),
        seen_by(
            wgpu::ShaderStages::FRAGMENT,
            layout::uniform(4, MAX_MAP_LIGHTS * size_of::<LightUniforms>(), false),
        ),
    ],
};

/// Distance maps read, their bands' ranges and the layers' ranges written (minmax.wgsl).
pub const MINMAX_LAYOUT: LayoutDesc = LayoutDesc {
    label: "min-max",
    entries: &[
        seen_by(
            wgpu::ShaderStages::COMPUTE,
            layout::texture(0, UNFILTERABLE, D2_ARRAY),
        ),
        layout::storage(1, false),
        layout::storage(2, false),
    ],
};

/// Bands of rows per face the min-max pass reduces first (minmax.wgsl's `BANDS`).
pub const MINMAX_BANDS: u32 = 64;

impl Maps {
    /// The maps of `plan` (which must have at least one), with the scene's cube-map sky
    /// group when it has one. Fails when the cube size is above the adapter's limit.
    pub fn new(
        r: &Renderer,
        plan: &ScenePlan,
        sky: Option<&wgpu::BindGroup>,
    ) -> Result<Maps, MissingInput> {
        let k = plan.reflections;
        let limit = r.gpu.device.limits().max_texture_dimension_2d;
        if k.cube_size > limit {
            return Err(MissingInput {
                pass: MAPS.name(),
                what: format!(
                    "reflections.cubeSize {} within the adapter's texture limit ({limit})",
                    k.cube_size
                ),
            });
        }
        if plan.maps.len() > MAX_MAPS {
            return Err(MissingInput {
                pass: MAPS.name(),
                what: format!(
                    "at most {MAX_MAPS} mirror and glass objects (the scene has {})",
                    plan.maps.len()
                ),
            });
        }
        let spec = MapSpec {
            maps: plan.maps.len() as u32,
            layers: k.layers,
            cube: k.cube_size,
        };
        let size = (spec.cube, spec.cube);
        let layers = spec.maps * spec.layers * 6;
        let material = LayeredTarget::new(
            r,
            "distance maps: material",
            size,
            layers,
            1,
            MATERIAL_FORMAT,
        );
        let geometry = LayeredTarget::new(
            r,
            "distance maps: geometry",
            size,
            layers,
            1,
            GEOMETRY_FORMAT,
        );
        // Depth peeling reads a copy of the previous layer (a 1×1 stand-in without peels: a
        // pass may not read the texture it renders into).
        let peel_size = if spec.layers > 3 { size } else { (1, 1) };
        let peel = LayeredTarget::new(r, "distance maps: peel", peel_size, 6, 1, GEOMETRY_FORMAT);
        let views = (0..layers)
            .map(|i| (material.layer(i, 0), geometry.layer(i, 0)))
            .collect();
        let depth = Target::new(&r.gpu.device, "distance maps: depth", size, DEPTH_FORMAT);
        let inputs = MapInputs::new(r, plan, layers);
        let ranges = r.buffer(
            "distance ranges",
            u64::from(spec.maps * spec.layers) * 8,
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        );
        let partials = r.buffer(
            "distance ranges by band",
            u64::from(layers * MINMAX_BANDS) * 8,
            wgpu::BufferUsages::STORAGE,
        );
        let tex = wgpu::BindingResource::TextureView;
        let light_bytes = MAX_MAP_LIGHTS * size_of::<LightUniforms>();
        let mut maps = Maps {
            read: r.group(
                "distance maps",
                &MAPS_LAYOUT,
                &[
                    tex(&material.sampled),
                    tex(&geometry.sampled),
                    ranges.as_entire_binding(),
                    inputs.params.as_entire_binding(),
                    layout::sized(&inputs.lights, light_bytes),
                ],
            ),
            minmax: r.group(
                "min-max",
                &MINMAX_LAYOUT,
                &[
                    tex(&geometry.sampled),
                    ranges.as_entire_binding(),
                    partials.as_entire_binding(),
                ],
            ),
            peel_read: r.group("peel", &PEEL_LAYOUT, &[tex(&peel.sampled)]),
            sky: sky.cloned().unwrap_or_else(|| no_sky(r)),
            spec,
            material,
            geometry,
            depth,
            peel,
            views,
            ranges,
            inputs,
        };
        maps.write(r, plan);
        Ok(maps)
    }
}

impl Maps {
    /// Writes what `plan`'s maps are drawn from (its maps must fit the spec); when that
    /// changed, the next frame renders them again.
    pub fn write(&mut self, r: &Renderer, plan: &ScenePlan) {
        self.inputs.write(r, plan, self.views.len());
    }

    /// Whether these maps fit `plan`'s knobs and map count.
    pub fn fits(&self, plan: &ScenePlan) -> bool {
        self.spec
            == MapSpec {
                maps: plan.maps.len() as u32,
                layers: plan.reflections.layers,
                cube: plan.reflections.cube_size,
            }
    }
}

/// distance_map.wgsl: one face of one layer of a distance map.
pub const DISTANCE_MAP: ShaderDesc = ShaderDesc::render("distance_map.wgsl");
/// reflect.wgsl: mirrors and glass through their maps.
pub const REFLECT: ShaderDesc = ShaderDesc::render("reflect.wgsl");
/// minmax.wgsl: each layer's distance range from its bands'.
pub const MINMAX: ComputeDesc = ComputeDesc {
    shader: ShaderDesc::compute("minmax.wgsl"),
    groups: &[MINMAX_LAYOUT],
};
/// minmax.wgsl: each band of rows' distance range.
pub const MINMAX_PARTIAL: ComputeDesc = ComputeDesc {
    shader: ShaderDesc {
        file: "minmax.wgsl",
        defs: &[],
        entry: Entry::Compute("cs_partial"),
    },
    groups: &[MINMAX_LAYOUT],
};

/// The distance-map pipeline (two targets: material and geometry).
pub fn map_pipeline() -> PipelineDesc {
    PipelineDesc {
        shader: DISTANCE_MAP,
        spec: PipelineSpec {
            groups: vec![
                FACE_LAYOUT,
                layout::OBJECT,
                layout::LIGHT_ARRAY,
                PEEL_LAYOUT,
            ],
            vertex_buffers: vec![vertex_layout()],
            blends: vec![None, None],
            depth: Some((true, wgpu::CompareFunction::Less)),
            ..PipelineSpec::default()
        },
    }
}

/// The fur's shells drawn into a distance map (shells.wgsl's `fs_distance`: forward-lit,
/// kept by their opacity, peeled as distance_map.wgsl peels), both sides.
pub fn fur_map_pipeline() -> PipelineDesc {
    PipelineDesc {
        shader: ShaderDesc {
            file: "shells.wgsl",
            defs: &[("FORWARD_LIGHT", 1), ("DISTANCE_MAP", 1)],
            entry: Entry::Render("vs_main", "fs_distance"),
        },
        spec: PipelineSpec {
            groups: vec![
                layout::FRAME,
                layout::OBJECT,
                layout::LIGHT_ARRAY,
                layout::FUR_TEXTURES,
                PEEL_LAYOUT,
            ],
            vertex_buffers: vec![vertex_layout(), fur_vertex_layout()],
            blends: vec![None, None],
            depth: Some((true, wgpu::CompareFunction::Less)),
            constants: vec![(
                "RESOLVED_BELOW",
                f64::from(pelt_scene::footprint::RESOLVED_BELOW),
            )],
            ..PipelineSpec::default()
        },
    }
}

/// The pipeline that draws mirrors and glass in the material and forward passes.
pub fn reflect_pipeline() -> PipelineDesc {
    PipelineDesc {
        shader: REFLECT,
        spec: PipelineSpec {
            groups: vec![
                layout::FRAME,
                layout::OBJECT,
                MAPS_LAYOUT,
                super::sky::LAYOUT,
            ],
            vertex_buffers: vec![vertex_layout()],
            blends: crate::draw::object_blends(Blend::None),
            depth: crate::draw::object_depth(Blend::None),
            ..PipelineSpec::default()
        },
    }
}

/// Mirrors and glass's feature.
pub const FEATURE: Feature = Feature {
    knobs: &[
        KnobDesc::of(&spec::REFLECTIONS),
        KnobDesc::of(&spec::LINEAR_STEPS),
        KnobDesc::of(&spec::SECANT_STEPS),
        KnobDesc::of(&spec::LAYERS),
        KnobDesc::of(&spec::CUBE_SIZE),
        KnobDesc::of(&spec::MAX_DEPTH),
        KnobDesc::of(&spec::MIN_MAX),
        KnobDesc::of(&spec::SILHOUETTES),
    ],
    pipelines: || {
        let both = [map_pipeline(), fur_map_pipeline(), reflect_pipeline()];
        both.into_iter()
            .flat_map(|d| [d.clone(), lights::without_suns(d)])
            .collect()
    },
    compute: &[MINMAX_PARTIAL, MINMAX],
    passes: &[
        PassDesc {
            cached: Some(CACHED),
            ..PassDesc::new(
                MAPS,
                Build::Many(map_passes),
                |plan| !plan.maps.is_empty(),
                explain_maps,
            )
        },
        PassDesc {
            cached: Some(CACHED),
            after: &[MAPS],
            ..PassDesc::new(
                MIN_MAX,
                Build::One(minmax_pass),
                |plan| {
                    !plan.maps.is_empty()
                        && plan.reflections.min_max
                        && plan.reflections.technique == Technique::DistanceMaps
                },
                explain_min_max,
            )
        },
    ],
    scene: Some(SceneState {
        make: |r, s, _, owned| follow(r, s, owned),
        follow,
    }),
    draws: &[DrawDesc {
        into: Shared::Shading,
        phase: Phase::Mirrors,
        draw: |f, r, s| draw(f, r, s.pass.name()),
    }],
    ..Feature::named("reflect")
};

/// The distance-map pass: every map's faces and layers.
pub const MAPS: Pass = Pass::new("distance-maps");
/// The min-max pass: each map layer's nearest and farthest distance, a compute pass.
pub const MIN_MAX: Pass = Pass::new("min-max");

/// The distance-map pass in words, with its cost drivers.
fn explain_maps(plan: &Plan) -> String {
    let r = &plan.reflections;
    let faces = plan.maps.len() as u64 * 6 * u64::from(r.layers);
    let texels = faces * u64::from(r.cube_size) * u64::from(r.cube_size);
    format!(
        "{} maps × 6 faces × {} layers (the object's front faces, its back faces, {} of the rest of the scene, depth-peeled) × {}² texels = {} face renders, {:.1} M texels: radiance + material (Listing 17-5's sign convention), normal + distance; every object of the scene (fur as its skin and at most {MAP_SHELLS} shells, kept by their opacity) × {} lights per texel",
        plan.maps.len(),
        r.layers,
        r.layers - 2,
        r.cube_size,
        faces,
        texels as f64 / 1e6,
        plan.map_lights
    )
}

/// The min-max pass in words.
fn explain_min_max(plan: &Plan) -> String {
    format!(
        "compute: minimum and maximum distance of each of {} maps × {} layers (Figure 17-4): one workgroup per band of {MINMAX_BANDS} of each face's rows, then one per layer",
        plan.maps.len(),
        plan.reflections.layers
    )
}

/// The scene's maps for `s`: none without mirrors or glass, those held rewritten where they
/// still fit, else new ones.
fn follow(r: &Renderer, s: &SceneInputs<'_>, owned: &mut Owned) -> Result<(), StateError> {
    match owned.get_mut::<Maps>() {
        _ if s.plan.maps.is_empty() => owned.remove::<Maps>(),
        Some(m) if m.fits(s.plan) => m.write(r, s.plan),
        _ => {
            let maps = Maps::new(r, s.plan, s.sky.map(|k| &k.group)).map_err(StateError::of)?;
            owned.insert(maps);
        }
    }
    Ok(())
}

/// The distance maps outlive the frame: drawn again only when the scene or its knobs
/// changed.
const CACHED: Cached = Cached {
    fresh: |f| f.scene.get::<Maps>().is_some_and(|m| m.inputs.fresh()),
    drawn: |f| {
        if let Some(m) = f.scene.get::<Maps>() {
            m.inputs.mark_fresh();
        }
    },
};

fn maps<'a>(f: &Frame<'a>, pass: &'static str) -> Result<&'a Maps, MissingInput> {
    f.scene.need(pass, "the scene's distance maps")
}

/// The distance-map pass: every face of every layer of every map, each a render pass (a
/// copy of the previous layer before each peeled one).
pub fn map_passes<'a>(f: &Frame<'a>) -> Result<Vec<Recipe<'a>>, MissingInput> {
    let name = MAPS.name();
    let m = maps(f, name)?;
    let mut out = Vec::new();
    for map in 0..m.spec.maps {
        for layer in 0..m.spec.layers {
            let base = (map * m.spec.layers + layer) * 6;
            if layer >= 3 {
                out.push(Recipe::copy(
                    MAPS,
                    &m.geometry.texture,
                    base - 6,
                    &m.peel.texture,
                    0,
                    6,
                    (m.spec.cube, m.spec.cube),
                ));
            }
            for face in 0..6 {
                let (mat, geo) = &m.views[(base + face) as usize];
                let mut r = Recipe::new(
                    MAPS,
                    vec![
                        Color {
                            view: mat,
                            format: MATERIAL_FORMAT,
                            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        },
                        Color {
                            view: geo,
                            format: GEOMETRY_FORMAT,
                            // Distance -1 + 0: no surface.
                            load: wgpu::LoadOp::Clear(wgpu::Color {
                                r: 0.0,
                                g: 0.0,
                                b: -1.0,
                                a: 0.0,
                            }),
                        },
                    ],
                    Some(Depth {
                        view: &m.depth.view,
                        format: DEPTH_FORMAT,
                        load: wgpu::LoadOp::Clear(1.0),
                    }),
                );
                r.pipeline(lights::suns_for_view(f, map_pipeline()));
                r.bind(
                    slot::FACE,
                    &m.inputs.faces_group,
                    Some((base + face) * UNIFORM_STRIDE as u32),
                );
                r.bind(slot::LIGHTS, &m.inputs.lights_group, Some(0));
                r.bind(slot::PEEL, &m.peel_read, None);
                for &(i, k, scene_index) in &m.inputs.draws {
                    let g = f.object_mesh(name, scene_index, k)?;
                    r.bind(
                        slot::OBJECT,
                        &m.inputs.objects_group,
                        Some(i as u32 * UNIFORM_STRIDE as u32),
                    );
                    r.push(Step::Vertices(crate::draw::vertex_slot::MESH, &g.vertices));
                    r.push(Step::Indices(&g.indices));
                    r.push(Step::DrawIndexed(0..g.count, 0..1));
                }
                if layer >= 2 {
                    draw_fur(f, &mut r, m, map, base + face)?;
                }
                out.push(r);
            }
        }
    }
    Ok(out)
}

/// The fur objects' shells into face `face` (maps × layers × 6) of map `map`.
fn draw_fur<'a>(
    f: &Frame<'a>,
    r: &mut Recipe<'a>,
    m: &'a Maps,
    map: u32,
    face: u32,
) -> Result<(), MissingInput> {
    if m.inputs.fur.is_empty() {
        return Ok(());
    }
    let name = MAPS.name();
    r.pipeline(lights::suns_for_view(f, fur_map_pipeline()));
    r.bind(
        slot::FACE,
        &m.inputs.fur_frames_group,
        Some(face * UNIFORM_STRIDE as u32),
    );
    let light_bytes = (MAX_MAP_LIGHTS * size_of::<LightUniforms>()) as u32;
    r.bind(
        slot::FUR_LIGHTS,
        &m.inputs.fur_lights_group,
        Some(map * light_bytes),
    );
    r.bind(slot::FUR_PEEL, &m.peel_read, None);
    for &(i, k, scene_index, shells) in &m.inputs.fur {
        let mesh = f.object_mesh(name, scene_index, k)?;
        let fur = mesh.fur.as_ref().ok_or_else(|| MissingInput {
            pass: name,
            what: format!("the fur of objects[{scene_index}] on the GPU"),
        })?;
        r.bind(
            slot::OBJECT,
            &m.inputs.objects_group,
            Some(i as u32 * UNIFORM_STRIDE as u32),
        );
        r.push(Step::Vertices(
            crate::draw::vertex_slot::MESH,
            &mesh.vertices,
        ));
        r.push(Step::Vertices(crate::draw::vertex_slot::FUR, &fur.vertices));
        r.push(Step::Indices(&mesh.indices));
        Frame::draw_fur_parts(r, mesh, fur, 0..shells + 1);
    }
    Ok(())
}

/// The min-max pass: one workgroup per band of each face's rows, then one per (map, layer).
pub fn minmax_pass<'a>(f: &Frame<'a>) -> Result<Recipe<'a>, MissingInput> {
    let m = maps(f, MIN_MAX.name())?;
    let mut r = Recipe::compute(MIN_MAX);
    r.push(Step::Compute(MINMAX_PARTIAL));
    r.bind(slot::RANGES, &m.minmax, None);
    let faces = m.spec.maps * m.spec.layers * 6;
    r.push(Step::Dispatch([faces, MINMAX_BANDS, 1]));
    r.push(Step::Compute(MINMAX));
    r.bind(slot::RANGES, &m.minmax, None);
    r.push(Step::Dispatch([m.spec.maps, m.spec.layers, 1]));
    Ok(r)
}

/// Draws the plan's mirror and glass objects through their maps (in the material or forward
/// pass, after the opaque objects; the caller binds the frame and rebinds its own slots after).
pub fn draw<'a>(f: &Frame<'a>, r: &mut Recipe<'a>, pass: &'static str) -> Result<(), MissingInput> {
    if f.plan.reflective.is_empty() {
        return Ok(());
    }
    let m = maps(f, pass)?;
    r.pipeline(lights::suns_for_view(f, reflect_pipeline()));
    r.bind(slot::MAPS, &m.read, None);
    r.bind(slot::SKY, &m.sky, None);
    f.draw_objects(r, pass, None, Sides::Both, &f.plan.reflective)
}
