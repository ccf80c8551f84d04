// light.wgsl: the light pass of inferred lighting (Kircher & Lawrance §2.2). One full-screen
// triangle per point light, clipped by the scissor rectangle of the light's screen-space bounds
// (set by the CPU) and placed just beyond the far side of the light's sphere of influence, so
// the depth test against the geometry pass's depth rejects, before shading, every pixel whose
// surface lies behind the light's reach (or is empty); the rest are added into the L-buffer:
// rgb = diffuse, a = specular intensity. The view-space position comes from the DSF buffer's
// linear depth; the normal from eqs. 2 and 3, or, for fur lit as strands (the shell table's
// STRAND_LIT), the strand tangent stored in its place, lit with Kajiya-Kay (strand_light). A
// directional light (the DIRECTIONAL pipeline) reaches every pixel: its triangle covers the
// L-buffer on the far plane. A shadow-casting light is weighted by how much of it the surface
// sees (shadows.wgsl), per L-buffer pixel, alpha layers included.

#import pelt::common::{DEPTH_EMPTY, DEPTH_STEPS, Light, STRAND_LIT, decode_normal, depth_from_code, one_light, point_reach, strand_light, sun_reach}
#import pelt::fullscreen::{fullscreen_position}
#import pelt::object_bindings::{frame}
#import pelt::shadows::{shadow_seen, strand_shadow_seen}

@group(1) @binding(0) var normals: texture_2d<f32>;
@group(1) @binding(1) var dsf: texture_2d<u32>;
@group(2) @binding(0) var<uniform> light: Light;

// The full-screen triangle at the depth of the light's far side, pushed back by a thousandth
// of its radius and four steps of the DSF buffer's depth code (the fragment shader reads the
// quantised depth, the test compares the exact one): a surface the test rejects is out of the
// light's reach, where one_light and strand_light add exactly zero. A sphere wholly in
// front of the near plane lights nothing (depth 0 passes no stored depth). A directional
// light reaches everything: its triangle stays on the far plane (depth 1).
@vertex
fn vs_light(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    var p = fullscreen_position(vi);
    if DIRECTIONAL {
        return p;
    }
    let step = (frame.proj_params.w - frame.proj_params.z) / DEPTH_STEPS;
    let r = light.position_radius.w;
    let far = light.position_radius.z - (1.001 * r + 4.0 * step);
    let c = frame.proj * vec4<f32>(0.0, 0.0, far, 1.0);
    p.z = select(0.0, clamp(c.z / c.w, 0.0, 1.0), c.w > 0.0);
    return p;
}
// The shell table (obliterate.wgsl): STRAND_LIT marks the IDs whose texels hold a strand
// tangent instead of a normal (Kajiya-Kay fur).
@group(3) @binding(0) var<uniform> shell_table: array<vec4<u32>, 64>;
// DIRECTIONAL: whether this pipeline draws directional lights (true) or point lights (false);
// the light pass switches pipeline where the kind changes, so neither kind pays for the
// other's code (a run-time branch on the kind made lavapipe's light pass five times slower).
override DIRECTIONAL: bool = false;
// STRAND_LIGHTS: whether any object's texels may hold strand tangents (a view with fur lit
// with Kajiya-Kay); false skips the shell-table lookup (lights.rs's `strand_lit`).
override STRAND_LIGHTS: bool = true;
// SHADOWS: whether any light of the view casts shadows; false compiles the lookup out (a
// CPU rasterizer pays for a branch it cannot prove uniform).
override SHADOWS: bool = true;
// FUR_SHADOWS: whether the fur casts by its coverage too (deep opacity maps); false compiles
// that lookup out.
override FUR_SHADOWS: bool = true;

// The light's direction and falloff at view-space point `p`.
fn reach(p: vec3<f32>) -> vec4<f32> {
    if DIRECTIONAL {
        return sun_reach(light);
    }
    return point_reach(p, light);
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let px = vec2<i32>(frag.xy);
    let d = textureLoad(dsf, px, 0);
    if d.x == DEPTH_EMPTY {
        discard;
    }
    let depth = depth_from_code(d.x, frame);
    // Pixel centre to a view ray through the z = -1 plane, scaled to the stored depth.
    let ndc = vec2<f32>(frag.x * frame.target_size.z * 2.0 - 1.0, 1.0 - frag.y * frame.target_size.w * 2.0);
    let p = vec3<f32>(ndc * frame.proj_params.xy, -1.0) * depth;
    let n = decode_normal(textureLoad(normals, px, 0).xy);
    let id = (d.y >> 8u) & 255u;
    if STRAND_LIGHTS && (shell_table[id >> 2u][id & 3u] & STRAND_LIT) != 0u {
        // A strand: lit by Kajiya-Kay along its tangent (stored as it runs from the root, not
        // flipped), its shadow lookup lifted along it.
        let r = reach(p);
        let lit = strand_light(p, n, r, light, frame.ambient.w);
        if !SHADOWS {
            return lit;
        }
        if all(lit == vec4<f32>(0.0)) {
            return lit;
        }
        // The stored depth is the strand's to within one step of its code.
        let step = (frame.proj_params.w - frame.proj_params.z) / DEPTH_STEPS;
        return lit * strand_shadow_seen(p, n, step, light, FUR_SHADOWS);
    }
    let lit = one_light(p, n, reach(p), light, frame.ambient.w);
    // Each override alone in its condition: a pipeline's constant decides the branch (and
    // tests/light_pass.rs reads what it leaves out).
    if !SHADOWS {
        return lit;
    }
    if all(lit == vec4<f32>(0.0)) {
        return lit;
    }
    return lit * shadow_seen(p, n, light, FUR_SHADOWS);
}
