//! The material pass (Kircher & Lawrance §2.3, §3): every surface's full material at output
//! resolution with its light inferred from the L-buffer through discontinuity sensitive
//! filtering. The pass is the core's shading pass ([`crate::shading`]) lit from the
//! L-buffer; this feature declares the material shader and draws the opaque objects, front
//! to back, in its opaque phase. The forward reference ([`super::forward`]) runs the same
//! phases with its own shader.

use crate::draw::{MissingInput, slot};
use crate::feature::{
    Build, DrawDesc, Feature, Frame, KnobDesc, PassDesc, Phase, Shade, Shared, Sides,
};
use crate::gpu_material::with_untextured;
use crate::layout;
use crate::pass::Pass;
use crate::plan::Plan;
use crate::recipe::Recipe;
use crate::renderer::{Blend, PipelineDesc};
use crate::shaders::{Lighting, ShaderDesc};
use crate::shading::{self, lit_pipeline};

/// material.wgsl.
pub const SHADER: ShaderDesc =
    ShaderDesc::render("material.wgsl").with_defs(&[("MATERIAL_GROUP", slot::MATERIAL)]);

/// The material shader's pipeline with `blend`.
pub fn pipeline(blend: Blend) -> PipelineDesc {
    lit_pipeline(SHADER, layout::TEXTURES, blend)
}

/// The material pass's feature.
pub const FEATURE: Feature = Feature {
    knobs: &[KnobDesc::of(&pelt_scene::knobs::spec::DSF)],
    pipelines: || with_untextured([pipeline(Blend::None), pipeline(Blend::Over)]),
    passes: &[PassDesc {
        after: &[
            Pass::new("distance-maps"),
            Pass::new("min-max"),
            Pass::new("shadow-maps"),
            Pass::new("opacity-maps"),
            Pass::new("light"),
            Pass::new("obliterate"),
        ],
        ..PassDesc::new(PASS, Build::One(pass), wanted, explain)
    }],
    draws: &[DrawDesc {
        into: Shared::Shading,
        phase: Phase::Opaque,
        draw: opaque,
    }],
    ..Feature::named("material")
};

/// The opaque objects, front to back, each part with its material.
pub fn opaque<'a>(f: &Frame<'a>, r: &mut Recipe<'a>, s: &Shade) -> Result<(), MissingInput> {
    if f.plan.opaque.is_empty() {
        return Ok(());
    }
    let (group, offset) = shading::lighting(f, s.lit).0;
    r.bind(slot::LIGHTING, group, offset);
    r.pipeline((s.object)(Blend::None));
    f.draw_objects(
        r,
        s.pass.name(),
        Some(slot::MATERIAL),
        Sides::Material,
        &f.plan.opaque,
    )
}

/// The material pass.
pub const PASS: Pass = Pass::new("material");

/// Whether `plan` shades through the material pass: every mode lit from an L-buffer, or by
/// the ambient term alone.
fn wanted(plan: &Plan) -> bool {
    plan.mode.is_deferred()
}

/// The material pass in words.
fn explain(plan: &Plan) -> String {
    let (w, h) = plan.output;
    let mut s = format!("{w}×{h}: ");
    s += if plan.lbuffer.is_none() {
        "no lights on screen, ambient only (no G-buffer or L-buffer); "
    } else if plan.dsf {
        "DSF bilinear over 4 L-buffer taps (ID equal, depth within threshold); "
    } else {
        "plain bilinear L-buffer taps; "
    };
    s += &format!(
        "{} opaque front to back, {} alpha back to front",
        plan.opaque.len(),
        plan.alpha.len()
    );
    plan.explain_shading(&mut s);
    s
}

/// The material pass's recipe.
pub fn pass<'a>(f: &Frame<'a>) -> Result<Recipe<'a>, MissingInput> {
    let s = Shade {
        shared: Shared::Shading,
        pass: PASS,
        lit: Lighting::Inferred,
        object: Box::new(pipeline),
    };
    shading::shade(f, &s)
}
