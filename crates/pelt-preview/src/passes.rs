//! The passes, each a function from its inputs to the target it writes (kajiya's
//! `renderers/*.rs` style): geometry → [`GBuffer`], light (reads the G-buffer) → [`LBuffer`],
//! material (reads L-buffer and DSF buffer) → [`Output`], and the forward reference →
//! [`Output`]. Kircher & Lawrance §2.1–2.3 and §4.

use crate::draw::{DrawData, GBuffer, LBuffer, Output};
use crate::plan::PlannedObject;
use crate::renderer::{PipelineKey, Renderer};
use crate::shaders::Shader;
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
    Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: wgpu::LoadOp::Clear(clear),
            store: wgpu::StoreOp::Store,
        },
    })
}

fn depth_attachment(
    view: &wgpu::TextureView,
) -> Option<wgpu::RenderPassDepthStencilAttachment<'_>> {
    Some(wgpu::RenderPassDepthStencilAttachment {
        view,
        depth_ops: Some(wgpu::Operations {
            load: wgpu::LoadOp::Clear(1.0),
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
    pass.set_pipeline(r.pipeline(PipelineKey {
        shader: Shader::GBuffer,
        blend: false,
    }));
    pass.set_bind_group(0, &d.frame, &[FRAME_LBUFFER]);
    draw_objects(&mut pass, d, &d.plan.opaque);
    draw_objects(&mut pass, d, &d.plan.alpha);
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
    pass.set_pipeline(r.pipeline(PipelineKey {
        shader: Shader::Light,
        blend: false,
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

/// Material pass (§2.3, §3, §4): opaque objects front to back, then alpha objects back to
/// front, blended; lighting from the L-buffer through DSF.
pub fn material_pass(
    enc: &mut wgpu::CommandEncoder,
    r: &Renderer,
    d: &DrawData,
    out: &Output,
    ts: Timestamps<'_>,
) {
    shade(enc, r, d, out, ts, Shader::Material, &d.lbuffer_read);
}

/// Forward reference: every object loops over every light at output resolution.
pub fn forward_pass(
    enc: &mut wgpu::CommandEncoder,
    r: &Renderer,
    d: &DrawData,
    out: &Output,
    ts: Timestamps<'_>,
) {
    shade(enc, r, d, out, ts, Shader::Forward, &d.light_array);
}

fn shade(
    enc: &mut wgpu::CommandEncoder,
    r: &Renderer,
    d: &DrawData,
    out: &Output,
    ts: Timestamps<'_>,
    shader: Shader,
    group2: &wgpu::BindGroup,
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
    pass.set_bind_group(0, &d.frame, &[FRAME_OUTPUT]);
    pass.set_bind_group(2, group2, &[]);
    if !d.plan.opaque.is_empty() {
        pass.set_pipeline(r.pipeline(PipelineKey {
            shader,
            blend: false,
        }));
        draw_objects(&mut pass, d, &d.plan.opaque);
    }
    if !d.plan.alpha.is_empty() {
        pass.set_pipeline(r.pipeline(PipelineKey {
            shader,
            blend: true,
        }));
        draw_objects(&mut pass, d, &d.plan.alpha);
    }
}
