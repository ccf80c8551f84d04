// skin.wgsl: the preview's skinning pass (glTF 2.0 §3.7.3.3, linear blend skinning), one
// invocation per vertex: the weighted sum of the vertex's joint matrices moves its position,
// its cofactor matrix its normal (signed by the determinant, so mirrored joints keep normals
// outward), its upper 3×3 its tangent (w kept). The tangent frame (normal, tangent) is the
// comb's frame, so the baked tangent-space comb rides along (Revie §2.4.1). Weights that do
// not sum to 1 (within 1e-3) are normalized; a vertex with no weight takes the last matrix
// (its node's own transform). The same arithmetic as pelt_anim::skinning (SkinJob::on_cpu),
// which the preview's tests compare against. Keep SkinVertex (and PosedVertex, in common.wgsl)
// in sync with crates/pelt-preview/src/features/skin.rs.

#import pelt::common::{PosedVertex}

struct SkinVertex {
    position: vec4<f32>,
    normal: vec4<f32>,
    tangent: vec4<f32>,
    // x: first influence; y: influence count.
    influences: vec4<u32>,
}

@group(0) @binding(0) var<storage, read> rest: array<SkinVertex>;
@group(0) @binding(1) var<storage, read_write> posed: array<PosedVertex>;
// (joint, bitcast weight) pairs.
@group(1) @binding(0) var<storage, read> influences: array<vec2<u32>>;
// The joints' matrices, then the unweighted vertices' matrix (the Storage layout's binding 1
// is read-write; the pass only reads it).
@group(1) @binding(1) var<storage, read_write> joints: array<mat4x4<f32>>;

fn normalize_or(v: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    let l = length(v);
    if l > 0.0 && l < 3.0e38 {
        return v / l;
    }
    return fallback;
}

@compute @workgroup_size(64)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let v = id.x;
    if v >= arrayLength(&rest) {
        return;
    }
    let r = rest[v];
    var m = mat4x4<f32>(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
    var sum = 0.0;
    for (var i = r.influences.x; i < r.influences.x + r.influences.y; i++) {
        let inf = influences[i];
        let w = bitcast<f32>(inf.y);
        if w != 0.0 {
            sum += w;
            m += joints[inf.x] * w;
        }
    }
    var b = joints[arrayLength(&joints) - 1u];
    if sum > 0.0 && sum < 3.0e38 {
        b = m;
        if abs(sum - 1.0) > 1e-3 {
            b = m * (1.0 / sum);
        }
    }
    let m3 = mat3x3<f32>(b[0].xyz, b[1].xyz, b[2].xyz);
    let cof = mat3x3<f32>(cross(m3[1], m3[2]), cross(m3[2], m3[0]), cross(m3[0], m3[1]));
    let sign = select(1.0, -1.0, determinant(m3) < 0.0);
    var o: PosedVertex;
    o.position = vec4<f32>((b * vec4<f32>(r.position.xyz, 1.0)).xyz, 1.0);
    o.normal = vec4<f32>(normalize_or(cof * r.normal.xyz * sign, r.normal.xyz), 0.0);
    o.tangent = vec4<f32>(normalize_or(m3 * r.tangent.xyz, r.tangent.xyz), r.tangent.w);
    posed[v] = o;
}
