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

use bytemuck::Zeroable;
use glam::Mat4;

use crate::draw::{ADD, MissingInput, fur_vertex_layout, slot, vertex_layout};
use crate::feature::Frame;
use crate::layout::{self, D2_ARRAY, LayoutDesc, UNFILTERABLE, seen_by};
use crate::pass::Pass;
use crate::plan::ScenePlan;
use crate::recipe::{Color, Depth, Recipe};
use crate::renderer::{DEPTH_FORMAT, PipelineDesc, PipelineSpec, Renderer};
use crate::shaders::{Coverage, Entry, ShaderDesc};
use crate::targets::LayeredTarget;
use crate::uniforms::{FrameUniforms, UNIFORM_STRIDE};
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

/// One layer's light frame: its view and projection (world to the light's face), the
/// opacity boundaries in `lbuffer_size`, the layer in `flags.x`, the most shells drawn from
/// the light in `flags.y` ([`SHELLS`]), the near plane in
/// `proj_params.z` (a directional map's distances start there) and the scene's wind.
pub struct LightFrame {
    /// World to the face's view space.
    pub view: Mat4,
    /// The face's projection.
    pub proj: Mat4,
    /// The near plane's distance.
    pub near: f32,
    /// The layer of the cubes.
    pub layer: u32,
}

impl LightFrame {
    /// The frame constants shells.wgsl reads.
    pub fn uniforms(&self, size: u32, sum: [f32; 4], plan: &ScenePlan) -> FrameUniforms {
        let s = size as f32;
        FrameUniforms {
            view: self.view.to_cols_array_2d(),
            proj: self.proj.to_cols_array_2d(),
            target_size: [s, s, 1.0 / s, 1.0 / s],
            lbuffer_size: sum,
            proj_params: [1.0, 1.0, self.near, 0.0],
            flags: [self.layer, SHELLS, 0, 0],
            wind: plan.wind.0,
            gust: plan.wind.1,
            ..FrameUniforms::zeroed()
        }
    }
}

/// The opacity layers of one scene, a layer per layer of the cubes (a 1×1 stand-in where no
/// fur shadows).
#[derive(Debug)]
pub struct OpacityMaps {
    /// Layers drawn: n > 0, a light casts shadows and the scene has fur.
    pub on: bool,
    /// The layers' optical depths.
    pub layers: LayeredTarget,
    layer_views: Vec<wgpu::TextureView>,
    near_group: wgpu::BindGroup,
    nothing: wgpu::BindGroup,
    frames: wgpu::Buffer,
    frames_group: wgpu::BindGroup,
}

impl OpacityMaps {
    /// Maps beside `cubes` for their drawn layers `drawn`.
    pub fn new(r: &Renderer, on: bool, cubes: &LayeredTarget, drawn: &[u32]) -> OpacityMaps {
        let (side, layers) = if on {
            (cubes.size.0, cubes.layers)
        } else {
            (1, 1)
        };
        let maps = LayeredTarget::new(r, "opacity layers", (side, side), layers, 1, FORMAT);
        let drawn = if on { drawn } else { &[] };
        let frames = r.buffer(
            "opacity frames",
            drawn.len().max(1) as u64 * UNIFORM_STRIDE,
            wgpu::BufferUsages::UNIFORM,
        );
        OpacityMaps {
            on,
            layer_views: drawn.iter().map(|&i| maps.layer(i, 0)).collect(),
            near_group: r.group(
                "nearest fur",
                &NEAR,
                &[wgpu::BindingResource::TextureView(&cubes.sampled)],
            ),
            nothing: r.group("nothing", &NOTHING, &[]),
            frames_group: r.group(
                "opacity frames",
                &layout::FRAME,
                &[layout::sized(&frames, size_of::<FrameUniforms>())],
            ),
            frames,
            layers: maps,
        }
    }

    /// Writes the drawn layers' frames (bytes: one [`FrameUniforms`] per stride).
    pub fn write(&self, r: &Renderer, frames: &[u8]) {
        if self.on && !frames.is_empty() {
            r.gpu.write_buffer(&self.frames, 0, frames);
        }
    }

    /// The two passes of drawn layer `i` (the nearest fur into `cube`, the cube's layer,
    /// then the opacity layers) drawing the fur objects that cast into the view with `depth`
    /// (the cubes' depth target), as recipes of `pass`.
    pub fn passes<'a>(
        &'a self,
        f: &Frame<'a>,
        pass: Pass,
        i: usize,
        cube: &'a wgpu::TextureView,
        depth: &'a wgpu::TextureView,
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
                pass,
                vec![Color {
                    view,
                    format: FORMAT,
                    load,
                }],
                nearest.then_some(Depth {
                    view: depth,
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
