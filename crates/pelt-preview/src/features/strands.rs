//! Explicit strands, the converged fur reference (`--mode strands`): in the forward pass, in
//! place of each fur object's shells and fins, its strands ([`crate::strands`]) drawn as
//! capsules, opaque and depth tested, lit per light with Kajiya-Kay (Revie Listing 2.4,
//! shaders/strands.wgsl). One frame is one sample: the caller jitters the projection and
//! accumulates (`pelt_measure::strands`).
//!
//! Where a light of the view casts shadows, each strand is lit as its shadow rays found it
//! ([`TracedShadows`], `pelt_trace::strands`): a bit per sample (its segments' ends) and
//! light, traced on the CPU through every other strand and the scene when the view is
//! prepared, blended along each segment (the `TRACED_SHADOWS` def of strands.wgsl).

use crate::draw::{MissingInput, object_blends, object_depth, slot};
use crate::feature::{DrawDesc, Feature, Frame, Phase, Shade, Shared};
use crate::plan::ScenePlan;
use crate::recipe::{Recipe, Step};
use crate::renderer::{Blend, PipelineDesc, PipelineSpec};
use crate::shaders::ShaderDesc;
use crate::shading;
use crate::uniforms::StrandRoot;
use pelt_scene::asset::MeshData;
use std::collections::HashMap;
use std::sync::Arc;

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

const TRACED_ATTRIBUTES: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![5 => Uint32x2];

/// The shadow bits' instance buffer: one `[u32; 2]` per strand (`Traced` in strands.wgsl).
pub fn traced_layout() -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: size_of::<[u32; 2]>() as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &TRACED_ATTRIBUTES,
    }
}

/// strands.wgsl, lit per light with Kajiya-Kay.
pub const SHADER: ShaderDesc = ShaderDesc::render("strands.wgsl");

/// strands.wgsl weighing each shadow-casting light by the strand's traced bits.
pub const TRACED: ShaderDesc = SHADER.with_defs(&[("TRACED_SHADOWS", 1)]);

/// The pipeline of strands.wgsl (opaque strands), `traced`: reading the shadow bits.
pub fn pipeline(traced: bool) -> PipelineDesc {
    PipelineDesc {
        shader: if traced { TRACED } else { SHADER },
        spec: PipelineSpec {
            groups: vec![
                crate::layout::FRAME,
                crate::layout::OBJECT,
                crate::layout::LIGHT_ARRAY,
            ],
            vertex_buffers: if traced {
                vec![layout(), traced_layout()]
            } else {
                vec![layout()]
            },
            blends: object_blends(Blend::None),
            depth: object_depth(Blend::None),
            ..PipelineSpec::default()
        },
    }
}

/// Each fur object's strands' shadow bits (`pelt_trace::strands::shadow_bits`), on the GPU.
#[derive(Debug)]
pub struct TracedShadows {
    /// By scene object index: one `[u32; 2]` per strand.
    bits: HashMap<usize, wgpu::Buffer>,
    /// What they were traced for (the casting lights, the objects and their fur).
    key: String,
}

impl TracedShadows {
    /// What `plan`'s bits depend on.
    fn key_of(plan: &ScenePlan) -> String {
        let lights: Vec<_> = plan.shadow_lights().map(|l| l.emitter).collect();
        let objects: Vec<_> = plan
            .objects
            .iter()
            .map(|(o, _)| (o.mesh, o.model, o.pattern, o.fur.map(|f| f.length)))
            .collect();
        format!("{lights:?} {objects:?}")
    }

    /// Whether these bits were traced for `plan`.
    pub fn fits(&self, plan: &ScenePlan) -> bool {
        self.key == Self::key_of(plan)
    }

    /// Traces the shadow rays of every fur object's `strands` (by mesh) of `plan` toward its
    /// shadow-casting lights through the strands and `meshes`, and uploads the bits.
    pub fn new(
        r: &crate::renderer::Renderer,
        plan: &ScenePlan,
        meshes: &[MeshData],
        strands: &[Option<Arc<crate::assets::GpuStrands>>],
    ) -> TracedShadows {
        let lights: Vec<_> = plan.shadow_lights().map(|l| l.emitter).collect();
        let mut objects = Vec::new();
        let mut sets = Vec::new();
        for (o, _) in &plan.objects {
            if let (Some(f), Some(Some(s))) = (o.fur, strands.get(o.mesh)) {
                objects.push(o.scene_index);
                sets.push(pelt_trace::strands::StrandSet {
                    model: o.model,
                    length: f.length,
                    roots: &s.planted,
                });
            }
        }
        let bits = if lights.is_empty() || sets.is_empty() {
            Vec::new()
        } else {
            let world = pelt_trace::World::new(plan, meshes, pelt_trace::SkyModel::Background);
            pelt_trace::strands::shadow_bits(&world, &sets, &lights)
        };
        let bits = objects
            .into_iter()
            .zip(bits)
            .map(|(k, b)| {
                // A buffer of zero bytes cannot be bound: an empty set keeps one record.
                let b = if b.is_empty() { vec![[0; 2]] } else { b };
                let buffer = r.gpu.buffer_init(
                    "strand shadow bits",
                    bytemuck::cast_slice(&b),
                    wgpu::BufferUsages::VERTEX,
                );
                (k, buffer)
            })
            .collect();
        TracedShadows {
            bits,
            key: Self::key_of(plan),
        }
    }
}

/// The strand reference's feature.
pub const FEATURE: Feature = Feature {
    pipelines: || vec![pipeline(false), pipeline(true)],
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
    let traced = super::shadows::any(f);
    let bits = if traced {
        Some(
            f.scene
                .need::<TracedShadows>(pass, "the strands' traced shadow bits")?,
        )
    } else {
        None
    };
    r.pipeline(pipeline(traced));
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
        if let Some(t) = bits {
            let b = t.bits.get(&o.scene_index).ok_or_else(|| MissingInput {
                pass,
                what: format!("the shadow bits of objects[{}]'s strands", o.scene_index),
            })?;
            r.push(Step::Vertices(crate::draw::vertex_slot::TRACED, b));
        }
        r.push(Step::Draw(0..3 * STRAND_SEGMENTS, 0..strands.count));
    }
    Ok(())
}
