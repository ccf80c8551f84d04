// minmax.wgsl: the minimum and maximum distance of every layer of every distance map
// (GPU Gems 3 ch. 17, Figure 17-4: the ray is clipped to the shell between the two spheres
// before the linear search). One workgroup per (map, layer): workgroup (m, l) of a grid of
// (maps, layers) reduces the six faces of layer m * layers + l. A layer with no surface gets
// (3.4e38, -1), which the search skips.

#import pelt::common::{texel_distance}

@group(0) @binding(0) var maps: texture_2d_array<f32>;
@group(0) @binding(1) var<storage, read_write> ranges: array<vec2<f32>>;

const THREADS: u32 = 64u;
var<workgroup> lo: array<f32, THREADS>;
var<workgroup> hi: array<f32, THREADS>;

@compute @workgroup_size(64)
fn cs_main(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) i: u32,
) {
    let layer = wg.x * groups.y + wg.y;
    let size = textureDimensions(maps).x;
    let per_face = size * size;
    var mn = 3.4e38;
    var mx = -1.0;
    for (var t = i; t < per_face * 6u; t += THREADS) {
        let f = t / per_face;
        let r = t % per_face;
        let d = texel_distance(textureLoad(maps, vec2<u32>(r % size, r / size), layer * 6u + f, 0));
        if d > 0.0 {
            mn = min(mn, d);
            mx = max(mx, d);
        }
    }
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
    if i == 0u {
        ranges[layer] = vec2<f32>(lo[0], hi[0]);
    }
}
