// fins.wgsl: silhouette fins (Lengyel et al. 2001; Frantzen's fur cards). wgpu has no
// geometry shaders, so each baked fin edge (docs/format.md) is one instance of a six-vertex
// quad: the edge at the root, the same edge pushed out along the combed direction of Listing
// 2.1 at the tip, textured with the fin texture (A coverage, R height along the strand). A fin
// fades in as the edge nears the silhouette (the view direction against both adjacent face
// normals: 1 where they face opposite ways, 0 once both face the viewer by more than
// FIN_SILHOUETTE, where the shells already cover) and as the fin turns face-on (edge-on fins
// are slivers). Fins with nothing to show collapse to a point, so they cost no fragments. Lit
// like the shells by `fur_lighting`. Keep `FinIn` in sync with `FinInstance` in
// crates/pelt-preview/src/uniforms.rs.

#import pelt::fur_common::{FurOut, fin_visibility, fur_out, fur_query, shell_offset, strand_tangent, view_dir_of, view_normal_of, wind_comb}
#ifdef FORWARD_LIGHT
#import pelt::fur_light_forward::{fur_lighting}
#else
#import pelt::fur_light_inferred::{fur_lighting}
#endif
#import pelt::object_bindings::{frame, object}
#import pelt::fur_bindings::{fin_sampler, fin_texture, heightfield, repeat_sampler}

// Set by the pipeline (crates/pelt-preview/src/features/fur.rs): true for the layers of the
// weighted blended OIT pass, false where they blend straight alpha "over". One fragment entry
// point serves both; the revealage output has a target only under WBOIT.
override WBOIT: bool = false;
// SUNS: whether any light of the view is directional; false compiles light_reach's branch on
// the kind out (lights.rs's `suns_for_view`).
override SUNS: bool = true;

struct FinIn {
    @location(0) p0: vec3<f32>,
    @location(1) p1: vec3<f32>,
    @location(2) n0: vec3<f32>,
    @location(3) n1: vec3<f32>,
    @location(4) c0: vec4<f32>,
    @location(5) c1: vec4<f32>,
    @location(6) f0: vec3<f32>,
    @location(7) f1: vec3<f32>,
    @location(8) u: vec2<f32>,
    @location(9) group: u32,
    // Linear base colour under the edge (vertex albedo times the base colour texture).
    @location(10) albedo: vec3<f32>,
}

struct FinOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) view_pos: vec3<f32>,
    @location(1) strand: vec3<f32>,
    @location(2) base_clip: vec4<f32>,
    @location(3) top_clip: vec4<f32>,
    // x: base linear depth, y: top linear depth, z: height on the fin (0 root, 1 tip),
    // w: fade.
    @location(4) depths: vec4<f32>,
    @location(5) uv: vec2<f32>,
    @location(6) @interpolate(flat) group: u32,
    // The fur's colour under the strand (white unless it comes from the texture).
    @location(7) @interpolate(flat) under: vec3<f32>,
}

// The visibility of a fin from its edge: silhouette closeness times face-on-ness.
fn fin_fade(fin: FinIn, to_view: mat4x4<f32>) -> f32 {
    let mid = to_view * vec4<f32>(0.5 * (fin.p0 + fin.p1), 1.0);
    let to_eye = normalize(-mid.xyz);
    let s0 = dot(view_normal_of(fin.f0, frame, object), to_eye);
    let s1 = dot(view_normal_of(fin.f1, frame, object), to_eye);
    let edge = view_dir_of(fin.p1 - fin.p0, frame, object);
    let up = view_dir_of(normalize(fin.n0 + fin.n1) + 0.5 * (fin.c0.xyz + fin.c1.xyz), frame, object);
    let fin_normal = cross(edge, up);
    let len = length(fin_normal);
    let face_on = select(0.0, abs(dot(fin_normal / len, to_eye)), len > 1e-6);
    // The comb lengths are 0 at both ends where the fur is too short for a fin (under
    // 5 % of the fur length at both ends: crates/pelt-scene/src/fur.rs, FIN_MIN_LENGTH).
    let has_fur = select(0.0, 1.0, max(fin.c0.w, fin.c1.w) > 0.0);
    return fin_visibility(s0, s1, face_on, object.fur_model.z == 0.0) * has_fur;
}

@vertex
fn vs_main(fin: FinIn, @builtin(vertex_index) vi: u32) -> FinOut {
    var o: FinOut;
    let to_view = frame.view * object.model;
    let fade = fin_fade(fin, to_view);
    if fade < 1e-3 {
        // Nothing to draw: every corner at one point, a zero-area quad.
        o.clip = vec4<f32>(0.0, 0.0, -1.0, 1.0);
        return o;
    }
    // Corners (end, height): two triangles.
    let ends = array<u32, 6>(0u, 1u, 1u, 0u, 1u, 0u);
    let ups = array<f32, 6>(0.0, 0.0, 1.0, 0.0, 1.0, 1.0);
    let e = ends[vi];
    let t = ups[vi];
    let p = select(fin.p0, fin.p1, e == 1u);
    let n = select(fin.n0, fin.n1, e == 1u);
    let c0 = select(fin.c0, fin.c1, e == 1u);
    let c = vec4<f32>(wind_comb(c0.xyz, n, p, frame, object), c0.w);
    let len = object.fur_base.w;
    let pv = to_view * vec4<f32>(p + shell_offset(n, c.xyz, t, len, c.w), 1.0);
    let pb = to_view * vec4<f32>(p, 1.0);
    let pt = to_view * vec4<f32>(p + shell_offset(n, c.xyz, 1.0, len, c.w), 1.0);
    o.clip = frame.proj * pv;
    o.view_pos = pv.xyz;
    o.strand = view_dir_of(strand_tangent(n, c.xyz, t), frame, object);
    o.base_clip = frame.proj * pb;
    o.top_clip = frame.proj * pt;
    o.depths = vec4<f32>(-pb.z, -pt.z, t, fade);
    o.uv = vec2<f32>(fin.u.x + f32(e) * fin.u.y * object.fur_tip.w, 1.0 - t);
    o.group = fin.group;
    o.under = select(vec3<f32>(1.0), fin.albedo, object.params.w == 1.0);
    return o;
}

fn shade(s: FinOut) -> vec4<f32> {
    let tex = textureSample(fin_texture, fin_sampler, s.uv);
    let l = fur_lighting(fur_query(
        s.view_pos, s.strand, s.base_clip, s.top_clip, s.depths.x, s.depths.y, s.group, s.depths.z, frame,
    ), SUNS);
    let albedo = object.tint.rgb * s.under * mix(object.fur_base.rgb, object.fur_tip.rgb, tex.r);
    return vec4<f32>(albedo * l.diffuse + object.params.y * l.specular, tex.a * s.depths.w);
}

@fragment
fn fs_main(s: FinOut) -> FurOut {
    let c = shade(s);
    if c.a <= 0.002 {
        discard;
    }
    return fur_out(c, -s.view_pos.z, object.fur_params.w, WBOIT);
}
