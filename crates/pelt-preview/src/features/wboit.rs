//! Weighted blended order-independent transparency (McGuire & Bavoil 2013, eq. 7 with view
//! depth; Frantzen's steps 2 and 3) for fur: shells and fins accumulate Σ colour·α·w and
//! Σ α·w additively and the revealage Π (1 − α) multiplicatively, depth-tested against the
//! image's opaque depth without writing it; the composite divides and blends the result over
//! the image, then draws the alpha objects.

use crate::features::registry::{Build, Feature, PassDesc};
use crate::features::{Frame, MissingInput, alpha, fur, material, slot};
use crate::frame_data::Res;
use crate::layout::{self, LayoutDesc};
use crate::plan::Pass;
use crate::recipe::{Color, Depth, Recipe, Step};
use crate::renderer::{Blend, PipelineDesc, PipelineSpec};
use crate::shaders::ShaderDesc;

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

/// Blends of the two OIT targets: additive accumulation, revealage dst × (1 − src).
pub fn blends() -> Vec<Option<wgpu::BlendState>> {
    let reveal = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::Zero,
        dst_factor: wgpu::BlendFactor::OneMinusSrc,
        operation: wgpu::BlendOperation::Add,
    };
    vec![
        Some(super::ADD),
        Some(wgpu::BlendState {
            color: reveal,
            alpha: reveal,
        }),
    ]
}

/// composite.wgsl.
pub const SHADER: ShaderDesc = ShaderDesc::fullscreen(
    &["common.wgsl", "fullscreen.wgsl", "composite.wgsl"],
    "fs_main",
);

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
    name: "wboit",
    explain: "fur layers accumulated order-independently, then composited",
    pipelines: || vec![pipeline()],
    compute: &[],
    passes: &[
        PassDesc::new(Pass::FurAccum, Build::One(accum_pass)),
        PassDesc::new(Pass::Composite, Build::One(composite_pass)),
    ],
};

fn missing(pass: Pass) -> MissingInput {
    MissingInput {
        pass: pass.name(),
        what: "the OIT targets".into(),
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
    let oit = f
        .targets
        .oit
        .as_ref()
        .ok_or_else(|| missing(Pass::FurAccum))?;
    let target = |t: &'a crate::targets::Target, clear| Color {
        view: &t.view,
        format: t.format,
        load: wgpu::LoadOp::Clear(clear),
    };
    let mut r = Recipe::new(
        Pass::FurAccum,
        vec![
            target(&oit.accum, wgpu::Color::TRANSPARENT),
            target(&oit.reveal, wgpu::Color::WHITE),
        ],
        keep_depth(f),
    );
    let lighting = material::object_lighting(f.plan);
    let (_, fur_light) = material::lighting(f, lighting);
    f.bind_frame(&mut r, Res::Output);
    r.bind(slot::LIGHTING, fur_light.0, fur_light.1);
    fur::layers(f, &mut r, Pass::FurAccum.name(), lighting, Blend::Wboit)?;
    Ok(r)
}

/// Resolves the OIT accumulation over the image, then draws the alpha objects.
pub fn composite_pass<'a>(f: &Frame<'a>) -> Result<Recipe<'a>, MissingInput> {
    let oit = f
        .targets
        .oit
        .as_ref()
        .ok_or_else(|| missing(Pass::Composite))?;
    let mut r = Recipe::new(
        Pass::Composite,
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
    let lit = material::object_lighting(f.plan);
    alpha::draw(f, &mut r, Pass::Composite.name(), lit)?;
    Ok(r)
}
