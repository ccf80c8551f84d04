// forward.wgsl: the forward reference (Kircher & Lawrance §1, §6): every object loops over
// every light per pixel, O(objects × lights). Same lighting model as light.wgsl, evaluated at
// full resolution, with the specular colour taken from each light rather than rebuilt, and the
// same material textures as the G-buffer and material passes read.

#import pelt::common::{Light, Surface, VertexIn, facing_normal, metal_rough, perturb_normal, light_reach, one_light, to_surface}
#import pelt::object_bindings::{frame, object}
#import pelt::shadows::{shadow_seen}
#import pelt::material_bindings::{base_sampler, base_texture, material, mr_sampler, mr_texture, normal_sampler, normal_texture}

const MAX_FORWARD_LIGHTS: u32 = 256u;

@group(2) @binding(0) var<uniform> lights: array<Light, MAX_FORWARD_LIGHTS>;

// TEXTURED: the pipeline of materials with textures (true) or of those without (false),
// which read the neutral texel's values (white base colour, metallic-roughness 1, no normal
// map) without sampling: an untextured material pays for no texture fetch. Keep the neutral
// values in sync with crates/pelt-preview/src/gpu_material.rs.
override TEXTURED: bool = true;
// SUNS: whether any light of the view is directional; false compiles light_reach's branch on
// the kind out, so a view of point lights pays nothing for directional ones.
override SUNS: bool = true;
// SHADOWS: whether any light of the view casts shadows; false compiles the lookup out.
override SHADOWS: bool = true;
// FUR_SHADOWS: whether the fur casts by its coverage too (deep opacity maps); false compiles
// that lookup out.
override FUR_SHADOWS: bool = true;

@vertex
fn vs_main(v: VertexIn) -> Surface {
    return to_surface(v, frame, object);
}

@fragment
fn fs_main(s: Surface, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var base_color = vec4<f32>(1.0);
    var mr = vec4<f32>(1.0);
    var n = facing_normal(s.view_normal, front);
    if TEXTURED {
        base_color = textureSample(base_texture, base_sampler, s.uv);
        mr = textureSample(mr_texture, mr_sampler, s.uv);
        let stored = textureSample(normal_texture, normal_sampler, s.uv).xyz;
        if material.flags.x == 1u {
            n = perturb_normal(n, s.view_pos, s.uv, stored, material.factors.x);
        }
    }
    let albedo = s.albedo * base_color;
    var diffuse = frame.ambient.rgb;
    var specular = vec3<f32>(0.0);
    let count = min(frame.flags.y, MAX_FORWARD_LIGHTS);
    for (var i = 0u; i < count; i++) {
        let light = lights[i];
        var r = one_light(s.view_pos, n, light_reach(s.view_pos, light, SUNS), light, frame.ambient.w);
        if SHADOWS {
            if any(r != vec4<f32>(0.0)) {
                r *= shadow_seen(s.view_pos, n, light, FUR_SHADOWS);
            }
        }
        diffuse += r.rgb;
        if light.color.w > 0.0 {
            specular += r.a * light.color.rgb / light.color.w;
        }
    }
    let metal = material.factors.y * mr.b;
    let k = metal_rough(metal, material.factors.z * mr.g);
    let spec_tint = mix(vec3<f32>(1.0), albedo.rgb, metal);
    let color = albedo.rgb * k.y * diffuse + object.params.y * k.x * spec_tint * specular;
    return vec4<f32>(color, object.params.x * albedo.a);
}
