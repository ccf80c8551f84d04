//! Weighted blended order-independent transparency (McGuire & Bavoil 2013, eq. 7 with view
//! depth; Frantzen's steps 2 and 3) for fur: shells and fins accumulate Σ colour·α·w and
//! Σ α·w additively and the revealage Π (1 − α) multiplicatively, depth-tested against the
//! image's opaque depth without writing it; the composite divides and blends the result over
//! the image, then draws the alpha objects.

use super::{alpha, fur};
use crate::draw::{MissingInput, slot};
use crate::feature::{Build, Feature, Frame, KnobDesc, PassDesc, Shade, Shared, TargetsDesc};
use crate::frame_data::Res;
use crate::layout::{self, LayoutDesc};
use crate::owned::Owned;
use crate::pass::Pass;
use crate::plan::Plan;
use crate::recipe::{Color, Depth, Recipe, Step};
use crate::renderer::{Blend, PipelineDesc, PipelineSpec, REVEAL_FORMAT, Renderer};
use crate::scene::FurBlend;
use crate::shaders::{Lighting, ShaderDesc};
use crate::shading;
use crate::targets::{Target, TargetSpec};

/// The accumulation and revealage targets read by the composite (composite.wgsl).
pub const LAYOUT: LayoutDesc = LayoutDesc {
    label: "oit",
    entries: &[
        layout::texture(0, layout::UNFILTERABLE, layout::D2),
        layout::texture(1, layout::UNFILTERABLE, layout::D2),
    ],
};

/// Bind-group slots of composite.wgsl.
pub mod slot_composite {
    /// Accumulation and revealage.
    pub const OIT: u32 = 0;
}

/// composite.wgsl.
pub const SHADER: ShaderDesc = ShaderDesc::fullscreen("composite.wgsl", "fs_main");

/// The composite shader's pipeline: the resolved layers over the image.
pub fn pipeline() -> PipelineDesc {
    PipelineDesc {
        shader: SHADER,
        spec: PipelineSpec {
            groups: vec![LAYOUT],
            blends: vec![Some(wgpu::BlendState::ALPHA_BLENDING)],
            depth: Some((false, wgpu::CompareFunction::Always)),
            ..PipelineSpec::default()
        },
    }
}

/// Weighted blended OIT's feature (its accumulation draws the fur's pipelines).
pub const FEATURE: Feature = Feature {
    knobs: &[KnobDesc::of(&pelt_scene::knobs::spec::FUR_BLEND)],
    pipelines: || vec![pipeline()],
    passes: &[
        PassDesc {
            after: &[
                Pass::new("shadow-maps"),
                Pass::new("opacity-maps"),
                Pass::new("material"),
                Pass::new("forward"),
            ],
            ..PassDesc::new(ACCUM, Build::One(accum_pass), wanted, explain_accum)
        },
        PassDesc {
            after: &[ACCUM, Pass::new("material"), Pass::new("forward")],
            ..PassDesc::new(
                COMPOSITE,
                Build::One(composite_pass),
                wanted,
                explain_composite,
            )
        },
    ],
    targets: Some(TargetsDesc {
        needed: wanted,
        make: make_targets,
    }),
    ..Feature::named("wboit")
};

/// The accumulation pass: fur shells and fins into the OIT targets.
pub const ACCUM: Pass = Pass::new("fur-oit");
/// The composite pass: the OIT resolve over the image, then the alpha objects.
pub const COMPOSITE: Pass = Pass::new("composite");

/// Whether `plan` blends its fur by weighted blended OIT.
fn wanted(plan: &Plan) -> bool {
    !plan.fur.is_empty() && plan.fur_blend == FurBlend::Wboit && !plan.mode.is_debug()
}

/// The accumulation pass in words.
fn explain_accum(plan: &Plan) -> String {
    let (w, h) = plan.output;
    format!(
        "{w}×{h}: shells and fins of {} fur objects into weighted blended OIT (depth-weighted accumulation, revealage)",
        plan.fur.len()
    )
}

/// The composite pass in words.
fn explain_composite(plan: &Plan) -> String {
    let (w, h) = plan.output;
    format!(
        "{w}×{h}: OIT resolve over the image; {} alpha back to front",
        plan.alpha.len()
    )
}

/// Weighted blended OIT targets, at output size (a view's, owned by this feature).
#[derive(Debug)]
pub struct Oit {
    /// Σ colour·α·w, Σ α·w.
    pub accum: Target,
    /// Π (1 − α).
    pub reveal: Target,
    /// Both, for the composite pass.
    pub read: wgpu::BindGroup,
}

/// The OIT targets of a view of `spec`.
fn make_targets(r: &Renderer, spec: &TargetSpec, owned: &mut Owned) {
    let device = &r.gpu.device;
    let accum = Target::new(device, "oit accum", spec.output, r.gpu.accum_format);
    let reveal = Target::new(device, "oit reveal", spec.output, REVEAL_FORMAT);
    let views = [&accum.view, &reveal.view].map(wgpu::BindingResource::TextureView);
    let read = r.group("oit", &LAYOUT, &views);
    owned.insert(Oit {
        accum,
        reveal,
        read,
    });
}

/// The view's OIT targets, or the error `pass` reports without them.
fn oit<'a>(f: &Frame<'a>, pass: Pass) -> Result<&'a Oit, MissingInput> {
    f.targets.owned.need(pass.name(), "the OIT targets")
}

/// The shading of the alpha objects the composite draws: the material or forward shader.
fn alpha_shade(f: &Frame<'_>) -> Shade {
    let lit = shading::object_lighting(f.plan);
    Shade {
        shared: Shared::Shading,
        pass: COMPOSITE,
        lit,
        object: match lit {
            Lighting::Inferred => Box::new(super::material::pipeline),
            Lighting::Forward => super::forward::for_view(f),
        },
    }
}

fn keep_depth<'a>(f: &Frame<'a>) -> Option<Depth<'a>> {
    Some(Depth {
        view: &f.targets.depth.view,
        format: f.targets.depth.format,
        load: wgpu::LoadOp::Load,
    })
}

/// Fur shells and fins into the OIT targets.
pub fn accum_pass<'a>(f: &Frame<'a>) -> Result<Recipe<'a>, MissingInput> {
    let oit = oit(f, ACCUM)?;
    let target = |t: &'a Target, clear| Color {
        view: &t.view,
        format: t.format,
        load: wgpu::LoadOp::Clear(clear),
    };
    let mut r = Recipe::new(
        ACCUM,
        vec![
            target(&oit.accum, wgpu::Color::TRANSPARENT),
            target(&oit.reveal, wgpu::Color::WHITE),
        ],
        keep_depth(f),
    );
    let lighting = shading::object_lighting(f.plan);
    let (_, fur_light) = shading::lighting(f, lighting);
    f.bind_frame(&mut r, Res::Output);
    r.bind(slot::LIGHTING, fur_light.0, fur_light.1);
    if lighting == Lighting::Forward {
        crate::lighting::bind(f, &mut r, ACCUM.name())?;
    }
    fur::layers(f, &mut r, ACCUM.name(), lighting, Blend::Wboit)?;
    Ok(r)
}

/// Resolves the OIT accumulation over the image, then draws the alpha objects.
pub fn composite_pass<'a>(f: &Frame<'a>) -> Result<Recipe<'a>, MissingInput> {
    let oit = oit(f, COMPOSITE)?;
    let mut r = Recipe::new(
        COMPOSITE,
        vec![Color {
            view: f.output.view,
            format: f.output.format,
            load: wgpu::LoadOp::Load,
        }],
        keep_depth(f),
    );
    r.pipeline(pipeline());
    r.bind(slot_composite::OIT, &oit.read, None);
    r.push(Step::Draw(0..3, 0..1));
    let shade = alpha_shade(f);
    if shade.lit == Lighting::Forward {
        crate::lighting::bind(f, &mut r, COMPOSITE.name())?;
    }
    alpha::draw(f, &mut r, &shade)?;
    Ok(r)
}
