// reflect.wgsl: mirrors and glass in the material (or forward) pass, by ray tracing their
// layered distance maps (GPU Gems 3 ch. 17). Per pixel: Listing 17-5's loop of reflections
// and refractions: Schlick's Fresnel for mirrors (F0 from n and k for metals, §17.3), the exact
// dielectric Fresnel for glass (Schlick's does not vanish at IOR 1), total internal
// reflection, and up to MAXDEPTH bounces; each next hit found by Hit(): a linear search per
// layer stepping uniformly in texture space between the projections of the ray's ends
// (Listing 17-1, Figure 17-3), clipped to the layer's min-max shell (Figure 17-4), the layer
// with the nearest refined hit taken; each bracket refined by a secant search (Listing 17-2)
// that keeps one undershooting and one overshooting bound, and dropped when the refinement
// does not land on the surface (the ray passed behind a silhouette). With the silhouettes
// knob, a ray that found no hit but passed behind a silhouette and ended behind a stored
// surface meets the farther surface of that silhouette (what the reference point cannot see
// is in no layer). The maps are
// 2D arrays (map, layer, face) read with textureLoad (a cube view cannot be); distances are
// filtered bilinearly within a face unless the four texels straddle a silhouette or an empty
// texel, where the nearest texel is taken. Technique 1 (environment mapping, the baseline)
// looks the direction up in the nearest layer of the rest of the scene instead of searching.
// A path that reaches another mirror or glass object continues in that object's map (Listing
// 17-5 stays in the first; the reached object's own layers see the scene from where the path
// now is). At the surface the camera sees, glass both reflects and refracts (two paths); a path that
// leaves the scene ends in the sky, and one still on a mirror after MAXDEPTH bounces ends in
// the sky in its mirror direction (pelt-trace's path.rs follows the same rules).
//
// Keep in sync with ReflectUniforms in crates/pelt-preview/src/features/reflect/mod.rs.

#import pelt::common::{Light, VertexIn, face_uv, light_reach, oct_decode, procedural, texel_distance}
#import pelt::object_bindings::{frame, object}

const MAX_MAPS: u32 = 64u;
const MAX_MAP_LIGHTS: u32 = 256u;
// SUNS: whether any light of the view is directional; false compiles light_reach's branch on
// the kind out (lights.rs's `suns_for_view`).
override SUNS: bool = true;

struct Reflect {
    // x: linear steps per quarter turn; y: secant steps; z: layers; w: most bounces.
    knobs: vec4<u32>,
    // x: min-max on (bit 0), silhouettes on (bit 1), maps (bits 8..); y: technique (0 distance maps, 1 environment map); z: sky (0 background,
    // 1 procedural, 2 cube map); w: cube face size.
    flags: vec4<u32>,
    // rgb: the background (no sky); w: the scene's radius.
    background: vec4<f32>,
    // x: specular strength; y: specular power; z: light count.
    shading: vec4<f32>,
    // xyz: each map's reference point (world); w: the radius about it that holds the whole
    // scene.
    maps: array<vec4<f32>, MAX_MAPS>,
    // xyz: each map's object's bounds centre (world); w: the radius of its bounds.
    objects: array<vec4<f32>, MAX_MAPS>,
}

@group(2) @binding(0) var material_maps: texture_2d_array<f32>;
@group(2) @binding(1) var geometry_maps: texture_2d_array<f32>;
@group(2) @binding(2) var<storage, read> ranges: array<vec2<f32>>;
@group(2) @binding(3) var<uniform> params: Reflect;
@group(2) @binding(4) var<uniform> lights: array<Light, MAX_MAP_LIGHTS>;
@group(3) @binding(0) var sky_cube: texture_cube<f32>;
@group(3) @binding(1) var sky_sampler: sampler;

struct Out {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

@vertex
fn vs_main(v: VertexIn) -> Out {
    var o: Out;
    let world = object.model * vec4<f32>(v.position, 1.0);
    o.clip = frame.proj * frame.view * world;
    o.world = world.xyz;
    o.normal = (object.normal_model * vec4<f32>(v.normal, 0.0)).xyz;
    return o;
}

// ---- Reading the maps ----


struct Taps {
    // The four texels (or the nearest one four times), their bilinear weights, and the
    // geometry texels already read (packed: decode with oct_decode and texel_distance).
    at: array<vec2<i32>, 4>,
    w: vec4<f32>,
    layer: i32,
    g: array<vec4<f32>, 4>,
}

// Whether the search handles silhouettes (the `silhouettes` knob): one_surface and
// behind_silhouette.
fn silhouettes() -> bool {
    return (params.flags.x & 2u) != 0u;
}

// The array layer and texel coordinates (continuous, texel centres at .5) of direction d in
// layer `layer` of map `map`.
fn texel_of(map: u32, layer: u32, d: vec3<f32>) -> vec3<f32> {
    let fuv = face_uv(d);
    let l = f32((map * params.knobs.z + layer) * 6u) + fuv.x;
    return vec3<f32>(fuv.yz * f32(params.flags.w), l);
}

// Whether taps whose normals agree (`n`) and whose distances run from `lo` to `far` can be
// one surface seen in direction `d`: a plane changes distance by about |p| tan(theta) per
// radian of direction (theta between its normal and the direction), and a texel spans
// about 2 / size radians, so a plane facing the reference point cannot differ by much across
// four taps. Two parallel surfaces at different distances fail it (a box's face before a
// wall parallel to it: filtered, the two made a slope in mid-air that the search took for a
// surface); a plane seen edge-on passes.
fn one_surface(d: vec3<f32>, n: vec3<f32>, lo: f32, far: f32) -> bool {
    let c = max(abs(dot(normalize(d), n)), 1e-3);
    let tan_t = sqrt(max(1.0 - c * c, 0.0)) / c;
    return far - lo <= lo * 3.0 * (2.0 / f32(params.flags.w)) * tan_t;
}

// The texels to read for direction d in layer `layer` of map `map`: bilinear within the face,
// unless the taps straddle a silhouette (distances more than 10% apart, and normals that
// disagree or, with silhouettes on, a step no one plane makes: one_surface; a plane seen
// edge-on from the reference point keeps its bilinear taps) or an empty texel; then the
// nearest.
fn taps(map: u32, layer: u32, d: vec3<f32>) -> Taps {
    let tc = texel_of(map, layer, d);
    let size = i32(params.flags.w);
    var t: Taps;
    t.layer = i32(tc.z);
    let p = tc.xy - 0.5;
    let p0 = floor(p);
    let f = p - p0;
    let hi = vec2<i32>(size - 1);
    let i0 = clamp(vec2<i32>(p0), vec2<i32>(0), hi);
    let i1 = clamp(vec2<i32>(p0) + 1, vec2<i32>(0), hi);
    t.at = array<vec2<i32>, 4>(i0, vec2<i32>(i1.x, i0.y), vec2<i32>(i0.x, i1.y), i1);
    t.w = vec4<f32>((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
    var lo = 3.4e38;
    var far = -3.4e38;
    for (var i = 0; i < 4; i++) {
        t.g[i] = textureLoad(geometry_maps, t.at[i], t.layer, 0);
        let d = texel_distance(t.g[i]);
        lo = min(lo, d);
        far = max(far, d);
    }
    var nearest = lo <= 0.0;
    if !nearest && far - lo > 0.1 * lo {
        let n0 = oct_decode(t.g[0].xy);
        var agree = 1.0;
        for (var i = 1; i < 4; i++) {
            agree = min(agree, dot(n0, oct_decode(t.g[i].xy)));
        }
        nearest = agree < 0.995 || (silhouettes() && !one_surface(d, n0, lo, far));
    }
    if nearest {
        let n = clamp(vec2<i32>(round(p)), vec2<i32>(0), hi);
        let k = select(select(0, 1, n.x != i0.x), select(2, 3, n.x != i0.x), n.y != i0.y);
        let g = t.g[k];
        t.at = array<vec2<i32>, 4>(n, n, n, n);
        t.g = array<vec4<f32>, 4>(g, g, g, g);
        t.w = vec4<f32>(1.0, 0.0, 0.0, 0.0);
    }
    return t;
}

// The filtered distance.
fn tap_distance(t: Taps) -> f32 {
    return t.w[0] * texel_distance(t.g[0]) + t.w[1] * texel_distance(t.g[1])
        + t.w[2] * texel_distance(t.g[2]) + t.w[3] * texel_distance(t.g[3]);
}

// The filtered unit normal.
fn tap_normal(t: Taps) -> vec3<f32> {
    var n = vec3<f32>(0.0);
    for (var i = 0; i < 4; i++) {
        n += t.w[i] * oct_decode(t.g[i].xy);
    }
    return normalize(n);
}

// The material; a mirror or glass code is never interpolated (diffuse radiance, a = 0, and
// fur radiance, a = FUR_TEXEL, are, among taps of one kind).
fn material(t: Taps) -> vec4<f32> {
    let first = textureLoad(material_maps, t.at[0], t.layer, 0);
    var m = vec4<f32>(0.0);
    for (var i = 0; i < 4; i++) {
        let x = textureLoad(material_maps, t.at[i], t.layer, 0);
        if x.a != first.a {
            return first;
        }
        m += t.w[i] * x;
    }
    return select(m, first, first.a != 0.0 && first.a != FUR_TEXEL);
}

// The stored distance in direction d (negative: no surface).
fn dist(map: u32, layer: u32, d: vec3<f32>) -> f32 {
    return tap_distance(taps(map, layer, d));
}

// ---- Hit(): linear and secant search ----

struct Bracket {
    found: bool,
    // Last undershooting ray parameter and |l|/|l'|, first overshooting ones.
    dl: f32,
    llp: f32,
    dp: f32,
    ppp: f32,
}

// Where the ray x + R d meets the sphere of radius r about the reference point, as
// (entry, exit); entry > exit when it misses.
fn sphere(x: vec3<f32>, r: vec3<f32>, radius: f32) -> vec2<f32> {
    let b = dot(x, r);
    let disc = b * b - dot(x, x) + radius * radius;
    if disc < 0.0 {
        return vec2<f32>(1.0, -1.0);
    }
    let s = sqrt(disc);
    return vec2<f32>(-b - s, -b + s);
}

// Listing 17-1 in one layer: march the ray from d0 to d1 in steps that are uniform in the
// direction seen from the reference point (Figure 17-3), and bracket the first place where
// it passes from in front of the layer's surface to behind it. The ray's far end is where it
// leaves the layer's max sphere (min-max on, Figure 17-4) or the sphere holding the whole
// scene (off: nothing lies beyond it, so this is the paper's r(infinity)); its near end is
// where it enters the min-max shell, or its start. The march is split where the ray passes
// closest to the reference point, so that no segment turns by 180 degrees (a ray through the
// reference point would otherwise interpolate through the zero direction).
fn linear(map: u32, layer: u32, x: vec3<f32>, r: vec3<f32>) -> March {
    var b: Bracket;
    b.found = false;
    var none = March(false, b, 0.0, false, b, false);
    var d0 = 0.0;
    var d1 = 0.0;
    var inner_start = false;
    if (params.flags.x & 1u) == 1u {
        let mm = ranges[map * params.knobs.z + layer];
        if mm.y <= 0.0 {
            return none;
        }
        let outer = sphere(x, r, mm.y * 1.0001);
        if outer.y < 0.0 || outer.x > outer.y {
            return none;
        }
        d1 = outer.y;
        if dot(x, x) < mm.x * mm.x {
            d0 = max(sphere(x, r, mm.x).y, 0.0);
        } else {
            d0 = max(outer.x, 0.0);
        }
        inner_start = d0 > 0.0;
    } else {
        d1 = max(sphere(x, r, params.maps[map].w).y, 0.0);
    }
    let dc = clamp(-dot(x, r), d0, d1);
    var state = March(false, b, 0.0, false, b, false);
    if dc > d0 {
        state = march(map, layer, x, r, d0, dc, state, !inner_start);
        if state.bracket.found {
            return state;
        }
    }
    state = march(map, layer, x, r, dc, d1, state, dc <= d0 && !inner_start);
    return state;
}

struct March {
    under: bool,
    bracket: Bracket,
    // The refined hit (valid when bracket.found).
    d: f32,
    // The last bracket passed over as a silhouette (`behind` set).
    behind: bool,
    passed: Bracket,
    // Whether the march's last sample lay behind the layer's surface. The last sample lies on
    // a sphere holding every stored distance, so this says that the ray's last direction has
    // a surface (it did not leave into an empty direction, the sky).
    ends_behind: bool,
}

// |p| / |p'|: the point's distance over the stored one in its direction; 0 where the layer
// has no surface in that direction (nothing there: as if infinitely far, so the point is in
// front). Listing 17-1 restarts its search there instead, which loses hits next to the sky:
// a step that lands in the sky just before a surface seen edge-on.
fn ratio_at(map: u32, layer: u32, p: vec3<f32>) -> f32 {
    let stored = dist(map, layer, p);
    return select(0.0, length(p) / stored, stored > 0.0);
}

// Listing 17-2 on a bracket: secant steps keeping one undershooting and one overshooting
// bound; returns (d, |ratio - 1| at d).
fn secant(map: u32, layer: u32, x: vec3<f32>, r: vec3<f32>, b_in: Bracket) -> vec2<f32> {
    var b = b_in;
    var d = b.dp;
    var miss = b.ppp - 1.0;
    for (var i = 0u; i < params.knobs.y; i++) {
        let dnew = b.dl + (b.dp - b.dl) * (1.0 - b.llp) / (b.ppp - b.llp);
        let p = x + r * dnew;
        // No surface in this direction: as if infinitely far (the point is in front).
        let ratio = ratio_at(map, layer, p);
        d = dnew;
        miss = abs(ratio - 1.0);
        if ratio < 0.9999 {
            b.llp = ratio;
            b.dl = dnew;
        } else if ratio > 1.0001 {
            b.ppp = ratio;
            b.dp = dnew;
        } else {
            break;
        }
    }
    return vec2<f32>(d, miss);
}

// One monotonic segment [da, db] of the linear search, `steps` per quarter turn of its arc;
// `skip_first`: its first sample is the ray's start. A bracket whose secant refinement does not
// come much closer to the surface than its ends were (within a quarter of their gap, or 0.5%) straddles a silhouette
// seen from the reference point (the ray passed behind a nearer surface, not through it): the
// march goes on past it.
fn march(map: u32, layer: u32, x: vec3<f32>, r: vec3<f32>, da: f32, db: f32, state_in: March, skip_first: bool) -> March {
    var st = state_in;
    let eps = 1e-6 * params.background.w;
    let pa = x + r * da;
    let pb = x + r * db;
    let la = max(length(pa), eps);
    let lb = max(length(pb), eps);
    let chord = length(pa / la - pb / lb);
    let steps = clamp(u32(ceil(f32(params.knobs.x) * chord / 1.41421356)), 1u, 4u * params.knobs.x);
    for (var i = 0u; i <= steps; i++) {
        let t = f32(i) / f32(steps);
        let d = da + (db - da) * t * la / ((1.0 - t) * lb + t * la);
        let p = x + r * d;
        let ratio = ratio_at(map, layer, p);
        // A start on this layer's own surface (the ray leaving it) is not a sample of what
        // the ray passes in front of: a texel's error there would be a hit at the start.
        let on_surface = skip_first && i == 0u && ratio > 0.98;
        st.ends_behind = ratio > 1.0;
        if ratio < 0.999 {
            if !on_surface {
                st.under = true;
                st.bracket.dl = d;
                st.bracket.llp = ratio;
            }
        } else if st.under && ratio > 1.0 {
            st.bracket.dp = d;
            st.bracket.ppp = ratio;
            let refined = secant(map, layer, x, r, st.bracket);
            let gap = min(1.0 - st.bracket.llp, ratio - 1.0);
            if params.knobs.y == 0u || refined.y <= max(0.005, 0.25 * gap) {
                st.bracket.found = true;
                st.d = refined.x;
                return st;
            }
            // The last one: after it the ray was never in front again (a sample in front
            // and a later one behind would have made a new bracket).
            st.behind = true;
            st.passed = st.bracket;
            st.under = false;
        }
    }
    return st;
}

// Behind a silhouette seen from the reference point: the bracket `b` straddled it (the ray
// passed behind the nearer surface, into what the reference point cannot see; a layer holds
// only what it sees). The farther of its two surfaces continues behind the silhouette, so if
// no layer holds a hit, the ray is taken to meet that surface's plane (its texel's point and
// normal), coloured as its texel.
struct Behind {
    // The ray parameter where it meets that plane.
    d: f32,
    // False where there is no such surface: an empty texel, or a step of less than 10 %
    // (within one surface's relief, such as fur's layers).
    ok: bool,
    // The bracket's end on the farther surface (map space).
    at: vec3<f32>,
}

fn behind_silhouette(map: u32, layer: u32, x: vec3<f32>, r: vec3<f32>, b: Bracket) -> Behind {
    var o = Behind(0.0, false, vec3<f32>(0.0));
    if b.llp <= 0.0 {
        return o;
    }
    let pl = x + r * b.dl;
    let pp = x + r * b.dp;
    let sl = length(pl) / b.llp;
    let sp = length(pp) / b.ppp;
    if max(sl, sp) < 1.1 * min(sl, sp) {
        return o;
    }
    let far_l = sl > sp;
    let at = select(pp, pl, far_l);
    let stored = select(sp, sl, far_l);
    let t = taps(map, layer, at);
    if tap_distance(t) <= 0.0 {
        return o;
    }
    let q = normalize(at) * stored;
    let n = tap_normal(t);
    let den = dot(r, n);
    o.d = select(b.dp, b.dl, far_l);
    if abs(den) > 1e-4 {
        // Not before the bracket (the ray was in front of that surface there), nor past
        // the sphere holding the scene.
        let s = dot(q - x, n) / den;
        if s >= b.dl && s <= sphere(x, r, params.maps[map].w).y {
            o.d = s;
        }
    }
    o.ok = true;
    o.at = at;
    return o;
}

struct HitResult {
    found: bool,
    // The hit point (map space), its material and unit outward normal.
    l: vec3<f32>,
    material: vec4<f32>,
    normal: vec3<f32>,
}

fn fetch(map: u32, layer: u32, l: vec3<f32>) -> HitResult {
    let t = taps(map, layer, l);
    var h: HitResult;
    h.found = tap_distance(t) > 0.0;
    h.l = l;
    h.material = material(t);
    h.normal = tap_normal(t);
    return h;
}

// The first hit of the ray x + R d in map `map`: each layer's first hit, the nearest kept.
fn hit(map: u32, x: vec3<f32>, r: vec3<f32>) -> HitResult {
    if params.flags.y == 1u {
        // Environment mapping: the direction alone, in the nearest layer of the rest.
        var o = fetch(map, 2u, r);
        o.l = r * dist(map, 2u, r);
        return o;
    }
    var found = false;
    var best = 0.0;
    var layer = 0u;
    var behind = false;
    var behind_d = 0.0;
    var behind_layer = 0u;
    var behind_at = vec3<f32>(0.0);
    for (var k = 0u; k < params.knobs.z; k++) {
        let m = linear(map, k, x, r);
        if m.bracket.found && (!found || m.d < best) {
            found = true;
            best = m.d;
            layer = k;
        }
        if !found && silhouettes() && m.behind && m.ends_behind && k >= 2u {
            let bs = behind_silhouette(map, k, x, r, m.passed);
            if bs.ok && (!behind || bs.d < behind_d) {
                behind = true;
                behind_d = bs.d;
                behind_layer = k;
                behind_at = bs.at;
            }
        }
    }
    if !found {
        if behind {
            // What the reference point cannot see: the surface behind the silhouette.
            var h = fetch(map, behind_layer, behind_at);
            h.l = x + r * behind_d;
            return h;
        }
        var miss: HitResult;
        miss.found = false;
        return miss;
    }
    return fetch(map, layer, x + r * best);
}

// ---- Listing 17-5 ----

// The material code of a fur texel (shells.wgsl's FUR_TEXEL): whole radiance, no specular
// to add; never a mirror or glass.
const FUR_TEXEL: f32 = -2.0;

fn sky(d: vec3<f32>) -> vec3<f32> {
    switch params.flags.z {
        case 1u: { return procedural(d); }
        case 2u: { return textureSampleLevel(sky_cube, sky_sampler, d, 0.0).rgb; }
        default: { return params.background.rgb; }
    }
}

// Schlick's Fresnel with F0 (a mirror's, from n and k: §17.3).
fn fresnel(f0: vec3<f32>, cos_v: f32) -> vec3<f32> {
    return f0 + (1.0 - f0) * pow(1.0 - min(abs(cos_v), 1.0), 5.0);
}

// The exact dielectric Fresnel (unpolarized) at cos_i with eta = n1 / n2; 1 under total
// internal reflection (pelt_scene::shading::fresnel_dielectric). Schlick's does not vanish
// at IOR 1.
fn fresnel_dielectric(cos_in: f32, eta: f32) -> f32 {
    let cos_i = clamp(cos_in, 0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = sqrt(1.0 - sin2_t);
    let rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

// The map of the mirror or glass object a specular hit at world point `w` lies on: the
// smallest object bounds holding it (the current map when none does). A path continues in the
// map of the object it reached, whose layers see the scene from that object.
fn map_at(w: vec3<f32>, current: u32) -> u32 {
    var best = current;
    var radius = 3.4e38;
    let count = params.flags.x >> 8u;
    for (var j = 0u; j < count; j++) {
        let o = params.objects[j];
        if length(w - o.xyz) <= o.w * 1.001 && o.w < radius {
            best = j;
            radius = o.w;
        }
    }
    return best;
}

// The specular of the local lighting at world point `w` with unit normal `n` seen along the
// unit direction `d` (the part of the forward pass's lighting the maps leave out).
fn specular(w: vec3<f32>, n_in: vec3<f32>, d: vec3<f32>) -> vec3<f32> {
    let n = select(-n_in, n_in, dot(n_in, d) < 0.0);
    var s = vec3<f32>(0.0);
    let count = min(u32(params.shading.z), MAX_MAP_LIGHTS);
    for (var i = 0u; i < count; i++) {
        let light = lights[i];
        let r = light_reach(w, light, SUNS);
        if r.w == 0.0 {
            continue;
        }
        let l = r.xyz;
        let atten = r.w;
        let ndl = max(dot(n, l), 0.0);
        let h = normalize(l - d);
        s += pow(max(dot(n, h), 0.0), params.shading.y) * ndl * atten * light.color.rgb;
    }
    return params.shading.x * s;
}

fn path(map_in: u32, x_in: vec3<f32>, v_in: vec3<f32>, n_in: vec3<f32>, m_in: vec4<f32>, reflect_first: bool) -> vec3<f32> {
    var map = map_in;
    var x = x_in;
    var v = v_in;
    var n = n_in;
    var m = m_in;
    var throughput = vec3<f32>(1.0);
    for (var depth = 0u; depth < params.knobs.w; depth++) {
        var r: vec3<f32>;
        if m.a <= 0.0 {
            // A mirror: m.rgb is its F0.
            throughput *= fresnel(m.rgb, dot(n, v));
            r = reflect(v, n);
        } else {
            // Glass: m.a is its IOR, m.rgb its tint.
            let entering = dot(v, n) <= 0.0;
            let nn = select(-n, n, entering);
            let eta = select(m.a, 1.0 / m.a, entering);
            let f = fresnel_dielectric(-dot(v, nn), eta);
            let t = refract(v, nn, eta);
            if dot(t, t) == 0.0 {
                r = reflect(v, nn);
            } else if reflect_first && depth == 0u {
                throughput *= f;
                r = reflect(v, nn);
            } else {
                throughput *= (1.0 - f) * select(vec3<f32>(1.0), m.rgb, entering);
                r = normalize(t);
            }
        }
        let h = hit(map, x, r);
        if !h.found {
            return throughput * sky(r);
        }
        if h.material.a == FUR_TEXEL {
            // Fur (shells.wgsl's fs_distance): its whole radiance, seen from the reference
            // point.
            return throughput * h.material.rgb;
        }
        if h.material.a == 0.0 {
            let w = h.l + params.maps[map].xyz;
            return throughput * (h.material.rgb + specular(w, h.normal, r));
        }
        m = h.material;
        let w = h.l + params.maps[map].xyz;
        map = map_at(w, map);
        x = w - params.maps[map].xyz;
        v = r;
        n = h.normal;
    }
    return throughput * sky(normalize(reflect(v, n)));
}

@fragment
fn fs_main(in: Out) -> @location(0) vec4<f32> {
    let map = u32(object.params.z);
    let reference = params.maps[map].xyz;
    // The camera: the view matrix is a rotation and a translation.
    let rot = mat3x3<f32>(frame.view[0].xyz, frame.view[1].xyz, frame.view[2].xyz);
    let eye = -(transpose(rot) * frame.view[3].xyz);
    let x = in.world - reference;
    let v = normalize(in.world - eye);
    let n = normalize(in.normal);
    var c = path(map, x, v, n, object.optics, false);
    if object.optics.a > 0.0 {
        c += path(map, x, v, n, object.optics, true);
    }
    return vec4<f32>(c, 1.0);
}
