// shadow_map.wgsl: one face of a shadow-casting point light's cube, or a light's one map
// (a directional light's orthographic one). Every opaque object of the scene (on screen or not) is drawn from the
// light, through a 90° face or the fitted box; each texel keeps the distance from the light
// (or the map's near plane) to the nearest surface (the target is cleared to a distance
// past every surface, so a texel that sees nothing never shadows). shadows.wgsl compares a
// receiver's own distance with it.
//
// Keep in sync with ShadowFace in crates/pelt-preview/src/features/shadows.rs.

#import pelt::common::{VertexIn}
#import pelt::object_bindings::{object}

struct ShadowFace {
    view_proj: mat4x4<f32>,
    // A cube's face: xyz the light's world position, w its radius. A light's one map: w = 0.
    light: vec4<f32>,
    // A light's one map: the distance from its near plane along its axis is dot(xyz, world) + w.
    plane: vec4<f32>,
}

@group(0) @binding(0) var<uniform> face: ShadowFace;

struct Caster {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
}

@vertex
fn vs_main(v: VertexIn) -> Caster {
    var o: Caster;
    let world = object.model * vec4<f32>(v.position, 1.0);
    o.clip = face.view_proj * world;
    o.world = world.xyz;
    return o;
}

// The distance as a half float and its half-float remainder (about 22 bits; GL renders to
// no 32-bit float target), as pack_geometry stores the distance maps'.
@fragment
fn fs_main(in: Caster) -> @location(0) vec4<f32> {
    var d = distance(in.world, face.light.xyz);
    if face.light.w == 0.0 {
        d = dot(face.plane.xyz, in.world) + face.plane.w;
    }
    let hi = bitcast<f32>(bitcast<u32>(d) & 0xffffe000u);
    return vec4<f32>(hi, d - hi, 0.0, 0.0);
}
