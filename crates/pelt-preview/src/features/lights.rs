//! Lights (Kircher & Lawrance §2.2): the L-buffer starts at the ambient term; each point
//! light adds its diffuse and specular intensity over its scissor rectangle only, reading
//! position and normal back from the G-buffer. The geometry pass's depth, tested read-only
//! against the far side of each light's reach, rejects the pixels behind it before shading.
//! A directional light covers the L-buffer. Each kind of light is drawn by a pipeline of its
//! own (light.wgsl's `DIRECTIONAL`), and a view without shadow-casting lights by pipelines
//! with the shadow lookup compiled out, so a light pays only for the code its kind needs.

use crate::draw::{ADD, MissingInput};
use crate::feature::{Build, Feature, Frame, KnobDesc, PassDesc};
use crate::frame_data::Res;
use crate::layout;
use crate::lighting;
use crate::pass::Pass;
use crate::plan::Plan;
use crate::recipe::{Color, Depth, Recipe, Step};
use crate::renderer::{PipelineDesc, PipelineSpec};
use crate::scene::FurLighting;
use crate::shaders::{Entry, ShaderDesc};
use pelt_scene::knobs::spec;
use pelt_scene::shading::Emitter;

/// Bind-group slots of light.wgsl.
pub mod slot {
    /// Frame constants.
    pub const FRAME: u32 = 0;
    /// G-buffer normals and DSF buffer.
    pub const GBUFFER: u32 = 1;
    /// The light.
    pub const LIGHT: u32 = 2;
    /// Which object IDs hold strand tangents (the fur's shell table).
    pub const SHELL_TABLE: u32 = 3;
    /// The lighting inputs (the shadow maps and the fur's opacity layers).
    pub const SHADOWS: u32 = crate::lighting::SLOT;
}

/// light.wgsl, a full-screen triangle per light (at its reach's far depth), scissored to it.
pub const SHADER: ShaderDesc = ShaderDesc {
    entry: Entry::Render("vs_light", "fs_main"),
    ..ShaderDesc::render("light.wgsl")
};

/// The light shader's pipeline: additive into the L-buffer, where the light's far depth is
/// at or beyond the surface's (the G-buffer's depth, not written).
pub fn pipeline() -> PipelineDesc {
    PipelineDesc {
        shader: SHADER,
        spec: PipelineSpec {
            groups: vec![
                layout::FRAME,
                layout::TEXTURES,
                layout::LIGHT,
                layout::SHELL_TABLE,
                lighting::LAYOUT,
            ],
            blends: vec![Some(ADD)],
            depth: Some((false, wgpu::CompareFunction::GreaterEqual)),
            ..PipelineSpec::default()
        },
    }
}

/// light.wgsl's override: whether any texel may hold a strand tangent.
const STRAND_LIGHTS: &str = "STRAND_LIGHTS";

/// light.wgsl's override: whether the pipeline draws directional lights (true) or point
/// lights (false).
pub const DIRECTIONAL: &str = "DIRECTIONAL";

/// The override of the shaders that loop over every light (forward.wgsl): whether the view
/// may hold a directional light; false compiles `light_reach`'s branch on the kind out.
pub const SUNS: &str = "SUNS";

/// `desc` (light.wgsl) for lights of `emitter`'s kind.
pub fn for_kind(desc: PipelineDesc, emitter: &Emitter) -> PipelineDesc {
    let directional = emitter.is_directional();
    desc.with_constant(DIRECTIONAL, directional.then_some(1.0))
}

/// Whether any light of `f`'s view needs the full `light_reach` (`Emitter::needs_suns`): the
/// loops over lights branch on the kind only then.
pub fn suns(f: &Frame<'_>) -> bool {
    f.plan.lights.iter().any(|l| l.emitter.needs_suns())
}

/// `desc`, a shader that loops over every light, as `f`'s view needs it: without `light_reach`'s
/// branch on the kind unless a light of the view needs it.
pub fn suns_for_view(f: &Frame<'_>, desc: PipelineDesc) -> PipelineDesc {
    if suns(f) { desc } else { without_suns(desc) }
}

/// `desc` with `light_reach`'s branch on the kind compiled out (point lights only).
pub fn without_suns(desc: PipelineDesc) -> PipelineDesc {
    desc.with_constant(SUNS, Some(0.0))
}

/// `desc` for views without fur lit as strands: no shell-table lookup per pixel.
fn without_strands(desc: PipelineDesc) -> PipelineDesc {
    desc.with_constant(STRAND_LIGHTS, Some(0.0))
}

/// Whether any object of the view is fur lit with Kajiya-Kay (its texels hold tangents).
fn strand_lit(f: &Frame<'_>) -> bool {
    f.plan
        .objects
        .iter()
        .any(|o| o.fur.is_some_and(|x| x.lighting == FurLighting::KajiyaKay))
}

/// The light pass: each light into the L-buffer.
pub const PASS: Pass = Pass::new("light");

/// The light pass in words.
fn explain(plan: &Plan) -> String {
    let (lw, lh) = plan.lbuffer.unwrap_or(plan.output);
    let area: f64 = plan
        .lights
        .iter()
        .map(|l| f64::from(l.rect[2] - l.rect[0]) * f64::from(l.rect[3] - l.rect[1]))
        .sum();
    format!(
        "{lw}×{lh}: {} lights, each a scissored full-screen triangle (mean {:.1}% of the L-buffer), added into RGB diffuse + A specular",
        plan.lights.len(),
        100.0 * area / plan.lights.len().max(1) as f64 / (f64::from(lw) * f64::from(lh))
    )
}

/// The light pass's feature.
pub const FEATURE: Feature = Feature {
    knobs: &[KnobDesc::of(&spec::LBUFFER_SCALE)],
    pipelines: || {
        let directional = Emitter::Directional {
            direction: glam::Vec3::NEG_Y,
        };
        let kinds = [pipeline(), for_kind(pipeline(), &directional)];
        let strands = kinds
            .into_iter()
            .flat_map(|d| [d.clone(), without_strands(d)]);
        lighting::with_unshadowed(strands.collect())
    },
    passes: &[PassDesc {
        after: &[
            Pass::new("shadow-maps"),
            Pass::new("opacity-maps"),
            Pass::new("geometry"),
        ],
        at_lbuffer: true,
        ..PassDesc::new(
            PASS,
            Build::One(pass),
            |plan| plan.lbuffer.is_some(),
            explain,
        )
    }],
    ..Feature::named("lights")
};

/// The light pass's recipe.
pub fn pass<'a>(f: &Frame<'a>) -> Result<Recipe<'a>, MissingInput> {
    let missing = |what: &str| MissingInput {
        pass: PASS.name(),
        what: what.into(),
    };
    let g = f
        .targets
        .gbuffer
        .as_ref()
        .ok_or_else(|| missing("a G-buffer"))?;
    let l = f
        .targets
        .lbuffer
        .as_ref()
        .ok_or_else(|| missing("an L-buffer"))?;
    let a = f.plan.ambient.as_dvec3();
    let mut r = Recipe::new(
        PASS,
        vec![Color {
            view: &l.view,
            format: l.format,
            load: wgpu::LoadOp::Clear(wgpu::Color {
                r: a.x,
                g: a.y,
                b: a.z,
                a: 0.0,
            }),
        }],
        Some(Depth {
            view: &g.depth.view,
            format: g.depth.format,
            load: wgpu::LoadOp::Load,
        }),
    );
    let desc = lighting::for_view(
        f,
        if strand_lit(f) {
            pipeline()
        } else {
            without_strands(pipeline())
        },
    );
    r.bind(
        slot::FRAME,
        f.data.frame(),
        Some(f.data.frame_offset(f.view, Res::Lbuffer)),
    );
    r.bind(slot::GBUFFER, &g.read, None);
    r.bind(slot::SHELL_TABLE, f.data.shell_table(), None);
    lighting::bind(f, &mut r, PASS.name())?;
    let mut kind = None;
    for (i, light) in f.plan.lights.iter().enumerate() {
        // In the scene's order (the L-buffer's sums stay as they were), switching pipeline
        // where the kind changes.
        let k = std::mem::discriminant(&light.emitter);
        if kind != Some(k) {
            r.pipeline(for_kind(desc.clone(), &light.emitter));
            kind = Some(k);
        }
        r.push(Step::Scissor(light.rect));
        r.bind(
            slot::LIGHT,
            f.data.lights(),
            Some(f.data.light_offset(f.view, i)),
        );
        r.push(Step::Draw(0..3, 0..1));
    }
    Ok(r)
}
