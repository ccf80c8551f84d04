// fur_light_forward.wgsl: the forward-shaded fur Revie provides for asset tools (§2.4), here
// the reference the deferred approximation is measured against: every light evaluated at the
// strand itself with the Kajiya-Kay model of Listing 2.4 (after Heidrich & Seidel), whose
// terms depend on the strand direction T rather than a normal:
//   diffuse  = sqrt(1 − (L·T)²)
//   specular = (sqrt(1 − (L·T)²) · sqrt(1 − (V·T)²) − (L·T)(V·T))^p
// with the same windowed inverse-square falloff as every other light in the preview. With the
// SHADOWS def (a view with a shadow-casting light), each light is weighted by how much of it
// the strand sees (shadows.wgsl, strand_shadow_seen); with the
// TRACED_SHADOWS def (the strand reference), by the strand's own shadow rays instead.

#define_import_path pelt::fur_light_forward
#import pelt::common::{Light, light_reach}
#import pelt::fur_common::{FurLight, FurQuery}
#import pelt::object_bindings::{frame}
#ifndef TRACED_SHADOWS
#ifdef SHADOWS
#import pelt::shadows::{strand_shadow_seen}
#endif
#endif

#ifdef TRACED_SHADOWS
// Bit `b` of the strand's shadow bits.
fn traced_bit(q: FurQuery, b: u32) -> f32 {
    let word = select(q.traced.x, q.traced.y, b >= 32u);
    return f32((word >> (b & 31u)) & 1u);
}

// How much of `light` the strand point of `q` sees: its segment's two ends' shadow rays,
// blended along it (1 for a light that casts no shadows).
fn traced_seen(q: FurQuery, light: Light) -> f32 {
    if light.shadow.x == 0u {
        return 1.0;
    }
    let b = 5u * (light.shadow.x - 1u) + q.segment;
    return mix(traced_bit(q, b), traced_bit(q, b + 1u), q.along);
}
#endif

@group(2) @binding(0) var<uniform> lights: array<Light, 256>;

// `suns`: the caller's SUNS override (whether the view may hold a directional light).
fn fur_lighting(q: FurQuery, suns: bool) -> FurLight {
    var out: FurLight;
    out.diffuse = frame.ambient.rgb;
    let t = q.strand;
    let v = normalize(-q.view_pos);
    let vt = dot(v, t);
    let sin_v = sqrt(max(1.0 - vt * vt, 0.0));
    let count = min(frame.flags.y, 256u);
    for (var i = 0u; i < count; i++) {
        let light = lights[i];
        let r = light_reach(q.view_pos, light, suns);
        if r.w == 0.0 {
            continue;
        }
        let l = r.xyz;
        let atten = r.w;
        let lt = dot(l, t);
        let sin_l = sqrt(max(1.0 - lt * lt, 0.0));
        var seen = atten;
#ifdef TRACED_SHADOWS
        seen *= traced_seen(q, light);
#else
#ifdef SHADOWS
#ifdef FUR_SHADOWS
        seen *= strand_shadow_seen(q.view_pos, t, 0.0, light, true);
#else
        seen *= strand_shadow_seen(q.view_pos, t, 0.0, light, false);
#endif
#endif
#endif
        out.diffuse += light.color.rgb * sin_l * seen;
        let spec = pow(max(sin_l * sin_v - lt * vt, 0.0), frame.ambient.w) * seen;
        out.specular += light.color.rgb * spec;
    }
    return out;
}
