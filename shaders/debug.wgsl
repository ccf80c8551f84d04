// debug.wgsl: the debug views, unlit. debug-groups: each normal group (Kircher & Lawrance
// §3.1) in the flat colour of its class, classes chosen on the CPU so that neighbouring
// groups differ (crates/pelt-scene/src/debug.rs). debug-comb: the comb decoded into the
// asset's space exactly as the fur passes decode it (fur_common.wgsl's comb_object), its
// direction as colour (x, y, z mapped from [-1, 1] to [0, 1]) and its length as brightness.
// Surfaces without a comb are drawn dark grey.

#import pelt::common::{VertexIn}
#import pelt::fur_common::{FurIn, comb_object}
#import pelt::object_bindings::{frame, object}

struct Flat {
    @builtin(position) clip: vec4<f32>,
    @location(0) @interpolate(flat) colour_class: u32,
    // How squarely the surface faces the eye, for shape.
    @location(1) facing: f32,
}

struct Combed {
    @builtin(position) clip: vec4<f32>,
    // The comb in the asset's space, w = its length.
    @location(0) comb: vec4<f32>,
}

// Brightness from how squarely the surface faces the eye, so that a flat colour still shows
// the shape: 0.6 edge-on to 1 face-on.
fn facing_of(v: VertexIn) -> f32 {
    let view = frame.view * object.model * vec4<f32>(v.position, 1.0);
    let n = (frame.view * object.normal_model * vec4<f32>(v.normal, 0.0)).xyz;
    let len = length(n) * length(view.xyz);
    return select(1.0, 0.6 + 0.4 * abs(dot(n, view.xyz)) / len, len > 0.0);
}

// Clip position of an asset-space point.
fn clip_of(p: vec3<f32>) -> vec4<f32> {
    return frame.proj * frame.view * object.model * vec4<f32>(p, 1.0);
}

// Class `c` of an object whose colours start `shift` places along the palette: twelve colours
// far apart in hue and lightness, so the first twelve classes of one object never match;
// classes past them walk the hue circle by the golden angle, darker than any of the twelve.
fn class_colour(c: u32, shift: u32) -> vec3<f32> {
    var palette = array<vec3<f32>, 12>(
        vec3<f32>(0.90, 0.10, 0.10), vec3<f32>(0.10, 0.60, 0.95), vec3<f32>(0.95, 0.85, 0.10),
        vec3<f32>(0.15, 0.75, 0.20), vec3<f32>(0.65, 0.20, 0.85), vec3<f32>(0.95, 0.50, 0.05),
        vec3<f32>(0.05, 0.85, 0.80), vec3<f32>(0.95, 0.45, 0.70), vec3<f32>(0.45, 0.30, 0.10),
        vec3<f32>(0.55, 0.55, 0.55), vec3<f32>(0.05, 0.15, 0.55), vec3<f32>(0.70, 0.95, 0.55),
    );
    if c < 12u {
        return palette[(c + shift) % 12u];
    }
    let h = fract(f32(c) * 0.618034) * 6.0;
    let k = vec3<f32>(5.0, 3.0, 1.0);
    let rgb = clamp(abs(fract((h + k) / 6.0) * 6.0 - 3.0) - 1.0, vec3<f32>(0.0), vec3<f32>(1.0));
    return mix(vec3<f32>(0.1), rgb, 0.5);
}

@vertex
fn vs_groups(v: VertexIn, @location(4) colour_class: u32) -> Flat {
    var o: Flat;
    o.clip = clip_of(v.position);
    o.colour_class = colour_class;
    o.facing = facing_of(v);
    return o;
}

@fragment
fn fs_groups(s: Flat) -> @location(0) vec4<f32> {
    // Each object's palette starts at its ID: objects that touch (a creature on its ground)
    // rarely match.
    return vec4<f32>(class_colour(s.colour_class, object.ids.x) * s.facing, 1.0);
}

@vertex
fn vs_comb(v: VertexIn, fur: FurIn) -> Combed {
    var o: Combed;
    o.clip = clip_of(v.position);
    o.comb = vec4<f32>(comb_object(v.normal, fur.tangent, fur.comb.xyz), fur.comb.w);
    return o;
}

@fragment
fn fs_comb(s: Combed) -> @location(0) vec4<f32> {
    let len = length(s.comb.xyz);
    if s.comb.w <= 0.0 || len <= 1e-6 {
        return vec4<f32>(0.08, 0.08, 0.08, 1.0);
    }
    let dir = s.comb.xyz / len * 0.5 + 0.5;
    return vec4<f32>(dir * clamp(s.comb.w, 0.0, 1.0), 1.0);
}

@vertex
fn vs_plain(v: VertexIn) -> Flat {
    var o: Flat;
    o.clip = clip_of(v.position);
    o.colour_class = 0u;
    o.facing = facing_of(v);
    return o;
}

@fragment
fn fs_plain(s: Flat) -> @location(0) vec4<f32> {
    return vec4<f32>(vec3<f32>(0.08) * s.facing, 1.0);
}
