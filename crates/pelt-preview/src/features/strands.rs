//! Explicit strands, the converged fur reference (`--mode strands`): in the forward pass, in
//! place of each fur object's shells and fins, its strands ([`crate::strands`]) drawn as
//! capsules, opaque and depth tested, lit per light with Kajiya-Kay (Revie Listing 2.4,
//! shaders/strands.wgsl). One frame is one sample: the caller jitters the projection and
//! accumulates (`pelt_measure::strands`).

use crate::draw::{MissingInput, object_blends, object_depth, slot};
use crate::feature::{DrawDesc, Feature, Frame, Phase, Shade, Shared};
use crate::recipe::{Recipe, Step};
use crate::renderer::{Blend, PipelineDesc, PipelineSpec};
use crate::shaders::ShaderDesc;
use crate::shading;
use crate::uniforms::StrandRoot;

/// Segments per strand. Keep in sync with `SEGMENTS` in shaders/strands.wgsl.
pub const STRAND_SEGMENTS: u32 = 4;

const ATTRIBUTES: [wgpu::VertexAttribute; 5] = wgpu::vertex_attr_array![
    0 => Float32x4, 1 => Float32x4, 2 => Float32x4, 3 => Float32x4, 4 => Float32x4
];

/// The strand instance buffer: one [`StrandRoot`] per strand (`StrandIn` in strands.wgsl).
pub fn layout() -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: size_of::<StrandRoot>() as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &ATTRIBUTES,
    }
}

/// strands.wgsl, lit per light with Kajiya-Kay.
pub const SHADER: ShaderDesc = ShaderDesc::render("strands.wgsl");

/// The pipeline of strands.wgsl (opaque strands).
pub fn pipeline() -> PipelineDesc {
    PipelineDesc {
        shader: SHADER,
        spec: PipelineSpec {
            groups: vec![
                crate::layout::FRAME,
                crate::layout::OBJECT,
                crate::layout::LIGHT_ARRAY,
            ],
            vertex_buffers: vec![layout()],
            blends: object_blends(Blend::None),
            depth: object_depth(Blend::None),
            ..PipelineSpec::default()
        },
    }
}

/// The strand reference's feature.
pub const FEATURE: Feature = Feature {
    pipelines: || vec![pipeline()],
    draws: &[DrawDesc {
        into: Shared::Shading,
        phase: Phase::FurLayers,
        draw: shade,
    }],
    ..Feature::named(
        "strands",
        "explicit strands lit per light: the converged fur reference",
    )
};

/// The strands in the shading pass, lit as fur (strands mode only).
fn shade<'a>(f: &Frame<'a>, r: &mut Recipe<'a>, s: &Shade) -> Result<(), MissingInput> {
    if f.plan.fur.is_empty() || f.plan.mode != crate::plan::Mode::Strands {
        return Ok(());
    }
    let (group, offset) = shading::lighting(f, s.lit).1;
    r.bind(slot::LIGHTING, group, offset);
    draw(f, r, s.pass.name())
}

/// Every fur object's strands. The frame and forward light-array groups must be bound.
pub fn draw<'a>(f: &Frame<'a>, r: &mut Recipe<'a>, pass: &'static str) -> Result<(), MissingInput> {
    r.pipeline(pipeline());
    for &k in &f.plan.fur {
        let o = &f.plan.objects[k];
        let strands = f
            .strands
            .get(o.mesh)
            .and_then(|s| s.as_deref())
            .ok_or_else(|| MissingInput {
                pass,
                what: format!("the strands of objects[{}] on the GPU", o.scene_index),
            })?;
        if strands.count == 0 {
            continue;
        }
        f.bind_object(r, k);
        r.push(Step::Vertices(
            crate::draw::vertex_slot::INSTANCES,
            &strands.roots,
        ));
        r.push(Step::Draw(0..3 * STRAND_SEGMENTS, 0..strands.count));
    }
    Ok(())
}
