//! The scene colour: where a frame blends fur layers, every pass that draws at output
//! resolution draws into a linear half-float target instead of the output, and the resolve
//! pass writes it to the output once (upscale.wgsl's filtered read at the same size: an
//! exact copy, encoded by the output's format).
//!
//! Why: the shells composite tens of thin layers (Lengyel et al. 2001; Revie §2.3.1), each
//! with an opacity of a few per cent. Blended one after another straight into an 8-bit sRGB
//! target, every layer's result is rounded to the nearest of 256 steps, and at that opacity
//! the rounding no longer averages out: on the demo scene the fur grew a fifth brighter from
//! 4 to 64 shells. Half floats keep 11 significant bits at every brightness.

use super::upscale::Upscale;
use crate::draw::MissingInput;
use crate::feature::{Build, DrawsInto, Feature, Frame, Output, PassDesc, TargetsDesc};
use crate::pass::Pass;
use crate::plan::{Mode, Plan};
use crate::recipe::Recipe;
use crate::renderer::{Renderer, SCENE_FORMAT};
use crate::targets::Target;

/// The resolve's feature (it draws the upscale feature's pipeline).
pub const FEATURE: Feature = Feature {
    passes: &[PassDesc {
        into: DrawsInto::Output,
        after: &[
            Pass::new("material"),
            Pass::new("forward"),
            Pass::new("fur-oit"),
            Pass::new("composite"),
        ],
        ..PassDesc::new(PASS, Build::One(pass), wanted, explain)
    }],
    targets: Some(TargetsDesc {
        needed: wanted,
        make: |r, spec, owned| owned.insert(SceneColor::new(r, spec.output)),
    }),
    ..Feature::named("resolve")
};

/// The resolve pass.
pub const PASS: Pass = Pass::new("resolve");

/// Whether `plan` draws into a scene colour: where fur layers blend (the strands are
/// opaque; the debug views unlit).
fn wanted(plan: &Plan) -> bool {
    !plan.fur.is_empty() && plan.mode != Mode::Strands && !plan.mode.is_debug()
}

/// The resolve pass in words.
fn explain(plan: &Plan) -> String {
    let (w, h) = plan.output;
    format!("{w}×{h}: the half-float colour the fur's layers blended into, to the output")
}

/// The scene colour target and the copy that resolves it.
#[derive(Debug)]
pub struct SceneColor {
    /// Linear RGBA in [`SCENE_FORMAT`], at output size.
    pub target: Target,
    copy: Upscale,
}

impl SceneColor {
    /// A scene colour target of `size`.
    pub fn new(r: &Renderer, size: (u32, u32)) -> SceneColor {
        let target = Target::new(&r.gpu.device, "scene colour", size, SCENE_FORMAT);
        let copy = Upscale::new(r, &target, size);
        SceneColor { target, copy }
    }
}

/// `f` as the passes before the resolve see it: drawing into the scene colour where the plan
/// resolves one, else `f` itself.
pub fn inner<'a>(f: &Frame<'a>) -> Result<Frame<'a>, MissingInput> {
    if !wanted(f.plan) {
        return Ok(*f);
    }
    let scene = scene_color(f)?;
    Ok(Frame {
        output: Output {
            view: &scene.target.view,
            format: scene.target.format,
        },
        ..*f
    })
}

fn scene_color<'a>(f: &Frame<'a>) -> Result<&'a SceneColor, MissingInput> {
    f.targets.owned.need(PASS.name(), "the scene colour target")
}

/// The resolve pass: the scene colour into `f`'s output.
pub fn pass<'a>(f: &Frame<'a>) -> Result<Recipe<'a>, MissingInput> {
    Ok(scene_color(f)?.copy.pass_as(PASS, f.output))
}
