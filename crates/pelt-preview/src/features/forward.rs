//! The forward reference: every object loops over every light at output resolution, in the
//! material pass's order; fur is lit per strand with Kajiya-Kay (Revie Listing 2.4).

use crate::features::{Frame, MissingInput, material, object_blends, object_depth, vertex_layout};
use crate::layout;
use crate::plan::Pass;
use crate::recipe::Recipe;
use crate::renderer::{PipelineKey, PipelineSpec};
use crate::shaders::Shader;

/// The pipeline of the forward shader.
pub fn spec(key: &PipelineKey) -> PipelineSpec {
    PipelineSpec {
        groups: vec![
            layout::FRAME,
            layout::OBJECT,
            layout::LIGHT_ARRAY,
            crate::gpu_material::LAYOUT,
        ],
        vertex_buffers: vec![vertex_layout()],
        blends: object_blends(key.blend),
        depth: object_depth(key.blend),
        ..PipelineSpec::default()
    }
}

/// The forward pass.
pub fn pass<'a>(f: &Frame<'a>) -> Result<Recipe<'a>, MissingInput> {
    material::shade(f, Pass::Forward, Shader::Forward)
}
