//! What a frame needs, decided on the CPU before any GPU work: the mode (inferred lighting,
//! deferred with a full-resolution L-buffer, or the forward reference), which objects and
//! lights can show, the order they are drawn in, object IDs and stipple patterns (Kircher &
//! Lawrance §3.1, §4), and whether an L-buffer is drawn (no lights on screen: the ambient
//! term needs none). These are facts: which passes run, and in what order, the renderer's
//! features decide from them (`pelt_preview::passes`). `--explain` prints this plan's facts
//! and each pass's line ([`Plan::explain`]).

use std::fmt::{self, Write as _};

use glam::{Mat4, Vec3};

use crate::asset::MeshData;
use crate::fur::FurLook;
use crate::light::LightKind;
use crate::scene::{
    FurBlend, FurCoverage, FurLighting, FurSettings, Material, Reflections, Scene, ShadowMaps, Sky,
    Technique,
};
use crate::shading::{Emitter, Light};
use crate::vertex::MAX_FORWARD_LIGHTS;
use crate::view::{View, assign_stipple};

/// How the frame is lit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Mode {
    /// Inferred lighting: G-buffer and L-buffer at the scene's L-buffer scale, DSF material
    /// pass at output resolution.
    #[default]
    Inferred,
    /// Deferred (light pre-pass): full-resolution L-buffer, no DSF.
    Deferred,
    /// Forward: every object loops over every light, O(objects × lights).
    Forward,
    /// The converged fur reference: forward, with each fur object's shells and fins replaced
    /// by explicit strands (Kajiya-Kay per light), accumulated over jittered samples by the
    /// caller (`pelt_measure::strands`).
    Strands,
    /// A debug view: the asset's surfaces unlit, coloured by what the bake wrote.
    Debug(DebugView),
}

/// What a debug view shows ([`crate::debug`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DebugView {
    /// Each normal group in its own flat colour, neighbouring groups always distinct.
    Groups,
    /// The decoded asset-space comb: direction as colour, length as brightness.
    Comb,
}

impl Mode {
    /// Whether every object loops over every light (forward and strands).
    pub fn is_forward(self) -> bool {
        matches!(self, Mode::Forward | Mode::Strands)
    }

    /// Whether lights reach surfaces through a G-buffer and an L-buffer (inferred and
    /// deferred).
    pub fn is_deferred(self) -> bool {
        matches!(self, Mode::Inferred | Mode::Deferred)
    }

    /// Whether it is a debug view (unlit).
    pub fn is_debug(self) -> bool {
        matches!(self, Mode::Debug(_))
    }
}

impl std::str::FromStr for Mode {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "inferred" => Ok(Mode::Inferred),
            "deferred" => Ok(Mode::Deferred),
            "forward" => Ok(Mode::Forward),
            "strands" => Ok(Mode::Strands),
            "debug-groups" => Ok(Mode::Debug(DebugView::Groups)),
            "debug-comb" => Ok(Mode::Debug(DebugView::Comb)),
            _ => Err(format!(
                "unknown mode {s:?} (expected inferred, deferred, forward, strands, debug-groups or debug-comb)"
            )),
        }
    }
}

impl fmt::Display for Mode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Mode::Inferred => "inferred",
            Mode::Deferred => "deferred",
            Mode::Forward => "forward",
            Mode::Strands => "strands",
            Mode::Debug(DebugView::Groups) => "debug-groups",
            Mode::Debug(DebugView::Comb) => "debug-comb",
        })
    }
}

/// A plan that cannot run.
#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    /// The forward reference takes a bounded light array.
    #[error(
        "lights: {mode} mode takes at most {max} lights in one pass; the scene has {count} on screen (inferred and deferred mode light any number)"
    )]
    TooManyLights {
        /// The mode that lights them in one pass (forward or strands).
        mode: Mode,
        /// Lights on screen.
        count: usize,
        /// The limit.
        max: usize,
    },
}

/// An object that will be drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannedObject {
    /// Index in the scene's object list.
    pub scene_index: usize,
    /// Index of its mesh in the loaded assets.
    pub mesh: usize,
    /// Object to world.
    pub model: Mat4,
    /// DSF object ID, 1..=255 (scene index mod 255, plus 1: more than 255 objects share IDs,
    /// as the paper accepts).
    pub id: u32,
    /// Stipple pattern: 0 opaque, 1..=3 alpha layer.
    pub pattern: u32,
    /// Opacity (1 for opaque).
    pub opacity: f32,
    /// Colour multiplied into the asset's albedo.
    pub color: Vec3,
    /// View depth of its bounds' centre.
    pub depth: f32,
    /// Its fur, when it is drawn as fur.
    pub fur: Option<PlannedFur>,
    /// How it reflects and refracts (the material the distance maps store).
    pub optics: Optics,
    /// Its distance map (an index into [`ScenePlan::maps`]), when it is drawn as a mirror
    /// or glass.
    pub map: Option<u32>,
}

/// What a surface does to a ray, in Listing 17-5's terms (GPU Gems 3 §17.3).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Optics {
    /// Lit locally (the rays end here).
    #[default]
    Diffuse,
    /// An ideal reflector with Fresnel reflectance `f0` at normal incidence.
    Mirror {
        /// F0 per channel.
        f0: Vec3,
    },
    /// An ideal refractor.
    Glass {
        /// Index of refraction.
        ior: f32,
        /// Colour multiplied into light entering it.
        tint: Vec3,
    },
}

impl Optics {
    /// The material as the distance maps store it: rgb = F0 (mirror) or tint (glass); a =
    /// Listing 17-5's sign convention: negative for a reflector, 0 diffuse, the IOR (> 0)
    /// for a refractor.
    pub fn encoded(self) -> [f32; 4] {
        match self {
            Optics::Diffuse => [0.0; 4],
            Optics::Mirror { f0 } => [f0.x, f0.y, f0.z, -1.0],
            Optics::Glass { ior, tint } => [tint.x, tint.y, tint.z, ior],
        }
    }
}

/// One mirror or glass object's layered distance map (GPU Gems 3 §17.2.1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlannedMap {
    /// The object's index in the scene.
    pub scene_index: usize,
    /// The reference point: the material's, or the centre of the object's world bounds.
    pub reference: Vec3,
    /// The centre of its world bounds.
    pub centre: Vec3,
    /// Half the diagonal of its world bounds.
    pub radius: f32,
}

/// How one object's fur is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlannedFur {
    /// Concentric shells above the base mesh (at this camera, once the view is planned).
    pub shells: u32,
    /// The most shells: the scene's or `--shells`' count, else the material's.
    pub max_shells: u32,
    /// The shells-by-screen-size rule that sets `shells` per view (None: `max_shells`
    /// always, as when a count is forced or the manifest has no rule).
    pub rule: Option<pelt_fur::shells::ShellRule>,
    /// Fin quads drawn (fins on and the asset has fin edges).
    pub fins: bool,
    /// DSF object ID of its outer shell's stippled texels.
    pub shell_id: u32,
    /// Fur length in mesh units (the asset's units where no node scales the mesh).
    pub length: f32,
    /// The most the fur reaches out from the mesh, in the asset's units: the length times the
    /// largest length scale of the mesh's nodes (`FurVertex::bend`'s w).
    pub reach: f32,
    /// Linear root colour (times the object's colour).
    pub base_color: Vec3,
    /// Linear tip colour (times the object's colour).
    pub tip_color: Vec3,
    /// Heightfield UV scale.
    pub uv_scale: f32,
    /// Root and tip colours multiply the material's base colour (texture and factor).
    pub color_from_texture: bool,
    /// The strand model as a medium: κ = Σ 2r / Σ π r² (per tile width) and the mean strand
    /// diameter (tile widths), from `pelt_fur::density`.
    pub medium: [f32; 2],
    /// How much of the skin each shell hides.
    pub coverage: FurCoverage,
    /// How the deferred paths light it.
    pub lighting: FurLighting,
    /// Secondary motion (its bends are written into the posed fur vertices).
    pub spring: Option<pelt_anim::spring::Spring>,
    /// The mesh's sparsest texel density ([`crate::footprint::texel_density`]).
    pub texel_density: f32,
    /// Whether a pixel of it may be fine enough to resolve single strands at this camera
    /// ([`crate::footprint`]): its shells then use the pipeline with the heightfield taps.
    pub resolved: bool,
    /// Whether the eye (or its near plane) may lie within the box the fur reaches: the
    /// shells above the camera then have no L-buffer sample, so the deferred paths light
    /// this object's shells forward ([`crate::view::View::holds_eye`]).
    pub eye_inside: bool,
}

impl PlannedFur {
    /// Whether the fur reaches nowhere (length 0, or under a node that collapses it): it has
    /// no shells and no fins to draw, only its skin, as the strand reference draws it.
    pub fn bald(&self) -> bool {
        self.reach.is_nan() || self.reach <= 0.0
    }
}

/// A light that reaches the screen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlannedLight {
    /// Where its light comes from.
    pub emitter: Emitter,
    /// Linear colour × intensity.
    pub color: Vec3,
    /// Scissor rectangle on the L-buffer.
    pub rect: [u32; 4],
    /// Its shadow map's slot, when it casts shadows.
    pub shadow: Option<u32>,
}

/// Everything decided before the GPU runs.
#[derive(Debug, Clone)]
pub struct Plan {
    /// The mode.
    pub mode: Mode,
    /// The camera.
    pub view: View,
    /// Output size.
    pub output: (u32, u32),
    /// L-buffer size (also the G-buffer's), when there is one.
    pub lbuffer: Option<(u32, u32)>,
    /// Discontinuity sensitive filtering in the material pass.
    pub dsf: bool,
    /// Objects to draw (the first [`Plan::shown`]), then the fur objects off screen that
    /// still cast shadows by their coverage (into the deep opacity maps).
    pub objects: Vec<PlannedObject>,
    /// How many of `objects` are on screen and drawn.
    pub shown: usize,
    /// Every fur object whose shells the deep opacity maps draw: those on screen and those
    /// off screen whose shadow may fall on it (every fur object while opacity layers are on
    /// and a light casts shadows).
    pub fur_casters: Vec<usize>,
    /// Opaque objects, nearest first (early depth rejection).
    pub opaque: Vec<usize>,
    /// Alpha objects, farthest first (blending order).
    pub alpha: Vec<usize>,
    /// Fur objects, farthest first.
    pub fur: Vec<usize>,
    /// Mirror and glass objects drawn through their distance maps, nearest first.
    pub reflective: Vec<usize>,
    /// Every distance map (the scene plan's, when a mirror or glass object shows).
    pub maps: Vec<PlannedMap>,
    /// The mirror and glass knobs.
    pub reflections: Reflections,
    /// The centre and radius of the scene's world bounds.
    pub extent: (Vec3, f32),
    /// Lights the distance maps are lit by (every light of the scene, on screen or not).
    pub map_lights: usize,
    /// The kind of each light that casts shadows, in slot order (each kind's map is fitted by
    /// the shadows feature).
    pub shadow_lights: Vec<LightKind>,
    /// The shadow cubes' size and filtering.
    pub shadow_maps: ShadowMaps,
    /// How fur shells and fins are composited.
    pub fur_blend: FurBlend,
    /// The background.
    pub sky: Sky,
    /// Lights that reach the screen.
    pub lights: Vec<PlannedLight>,
    /// The wind's per-frame constants at the scene's time ([`crate::wind::constants`]).
    pub wind: ([f32; 4], [f32; 4]),
    /// Linear ambient light.
    pub ambient: Vec3,
    /// Objects culled (off screen).
    pub culled_objects: usize,
    /// Lights culled (their sphere misses the screen).
    pub culled_lights: usize,
    /// Alpha objects that found all three stipple patterns taken by overlapping ones.
    pub crowded_alpha: usize,
    /// Materials drawn as something simpler, with the reason.
    pub notes: Vec<String>,
}

/// What an asset contributes to a plan, computed once per loaded mesh (bounds are a pass
/// over every vertex; a frame must not redo it).
#[derive(Debug, Clone, PartialEq)]
pub struct MeshInfo {
    /// Axis-aligned bounds in the asset's space.
    pub bounds: (Vec3, Vec3),
    /// Its fur's look and whether it has fin edges, when it has a baked comb.
    pub fur: Option<(FurLook, bool)>,
    /// Its fur's strand model as a medium: κ and the mean diameter ([`PlannedFur::medium`]).
    pub medium: [f32; 2],
    /// Its fur's sparsest texel density ([`crate::footprint::texel_density`]).
    pub texel_density: f32,
    /// Whether the GPU skins it (a fur spring has motion to follow).
    pub skinned: bool,
    /// The largest length scale of its fur vertices (what its nodes make of a mesh unit
    /// across the surface); 1 without fur.
    pub fur_scale: f32,
    /// The lights it places (glTF's `KHR_lights_punctual`), in its space.
    pub lights: Vec<crate::light::Light>,
}

impl MeshInfo {
    /// The info of `mesh`.
    pub fn of(mesh: &MeshData) -> MeshInfo {
        MeshInfo {
            bounds: mesh.bounds(),
            fur: mesh
                .fur
                .as_ref()
                .map(|f| (f.look.clone(), !f.fins.is_empty())),
            medium: mesh.fur.as_ref().map_or([0.0; 2], |f| {
                [f.density.kappa as f32, f.density.diameter as f32]
            }),
            texel_density: crate::footprint::texel_density(mesh),
            skinned: mesh.skin.is_some(),
            fur_scale: mesh.fur.as_ref().map_or(1.0, |f| {
                f.vertices.iter().map(|v| v.bend[3]).fold(0.0, f32::max)
            }),
            lights: mesh.lights.clone(),
        }
    }
}

/// The lights `scene` shines: its own, then those its objects' assets place (glTF's
/// `KHR_lights_punctual`, moved with their objects), without the dark ones, shadows kept on
/// the first [`MAX_SHADOW_LIGHTS`] ([`cap_shadows`]); and how many the scene has in all.
fn planned_lights(
    scene: &Scene,
    infos: &[MeshInfo],
    mesh_of: &[usize],
    notes: &mut Vec<String>,
) -> (Vec<Light>, usize) {
    let placed = scene.objects.iter().enumerate().flat_map(|(i, o)| {
        let model = o.transform.matrix();
        infos[mesh_of[i]]
            .lights
            .iter()
            .map(move |l| crate::light::Light {
                emitter: l.emitter.moved(model),
                ..*l
            })
    });
    let all: Vec<crate::light::Light> = scene.lights.iter().copied().chain(placed).collect();
    let lights: Vec<Light> = all
        .iter()
        .filter(|l| l.intensity.0 > 0.0 && l.color.iter().any(|&c| c > 0.0))
        .map(|l| Light {
            emitter: l.emitter,
            color: Vec3::from(l.color) * l.intensity.0,
            shadows: l.shadows,
        })
        .collect();
    (cap_shadows(lights, scene, notes), all.len())
}

/// Most lights that cast shadows (shadow-map slots).
pub const MAX_SHADOW_LIGHTS: usize = 8;

/// Keeps `shadows` on the first [`MAX_SHADOW_LIGHTS`] lights that ask for it, with a note
/// naming each light past them.
fn cap_shadows(mut lights: Vec<Light>, scene: &Scene, notes: &mut Vec<String>) -> Vec<Light> {
    let mut casting = 0;
    for l in lights.iter_mut().filter(|l| l.shadows) {
        casting += 1;
        if casting > MAX_SHADOW_LIGHTS {
            l.shadows = false;
        }
    }
    if casting > MAX_SHADOW_LIGHTS {
        let over: Vec<String> = scene
            .lights
            .iter()
            .enumerate()
            .filter(|(_, l)| l.shadows)
            .skip(MAX_SHADOW_LIGHTS)
            .map(|(i, _)| format!("lights[{i}]"))
            .collect();
        notes.push(format!(
            "{}: at most {MAX_SHADOW_LIGHTS} lights cast shadows; these light without",
            over.join(", ")
        ));
    }
    lights
}

/// The part of a plan that depends on the scene, its assets, the mode and the knobs, but not
/// on the camera: every object that can be drawn with its material decisions, IDs and fur,
/// and the lights. A camera move keeps it; a knob change makes a new one (no asset is read).
#[derive(Debug, Clone)]
pub struct ScenePlan {
    /// The mode.
    pub mode: Mode,
    /// Output size.
    pub output: (u32, u32),
    /// L-buffer size for the mode, before knowing whether any light shows.
    pub lbuffer: Option<(u32, u32)>,
    /// DSF requested.
    pub dsf: bool,
    /// Every object (pattern and depth are filled in per camera), with its mesh bounds.
    pub objects: Vec<(PlannedObject, (Vec3, Vec3))>,
    /// Lights that give any light.
    pub lights: Vec<Light>,
    /// How fur is composited.
    pub fur_blend: FurBlend,
    /// The background.
    pub sky: Sky,
    /// The wind's per-frame constants at the scene's time ([`crate::wind::constants`]).
    pub wind: ([f32; 4], [f32; 4]),
    /// Linear ambient light.
    pub ambient: Vec3,
    /// The scene's light count.
    pub scene_lights: usize,
    /// Materials drawn as something simpler.
    pub notes: Vec<String>,
    /// The mirror and glass knobs.
    pub reflections: Reflections,
    /// One distance map per mirror or glass object (none when the technique is off).
    pub maps: Vec<PlannedMap>,
    /// The centre and radius of the whole scene's world bounds.
    pub extent: (Vec3, f32),
    /// The shadow cubes' size and filtering.
    pub shadow_maps: ShadowMaps,
}

/// The world bounds of `lo..hi` under `model`.
fn world_box(model: Mat4, lo: Vec3, hi: Vec3) -> (Vec3, Vec3) {
    let mut wlo = Vec3::splat(f32::INFINITY);
    let mut whi = Vec3::splat(f32::NEG_INFINITY);
    for i in 0..8 {
        let c = Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        let w = model.transform_point3(c);
        wlo = wlo.min(w);
        whi = whi.max(w);
    }
    (wlo, whi)
}

/// The fur of scene object `i` with fur settings `f` on a mesh of `info`, drawn with shell
/// ID `shell_id`: its look from the bake, overridden by the scene; a note where its spring
/// has no motion to follow, or where the mesh has no baked comb (then no fur: drawn opaque).
fn planned_fur(
    scene: &Scene,
    i: usize,
    f: &FurSettings,
    info: &MeshInfo,
    mode: Mode,
    shell_id: u32,
    notes: &mut Vec<String>,
) -> Option<PlannedFur> {
    let Some((look, has_fins)) = &info.fur else {
        notes.push(format!(
            "objects[{i}]: fur needs a baked _FUR_COMB (run pelt bake on the asset); drawn opaque"
        ));
        return None;
    };
    let color = Vec3::from(scene.objects[i].color);
    let length = f.length.unwrap_or(look.length);
    let reach = length * info.fur_scale;
    let shells = f
        .shells
        .unwrap_or(look.shells)
        .clamp(1, crate::scene::MAX_SHELLS);
    if f.spring.is_some_and(|s| !s.rigid()) && !info.skinned {
        notes.push(format!(
            "objects[{i}]: the fur's spring has no motion to follow (no clip plays, or the mesh is posed on the CPU); its fur stands as combed"
        ));
    }
    Some(PlannedFur {
        shells,
        max_shells: shells,
        rule: look.shell_rule.filter(|_| f.shells.is_none()),
        fins: f.fins_with(scene.fur_coverage) && *has_fins && mode != Mode::Strands && reach > 0.0,
        shell_id,
        length,
        reach,
        base_color: look.base_color * color,
        tip_color: look.tip_color * color,
        uv_scale: look.uv_scale,
        color_from_texture: look.color_from_texture,
        medium: info.medium,
        coverage: scene.fur_coverage,
        lighting: scene.fur_lighting,
        texel_density: info.texel_density,
        spring: f.spring.filter(|s| !s.rigid()),
        resolved: false,
        eye_inside: false,
    })
}

/// How `material` reflects and refracts, with its distance map's reference point when the
/// scene gives one.
fn optics_of(material: &Material) -> (Optics, Option<[f32; 3]>) {
    match *material {
        Material::Mirror { f0, reference } => (Optics::Mirror { f0: Vec3::from(f0) }, reference),
        Material::Glass {
            ior,
            tint,
            reference,
        } => (
            Optics::Glass {
                ior: ior.0,
                tint: Vec3::from(tint),
            },
            reference,
        ),
        _ => (Optics::Diffuse, None),
    }
}

impl ScenePlan {
    /// The longest fur in world units (its length times its object's largest scale); 0
    /// without fur.
    pub fn fur_depth(&self) -> f32 {
        self.objects
            .iter()
            .filter_map(|(o, _)| {
                let f = o.fur?;
                let m = o.model;
                let scale = [m.x_axis, m.y_axis, m.z_axis]
                    .iter()
                    .map(|a| a.truncate().length())
                    .fold(0.0f32, f32::max);
                Some(f.reach * scale)
            })
            .fold(0.0, f32::max)
    }

    /// Whether fur shadows by its coverage (deep opacity maps): opacity layers, a light that
    /// casts shadows and fur to cast.
    pub fn fur_casts(&self) -> bool {
        self.shadow_maps.opacity_layers > 0
            && self.shadow_lights().next().is_some()
            && self.fur_depth() > 0.0
    }

    /// The lights that cast shadows, in slot order.
    pub fn shadow_lights(&self) -> impl Iterator<Item = &Light> {
        self.lights.iter().filter(|l| l.shadows)
    }

    /// `light`'s shadow-map slot (its place among the lights that cast shadows).
    pub fn shadow_slot(&self, light: &Light) -> Option<u32> {
        light.shadows.then(|| {
            self.shadow_lights()
                .position(|l| std::ptr::eq(l, light))
                .map_or(0, |i| i as u32)
        })
    }

    /// The camera-independent plan of `scene` in `mode`; `infos[mesh_of[i]]` is object i's
    /// mesh.
    pub fn new(scene: &Scene, infos: &[MeshInfo], mesh_of: &[usize], mode: Mode) -> ScenePlan {
        let output = (scene.output.width, scene.output.height);
        let (lbuffer, dsf) = match mode {
            Mode::Inferred => (Some(scene.lbuffer_size()), scene.dsf),
            Mode::Deferred => (Some(output), false),
            Mode::Forward | Mode::Strands | Mode::Debug(_) => (None, false),
        };
        let mut objects = Vec::new();
        let mut notes = Vec::new();
        let mut fur_count = 0;
        let mut maps = Vec::new();
        let (mut scene_lo, mut scene_hi) =
            (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for (i, o) in scene.objects.iter().enumerate() {
            let info = &infos[mesh_of[i]];
            let mut fur = None;
            let (pattern, opacity) = match o.material {
                Material::Alpha { opacity } => (1, opacity.0),
                Material::Opaque => (0, 1.0),
                Material::Fur(f) => {
                    let shell_id = ((scene.objects.len() + fur_count) % 255) as u32 + 1;
                    fur = planned_fur(scene, i, &f, info, mode, shell_id, &mut notes);
                    fur_count += usize::from(fur.is_some());
                    (0, 1.0)
                }
                Material::Mirror { .. } | Material::Glass { .. } => (0, 1.0),
            };
            let (optics, reference) = optics_of(&o.material);
            let model = o.transform.matrix();
            let (wlo, whi) = world_box(model, info.bounds.0, info.bounds.1);
            scene_lo = scene_lo.min(wlo);
            scene_hi = scene_hi.max(whi);
            let map = (optics != Optics::Diffuse
                && scene.reflections.technique != Technique::Off
                && !mode.is_debug())
            .then(|| {
                maps.push(PlannedMap {
                    scene_index: i,
                    reference: reference.map_or((wlo + whi) / 2.0, Vec3::from),
                    centre: (wlo + whi) / 2.0,
                    radius: (whi - wlo).length() / 2.0,
                });
                maps.len() as u32 - 1
            });
            let planned = PlannedObject {
                scene_index: i,
                mesh: mesh_of[i],
                model,
                id: (i % 255) as u32 + 1,
                pattern,
                opacity,
                color: Vec3::from(o.color),
                depth: 0.0,
                fur,
                optics,
                map,
            };
            // Fur reaches out to its length (times a comb length of at most 1) beyond the
            // mesh: an object whose base mesh is off screen can still show its fur.
            let reach = planned.fur.map_or(0.0, |f| f.reach.max(0.0) * 1.1);
            let bounds = (
                info.bounds.0 - Vec3::splat(reach),
                info.bounds.1 + Vec3::splat(reach),
            );
            let noted = crate::precision::NotedObject {
                scene_index: planned.scene_index,
                model: planned.model,
                fur: planned.fur.map(|f| (f.reach, f.shells)),
            };
            notes.extend(crate::precision::fur_note(
                &scene.camera,
                &noted,
                info.bounds,
            ));
            objects.push((planned, bounds));
        }
        notes.extend(crate::precision::range_note(&scene.camera));
        let (lights, scene_lights) = planned_lights(scene, infos, mesh_of, &mut notes);
        ScenePlan {
            mode,
            output,
            lbuffer,
            dsf,
            objects,
            lights,
            fur_blend: if mode == Mode::Strands {
                FurBlend::Stipple
            } else {
                scene.fur_blend
            },
            sky: scene.sky.clone(),
            ambient: Vec3::from(scene.ambient),
            wind: crate::wind::constants(scene.wind.as_ref(), scene.time),
            scene_lights,
            notes,
            reflections: scene.reflections,
            shadow_maps: scene.shadow_maps,
            maps,
            extent: if scene_lo.x <= scene_hi.x {
                (
                    (scene_lo + scene_hi) / 2.0,
                    (scene_hi - scene_lo).length() / 2.0,
                )
            } else {
                (Vec3::ZERO, 1.0)
            },
        }
    }
}

/// The objects of a scene plan a camera sees, with their screen rectangles and their fur's
/// decisions at their size on screen (shells by the rule, strands resolved, the eye inside),
/// and the fur objects off screen that still cast by their coverage.
struct Culled {
    objects: Vec<PlannedObject>,
    rects: Vec<[u32; 4]>,
    casting: Vec<PlannedObject>,
    culled: usize,
}

/// Culls `scene`'s objects against `view`; `fur_casts`: fur off screen still casts.
fn cull(scene: &ScenePlan, view: &View, fur_casts: bool) -> Culled {
    let output = scene.output;
    let mut out = Culled {
        objects: Vec::new(),
        rects: Vec::new(),
        casting: Vec::new(),
        culled: 0,
    };
    for (o, (lo, hi)) in &scene.objects {
        let (vlo, vhi) = view.view_box(o.model, *lo, *hi);
        let depth = -(vlo.z + vhi.z) / 2.0;
        let Some(rect) = view.screen_rect(vlo, vhi, output) else {
            out.culled += 1;
            if let Some(f) = o.fur.filter(|_| fur_casts) {
                out.casting.push(PlannedObject {
                    depth,
                    fur: Some(PlannedFur {
                        resolved: false,
                        eye_inside: false,
                        ..f
                    }),
                    ..o.clone()
                });
            }
            continue;
        };
        out.rects.push(rect);
        let mut fur = o.fur;
        if let Some(f) = &mut fur {
            let finest = crate::footprint::finest_footprint(
                view,
                output,
                o.model,
                -vhi.z,
                f.texel_density,
                f.uv_scale,
            );
            f.resolved = f.coverage == FurCoverage::Analytic
                && crate::footprint::resolves_strands(finest, f.medium[1]);
            if let Some(rule) = f.rule {
                let px = crate::footprint::fur_pixels(view, output, o.model, -vhi.z, f.reach);
                f.shells = rule.shells(f64::from(px), f.max_shells);
            }
            f.eye_inside = view.holds_eye(o.model, *lo, *hi);
        }
        out.objects.push(PlannedObject {
            depth,
            fur,
            ..o.clone()
        });
    }
    out
}

/// The lights of `scene` whose reach `view` sees, with their scissor rectangles on
/// `target` (the L-buffer, or the output without one).
fn lights_on_screen(scene: &ScenePlan, view: &View, target: (u32, u32)) -> Vec<PlannedLight> {
    scene
        .lights
        .iter()
        .filter_map(|l| {
            Some(PlannedLight {
                emitter: l.emitter,
                color: l.color,
                rect: match l.emitter.bounds() {
                    Some((centre, radius)) => view.light_rect(centre, radius, target)?,
                    None => [0, 0, target.0, target.1],
                },
                shadow: scene.shadow_slot(l),
            })
        })
        .collect()
}

/// Gives each alpha object on screen a stipple pattern (Kircher & Lawrance §4), overlapping
/// ones distinct where three allow; `rects` are the objects' screen rectangles. Returns how
/// many found all three taken.
fn stipple(objects: &mut [PlannedObject], rects: &[[u32; 4]]) -> usize {
    let alpha: Vec<usize> = (0..objects.len())
        .filter(|&k| objects[k].pattern != 0)
        .collect();
    let (patterns, crowded) = assign_stipple(
        &alpha
            .iter()
            .map(|&k| (Some(rects[k]), objects[k].depth))
            .collect::<Vec<_>>(),
    );
    for (&k, p) in alpha.iter().zip(patterns) {
        objects[k].pattern = p;
    }
    crowded
}

/// The objects on screen by kind, each in the order it is drawn.
struct DrawOrder {
    /// Opaque, nearest first (early depth rejection).
    opaque: Vec<usize>,
    /// Mirrors and glass, nearest first.
    reflective: Vec<usize>,
    /// Fur, farthest first.
    fur: Vec<usize>,
    /// Alpha, farthest first (blending order).
    alpha: Vec<usize>,
}

impl DrawOrder {
    /// The draw orders of `objects` (their stipple patterns assigned).
    fn of(objects: &[PlannedObject]) -> DrawOrder {
        let sorted = |keep: &dyn Fn(&PlannedObject) -> bool, far_first: bool| {
            let mut v: Vec<usize> = (0..objects.len()).filter(|&k| keep(&objects[k])).collect();
            v.sort_by(|&a, &b| {
                let o = objects[a].depth.total_cmp(&objects[b].depth);
                if far_first { o.reverse() } else { o }.then(a.cmp(&b))
            });
            v
        };
        DrawOrder {
            opaque: sorted(
                &|o| o.pattern == 0 && o.fur.is_none() && o.map.is_none(),
                false,
            ),
            reflective: sorted(&|o| o.map.is_some(), false),
            fur: sorted(&|o| o.fur.is_some(), true),
            alpha: sorted(&|o| o.pattern != 0, true),
        }
    }
}

impl Plan {
    /// Plans `scene` in `mode`; `meshes[mesh_of[i]]` is object i's mesh.
    pub fn new(
        scene: &Scene,
        meshes: &[MeshData],
        mesh_of: &[usize],
        mode: Mode,
    ) -> Result<Plan, PlanError> {
        let infos: Vec<MeshInfo> = meshes.iter().map(MeshInfo::of).collect();
        Plan::with_camera(
            &ScenePlan::new(scene, &infos, mesh_of, mode),
            &View::of(&scene.camera, scene.output),
        )
    }

    /// The camera-dependent half: culling, draw order, stipple patterns and light scissor
    /// rectangles, for `scene` seen through `view`.
    pub fn with_camera(scene: &ScenePlan, view: &View) -> Result<Plan, PlanError> {
        let view = *view;
        let output = scene.output;
        // Off screen, fur still casts by its coverage where the opacity maps are drawn.
        let fur_casts = scene.fur_casts();
        let Culled {
            mut objects,
            rects,
            casting,
            culled: culled_objects,
        } = cull(scene, &view, fur_casts);
        let crowded_alpha = stipple(&mut objects, &rects);
        let DrawOrder {
            opaque,
            reflective,
            fur,
            alpha,
        } = DrawOrder::of(&objects);
        let maps = if reflective.is_empty() {
            Vec::new()
        } else {
            scene.maps.clone()
        };
        let shown = objects.len();
        let fur_casters = if fur_casts {
            fur.iter()
                .copied()
                .chain(shown..shown + casting.len())
                .collect()
        } else {
            Vec::new()
        };
        objects.extend(casting);

        let mode = scene.mode;
        let lights = lights_on_screen(scene, &view, scene.lbuffer.unwrap_or(output));
        let culled_lights = scene.scene_lights - lights.len();
        if mode.is_forward() && lights.len() > MAX_FORWARD_LIGHTS {
            return Err(PlanError::TooManyLights {
                mode,
                count: lights.len(),
                max: MAX_FORWARD_LIGHTS,
            });
        }
        // The G-buffer and L-buffer exist where the mode lights through them and a light and
        // an object show; with no light on screen, the ambient term needs neither.
        let lbuffer = scene
            .lbuffer
            .filter(|_| mode.is_deferred() && !lights.is_empty() && shown > 0);
        Ok(Plan {
            mode,
            view,
            output,
            dsf: scene.dsf && lbuffer.is_some(),
            lbuffer,
            objects,
            shown,
            fur_casters,
            opaque,
            alpha,
            fur,
            reflective,
            maps,
            reflections: scene.reflections,
            extent: scene.extent,
            map_lights: scene.lights.len(),
            shadow_lights: scene.shadow_lights().map(|l| l.emitter.kind()).collect(),
            shadow_maps: scene.shadow_maps,
            fur_blend: scene.fur_blend,
            sky: scene.sky.clone(),
            lights,
            ambient: scene.ambient,
            wind: scene.wind,
            culled_objects,
            culled_lights,
            crowded_alpha,
            notes: scene.notes.clone(),
        })
    }

    /// Whether fur is drawn through the L-buffer (an L-buffer and fur on screen): its outer
    /// shell's stipple is obliterated from a composition copy of the L-buffer.
    pub fn deferred_fur(&self) -> bool {
        self.lbuffer.is_some() && !self.fur.is_empty()
    }

    /// The plan in words (`--explain`): its facts, then each planned pass by name with its
    /// line (the renderer declares the passes, when each runs and what each says of this
    /// plan: `pelt_preview::explain`), then the notes.
    pub fn explain(&self, passes: &[(&str, String)]) -> String {
        let mut s = String::new();
        let (w, h) = self.output;
        let _ = write!(s, "mode {}: output {w}×{h}", self.mode);
        if let Some((lw, lh)) = self.lbuffer {
            let _ = write!(
                s,
                ", L-buffer {lw}×{lh}, DSF {}",
                if self.dsf { "on" } else { "off" }
            );
        }
        let _ = writeln!(
            s,
            "\nobjects: {} drawn ({} opaque, {} alpha), {} off screen; lights: {} on screen, {} culled",
            self.shown,
            self.opaque.len(),
            self.alpha.len(),
            self.culled_objects,
            self.lights.len(),
            self.culled_lights
        );
        self.explain_wind(&mut s);
        let _ = writeln!(s, "passes:");
        for (name, line) in passes {
            let _ = writeln!(s, "  {name:<14}{line}");
        }
        for n in &self.notes {
            let _ = writeln!(s, "note: {n}");
        }
        s
    }

    /// The wind in words, when it blows.
    fn explain_wind(&self, s: &mut String) {
        let (wind, gust) = self.wind;
        if wind[..3] != [0.0; 3] {
            let v = Vec3::from_slice(&wind[..3]);
            let d = v.normalize();
            let _ = writeln!(
                s,
                "wind toward [{:.2}, {:.2}, {:.2}], strength {:.2}, {} gusts/s, turbulence {:.2}, \
                 at {} s: bends every fur object's comb (shells, fins, strands)",
                d.x,
                d.y,
                d.z,
                v.length(),
                gust[0],
                gust[1],
                wind[3]
            );
        }
    }

    /// The stipple patterns the alpha objects use, in words (`; stipple patterns used [1,
    /// 2]`), or nothing without alpha objects.
    pub fn explain_stipple(&self) -> String {
        let mut s = String::new();
        if !self.alpha.is_empty() {
            let mut used: Vec<u32> = self
                .alpha
                .iter()
                .map(|&k| self.objects[k].pattern)
                .collect();
            used.sort_unstable();
            used.dedup();
            let _ = write!(s, "; stipple patterns used {used:?}");
            if self.crowded_alpha > 0 {
                let _ = write!(
                    s,
                    " ({} alpha objects overlap 3 others and share a pattern)",
                    self.crowded_alpha
                );
            }
        }
        s
    }

    /// The mirror and glass part of the material (or forward) pass in words.
    fn explain_reflective(&self, s: &mut String) {
        if self.reflective.is_empty() {
            return;
        }
        let r = &self.reflections;
        let _ = write!(s, "; {} mirror/glass objects by ", self.reflective.len());
        match r.technique {
            Technique::Envmap => {
                let _ = write!(
                    s,
                    "environment mapping (direction lookups in the same cube maps), up to {} bounces",
                    r.max_depth
                );
            }
            _ => {
                let _ = write!(
                    s,
                    "ray tracing their distance maps: {} linear steps per quarter turn per layer, {} secant steps, min-max {}, silhouettes {}, up to {} bounces",
                    r.linear_steps,
                    r.secant_steps,
                    if r.min_max { "on" } else { "off" },
                    if r.silhouettes { "on" } else { "off" },
                    r.max_depth
                );
            }
        }
    }

    /// The mirror, glass, fur and sky part of the shading (material or forward) pass in
    /// words.
    pub fn explain_shading(&self, s: &mut String) {
        self.explain_reflective(s);
        for &k in &self.fur {
            let o = &self.objects[k];
            if let (Some(_), Mode::Strands) = (o.fur, self.mode) {
                let _ = write!(
                    s,
                    "; objects[{}] fur: base + explicit strands from the strand model (Kajiya-Kay per light, opaque, jittered samples accumulated)",
                    o.scene_index
                );
            } else if let Some(f) = o.fur {
                let _ = write!(
                    s,
                    "; objects[{}] fur: base + {} shells{}{}{}, {}",
                    o.scene_index,
                    f.shells,
                    if f.rule.is_some() {
                        format!(" (by screen size, at most {})", f.max_shells)
                    } else {
                        String::new()
                    },
                    if f.fins { " + fins" } else { "" },
                    if f.resolved {
                        " (near enough to resolve single strands: heightfield taps)"
                    } else {
                        ""
                    },
                    match (self.fur_blend, self.mode) {
                        (FurBlend::Wboit, _) => "into the OIT pass",
                        (_, Mode::Forward) => "Kajiya-Kay per light, blended over inner to outer",
                        _ => "lit from the L-buffer at root and tip, blended over inner to outer",
                    }
                );
            }
        }
        match &self.sky {
            Sky::None => {}
            Sky::Procedural => s.push_str("; procedural sky"),
            Sky::Cubemap(_) => s.push_str("; cube-map sky"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::asset::builtin;
    use crate::procedural::grid_scene;
    use crate::scene::Unit;
    use std::path::Path;

    fn plan(scene: &Scene, mode: Mode) -> Plan {
        let meshes = vec![builtin("cube").expect("cube")];
        Plan::new(scene, &meshes, &vec![0; scene.objects.len()], mode).expect("plan")
    }

    #[test]
    fn modes_round_trip_their_names() {
        for name in [
            "inferred",
            "deferred",
            "forward",
            "strands",
            "debug-groups",
            "debug-comb",
        ] {
            let mode: Mode = name.parse().expect("a mode");
            assert_eq!(mode.to_string(), name);
        }
        let e = "debug".parse::<Mode>().expect_err("not a mode");
        assert!(e.contains("debug-groups or debug-comb"), "{e}");
    }

    #[test]
    fn the_lbuffer_follows_the_mode_and_the_lights_on_screen() {
        let mut s = grid_scene(Path::new("builtin:cube"), 9, 5, 1, 160, 90);
        s.lbuffer_scale = 0.5;
        let p = plan(&s, Mode::Inferred);
        assert_eq!((p.lbuffer, p.dsf), (Some((80, 45)), true));
        let d = plan(&s, Mode::Deferred);
        assert_eq!((d.lbuffer, d.dsf), (Some((160, 90)), false));
        for mode in [Mode::Forward, Mode::Strands, Mode::Debug(DebugView::Groups)] {
            assert_eq!(plan(&s, mode).lbuffer, None, "{mode}");
        }
        // No lights: the ambient term needs no L-buffer.
        s.lights.clear();
        assert_eq!(plan(&s, Mode::Inferred).lbuffer, None);
    }

    #[test]
    fn explain_lists_the_passes_it_is_given_between_the_facts_and_the_notes() {
        let s = grid_scene(Path::new("builtin:cube"), 2, 1, 1, 160, 90);
        let mut p = plan(&s, Mode::Inferred);
        p.notes.push("a note".into());
        let e = p.explain(&[("first", "one".into()), ("second-pass", "two".into())]);
        assert!(e.starts_with("mode inferred: output 160×90"), "{e}");
        assert!(
            e.contains("passes:\n  first         one\n  second-pass   two\nnote: a note\n"),
            "{e}"
        );
    }

    #[test]
    fn alpha_is_sorted_back_to_front_and_opaque_front_to_back() {
        let mut s = grid_scene(Path::new("builtin:cube"), 4, 1, 1, 160, 90);
        for o in &mut s.objects[..3] {
            o.material = Material::Alpha { opacity: Unit(0.5) };
        }
        s.objects[0].transform.translation = [0.0, 0.5, 0.0];
        s.objects[1].transform.translation = [0.0, 0.5, 1.0];
        s.objects[2].transform.translation = [0.0, 0.5, -1.0];
        let p = plan(&s, Mode::Inferred);
        let order: Vec<usize> = p.alpha.iter().map(|&k| p.objects[k].scene_index).collect();
        assert_eq!(order, vec![2, 0, 1], "farthest (−Z) first");
        let pats: Vec<u32> = p.alpha.iter().map(|&k| p.objects[k].pattern).collect();
        assert_eq!(pats, vec![3, 2, 1], "nearest takes pattern 1; all differ");
        assert_eq!(p.opaque.len(), 1);
        assert_eq!(p.explain_stipple(), "; stipple patterns used [1, 2, 3]");
    }

    #[test]
    fn off_screen_lights_and_objects_are_culled() {
        let mut s = grid_scene(Path::new("builtin:cube"), 1, 0, 1, 160, 90);
        s.lights.push(at([0.0, 0.0, 100.0]));
        s.lights.push(at([0.0, 0.5, 0.0]));
        let mut far = s.objects[0].clone();
        far.transform.translation = [0.0, 0.0, 500.0];
        s.objects.push(far);
        let p = plan(&s, Mode::Inferred);
        assert_eq!((p.lights.len(), p.culled_lights), (1, 1));
        assert_eq!((p.objects.len(), p.culled_objects), (1, 1));
    }

    #[test]
    fn the_lights_an_asset_places_move_with_its_object() {
        let mut s = grid_scene(Path::new("builtin:cube"), 1, 0, 1, 160, 90);
        s.lights.clear();
        s.objects[0].transform.translation = [0.0, 0.0, 1.0];
        s.objects[0].transform.scale = [2.0; 3];
        let mut cube = builtin("cube").expect("cube");
        let infos = |cube: &MeshData| vec![MeshInfo::of(cube)];
        let p = ScenePlan::new(&s, &infos(&cube), &[0], Mode::Inferred);
        assert!(p.lights.is_empty(), "the cube places none (the control)");
        let mut placed = at([0.0, 0.25, 0.0]);
        placed.emitter = Emitter::Point {
            position: Vec3::new(0.0, 0.25, 0.0),
            radius: 1.5,
        };
        cube.lights.push(placed);
        let p = ScenePlan::new(&s, &infos(&cube), &[0], Mode::Inferred);
        assert_eq!(p.lights.len(), 1);
        assert_eq!(p.scene_lights, 1);
        let Emitter::Point { position, radius } = p.lights[0].emitter else {
            panic!("{:?}", p.lights[0]);
        };
        let model = s.objects[0].transform.matrix();
        assert!(position.abs_diff_eq(model.transform_point3(Vec3::new(0.0, 0.25, 0.0)), 1e-6));
        assert!(
            (radius - 3.0).abs() < 1e-5,
            "scaled with the object: {radius}"
        );
    }

    fn s_light() -> crate::scene::Light {
        crate::procedural::random_lights(1, 0, Vec3::ZERO, Vec3::ZERO, (1.0, 1.0), 1.0)[0]
    }

    /// [`s_light`] moved to `p`.
    fn at(p: [f32; 3]) -> crate::scene::Light {
        let mut l = s_light();
        l.emitter = Emitter::Point {
            position: Vec3::from(p),
            radius: l.emitter.radius().expect("a point light"),
        };
        l
    }

    #[test]
    fn forward_refuses_more_lights_than_its_array() {
        let s = grid_scene(Path::new("builtin:cube"), 4, 300, 1, 160, 90);
        let meshes = vec![builtin("cube").expect("cube")];
        let visible = plan(&s, Mode::Inferred).lights.len();
        let r = Plan::new(&s, &meshes, &[0; 4], Mode::Forward);
        if visible > MAX_FORWARD_LIGHTS {
            assert!(matches!(r, Err(PlanError::TooManyLights { .. })));
        } else {
            assert!(r.is_ok());
        }
        assert!(
            visible > MAX_FORWARD_LIGHTS,
            "the test scene should exceed the limit: {visible}"
        );
    }
}
