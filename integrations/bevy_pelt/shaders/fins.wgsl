// fins.wgsl: pelt's fins (shaders/fins.wgsl in pelt) in Bevy's main pass: each fin a quad
// from its edge at the root to the edge pushed out along the combed path at the tip (Revie
// §2.3's offset, bent by the wind), faded in where the edge is on the silhouette (pelt's
// `fin_visibility`), textured with the fin texture and lit with Kajiya-Kay over Bevy's lights.

#import bevy_pbr::{
    mesh_functions,
    skinning,
    mesh_bindings::mesh,
    mesh_types::MESH_FLAGS_SHADOW_RECEIVER_BIT,
    mesh_view_bindings::view,
    pbr_bindings,
}
#import pelt::fur_common::{wind_comb, shell_offset, strand_tangent, view_dir_of, view_normal_of, fin_visibility}
#import bevy_pelt::frame::{pelt_frame, pelt_object}
#import bevy_pelt::lights::{Site, lighting}

const SPECULAR_POWER: f32 = 32.0;
const SPECULAR_STRENGTH: f32 = 0.25;

// Keep in sync with `FinUniform` in src/fins.rs.
struct FinUniform {
    root: vec4<f32>,
    tip: vec4<f32>,
    tint: vec4<f32>,
    wind: vec4<f32>,
    gust: vec4<f32>,
}

@group(#{MATERIAL_BIND_GROUP}) @binding(100) var<uniform> fin: FinUniform;
@group(#{MATERIAL_BIND_GROUP}) @binding(101) var fin_texture: texture_2d<f32>;
@group(#{MATERIAL_BIND_GROUP}) @binding(102) var fin_sampler: sampler;

struct FinVertex {
    @builtin(instance_index) instance_index: u32,
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) base_uv: vec2<f32>,
#ifdef SKINNED
    @location(6) joint_indices: vec4<u32>,
    @location(7) joint_weights: vec4<f32>,
#endif
    @location(9) comb: vec4<f32>,
    @location(10) other: vec4<f32>,
    @location(11) other_normal: vec4<f32>,
    @location(12) other_comb: vec4<f32>,
    @location(13) face0: vec3<f32>,
    @location(14) face1: vec3<f32>,
}

struct FinVarying {
    @builtin(position) position: vec4<f32>,
    @location(0) world_position: vec4<f32>,
    @location(1) view_pos: vec3<f32>,
    @location(2) strand: vec3<f32>,
    // x: height on the fin; y: its fade.
    @location(3) fade: vec2<f32>,
    @location(4) uv: vec2<f32>,
    @location(5) @interpolate(flat) under: vec3<f32>,
    @location(6) world_normal: vec3<f32>,
    @location(7) shadow_at: vec3<f32>,
    @location(8) @interpolate(flat) instance_index: u32,
}

fn world_from_local(v: FinVertex) -> mat4x4<f32> {
#ifdef SKINNED
    return skinning::skin_model(v.joint_indices, v.joint_weights, v.instance_index);
#else
    return mesh_functions::get_world_from_local(v.instance_index);
#endif
}

@vertex
fn vertex(v: FinVertex) -> FinVarying {
    let model = world_from_local(v);
    let frame = pelt_frame(fin.wind, fin.gust);
    let object = pelt_object(model, fin.root.w);
    let to_view = view.view_from_world * model;
    let p_other = v.other.xyz;
    let t = v.other.w;
    // The fade, from the edge as a whole (symmetric in its two ends).
    let mid = to_view * vec4<f32>(0.5 * (v.position + p_other), 1.0);
    let to_eye = normalize(-mid.xyz);
    let s0 = dot(view_normal_of(v.face0, frame, object), to_eye);
    let s1 = dot(view_normal_of(v.face1, frame, object), to_eye);
    let edge = view_dir_of(p_other - v.position, frame, object);
    let up = view_dir_of(normalize(v.normal + v.other_normal.xyz) + 0.5 * (v.comb.xyz + v.other_comb.xyz), frame, object);
    let fin_normal = cross(edge, up);
    let len = length(fin_normal);
    let face_on = select(0.0, abs(dot(fin_normal / max(len, 1e-12), to_eye)), len > 1e-6);
    let has_fur = select(0.0, 1.0, max(v.comb.w, v.other_comb.w) > 0.0);
    let fade = fin_visibility(s0, s1, face_on, fin.tip.w > 0.5) * has_fur;
    var out: FinVarying;
    if fade < 1e-3 {
        out.position = vec4<f32>(0.0, 0.0, -1.0, 1.0);
        return out;
    }
    let c = wind_comb(v.comb.xyz, v.normal, v.position, frame, object);
    let pv = to_view * vec4<f32>(v.position + shell_offset(v.normal, c, t, fin.root.w, v.comb.w), 1.0);
    let tip = model * vec4<f32>(v.position + shell_offset(v.normal, c, 1.0, fin.root.w, v.comb.w), 1.0);
    out.position = view.clip_from_view * pv;
    out.world_position = view.world_from_view * pv;
    out.view_pos = pv.xyz;
    out.strand = view_dir_of(strand_tangent(v.normal, c, t), frame, object);
    out.fade = vec2<f32>(t, fade);
    out.uv = v.uv;
    let m = pbr_bindings::material;
    let texel = textureSampleLevel(pbr_bindings::base_color_texture, pbr_bindings::base_color_sampler, (m.uv_transform * vec3<f32>(v.base_uv, 1.0)).xy, 0.0).rgb;
    // The colour under the edge where the fur takes its colour from the base colour (three's
    // runtime and pelt's fin instances alike): white otherwise.
    out.under = select(vec3<f32>(1.0), m.base_color.rgb * texel, fin.tint.w > 0.5);
    out.world_normal = normalize((object.normal_model * vec4<f32>(v.normal, 0.0)).xyz);
    out.shadow_at = tip.xyz;
    out.instance_index = v.instance_index;
    return out;
}

@fragment
fn fragment(in: FinVarying) -> @location(0) vec4<f32> {
    let tex = textureSample(fin_texture, fin_sampler, in.uv);
    let a = tex.a * in.fade.y;
    if a <= 0.002 {
        discard;
    }
    var s: Site;
    s.world = vec4<f32>(in.shadow_at, 1.0);
    s.view = in.view_pos;
    s.normal = in.world_normal;
    s.frag = in.position;
    s.receiver = (mesh[in.instance_index].flags & MESH_FLAGS_SHADOW_RECEIVER_BIT) != 0u;
    let lit = lighting(s, normalize(in.strand), true, SPECULAR_POWER);
    let albedo = fin.tint.rgb * in.under * mix(fin.root.rgb, fin.tip.rgb, tex.r);
    return vec4<f32>((albedo * lit.diffuse + SPECULAR_STRENGTH * lit.specular) * view.exposure, a);
}
