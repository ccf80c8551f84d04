// gbuffer.wgsl: the geometry pass of inferred lighting (Kircher & Lawrance §2.1), at L-buffer
// resolution. Writes view-space normals as X/Y after the hemisphere mapping of eq. 1, and the
// DSF buffer: 16-bit linear depth and the 16-bit ID (object << 8 | normal group, §3.1).
// A material's normal texture perturbs the normal (common.wgsl's perturb_normal).
// Alpha objects write only the pixels of their 2×2 stipple pattern (§4).

#import pelt::common::{Surface, VertexIn, depth_code, dsf_id, encode_normal, facing_normal, in_stipple, perturb_normal, to_surface}
#import pelt::object_bindings::{frame, object}
#import pelt::material_bindings::{material, normal_sampler, normal_texture}

// TEXTURED: the pipeline of materials with textures (true) or of those without (false),
// which read the neutral texel's values (white base colour, metallic-roughness 1, no normal
// map) without sampling: an untextured material pays for no texture fetch. Keep the neutral
// values in sync with crates/pelt-preview/src/gpu_material.rs.
override TEXTURED: bool = true;
// STIPPLED: the pipeline of stippled alpha objects (true), which discard the pixels outside
// their pattern, or of opaque ones (false), which keep every pixel: a shader that never
// discards lets the rasterizer test depth before shading. Keep in sync with
// crates/pelt-preview/src/features/geometry.rs.
override STIPPLED: bool = true;

@vertex
fn vs_main(v: VertexIn) -> Surface {
    return to_surface(v, frame, object);
}

struct GBufferOut {
    @location(0) normal: vec2<f32>,
    @location(1) dsf: vec2<u32>,
}

@fragment
fn fs_main(s: Surface, @builtin(front_facing) front: bool) -> GBufferOut {
    if STIPPLED && !in_stipple(vec2<u32>(s.clip.xy), object.ids.y) {
        discard;
    }
    var out: GBufferOut;
    var n = facing_normal(s.view_normal, front);
    if TEXTURED {
        // Sampled before the material's branch: derivatives need uniform control flow.
        let stored = textureSample(normal_texture, normal_sampler, s.uv).xyz;
        if material.flags.x == 1u {
            n = perturb_normal(n, s.view_pos, s.uv, stored, material.factors.x);
        }
    }
    out.normal = encode_normal(n);
    out.dsf = vec2<u32>(depth_code(-s.view_pos.z, frame), dsf_id(object, s.group));
    return out;
}
