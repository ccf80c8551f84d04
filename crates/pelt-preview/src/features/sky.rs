//! The skybox at infinity (Frantzen): a full-screen triangle at the far plane, drawn where
//! nothing else is, looking the pixel's world direction up in a cube map made from six images
//! or in a procedural sky.

use crate::features::{Frame, MissingInput};
use crate::layout::{self, FILTERABLE, LayoutDesc};
use crate::recipe::{Recipe, Step};
use crate::renderer::{Blend, PipelineKey, PipelineSpec};
use crate::scene::Sky;
use crate::shaders::Shader;

/// Bind-group slots of sky.wgsl.
pub mod slot {
    /// Frame constants.
    pub const FRAME: u32 = 0;
    /// The cube map.
    pub const CUBE: u32 = 1;
}

/// The cube map and its sampler (sky.wgsl's `fs_cube`).
pub const LAYOUT: LayoutDesc = LayoutDesc {
    label: "sky cube",
    entries: &[
        layout::texture(0, FILTERABLE, wgpu::TextureViewDimension::Cube),
        layout::sampler(1),
    ],
};

/// The pipelines of the sky shaders: depth test "less or equal" at depth 1, no writes.
pub fn spec(key: &PipelineKey) -> PipelineSpec {
    PipelineSpec {
        groups: if key.shader == Shader::SkyCube {
            vec![layout::FRAME, LAYOUT]
        } else {
            vec![layout::FRAME]
        },
        blends: vec![None],
        depth: Some((false, wgpu::CompareFunction::LessEqual)),
        ..PipelineSpec::default()
    }
}

/// Draws the sky (the frame group at the output's slot must be bound).
pub fn draw<'a>(f: &Frame<'a>, r: &mut Recipe<'a>, pass: &'static str) -> Result<(), MissingInput> {
    match f.plan.sky {
        Sky::None => return Ok(()),
        Sky::Procedural => r.pipeline(Shader::SkyProcedural, Blend::None),
        Sky::Cubemap(_) => {
            let sky = f.sky.ok_or_else(|| MissingInput {
                pass,
                what: "the cube-map sky on the GPU".into(),
            })?;
            r.pipeline(Shader::SkyCube, Blend::None);
            r.bind(slot::CUBE, &sky.group, None);
        }
    }
    r.push(Step::Draw(0..3, 0..1));
    Ok(())
}
