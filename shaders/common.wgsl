// common.wgsl: structs and functions shared by every pass of pelt's preview renderer.
// Imported by name (`#import pelt::common::{Frame, …}`, composed by naga_oil: see
// shaders/README.md); it declares no bindings (object_bindings.wgsl holds the shared ones).
//
// Keep in sync with crates/pelt-preview/src/uniforms.rs (FrameUniforms, ObjectUniforms,
// LightUniforms, Vertex).

#define_import_path pelt::common

struct Frame {
    view: mat4x4<f32>,
    proj: mat4x4<f32>,
    // rgb: ambient light; w: specular power.
    ambient: vec4<f32>,
    // This pass's render target: width, height, 1/width, 1/height.
    target_size: vec4<f32>,
    // The L-buffer: width, height, 1/width, 1/height.
    lbuffer_size: vec4<f32>,
    // tan(fov_x / 2), tan(fov_y / 2), near, far.
    proj_params: vec4<f32>,
    // x: DSF on (1) or plain bilinear (0); y: light count (forward pass);
    // z: DSF depth-threshold floor in quantisation steps; w: the frame has an L-buffer (1) or
    // lights nothing on screen (0: ambient only).
    flags: vec4<u32>,
    // The wind (crates/pelt-scene/src/wind.rs): xyz its world direction × strength (all zero:
    // none), w the scene's time in seconds.
    wind: vec4<f32>,
    // x: gusts per second; y: turbulence (0 to 1); zw: unused.
    gust: vec4<f32>,
}

struct Object {
    model: mat4x4<f32>,
    // Inverse transpose of `model` (its upper 3×3 transforms normals).
    normal_model: mat4x4<f32>,
    // rgb: linear colour multiplied into the vertex albedo; a: unused.
    tint: vec4<f32>,
    // x: opacity; y: specular strength; z: the object's distance map (mirror and glass);
    // w: fur only, root and tip colours multiply the base colour texture (1) or not (0).
    params: vec4<f32>,
    // Fur only. rgb: root colour (linear, times the object's colour); w: fur length.
    fur_base: vec4<f32>,
    // rgb: tip colour; w: heightfield UV scale.
    fur_tip: vec4<f32>,
    // x: rim strength; y: rim falloff (Revie Listing 2.3); z: strand fade width in shell
    // depth; w: WBOIT weight scale.
    fur_params: vec4<f32>,
    // Fur only, the strand model as a medium (pelt_fur::density): x: κ = Σ 2r / Σ π r² (per
    // tile width); y: mean strand diameter (tile widths); z: coverage (0 analytic, 1 the
    // binary heightfield alone); w: deferred fur lighting (0 Kajiya-Kay, 1 Revie's normals).
    fur_model: vec4<f32>,
    // x: object ID (1..255); y: stipple pattern (0 = opaque, 1..3 = alpha layer); z: the
    // fur's outer-shell ID; w: shell count.
    ids: vec4<u32>,
    // What the surface does to rays (GPU Gems 3 Listing 17-5's convention): rgb = F0 for a
    // mirror, the tint for glass; a = -1 for a mirror, 0 diffuse, the IOR for glass.
    optics: vec4<f32>,
}

// One material's factors (glTF 2.0 §3.9). Keep in sync with MaterialUniforms in
// crates/pelt-preview/src/uniforms.rs.
struct MaterialParams {
    // x: normalTexture.scale; y: metallicFactor; z: roughnessFactor; w: unused.
    factors: vec4<f32>,
    // x: has a normal texture; y: a base colour texture; z: a metallic-roughness texture.
    flags: vec4<u32>,
}

// A skinned vertex (skin.wgsl writes them, skin_scatter.wgsl copies them into the vertex
// buffers). Keep in sync with PosedVertex in crates/pelt-preview/src/features/skin.rs.
struct PosedVertex {
    position: vec4<f32>,
    normal: vec4<f32>,
    tangent: vec4<f32>,
}

struct Light {
    // A point or spot light's view-space position and radius; a directional light's unit
    // view-space direction toward it and 0 (light_reach).
    position_radius: vec4<f32>,
    // rgb: colour × intensity; w: intensity × luminance(colour), the specular scale.
    color: vec4<f32>,
    // x: its shadow cube's slot + 1 (0: it casts no shadows; shadows.wgsl); yzw: unused.
    shadow: vec4<u32>,
    // A spot light's cone: xyz its unit view-space axis times 1 / (cos inner − cos outer), w
    // −cos outer times the same; (0, 0, 0, 1) for a light without one (point_reach).
    cone: vec4<f32>,
}

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) albedo: vec4<f32>,
    @location(3) group: u32,
    // The TEXCOORD set the material samples.
    @location(7) uv: vec2<f32>,
}

// VertexIn and fur_common.wgsl's FurIn as 32-bit words (compute passes that write vertex
// records: skin_scatter.wgsl, fin_rebuild.wgsl). The shader-validation test checks them
// against size_of::<Vertex>() and size_of::<FurVertex>().
const VERTEX_FLOATS: u32 = 13u;
const FUR_FLOATS: u32 = 14u;

struct Surface {
    @builtin(position) clip: vec4<f32>,
    @location(0) view_pos: vec3<f32>,
    @location(1) view_normal: vec3<f32>,
    @location(2) albedo: vec4<f32>,
    @location(3) @interpolate(flat) group: u32,
    @location(4) uv: vec2<f32>,
}

// Linear depth 0 and 65535 are reserved: 65535 marks an empty DSF texel.
const DEPTH_EMPTY: u32 = 65535u;
const DEPTH_STEPS: f32 = 65534.0;

fn to_surface(v: VertexIn, frame: Frame, object: Object) -> Surface {
    var s: Surface;
    let world = object.model * vec4<f32>(v.position, 1.0);
    let view = frame.view * world;
    s.clip = frame.proj * view;
    s.view_pos = view.xyz;
    let n_world = (object.normal_model * vec4<f32>(v.normal, 0.0)).xyz;
    s.view_normal = (frame.view * vec4<f32>(n_world, 0.0)).xyz;
    s.albedo = v.albedo * vec4<f32>(object.tint.rgb, 1.0);
    s.group = v.group;
    s.uv = v.uv;
    return s;
}

// The normal map's normal (tangent space, [0, 1] encoded, xy scaled by `scale` as glTF
// 2.0 §3.9.3 says) on the surface with view-space position `p`, unit normal `n` and texture
// coordinates `uv`. The tangent frame is the cotangent frame the screen-space derivatives of
// `p` and `uv` give (Schüler, "Normal Mapping Without Precomputed Tangents", ShaderX5 2006):
// per pixel, from the UV layout itself, so skinned and morphed surfaces need no tangent
// update. Degenerate UVs keep `n`.
fn perturb_normal(n: vec3<f32>, p: vec3<f32>, uv: vec2<f32>, stored: vec3<f32>, scale: f32) -> vec3<f32> {
    let dp1 = dpdx(p);
    let dp2 = dpdy(p);
    let duv1 = dpdx(uv);
    let duv2 = dpdy(uv);
    let dp2perp = cross(dp2, n);
    let dp1perp = cross(n, dp1);
    // The adjugate's sign: the determinant is negative when the window's Y runs down (as in
    // wgpu) or the surface is seen from behind; Schüler's GL derivation assumes positive.
    let side = select(-1.0, 1.0, dot(dp1, dp2perp) >= 0.0);
    let t = side * (dp2perp * duv1.x + dp1perp * duv2.x);
    // glTF's V runs down the image: its bitangent is minus the +V derivative direction.
    let b = -side * (dp2perp * duv1.y + dp1perp * duv2.y);
    let m = max(dot(t, t), dot(b, b));
    var tn = stored * 2.0 - 1.0;
    tn = vec3<f32>(tn.xy * scale, tn.z);
    if m < 1e-20 {
        return n;
    }
    let inv = inverseSqrt(m);
    return normalize(t * inv * tn.x + b * inv * tn.y + n * tn.z);
}

// Specular scale and diffuse scale of a metallic-roughness surface on pelt's lighting model
// (one specular power for the whole frame, Kircher & Lawrance §2.2): a rough surface's
// highlight spreads out, which at one power reads as a dimmer highlight, so roughness r
// scales the specular term by clamp(2 (1 - r), 0, 1) (1 up to r = 0.5, 0 at r = 1); a metal
// has no diffuse term and a specular colour of its albedo.
fn metal_rough(metallic: f32, roughness: f32) -> vec2<f32> {
    return vec2<f32>(clamp(2.0 * (1.0 - roughness), 0.0, 1.0), 1.0 - metallic);
}

// The shading normal facing the viewer: back faces (double-sided or mis-wound geometry)
// use the flipped normal, so every stored normal has z >= 0 up to interpolation.
fn facing_normal(n: vec3<f32>, front: bool) -> vec3<f32> {
    let u = normalize(n);
    return select(-u, u, front);
}

// Kircher & Lawrance eq. 1: map the sphere onto the +Z hemisphere; X and Y are stored,
// remapped from [-1, 1] to [0, 1] so a 16-bit unorm target holds them.
fn encode_normal(n: vec3<f32>) -> vec2<f32> {
    let m = n + vec3<f32>(0.0, 0.0, 1.0);
    let len = length(m);
    if len < 1e-6 {
        return vec2<f32>(0.5, 0.5);
    }
    return m.xy / len * 0.5 + 0.5;
}

// Kircher & Lawrance eqs. 2 and 3, after undoing the [0, 1] remap.
fn decode_normal(stored: vec2<f32>) -> vec3<f32> {
    let e = stored * 2.0 - 1.0;
    let z = sqrt(max(1.0 - dot(e, e), 0.0));
    return vec3<f32>(2.0 * z * e.x, 2.0 * z * e.y, 2.0 * z * z - 1.0);
}

// Linear (view) depth to its 16-bit code: 0 at near, 65534 at far.
fn depth_code(d: f32, frame: Frame) -> u32 {
    let t = clamp((d - frame.proj_params.z) / (frame.proj_params.w - frame.proj_params.z), 0.0, 1.0);
    return u32(round(t * DEPTH_STEPS));
}

fn depth_from_code(c: u32, frame: Frame) -> f32 {
    return frame.proj_params.z + f32(c) / DEPTH_STEPS * (frame.proj_params.w - frame.proj_params.z);
}

// The DSF ID of Kircher & Lawrance §3.1: object ID in the high byte, normal group in the low.
fn dsf_id(object: Object, group: u32) -> u32 {
    return ((object.ids.x & 255u) << 8u) | (group & 255u);
}

// Whether pixel `p` belongs to stipple pattern `pattern` (1..3 of the 2×2 cell; 0 = opaque,
// which owns every pixel).
fn in_stipple(p: vec2<u32>, pattern: u32) -> bool {
    return pattern == 0u || ((p.x & 1u) | ((p.y & 1u) << 1u)) == pattern;
}

fn luminance(c: vec3<f32>) -> f32 {
    return dot(c, vec3<f32>(0.2126, 0.7152, 0.0722));
}

// A point or spot light's reach at view-space point `p`: the unit direction toward it (xyz)
// and its inverse-square falloff, windowed to reach exactly zero at its radius and beyond, times
// a spot light's cone, clamp(dot(axis, −l) · s − cos outer · s, 0, 1)² with s = 1 / (cos inner −
// cos outer) as glTF's KHR_lights_punctual (1 without a cone). The clamps reach zero with no
// branch, so every term they scale is exactly zero (a CPU rasterizer runs both sides of a
// branch its lanes disagree on).
fn point_reach(p: vec3<f32>, light: Light) -> vec4<f32> {
    let r = bare_reach(p, light);
    let cone = clamp(dot(light.cone.xyz, -r.xyz) + light.cone.w, 0.0, 1.0);
    return vec4<f32>(r.xyz, r.w * (cone * cone));
}

// point_reach without the cone: a plain point light's (what a loop over a view of point
// lights alone evaluates: the cone's terms cost a fifth of forward shading's light loop on a
// CPU rasterizer).
fn bare_reach(p: vec3<f32>, light: Light) -> vec4<f32> {
    let radius = light.position_radius.w;
    let to_light = light.position_radius.xyz - p;
    let dist = length(to_light);
    let x = dist / radius;
    let window = clamp(1.0 - x * x * x * x, 0.0, 1.0);
    return vec4<f32>(to_light / max(dist, 1e-6), window * window / (1.0 + dist * dist));
}

// A directional light's reach (radius 0, xyz its unit view-space direction toward the light):
// everywhere, with no falloff.
fn sun_reach(light: Light) -> vec4<f32> {
    return vec4<f32>(light.position_radius.xyz, 1.0);
}

// Any light's reach, by its kind, for a loop over lights of every kind. `suns`: whether the
// view may hold a light other than a plain point light (a directional or a spot light:
// `Emitter::needs_suns`); pass the pipeline's SUNS override, so a view of point lights alone
// compiles the branch and the cones out (a CPU rasterizer pays for a branch it cannot prove
// uniform: light_reach's run-time branch made lavapipe's light pass five times slower). Keep in
// sync with `Emitter::reach` in crates/pelt-scene/src/light.rs.
fn light_reach(p: vec3<f32>, light: Light, suns: bool) -> vec4<f32> {
    if suns {
        if light.position_radius.w == 0.0 {
            return sun_reach(light);
        }
        return point_reach(p, light);
    }
    return bare_reach(p, light);
}

// One light of reach `r` (light_reach) at view-space point `p` with normal `n`: rgb = diffuse
// irradiance, a = specular intensity (Blinn-Phong, scalar, as the L-buffer stores it). Out of
// reach (r.w zero) every term is exactly zero, with no branch of its own.
fn one_light(p: vec3<f32>, n: vec3<f32>, r: vec4<f32>, light: Light, spec_power: f32) -> vec4<f32> {
    let l = r.xyz;
    let atten = r.w;
    let ndl = max(dot(n, l), 0.0);
    let v = normalize(-p);
    let h = normalize(l + v);
    let spec = pow(max(dot(n, h), 0.0), spec_power) * ndl * atten;
    return vec4<f32>(light.color.rgb * (ndl * atten), spec * light.color.w);
}

// The shell table's flag for object IDs whose G-buffer texels hold a strand tangent (the
// fur's base and outer shell under Kajiya-Kay lighting). Keep in sync with STRAND_LIT in
// crates/pelt-preview/src/frame_data.rs.
const STRAND_LIT: u32 = 65536u;

// one_light for a strand running along `t` (either sign) instead of a surface with normal
// `n`, with reach `r`: Kajiya-Kay (Revie Listing 2.4), diffuse sin(T, L), specular (sin(T, L) sin(T, V) −
// (T·L)(T·V))^p, with the same falloff; fur_light_forward.wgsl evaluates the same terms.
fn strand_light(p: vec3<f32>, t: vec3<f32>, r: vec4<f32>, light: Light, spec_power: f32) -> vec4<f32> {
    let l = r.xyz;
    let atten = r.w;
    let v = normalize(-p);
    let lt = dot(l, t);
    let vt = dot(v, t);
    let sin_l = sqrt(max(1.0 - lt * lt, 0.0));
    let sin_v = sqrt(max(1.0 - vt * vt, 0.0));
    let spec = pow(max(sin_l * sin_v - lt * vt, 0.0), spec_power) * atten;
    return vec4<f32>(light.color.rgb * (sin_l * atten), spec * light.color.w);
}

// Kircher & Lawrance §2.2: the specular colour is rebuilt by scaling the stored intensity by
// the colour of the diffuse lighting (normalised to unit luminance).
fn specular_color(l: vec4<f32>) -> vec3<f32> {
    let lum = luminance(l.rgb);
    if lum <= 1e-5 {
        return vec3<f32>(0.0);
    }
    return l.a * l.rgb / lum;
}

// Octahedral encoding of a unit vector into [-1, 1]^2 (Cigolle et al. 2014), and back.
fn oct_encode(n: vec3<f32>) -> vec2<f32> {
    let p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
    if n.z >= 0.0 {
        return p;
    }
    return (1.0 - abs(p.yx)) * select(vec2<f32>(-1.0), vec2<f32>(1.0), p >= vec2<f32>(0.0));
}

fn oct_decode(e: vec2<f32>) -> vec3<f32> {
    var n = vec3<f32>(e, 1.0 - abs(e.x) - abs(e.y));
    let t = max(-n.z, 0.0);
    n.x += select(t, -t, n.x >= 0.0);
    n.y += select(t, -t, n.y >= 0.0);
    return normalize(n);
}

// A distance-map geometry texel (Rgba16Float on every back end): xy the octahedral normal,
// z the distance cut to f16's 10 mantissa bits (exact in f16 over the range distances take),
// w the remainder (so the sum keeps about 21 bits).
fn pack_geometry(n: vec3<f32>, d: f32) -> vec4<f32> {
    let hi = bitcast<f32>(bitcast<u32>(d) & 0xffffe000u);
    return vec4<f32>(oct_encode(n), hi, d - hi);
}

// The distance of a geometry texel (negative: no surface).
fn texel_distance(g: vec4<f32>) -> f32 {
    return g.z + g.w;
}

// The procedural sky in unit world direction d: a zenith-to-horizon gradient, a darker ground
// and a soft sun glow (sky.wgsl draws it; reflect.wgsl looks it up where rays leave the scene;
// pelt_scene::shading::procedural_sky is its CPU twin).
const SUN: vec3<f32> = vec3<f32>(0.48, 0.62, 0.62);

fn procedural(d: vec3<f32>) -> vec3<f32> {
    let zenith = vec3<f32>(0.10, 0.22, 0.55);
    let horizon = vec3<f32>(0.55, 0.63, 0.75);
    let ground = vec3<f32>(0.09, 0.08, 0.07);
    let up = d.y;
    let sky = mix(horizon, zenith, pow(clamp(up, 0.0, 1.0), 0.6));
    let below = mix(horizon * 0.6, ground, clamp(-up * 6.0, 0.0, 1.0));
    var c = select(below, sky, up >= 0.0);
    let s = max(dot(d, normalize(SUN)), 0.0);
    c += vec3<f32>(1.0, 0.85, 0.6) * (0.6 * pow(s, 64.0) + 0.15 * pow(s, 6.0));
    return c;
}

// The face (+X -X +Y -Y +Z -Z) and texture coordinates (v down) of direction d, by the
// cube-map convention the faces were rendered with (`cube::face_view` in pelt-preview:
// distance maps and shadow cubes).
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
