//! The forward reference: every object loops over every light at output resolution, in the
//! material pass's order; fur is lit per strand with Kajiya-Kay (Revie Listing 2.4).

use crate::features::registry::{Feature, PassDesc};
use crate::features::{Frame, MissingInput, material, object_blends, object_depth, vertex_layout};
use crate::layout;
use crate::plan::Pass;
use crate::recipe::Recipe;
use crate::renderer::{Blend, PipelineDesc, PipelineSpec};
use crate::shaders::{Lighting, ShaderDesc};

/// forward.wgsl.
pub const SHADER: ShaderDesc = ShaderDesc::render(&["common.wgsl", "forward.wgsl"]);

/// The forward shader's pipeline with `blend`.
pub fn pipeline(blend: Blend) -> PipelineDesc {
    PipelineDesc {
        shader: SHADER,
        spec: PipelineSpec {
            groups: vec![
                layout::FRAME,
                layout::OBJECT,
                layout::LIGHT_ARRAY,
                crate::gpu_material::LAYOUT,
            ],
            vertex_buffers: vec![vertex_layout()],
            blends: object_blends(blend),
            depth: object_depth(blend),
            ..PipelineSpec::default()
        },
    }
}

/// The forward reference's feature.
pub const FEATURE: Feature = Feature {
    name: "forward",
    explain: "the forward reference: every object loops over every light",
    pipelines: || vec![pipeline(Blend::None), pipeline(Blend::Over)],
    compute: &[],
    passes: &[PassDesc::new(Pass::Forward, build_pass)],
};

/// The forward pass.
pub fn pass<'a>(f: &Frame<'a>) -> Result<Recipe<'a>, MissingInput> {
    material::shade(f, Pass::Forward, Lighting::Forward)
}

fn build_pass<'a>(f: &Frame<'a>) -> Result<Vec<Recipe<'a>>, MissingInput> {
    pass(f).map(|r| vec![r])
}
