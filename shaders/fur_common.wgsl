// fur_common.wgsl: what every fur shader shares (Revie, "Implementing Fur Using Deferred
// Shading", §2.3–2.4): the per-vertex fur attributes, the comb decoded with the current TBN,
// the shell offset of Listing 2.1, the grain normal of Listing 2.5 and the rim bend of
// Listing 2.3, and the layers' output. Imported by the fur passes (shaders/README.md). Keep
// `FurIn` in sync with `FurVertex` in crates/pelt-preview/src/uniforms.rs.

#define_import_path pelt::fur_common
#import pelt::common::{Frame, Object}

// The cosine between view ray and normal below which a shell layer's path length stops
// growing (a shell near the silhouette is crossed along a chord, not an infinite slab);
// with analytic coverage the fins carry the silhouette's fur below it (fins.wgsl).
const MIN_COS: f32 = 0.1;

struct FurIn {
    @location(4) tangent: vec4<f32>,
    @location(5) uv: vec2<f32>,
    // Tangent-space comb direction; w = comb length (0 = no fur).
    @location(6) comb: vec4<f32>,
    // xyz: the springs' bend of the comb, object space (crates/pelt-scene/src/springs.rs);
    // w: the length scale, what the asset's node transforms make of one mesh unit across the
    // surface (fur length is in mesh units; crates/pelt-scene/src/fur.rs, fur_vertices).
    @location(8) bend: vec4<f32>,
}

// The tangent frame's T exactly as pelt_geom::frame::Frame::new builds it (the one rule the
// bake, inspect and the preview share): T Gram-Schmidt'd against unit N; where nothing is left
// of it (|T − N(N·T)| ≤ 1e-6 |T|, or T zero) the coordinate axis least aligned with N (x, then
// y, then z on ties), projected.
fn frame_tangent(n: vec3<f32>, t: vec3<f32>) -> vec3<f32> {
    let p = t - n * dot(n, t);
    let tl = length(t);
    if tl > 0.0 && length(p) > 1e-6 * tl {
        return normalize(p);
    }
    let a = abs(n);
    var e = vec3<f32>(0.0, 0.0, 1.0);
    if a.x <= a.y && a.x <= a.z {
        e = vec3<f32>(1.0, 0.0, 0.0);
    } else if a.y <= a.z {
        e = vec3<f32>(0.0, 1.0, 0.0);
    }
    return normalize(e - n * dot(n, e));
}

// Revie §2.4.1 decoded: the comb `c` (tangent space) at a vertex with normal `n` and tangent `t`
// (w = handedness) as an object-space unit direction; the tangent where the comb has no
// direction. pelt_geom::frame::Frame::comb_direction on the CPU.
fn comb_object(n: vec3<f32>, t: vec4<f32>, c: vec3<f32>) -> vec3<f32> {
    let nl = length(n);
    let nn = select(vec3<f32>(0.0, 0.0, 1.0), n / nl, nl > 0.0);
    let tt = frame_tangent(nn, t.xyz);
    let b = cross(nn, tt) * select(1.0, -1.0, t.w < 0.0);
    let d = c.x * tt + c.y * b + c.z * nn;
    let len = length(d);
    return select(tt, d / len, len > 1e-6);
}

// A hash of lattice point `c` to −1..1 (integer mixing: the same on every back end).
fn lattice(c: vec3<i32>) -> f32 {
    var h = (bitcast<u32>(c.x) * 0x8da6b343u) ^ (bitcast<u32>(c.y) * 0xd8163841u) ^ (bitcast<u32>(c.z) * 0xcb1ab31fu);
    h = (h ^ (h >> 16u)) * 0x7feb352du;
    h = (h ^ (h >> 15u)) * 0x846ca68bu;
    h = h ^ (h >> 16u);
    return f32(h >> 8u) / 8388607.5 - 1.0;
}

// Value noise at `x` (lattice spacing 1), smoothly interpolated between lattice values: −1..1.
fn value_noise(x: vec3<f32>) -> f32 {
    let i = vec3<i32>(floor(x));
    let f = fract(x);
    let u = f * f * (3.0 - 2.0 * f);
    let x00 = mix(lattice(i), lattice(i + vec3<i32>(1, 0, 0)), u.x);
    let x10 = mix(lattice(i + vec3<i32>(0, 1, 0)), lattice(i + vec3<i32>(1, 1, 0)), u.x);
    let x01 = mix(lattice(i + vec3<i32>(0, 0, 1)), lattice(i + vec3<i32>(1, 0, 1)), u.x);
    let x11 = mix(lattice(i + vec3<i32>(0, 1, 1)), lattice(i + vec3<i32>(1, 1, 1)), u.x);
    return mix(mix(x00, x10, u.y), mix(x01, x11, u.y), u.z);
}

// Wind (Frantzen's "uniform vector for further dynamic displacement"; crates/pelt-scene/src/
// wind.rs): the object-space comb `comb` of a strand rooted at object-space `root` with
// normal `n`, bent by the frame's wind there: its vector, carried into object space (its
// length kept), gusting as 1 + ½ sin(2π f T) and stirred by ± turbulence with value noise
// (cells of 16 fur lengths) scrolling along the wind at a cell a second; it is added to the
// comb, so it bends the strand as a comb does, most at the tip: fur facing the wind is
// pressed flat (its part into the surface held to 0.8), fur in its lee stands up and streams
// with it. The shells, fins, deferred fur and strand reference all bend by it. No wind:
// `comb` itself.
fn wind_comb(comb: vec3<f32>, n: vec3<f32>, root: vec3<f32>, frame: Frame, object: Object) -> vec3<f32> {
    let w = frame.wind;
    if all(w.xyz == vec3<f32>(0.0)) {
        return comb;
    }
    let t = w.w;
    // World to object for a vector: the inverse of the model's 3×3, the transpose of
    // normal_model's.
    let m = mat3x3<f32>(object.normal_model[0].xyz, object.normal_model[1].xyz, object.normal_model[2].xyz);
    let dir = normalize(transpose(m) * w.xyz);
    let cell = max(object.fur_base.w, 1e-6) * 16.0;
    let gust = 1.0 + 0.5 * sin(6.2831853 * frame.gust.x * t);
    let stir = 1.0 + frame.gust.y * value_noise(root / cell - dir * t);
    let v = dir * (length(w.xyz) * gust * stir);
    // Into the surface at most 0.8 (the tip's n + (comb + v) keeps a fifth of its normal: a
    // strand pressed flat by the wind never turns into the body).
    let nn = normalize(n);
    let vn = dot(v, nn);
    return comb + v + nn * (max(vn, -0.8) - vn);
}

// The vertex's comb length in the asset's units: the baked length (0..1, what the fade
// below 5 % reads) times the node's length scale.
fn comb_length(f: FurIn) -> f32 {
    return f.comb.w * f.bend.w;
}

// The object-space comb of a shell or fur G-buffer vertex as it moves: the baked comb carried
// by the (skinned) tangent frame (comb_object), bent by the springs (FurIn.bend, written on the
// CPU by crates/pelt-scene/src/springs.rs) and then by the wind (wind_comb). The fins take the
// same sum (fin_rebuild.wgsl, then wind_comb in fins.wgsl), and so do the strands' roots.
fn moving_comb(n: vec3<f32>, f: FurIn, root: vec3<f32>, frame: Frame, object: Object) -> vec3<f32> {
    return wind_comb(comb_object(n, f.tangent, f.comb.xyz) + f.bend.xyz, n, root, frame, object);
}

// Listing 2.1: the offset of a vertex on the shell at normalized depth `sd`: along the normal
// bent toward the comb by `sd`, scaled by the fur length and the vertex's comb length.
fn shell_offset(n: vec3<f32>, comb: vec3<f32>, sd: f32, fur_length: f32, comb_length: f32) -> vec3<f32> {
    let dir = normalize(normalize(n) + comb * sd);
    return dir * sd * fur_length * comb_length;
}

// The direction a strand runs at height `z` (fraction of the fur length), the tangent
// Kajiya-Kay lights: the derivative of the Listing 2.1 path P(z) = z D(z), D = normalize(n +
// c z): P' = D + z D', D' = (c − D (D·c)) / |n + c z| (pelt_fur::path::tangent on the CPU).
fn strand_tangent(n: vec3<f32>, comb: vec3<f32>, z: f32) -> vec3<f32> {
    return normalize(strand_velocity(n, comb, z));
}

// P'(z) itself (per unit of fur length × comb length).
fn strand_velocity(n: vec3<f32>, comb: vec3<f32>, z: f32) -> vec3<f32> {
    let m = normalize(n) + comb * z;
    let len = length(m);
    if len <= 1e-6 {
        return select(normalize(n), comb, length(comb) > 1e-6);
    }
    let d = m / len;
    let dd = (comb - d * dot(d, comb)) / len;
    return d + dd * z;
}

// Bin `i` (0..7) of the two density samples. Selects, not a local array: a dynamically
// indexed array spills to memory on some drivers (llvmpipe), at a cost per shell fragment.
fn density_bin(lo: vec4<f32>, hi: vec4<f32>, i: u32) -> f32 {
    let v = select(hi, lo, i < 4u);
    let j = i & 3u;
    return select(select(v.w, v.z, j == 2u), select(v.y, v.x, j == 0u), j < 2u);
}

// T(z) (pelt_fur::density::t_at) from the two density samples: linear between the bins,
// 0 at z = 1.
fn t_at(lo: vec4<f32>, hi: vec4<f32>, z: f32) -> f32 {
    let x = clamp(z, 0.0, 1.0) * 8.0;
    let k = min(u32(floor(x)), 7u);
    let next = select(density_bin(lo, hi, k + 1u), 0.0, k == 7u);
    return mix(density_bin(lo, hi, k), next, x - f32(k));
}

// The opacity of the layer between heights `z0` and `z1` where a pixel holds many strands
// (pelt_fur::density): 1 − e^(−Δτ), Δτ = (κ T(z_mid) sin ψ ℓ + T(z0) − T(z1)) / μ, with `lo`
// and `hi` the pixel's two density samples, `kappa` κ, `sin_psi` the sine of the angle
// between view ray and strand, `len` the strand's length across the layer in tile widths
// (its view length times √J, the tile area per unit of surface area) and `mu` the view's
// |cos θ| from the normal (held at MIN_COS and above by the caller).
fn layer_opacity(lo: vec4<f32>, hi: vec4<f32>, z0: f32, z1: f32, kappa: f32, sin_psi: f32, len: f32, mu: f32) -> f32 {
    let zm = 0.5 * (z0 + z1);
    let tau = (kappa * t_at(lo, hi, zm) * sin_psi * len + max(t_at(lo, hi, z0) - t_at(lo, hi, z1), 0.0)) / mu;
    return 1.0 - exp(-tau);
}

// The view-to-face cosine below which a fin starts to show with binary coverage (the shells
// alone hold the fur above it).
const FIN_SILHOUETTE: f32 = 0.35;

// A fin's visibility (fins.wgsl): `s0`, `s1` the cosines between the direction to the eye
// and its edge's two face normals, `face_on` |cos| between the eye and the fin's own normal.
// 1 where the faces face opposite ways, fading to 0 once both face the viewer by more than
// the reach (MIN_COS with `analytic` coverage, whose shells' optical depth holds the fur down
// to it; FIN_SILHOUETTE otherwise), times how face-on the fin is (edge-on fins are slivers).
fn fin_visibility(s0: f32, s1: f32, face_on: f32, analytic: bool) -> f32 {
    let near = min(abs(s0), abs(s1));
    let reach = select(FIN_SILHOUETTE, MIN_COS, analytic);
    let silhouette = select(1.0 - smoothstep(0.0, reach, near), 1.0, s0 * s1 <= 0.0);
    return silhouette * smoothstep(0.05, 0.3, face_on);
}

// An object-space direction (a tangent vector) in view space.
fn view_dir_of(d: vec3<f32>, frame: Frame, object: Object) -> vec3<f32> {
    let w = (object.model * vec4<f32>(d, 0.0)).xyz;
    let v = (frame.view * vec4<f32>(w, 0.0)).xyz;
    let len = length(v);
    return select(vec3<f32>(1.0, 0.0, 0.0), v / len, len > 1e-12);
}

// An object-space normal in view space.
fn view_normal_of(n: vec3<f32>, frame: Frame, object: Object) -> vec3<f32> {
    let w = (object.normal_model * vec4<f32>(n, 0.0)).xyz;
    return normalize((frame.view * vec4<f32>(w, 0.0)).xyz);
}

// Listing 2.5: the normal coplanar with the eye vector and the grain direction. `dir` is the
// comb in view space, `eye` the direction from the eye to the point. The comb is first made
// tangential to `n`; where it runs along the eye vector, the surface normal is kept.
fn grain_normal(n: vec3<f32>, dir: vec3<f32>, eye: vec3<f32>) -> vec3<f32> {
    var d = dir - dot(dir, n) * n;
    if dot(d, d) < 1e-10 {
        return n;
    }
    d = normalize(d);
    let binorm = cross(eye, d);
    let g = cross(binorm, d);
    let len = length(g);
    if len < 1e-5 {
        return n;
    }
    // cross(cross(e, d), d) = d·(e·d) − e: it faces the viewer.
    return g / len;
}

// Listing 2.3: near the silhouette, bend the normal away from the viewer so the point takes
// light arriving from behind (the halo of scattering through the fur layer).
fn rim_normal(n: vec3<f32>, eye: vec3<f32>, strength: f32, falloff: f32) -> vec3<f32> {
    let ndv = clamp(dot(n, -eye), 0.0, 1.0);
    let w = strength * pow(1.0 - ndv, falloff);
    return normalize(n + eye * w);
}

// Screen position (output pixels) of a clip-space point.
fn clip_to_pixel(c: vec4<f32>, frame: Frame) -> vec2<f32> {
    let ndc = c.xy / max(c.w, 1e-6);
    return vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5) * frame.target_size.xy;
}

// McGuire & Bavoil (2013), eq. 7: the weight of a layer at view depth `z` (positive, in scene
// units) with coverage `a`. Nearer layers weigh more; the clamp keeps the ratio of any two
// weights under 3e5. `scale` (Object.fur_params.w) keeps the sum of every layer's weight
// below the accumulation format's largest value (see crates/pelt-preview/src/draw.rs).
fn wboit_weight(z: f32, a: f32, scale: f32) -> f32 {
    let zz = z / 5.0;
    let z6 = pow(z / 200.0, 6.0);
    return a * clamp(10.0 / (1e-5 + zz * zz + z6), 1e-2, 3e3) * scale;
}

// Everything a fur fragment needs to be lit, by the L-buffer or by the lights directly.
struct FurQuery {
    // View-space point and the strand direction there (forward, Kajiya-Kay).
    view_pos: vec3<f32>,
    strand: vec3<f32>,
    // Output-pixel positions and linear depths of the strand's root on the base mesh and of
    // its tip on the outer shell (inferred: the two L-buffer samples of §2.4.4).
    base_pixel: vec2<f32>,
    base_depth: f32,
    top_pixel: vec2<f32>,
    top_depth: f32,
    // Normal group of the base mesh there.
    group: u32,
    // Height on the strand (fraction of the fur length).
    height: f32,
    // The strand reference with traced shadows (strands.wgsl): bit 5 l + k of the 64 set
    // where sample k (the ends of its segments) sees shadow-casting light l, the segment the
    // point lies on and how far along it (0 to 1).
    traced: vec2<u32>,
    segment: u32,
    along: f32,
}

// The query of a fragment at view-space `view_pos` on a strand running along `strand`, whose
// root and tip project to `base_clip` and `top_clip` at linear depths `base_depth` and
// `top_depth`.
fn fur_query(
    view_pos: vec3<f32>,
    strand: vec3<f32>,
    base_clip: vec4<f32>,
    top_clip: vec4<f32>,
    base_depth: f32,
    top_depth: f32,
    group: u32,
    height: f32,
    frame: Frame,
) -> FurQuery {
    var q: FurQuery;
    q.view_pos = view_pos;
    q.strand = normalize(strand);
    q.base_pixel = clip_to_pixel(base_clip, frame);
    q.base_depth = base_depth;
    q.top_pixel = clip_to_pixel(top_clip, frame);
    q.top_depth = top_depth;
    q.group = group;
    q.height = height;
    return q;
}

struct FurLight {
    diffuse: vec3<f32>,
    specular: vec3<f32>,
}


struct FurOut {
    // Straight colour and alpha ("over"), or Σ colour·α·w and Σ α·w (WBOIT).
    @location(0) color: vec4<f32>,
    // WBOIT: α, multiplied into the revealage target as 1 − α.
    @location(1) reveal: vec4<f32>,
}

// A layer's output (`wboit`: the shader's WBOIT override): straight alpha, or its contribution to the weighted blended
// accumulation (McGuire & Bavoil eq. 7 with view depth `depth`).
fn fur_out(c: vec4<f32>, depth: f32, scale: f32, wboit: bool) -> FurOut {
    var o: FurOut;
    if wboit {
        let w = wboit_weight(depth, c.a, scale);
        o.color = vec4<f32>(c.rgb * c.a, c.a) * w;
        o.reveal = vec4<f32>(c.a);
    } else {
        o.color = c;
        o.reveal = vec4<f32>(0.0);
    }
    return o;
}
