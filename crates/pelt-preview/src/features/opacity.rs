//! Deep opacity maps (Yuksel & Keyser, "Deep Opacity Maps", Eurographics 2008): how fur
//! shadows itself and everything behind it by its coverage, for each layer of the shadow
//! cubes ([`super::shadows`]). Two passes per layer draw the fur objects' shells from the
//! light (shells.wgsl with the `OPACITY_MAP` def): the outer shell's distance, the nearest
//! fur, into the cube's own z and w, then each shell fragment's optical depth seen from the
//! light, −ln(1 − α), added into every opacity layer whose boundary past the nearest fur it
//! lies within (the last layer takes all).
//! shadows.wgsl reads the optical depth at a receiver's depth past the nearest fur, linear
//! between the layers' boundaries, and passes exp(−τ) of the light.
//!
//! With n layers the boundaries lie at 2D / 2^(n−1−k) past the nearest fur, D the scene's
//! longest fur in world units: three layers at D/2, D and 2D, dense where the fur is (the
//! paper's three layers are its artifact-free point), the last reaching a grazing light's
//! path through the fur. The base meshes still cast through the opaque cubes.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use bytemuck::{Pod, Zeroable};

use crate::draw::{ADD, MissingInput, fur_vertex_layout, slot, vertex_layout};
use crate::feature::{
    Build, Cached, Feature, Frame, KnobDesc, LayerWriter, LightingInput, PassDesc, Resource,
};
use crate::layout::{self, D2_ARRAY, LayoutDesc, UNFILTERABLE, seen_by};
use crate::lighting::{self, FUR_READ_SIZE, LightFrame, ShadowLayers, binding, layers_kept};
use crate::owned::Owned;
use crate::pass::Pass;
use crate::plan::{Plan, ScenePlan};
use crate::recipe::{Color, Depth, Recipe};
use crate::renderer::{DEPTH_FORMAT, PipelineDesc, PipelineSpec, Renderer};
use crate::scene_state::SceneState;
use crate::shaders::{Coverage, Entry, ShaderDesc};
use crate::targets::{LayeredTarget, Target};
use crate::uniforms::{FrameUniforms, UNIFORM_STRIDE};
use pelt_scene::knobs::spec;
use pelt_scene::scene::FurCoverage;

/// Format of the opacity layers: their optical depths.
pub const FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// What the nearest-fur pass reads at `slot::LIGHTING`'s place: nothing.
pub const NOTHING: LayoutDesc = LayoutDesc {
    label: "nothing",
    entries: &[],
};

/// The cubes, whose zw hold the nearest fur's distance, as the opacity pass reads them
/// (`cubes` in shells.wgsl).
pub const NEAR: LayoutDesc = LayoutDesc {
    label: "nearest fur",
    entries: &[seen_by(
        wgpu::ShaderStages::FRAGMENT,
        layout::texture(0, UNFILTERABLE, D2_ARRAY),
    )],
};

const DEFS: &[(&str, u32)] = &[("OPACITY_MAP", 1)];

/// Most shells drawn from a light: fewer, thicker layers sum to the same optical depth (each
/// layer's coverage is the strand model's over its thickness), and the layers' depths need
/// no finer steps than the three opacity layers resolve. (The fixture sphere's self-shadowing
/// against the strands' shadow rays, 32 shells on screen: 1.000× the strands' darkening with
/// every shell drawn from the light, 0.985× with 8.)
pub const SHELLS: u32 = 8;

/// The shells from a light: `fs_nearest` or `fs_opacity`.
const fn shader(fs: &'static str) -> ShaderDesc {
    ShaderDesc {
        file: "shells.wgsl",
        defs: DEFS,
        entry: Entry::Render("vs_main", fs),
    }
}

/// The pipeline of the nearest-fur pass (`nearest`: the nearest kept by depth, written into
/// the cube's z and w alone) or the opacity pass (additive), for shells of `coverage`. Both
/// sides drawn: the light sees shells from below too.
pub fn pipeline(nearest: bool, coverage: Coverage) -> PipelineDesc {
    PipelineDesc {
        shader: shader(if nearest { "fs_nearest" } else { "fs_opacity" }),
        spec: PipelineSpec {
            groups: vec![
                layout::FRAME,
                layout::OBJECT,
                if nearest { NOTHING } else { NEAR },
                layout::FUR_TEXTURES,
            ],
            vertex_buffers: vec![vertex_layout(), fur_vertex_layout()],
            blends: vec![if nearest { None } else { Some(ADD) }],
            depth: nearest.then_some((true, wgpu::CompareFunction::Less)),
            writes: nearest.then_some(wgpu::ColorWrites::BLUE | wgpu::ColorWrites::ALPHA),
            constants: [
                (coverage != Coverage::Medium).then_some(("COVERAGE", coverage.constant())),
                Some((
                    "RESOLVED_BELOW",
                    f64::from(pelt_scene::footprint::RESOLVED_BELOW),
                )),
            ]
            .into_iter()
            .flatten()
            .collect(),
            ..PipelineSpec::default()
        },
    }
}

/// Every pipeline the maps draw with.
pub fn pipelines() -> Vec<PipelineDesc> {
    [true, false]
        .into_iter()
        .flat_map(|n| [Coverage::Medium, Coverage::Binary].map(|c| pipeline(n, c)))
        .collect()
}

/// The layers' boundaries past the nearest fur for `n` layers and longest fur `depth`: as
/// the opacity pass sums into them (the last layer takes all, unused ones none) and as the
/// lookup interpolates them (the last at 2D; w the layer count).
pub fn boundaries(n: u32, depth: f32) -> ([f32; 4], [f32; 4]) {
    let mut sum = [-3.0e38; 4];
    let mut read = [0.0; 4];
    for k in 0..n as usize {
        let b = 2.0 * depth / (1u32 << (n as usize - 1 - k)) as f32;
        read[k] = b;
        sum[k] = if k + 1 == n as usize { 3.0e38 } else { b };
    }
    read[3] = n as f32;
    (sum, read)
}

/// The frame constants shells.wgsl reads from light frame `lf` of maps `size` texels a side:
/// its view and projection (world to the light's face), the opacity boundaries `sum` in
/// `lbuffer_size`, the layer in `flags.x`, the most shells drawn from the light in `flags.y`
/// ([`SHELLS`]), whether distances run along its axis in `flags.z`, the near plane in
/// `proj_params.z` (where they start then) and the scene's wind.
pub fn frame_uniforms(
    lf: &LightFrame,
    size: u32,
    sum: [f32; 4],
    plan: &ScenePlan,
) -> FrameUniforms {
    let s = size as f32;
    FrameUniforms {
        view: lf.view.to_cols_array_2d(),
        proj: lf.proj.to_cols_array_2d(),
        target_size: [s, s, 1.0 / s, 1.0 / s],
        lbuffer_size: sum,
        proj_params: [1.0, 1.0, lf.near, 0.0],
        flags: [lf.layer, SHELLS, u32::from(lf.along_axis), 0],
        wind: plan.wind.0,
        gust: plan.wind.1,
        ..FrameUniforms::zeroed()
    }
}

/// How the opacity layers are read (the lighting input [`binding::FUR_READ`]). Keep in sync
/// with `FurRead` in shaders/lighting_inputs.wgsl.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct FurRead {
    /// The layers' boundaries (world units past the nearest fur) and w their count (0: fur
    /// casts no coverage; [`boundaries`]).
    pub layers: [f32; 4],
}

const _: () = assert!(size_of::<FurRead>() == FUR_READ_SIZE);

/// The opacity layers of one scene, a layer per layer of its shadow maps (a 1×1 stand-in
/// where no fur shadows).
#[derive(Debug)]
pub struct OpacityMaps {
    /// Their identity ([`lighting::next_id`]).
    id: u64,
    /// The shadow layers they were made for ([`ShadowLayers::id`]).
    shadows: u64,
    /// Layers drawn: n > 0, a light casts shadows and the scene has fur.
    pub on: bool,
    /// The layers' optical depths.
    pub layers: LayeredTarget,
    layer_views: Vec<wgpu::TextureView>,
    depth: Target,
    near_group: wgpu::BindGroup,
    nothing: wgpu::BindGroup,
    frames: wgpu::Buffer,
    frames_group: wgpu::BindGroup,
    read: wgpu::Buffer,
    /// The frames and read constants as last written.
    written: (Vec<u8>, Option<FurRead>),
    /// Whether the frames changed since a frame last drew the maps.
    stale: AtomicBool,
    /// Which fur the maps hold ([`OpacityMaps::fur_key`]).
    fur_drawn: AtomicU64,
}

impl OpacityMaps {
    /// Maps beside shadow layers `l`, for `plan`, written.
    pub fn new(r: &Renderer, plan: &ScenePlan, l: &ShadowLayers) -> OpacityMaps {
        let on = plan.fur_casts();
        let (side, layers) = if on { (l.size, l.count) } else { (1, 1) };
        let maps = LayeredTarget::new(r, "opacity layers", (side, side), layers, 1, FORMAT);
        let drawn = if on { l.drawn.len() } else { 0 };
        let frames = r.buffer(
            "opacity frames",
            drawn.max(1) as u64 * UNIFORM_STRIDE,
            wgpu::BufferUsages::UNIFORM,
        );
        let read = r.buffer(
            "opacity read",
            size_of::<FurRead>() as u64,
            wgpu::BufferUsages::UNIFORM,
        );
        let mut m = OpacityMaps {
            id: lighting::next_id(),
            shadows: l.id,
            on,
            layer_views: l.drawn[..drawn]
                .iter()
                .map(|(_, f)| maps.layer(f.layer, 0))
                .collect(),
            depth: Target::new(&r.gpu.device, "opacity depth", (side, side), DEPTH_FORMAT),
            near_group: r.group(
                "nearest fur",
                &NEAR,
                &[wgpu::BindingResource::TextureView(&l.sampled)],
            ),
            nothing: r.group("nothing", &NOTHING, &[]),
            frames_group: r.group(
                "opacity frames",
                &layout::FRAME,
                &[layout::sized(&frames, size_of::<FrameUniforms>())],
            ),
            frames,
            read,
            layers: maps,
            written: (Vec::new(), None),
            stale: AtomicBool::new(true),
            fur_drawn: AtomicU64::new(0),
        };
        m.write(r, plan, l.size, &frames_of(l));
        m
    }

    /// Whether these maps fit shadow layers `id` with `drawn` layers, and `plan`.
    fn fits(&self, plan: &ScenePlan, id: u64, drawn: usize) -> bool {
        self.shadows == id
            && self.on == plan.fur_casts()
            && (!self.on || self.layer_views.len() == drawn)
    }

    /// Writes each drawn layer's frame (`frames`, of maps `size` texels a side) and the read
    /// constants for `plan`; changed frames have the next frame draw the maps (and the
    /// shadow layers) again.
    fn write(&mut self, r: &Renderer, plan: &ScenePlan, size: u32, frames: &[LightFrame]) {
        let n = if self.on {
            plan.shadow_maps.opacity_layers
        } else {
            0
        };
        let (sum, layers) = boundaries(n, plan.fur_depth());
        let read = FurRead { layers };
        if self.written.1 != Some(read) {
            r.gpu.write_buffer(&self.read, 0, bytemuck::bytes_of(&read));
            self.written.1 = Some(read);
        }
        if !self.on {
            return;
        }
        let stride = UNIFORM_STRIDE as usize;
        let mut bytes = vec![0u8; frames.len() * stride];
        for (k, lf) in frames.iter().enumerate() {
            let fu = frame_uniforms(lf, size, sum, plan);
            bytes[k * stride..k * stride + size_of_val(&fu)]
                .copy_from_slice(bytemuck::bytes_of(&fu));
        }
        if bytes != self.written.0 {
            r.gpu.write_buffer(&self.frames, 0, &bytes);
            self.written.0 = bytes;
            self.stale.store(true, Ordering::Relaxed);
        }
    }

    /// What fur view `f` draws into the maps (each object's scene index, shells, coverage,
    /// length and strand medium), hashed; 0 without them.
    fn fur_key(&self, f: &Frame<'_>) -> u64 {
        if !self.on {
            return 0;
        }
        let mut h = std::hash::DefaultHasher::new();
        for &k in &f.plan.fur_casters {
            let o = &f.plan.objects[k];
            let fur = o.fur.map(|p| {
                (
                    p.shells,
                    p.coverage == FurCoverage::Binary,
                    p.length.to_bits(),
                    p.medium.map(f32::to_bits),
                )
            });
            std::hash::Hash::hash(&(o.scene_index, fur), &mut h);
        }
        std::hash::Hasher::finish(&h) | 1
    }

    /// The two passes of drawn layer `i` (the nearest fur into `cube`, the shadow maps'
    /// layer, then the opacity layers) drawing the fur objects that cast into the view.
    fn layer_passes<'a>(
        &'a self,
        f: &Frame<'a>,
        i: usize,
        cube: &'a wgpu::TextureView,
    ) -> Result<Vec<Recipe<'a>>, MissingInput> {
        let mut out = Vec::new();
        for nearest in [true, false] {
            let (view, load) = if nearest {
                (cube, wgpu::LoadOp::Load)
            } else {
                (
                    &self.layer_views[i],
                    wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                )
            };
            let mut r = Recipe::new(
                PASS,
                vec![Color {
                    view,
                    format: FORMAT,
                    load,
                }],
                nearest.then_some(Depth {
                    view: &self.depth.view,
                    format: DEPTH_FORMAT,
                    load: wgpu::LoadOp::Clear(1.0),
                }),
            );
            let offset = i as u32 * UNIFORM_STRIDE as u32;
            r.bind(slot::FRAME, &self.frames_group, Some(offset));
            let group = if nearest {
                &self.nothing
            } else {
                &self.near_group
            };
            r.bind(slot::LIGHTING, group, None);
            draw_fur(f, &mut r, nearest)?;
            out.push(r);
        }
        Ok(out)
    }
}

/// The opacity pass: for each drawn layer of the shadow maps, after the shadow pass drew
/// it, the nearest fur into it and the fur's optical depth into the opacity layers.
fn passes<'a>(f: &Frame<'a>) -> Result<Vec<Recipe<'a>>, MissingInput> {
    let name = PASS.name();
    let m: &OpacityMaps = f.scene.need(name, "the scene's opacity maps")?;
    if !m.on {
        return Ok(Vec::new());
    }
    let l: &ShadowLayers = f.scene.need(name, "the scene's shadow layers")?;
    let mut out = Vec::new();
    for (i, (cube, _)) in l.drawn.iter().enumerate() {
        out.extend(m.layer_passes(f, i, cube)?);
    }
    Ok(out)
}

/// The opacity pass: its own pass, after the shadow maps'.
pub const PASS: Pass = Pass::new("opacity-maps");

/// Whether `plan` draws the opacity maps: a light casts shadows, fur casts, layers asked for.
fn wanted(plan: &Plan) -> bool {
    !plan.shadow_lights.is_empty()
        && plan.shadow_maps.opacity_layers > 0
        && !plan.fur_casters.is_empty()
        && !plan.mode.is_debug()
}

/// The opacity pass in words.
fn explain(plan: &Plan) -> String {
    let layers = plan.shadow_maps.opacity_layers;
    let mut s = format!(
        "each shadow-map layer: the fur's nearest distance, then {layers} deep opacity layer(s) of its shells' optical depth (Yuksel & Keyser 2008), which fur and everything behind it read"
    );
    let off = plan.fur_casters.len() - plan.fur.len();
    if off > 0 {
        s += &format!(" ({off} fur object(s) off screen cast too)");
    }
    s
}

/// The maps outlive the frame with the shadow layers they draw into ([`layers_kept`]).
const CACHED: Cached = Cached {
    fresh: layers_kept,
    drawn: |f| {
        if let Some(m) = f.scene.get::<OpacityMaps>() {
            m.stale.store(false, Ordering::Relaxed);
            m.fur_drawn.store(m.fur_key(f), Ordering::Relaxed);
        }
    },
};

/// Whether what the maps draw into the shadow layers is as a frame last drew it (true where
/// the view draws none).
fn unchanged(f: &Frame<'_>) -> bool {
    !wanted(f.plan)
        || f.scene.get::<OpacityMaps>().is_none_or(|m| {
            !m.on
                || (!m.stale.load(Ordering::Relaxed)
                    && m.fur_drawn.load(Ordering::Relaxed) == m.fur_key(f))
        })
}

/// Each drawn layer's light frame of shadow layers `l`.
fn frames_of(l: &ShadowLayers) -> Vec<LightFrame> {
    l.drawn.iter().map(|(_, f)| *f).collect()
}

/// Makes or refits the maps beside the scene's shadow layers (none without them).
fn follow(r: &Renderer, plan: &ScenePlan, owned: &mut Owned) {
    let Some(l) = owned.get::<ShadowLayers>() else {
        owned.remove::<OpacityMaps>();
        return;
    };
    let (id, size, frames) = (l.id, l.size, frames_of(l));
    if let Some(m) = owned
        .get_mut::<OpacityMaps>()
        .filter(|m| m.fits(plan, id, frames.len()))
    {
        m.write(r, plan, size, &frames);
        return;
    }
    let Some(l) = owned.get::<ShadowLayers>() else {
        return;
    };
    let m = OpacityMaps::new(r, plan, l);
    owned.insert(m);
}

/// The deep opacity maps' feature.
pub const FEATURE: Feature = Feature {
    knobs: &[KnobDesc::of(&spec::OPACITY_LAYERS)],
    pipelines,
    scene: Some(SceneState {
        make: |r, s, _, owned| {
            follow(r, s.plan, owned);
            Ok(())
        },
        follow: |r, s, owned| {
            follow(r, s.plan, owned);
            Ok(())
        },
    }),
    passes: &[PassDesc {
        cached: Some(CACHED),
        after: &[Pass::new("shadow-maps")],
        ..PassDesc::new(PASS, Build::Many(passes), wanted, explain)
    }],
    lighting: &[
        LightingInput {
            binding: binding::FUR_OPACITY,
            what: "the fur's opacity layers",
            resource: |o| {
                let m = o.get::<OpacityMaps>().filter(|m| m.on)?;
                Some((Resource::Texture(&m.layers.sampled), m.id))
            },
        },
        LightingInput {
            binding: binding::FUR_READ,
            what: "how to read the fur's opacity layers",
            resource: |o| {
                let m = o.get::<OpacityMaps>().filter(|m| m.on)?;
                Some((Resource::Buffer(&m.read), m.id))
            },
        },
    ],
    layer_writer: Some(LayerWriter { unchanged }),
    ..Feature::named("opacity")
};

/// Every fur object that casts into the view, on screen or off ([`crate::plan::Plan`]'s
/// `fur_casters`): its outer shell (`nearest`), or its shells without the base mesh.
fn draw_fur<'a>(f: &Frame<'a>, r: &mut Recipe<'a>, nearest: bool) -> Result<(), MissingInput> {
    for &k in &f.plan.fur_casters {
        let Some(planned) = f.plan.objects[k].fur.filter(|p| !p.bald()) else {
            continue;
        };
        let coverage = match planned.coverage {
            FurCoverage::Binary => Coverage::Binary,
            _ => Coverage::Medium,
        };
        r.pipeline(pipeline(nearest, coverage));
        let pass = r.pass.name();
        let (mesh, fur) = f.bind_fur(r, pass, k)?;
        let n = planned.shells.min(SHELLS);
        let shells = if nearest { n..n + 1 } else { 1..n + 1 };
        Frame::draw_fur_parts(r, mesh, fur, shells);
    }
    Ok(())
}
