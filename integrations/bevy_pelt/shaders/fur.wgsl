// fur.wgsl: pelt's forward fur in Bevy's main pass (shaders/shells.wgsl with
// fur_light_forward.wgsl in pelt): the base mesh (shell 0, opaque, lit along the strands) and
// the shells (1..n, blended over inner to outer), after Revie §2.3–2.4, lit with Kajiya-Kay
// (Listing 2.4) over Bevy's clustered lights and shadow maps (lights.wgsl).

#import bevy_pbr::{
    mesh_bindings::mesh,
    mesh_types::MESH_FLAGS_SHADOW_RECEIVER_BIT,
    mesh_view_bindings::view,
}
#import bevy_pelt::fur_shell::{FurVertex, FurVarying, fur, shell_vertex, coverage, under}
#import bevy_pelt::lights::{Site, lighting}

// pelt_scene::shading: the specular power and strength of every pelt surface.
const SPECULAR_POWER: f32 = 32.0;
const SPECULAR_STRENGTH: f32 = 0.25;

@vertex
fn vertex(v: FurVertex) -> FurVarying {
    return shell_vertex(v);
}

@fragment
fn fragment(in: FurVarying) -> @location(0) vec4<f32> {
    // Sampled before the discard (derivatives in uniform control flow).
    let base = under(in.uv);
    let a = coverage(in);
    if a <= 0.0 {
        discard;
    }
    var s: Site;
    s.world = vec4<f32>(in.shadow_at, 1.0);
    s.view = in.view_pos;
    s.normal = normalize(in.world_normal);
    s.frag = in.position;
    s.receiver = (mesh[in.instance_index].flags & MESH_FLAGS_SHADOW_RECEIVER_BIT) != 0u;
    let lit = lighting(s, normalize(in.strand), true, SPECULAR_POWER);
    let albedo = base * fur.tint.rgb * mix(fur.root.rgb, fur.tip.rgb, in.height.x);
    let c = albedo * lit.diffuse + SPECULAR_STRENGTH * lit.specular;
    return vec4<f32>(c * view.exposure, a);
}
