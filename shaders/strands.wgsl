// strands.wgsl: the converged fur reference's explicit strands (see
// crates/pelt-scene/src/strands.rs for how they are planted from the strand model). One
// instance per strand; its vertex stage builds SEGMENTS segments along the shells' path
// (Revie Listing 2.1: along the normal bent toward the comb, scaled by the fur length and the
// comb length) plus the model's lean, each a screen-aligned quad around the segment's
// capsule (a sphere swept along it: a cylinder of the strand's radius with round ends), one
// triangle per segment. The
// fragment stage keeps the pixels whose centre lies inside the projected capsule, so a
// strand thinner than a pixel is exact under jittered supersampling, and shades them with
// Kajiya-Kay per light (fur_light_forward.wgsl, Listing 2.4) about the path's direction (its
// derivative at each end, blended along the segment: no shading jump at the joints),
// the albedo the shells use at that height (root-to-tip lerp). Opaque, depth tested.
// Keep `StrandIn` in sync with `StrandRoot` in crates/pelt-scene/src/vertex.rs and SEGMENTS
// with `STRAND_SEGMENTS` in crates/pelt-preview/src/features/strands.rs.

#import pelt::fur_common::{FurQuery, clip_to_pixel, shell_offset, strand_velocity, view_dir_of, wind_comb}
#import pelt::fur_light_forward::{fur_lighting}
#import pelt::object_bindings::{frame, object}

const SEGMENTS: u32 = 4u;
// SUNS: whether any light of the view is directional; false compiles light_reach's branch on
// the kind out (lights.rs's `suns_for_view`).
override SUNS: bool = true;

struct StrandIn {
    // xyz: root (asset space); w: height (fraction of the fur length).
    @location(0) root: vec4<f32>,
    // xyz: surface normal; w: comb length.
    @location(1) normal: vec4<f32>,
    // xyz: object-space comb; w: radius (asset units).
    @location(2) comb: vec4<f32>,
    // xyz: lean per unit height (asset units); w: tint.
    @location(3) lean: vec4<f32>,
    @location(4) albedo: vec4<f32>,
}

#ifdef TRACED_SHADOWS
// The strand's shadow bits (crates/pelt-trace/src/strands.rs): bit 5 l + k where sample k
// (k / SEGMENTS of its height) sees shadow-casting light l.
struct Traced {
    @location(5) bits: vec2<u32>,
}
#endif

struct StrandOut {
    @builtin(position) clip: vec4<f32>,
    // View-space ends of the segment.
    @location(0) @interpolate(flat) v0: vec3<f32>,
    @location(1) @interpolate(flat) v1: vec3<f32>,
    // Pixel position and radius in pixels of each end.
    @location(2) @interpolate(flat) s0: vec3<f32>,
    @location(3) @interpolate(flat) s1: vec3<f32>,
    // Heights of the ends (fraction of the fur length).
    @location(4) @interpolate(flat) z: vec2<f32>,
    @location(5) @interpolate(flat) albedo: vec3<f32>,
    // The strand's view-space direction at each end (the path's derivative there, lean
    // included): blended along the segment, so the shading has no jump at the joints.
    @location(6) @interpolate(flat) t0: vec3<f32>,
    @location(7) @interpolate(flat) t1: vec3<f32>,
    // The strand's radius in view units.
    @location(8) @interpolate(flat) radius: f32,
    // The strand's shadow bits (0 without traced shadows) and this segment.
    @location(9) @interpolate(flat) traced: vec2<u32>,
    @location(10) @interpolate(flat) segment: u32,
}

// Strand `s`'s comb, bent by the wind at its root as the shells' and fins' (wind_comb).
fn comb_of(s: StrandIn) -> vec3<f32> {
    return wind_comb(s.comb.xyz, s.normal.xyz, s.root.xyz, frame, object);
}

// The point at height `z` (fraction of the fur length) of strand `s`, in asset space.
fn strand_point(s: StrandIn, z: f32) -> vec3<f32> {
    let len = object.fur_base.w;
    return s.root.xyz + s.lean.xyz * z + shell_offset(s.normal.xyz, comb_of(s), z, len, s.normal.w);
}

// The direction of strand `s` at height `z`, in view space.
fn strand_direction(s: StrandIn, z: f32) -> vec3<f32> {
    let k = object.fur_base.w * s.normal.w;
    let d = s.lean.xyz + strand_velocity(s.normal.xyz, comb_of(s), z) * k;
    return view_dir_of(d, frame, object);
}

// Pixels per view-space unit at view depth `w` (vertical).
fn pixels_per_unit(w: f32) -> f32 {
    return frame.proj[1][1] * 0.5 * frame.target_size.y / max(w, 1e-6);
}

@vertex
fn vs_main(
    s: StrandIn,
#ifdef TRACED_SHADOWS
    traced: Traced,
#endif
    @builtin(vertex_index) vid: u32,
) -> StrandOut {
    var o: StrandOut;
    let seg = vid / 3u;
    let corner = vid % 3u;
    o.segment = seg;
#ifdef TRACED_SHADOWS
    o.traced = traced.bits;
#endif
    let z0 = s.root.w * f32(seg) / f32(SEGMENTS);
    let z1 = s.root.w * f32(seg + 1u) / f32(SEGMENTS);
    let to_view = frame.view * object.model;
    let v0 = (to_view * vec4<f32>(strand_point(s, z0), 1.0)).xyz;
    let v1 = (to_view * vec4<f32>(strand_point(s, z1), 1.0)).xyz;
    // The model's scale, for the radius (uniform scales exactly, others on average).
    let scale = (length(to_view[0].xyz) + length(to_view[1].xyz) + length(to_view[2].xyz)) / 3.0;
    let radius = s.comb.w * scale;
    let c0 = frame.proj * vec4<f32>(v0, 1.0);
    let c1 = frame.proj * vec4<f32>(v1, 1.0);
    o.v0 = v0;
    o.v1 = v1;
    o.radius = radius;
    o.z = vec2<f32>(z0, z1);
    o.t0 = strand_direction(s, z0);
    o.t1 = strand_direction(s, z1);
    o.albedo = s.albedo.rgb * object.tint.rgb;
    let near = frame.proj_params.z;
    let reach = object.fur_base.w * s.normal.w * s.root.w;
    if -v0.z < near || -v1.z < near || !(reach > 0.0) {
        // Crossing the near plane, or no fur (length, comb length or height 0): dropped (a
        // zero-area triangle).
        o.clip = vec4<f32>(2.0, 2.0, 0.5, 1.0);
        return o;
    }
    let p0 = clip_to_pixel(c0, frame);
    let p1 = clip_to_pixel(c1, frame);
    let r0 = radius * pixels_per_unit(c0.w);
    let r1 = radius * pixels_per_unit(c1.w);
    o.s0 = vec3<f32>(p0, r0);
    o.s1 = vec3<f32>(p1, r1);
    var d = p1 - p0;
    let l = length(d);
    d = select(vec2<f32>(1.0, 0.0), d / l, l > 1e-6);
    let across = vec2<f32>(-d.y, d.x);
    // One triangle around the rectangle that holds both end discs (a hundredth of a pixel
    // wider, against rounding): the rectangle [0, W] × [0, H] lies in the triangle (0, 0), (2W, 0),
    // (0, 2H). Twice the area of two triangles, half the vertices: the strand reference is
    // bound by geometry work on a CPU rasterizer.
    let r = max(r0, r1) + 0.01;
    let origin = p0 - d * r - across * r;
    var px = origin;
    var along = -r;
    if corner == 1u {
        along = 2.0 * (l + 2.0 * r) - r;
        px = origin + d * 2.0 * (l + 2.0 * r);
    } else if corner == 2u {
        px = origin + across * 4.0 * r;
    }
    // Depth linear in screen space along the segment, exact at both ends (no perspective
    // division: w = 1), so early depth testing still works.
    let d0 = c0.z / c0.w;
    let d1 = c1.z / c1.w;
    // A segment seen end-on (shorter on screen than it is wide) shows its near end's cap.
    let end_on = l < max(r0, r1);
    let z = select(d0 + (d1 - d0) * along / l, min(d0, d1), end_on);
    let ndc = vec2<f32>(px.x / frame.target_size.x * 2.0 - 1.0, 1.0 - px.y / frame.target_size.y * 2.0);
    o.clip = vec4<f32>(ndc, clamp(z, 0.0, 1.0), 1.0);
    return o;
}

// The view-space direction of the ray through pixel `p` (framebuffer coordinates) for a
// perspective projection, jittered or not (the jitter is a shift of P[2].xy).
fn pixel_ray(p: vec2<f32>) -> vec3<f32> {
    let ndc = vec2<f32>(p.x * frame.target_size.z * 2.0 - 1.0, 1.0 - p.y * frame.target_size.w * 2.0);
    let x = (ndc.x + frame.proj[2][0]) / frame.proj[0][0];
    let y = (ndc.y + frame.proj[2][1]) / frame.proj[1][1];
    return normalize(vec3<f32>(x, y, -1.0));
}

// Where along the capsule of radius `r` around segment a → b (0 at a, 1 at b) the eye's ray
// `rd` first meets its surface (x; −1 where it misses) and how far from the eye (y). The ray starts at its closest
// approach to `a` rather than at the eye, so that f32 keeps the precision of a capsule far
// thinner than its distance.
fn capsule_hit(rd: vec3<f32>, a: vec3<f32>, b: vec3<f32>, r: f32) -> vec2<f32> {
    let t0 = dot(a, rd);
    let ro = rd * t0;
    let ba = b - a;
    let oa = ro - a;
    let baba = dot(ba, ba);
    let bard = dot(ba, rd);
    let baoa = dot(ba, oa);
    let rdoa = dot(rd, oa);
    let qa = baba - bard * bard;
    let qb = baba * rdoa - baoa * bard;
    let qc = baba * dot(oa, oa) - baoa * baoa - r * r * baba;
    let disc = qb * qb - qa * qc;
    if disc >= 0.0 && qa > 1e-12 * baba {
        // The cylinder's side, where it lies between the ends.
        let t = (-qb - sqrt(disc)) / qa;
        let y = baoa + t * bard;
        if y > 0.0 && y < baba {
            return vec2<f32>(y / baba, t0 + t);
        }
    }
    // The round ends: the nearer sphere the ray meets.
    var best = -1.0;
    var depth = 1e30;
    for (var e = 0u; e < 2u; e++) {
        let centre = select(a, b, e == 1u);
        let oc = ro - centre;
        let hb = dot(rd, oc);
        let hc = dot(oc, oc) - r * r;
        let h = hb * hb - hc;
        if h >= 0.0 {
            let t = -hb - sqrt(h);
            if t < depth {
                depth = t;
                best = f32(e);
            }
        }
    }
    if best < 0.0 {
        return vec2<f32>(-1.0, 0.0);
    }
    // Inside the sphere's half that the cylinder does not cover: the axis parameter there.
    let hit = ro + rd * depth;
    return vec2<f32>(clamp(dot(hit - a, ba) / max(baba, 1e-30), 0.0, 1.0), t0 + depth);
}

struct StrandFragment {
    @location(0) color: vec4<f32>,
    @builtin(frag_depth) depth: f32,
}

@fragment
fn fs_main(f: StrandOut) -> StrandFragment {
    // The visible point is where the pixel's ray meets the capsule first; the strand's
    // height, direction and colour are the axis's there (the point of the axis nearest the
    // hit), so a strand wider than a pixel shows the part of its length that faces the eye.
    let r = f.radius;
    let rd = pixel_ray(f.clip.xy);
    let hit = capsule_hit(rd, f.v0, f.v1, r);
    if hit.x < 0.0 {
        discard;
    }
    let t = hit.x;
    // The depth of the hit itself: the quad's own depth, extrapolated past a steep
    // segment's root, would pass under the skin and be hidden there.
    let c = frame.proj * vec4<f32>(rd * hit.y, 1.0);
    let view_pos = mix(f.v0, f.v1, t);
    let blend = mix(f.t0, f.t1, t);
    let dir = select(f.t0, normalize(blend), length(blend) > 1e-6);
    var q: FurQuery;
    q.view_pos = view_pos;
    q.strand = dir;
    q.traced = f.traced;
    q.segment = f.segment;
    q.along = t;
    let l = fur_lighting(q, SUNS);
    let height = mix(f.z.x, f.z.y, t);
    let albedo = f.albedo * mix(object.fur_base.rgb, object.fur_tip.rgb, height);
    var o: StrandFragment;
    o.color = vec4<f32>(albedo * l.diffuse + object.params.y * l.specular, 1.0);
    o.depth = clamp(c.z / c.w, 0.0, 1.0);
    return o;
}
