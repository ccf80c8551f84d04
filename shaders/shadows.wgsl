// shadows.wgsl: how much of a point light a surface sees, from the light's shadow cube
// (shadow_map.wgsl), one lookup per lit pixel: in the light pass per L-buffer pixel, so
// opaque surfaces and every stippled alpha layer receive it (Kircher & Lawrance §4), and in
// the forward pass per pixel, identically.
//
// The receiver is lifted off its surface along its normal by one and a half texels of the
// cube at its distance, and compared one texel nearer than itself (the bias grows with the
// distance, as the texels do), over a square of PCF × PCF texels (percentage-closer
// filtering). The group is `slot::CUBES` in crates/pelt-preview/src/features/shadows.rs.

#define_import_path pelt::shadows

#import pelt::common::{Light, face_uv}
#import pelt::object_bindings::{frame}

// How to read the cubes. Keep in sync with ShadowRead in
// crates/pelt-preview/src/features/shadows.rs.
struct ShadowRead {
    // x: the PCF side in texels (the scene's shadowMaps.pcf); yzw: unused.
    pcf: vec4<u32>,
}

@group(4) @binding(0) var shadow_cubes: texture_2d_array<f32>;
@group(4) @binding(1) var<uniform> shadow_read: ShadowRead;

// The distance from the light to the nearest surface in texel `at` of cube face `layer`
// (shadow_map.wgsl's two halves).
fn nearest(at: vec2<i32>, layer: i32) -> f32 {
    let t = textureLoad(shadow_cubes, at, layer, 0);
    return t.x + t.y;
}

// The fraction (0 to 1) of `light` that view-space point `p` with unit normal `n` sees; 1
// for a light that casts no shadows.
fn shadow_seen(p: vec3<f32>, n: vec3<f32>, light: Light) -> f32 {
    if light.shadow.x == 0u {
        return 1.0;
    }
    let dist = distance(p, light.position_radius.xyz);
    let size = f32(textureDimensions(shadow_cubes).x);
    let texel = 2.0 * dist / size;
    let lifted = p + n * (1.5 * texel);
    // View to world directions: the view's rotation is orthonormal, so its inverse is its
    // transpose.
    let rot = mat3x3<f32>(frame.view[0].xyz, frame.view[1].xyz, frame.view[2].xyz);
    let d = transpose(rot) * (lifted - light.position_radius.xyz);
    let f = face_uv(d);
    let layer = i32((light.shadow.x - 1u) * 6u) + i32(f.x);
    let reach = length(d) - texel;
    // pcf × pcf texels compared: 1 reads the nearest texel (a hard edge); from 2 on, the
    // lookup's square of that side, its outer texels weighted bilinearly by how far the lookup
    // falls toward them (2 is the 2×2 bilinear comparison hardware PCF does).
    let last = i32(size) - 1;
    let c = f.yz * size - 0.5;
    let pcf = i32(shadow_read.pcf.x);
    if pcf <= 1 {
        let at = clamp(vec2<i32>(round(c)), vec2<i32>(0), vec2<i32>(last));
        return select(0.0, 1.0, reach <= nearest(at, layer));
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
            seen += wx * wy * select(0.0, 1.0, reach <= nearest(at, layer));
        }
    }
    return seen / f32(k * k);
}
