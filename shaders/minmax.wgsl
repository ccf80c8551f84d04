// minmax.wgsl: the minimum and maximum distance of every layer of every distance map
// (GPU Gems 3 ch. 17, Figure 17-4: the ray is clipped to the shell between the two spheres
// before the linear search), in two steps. cs_partial: one workgroup per (face, band of
// rows) of every layer, dispatched as (maps × layers × 6, BANDS), writes the band's range into
// `partials`; cs_main: one workgroup per (map, layer), dispatched as (maps, layers), reduces
// its six faces' bands into `ranges`. (One workgroup reducing a whole layer looped over
// 6 × size² / 64 texels per thread; on llvmpipe such a loop came back with too small a
// maximum at a 1024 face, and the search then clipped away the farthest surfaces.) A layer
// with no surface gets (3.4e38, -1), which the search skips.

#import pelt::common::{texel_distance}

@group(0) @binding(0) var maps: texture_2d_array<f32>;
@group(0) @binding(1) var<storage, read_write> ranges: array<vec2<f32>>;
@group(0) @binding(2) var<storage, read_write> partials: array<vec2<f32>>;

const THREADS: u32 = 64u;
// Bands of rows per face (crates/pelt-preview/src/features/reflect/mod.rs's MINMAX_BANDS).
const BANDS: u32 = 64u;
var<workgroup> lo: array<f32, THREADS>;
var<workgroup> hi: array<f32, THREADS>;

// The workgroup's minimum and maximum of this thread's (mn, mx), in lo[0] and hi[0].
fn reduce(i: u32, mn: f32, mx: f32) {
    lo[i] = mn;
    hi[i] = mx;
    workgroupBarrier();
    for (var step = THREADS / 2u; step > 0u; step /= 2u) {
        if i < step {
            lo[i] = min(lo[i], lo[i + step]);
            hi[i] = max(hi[i], hi[i + step]);
        }
        workgroupBarrier();
    }
}

@compute @workgroup_size(64)
fn cs_partial(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(local_invocation_index) i: u32,
) {
    let face = wg.x;
    let band = wg.y;
    let size = textureDimensions(maps).x;
    let rows = (size + BANDS - 1u) / BANDS;
    let first = min(band * rows, size);
    let count = (min(first + rows, size) - first) * size;
    var mn = 3.4e38;
    var mx = -1.0;
    for (var t = i; t < count; t += THREADS) {
        let d = texel_distance(textureLoad(maps, vec2<u32>(t % size, first + t / size), face, 0));
        if d > 0.0 {
            mn = min(mn, d);
            mx = max(mx, d);
        }
    }
    reduce(i, mn, mx);
    if i == 0u {
        partials[face * BANDS + band] = vec2<f32>(lo[0], hi[0]);
    }
}

@compute @workgroup_size(64)
fn cs_main(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) i: u32,
) {
    let layer = wg.x * groups.y + wg.y;
    var mn = 3.4e38;
    var mx = -1.0;
    for (var t = i; t < 6u * BANDS; t += THREADS) {
        let p = partials[layer * 6u * BANDS + t];
        mn = min(mn, p.x);
        mx = max(mx, p.y);
    }
    reduce(i, mn, mx);
    if i == 0u {
        ranges[layer] = vec2<f32>(lo[0], hi[0]);
    }
}
