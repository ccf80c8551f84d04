//! Opaque geometry (Kircher & Lawrance §2.1): the geometry pass at L-buffer resolution
//! writes every object's view normal (eq. 1), its 16-bit linear depth and DSF ID (object ID
//! and normal group, §3.1) and hardware depth. Opaque objects go first, nearest first; the fur
//! feature adds its base mesh and stippled outer shell, the alpha feature its stippled
//! objects.

use crate::draw::{MissingInput, slot, vertex_layout};
use crate::feature::{Build, DrawDesc, Feature, Frame, PassDesc, Phase, Shade, Shared, Sides};
use crate::frame_data::Res;
use crate::gpu_material::with_untextured;
use crate::layout;
use crate::pass::Pass;
use crate::plan::Plan;
use crate::recipe::{Color, Depth, Recipe};
use crate::renderer::{PipelineDesc, PipelineSpec};
use crate::shaders::{Lighting, ShaderDesc};
use crate::shading;

/// gbuffer.wgsl.
pub const SHADER: ShaderDesc =
    ShaderDesc::render("gbuffer.wgsl").with_defs(&[("MATERIAL_GROUP", slot::GBUFFER_MATERIAL)]);

/// The G-buffer shader's pipeline.
pub fn pipeline() -> PipelineDesc {
    PipelineDesc {
        shader: SHADER,
        spec: PipelineSpec {
            groups: vec![layout::FRAME, layout::OBJECT, crate::gpu_material::LAYOUT],
            vertex_buffers: vec![vertex_layout()],
            blends: vec![None, None],
            depth: Some((true, wgpu::CompareFunction::Less)),
            ..PipelineSpec::default()
        },
    }
}

/// gbuffer.wgsl's override constant: whether the objects drawn are stippled (alpha layers
/// discard the pixels outside their pattern); keep in sync with gbuffer.wgsl.
pub const STIPPLED: &str = "STIPPLED";

/// The G-buffer pipeline of opaque objects: every pixel kept, so the shader never discards
/// and the rasterizer tests depth before shading.
pub fn opaque_pipeline() -> PipelineDesc {
    pipeline().with_constant(STIPPLED, Some(0.0))
}

/// The geometry pass: the G-buffer at the L-buffer's size.
pub const PASS: Pass = Pass::new("geometry");

/// The geometry pass in words.
fn explain(plan: &Plan) -> String {
    let (lw, lh) = plan.lbuffer.unwrap_or(plan.output);
    let mut s = format!(
        "{lw}×{lh}: view normals (eq. 1, X/Y 16-bit), DSF (16-bit linear depth, ID object<<8|group), depth; {} opaque, {} alpha stippled 2×2",
        plan.opaque.len(),
        plan.alpha.len()
    );
    s += &plan.explain_stipple();
    if !plan.fur.is_empty() {
        s += &format!(
            "; {} fur: base mesh with grain normals (Revie 2.5), outer shell stippled 1 in 4 with rim normals (2.1, 2.3)",
            plan.fur.len()
        );
    }
    s
}

/// The geometry pass's feature.
pub const FEATURE: Feature = Feature {
    pipelines: || with_untextured([pipeline(), opaque_pipeline()]),
    passes: &[PassDesc {
        at_lbuffer: true,
        ..PassDesc::new(
            PASS,
            Build::One(pass),
            |plan| plan.lbuffer.is_some(),
            explain,
        )
    }],
    draws: &[DrawDesc {
        into: Shared::Geometry,
        phase: Phase::Opaque,
        draw: opaque,
    }],
    ..Feature::named("geometry")
};

/// The G-buffer's colour and depth attachments, cleared: normals 0, DSF depth code 65535
/// (no surface) and ID 0, depth 1.
fn attachments<'a>(f: &Frame<'a>) -> Result<Recipe<'a>, MissingInput> {
    let g = f.targets.gbuffer.as_ref().ok_or_else(|| MissingInput {
        pass: PASS.name(),
        what: "a G-buffer".into(),
    })?;
    let dsf_empty = wgpu::Color {
        r: 65535.0,
        g: 0.0,
        b: 0.0,
        a: 0.0,
    };
    Ok(Recipe::new(
        PASS,
        vec![
            Color {
                view: &g.normals.view,
                format: g.normals.format,
                load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
            },
            Color {
                view: &g.dsf.view,
                format: g.dsf.format,
                load: wgpu::LoadOp::Clear(dsf_empty),
            },
        ],
        Some(Depth {
            view: &g.depth.view,
            format: g.depth.format,
            load: wgpu::LoadOp::Clear(1.0),
        }),
    ))
}

/// Opaque objects, then mirrors and glass: they hold their pixels' depth and IDs (they are
/// shaded later, from their distance maps, not from the L-buffer).
fn opaque<'a>(f: &Frame<'a>, r: &mut Recipe<'a>, s: &Shade) -> Result<(), MissingInput> {
    if f.plan.opaque.is_empty() && f.plan.reflective.is_empty() {
        return Ok(());
    }
    r.pipeline(opaque_pipeline());
    let material = Some(slot::GBUFFER_MATERIAL);
    let sides = Sides::Material;
    f.draw_objects(r, s.pass.name(), material, sides, &f.plan.opaque)?;
    f.draw_objects(r, s.pass.name(), material, sides, &f.plan.reflective)
}

/// The geometry pass: the G-buffer cleared, then the registered features' draws into it
/// (opaque objects here, the fur's base and outer shell, stippled alpha), phase by phase.
pub fn pass<'a>(f: &Frame<'a>) -> Result<Recipe<'a>, MissingInput> {
    let mut r = attachments(f)?;
    f.bind_frame(&mut r, Res::Lbuffer);
    let s = Shade {
        shared: Shared::Geometry,
        pass: PASS,
        lit: Lighting::Inferred,
        object: Box::new(|_| pipeline()),
    };
    shading::run_phases(f, &mut r, &s)?;
    Ok(r)
}
