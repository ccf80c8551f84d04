//! The material pass (Kircher & Lawrance §2.3, §3, §4; Revie §2.4.4) at output resolution:
//! every surface's full material with its light inferred from the L-buffer through
//! discontinuity sensitive filtering. It draws, in order: opaque objects front to back, mirror
//! and glass objects through their distance maps ([`super::reflect`]), each
//! fur object's base mesh, the sky, then every fur object's shells and fins far to near
//! (stipple blend) and the alpha objects back to front, unless the OIT composite draws them.
//! The forward reference ([`super::forward`]) takes the same order with its own shader.

use crate::features::registry::{Build, Feature, PassDesc};
use crate::features::vertex_layout;
use crate::features::{
    Frame, MissingInput, alpha, fur, object_blends, object_depth, reflect, sky, slot, strands,
};
use crate::frame_data::Res;
use crate::layout::{self, LayoutDesc};
use crate::plan::Pass;
use crate::recipe::{Color, Depth, Recipe};
use crate::renderer::{Blend, PipelineDesc, PipelineSpec};
use crate::scene::FurBlend;
use crate::shaders::{Lighting, ShaderDesc};

/// Background of the output (linear; [`pelt_scene::shading::BACKGROUND`]).
pub const BACKGROUND: wgpu::Color = wgpu::Color {
    r: pelt_scene::shading::BACKGROUND[0] as f64,
    g: pelt_scene::shading::BACKGROUND[1] as f64,
    b: pelt_scene::shading::BACKGROUND[2] as f64,
    a: 1.0,
};

/// material.wgsl.
pub const SHADER: ShaderDesc = ShaderDesc::render(&["common.wgsl", "material.wgsl"]);

/// The material shader's pipeline with `blend`.
pub fn pipeline(blend: Blend) -> PipelineDesc {
    lit_pipeline(SHADER, layout::TEXTURES, blend)
}

/// An object shader's pipeline that shades with the object's material, lit through
/// `lighting` at [`slot::LIGHTING`] (the L-buffer, or the forward light array).
pub fn lit_pipeline(shader: ShaderDesc, lighting: LayoutDesc, blend: Blend) -> PipelineDesc {
    PipelineDesc {
        shader,
        spec: PipelineSpec {
            groups: vec![
                layout::FRAME,
                layout::OBJECT,
                lighting,
                crate::gpu_material::LAYOUT,
            ],
            vertex_buffers: vec![vertex_layout()],
            blends: object_blends(blend),
            depth: object_depth(blend),
            ..PipelineSpec::default()
        },
    }
}

/// The material pass's feature.
pub const FEATURE: Feature = Feature {
    name: "material",
    explain: "materials at output resolution, lit from the L-buffer through DSF",
    pipelines: || vec![pipeline(Blend::None), pipeline(Blend::Over)],
    compute: &[],
    passes: &[PassDesc::new(Pass::Material, Build::One(pass))],
};

/// The pipeline ordinary objects are drawn with, lit by `lighting`, with `blend`.
pub fn object_pipeline(lighting: Lighting, blend: Blend) -> PipelineDesc {
    match lighting {
        Lighting::Inferred => pipeline(blend),
        Lighting::Forward => super::forward::pipeline(blend),
    }
}

/// How ordinary objects are lit in `plan`'s mode.
pub fn object_lighting(plan: &crate::plan::Plan) -> Lighting {
    if plan.mode.is_forward() {
        Lighting::Forward
    } else {
        Lighting::Inferred
    }
}

/// The lighting groups of objects lit by `lighting`: (the objects' lighting group, the
/// fur's, each with its offset).
pub fn lighting<'a>(f: &Frame<'a>, lighting: Lighting) -> (Bound<'a>, Bound<'a>) {
    if lighting == Lighting::Forward {
        let a = (
            f.data.light_array(),
            Some(f.data.light_array_offset(f.view)),
        );
        (a, a)
    } else {
        (
            (&f.targets.material_read, None),
            (&f.targets.lbuffer_read, None),
        )
    }
}

/// A bind group with its dynamic offset, if it has one.
pub type Bound<'a> = (&'a wgpu::BindGroup, Option<u32>);

/// The output attachments: colour cleared to the background, depth to 1.
fn attachments<'a>(f: &Frame<'a>, pass: Pass) -> Recipe<'a> {
    Recipe::new(
        pass,
        vec![Color {
            view: f.output.view,
            format: f.output.format,
            load: wgpu::LoadOp::Clear(BACKGROUND),
        }],
        Some(Depth {
            view: &f.targets.depth.view,
            format: f.targets.depth.format,
            load: wgpu::LoadOp::Clear(1.0),
        }),
    )
}

/// The material pass (or, lit forward, the forward pass).
pub fn shade<'a>(f: &Frame<'a>, pass: Pass, lit: Lighting) -> Result<Recipe<'a>, MissingInput> {
    let mut r = attachments(f, pass);
    let (objects_light, fur_light) = lighting(f, lit);
    let fur_lighting = lit;
    f.bind_frame(&mut r, Res::Output);
    r.bind(slot::LIGHTING, objects_light.0, objects_light.1);
    if !f.plan.opaque.is_empty() {
        r.pipeline(object_pipeline(lit, Blend::None));
        f.draw_objects(&mut r, pass.name(), Some(slot::MATERIAL), &f.plan.opaque)?;
    }
    if !f.plan.reflective.is_empty() {
        reflect::draw(f, &mut r, pass.name())?;
        r.bind(slot::LIGHTING, objects_light.0, objects_light.1);
    }
    let has_fur = !f.plan.fur.is_empty();
    if has_fur {
        r.bind(slot::LIGHTING, fur_light.0, fur_light.1);
        fur::base(f, &mut r, pass.name(), fur_lighting)?;
    }
    sky::draw(f, &mut r, pass.name())?;
    let wboit = has_fur && f.plan.fur_blend == FurBlend::Wboit;
    if has_fur && f.plan.mode == crate::plan::Mode::Strands {
        r.bind(slot::LIGHTING, fur_light.0, fur_light.1);
        strands::draw(f, &mut r, pass.name())?;
    } else if has_fur && !wboit {
        r.bind(slot::LIGHTING, fur_light.0, fur_light.1);
        fur::layers(f, &mut r, pass.name(), fur_lighting, Blend::Over)?;
    }
    if !wboit {
        alpha::draw(f, &mut r, pass.name(), lit)?;
    }
    Ok(r)
}

/// The material pass.
pub fn pass<'a>(f: &Frame<'a>) -> Result<Recipe<'a>, MissingInput> {
    shade(f, Pass::Material, Lighting::Inferred)
}
