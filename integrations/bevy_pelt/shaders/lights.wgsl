// lights.wgsl: Bevy's lights as pelt's (shaders/common.wgsl `Light`), and the loops that sum
// them: every point light of the fragment's cluster (Bevy's clustered forward lists) and every
// directional light, each weighted by Bevy's shadow map for it. One light's term is pelt's own
// function: `strand_light` (Kajiya-Kay, Revie Listing 2.4) for fur, `one_light` (Blinn-Phong)
// for pelt's opaque surfaces, with pelt's windowed falloff, `window² / (1 + d²)`, reaching zero
// at the light's `range`.
//
// Units: a light's colour here is Bevy's radiometric value over π, what Bevy's own Lambert
// term applies (a point light's lumens / 4π, a directional light's lux); the ambient light is
// Bevy's ambient colour × brightness. docs/bevy.md gives the conversion from pelt's scene files.

#define_import_path bevy_pelt::lights

#import bevy_pbr::{
    mesh_view_bindings as view_bindings,
    mesh_view_types::{POINT_LIGHT_FLAGS_SHADOWS_ENABLED_BIT, DIRECTIONAL_LIGHT_FLAGS_SHADOWS_ENABLED_BIT},
    clustered_forward as clustering,
    shadows,
}
#import pelt::common::{Light, light_reach, one_light, strand_light, luminance}

const INV_PI: f32 = 0.31830988618;

// Where a fragment is: world and view-space position, the normal the shadow lookups offset
// along (world space), its frag coord and whether its mesh receives shadows.
struct Site {
    world: vec4<f32>,
    view: vec3<f32>,
    normal: vec3<f32>,
    frag: vec4<f32>,
    receiver: bool,
}

// What the lights add up to: diffuse (ambient included) and specular colour.
struct Lit {
    diffuse: vec3<f32>,
    specular: vec3<f32>,
}

fn pelt_light(rgb: vec3<f32>, position_radius: vec4<f32>) -> Light {
    var l: Light;
    l.position_radius = position_radius;
    let c = rgb * INV_PI;
    l.color = vec4<f32>(c, luminance(c));
    return l;
}

// Clustered light `id` (a point light) as pelt's, its position in view space.
fn point_light(id: u32) -> Light {
    let c = &view_bindings::clustered_lights.data[id];
    let p = (view_bindings::view.view_from_world * vec4<f32>((*c).position_radius.xyz, 1.0)).xyz;
    return pelt_light((*c).color_inverse_square_range.rgb, vec4<f32>(p, (*c).range));
}

// Directional light `i` as pelt's: its view-space direction toward the light, radius 0.
fn sun_light(i: u32) -> Light {
    let d = &view_bindings::lights.directional_lights[i];
    let v = normalize((view_bindings::view.view_from_world * vec4<f32>((*d).direction_to_light, 0.0)).xyz);
    return pelt_light((*d).color.rgb, vec4<f32>(v, 0.0));
}

fn point_shadow(id: u32, s: Site) -> f32 {
    let flags = view_bindings::clustered_lights.data[id].flags;
    if !s.receiver || (flags & POINT_LIGHT_FLAGS_SHADOWS_ENABLED_BIT) == 0u {
        return 1.0;
    }
    return shadows::fetch_point_shadow(id, s.world, s.normal, s.frag.xy);
}

fn sun_shadow(i: u32, s: Site) -> f32 {
    let flags = view_bindings::lights.directional_lights[i].flags;
    if !s.receiver || (flags & DIRECTIONAL_LIGHT_FLAGS_SHADOWS_ENABLED_BIT) == 0u {
        return 1.0;
    }
    return shadows::fetch_directional_shadow(i, s.world, s.normal, s.view.z, s.frag.xy);
}

// One light's term (rgb diffuse, a specular intensity) for a strand along view-space `t`
// (`strand`) or a surface with view-space normal `t`.
fn term(s: Site, t: vec3<f32>, l: Light, suns: bool, strand: bool, spec_power: f32) -> vec4<f32> {
    let r = light_reach(s.view, l, suns);
    if strand {
        return strand_light(s.view, t, r, l, spec_power);
    }
    return one_light(s.view, t, r, l, spec_power);
}

fn add(out: ptr<function, Lit>, v: vec4<f32>, l: Light) {
    (*out).diffuse += v.rgb;
    if l.color.w > 0.0 {
        (*out).specular += v.a * l.color.rgb / l.color.w;
    }
}

// Every light of the view at `s`: Kajiya-Kay along `t` when `strand`, else Blinn-Phong about
// the normal `t` (view space).
fn lighting(s: Site, t: vec3<f32>, strand: bool, spec_power: f32) -> Lit {
    var out: Lit;
    out.diffuse = view_bindings::lights.ambient_color.rgb;
    out.specular = vec3<f32>(0.0);
    let orthographic = view_bindings::view.clip_from_view[3].w == 1.0;
    let cluster = clustering::view_fragment_cluster_index(s.frag.xy, s.view.z, orthographic);
    let ranges = clustering::unpack_clusterable_object_index_ranges(cluster);
    for (var i = ranges.first_point_light_index_offset; i < ranges.first_spot_light_index_offset; i++) {
        let id = clustering::get_clusterable_object_id(i);
        let l = point_light(id);
        add(&out, term(s, t, l, false, strand, spec_power) * point_shadow(id, s), l);
    }
    let suns = view_bindings::lights.n_directional_lights;
    for (var i = 0u; i < suns; i++) {
        let l = sun_light(i);
        add(&out, term(s, t, l, true, strand, spec_power) * sun_shadow(i, s), l);
    }
    return out;
}
