//! The debug views: every object's surface, unlit, in the colours of what the bake wrote.
//! `debug-groups` shows the normal groups the DSF tells apart (Kircher & Lawrance §3.1), each
//! in the colour of its class, neighbours always distinct ([`pelt_scene::debug`] colours the
//! groups on the CPU); `debug-comb` shows the comb decoded into the asset's space as the fur
//! passes decode it (Revie §2.4.1), direction as colour and length as brightness. Fur draws
//! as its base mesh, mirrors and glass as plain surfaces: the views show the asset, not the
//! shading.

use crate::assets::Uploads;
use crate::draw::{MissingInput, fur_vertex_layout, vertex_layout, vertex_slot};
use crate::feature::{Build, Feature, Frame, PassDesc};
use crate::frame_data::Res;
use crate::layout;
use crate::pass::Pass;
use crate::plan::{DebugView, Mode, Plan};
use crate::recipe::{Color, Depth, Recipe, Step};
use crate::renderer::{PipelineDesc, PipelineSpec};
use crate::shaders::{Entry, ShaderDesc};

/// The groups view: the mesh's vertices and each vertex's group class.
pub const GROUPS: ShaderDesc = entries("vs_groups", "fs_groups");
/// The comb view: the mesh's vertices and its fur vertices.
pub const COMB: ShaderDesc = entries("vs_comb", "fs_comb");
/// A surface with nothing to show (no comb), dark grey.
pub const PLAIN: ShaderDesc = entries("vs_plain", "fs_plain");

const fn entries(vs: &'static str, fs: &'static str) -> ShaderDesc {
    ShaderDesc {
        entry: Entry::Render(vs, fs),
        ..ShaderDesc::render("debug.wgsl")
    }
}

/// The class buffer's layout (vertex buffer [`vertex_slot::FUR`] of the groups view): one
/// `u32` per vertex at location 4.
const CLASS_ATTRIBUTES: [wgpu::VertexAttribute; 1] = wgpu::vertex_attr_array![4 => Uint32];

fn class_layout() -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: size_of::<u32>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &CLASS_ATTRIBUTES,
    }
}

/// The pipeline of `shader` (one of [`GROUPS`], [`COMB`], [`PLAIN`]).
pub fn pipeline(shader: ShaderDesc) -> PipelineDesc {
    let mut vertex_buffers = vec![vertex_layout()];
    if shader == GROUPS {
        vertex_buffers.push(class_layout());
    } else if shader == COMB {
        vertex_buffers.push(fur_vertex_layout());
    }
    PipelineDesc {
        shader,
        spec: PipelineSpec {
            groups: vec![layout::FRAME, layout::OBJECT],
            vertex_buffers,
            blends: vec![None],
            depth: Some((true, wgpu::CompareFunction::Less)),
            ..PipelineSpec::default()
        },
    }
}

/// The debug pass.
pub const PASS: Pass = Pass::new("debug");

/// The debug views' feature.
pub const FEATURE: Feature = Feature {
    pipelines: || [GROUPS, COMB, PLAIN].map(pipeline).to_vec(),
    passes: &[PassDesc::new(
        PASS,
        Build::One(pass),
        |plan| plan.mode.is_debug(),
        explain,
    )],
    uploads: Some(|plan, _, mesh| match plan.mode {
        Mode::Debug(DebugView::Comb) => Uploads {
            fur: mesh.fur.is_some(),
            groups: false,
        },
        Mode::Debug(DebugView::Groups) => Uploads {
            fur: false,
            groups: true,
        },
        _ => Uploads::default(),
    }),
    ..Feature::named("debug")
};

/// The debug pass in words.
fn explain(plan: &Plan) -> String {
    let (w, h) = plan.output;
    format!(
        "{w}×{h}: {} objects unlit, {}",
        plan.shown,
        match plan.mode {
            Mode::Debug(DebugView::Comb) => "the decoded comb as colour, its length as brightness",
            _ => "each normal group in its class's colour, neighbours distinct",
        }
    )
}

/// The debug pass: every planned object, nearest first within each kind, into the output.
pub fn pass<'a>(f: &Frame<'a>) -> Result<Recipe<'a>, MissingInput> {
    let Mode::Debug(view) = f.plan.mode else {
        return Err(MissingInput {
            pass: PASS.name(),
            what: "a debug mode (debug-groups or debug-comb)".into(),
        });
    };
    let mut r = Recipe::new(
        PASS,
        vec![Color {
            view: f.output.view,
            format: f.output.format,
            load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
        }],
        Some(Depth {
            view: &f.targets.depth.view,
            format: f.targets.depth.format,
            load: wgpu::LoadOp::Clear(1.0),
        }),
    );
    f.bind_frame(&mut r, Res::Output);
    let p = f.plan;
    for &k in [&p.opaque, &p.reflective, &p.fur, &p.alpha]
        .into_iter()
        .flatten()
    {
        let mesh = f.mesh(PASS.name(), k)?;
        let second = match view {
            DebugView::Groups => Some((
                GROUPS,
                mesh.groups.as_ref().ok_or_else(|| MissingInput {
                    pass: PASS.name(),
                    what: format!(
                        "the normal-group classes of objects[{}]",
                        p.objects[k].scene_index
                    ),
                })?,
            )),
            DebugView::Comb => mesh.fur.as_ref().map(|fur| (COMB, &fur.vertices)),
        };
        f.bind_object(&mut r, k);
        r.push(Step::Vertices(vertex_slot::MESH, &mesh.vertices));
        match second {
            Some((shader, buffer)) => {
                r.pipeline(pipeline(shader));
                r.push(Step::Vertices(vertex_slot::FUR, buffer));
            }
            None => r.pipeline(pipeline(PLAIN)),
        }
        r.front(f.front_face(k));
        r.push(Step::Indices(&mesh.indices));
        r.push(Step::DrawIndexed(0..mesh.count, 0..1));
    }
    Ok(r)
}
