//! The shading pass: one render pass at output resolution in which every surface gets its
//! full material (Kircher & Lawrance §2.3: lit from the L-buffer through DSF; or, lit
//! forward, from the light array). Features add their draws to it by [`Phase`], and
//! [`shade`] runs the phases in order over the registered features: opaque objects, mirrors
//! and glass (GPU Gems 3 ch. 17), the fur's base mesh (Revie §2.4.4), the sky, the fur's
//! layers far to near, then alpha objects back to front. Each draw binds the lighting it
//! reads, so no draw depends on what an earlier one left bound.

use crate::draw::{MissingInput, object_blends, object_depth, vertex_layout};
use crate::feature::{Frame, Phase, Shade};
use crate::frame_data::Res;
use crate::layout::{self, LayoutDesc};
use crate::pass::Pass;
use crate::recipe::{Color, Depth, Recipe};
use crate::renderer::{Blend, PipelineDesc, PipelineSpec};
use crate::shaders::{Lighting, ShaderDesc};

/// Background of the output (linear; [`pelt_scene::shading::BACKGROUND`]).
pub const BACKGROUND: wgpu::Color = wgpu::Color {
    r: pelt_scene::shading::BACKGROUND[0] as f64,
    g: pelt_scene::shading::BACKGROUND[1] as f64,
    b: pelt_scene::shading::BACKGROUND[2] as f64,
    a: 1.0,
};

/// A bind group with its dynamic offset, if it has one.
pub type Bound<'a> = (&'a wgpu::BindGroup, Option<u32>);

/// The lighting groups of objects lit by `lighting`: (the objects' lighting group, the
/// fur's, each with its offset). Inferred: the material pass's read of the L-buffer (the
/// obliterated composition where there is one) and the original L-buffer the fur reads at
/// root and tip; forward: the light array for both.
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

/// How ordinary objects are lit in `plan`'s mode.
pub fn object_lighting(plan: &crate::plan::Plan) -> Lighting {
    if plan.mode.is_forward() {
        Lighting::Forward
    } else {
        Lighting::Inferred
    }
}

/// An object shader's pipeline that shades with the object's material, lit through
/// `lighting` at [`crate::draw::slot::LIGHTING`] (the L-buffer, or the forward light array).
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

/// The registered features' draws into `s.shared`, phase by phase (registry order within a
/// phase), appended to `r`.
pub fn run_phases<'a>(f: &Frame<'a>, r: &mut Recipe<'a>, s: &Shade) -> Result<(), MissingInput> {
    for phase in Phase::ALL {
        let draws = f.features.iter().flat_map(|x| x.draws);
        for d in draws.filter(|d| d.into == s.shared && d.phase == phase) {
            (d.draw)(f, r, s)?;
        }
    }
    Ok(())
}

/// The shading pass `s` begun: the output cleared and the frame bound, before any draw.
pub fn begin<'a>(f: &Frame<'a>, s: &Shade) -> Recipe<'a> {
    let mut r = attachments(f, s.pass);
    f.bind_frame(&mut r, Res::Output);
    r
}

/// The shading pass `s`: [`begin`], then the registered features' draws.
pub fn shade<'a>(f: &Frame<'a>, s: &Shade) -> Result<Recipe<'a>, MissingInput> {
    let mut r = begin(f, s);
    run_phases(f, &mut r, s)?;
    Ok(r)
}
