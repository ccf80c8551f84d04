// shells.wgsl: the concentric shells of the material phase (Revie §2.3.1, §2.4.4; Lengyel et
// al. 2001). One instanced draw per fur object: instance 0 is the base mesh, drawn opaque;
// instance s of N stands for the layer of fur between heights (s − 1)/N and s/N and is drawn
// at its middle (Listing 2.1). Each fragment is lit at the strand's root (base mesh) and tip
// (outer shell) through `fur_lighting` (the L-buffer in the deferred pipeline,
// fur_light_inferred.wgsl, or every light directly with Kajiya-Kay, fur_light_forward.wgsl)
// about the strand's tangent at that height, and takes the root-to-tip albedo lerp there.
// Its opacity is what the strand model hides of the view ray across its layer
// (pelt_fur::density): where the pixel resolves single strands, the binary heightfield
// sampled at TEXCOORD_0 × uvScale (the strands taller than the layer); where it holds many,
// 1 − e^(−Δτ) with Δτ the optical depth of the strands' sides and tips over the layer,
// slanted by the view. fs_main writes straight alpha for "over" blending (inner shells
// first) or, with the WBOIT override, weighted blended OIT (McGuire & Bavoil 2013).
//
// With the OPACITY_MAP def, the same shells are drawn from a shadow-casting light into its
// deep opacity maps (Yuksel & Keyser 2008; crates/pelt-preview/src/features/shadows.rs): the
// frame is the light's face, and two fragment entry points replace fs_main: fs_nearest keeps
// the distance from the light to the outer shell, fs_opacity adds each layer's optical depth
// seen from the light, −ln(1 − α), into the opacity layers at and past its depth in the fur.
//
// With the DISTANCE_MAP def (and FORWARD_LIGHT), the same shells are drawn into a mirror or
// glass object's layered distance maps (GPU Gems 3 ch. 17; crates/pelt-preview/src/features/
// reflect): the frame is one cube face about the map's reference point, and fs_distance keeps
// each shell fragment with probability equal to its layer's opacity (a per-texel hash), so a
// texel holds the nearest surviving layer: the fur's grain and, averaged over texels, the
// "over" blend of the layers seen from the reference point (P(layer s shows) = α_s Π(1 − α_t)
// over the layers t in front of it). Its colour is the shell's forward lighting seen from the
// reference point, stored as the fur code (no specular added where a ray meets it); its
// distance is the fur's top above the fragment's point, one smooth surface for the search
// (the surviving layer's own distance jumps by up to the fur's length from texel to texel,
// and the search's secant steps took those jumps for silhouettes and passed through).

#import pelt::common::{VertexIn, pack_geometry, texel_distance}
#import pelt::fur_common::{FurIn, FurOut, MIN_COS, comb_length, fur_out, fur_query, layer_opacity, moving_comb, shell_offset, strand_tangent, view_dir_of, view_normal_of}
#ifndef OPACITY_MAP
#ifdef FORWARD_LIGHT
#import pelt::fur_light_forward::{fur_lighting}
#else
#import pelt::fur_light_inferred::{fur_lighting}
#endif
#endif
#import pelt::object_bindings::{frame, object}
#import pelt::fur_bindings::{base_sampler, base_texture, density_hi, density_lo, fin_sampler, fin_texture, heightfield, repeat_sampler}

// Set by the pipeline (crates/pelt-preview/src/features/fur.rs): true for the layers of the
// weighted blended OIT pass, false where they blend straight alpha "over". One fragment entry
// point serves both; the revealage output has a target only under WBOIT.
override WBOIT: bool = false;
// SUNS: whether any light of the view is directional; false compiles light_reach's branch on
// the kind out (lights.rs's `suns_for_view`).
override SUNS: bool = true;

// The coverage code this pipeline holds (`Coverage` in shaders.rs): 0 the medium alone,
// 1 the medium and the strand-resolving taps (only for objects the plan finds near enough
// for a pixel under 0.75 strand diameters, pelt_scene::footprint), 2 the binary heightfield
// alone. The branches on it are gone at pipeline creation: drivers that run a fragment's
// lanes in lockstep (llvmpipe) would otherwise pay for every side on every shell fragment.
override COVERAGE: u32 = 0u;
// Strand diameters under which a pixel's footprint reads single strands (the upper end of
// the taps' blend into the medium): pelt_scene::footprint::RESOLVED_BELOW, set by the
// renderer, so the plan and the shader share one threshold.
override RESOLVED_BELOW: f32;

struct ShellOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) view_pos: vec3<f32>,
    @location(1) strand: vec3<f32>,
    @location(2) base_clip: vec4<f32>,
    @location(3) top_clip: vec4<f32>,
    // x: base linear depth, y: top linear depth, z: shell depth, w: comb length.
    @location(4) depths: vec4<f32>,
    @location(5) uv: vec2<f32>,
    @location(6) albedo: vec3<f32>,
    @location(7) @interpolate(flat) group: u32,
    @location(8) @interpolate(flat) shell: u32,
    // The material's texture coordinates (the base colour texture's set).
    @location(9) base_uv: vec2<f32>,
    // x, y: the heights the layer spans; z: the strand's length across it; w: the path's
    // length scale, |P(1)| (view units).
    @location(10) layer: vec4<f32>,
    @location(11) view_normal: vec3<f32>,
    // The comb in view space (unit): with the normal, the path's shape (a uniform scale).
    @location(12) comb: vec3<f32>,
#ifdef DISTANCE_MAP
    // The distance from the reference point to the fur's top above this point.
    @location(13) hull: f32,
#endif
}

@vertex
fn vs_main(v: VertexIn, f: FurIn, @builtin(instance_index) shell: u32) -> ShellOut {
    var o: ShellOut;
#ifdef OPACITY_MAP
    // From a light, at most `frame.flags.y` thicker layers: their optical depths add up to
    // the same fur.
    let n = f32(max(min(object.ids.w, frame.flags.y), 1u));
#else
#ifdef DISTANCE_MAP
    // Into a distance map, at most `frame.lbuffer_size.x` thicker layers, likewise.
    let n = f32(max(min(object.ids.w, u32(frame.lbuffer_size.x)), 1u));
#else
    let n = f32(max(object.ids.w, 1u));
#endif
#endif
    let z0 = max(f32(shell) - 1.0, 0.0) / n;
    let z1 = f32(shell) / n;
    // The base mesh at the root; each shell in the middle of its layer.
    let sd = select(0.5 * (z0 + z1), 0.0, shell == 0u);
    let comb = moving_comb(v.normal, f, v.position, frame, object);
    let len = object.fur_base.w;
    let to_view = frame.view * object.model;
    let p = to_view * vec4<f32>(v.position + shell_offset(v.normal, comb, sd, len, comb_length(f)), 1.0);
    let pb = to_view * vec4<f32>(v.position, 1.0);
    let pt = to_view * vec4<f32>(v.position + shell_offset(v.normal, comb, 1.0, len, comb_length(f)), 1.0);
    let p0 = to_view * vec4<f32>(v.position + shell_offset(v.normal, comb, z0, len, comb_length(f)), 1.0);
    let p1 = to_view * vec4<f32>(v.position + shell_offset(v.normal, comb, z1, len, comb_length(f)), 1.0);
    o.clip = frame.proj * p;
    o.view_pos = p.xyz;
    o.strand = view_dir_of(strand_tangent(v.normal, comb, sd), frame, object);
    o.base_clip = frame.proj * pb;
    o.top_clip = frame.proj * pt;
    o.depths = vec4<f32>(-pb.z, -pt.z, sd, f.comb.w);
    o.uv = f.uv;
    o.albedo = v.albedo.rgb * object.tint.rgb;
    o.group = v.group;
    o.shell = shell;
    o.base_uv = v.uv;
    o.layer = vec4<f32>(z0, z1, length(p1.xyz - p0.xyz), length(pt.xyz - pb.xyz));
    o.comb = view_dir_of(comb, frame, object);
    o.view_normal = view_normal_of(v.normal, frame, object);
#ifdef DISTANCE_MAP
    o.hull = length(pt.xyz);
#endif
    return o;
}

// The unit direction from view-space point `p` toward the eye: a light's orthographic map
// (the projection's w row is (0, 0, 0, 1)) looks along −z everywhere.
fn eye_of(p: vec3<f32>) -> vec3<f32> {
    return select(normalize(-p), vec3<f32>(0.0, 0.0, 1.0), frame.proj[3][3] == 1.0);
}

// Where the pixel resolves single strands, the heightfield is read at level 0 without
// filtering, at four taps of a rotated grid across the pixel's footprint: a filtered or
// coarser level blends a strand's height with the bare skin beside it, so a high layer would
// see every strand thinner than it is, while an unfiltered texel is covered exactly where the
// strand covers its centre.
//
// The layers over a pixel are not independent there: a strand covering part of the pixel
// covers that same part in every layer it crosses, and blending each layer "over" the ones
// below with its own fraction of covered taps would let the partly covered edge of a strand
// add up to an opaque pixel of its highest colour. So each tap also asks whether the ray
// through it is covered at the next layer up, read where the ray meets that shell. A layer's
// opacity is the share of its taps that it covers and the next layer does not, among the
// taps the next layer does not cover; blended inner to outer, every tap then shows the
// highest layer covering it, as the strands would. (A ray that leaves one strand and meets
// another higher up is counted by both; testing three more heights up to the tips changed
// the zoomed patch's brightness by under 0.1 % and doubled the reads, so the shader does not.)
fn tap_texel(uv: vec2<f32>, dims: vec2<f32>) -> vec2<i32> {
    return clamp(vec2<i32>(floor(fract(uv) * dims)), vec2<i32>(0), vec2<i32>(dims) - vec2<i32>(1));
}

// The ray through a fragment and the shell's local frame: where the ray meets the shell at
// another height, as a shift along the texture.
struct RayFrame {
    eye_dir: vec3<f32>,
    normal: vec3<f32>,
    comb: vec3<f32>,
    // The path's scale (view units per unit height) and this shell's height.
    scale: f32,
    height: f32,
    // Screen-space derivatives of the position and of the texture coordinates.
    p_dx: vec3<f32>,
    p_dy: vec3<f32>,
    uv_dx: vec2<f32>,
    uv_dy: vec2<f32>,
}

// The path's offset at height `z` in view units (pelt_fur::path::point, scaled).
fn path_at(f: RayFrame, z: f32) -> vec3<f32> {
    return normalize(f.normal + f.comb * z) * z * f.scale;
}

// How far along the texture the ray moves from this shell to the shell at height `z`: that
// shell is this one moved by the path's step, and the ray meets it nearer the eye (or
// further); the difference lies in the shell's tangent plane, mapped to texture coordinates
// through the screen-space derivatives (least squares).
fn shift_to(f: RayFrame, z: f32) -> vec2<f32> {
    let step = path_at(f, z) - path_at(f, f.height);
    let en = dot(f.eye_dir, f.normal);
    let g00 = dot(f.p_dx, f.p_dx);
    let g01 = dot(f.p_dx, f.p_dy);
    let g11 = dot(f.p_dy, f.p_dy);
    let det = g00 * g11 - g01 * g01;
    if abs(en) < 1e-4 || det <= 1e-30 {
        return vec2<f32>(0.0);
    }
    let d = f.eye_dir * (dot(step, f.normal) / en) - step;
    let r0 = dot(d, f.p_dx);
    let r1 = dot(d, f.p_dy);
    return ((r0 * g11 - r1 * g01) * f.uv_dx + (r1 * g00 - r0 * g01) * f.uv_dy) / det;
}

// One tap at `uv`: (covered here and not at the next layer, covered at the next layer).
fn tap(uv: vec2<f32>, shift: vec2<f32>, dims: vec2<f32>, z0: f32, z1: f32, dz: f32) -> vec2<f32> {
    let here = textureLoad(heightfield, tap_texel(uv, dims), 0).r;
    let next = textureLoad(heightfield, tap_texel(uv + shift, dims), 0).r;
    let covered = clamp((here - z0) / dz, 0.0, 1.0);
    let higher = clamp((next - z1) / dz, 0.0, 1.0);
    return vec2<f32>(covered * (1.0 - higher), higher);
}

// Four taps of a rotated grid, written out: a dynamically indexed local array spills to
// memory on some drivers (llvmpipe), at a cost per shell fragment.
fn resolved_alpha(f: RayFrame, tuv: vec2<f32>, z0: f32, z1: f32) -> f32 {
    let dims = vec2<f32>(textureDimensions(heightfield, 0));
    let dz = max(z1 - z0, 1e-6);
    let shift = shift_to(f, f.height + dz);
    let dx = f.uv_dx;
    let dy = f.uv_dy;
    let t = tap(tuv - 0.125 * dx - 0.375 * dy, shift, dims, z0, z1, dz)
        + tap(tuv + 0.375 * dx - 0.125 * dy, shift, dims, z0, z1, dz)
        + tap(tuv + 0.125 * dx + 0.375 * dy, shift, dims, z0, z1, dz)
        + tap(tuv - 0.375 * dx + 0.125 * dy, shift, dims, z0, z1, dz);
    // t.x: taps this layer shows; t.y: taps a higher layer covers.
    return clamp(t.x / max(4.0 - t.y, 1e-3), 0.0, 1.0);
}

// The opacity of shell fragment `s`'s layer at tile coordinates `tuv` (pelt_fur::density):
// Δτ = (κ T(z_mid) sin ψ ℓ √J + T(z0) − T(z1)) / |cos θ|, with ψ the angle between view ray
// and strand, ℓ the strand's length across the layer, J the tile area per unit of surface
// area and θ the angle from the normal; the binary heightfield (the fraction of the layer
// the strand over the texel reaches into) where a pixel is under about a strand wide.
fn layer_alpha(s: ShellOut, tuv: vec2<f32>, uv_dx: vec2<f32>, uv_dy: vec2<f32>, p_dx: vec3<f32>, p_dy: vec3<f32>) -> f32 {
    let z0 = s.layer.x;
    let z1 = s.layer.y;
    if COVERAGE == 2u {
        // The heightfield alone, faded over the strand's top (Revie §2.4.4).
        let h = textureSample(heightfield, repeat_sampler, tuv).r;
        return 1.0 - smoothstep(h - object.fur_params.z, h, z1);
    }
    // T over the pixel's own footprint. Trilinear filtering at the footprint's level spreads
    // a sample over about twice the pixel (the mip texel's box widened by the bilinear tent),
    // which blurred away the grain of the strands a pixel actually covers; gradients of half
    // the footprint make the filter about as wide as the pixel (demo scene, 320×180, forward
    // 64 shells: FLIP against the strands 0.0245 -> 0.0219), at the same two reads.
    let lo = textureSampleGrad(density_lo, repeat_sampler, tuv, 0.5 * uv_dx, 0.5 * uv_dy);
    let hi = textureSampleGrad(density_hi, repeat_sampler, tuv, 0.5 * uv_dx, 0.5 * uv_dy);
    let surface_area = length(cross(p_dx, p_dy));
    let tile_area = abs(uv_dx.x * uv_dy.y - uv_dx.y * uv_dy.x);
    let eye = eye_of(s.view_pos);
    let mu = max(abs(dot(normalize(s.view_normal), eye)), MIN_COS);
    let vt = dot(eye, normalize(s.strand));
    let sin_psi = sqrt(max(1.0 - vt * vt, 0.0));
    let sqrt_j = sqrt(tile_area / max(surface_area, 1e-20));
    let statistical = layer_opacity(lo, hi, z0, z1, object.fur_model.x, sin_psi, s.layer.z * sqrt_j, mu);
    // A pixel footprint (tile widths) under half a strand's diameter resolves it; over
    // RESOLVED_BELOW (three quarters) the medium alone is truer than four point taps of single strands (demo scene
    // at 1280×720 box-filtered to 320×180 against the strands: with the taps blended in up to
    // 1.5 diameters, 64 shells read 0.031 and 1.045× the strands' brightness, worse than 16;
    // the medium alone 0.020 and 0.995×).
    let footprint = sqrt(tile_area);
    let d = max(object.fur_model.y, 1e-9);
    let w = smoothstep(0.5 * d, RESOLVED_BELOW * d, footprint);
    if COVERAGE != 1u || w >= 1.0 {
        return clamp(statistical, 0.0, 1.0);
    }
    var f: RayFrame;
    f.eye_dir = -eye_of(s.view_pos);
    f.normal = normalize(s.view_normal);
    f.comb = normalize(s.comb);
    f.scale = s.layer.w;
    f.height = 0.5 * (z0 + z1);
    f.p_dx = p_dx;
    f.p_dy = p_dy;
    f.uv_dx = uv_dx;
    f.uv_dy = uv_dy;
    let binary = resolved_alpha(f, tuv, z0, z1);
    return clamp(mix(binary, statistical, w), 0.0, 1.0);
}

// The opacity of a shell fragment's layer (1 for the base mesh).
fn coverage_of(s: ShellOut) -> f32 {
    let tuv = s.uv * object.fur_tip.w;
    // Fur shorter than 5 % of the length fades away rather than lying flat on the skin.
    // Tile area and surface area one pixel covers (the shell's own, at this fragment).
    let uv_dx = dpdx(tuv);
    let uv_dy = dpdy(tuv);
    let coverage = layer_alpha(s, tuv, uv_dx, uv_dy, dpdx(s.view_pos), dpdy(s.view_pos));
    let strand = coverage * clamp(s.depths.w * 20.0, 0.0, 1.0);
    return select(strand, 1.0, s.shell == 0u);
}

#ifndef OPACITY_MAP
// Colour and coverage of a shell fragment.
fn shade(s: ShellOut) -> vec4<f32> {
    let sd = s.depths.z;
    let under = textureSample(base_texture, base_sampler, s.base_uv).rgb;
    let a = coverage_of(s);
    let l = fur_lighting(fur_query(
        s.view_pos, s.strand, s.base_clip, s.top_clip, s.depths.x, s.depths.y, s.group, sd, frame,
    ), SUNS);
    // With the fur config's colorFromTexture, the base colour texture under the strand
    // colours the whole strand (root and tip colours then shade it).
    let tint = select(vec3<f32>(1.0), under, object.params.w == 1.0);
    let albedo = s.albedo * tint * mix(object.fur_base.rgb, object.fur_tip.rgb, sd);
    return vec4<f32>(albedo * l.diffuse + object.params.y * l.specular, a);
}

@fragment
fn fs_main(s: ShellOut) -> FurOut {
    let c = shade(s);
    if c.a <= 0.0 {
        discard;
    }
    return fur_out(c, -s.view_pos.z, object.fur_params.w, WBOIT);
}
#endif

#ifdef OPACITY_MAP
// The shadow cubes (crates/pelt-preview/src/features/shadows.rs): zw the nearest fur's
// distance from the light, in two halves, in layer `frame.flags.x`.
@group(2) @binding(0) var cubes: texture_2d_array<f32>;

// The distance from the light to view-space point `p` of the light's face, or, where its map
// measures along its axis (`frame.flags.z` 1: a light's one map), from the map's near plane
// (`frame.proj_params.z`), as shadow_map.wgsl and shadows.wgsl measure it.
fn light_distance(p: vec3<f32>) -> f32 {
    return select(length(p), -p.z - frame.proj_params.z, frame.flags.z == 1u);
}

// The outer shell's distance as a half float and its half-float remainder, into the cube's
// z and w (the pipeline writes those two channels alone).
@fragment
fn fs_nearest(s: ShellOut) -> @location(0) vec4<f32> {
    let d = light_distance(s.view_pos);
    let hi = bitcast<f32>(bitcast<u32>(d) & 0xffffe000u);
    return vec4<f32>(0.0, 0.0, hi, d - hi);
}

// The layer's optical depth seen from the light, added (additive blending) into each deep
// opacity layer whose far boundary (`frame.lbuffer_size`, depth past the nearest fur; the
// last layer's is past everything) it lies within.
@fragment
fn fs_opacity(s: ShellOut) -> @location(0) vec4<f32> {
    let a = min(coverage_of(s), 0.999);
    if a <= 0.0 {
        discard;
    }
    let tau = -log(1.0 - a);
    let near = textureLoad(cubes, vec2<i32>(s.clip.xy), i32(frame.flags.x), 0);
    let x = light_distance(s.view_pos) - (near.z + near.w);
    let b = frame.lbuffer_size;
    return vec4<f32>(select(vec3<f32>(0.0), vec3<f32>(tau), vec3<f32>(x) <= b.xyz), 0.0);
}
#endif

#ifdef DISTANCE_MAP
// The previous layer's distances (depth peeling, as distance_map.wgsl peels).
@group(4) @binding(0) var peel: texture_2d_array<f32>;

// The material code of a fur texel: its radiance is whole (reflect.wgsl adds no specular).
const FUR_TEXEL: f32 = -2.0;

struct Texel {
    @location(0) material: vec4<f32>,
    @location(1) geometry: vec4<f32>,
}

// A uniform number in [0, 1) for texel `p` and layer `shell` of face `face` (PCG).
fn coverage_hash(p: vec2<u32>, shell: u32, face: u32) -> f32 {
    var h = p.x * 747796405u + p.y * 2891336453u + shell * 277803737u + face * 1442695041u;
    h = h * 747796405u + 2891336453u;
    h = ((h >> ((h >> 28u) + 4u)) ^ h) * 277803737u;
    h = (h >> 22u) ^ h;
    return f32(h >> 8u) / 16777216.0;
}

// frame.flags: x the layer (2 the nearest of the rest of the scene, 3.. peeled), w the face.
@fragment
fn fs_distance(s: ShellOut) -> Texel {
    let c = shade(s);
    let texel = vec2<u32>(s.clip.xy);
    if c.a <= coverage_hash(texel, s.shell, frame.flags.w) {
        discard;
    }
    // The frame's view only moves the reference point to the origin: view space is world
    // space about it.
    let dist = s.hull;
    if frame.flags.x >= 3u {
        let before = texel_distance(textureLoad(peel, vec2<i32>(texel), i32(frame.flags.w), 0));
        if before < 0.0 || dist <= before * 1.0005 {
            discard;
        }
    }
    var t: Texel;
    t.geometry = pack_geometry(normalize(s.view_normal), dist);
    t.material = vec4<f32>(c.rgb, FUR_TEXEL);
    return t;
}
#endif
