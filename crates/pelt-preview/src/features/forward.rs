//! The forward reference: every object loops over every light at output resolution, in the
//! shading pass's phases ([`crate::shading`]) with its own shader; fur is lit per strand
//! with Kajiya-Kay (Revie Listing 2.4).

use super::lights;
use crate::draw::{MissingInput, slot};
use crate::feature::{Build, Feature, Frame, PassDesc, Shade, Shared};
use crate::gpu_material::with_untextured;
use crate::layout;
use crate::lighting;
use crate::pass::Pass;
use crate::plan::Plan;
use crate::recipe::Recipe;
use crate::renderer::{Blend, PipelineDesc};
use crate::shaders::{Lighting, ShaderDesc};
use crate::shading::{self, lit_pipeline};

/// forward.wgsl.
pub const SHADER: ShaderDesc =
    ShaderDesc::render("forward.wgsl").with_defs(&[("MATERIAL_GROUP", slot::MATERIAL)]);

/// The forward shader's pipeline with `blend`, reading the shadow cubes.
pub fn pipeline(blend: Blend) -> PipelineDesc {
    let mut p = lit_pipeline(SHADER, layout::LIGHT_ARRAY, blend);
    p.spec.groups.push(lighting::LAYOUT);
    p
}

/// [`pipeline`] for views without a shadow-casting light (the lookup compiled out).
pub fn unshadowed(blend: Blend) -> PipelineDesc {
    lighting::unshadowed(pipeline(blend))
}

/// The forward pipeline the view needs, by blend: the shadow lookups compiled out where no
/// light casts shadows (or the fur casts no coverage), `light_reach`'s branch on the kind
/// where no light is directional.
pub fn for_view(f: &Frame<'_>) -> Box<dyn Fn(Blend) -> PipelineDesc> {
    let shadowed: fn(Blend) -> PipelineDesc = match (lighting::any(f), lighting::fur_casts(f)) {
        (false, _) => unshadowed,
        (true, false) => without_fur,
        (true, true) => pipeline,
    };
    if lights::suns(f) {
        Box::new(shadowed)
    } else {
        Box::new(move |b| lights::without_suns(shadowed(b)))
    }
}

/// [`pipeline`] for views whose fur casts no coverage (that lookup compiled out).
pub fn without_fur(blend: Blend) -> PipelineDesc {
    lighting::without_fur(pipeline(blend))
}

/// The forward reference's feature.
pub const FEATURE: Feature = Feature {
    pipelines: || {
        let kinds = [pipeline(Blend::None), pipeline(Blend::Over)]
            .into_iter()
            .flat_map(|d| [d.clone(), lights::without_suns(d)]);
        with_untextured(lighting::with_unshadowed(kinds.collect()))
    },
    passes: &[PassDesc {
        after: &[
            Pass::new("distance-maps"),
            Pass::new("min-max"),
            Pass::new("shadow-maps"),
            Pass::new("opacity-maps"),
        ],
        ..PassDesc::new(
            PASS,
            Build::One(pass),
            |plan| plan.mode.is_forward(),
            explain,
        )
    }],
    ..Feature::named("forward")
};

/// The forward pass.
pub const PASS: Pass = Pass::new("forward");

/// The forward pass in words.
fn explain(plan: &Plan) -> String {
    let (w, h) = plan.output;
    let mut s = format!(
        "{w}×{h}: {} objects × {} lights in a per-pixel loop; {} alpha back to front",
        plan.shown,
        plan.lights.len(),
        plan.alpha.len()
    );
    plan.explain_shading(&mut s);
    s
}

/// The forward pass's recipe.
pub fn pass<'a>(f: &Frame<'a>) -> Result<Recipe<'a>, MissingInput> {
    let s = Shade {
        shared: Shared::Shading,
        pass: PASS,
        lit: Lighting::Forward,
        object: for_view(f),
    };
    let mut r = shading::begin(f, &s);
    lighting::bind(f, &mut r, PASS.name())?;
    shading::run_phases(f, &mut r, &s)?;
    Ok(r)
}
