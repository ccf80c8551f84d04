// tangent_frames.wgsl: the GPU half of the tangent-frame contract, as a compute pass: for
// each record (normal, tangent, comb) of `records`, the object-space comb direction
// `comb_object` (fur_common.wgsl) gives, into `directions`. The preview's tests run it against
// pelt_geom::frame on the CPU, so the shaders and the bake cannot drift apart; it is also the
// renderer's reference compute pass (storage buffer in, storage buffer out).

#import pelt::fur_common::{comb_object}

struct FrameRecord {
    // xyz: vertex normal.
    n: vec4<f32>,
    // xyz: tangent, w: handedness.
    t: vec4<f32>,
    // xyz: tangent-space comb.
    c: vec4<f32>,
}

@group(0) @binding(0) var<storage, read> records: array<FrameRecord>;
@group(0) @binding(1) var<storage, read_write> directions: array<vec4<f32>>;

@compute @workgroup_size(64)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&records) {
        return;
    }
    let r = records[i];
    directions[i] = vec4<f32>(comb_object(r.n.xyz, r.t, r.c.xyz), 0.0);
}
