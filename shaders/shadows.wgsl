// shadows.wgsl: how much of a light a surface sees, from a point light's shadow cube or a
// light's one projective map (a directional light's orthographic one; shadow_map.wgsl), one lookup per lit pixel: in the light pass per L-buffer pixel, so
// opaque surfaces and every stippled alpha layer receive it (Kircher & Lawrance §4), and in
// the forward pass per pixel, identically.
//
// Each texel of the lookup's square of PCF × PCF texels (percentage-closer filtering) is
// compared with the receiver's own tangent plane where that texel sees it (receiver plane
// depth bias, Isidoro 2006), the receiver lifted a quarter texel along its normal and
// compared half a texel nearer (texels of the map at its distance: a cube's grow with the
// distance, a map's with the depth its `w` gives, one size in an orthographic map). The maps
// and how to read them are lighting inputs (lighting_inputs.wgsl).
//
// Fur shadows by its coverage through deep opacity maps (Yuksel & Keyser 2008): in each
// layer of the cubes, the distance to the nearest fur (zw), and beside it up to three layers
// of the fur's optical depth seen from the light, each summed to its boundary past the nearest
// fur. The opaque visibility is multiplied by exp(−τ), bilinear over the 2×2 texels of the
// lookup, τ read at the receiver's depth past the nearest fur, linear between the layers'
// boundaries (none in front of the fur, the last layer's past it): fur shadows itself, and
// its shadow on everything behind it is as soft as the fur is thin.

#define_import_path pelt::shadows

#import pelt::common::{Light, face_uv}
#import pelt::lighting_inputs::{fur_opacity, fur_read, shadow_cubes, shadow_read}
#import pelt::object_bindings::{frame}

// The distance from the light to the nearest surface in texel `at` of cube face `layer`
// (shadow_map.wgsl's two halves).
fn nearest(at: vec2<i32>, layer: i32) -> f32 {
    let t = textureLoad(shadow_cubes, at, layer, 0);
    return t.x + t.y;
}

// The fur's optical depth between the light and distance `reach` in texel `at` of `layer`:
// piecewise linear through (0, 0) and each opacity layer's (boundary, value), the last value
// past it; none where the texel holds no fur or in front of it. A sum of clamped segments,
// without branches (a CPU rasterizer runs every side of a branch its lanes disagree on).
fn fur_depth(at: vec2<i32>, layer: i32, reach: f32) -> f32 {
    let near = textureLoad(shadow_cubes, at, layer, 0);
    let x = reach - (near.z + near.w);
    let b = fur_read.layers;
    let t = textureLoad(fur_opacity, at, layer, 0).xyz;
    let s0 = t.x * clamp(x / b.x, 0.0, 1.0);
    let s1 = (t.y - t.x) * clamp((x - b.x) / (b.y - b.x), 0.0, 1.0);
    let s2 = (t.z - t.y) * clamp((x - b.y) / (b.z - b.y), 0.0, 1.0);
    let tau = s0 + select(0.0, s1, b.w >= 2.0) + select(0.0, s2, b.w >= 3.0);
    return select(tau, 0.0, near.z == 0.0);
}

// The fur's transmittance toward the light at distance `reach`, bilinear over the 2×2 texels
// about texel coordinate `c` of `layer`.
fn fur_seen(c: vec2<f32>, layer: i32, reach: f32) -> f32 {
    let last = i32(textureDimensions(shadow_cubes).x) - 1;
    let base = vec2<i32>(floor(c));
    let f = fract(c);
    let lo = clamp(base, vec2<i32>(0), vec2<i32>(last));
    let hi = clamp(base + vec2<i32>(1), vec2<i32>(0), vec2<i32>(last));
    let t00 = exp(-fur_depth(lo, layer, reach));
    let t10 = exp(-fur_depth(vec2<i32>(hi.x, lo.y), layer, reach));
    let t01 = exp(-fur_depth(vec2<i32>(lo.x, hi.y), layer, reach));
    let t11 = exp(-fur_depth(hi, layer, reach));
    return mix(mix(t00, t10, f.x), mix(t01, t11, f.x), f.y);
}

// The fraction (0 to 1) of `light` that view-space point `p` with unit normal `n` sees; 1
// for a light that casts no shadows. `fur`: the fur's opacity layers are read too (a
// pipeline constant in the caller, so the lookup is compiled out where no fur casts).
// A lift along the normal would move the shadow sideways by the lift times the tangent of
// the light's angle, so the receiver plane (header) does the work and the lift is small.
fn shadow_seen(p: vec3<f32>, n: vec3<f32>, light: Light, fur: bool) -> f32 {
    if light.shadow.x == 0u {
        return 1.0;
    }
    let slot = light.shadow.x - 1u;
    let size = f32(textureDimensions(shadow_cubes).x);
    // View to world: the view's rotation is orthonormal, so its inverse is its transpose.
    let to_world = transpose(mat3x3<f32>(frame.view[0].xyz, frame.view[1].xyz, frame.view[2].xyz));
    let nw = to_world * n;
    let map = shadow_read.maps[slot];
    if map.texel.x > 0.0 {
        // The light's one map: texels as large as its depth at the receiver makes them.
        let own = to_world * (p - frame.view[3].xyz);
        let texel = map.texel.x * (map.to_map * vec4<f32>(own, 1.0)).w;
        let world = own + nw * (LIFT * texel);
        let at = map_point(map.to_map, world, size);
        let e = tangents(nw);
        let a = map_point(map.to_map, world + e[0] * texel, size) - at;
        let b = map_point(map.to_map, world + e[1] * texel, size) - at;
        let slope = plane_slope(a, b, texel);
        return with_fur(at.xy, i32(slot * 6u), at.z - NEARER * texel, slope, fur);
    }
    let dist = distance(p, light.position_radius.xyz);
    let texel = 2.0 * dist / size;
    let d = to_world * (p + n * (LIFT * texel) - light.position_radius.xyz);
    let f = face_uv(d);
    let face = i32(f.x);
    let e = tangents(nw);
    let at = vec3<f32>(f.yz * size - 0.5, length(d));
    let axes = face_axes(face);
    let a = cube_point(d + e[0] * texel, axes, size) - at;
    let b = cube_point(d + e[1] * texel, axes, size) - at;
    let slope = plane_slope(a, b, texel);
    return with_fur(at.xy, i32(slot * 6u) + face, at.z - NEARER * texel, slope, fur);
}

// How far along its normal a receiver is lifted, and how much nearer than its plane it is
// compared, in texels of the map at its distance.
const LIFT: f32 = 0.25;
const NEARER: f32 = 0.5;

// The steepest receiver plane followed (its depth per texel, in texels): about 88.6° from
// facing the light; a steeper plane is compared as this one, and its n·l shading is dim.
const MAX_SLOPE: f32 = 40.0;

// World point `w` in a projective map: (texel coordinates, texel centres at integers; the
// distance the map stores).
fn map_point(to_map: mat4x4<f32>, w: vec3<f32>, size: f32) -> vec3<f32> {
    let q = to_map * vec4<f32>(w, 1.0);
    return vec3<f32>(q.xy / q.w * size - 0.5, q.z);
}

// Cube face `face`'s axes in face_uv's layout: its s and t directions and its major axis,
// without a branch per face (selects).
fn face_axes(face: i32) -> mat3x3<f32> {
    let axis = face / 2;
    let sg = f32(1 - 2 * (face % 2));
    let major = sg * vec3<f32>(f32(axis == 0), f32(axis == 1), f32(axis == 2));
    let s = select(select(vec3<f32>(sg, 0.0, 0.0), vec3<f32>(1.0, 0.0, 0.0), axis == 1), vec3<f32>(0.0, 0.0, -sg), axis == 0);
    let t = select(vec3<f32>(0.0, -1.0, 0.0), vec3<f32>(0.0, 0.0, sg), axis == 1);
    return mat3x3<f32>(s, t, major);
}

// Light-relative world direction `d` on the cube face whose axes are `axes` (face_axes),
// whatever its major axis: (texel coordinates, the distance to the light).
fn cube_point(d: vec3<f32>, axes: mat3x3<f32>, size: f32) -> vec3<f32> {
    let st = d * axes;
    let uv = (st.xy / max(st.z, 1e-20) + 1.0) * 0.5;
    return vec3<f32>(uv * size - 0.5, length(d));
}

// Two unit vectors spanning the plane normal to unit `n`.
fn tangents(n: vec3<f32>) -> array<vec3<f32>, 2> {
    let helper = select(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), abs(n.x) > 0.9);
    let u = normalize(cross(n, helper));
    return array<vec3<f32>, 2>(u, cross(n, u));
}

// The receiver plane's stored distance per texel along the map's two axes, from two steps
// within it (`a`, `b`: each its change of texel coordinates and distance), its length held
// to MAX_SLOPE texels of `texel` (a plane seen edge-on by the light steps no texels).
fn plane_slope(a: vec3<f32>, b: vec3<f32>, texel: f32) -> vec2<f32> {
    let det = a.x * b.y - a.y * b.x;
    let s = vec2<f32>(a.z * b.y - b.z * a.y, b.z * a.x - a.z * b.x) / det;
    let limit = MAX_SLOPE * texel;
    let len = length(s);
    return select(vec2<f32>(0.0), s * min(1.0, limit / len), abs(det) > 1e-12 && len > 0.0);
}

// shadow_seen for a point on a strand, view-space `p` on a strand running along unit `t` from
// its root. Against the opaque casters the point is lifted along the strand, away from the
// surface it grows from, as a surface is along its normal (a lift toward the light would
// carry the root of a strand lit from behind its own surface, a light inside or under it,
// through that surface and out of its shadow); the fur's optical depth is read where the
// point lies, one and a half texels toward the light and one nearer. `slack`: how far `p` may
// be from the strand (world units; the light pass's depth step, 0 in the forward pass),
// compared that much nearer.
fn strand_shadow_seen(p: vec3<f32>, t: vec3<f32>, slack: f32, light: Light, fur: bool) -> f32 {
    if light.shadow.x == 0u {
        return 1.0;
    }
    let slot = light.shadow.x - 1u;
    let size = f32(textureDimensions(shadow_cubes).x);
    let to_world = transpose(mat3x3<f32>(frame.view[0].xyz, frame.view[1].xyz, frame.view[2].xyz));
    var seen: f32;
    var c: vec2<f32>;
    var layer: i32;
    var fur_reach: f32;
    let map = shadow_read.maps[slot];
    if map.texel.x > 0.0 {
        let q = map.to_map * vec4<f32>(to_world * (p - frame.view[3].xyz), 1.0);
        let texel = map.texel.x * q.w;
        let lifted = p + t * (1.5 * texel);
        let ql = map.to_map * vec4<f32>(to_world * (lifted - frame.view[3].xyz), 1.0);
        layer = i32(slot * 6u);
        seen = filtered(ql.xy / ql.w * size - 0.5, layer, ql.z - texel - slack, vec2<f32>(0.0));
        c = q.xy / q.w * size - 0.5;
        fur_reach = q.z - 2.5 * texel - slack;
    } else {
        let dist = distance(p, light.position_radius.xyz);
        let texel = 2.0 * dist / size;
        let dl = to_world * (p + t * (1.5 * texel) - light.position_radius.xyz);
        let fl = face_uv(dl);
        seen = filtered(fl.yz * size - 0.5, i32(slot * 6u) + i32(fl.x), length(dl) - texel - slack, vec2<f32>(0.0));
        let f = face_uv(to_world * (p - light.position_radius.xyz));
        c = f.yz * size - 0.5;
        layer = i32(slot * 6u) + i32(f.x);
        fur_reach = dist - 2.5 * texel - slack;
    }
    if !fur {
        return seen;
    }
    return seen * fur_seen(c, layer, fur_reach);
}

// The opaque casters' filtered visibility at texel coordinate `c` of `layer` and distance
// `reach`, times the fur's transmittance there when the fur casts (deep opacity layers).
fn with_fur(c: vec2<f32>, layer: i32, reach: f32, slope: vec2<f32>, fur: bool) -> f32 {
    let seen = filtered(c, layer, reach, slope);
    if !fur {
        return seen;
    }
    return seen * fur_seen(c, layer, reach);
}

// The fraction of the pcf × pcf texels about texel coordinate `c` (texel centres at
// integers) of `layer` whose nearest surface lies at or beyond `reach`: 1 reads the nearest
// texel (a hard edge); from 2 on, the lookup's square of that side, its outer texels
// weighted bilinearly by how far the lookup falls toward them (2 is the 2×2 bilinear
// comparison hardware PCF does).
fn filtered(c: vec2<f32>, layer: i32, reach: f32, slope: vec2<f32>) -> f32 {
    let last = i32(textureDimensions(shadow_cubes).x) - 1;
    let pcf = i32(shadow_read.pcf.x);
    if pcf <= 1 {
        let at = clamp(vec2<i32>(round(c)), vec2<i32>(0), vec2<i32>(last));
        return select(0.0, 1.0, reach + dot(slope, round(c) - c) <= nearest(at, layer));
    }
    let k = pcf - 1;
    let base = vec2<i32>(floor(c)) - vec2<i32>((k - 1) / 2);
    let frac = fract(c);
    var seen = 0.0;
    for (var j = 0; j <= k; j++) {
        let wy = select(select(1.0, frac.y, j == k), 1.0 - frac.y, j == 0);
        for (var i = 0; i <= k; i++) {
            let wx = select(select(1.0, frac.x, i == k), 1.0 - frac.x, i == 0);
            let tap = base + vec2<i32>(i, j);
            let at = clamp(tap, vec2<i32>(0), vec2<i32>(last));
            let own = reach + dot(slope, vec2<f32>(tap) - c);
            seen += wx * wy * select(0.0, 1.0, own <= nearest(at, layer));
        }
    }
    return seen / f32(k * k);
}
