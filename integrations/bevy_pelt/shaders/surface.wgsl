// surface.wgsl: pelt's forward opaque surface (shaders/forward.wgsl in pelt) as the fragment
// stage of a Bevy material: the base colour (factor × texture with its KHR_texture_transform)
// lit by Blinn-Phong over Bevy's lights (lights.wgsl), metal_rough as pelt. The scene files'
// objects without fur are drawn with it, so that a scene looks as in `pelt render`.

#import bevy_pbr::{
    forward_io::VertexOutput,
    mesh_bindings::mesh,
    mesh_types::MESH_FLAGS_SHADOW_RECEIVER_BIT,
    mesh_view_bindings::view,
    pbr_bindings,
}
#import pelt::common::{metal_rough, facing_normal}
#import bevy_pelt::lights::{Site, lighting}

const SPECULAR_POWER: f32 = 32.0;
const SPECULAR_STRENGTH: f32 = 0.25;

@fragment
fn fragment(in: VertexOutput, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let m = pbr_bindings::material;
#ifdef VERTEX_UVS_A
    let t = (m.uv_transform * vec3<f32>(in.uv, 1.0)).xy;
    let a = m.base_color * textureSample(pbr_bindings::base_color_texture, pbr_bindings::base_color_sampler, t);
#else
    let a = m.base_color;
#endif
    let wn = normalize(in.world_normal);
    let n = facing_normal((view.view_from_world * vec4<f32>(wn, 0.0)).xyz, front);
    var s: Site;
    s.world = in.world_position;
    s.view = (view.view_from_world * in.world_position).xyz;
    s.normal = select(-wn, wn, front);
    s.frag = in.position;
    s.receiver = (mesh[in.instance_index].flags & MESH_FLAGS_SHADOW_RECEIVER_BIT) != 0u;
    let lit = lighting(s, n, false, SPECULAR_POWER);
    let k = metal_rough(m.metallic, m.perceptual_roughness);
    let spec_tint = mix(vec3<f32>(1.0), a.rgb, m.metallic);
    let c = a.rgb * k.y * lit.diffuse + SPECULAR_STRENGTH * k.x * spec_tint * lit.specular;
    return vec4<f32>(c * view.exposure, a.a);
}
