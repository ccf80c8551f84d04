// distance_map.wgsl: one face of one layer of a mirror or glass object's layered distance map
// (GPU Gems 3 ch. 17, §17.2.1). The scene is drawn from the reference point through a 90°
// cube face; each texel keeps, in two targets, the material (rgb radiance lit by the scene's
// lights with the same local lighting as the main view, seen from the reference point, a = 0;
// (its view-independent part: the specular is added where a ray meets the texel); or, for
// mirrors and glass, Listing 17-5's material: rgb F0 or tint, a = -1 or the IOR) and
// the geometry (the unit outward normal and the distance from the reference point, packed by
// common.wgsl's pack_geometry; the target is cleared to distance -1, so a texel with no
// surface has a negative distance).
// Fur objects go in as their shells (shells.wgsl's fs_distance, the fur code -2 in a).
// Layers: 0 keeps the object's own faces that face the reference point, 1 its faces that face
// away, 2 the nearest surfaces of the rest of the scene, 3.. the next ones, each peeled behind
// the layer before (the previous layer's distances come in as `peel`).
//
// Keep in sync with FaceUniforms in crates/pelt-preview/src/features/reflect/mod.rs.

#import pelt::common::{Light, VertexIn, light_reach, pack_geometry, one_light, texel_distance}
#import pelt::object_bindings::{object}

struct Face {
    view_proj: mat4x4<f32>,
    // xyz: the reference point (world); w: unused.
    reference: vec4<f32>,
    // rgb: ambient light; w: specular power.
    ambient: vec4<f32>,
    // x: the layer; y: light count; z: the map's object (scene index); w: the face (0..5).
    ids: vec4<u32>,
}

const MAX_MAP_LIGHTS: u32 = 256u;
// SUNS: whether any light of the view is directional; false compiles light_reach's branch on
// the kind out (lights.rs's `suns_for_view`).
override SUNS: bool = true;

@group(0) @binding(0) var<uniform> face: Face;
@group(2) @binding(0) var<uniform> lights: array<Light, MAX_MAP_LIGHTS>;
@group(3) @binding(0) var peel: texture_2d_array<f32>;

struct MapVertex {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) albedo: vec4<f32>,
}

@vertex
fn vs_main(v: VertexIn) -> MapVertex {
    var o: MapVertex;
    let world = object.model * vec4<f32>(v.position, 1.0);
    o.clip = face.view_proj * world;
    o.world = world.xyz;
    o.normal = (object.normal_model * vec4<f32>(v.normal, 0.0)).xyz;
    // Fur objects are drawn by shells.wgsl's fs_distance instead.
    o.albedo = v.albedo * vec4<f32>(object.tint.rgb, 1.0);
    return o;
}

struct Texel {
    @location(0) material: vec4<f32>,
    @location(1) geometry: vec4<f32>,
}

// The view-independent part of the forward pass's lighting at `p` (relative to the reference
// point) with `n` facing the reference point: ambient plus every light's diffuse, times the
// albedo. The specular, which depends on where the surface is seen from, is added where a
// ray finds the texel (reflect.wgsl), from the ray's own direction.
fn radiance(albedo: vec3<f32>, p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    var diffuse = face.ambient.rgb;
    let count = min(face.ids.y, MAX_MAP_LIGHTS);
    for (var i = 0u; i < count; i++) {
        var light = lights[i];
        // A point light's position relative to the reference point (a direction stays).
        if light.position_radius.w != 0.0 {
            light.position_radius = vec4<f32>(
                light.position_radius.xyz - face.reference.xyz,
                light.position_radius.w,
            );
        }
        diffuse += one_light(p, n, light_reach(p, light, SUNS), light, face.ambient.w).rgb;
    }
    return albedo * diffuse;
}

@fragment
fn fs_main(in: MapVertex) -> Texel {
    let rel = in.world - face.reference.xyz;
    let dist = length(rel);
    let n = normalize(in.normal);
    let layer = face.ids.x;
    let own = object.ids.x == face.ids.z;
    if layer <= 1u {
        // The object's own faces, split by whether they face the reference point.
        let facing = dot(n, rel) < 0.0;
        if !own || facing != (layer == 0u) {
            discard;
        }
    } else {
        if own {
            discard;
        }
        if layer >= 3u {
            let before = texel_distance(textureLoad(peel, vec2<i32>(in.clip.xy), i32(face.ids.w), 0));
            if before < 0.0 || dist <= before * 1.0005 {
                discard;
            }
        }
    }
    var t: Texel;
    t.geometry = pack_geometry(n, dist);
    if object.optics.a != 0.0 {
        t.material = object.optics;
    } else {
        let toward = select(-n, n, dot(n, rel) < 0.0);
        t.material = vec4<f32>(radiance(in.albedo.rgb, rel, toward), 0.0);
    }
    return t;
}
