// fur_light_inferred.wgsl: how the fur is lit in the deferred pipeline (Revie §2.4.4): from
// the L-buffer, at two points per strand: the root on the base mesh (the base pass's texels)
// and the tip on the outer shell (the stippled texels, top-left of each 2×2 cell). A tap is
// kept only when its ID is that surface's and its stored linear depth matches the point's, so
// an occluder in front of either point is never sampled into the strand. With Kajiya-Kay fur
// lighting the two hold the strand lit at a quarter and three quarters of its height and are
// mixed by the fragment's height; with Revie's normals the maximum of the valid samples is
// taken (the halo of back-lit fur without darkening edges). With none valid, the taps of the
// same fur at any depth (the fur seen past itself: a camera inside it, a grazing view); with
// none of those either, the same fur's taps within a few texels (a thin edge of fur); then
// the ambient term. The L-buffer holds light without albedo (inferred
// lighting), so Revie's division by the albedo is the identity here.

#define_import_path pelt::fur_light_inferred
#import pelt::common::{DEPTH_EMPTY, DEPTH_STEPS, depth_from_code, specular_color}
#import pelt::fur_common::{FurLight, FurQuery}
#import pelt::object_bindings::{frame, object}

@group(2) @binding(0) var lbuffer: texture_2d<f32>;
@group(2) @binding(1) var dsf: texture_2d<u32>;

struct Taps {
    light: vec4<f32>,
    weight: f32,
    // The taps whose ID is the surface's at any depth: the same fur elsewhere along the
    // texel's ray (a camera inside the fur, a grazing view), the fallback where no tap is
    // valid at the point's depth.
    near_light: vec4<f32>,
    near_weight: f32,
}

// The taps bilinear filtering would read around output pixel `pixel`, on every L-buffer texel
// (`stipple` false) or on the stipple lattice (top-left texels, `stipple` true), keeping those
// whose ID is `id` and whose depth is within `threshold` of `depth`.
fn fur_taps(pixel: vec2<f32>, id: u32, depth: f32, threshold: f32, stipple: bool) -> Taps {
    let ratio = frame.lbuffer_size.xy * frame.target_size.zw;
    let size = vec2<i32>(frame.lbuffer_size.xy);
    let lattice = select(1.0, 2.0, stipple);
    let c = (pixel * ratio - vec2<f32>(0.5)) / lattice;
    let base = floor(c);
    let f = c - base;
    let step = i32(lattice);
    let origin = vec2<i32>(base) * step;
    var t: Taps;
    for (var k = 0u; k < 4u; k++) {
        let corner = vec2<i32>(i32(k & 1u), i32(k >> 1u));
        var tap = origin + corner * step;
        tap = select(tap, tap + vec2<i32>(step), tap < vec2<i32>(0));
        tap = select(tap, tap - vec2<i32>(step), tap >= size);
        tap = clamp(tap, vec2<i32>(0), size - vec2<i32>(1));
        let w = select(1.0 - f.x, f.x, corner.x == 1) * select(1.0 - f.y, f.y, corner.y == 1);
        let d = textureLoad(dsf, tap, 0);
        let same = d.y == id && d.x != DEPTH_EMPTY;
        let ok = same && abs(depth_from_code(d.x, frame) - depth) <= threshold;
        let wk = select(0.0, max(w, 1e-4), ok);
        let wn = select(0.0, max(w, 1e-4), same);
        let l = textureLoad(lbuffer, tap, 0);
        t.light += wk * l;
        t.weight += wk;
        t.near_light += wn * l;
        t.near_weight += wn;
    }
    return t;
}

// How far (in L-buffer texels) the last fallback looks for the same fur.
const WIDE: i32 = 3;

// The taps of the same fur (its skin's or its outer shell's ID, `ids`, at any depth) within
// WIDE L-buffer texels of output pixel `pixel`, nearer ones weighted more: the last fallback
// where a thin edge of the fur (a slab's ends seen at a grazing angle) has none of its own
// four taps; with none here either, the ambient term.
fn wide_taps(pixel: vec2<f32>, ids: vec2<u32>) -> vec4<f32> {
    let ratio = frame.lbuffer_size.xy * frame.target_size.zw;
    let size = vec2<i32>(frame.lbuffer_size.xy);
    let c = vec2<i32>(floor(pixel * ratio));
    var sum = vec4<f32>(0.0);
    var weight = 0.0;
    // One loop whose bound the compiler cannot know (it depends on the L-buffer's size): an
    // unrolled loop would be run, masked, by every fragment of a lockstep rasterizer
    // (llvmpipe, lavapipe); a loop runs only while a lane needs it.
    let side = 2 * min(WIDE, max(size.x, size.y)) + 1;
    for (var i = 0; i < side * side; i++) {
        let o = vec2<i32>(i % side, i / side) - vec2<i32>(side / 2);
        let tap = c + o;
        if any(tap < vec2<i32>(0)) || any(tap >= size) {
            continue;
        }
        let d = textureLoad(dsf, tap, 0);
        if d.x == DEPTH_EMPTY || (d.y != ids.x && d.y != ids.y) {
            continue;
        }
        let w = 1.0 / f32(1 + o.x * o.x + o.y * o.y);
        sum += w * textureLoad(lbuffer, tap, 0);
        weight += w;
    }
    if weight == 0.0 {
        return vec4<f32>(frame.ambient.rgb, 0.0);
    }
    return sum / weight;
}

// `suns`: unused here (the L-buffer holds every light); fur_light_forward.wgsl's signature.
fn fur_lighting(q: FurQuery, suns: bool) -> FurLight {
    var out: FurLight;
    if frame.flags.w == 0u {
        out.diffuse = frame.ambient.rgb;
        return out;
    }
    let ratio = frame.lbuffer_size.xy * frame.target_size.zw;
    let spacing = 1.0 / min(ratio.x, ratio.y);
    let step = (frame.proj_params.w - frame.proj_params.z) / DEPTH_STEPS;
    let floor_t = f32(frame.flags.z) * step;
    // Depth can change across the taps by the point's depth slope over their spacing.
    let tb = 2.0 * fwidth(q.base_depth) * spacing + floor_t + 0.004 * q.base_depth;
    let tt = 4.0 * fwidth(q.top_depth) * spacing + floor_t + 0.004 * q.top_depth;
    let base_id = ((object.ids.x & 255u) << 8u) | (q.group & 255u);
    let top_id = ((object.ids.z & 255u) << 8u) | (q.group & 255u);
    let b = fur_taps(q.base_pixel, base_id, q.base_depth, tb, false);
    let t = fur_taps(q.top_pixel, top_id, q.top_depth, tt, true);
    var l = vec4<f32>(frame.ambient.rgb, 0.0);
    if b.weight > 0.0 && t.weight > 0.0 {
        if object.fur_model.w == 0.0 {
            // Kajiya-Kay: the two samples are the strand lit at ROOT_HEIGHT and TIP_HEIGHT
            // (fur_gbuffer.wgsl); between them, and beyond, the nearer one's share by height.
            l = mix(b.light / b.weight, t.light / t.weight, clamp((q.height - 0.25) / 0.5, 0.0, 1.0));
        } else {
            l = max(b.light / b.weight, t.light / t.weight);
        }
    } else if b.weight > 0.0 {
        l = b.light / b.weight;
    } else if t.weight > 0.0 {
        l = t.light / t.weight;
    } else if b.near_weight + t.near_weight > 0.0 {
        l = (b.near_light + t.near_light) / (b.near_weight + t.near_weight);
    } else {
        l = wide_taps(q.base_pixel, vec2<u32>(base_id, top_id));
    }
    out.diffuse = l.rgb;
    out.specular = specular_color(l);
    return out;
}
