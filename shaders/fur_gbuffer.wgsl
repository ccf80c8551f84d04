// fur_gbuffer.wgsl: the geometry phase of deferred fur (Revie §2.4.2), at L-buffer
// resolution, into the same G-buffer as every other object (Kircher & Lawrance's normals and
// DSF buffer). Pass 1 (vs_base/fs_base) draws the base mesh with the grain normal of Listing
// 2.5. Pass 2 (vs_outer/fs_outer) draws the outermost shell, pushed out by the fur length ×
// the comb length and combed per Listing 2.1, into one pixel in four (the top-left of each
// 2×2 cell, Listing 2.6), with the grain normal bent toward the back at the silhouette
// (Listing 2.3). Its texels carry the fur's outer-shell ID, so the material phase can tell
// them from the base mesh. With Kajiya-Kay fur lighting (Object.fur_model.w = 0) both passes
// store, in place of a normal, the strand's tangent (the Listing 2.1 path's derivative) at
// ROOT_HEIGHT and TIP_HEIGHT as it runs from the root; light.wgsl lights them with Kajiya-Kay and the shells mix the two by height
// (fur_light_inferred.wgsl).

#import pelt::common::{VertexIn, depth_code, encode_normal, facing_normal}
#import pelt::fur_common::{FurIn, comb_length, grain_normal, rim_normal, moving_comb, shell_offset, strand_tangent, view_dir_of, view_normal_of}
#import pelt::object_bindings::{frame, object}

// The heights whose strand tangents the base and outer passes store (Kajiya-Kay lighting).
// Keep in sync with fur_light_inferred.wgsl.
const ROOT_HEIGHT: f32 = 0.25;
const TIP_HEIGHT: f32 = 0.75;

struct FurSurface {
    @builtin(position) clip: vec4<f32>,
    @location(0) view_pos: vec3<f32>,
    @location(1) view_normal: vec3<f32>,
    @location(2) view_comb: vec3<f32>,
    @location(3) @interpolate(flat) group: u32,
    // The strand's view-space tangent at this pass's height.
    @location(4) view_strand: vec3<f32>,
}

struct GBufferOut {
    @location(0) normal: vec2<f32>,
    @location(1) dsf: vec2<u32>,
}

fn fur_surface(v: VertexIn, f: FurIn, sd: f32, lit_at: f32) -> FurSurface {
    var s: FurSurface;
    let comb = moving_comb(v.normal, f, v.position, frame, object);
    let p = v.position + shell_offset(v.normal, comb, sd, object.fur_base.w, comb_length(f));
    let view = frame.view * (object.model * vec4<f32>(p, 1.0));
    s.clip = frame.proj * view;
    s.view_pos = view.xyz;
    s.view_normal = view_normal_of(v.normal, frame, object);
    s.view_comb = view_dir_of(comb, frame, object);
    s.view_strand = view_dir_of(strand_tangent(v.normal, comb, lit_at), frame, object);
    s.group = v.group;
    return s;
}

@vertex
fn vs_base(v: VertexIn, f: FurIn) -> FurSurface {
    return fur_surface(v, f, 0.0, ROOT_HEIGHT);
}

@vertex
fn vs_outer(v: VertexIn, f: FurIn) -> FurSurface {
    return fur_surface(v, f, 1.0, TIP_HEIGHT);
}

// The strand tangent as it runs from the root (Kircher & Lawrance's encoding holds every
// direction but straight away from the viewer): Kajiya-Kay does not see its sign, the shadow
// lookup lifts the strand along it (shadows.wgsl, strand_shadow_seen).
fn stored_strand(s: FurSurface) -> vec3<f32> {
    return normalize(s.view_strand);
}

fn kajiya_kay() -> bool {
    return object.fur_model.w == 0.0;
}

fn grain(s: FurSurface, front: bool) -> vec3<f32> {
    let n = facing_normal(s.view_normal, front);
    return grain_normal(n, normalize(s.view_comb), normalize(s.view_pos));
}

@fragment
fn fs_base(s: FurSurface, @builtin(front_facing) front: bool) -> GBufferOut {
    var out: GBufferOut;
    out.normal = encode_normal(select(grain(s, front), stored_strand(s), kajiya_kay()));
    out.dsf = vec2<u32>(depth_code(-s.view_pos.z, frame), ((object.ids.x & 255u) << 8u) | (s.group & 255u));
    return out;
}

@fragment
fn fs_outer(s: FurSurface, @builtin(front_facing) front: bool) -> GBufferOut {
    let p = vec2<u32>(s.clip.xy);
    if ((p.x | p.y) & 1u) != 0u {
        discard;
    }
    let eye = normalize(s.view_pos);
    let n = rim_normal(grain(s, front), eye, object.fur_params.x, object.fur_params.y);
    var out: GBufferOut;
    out.normal = encode_normal(select(n, stored_strand(s), kajiya_kay()));
    out.dsf = vec2<u32>(depth_code(-s.view_pos.z, frame), ((object.ids.z & 255u) << 8u) | (s.group & 255u));
    return out;
}
