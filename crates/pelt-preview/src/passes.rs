//! The passes, each a function from its inputs to the target it writes (kajiya's
//! `renderers/*.rs` style): geometry → [`GBuffer`], light (reads the G-buffer) → [`LBuffer`],
//! obliterate (reads the L-buffer and DSF buffer) → [`Composition`], material (reads the
//! composition, the fur reads the original) → [`Output`], the forward reference →
//! [`Output`], fur OIT accumulation → [`Oit`], and its composite → [`Output`]. Kircher &
//! Lawrance §2.1–2.3 and §4; Revie §2.4; McGuire & Bavoil's weighted blended OIT.

use crate::draw::{Composition, DrawData, GBuffer, LBuffer, Oit, Output};
use crate::plan::{Mode, PlannedObject};
use crate::renderer::{Blend, PipelineKey, Renderer};
use crate::scene::{FurBlend, Sky};
use crate::shaders::{Lighting, Shader};
use crate::uniforms::UNIFORM_STRIDE;

/// Frame uniform slots in [`DrawData::frame`].
const FRAME_LBUFFER: u32 = 0;
const FRAME_OUTPUT: u32 = UNIFORM_STRIDE as u32;

/// Where a pass writes its GPU timestamps, if anywhere.
pub type Timestamps<'a> = Option<wgpu::RenderPassTimestampWrites<'a>>;

fn draw_objects(pass: &mut wgpu::RenderPass<'_>, d: &DrawData, order: &[usize]) {
    for &k in order {
        let o: &PlannedObject = &d.plan.objects[k];
        let mesh = &d.meshes[o.mesh];
        pass.set_bind_group(1, &d.objects, &[DrawData::object_offset(k)]);
        pass.set_vertex_buffer(0, mesh.vertices.slice(..));
        pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..mesh.count, 0, 0..1);
    }
}

fn color_attachment(
    view: &wgpu::TextureView,
    clear: wgpu::Color,
) -> Option<wgpu::RenderPassColorAttachment<'_>> {
    color_load(view, wgpu::LoadOp::Clear(clear))
}

fn color_load(
    view: &wgpu::TextureView,
    load: wgpu::LoadOp<wgpu::Color>,
) -> Option<wgpu::RenderPassColorAttachment<'_>> {
    Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load,
            store: wgpu::StoreOp::Store,
        },
    })
}

fn depth_attachment(
    view: &wgpu::TextureView,
) -> Option<wgpu::RenderPassDepthStencilAttachment<'_>> {
    depth_load(view, wgpu::LoadOp::Clear(1.0))
}

fn depth_load(
    view: &wgpu::TextureView,
    load: wgpu::LoadOp<f32>,
) -> Option<wgpu::RenderPassDepthStencilAttachment<'_>> {
    Some(wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load,
            store: wgpu::StoreOp::Store,
        }),
        stencil_ops: None,
    })
}

/// Background of the output (linear).
pub const BACKGROUND: wgpu::Color = wgpu::Color {
    r: 0.02,
    g: 0.022,
    b: 0.028,
    a: 1.0,
};

/// Geometry pass (§2.1): every object at L-buffer resolution into normals and DSF data; alpha
/// objects only into their stipple pattern (§4).
pub fn geometry_pass(
    enc: &mut wgpu::CommandEncoder,
    r: &Renderer,
    d: &DrawData,
    out: &GBuffer,
    ts: Timestamps<'_>,
) {
    let empty = wgpu::Color {
        r: 0.0,
        g: 0.0,
        b: 0.0,
        a: 0.0,
    };
    // The DSF clear marks texels no surface wrote: depth code 65535, ID 0.
    let dsf_empty = wgpu::Color {
        r: 65535.0,
        g: 0.0,
        b: 0.0,
        a: 0.0,
    };
    let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("geometry"),
        color_attachments: &[
            color_attachment(&out.normals.view, empty),
            color_attachment(&out.dsf.view, dsf_empty),
        ],
        depth_stencil_attachment: depth_attachment(&out.depth.view),
        timestamp_writes: ts,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_bind_group(0, &d.frame, &[FRAME_LBUFFER]);
    let gbuffer = r.pipeline(PipelineKey {
        shader: Shader::GBuffer,
        blend: Blend::None,
    });
    if !d.plan.opaque.is_empty() {
        pass.set_pipeline(&gbuffer);
        draw_objects(&mut pass, d, &d.plan.opaque);
    }
    // Revie §2.4.2: pass 1, the fur's base mesh; pass 2, its stippled outer shell.
    for shader in [Shader::FurBase, Shader::FurOuter] {
        if d.plan.fur.is_empty() {
            break;
        }
        pass.set_pipeline(&r.pipeline(PipelineKey {
            shader,
            blend: Blend::None,
        }));
        for &k in &d.plan.fur {
            let o = &d.plan.objects[k];
            let mesh = &d.meshes[o.mesh];
            let Some(fur) = &mesh.fur else { continue };
            pass.set_bind_group(1, &d.objects, &[DrawData::object_offset(k)]);
            pass.set_vertex_buffer(0, mesh.vertices.slice(..));
            pass.set_vertex_buffer(1, fur.vertices.slice(..));
            pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..mesh.count, 0, 0..1);
        }
    }
    if !d.plan.alpha.is_empty() {
        pass.set_pipeline(&gbuffer);
        draw_objects(&mut pass, d, &d.plan.alpha);
    }
}

/// Light pass (§2.2): the L-buffer starts at the ambient term; each light adds its diffuse
/// and specular over its scissor rectangle only.
pub fn light_pass(
    enc: &mut wgpu::CommandEncoder,
    r: &Renderer,
    d: &DrawData,
    g: &GBuffer,
    out: &LBuffer,
    ts: Timestamps<'_>,
) {
    let a = d.plan.ambient.as_dvec3();
    let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("light"),
        color_attachments: &[color_attachment(
            &out.light.view,
            wgpu::Color {
                r: a.x,
                g: a.y,
                b: a.z,
                a: 0.0,
            },
        )],
        depth_stencil_attachment: None,
        timestamp_writes: ts,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    debug_assert_eq!(g.size, out.size);
    pass.set_pipeline(&r.pipeline(PipelineKey {
        shader: Shader::Light,
        blend: Blend::None,
    }));
    pass.set_bind_group(0, &d.frame, &[FRAME_LBUFFER]);
    if let Some(read) = &d.gbuffer_read {
        pass.set_bind_group(1, read, &[]);
    }
    for (i, l) in d.plan.lights.iter().enumerate() {
        let [x0, y0, x1, y1] = l.rect;
        pass.set_scissor_rect(x0, y0, x1 - x0, y1 - y0);
        pass.set_bind_group(2, &d.light, &[(i as u64 * UNIFORM_STRIDE) as u32]);
        pass.draw(0..3, 0..1);
    }
}

/// Stipple obliteration (Revie §2.4.4): the composition copy of the L-buffer and DSF buffer,
/// with every outer-shell texel replaced by a neighbour of its 2×2 cell.
pub fn obliterate_pass(
    enc: &mut wgpu::CommandEncoder,
    r: &Renderer,
    d: &DrawData,
    out: &Composition,
    ts: Timestamps<'_>,
) {
    let Some(table) = &d.shell_table else { return };
    let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("obliterate"),
        color_attachments: &[
            color_attachment(&out.light.view, wgpu::Color::TRANSPARENT),
            color_attachment(&out.dsf.view, wgpu::Color::TRANSPARENT),
        ],
        depth_stencil_attachment: None,
        timestamp_writes: ts,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_pipeline(&r.pipeline(PipelineKey {
        shader: Shader::Obliterate,
        blend: Blend::None,
    }));
    pass.set_bind_group(0, &d.lbuffer_read, &[]);
    pass.set_bind_group(1, table, &[]);
    pass.draw(0..3, 0..1);
}

/// Material pass (§2.3, §3, §4; Revie §2.4.4): opaque objects front to back, each fur
/// object's base mesh, the sky, then (stipple blend) every fur object's shells and fins far
/// to near, and alpha objects back to front unless the OIT composite draws them.
pub fn material_pass(
    enc: &mut wgpu::CommandEncoder,
    r: &Renderer,
    d: &DrawData,
    out: &Output,
    ts: Timestamps<'_>,
) {
    shade(enc, r, d, out, ts, Shader::Material);
}

/// Forward reference: every object loops over every light at output resolution; fur is lit
/// per strand with Kajiya-Kay (Revie Listing 2.4).
pub fn forward_pass(
    enc: &mut wgpu::CommandEncoder,
    r: &Renderer,
    d: &DrawData,
    out: &Output,
    ts: Timestamps<'_>,
) {
    shade(enc, r, d, out, ts, Shader::Forward);
}

/// The shader ordinary objects are drawn with in this plan's mode.
fn object_shader(d: &DrawData) -> Shader {
    if d.plan.mode == Mode::Forward {
        Shader::Forward
    } else {
        Shader::Material
    }
}

/// What the object shader (Material or Forward) implies for the fur.
fn fur_lighting(shader: Shader) -> Lighting {
    if shader == Shader::Forward {
        Lighting::Forward
    } else {
        Lighting::Inferred
    }
}

/// Group 2 for `shader`'s objects, and for its fur.
fn light_groups(d: &DrawData, shader: Shader) -> (&wgpu::BindGroup, &wgpu::BindGroup) {
    if shader == Shader::Forward {
        (&d.light_array, &d.light_array)
    } else {
        (&d.material_read, &d.lbuffer_read)
    }
}

/// Draws fur object `k`'s shells `shells` (instance 0 is the base mesh) with `pipeline`.
fn draw_shells(
    pass: &mut wgpu::RenderPass<'_>,
    d: &DrawData,
    k: usize,
    shells: std::ops::Range<u32>,
) {
    let o = &d.plan.objects[k];
    let mesh = &d.meshes[o.mesh];
    let Some(fur) = &mesh.fur else { return };
    pass.set_bind_group(1, &d.objects, &[DrawData::object_offset(k)]);
    pass.set_bind_group(3, &fur.textures, &[]);
    pass.set_vertex_buffer(0, mesh.vertices.slice(..));
    pass.set_vertex_buffer(1, fur.vertices.slice(..));
    pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
    pass.draw_indexed(0..mesh.count, 0, shells);
}

/// Draws fur object `k`'s fins, if it has them.
fn draw_fins(pass: &mut wgpu::RenderPass<'_>, d: &DrawData, k: usize) {
    let o = &d.plan.objects[k];
    let mesh = &d.meshes[o.mesh];
    let (Some(fur), Some(f)) = (&mesh.fur, o.fur) else {
        return;
    };
    let Some(fins) = &fur.fins else { return };
    if !f.fins {
        return;
    }
    pass.set_bind_group(1, &d.objects, &[DrawData::object_offset(k)]);
    pass.set_bind_group(3, &fur.textures, &[]);
    pass.set_vertex_buffer(0, fins.slice(..));
    pass.draw(0..6, 0..fur.fin_count);
}

/// Every fur object's shells and fins, far first, with `blend`.
fn draw_fur_layers(
    pass: &mut wgpu::RenderPass<'_>,
    r: &Renderer,
    d: &DrawData,
    lighting: Lighting,
    blend: Blend,
) {
    pass.set_pipeline(&r.pipeline(PipelineKey {
        shader: Shader::Shells(lighting),
        blend,
    }));
    for &k in &d.plan.fur {
        let n = d.plan.objects[k].fur.map_or(0, |f| f.shells);
        draw_shells(pass, d, k, 1..n + 1);
    }
    if d.plan
        .fur
        .iter()
        .any(|&k| d.plan.objects[k].fur.is_some_and(|f| f.fins))
    {
        pass.set_pipeline(&r.pipeline(PipelineKey {
            shader: Shader::Fins(lighting),
            blend,
        }));
        for &k in &d.plan.fur {
            draw_fins(pass, d, k);
        }
    }
}

fn draw_alpha(pass: &mut wgpu::RenderPass<'_>, r: &Renderer, d: &DrawData, shader: Shader) {
    if d.plan.alpha.is_empty() {
        return;
    }
    pass.set_bind_group(0, &d.frame, &[FRAME_OUTPUT]);
    pass.set_bind_group(2, light_groups(d, shader).0, &[]);
    pass.set_pipeline(&r.pipeline(PipelineKey {
        shader,
        blend: Blend::Over,
    }));
    draw_objects(pass, d, &d.plan.alpha);
}

fn shade(
    enc: &mut wgpu::CommandEncoder,
    r: &Renderer,
    d: &DrawData,
    out: &Output,
    ts: Timestamps<'_>,
    shader: Shader,
) {
    let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(if shader == Shader::Forward {
            "forward"
        } else {
            "material"
        }),
        color_attachments: &[color_attachment(&out.color.view, BACKGROUND)],
        depth_stencil_attachment: depth_attachment(&out.depth.view),
        timestamp_writes: ts,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    let (objects_light, fur_light) = light_groups(d, shader);
    let lighting = fur_lighting(shader);
    pass.set_bind_group(0, &d.frame, &[FRAME_OUTPUT]);
    pass.set_bind_group(2, objects_light, &[]);
    if !d.plan.opaque.is_empty() {
        pass.set_pipeline(&r.pipeline(PipelineKey {
            shader,
            blend: Blend::None,
        }));
        draw_objects(&mut pass, d, &d.plan.opaque);
    }
    let has_fur = !d.plan.fur.is_empty();
    if has_fur {
        pass.set_bind_group(2, fur_light, &[]);
        pass.set_pipeline(&r.pipeline(PipelineKey {
            shader: Shader::Shells(lighting),
            blend: Blend::None,
        }));
        for &k in &d.plan.fur {
            draw_shells(&mut pass, d, k, 0..1);
        }
    }
    let sky = match d.plan.sky {
        Sky::None => None,
        Sky::Procedural => Some(Shader::SkyProcedural),
        Sky::Cubemap(_) => Some(Shader::SkyCube),
    };
    if let Some(sky) = sky {
        pass.set_pipeline(&r.pipeline(PipelineKey {
            shader: sky,
            blend: Blend::None,
        }));
        if let Some(g) = &d.sky {
            pass.set_bind_group(1, g, &[]);
        }
        pass.draw(0..3, 0..1);
    }
    let wboit = has_fur && d.plan.fur_blend == FurBlend::Wboit;
    if has_fur && !wboit {
        pass.set_bind_group(2, fur_light, &[]);
        draw_fur_layers(&mut pass, r, d, lighting, Blend::Over);
    }
    if !wboit {
        draw_alpha(&mut pass, r, d, shader);
    }
}

/// Fur shells and fins into the weighted blended OIT targets (McGuire & Bavoil; Frantzen's
/// step 2), depth-tested against the image's opaque depth without writing it.
pub fn fur_accum_pass(
    enc: &mut wgpu::CommandEncoder,
    r: &Renderer,
    d: &DrawData,
    oit: &Oit,
    ts: Timestamps<'_>,
) {
    let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("fur-oit"),
        color_attachments: &[
            color_attachment(&oit.accum.view, wgpu::Color::TRANSPARENT),
            color_attachment(&oit.reveal.view, wgpu::Color::WHITE),
        ],
        depth_stencil_attachment: depth_load(&d.output.depth.view, wgpu::LoadOp::Load),
        timestamp_writes: ts,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    let shader = object_shader(d);
    pass.set_bind_group(0, &d.frame, &[FRAME_OUTPUT]);
    pass.set_bind_group(2, light_groups(d, shader).1, &[]);
    draw_fur_layers(&mut pass, r, d, fur_lighting(shader), Blend::Wboit);
}

/// Resolves the OIT accumulation over the image, then draws the alpha objects.
pub fn composite_pass(
    enc: &mut wgpu::CommandEncoder,
    r: &Renderer,
    d: &DrawData,
    oit: &Oit,
    out: &Output,
    ts: Timestamps<'_>,
) {
    let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("composite"),
        color_attachments: &[color_load(&out.color.view, wgpu::LoadOp::Load)],
        depth_stencil_attachment: depth_load(&out.depth.view, wgpu::LoadOp::Load),
        timestamp_writes: ts,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    pass.set_pipeline(&r.pipeline(PipelineKey {
        shader: Shader::Composite,
        blend: Blend::Over,
    }));
    pass.set_bind_group(0, &oit.read, &[]);
    pass.draw(0..3, 0..1);
    let shader = object_shader(d);
    draw_alpha(&mut pass, r, d, shader);
}
