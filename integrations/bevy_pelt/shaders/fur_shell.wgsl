// fur_shell.wgsl: what the fur's main pass (fur.wgsl) and its prepass and shadow passes
// (fur_prepass.wgsl) share, after Revie §2.3: the material's bindings, the vertex stage that
// pushes the base mesh (shell 0) or a shell out along Bevy's skinned frame by pelt's Listing
// 2.1 offset and wind, and the layer's opacity from the strand model as a medium
// (pelt_fur::density, shells.wgsl's coverage in pelt). Every formula is pelt's own
// (`pelt::fur_common`, imported unchanged); what is written here is the plumbing.

#define_import_path bevy_pelt::fur_shell

#import bevy_pbr::{
    mesh_functions,
    skinning,
    mesh_view_bindings::view,
    pbr_bindings,
}
#import pelt::fur_common::{MIN_COS, comb_object, wind_comb, shell_offset, strand_tangent, view_dir_of, view_normal_of, layer_opacity}
#import bevy_pelt::frame::{pelt_frame, pelt_object}

// Keep in sync with `FurUniform` in src/material.rs.
struct FurUniform {
    // rgb: root colour (linear); w: fur length (mesh units).
    root: vec4<f32>,
    // rgb: tip colour; w: the density texture's UV scale.
    tip: vec4<f32>,
    // x: this shell (0: the base mesh); y: shells drawn; z: κ (pelt_fur::density); w: root
    // and tip colours multiply the base colour texture (1) or not (0).
    shell: vec4<f32>,
    // rgb: the object's tint; w: every shell opaque (1: a negative control of the tests).
    tint: vec4<f32>,
    // xyz: the wind's world direction × strength; w: the time in seconds.
    wind: vec4<f32>,
    // x: gusts per second; y: turbulence.
    gust: vec4<f32>,
}

@group(#{MATERIAL_BIND_GROUP}) @binding(100) var<uniform> fur: FurUniform;
@group(#{MATERIAL_BIND_GROUP}) @binding(101) var density_lo: texture_2d<f32>;
@group(#{MATERIAL_BIND_GROUP}) @binding(102) var density_lo_sampler: sampler;
@group(#{MATERIAL_BIND_GROUP}) @binding(103) var density_hi: texture_2d<f32>;
@group(#{MATERIAL_BIND_GROUP}) @binding(104) var density_hi_sampler: sampler;

struct FurVertex {
    @builtin(instance_index) instance_index: u32,
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(4) tangent: vec4<f32>,
#ifdef SKINNED
    @location(6) joint_indices: vec4<u32>,
    @location(7) joint_weights: vec4<f32>,
#endif
    // The decoded comb (docs/extension/PELT_fur): xyz tangent space, w the comb length.
    @location(9) comb: vec4<f32>,
}

struct FurVarying {
    @builtin(position) position: vec4<f32>,
    @location(0) world_position: vec4<f32>,
    @location(1) view_pos: vec3<f32>,
    // The strand's direction at this height, view space.
    @location(2) strand: vec3<f32>,
    // x: height on the strand (0..1); y: the vertex's comb length.
    @location(3) height: vec2<f32>,
    @location(4) uv: vec2<f32>,
    // x, y: the layer's heights z0, z1; z: the strand's view length across it.
    @location(5) layer: vec3<f32>,
    @location(6) view_normal: vec3<f32>,
    @location(7) world_normal: vec3<f32>,
    @location(8) @interpolate(flat) instance_index: u32,
    // Where the fragment's shadows are looked up (world): its strand's tip, above the
    // strand's own layers, as pelt lifts a strand's point along it (shadows.wgsl).
    @location(10) shadow_at: vec3<f32>,
#ifdef UNCLIPPED_DEPTH_ORTHO_EMULATION
    // A directional light's shadow pass without depth clip control (Bevy's prepass.wgsl).
    @location(9) unclipped_depth: f32,
#endif
}

fn world_from_local(v: FurVertex) -> mat4x4<f32> {
#ifdef SKINNED
    return skinning::skin_model(v.joint_indices, v.joint_weights, v.instance_index);
#else
    return mesh_functions::get_world_from_local(v.instance_index);
#endif
}

// The vertex of the base mesh or shell `fur.shell.x` in the current view.
fn shell_vertex(v: FurVertex) -> FurVarying {
    let model = world_from_local(v);
    let frame = pelt_frame(fur.wind, fur.gust);
    let object = pelt_object(model, fur.root.w);
    let shell = fur.shell.x;
    let n = max(fur.shell.y, 1.0);
    let z0 = max(shell - 1.0, 0.0) / n;
    let z1 = shell / n;
    let sd = select(0.5 * (z0 + z1), 0.0, shell == 0.0);
    let comb = wind_comb(comb_object(v.normal, v.tangent, v.comb.xyz), v.normal, v.position, frame, object);
    let cl = v.comb.w;
    let len = fur.root.w;
    let to_view = view.view_from_world * model;
    let p = to_view * vec4<f32>(v.position + shell_offset(v.normal, comb, sd, len, cl), 1.0);
    let p0 = to_view * vec4<f32>(v.position + shell_offset(v.normal, comb, z0, len, cl), 1.0);
    let p1 = to_view * vec4<f32>(v.position + shell_offset(v.normal, comb, z1, len, cl), 1.0);
    let tip = model * vec4<f32>(v.position + shell_offset(v.normal, comb, 1.0, len, cl), 1.0);
    var out: FurVarying;
    out.position = view.clip_from_view * p;
    out.world_position = view.world_from_view * p;
    out.view_pos = p.xyz;
    out.strand = view_dir_of(strand_tangent(v.normal, comb, sd), frame, object);
    out.height = vec2<f32>(sd, cl);
    out.uv = v.uv;
    out.layer = vec3<f32>(z0, z1, length(p1.xyz - p0.xyz));
    out.view_normal = view_normal_of(v.normal, frame, object);
    out.world_normal = normalize((object.normal_model * vec4<f32>(v.normal, 0.0)).xyz);
    out.instance_index = v.instance_index;
    out.shadow_at = tip.xyz;
#ifdef UNCLIPPED_DEPTH_ORTHO_EMULATION
    out.unclipped_depth = out.position.z;
    out.position.z = min(out.position.z, 1.0);
#endif
    return out;
}

// The layer's opacity (shells.wgsl's coverage with the medium): 1 on the base mesh.
fn coverage(in: FurVarying) -> f32 {
    if fur.shell.x == 0.0 || fur.tint.w > 0.5 {
        return 1.0;
    }
    let tuv = in.uv * fur.tip.w;
    let uv_dx = dpdx(tuv);
    let uv_dy = dpdy(tuv);
    let p_dx = dpdx(in.view_pos);
    let p_dy = dpdy(in.view_pos);
    let lo = textureSampleGrad(density_lo, density_lo_sampler, tuv, 0.5 * uv_dx, 0.5 * uv_dy);
    let hi = textureSampleGrad(density_hi, density_hi_sampler, tuv, 0.5 * uv_dx, 0.5 * uv_dy);
    let surface_area = length(cross(p_dx, p_dy));
    let tile_area = abs(uv_dx.x * uv_dy.y - uv_dx.y * uv_dy.x);
    let orthographic = view.clip_from_view[3].w == 1.0;
    let eye = select(normalize(-in.view_pos), vec3<f32>(0.0, 0.0, 1.0), orthographic);
    let mu = max(abs(dot(normalize(in.view_normal), eye)), MIN_COS);
    let vt = dot(eye, normalize(in.strand));
    let sin_psi = sqrt(max(1.0 - vt * vt, 0.0));
    let sqrt_j = sqrt(tile_area / max(surface_area, 1e-20));
    let a = clamp(layer_opacity(lo, hi, in.layer.x, in.layer.y, fur.shell.z, sin_psi, in.layer.z * sqrt_j, mu), 0.0, 1.0);
    return a * clamp(in.height.y * 20.0, 0.0, 1.0);
}

// The base colour under the strand: the material's factor times its texture (with its
// KHR_texture_transform) where the fur takes its colour from it.
fn under(uv: vec2<f32>) -> vec3<f32> {
    let t = (pbr_bindings::material.uv_transform * vec3<f32>(uv, 1.0)).xy;
    let texel = textureSample(pbr_bindings::base_color_texture, pbr_bindings::base_color_sampler, t).rgb;
    return pbr_bindings::material.base_color.rgb * select(vec3<f32>(1.0), texel, fur.shell.w > 0.5);
}


// A hash of `p` to 0..1 (the shadow passes' hashed alpha test).
fn hash3(p_in: vec3<f32>) -> f32 {
    var p = fract(p_in * vec3<f32>(0.1031, 0.1030, 0.0973));
    p += dot(p, p.yxz + 33.33);
    return fract((p.x + p.y) * p.z);
}
