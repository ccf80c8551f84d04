//! Revie's deferred fur (§2.3–2.4) with Lengyel's fins. In the geometry pass, pass 1 draws
//! each fur object's base mesh with the grain normal (Listing 2.5) and pass 2 its outer
//! shell stippled into the top-left pixel of each 2×2 cell with rim normals (Listings 2.1,
//! 2.3). The obliteration pass (§2.4.4) writes the composition copy of the L-buffer and DSF
//! buffer with those texels replaced, which ordinary materials read. At output resolution the
//! base mesh is drawn opaque, then N shells in one instanced draw and the silhouette fins,
//! lit from the L-buffer at root and tip (or per light, forward), blended over or into the
//! OIT targets.

use crate::assets::Uploads;
use crate::draw::{
    MissingInput, fur_vertex_layout, object_blends, object_depth, slot, vertex_layout,
};
use crate::feature::{Build, DrawDesc, Feature, Frame, KnobDesc, PassDesc, Phase, Shade, Shared};
use crate::knobs::spec;
use crate::layout::{self, LayoutDesc};
use crate::pass::Pass;
use crate::plan::Plan;
use crate::recipe::{Color, Recipe, Step};
use crate::renderer::{Blend, ComputeDesc, PipelineDesc, PipelineSpec};
use crate::scene::{FurBlend, FurCoverage};
use crate::shaders::{Coverage, Entry, Lighting, ShaderDesc};
use crate::shading;
use crate::uniforms::FinInstance;

use super::lights;
use crate::lighting;

/// Bind-group slots of obliterate.wgsl.
pub mod obliterate_slot {
    /// The L-buffer and DSF buffer read.
    pub const SOURCE: u32 = 0;
    /// Which IDs are outer shells.
    pub const SHELL_TABLE: u32 = 1;
}

const FIN_ATTRIBUTES: [wgpu::VertexAttribute; 11] = wgpu::vertex_attr_array![
    0 => Float32x3, 1 => Float32x3, 2 => Float32x3, 3 => Float32x3, 4 => Float32x4,
    5 => Float32x4, 6 => Float32x3, 7 => Float32x3, 8 => Float32x2, 9 => Uint32,
    10 => Float32x3
];

/// The fin instance buffer: one [`FinInstance`] per quad (`FinIn` in fins.wgsl).
pub fn fin_layout() -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: size_of::<FinInstance>() as u64,
        step_mode: wgpu::VertexStepMode::Instance,
        attributes: &FIN_ATTRIBUTES,
    }
}

/// The fur's textures, as the asset cache binds them.
pub const LAYOUT: LayoutDesc = layout::FUR_TEXTURES;

/// Fur geometry pass 1: the base mesh with grain normals (Revie §2.4.2).
pub const BASE: ShaderDesc = ShaderDesc {
    entry: Entry::Render("vs_base", "fs_base"),
    ..ShaderDesc::render("fur_gbuffer.wgsl")
};
/// Fur geometry pass 2: the stippled outer shell with rim normals.
pub const OUTER: ShaderDesc = ShaderDesc {
    entry: Entry::Render("vs_outer", "fs_outer"),
    ..ShaderDesc::render("fur_gbuffer.wgsl")
};
/// Stipple obliteration into the composition copy (§2.4.4).
pub const OBLITERATE: ShaderDesc = ShaderDesc::fullscreen("obliterate.wgsl", "fs_main");
/// Compute: comb directions from tangent frames (the GPU half of `pelt_geom::frame`).
pub const TANGENT_FRAMES: ComputeDesc = ComputeDesc {
    shader: ShaderDesc::compute("tangent_frames.wgsl"),
    groups: &[layout::STORAGE],
};
/// Compute: fin records decoded through the index list (the GPU half of
/// `pelt_io::topology::fin_geometry`).
pub const FIN_RECORDS: ComputeDesc = ComputeDesc {
    shader: ShaderDesc::compute("fin_records.wgsl"),
    groups: &[layout::STORAGE, layout::STORAGE],
};

/// The shader def that composes a fur layer shader with the forward lighting chunk
/// (`pelt::fur_light_forward`: Kajiya-Kay per light) instead of the L-buffer's.
const FORWARD_LIGHT: &[(&str, u32)] = &[("FORWARD_LIGHT", 1)];

/// [`FORWARD_LIGHT`] reading the shadow cubes too (a view with a shadow-casting light).
const FORWARD_SHADOWED: &[(&str, u32)] = &[("FORWARD_LIGHT", 1), ("SHADOWS", 1)];

/// [`FORWARD_SHADOWED`] reading the fur's opacity layers too.
const FORWARD_SHADOWED_FUR: &[(&str, u32)] =
    &[("FORWARD_LIGHT", 1), ("SHADOWS", 1), ("FUR_SHADOWS", 1)];

/// `desc`, a forward-lit layer pipeline, reading the shadow cubes (at
/// `lighting::SLOT`, which the pass binds), and with `fur` the fur's opacity layers.
pub fn shadowed(mut desc: PipelineDesc, fur: bool) -> PipelineDesc {
    desc.shader = desc.shader.with_defs(if fur {
        FORWARD_SHADOWED_FUR
    } else {
        FORWARD_SHADOWED
    });
    desc.spec.groups.push(lighting::LAYOUT);
    desc
}

/// The layer pipeline `f`'s view needs: forward-lit layers read the shadow cubes where a
/// light of the view casts shadows, and the opacity layers where its fur casts, and leave
/// `light_reach`'s branch on the kind out where no light is directional.
fn for_view(f: &Frame<'_>, lighting: Lighting, desc: PipelineDesc) -> PipelineDesc {
    if lighting == Lighting::Inferred {
        return desc;
    }
    let desc = lights::suns_for_view(f, desc);
    if lighting::any(f) {
        shadowed(desc, lighting::fur_casts(f))
    } else {
        desc
    }
}

/// Binds what forward-lit layers read in a deferred pass: the light array and, where a
/// light casts shadows, the shadow cubes.
fn bind_forward<'a>(
    f: &Frame<'a>,
    r: &mut Recipe<'a>,
    pass: &'static str,
) -> Result<(), MissingInput> {
    let (group, offset) = shading::lighting(f, Lighting::Forward).1;
    r.bind(slot::LIGHTING, group, offset);
    if lighting::any(f) {
        lighting::bind(f, r, pass)?;
    }
    Ok(())
}

/// The shells (instance 0: the base mesh), lit by `lighting`.
pub const fn shells(lighting: Lighting) -> ShaderDesc {
    match lighting {
        Lighting::Inferred => ShaderDesc::render("shells.wgsl"),
        Lighting::Forward => ShaderDesc::render("shells.wgsl").with_defs(FORWARD_LIGHT),
    }
}

/// The silhouette fins, lit by `lighting`.
pub const fn fins(lighting: Lighting) -> ShaderDesc {
    match lighting {
        Lighting::Inferred => ShaderDesc::render("fins.wgsl"),
        Lighting::Forward => ShaderDesc::render("fins.wgsl").with_defs(FORWARD_LIGHT),
    }
}

/// A fur geometry-pass pipeline (`shader`: [`BASE`] or [`OUTER`]).
pub fn gbuffer_pipeline(shader: ShaderDesc) -> PipelineDesc {
    PipelineDesc {
        shader,
        spec: PipelineSpec {
            groups: vec![layout::FRAME, layout::OBJECT],
            vertex_buffers: vec![vertex_layout(), fur_vertex_layout()],
            blends: vec![None, None],
            depth: Some((true, wgpu::CompareFunction::Less)),
            ..PipelineSpec::default()
        },
    }
}

/// The obliteration pipeline.
pub fn obliterate_pipeline() -> PipelineDesc {
    PipelineDesc {
        shader: OBLITERATE,
        spec: PipelineSpec {
            groups: vec![layout::TEXTURES, layout::SHELL_TABLE],
            blends: vec![None, None],
            ..PipelineSpec::default()
        },
    }
}

/// What a shell or fin pipeline differs by.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layer {
    /// Shells with this coverage code.
    Shells(Coverage),
    /// Fins.
    Fins,
}

/// The pipeline of shells or fins lit by `lighting`, drawn with `blend`.
pub fn layer_pipeline(layer: Layer, lighting: Lighting, blend: Blend) -> PipelineDesc {
    let shells = matches!(layer, Layer::Shells(_));
    PipelineDesc {
        shader: match layer {
            Layer::Shells(_) => self::shells(lighting),
            Layer::Fins => fins(lighting),
        },
        spec: PipelineSpec {
            groups: vec![
                layout::FRAME,
                layout::OBJECT,
                match lighting {
                    Lighting::Inferred => layout::TEXTURES,
                    Lighting::Forward => layout::LIGHT_ARRAY,
                },
                LAYOUT,
            ],
            vertex_buffers: if shells {
                vec![vertex_layout(), fur_vertex_layout()]
            } else {
                vec![fin_layout()]
            },
            blends: object_blends(blend),
            depth: object_depth(blend),
            // Blended shells show only their outer side (the far side's shells stick out
            // behind the silhouette, where they would blend in the wrong order).
            cull: (shells && blend != Blend::None).then_some(wgpu::Face::Back),
            front_face: wgpu::FrontFace::Ccw,
            // One fragment entry point: straight alpha, or with WBOIT the OIT outputs; the
            // coverage code the object needs (the strand-resolving taps only where the plan
            // says a pixel may resolve strands).
            constants: [
                (blend == Blend::Wboit).then_some(("WBOIT", 1.0)),
                match layer {
                    Layer::Shells(c) if c != Coverage::Medium => Some(("COVERAGE", c.constant())),
                    _ => None,
                },
                // Where the taps give way to the medium: the plan's threshold, one home.
                shells.then_some((
                    "RESOLVED_BELOW",
                    f64::from(pelt_scene::footprint::RESOLVED_BELOW),
                )),
            ]
            .into_iter()
            .flatten()
            .collect(),
            writes: None,
        },
    }
}

fn pipelines() -> Vec<PipelineDesc> {
    let mut out = vec![
        gbuffer_pipeline(BASE),
        gbuffer_pipeline(OUTER),
        obliterate_pipeline(),
    ];
    for lighting in [Lighting::Inferred, Lighting::Forward] {
        for blend in [Blend::None, Blend::Over, Blend::Wboit] {
            for coverage in [Coverage::Medium, Coverage::Resolved, Coverage::Binary] {
                out.push(layer_pipeline(Layer::Shells(coverage), lighting, blend));
            }
            out.push(layer_pipeline(Layer::Fins, lighting, blend));
        }
    }
    for blend in [Blend::None, Blend::Over, Blend::Wboit] {
        for coverage in [Coverage::Medium, Coverage::Resolved, Coverage::Binary] {
            let desc = layer_pipeline(Layer::Shells(coverage), Lighting::Forward, blend);
            out.push(lights::without_suns(desc));
        }
        out.push(lights::without_suns(layer_pipeline(
            Layer::Fins,
            Lighting::Forward,
            blend,
        )));
    }
    for blend in [Blend::None, Blend::Over, Blend::Wboit] {
        for fur in [false, true] {
            for coverage in [Coverage::Medium, Coverage::Resolved, Coverage::Binary] {
                let desc = layer_pipeline(Layer::Shells(coverage), Lighting::Forward, blend);
                out.push(shadowed(desc, fur));
            }
            let fins = layer_pipeline(Layer::Fins, Lighting::Forward, blend);
            out.push(shadowed(fins, fur));
        }
    }
    out
}

/// Revie's fur's feature.
pub const FEATURE: Feature = Feature {
    knobs: &[
        KnobDesc::of(&spec::SHELLS),
        KnobDesc::of(&spec::FINS),
        KnobDesc::of(&spec::FUR_COVERAGE),
        KnobDesc::of(&spec::FUR_LIGHTING),
        KnobDesc::of(&spec::TEXTURE_SIZE),
        KnobDesc::of(&spec::HEIGHT_BITS),
        KnobDesc::of(&spec::QUANTIZE),
    ],
    pipelines,
    compute: &[TANGENT_FRAMES, FIN_RECORDS],
    passes: &[PassDesc {
        after: &[Pass::new("light")],
        at_lbuffer: true,
        ..PassDesc::new(
            OBLITERATE_PASS,
            Build::One(obliterate_pass),
            Plan::deferred_fur,
            explain_obliterate,
        )
    }],
    draws: &[
        DrawDesc {
            into: Shared::Geometry,
            phase: Phase::FurBase,
            draw: |f, r, _| gbuffer(f, r),
        },
        DrawDesc {
            into: Shared::Shading,
            phase: Phase::FurBase,
            draw: shade_base,
        },
        DrawDesc {
            into: Shared::Shading,
            phase: Phase::FurLayers,
            draw: shade_layers,
        },
    ],
    uploads: Some(|plan, k, _| Uploads {
        fur: plan
            .objects
            .iter()
            .any(|(o, _)| o.mesh == k && o.fur.is_some()),
        groups: false,
    }),
    ..Feature::named("fur")
};

/// The fur's base mesh in the shading pass, lit as fur.
fn shade_base<'a>(f: &Frame<'a>, r: &mut Recipe<'a>, s: &Shade) -> Result<(), MissingInput> {
    if f.plan.fur.is_empty() {
        return Ok(());
    }
    let (group, offset) = shading::lighting(f, s.lit).1;
    r.bind(slot::LIGHTING, group, offset);
    base(f, r, s.pass.name(), s.lit)
}

/// The shells and fins far to near, blended over, unless the strands are drawn instead or
/// the OIT passes take them.
fn shade_layers<'a>(f: &Frame<'a>, r: &mut Recipe<'a>, s: &Shade) -> Result<(), MissingInput> {
    let strands = f.plan.mode == crate::plan::Mode::Strands;
    if f.plan.fur.is_empty() || strands || f.plan.fur_blend == FurBlend::Wboit {
        return Ok(());
    }
    let (group, offset) = shading::lighting(f, s.lit).1;
    r.bind(slot::LIGHTING, group, offset);
    layers(f, r, s.pass.name(), s.lit, Blend::Over)
}

/// Geometry pass: base meshes, then stippled outer shells (Revie §2.4.2).
pub fn gbuffer<'a>(f: &Frame<'a>, r: &mut Recipe<'a>) -> Result<(), MissingInput> {
    if f.plan.fur.is_empty() {
        return Ok(());
    }
    let pass = r.pass.name();
    for shader in [BASE, OUTER] {
        r.pipeline(gbuffer_pipeline(shader));
        for &k in &f.plan.fur {
            let (mesh, _) = f.bind_fur(r, pass, k)?;
            r.push(Step::DrawIndexed(0..mesh.count, 0..1));
        }
    }
    Ok(())
}

/// The obliteration pass (Revie §2.4.4).
pub const OBLITERATE_PASS: Pass = Pass::new("obliterate");

/// The obliteration pass in words.
fn explain_obliterate(plan: &Plan) -> String {
    let (lw, lh) = plan.lbuffer.unwrap_or(plan.output);
    format!(
        "{lw}×{lh}: composition copy of the L-buffer and DSF buffer with the outer-shell stipple texels replaced by base-mesh neighbours"
    )
}

/// Stipple obliteration (Revie §2.4.4): the composition copy of the L-buffer and DSF buffer,
/// with every outer-shell texel replaced by a neighbour of its 2×2 cell.
pub fn obliterate_pass<'a>(f: &Frame<'a>) -> Result<Recipe<'a>, MissingInput> {
    let c = f.targets.composition.as_ref().ok_or_else(|| MissingInput {
        pass: OBLITERATE_PASS.name(),
        what: "the composition copy of the L-buffer".into(),
    })?;
    let clear = |t: &'a crate::targets::Target| Color {
        view: &t.view,
        format: t.format,
        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
    };
    let mut r = Recipe::new(OBLITERATE_PASS, vec![clear(&c.light), clear(&c.dsf)], None);
    r.pipeline(obliterate_pipeline());
    r.bind(obliterate_slot::SOURCE, &f.targets.lbuffer_read, None);
    r.bind(obliterate_slot::SHELL_TABLE, f.data.shell_table(), None);
    r.push(Step::Draw(0..3, 0..1));
    Ok(r)
}

/// Material pass: each fur object's base mesh, opaque (shell instance 0).
pub fn base<'a>(
    f: &Frame<'a>,
    r: &mut Recipe<'a>,
    pass: &'static str,
    lighting: Lighting,
) -> Result<(), MissingInput> {
    r.pipeline(for_view(
        f,
        lighting,
        layer_pipeline(Layer::Shells(Coverage::Medium), lighting, Blend::None),
    ));
    for &k in &f.plan.fur {
        let (mesh, fur) = f.bind_fur(r, pass, k)?;
        Frame::draw_fur_parts(r, mesh, fur, 0..1);
    }
    Ok(())
}

/// Every fur object's shells (far objects first, inner shells first) and fins, with
/// `blend`. The frame and lighting groups must be bound.
pub fn layers<'a>(
    f: &Frame<'a>,
    r: &mut Recipe<'a>,
    pass: &'static str,
    lighting: Lighting,
    blend: Blend,
) -> Result<(), MissingInput> {
    for &k in &f.plan.fur {
        let planned = f.plan.objects[k].fur;
        // Bald fur draws its skin alone (in the base pass).
        let n = planned.filter(|p| !p.bald()).map_or(0, |p| p.shells);
        if n == 0 {
            continue;
        }
        let coverage = match planned {
            Some(p) if p.coverage == FurCoverage::Binary => Coverage::Binary,
            Some(p) if p.resolved => Coverage::Resolved,
            _ => Coverage::Medium,
        };
        // With the eye within the fur, the shells above it have no L-buffer sample: its
        // shells are lit forward, as the forward reference lights them.
        let inside = lighting == Lighting::Inferred && planned.is_some_and(|p| p.eye_inside);
        let lit = if inside { Lighting::Forward } else { lighting };
        let desc = layer_pipeline(Layer::Shells(coverage), lit, blend);
        r.pipeline(for_view(f, lit, desc));
        if inside {
            bind_forward(f, r, pass)?;
        }
        let (mesh, fur) = f.bind_fur(r, pass, k)?;
        Frame::draw_fur_parts(r, mesh, fur, 1..n + 1);
        if inside {
            let (group, offset) = shading::lighting(f, lighting).1;
            r.bind(slot::LIGHTING, group, offset);
        }
    }
    let with_fins: Vec<usize> = f
        .plan
        .fur
        .iter()
        .copied()
        .filter(|&k| f.plan.objects[k].fur.is_some_and(|p| p.fins))
        .collect();
    if with_fins.is_empty() {
        return Ok(());
    }
    let desc = layer_pipeline(Layer::Fins, lighting, blend);
    r.pipeline(for_view(f, lighting, desc));
    for k in with_fins {
        let mesh = f.mesh(pass, k)?;
        let fur = mesh.fur.as_ref();
        let Some((fins, fur)) = fur.and_then(|x| x.fins.as_ref().map(|b| (b, x))) else {
            // The plan turns fins on only for assets with fin edges.
            return Err(MissingInput {
                pass,
                what: format!(
                    "the fin edges of objects[{}] on the GPU",
                    f.plan.objects[k].scene_index
                ),
            });
        };
        f.bind_object(r, k);
        // Fins carry their own colour under the fur (FinInstance::albedo): any material's
        // group gives the heightfield and fin texture.
        r.bind(slot::FUR, &fur.textures[0], None);
        r.push(Step::Vertices(crate::draw::vertex_slot::INSTANCES, fins));
        r.push(Step::Draw(0..6, 0..fur.fin_count));
    }
    Ok(())
}
