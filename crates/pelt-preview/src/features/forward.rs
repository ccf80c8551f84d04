//! The forward reference: every object loops over every light at output resolution, in the
//! material pass's order; fur is lit per strand with Kajiya-Kay (Revie Listing 2.4).

use crate::features::registry::{Build, Feature, PassDesc};
use crate::features::{Frame, MissingInput, material};
use crate::layout;
use crate::plan::Pass;
use crate::recipe::Recipe;
use crate::renderer::{Blend, PipelineDesc};
use crate::shaders::{Lighting, ShaderDesc};

/// forward.wgsl.
pub const SHADER: ShaderDesc = ShaderDesc::render(&["common.wgsl", "forward.wgsl"]);

/// The forward shader's pipeline with `blend`.
pub fn pipeline(blend: Blend) -> PipelineDesc {
    material::lit_pipeline(SHADER, layout::LIGHT_ARRAY, blend)
}

/// The forward reference's feature.
pub const FEATURE: Feature = Feature {
    name: "forward",
    explain: "the forward reference: every object loops over every light",
    pipelines: || vec![pipeline(Blend::None), pipeline(Blend::Over)],
    compute: &[],
    passes: &[PassDesc::new(Pass::Forward, Build::One(pass))],
};

/// The forward pass.
pub fn pass<'a>(f: &Frame<'a>) -> Result<Recipe<'a>, MissingInput> {
    material::shade(f, Pass::Forward, Lighting::Forward)
}
