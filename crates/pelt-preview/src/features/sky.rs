//! The skybox at infinity (Frantzen): a full-screen triangle at the far plane, drawn where
//! nothing else is, looking the pixel's world direction up in a cube map made from six images
//! or in a procedural sky.

use crate::draw::MissingInput;
use crate::feature::{DrawDesc, Feature, Frame, Phase, Shared};
use crate::layout::{self, LayoutDesc};
use crate::recipe::{Recipe, Step};
use crate::renderer::{PipelineDesc, PipelineSpec};
use crate::scene::Sky;
use crate::shaders::ShaderDesc;

/// Bind-group slots of sky.wgsl.
pub mod slot {
    /// Frame constants.
    pub const FRAME: u32 = 0;
    /// The cube map.
    pub const CUBE: u32 = 1;
}

/// The cube map and its sampler, as the asset cache binds them.
pub const LAYOUT: LayoutDesc = layout::SKY_CUBE;

/// sky.wgsl's procedural sky.
pub const PROCEDURAL: ShaderDesc = ShaderDesc::fullscreen("sky.wgsl", "fs_procedural");
/// sky.wgsl's cube-map sky.
pub const CUBE: ShaderDesc = ShaderDesc::fullscreen("sky.wgsl", "fs_cube");

/// The pipeline of a sky (`cube`: the cube map's, else the procedural one): depth test
/// "less or equal" at depth 1, no writes.
pub fn pipeline(cube: bool) -> PipelineDesc {
    PipelineDesc {
        shader: if cube { CUBE } else { PROCEDURAL },
        spec: PipelineSpec {
            groups: if cube {
                vec![layout::FRAME, LAYOUT]
            } else {
                vec![layout::FRAME]
            },
            blends: vec![None],
            depth: Some((false, wgpu::CompareFunction::LessEqual)),
            ..PipelineSpec::default()
        },
    }
}

/// The sky's feature.
pub const FEATURE: Feature = Feature {
    pipelines: || vec![pipeline(false), pipeline(true)],
    draws: &[DrawDesc {
        into: Shared::Shading,
        phase: Phase::Sky,
        draw: |f, r, s| draw(f, r, s.pass.name()),
    }],
    ..Feature::named("sky")
};

/// Draws the sky (the frame group at the output's slot must be bound).
pub fn draw<'a>(f: &Frame<'a>, r: &mut Recipe<'a>, pass: &'static str) -> Result<(), MissingInput> {
    match f.plan.sky {
        Sky::None => return Ok(()),
        Sky::Procedural => r.pipeline(pipeline(false)),
        Sky::Cubemap(_) => {
            let sky = f.sky.ok_or_else(|| MissingInput {
                pass,
                what: "the cube-map sky on the GPU".into(),
            })?;
            r.pipeline(pipeline(true));
            r.bind(slot::CUBE, &sky.group, None);
        }
    }
    r.push(Step::Draw(0..3, 0..1));
    Ok(())
}
