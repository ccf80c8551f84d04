// reflect.wgsl: mirrors and glass in the material (or forward) pass, by ray tracing their
// layered distance maps (GPU Gems 3 ch. 17). Per pixel: Listing 17-5's loop of reflections
// and refractions with Schlick's Fresnel (F0 from n and k for metals), total internal
// reflection, and up to MAXDEPTH bounces; each next hit found by Hit(): a linear search per
// layer stepping uniformly in texture space between the projections of the ray's ends
// (Listing 17-1, Figure 17-3), clipped to the layer's min-max shell (Figure 17-4), the layer
// with the nearest overshoot taken, then a secant search (Listing 17-2) that keeps one
// undershooting and one overshooting bound and stops at a sample with no surface. The maps are
// 2D arrays (map, layer, face) read with textureLoad (a cube view cannot be); distances are
// filtered bilinearly within a face unless the four texels straddle a silhouette or an empty
// texel, where the nearest texel is taken. Technique 1 (environment mapping, the baseline)
// looks the direction up in the nearest layer of the rest of the scene instead of searching.
// At the surface the camera sees, glass both reflects and refracts (two paths); a path that
// leaves the scene ends in the sky, and one still on a mirror after MAXDEPTH bounces ends in
// the sky in its mirror direction (pelt-trace's path.rs follows the same rules).
//
// Keep in sync with ReflectUniforms in crates/pelt-preview/src/features/reflect.rs.

const MAX_MAPS: u32 = 64u;

struct Reflect {
    // x: linear steps per quarter turn; y: secant steps; z: layers; w: most bounces.
    knobs: vec4<u32>,
    // x: min-max on; y: technique (0 distance maps, 1 environment map); z: sky (0 background,
    // 1 procedural, 2 cube map); w: cube face size.
    flags: vec4<u32>,
    // rgb: the background (no sky); w: the scene's radius.
    background: vec4<f32>,
    // xyz: each map's reference point (world).
    maps: array<vec4<f32>, MAX_MAPS>,
}

@group(0) @binding(0) var<uniform> frame: Frame;
@group(1) @binding(0) var<uniform> object: Object;
@group(2) @binding(0) var material_maps: texture_2d_array<f32>;
@group(2) @binding(1) var geometry_maps: texture_2d_array<f32>;
@group(2) @binding(2) var<storage, read> ranges: array<vec2<f32>>;
@group(2) @binding(3) var<uniform> params: Reflect;
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

// The face (+X -X +Y -Y +Z -Z) and texture coordinates (v down) of direction d, by the
// cube-map convention the faces were rendered with.
fn face_uv(d: vec3<f32>) -> vec3<f32> {
    let a = abs(d);
    var f = 0.0;
    var sc = 0.0;
    var tc = 0.0;
    var ma = 0.0;
    if a.x >= a.y && a.x >= a.z {
        ma = a.x;
        tc = -d.y;
        if d.x > 0.0 { f = 0.0; sc = -d.z; } else { f = 1.0; sc = d.z; }
    } else if a.y >= a.z {
        ma = a.y;
        sc = d.x;
        if d.y > 0.0 { f = 2.0; tc = d.z; } else { f = 3.0; tc = -d.z; }
    } else {
        ma = a.z;
        tc = -d.y;
        if d.z > 0.0 { f = 4.0; sc = d.x; } else { f = 5.0; sc = -d.x; }
    }
    ma = max(ma, 1e-20);
    return vec3<f32>(f, (sc / ma + 1.0) * 0.5, (tc / ma + 1.0) * 0.5);
}

struct Taps {
    // The four texels (or the nearest one four times) and their bilinear weights.
    at: array<vec2<i32>, 4>,
    w: vec4<f32>,
    layer: i32,
}

// The texels to read for direction d in layer `layer` of map `map`: bilinear within the face
// unless the taps straddle a silhouette or an empty texel (then the nearest).
fn taps(map: u32, layer: u32, d: vec3<f32>) -> Taps {
    let fuv = face_uv(d);
    let size = i32(params.flags.w);
    var t: Taps;
    t.layer = i32((map * params.knobs.z + layer) * 6u) + i32(fuv.x);
    let p = fuv.yz * f32(size) - 0.5;
    let p0 = floor(p);
    let f = p - p0;
    let hi = vec2<i32>(size - 1);
    let i0 = clamp(vec2<i32>(p0), vec2<i32>(0), hi);
    let i1 = clamp(vec2<i32>(p0) + 1, vec2<i32>(0), hi);
    t.at = array<vec2<i32>, 4>(i0, vec2<i32>(i1.x, i0.y), vec2<i32>(i0.x, i1.y), i1);
    t.w = vec4<f32>((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
    let d4 = vec4<f32>(
        textureLoad(geometry_maps, t.at[0], t.layer, 0).w,
        textureLoad(geometry_maps, t.at[1], t.layer, 0).w,
        textureLoad(geometry_maps, t.at[2], t.layer, 0).w,
        textureLoad(geometry_maps, t.at[3], t.layer, 0).w,
    );
    let lo = min(min(d4.x, d4.y), min(d4.z, d4.w));
    let hi4 = max(max(d4.x, d4.y), max(d4.z, d4.w));
    if lo <= 0.0 || hi4 - lo > 0.1 * lo {
        let n = clamp(vec2<i32>(round(p)), vec2<i32>(0), hi);
        t.at = array<vec2<i32>, 4>(n, n, n, n);
        t.w = vec4<f32>(1.0, 0.0, 0.0, 0.0);
    }
    return t;
}

fn geometry(t: Taps) -> vec4<f32> {
    var g = vec4<f32>(0.0);
    for (var i = 0; i < 4; i++) {
        g += t.w[i] * textureLoad(geometry_maps, t.at[i], t.layer, 0);
    }
    return g;
}

// The material; a mirror or glass code (a != 0) is never interpolated.
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
    return select(m, first, first.a != 0.0);
}

// The stored distance in direction d (negative: no surface).
fn dist(map: u32, layer: u32, d: vec3<f32>) -> f32 {
    return geometry(taps(map, layer, d)).w;
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

// Listing 17-1 in one layer: march the ray from d0 to d1 (d1 < 0: to infinity) in steps that
// are uniform in the direction seen from the reference point, and bracket the first place
// where it passes from in front of the layer's surface to behind it.
fn linear(map: u32, layer: u32, x: vec3<f32>, r: vec3<f32>) -> Bracket {
    var b: Bracket;
    b.found = false;
    var d0 = 0.0;
    var d1 = -1.0;
    let eps = 1e-5 * params.background.w;
    if params.flags.x == 1u {
        let mm = ranges[map * params.knobs.z + layer];
        if mm.y <= 0.0 {
            return b;
        }
        let outer = sphere(x, r, mm.y);
        if outer.y < 0.0 || outer.x > outer.y {
            return b;
        }
        d1 = outer.y;
        let inner = sphere(x, r, mm.x);
        if dot(x, x) < mm.x * mm.x {
            d0 = max(inner.y, 0.0);
        } else {
            d0 = max(outer.x, 0.0);
        }
    }
    let p0 = x + r * d0;
    let l0 = max(length(p0), eps);
    var e = r;
    var l1 = 1.0;
    if d1 >= 0.0 {
        e = x + r * d1;
        l1 = max(length(e), eps);
    }
    let chord = length(p0 / l0 - e / l1);
    let steps = clamp(u32(ceil(f32(params.knobs.x) * chord / 1.41421356)), 1u, 4u * params.knobs.x);
    var under = false;
    for (var i = 0u; i <= steps; i++) {
        var t = f32(i) / f32(steps);
        var d = 0.0;
        if d1 >= 0.0 {
            d = d0 + (d1 - d0) * t * l0 / ((1.0 - t) * l1 + t * l0);
        } else {
            t = min(t, 1.0 - 0.5 / f32(steps));
            d = d0 + l0 * t / (1.0 - t);
        }
        let p = x + r * d;
        let stored = dist(map, layer, p);
        if stored <= 0.0 {
            under = false;
            continue;
        }
        let ratio = length(p) / stored;
        // The start is on a surface when the ray leaves one; it is not a sample of what the
        // ray passes in front of (a texel's error there would be a hit at the start).
        if ratio < 0.999 && i > 0u {
            under = true;
            b.dl = d;
            b.llp = ratio;
        } else if under && ratio > 1.0 {
            b.found = true;
            b.dp = d;
            b.ppp = ratio;
            return b;
        }
    }
    return b;
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
    let g = geometry(t);
    h.found = g.w > 0.0;
    h.l = l;
    h.material = material(t);
    h.normal = normalize(g.xyz);
    return h;
}

// The first hit of the ray x + R d in map `map`.
fn hit(map: u32, x: vec3<f32>, r: vec3<f32>) -> HitResult {
    if params.flags.y == 1u {
        // Environment mapping: the direction alone, in the nearest layer of the rest.
        let h = fetch(map, 2u, r);
        var o = h;
        o.l = r * geometry(taps(map, 2u, r)).w;
        return o;
    }
    var best: Bracket;
    best.found = false;
    var layer = 0u;
    for (var k = 0u; k < params.knobs.z; k++) {
        let b = linear(map, k, x, r);
        if b.found && (!best.found || b.dp < best.dp) {
            best = b;
            layer = k;
        }
    }
    var miss: HitResult;
    miss.found = false;
    if !best.found {
        return miss;
    }
    var d = best.dp;
    for (var i = 0u; i < params.knobs.y; i++) {
        let dnew = best.dl + (best.dp - best.dl) * (1.0 - best.llp) / (best.ppp - best.llp);
        let p = x + r * dnew;
        let stored = dist(map, layer, p);
        if stored <= 0.0 {
            break;
        }
        d = dnew;
        let ratio = length(p) / stored;
        if ratio < 0.9999 {
            best.llp = ratio;
            best.dl = dnew;
        } else if ratio > 1.0001 {
            best.ppp = ratio;
            best.dp = dnew;
        } else {
            break;
        }
    }
    return fetch(map, layer, x + r * d);
}

// ---- Listing 17-5 ----

fn sky(d: vec3<f32>) -> vec3<f32> {
    switch params.flags.z {
        case 1u: { return procedural(d); }
        case 2u: { return textureSampleLevel(sky_cube, sky_sampler, d, 0.0).rgb; }
        default: { return params.background.rgb; }
    }
}

const SUN: vec3<f32> = vec3<f32>(0.48, 0.62, 0.62);

// sky.wgsl's procedural sky (pelt_scene::shading::procedural_sky on the CPU).
fn procedural(d: vec3<f32>) -> vec3<f32> {
    let zenith = vec3<f32>(0.10, 0.22, 0.55);
    let horizon = vec3<f32>(0.55, 0.63, 0.75);
    let ground = vec3<f32>(0.09, 0.08, 0.07);
    let up = d.y;
    let s_ = mix(horizon, zenith, pow(clamp(up, 0.0, 1.0), 0.6));
    let below = mix(horizon * 0.6, ground, clamp(-up * 6.0, 0.0, 1.0));
    var c = select(below, s_, up >= 0.0);
    let s = max(dot(d, normalize(SUN)), 0.0);
    c += vec3<f32>(1.0, 0.85, 0.6) * (0.6 * pow(s, 64.0) + 0.15 * pow(s, 6.0));
    return c;
}

fn fresnel(f0: vec3<f32>, cos_v: f32) -> vec3<f32> {
    return f0 + (1.0 - f0) * pow(1.0 - min(abs(cos_v), 1.0), 5.0);
}

// F0 of a code: a mirror's rgb, or a dielectric's ((n - 1) / (n + 1))^2.
fn f0_of(m: vec4<f32>) -> vec3<f32> {
    if m.a > 0.0 {
        let r = (m.a - 1.0) / (m.a + 1.0);
        return vec3<f32>(r * r);
    }
    return m.rgb;
}

fn path(map: u32, x_in: vec3<f32>, v_in: vec3<f32>, n_in: vec3<f32>, m_in: vec4<f32>, reflect_first: bool) -> vec3<f32> {
    var x = x_in;
    var v = v_in;
    var n = n_in;
    var m = m_in;
    var throughput = vec3<f32>(1.0);
    for (var depth = 0u; depth < params.knobs.w; depth++) {
        let f = fresnel(f0_of(m), dot(n, v));
        var r: vec3<f32>;
        if m.a <= 0.0 || (reflect_first && depth == 0u) {
            throughput *= f;
            r = reflect(v, n);
        } else {
            let entering = dot(v, n) <= 0.0;
            let nn = select(-n, n, entering);
            let eta = select(m.a, 1.0 / m.a, entering);
            let t = refract(v, nn, eta);
            if dot(t, t) == 0.0 {
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
        if h.material.a == 0.0 {
            return throughput * h.material.rgb;
        }
        m = h.material;
        x = h.l;
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
