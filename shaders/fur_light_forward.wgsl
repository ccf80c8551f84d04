// fur_light_forward.wgsl: the forward-shaded fur Revie provides for asset tools (§2.4), here
// the reference the deferred approximation is measured against: every light evaluated at the
// strand itself with the Kajiya-Kay model of Listing 2.4 (after Heidrich & Seidel), whose
// terms depend on the strand direction T rather than a normal:
//   diffuse  = sqrt(1 − (L·T)²)
//   specular = (sqrt(1 − (L·T)²) · sqrt(1 − (V·T)²) − (L·T)(V·T))^p
// with the same windowed inverse-square falloff as every other light in the preview. With the
// SHADOWS def (a view with a shadow-casting light), each light is weighted by how much of it
// the strand sees (shadows.wgsl, stepping off the strand toward the light).

#define_import_path pelt::fur_light_forward
#import pelt::common::{Light, light_reach}
#import pelt::fur_common::{FurLight, FurQuery}
#import pelt::object_bindings::{frame}
#ifdef SHADOWS
#import pelt::shadows::{shadow_seen}
#endif

@group(2) @binding(0) var<uniform> lights: array<Light, 256>;

fn fur_lighting(q: FurQuery) -> FurLight {
    var out: FurLight;
    out.diffuse = frame.ambient.rgb;
    let t = q.strand;
    let v = normalize(-q.view_pos);
    let vt = dot(v, t);
    let sin_v = sqrt(max(1.0 - vt * vt, 0.0));
    let count = min(frame.flags.y, 256u);
    for (var i = 0u; i < count; i++) {
        let light = lights[i];
        let r = light_reach(q.view_pos, light);
        if r.w == 0.0 {
            continue;
        }
        let l = r.xyz;
        let atten = r.w;
        let lt = dot(l, t);
        let sin_l = sqrt(max(1.0 - lt * lt, 0.0));
        var seen = atten;
#ifdef SHADOWS
        seen *= shadow_seen(q.view_pos, l, light);
#endif
        out.diffuse += light.color.rgb * sin_l * seen;
        let spec = pow(max(sin_l * sin_v - lt * vt, 0.0), frame.ambient.w) * seen;
        out.specular += light.color.rgb * spec;
    }
    return out;
}
