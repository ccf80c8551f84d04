// obliterate.wgsl: the stipple obliteration pass of deferred fur (Revie §2.4.4, Figure
// 2.19), at L-buffer resolution. It writes the composition copy of the L-buffer and of the
// DSF buffer (depth and ID) that every ordinary material reads: each outer-shell texel (an
// ID the table marks as a fur's outer shell, on the top-left of its 2×2 cell) is replaced by
// a neighbour in its cell, the fur's base mesh where one is there, so no stipple value reaches
// the image and the depth there is the base mesh's again. The shells themselves still read
// the original buffers.

#import pelt::fullscreen::{fullscreen_position}

@vertex
fn vs_fullscreen(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(vi);
}

@group(0) @binding(0) var lbuffer: texture_2d<f32>;
@group(0) @binding(1) var dsf: texture_2d<u32>;
// For each object ID (0..255): the base ID of the fur whose outer shell it is, else 0 (the
// low byte; STRAND_LIT above it, see light.wgsl).
@group(1) @binding(0) var<uniform> shell_table: array<vec4<u32>, 64>;

struct ObliterateOut {
    @location(0) light: vec4<f32>,
    @location(1) dsf: vec2<u32>,
}

fn base_of(object_id: u32) -> u32 {
    let i = object_id & 255u;
    return shell_table[i >> 2u][i & 3u] & 255u;
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> ObliterateOut {
    let q = vec2<i32>(pos.xy);
    let size = vec2<i32>(textureDimensions(dsf));
    var out: ObliterateOut;
    let d = textureLoad(dsf, q, 0);
    out.light = textureLoad(lbuffer, q, 0);
    out.dsf = d.xy;
    let base = base_of(d.y >> 8u);
    if ((q.x | q.y) & 1) != 0 || base == 0u {
        return out;
    }
    // Right, below, diagonal: the first of the fur's own base mesh, else the first that is no
    // outer shell.
    let offsets = array<vec2<i32>, 3>(vec2<i32>(1, 0), vec2<i32>(0, 1), vec2<i32>(1, 1));
    var pick = -1;
    var fallback = -1;
    for (var k = 0; k < 3; k++) {
        let n = min(q + offsets[k], size - vec2<i32>(1));
        let dn = textureLoad(dsf, n, 0);
        if pick < 0 && (dn.y >> 8u) == base {
            pick = k;
        }
        if fallback < 0 && base_of(dn.y >> 8u) == 0u && any(n != q) {
            fallback = k;
        }
    }
    let k = select(fallback, pick, pick >= 0);
    if k >= 0 {
        let n = min(q + offsets[k], size - vec2<i32>(1));
        out.light = textureLoad(lbuffer, n, 0);
        out.dsf = textureLoad(dsf, n, 0).xy;
    }
    return out;
}
