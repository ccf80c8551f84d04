// shadows.wgsl: how much of a light a surface sees, from a point light's shadow cube or a
// directional light's orthographic map (shadow_map.wgsl), one lookup per lit pixel: in the light pass per L-buffer pixel, so
// opaque surfaces and every stippled alpha layer receive it (Kircher & Lawrance §4), and in
// the forward pass per pixel, identically.
//
// The receiver is lifted off its surface along its normal by one and a half texels of the
// map at its distance, and compared one texel nearer than itself (a cube's bias grows with
// the distance, as its texels do; an orthographic map's texels are one size), over a square of PCF × PCF texels (percentage-closer
// filtering). The group is `slot::CUBES` in crates/pelt-preview/src/features/shadows.rs.
//
// Fur shadows by its coverage through deep opacity maps (Yuksel & Keyser 2008): beside each
// layer of the cubes, the distance to the nearest fur and up to three layers of the fur's
// optical depth seen from the light, each summed to its boundary past the nearest fur. Each
// texel of the lookup passes exp(−τ) of the light, τ read at the receiver's depth past the
// nearest fur, linear between the layers' boundaries (none in front of the fur, the last
// layer's past it): fur shadows itself, and its shadow on everything behind it is as soft as
// the fur is thin.

#define_import_path pelt::shadows

#import pelt::common::{Light, face_uv}
#import pelt::object_bindings::{frame}

// A directional light's map: one layer of its slot, an orthographic view fitted to the
// scene. Keep in sync with SunMap in crates/pelt-preview/src/features/shadows.rs.
struct SunMap {
    // World to the map: xy its texture coordinates, z the distance from its near plane along
    // the light's direction (what shadow_map.wgsl stores).
    to_map: mat4x4<f32>,
    // x: the world size of one texel; yzw: unused.
    texel: vec4<f32>,
}

// How to read the cubes. Keep in sync with ShadowRead in
// crates/pelt-preview/src/features/shadows.rs.
struct ShadowRead {
    // x: the PCF side in texels (the scene's shadowMaps.pcf); yzw: unused.
    pcf: vec4<u32>,
    // The deep opacity layers' boundaries (world units past the nearest fur; the last one
    // where its value is reached) and w: how many layers there are (0: fur casts no coverage).
    layers: vec4<f32>,
    // Each slot's map when its light is directional.
    suns: array<SunMap, 8>,
}

@group(4) @binding(0) var shadow_cubes: texture_2d_array<f32>;
@group(4) @binding(1) var<uniform> shadow_read: ShadowRead;
// Per layer of the cubes: xy the nearest fur's distance (two halves), z 1 where a texel holds
// fur; and the optical depth of each deep opacity layer (xyz).
@group(4) @binding(2) var fur_near: texture_2d_array<f32>;
@group(4) @binding(3) var fur_opacity: texture_2d_array<f32>;

// The distance from the light to the nearest surface in texel `at` of cube face `layer`
// (shadow_map.wgsl's two halves).
fn nearest(at: vec2<i32>, layer: i32) -> f32 {
    let t = textureLoad(shadow_cubes, at, layer, 0);
    return t.x + t.y;
}

// The fur's optical depth between the light and distance `reach` in texel `at` of `layer`:
// piecewise linear through (0, 0) and each opacity layer's (boundary, value), the last value
// past it.
fn fur_depth(at: vec2<i32>, layer: i32, reach: f32) -> f32 {
    let near = textureLoad(fur_near, at, layer, 0);
    let x = reach - (near.x + near.y);
    if near.z == 0.0 || x <= 0.0 {
        return 0.0;
    }
    let b = shadow_read.layers;
    let t = textureLoad(fur_opacity, at, layer, 0).xyz;
    if x <= b.x {
        return t.x * x / b.x;
    }
    if b.w < 2.0 {
        return t.x;
    }
    if x <= b.y {
        return mix(t.x, t.y, (x - b.x) / (b.y - b.x));
    }
    if b.w < 3.0 {
        return t.y;
    }
    return mix(t.y, t.z, clamp((x - b.y) / (b.z - b.y), 0.0, 1.0));
}

// How much of the light reaches distance `reach` in texel `at` of `layer`: none behind the
// nearest opaque surface, exp(−τ) of the fur in front of it.
fn seen_at(at: vec2<i32>, layer: i32, reach: f32) -> f32 {
    if !(reach <= nearest(at, layer)) {
        return 0.0;
    }
    if shadow_read.layers.w == 0.0 {
        return 1.0;
    }
    return exp(-fur_depth(at, layer, reach));
}

// The fraction (0 to 1) of `light` that view-space point `p` with unit normal `n` sees; 1
// for a light that casts no shadows.
fn shadow_seen(p: vec3<f32>, n: vec3<f32>, light: Light) -> f32 {
    if light.shadow.x == 0u {
        return 1.0;
    }
    let slot = light.shadow.x - 1u;
    let size = f32(textureDimensions(shadow_cubes).x);
    // View to world: the view's rotation is orthonormal, so its inverse is its transpose.
    let rot = mat3x3<f32>(frame.view[0].xyz, frame.view[1].xyz, frame.view[2].xyz);
    if light.position_radius.w == 0.0 {
        // A directional light: its orthographic map, texels of one size everywhere.
        let sun = shadow_read.suns[slot];
        let texel = sun.texel.x;
        let lifted = p + n * (1.5 * texel);
        let world = transpose(rot) * (lifted - frame.view[3].xyz);
        let q = sun.to_map * vec4<f32>(world, 1.0);
        return filtered(q.xy * size - 0.5, i32(slot * 6u), q.z - texel);
    }
    let dist = distance(p, light.position_radius.xyz);
    let texel = 2.0 * dist / size;
    let lifted = p + n * (1.5 * texel);
    let d = transpose(rot) * (lifted - light.position_radius.xyz);
    let f = face_uv(d);
    let layer = i32(slot * 6u) + i32(f.x);
    return filtered(f.yz * size - 0.5, layer, length(d) - texel);
}

// The fraction of the pcf × pcf texels about texel coordinate `c` (texel centres at
// integers) of `layer` whose nearest surface lies at or beyond `reach`: 1 reads the nearest
// texel (a hard edge); from 2 on, the lookup's square of that side, its outer texels
// weighted bilinearly by how far the lookup falls toward them (2 is the 2×2 bilinear
// comparison hardware PCF does).
fn filtered(c: vec2<f32>, layer: i32, reach: f32) -> f32 {
    let last = i32(textureDimensions(shadow_cubes).x) - 1;
    let pcf = i32(shadow_read.pcf.x);
    if pcf <= 1 {
        let at = clamp(vec2<i32>(round(c)), vec2<i32>(0), vec2<i32>(last));
        return seen_at(at, layer, reach);
    }
    let k = pcf - 1;
    let base = vec2<i32>(floor(c)) - vec2<i32>((k - 1) / 2);
    let frac = fract(c);
    var seen = 0.0;
    for (var j = 0; j <= k; j++) {
        let wy = select(select(1.0, frac.y, j == k), 1.0 - frac.y, j == 0);
        for (var i = 0; i <= k; i++) {
            let wx = select(select(1.0, frac.x, i == k), 1.0 - frac.x, i == 0);
            let at = clamp(base + vec2<i32>(i, j), vec2<i32>(0), vec2<i32>(last));
            seen += wx * wy * seen_at(at, layer, reach);
        }
    }
    return seen / f32(k * k);
}
