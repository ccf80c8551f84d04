// fin_rebuild.wgsl: a skinned mesh's fin instances rebuilt from its skinned vertices, one
// invocation per fin edge. Each edge is kept as vertex indices (crates/pelt-scene/src/skin.rs's
// FinSource: the edge's two vertices, then both faces' three in winding order), so the fins
// follow the skin: positions and normals from the vertex records, the combed direction from
// the skinned tangent frame (comb_object, the same rule the shells use), both faces' normals
// from the skinned positions; the fin texture offset, group and colour are copied from the
// loaded instance. The output is FinInstance's layout (fins.wgsl's FinIn, 32 floats). The strides
// are common.wgsl's VERTEX_FLOATS and FUR_FLOATS; the offsets follow crates/pelt-scene/src/vertex.rs.

#import pelt::common::{FUR_FLOATS, VERTEX_FLOATS}
#import pelt::fur_common::{comb_object}

const FIN_FLOATS: u32 = 32u;
// crates/pelt-scene/src/fur.rs's FIN_MIN_LENGTH.
const FIN_MIN_LENGTH: f32 = 0.05;
// Per fin in `fin_in`: 8 source indices, then the loaded instance's 32 words.
const FIN_IN_WORDS: u32 = 40u;

@group(0) @binding(0) var<storage, read> fin_in: array<u32>;
@group(0) @binding(1) var<storage, read_write> fin_out: array<f32>;
@group(1) @binding(0) var<storage, read> fur: array<f32>;
// The Storage layout's binding 1 is read-write; the pass only reads the vertices.
@group(1) @binding(1) var<storage, read_write> vertices: array<f32>;

fn position_of(v: u32) -> vec3<f32> {
    let o = v * VERTEX_FLOATS;
    return vec3<f32>(vertices[o], vertices[o + 1u], vertices[o + 2u]);
}

fn normal_of(v: u32) -> vec3<f32> {
    let o = v * VERTEX_FLOATS + 3u;
    return vec3<f32>(vertices[o], vertices[o + 1u], vertices[o + 2u]);
}

fn fur_of(v: u32, at: u32) -> vec4<f32> {
    let o = v * FUR_FLOATS + at;
    return vec4<f32>(fur[o], fur[o + 1u], fur[o + 2u], fur[o + 3u]);
}

// The combed direction (object space) bent by the springs, and the comb length, of vertex v.
fn comb_at(v: u32) -> vec4<f32> {
    let c = fur_of(v, 6u);
    let bend = fur_of(v, 10u);
    // w: the comb length in the asset's units (fur_common.wgsl's comb_length).
    return vec4<f32>(comb_object(normal_of(v), fur_of(v, 0u), c.xyz) + bend.xyz, c.w * bend.w);
}

fn face_normal(a: u32, b: u32, c: u32) -> vec3<f32> {
    let pa = position_of(a);
    let n = cross(position_of(b) - pa, position_of(c) - pa);
    let l = length(n);
    return select(vec3<f32>(0.0), n / l, l > 0.0);
}

fn put3(o: u32, v: vec3<f32>) {
    fin_out[o] = v.x;
    fin_out[o + 1u] = v.y;
    fin_out[o + 2u] = v.z;
}

fn put4(o: u32, v: vec4<f32>) {
    put3(o, v.xyz);
    fin_out[o + 3u] = v.w;
}

@compute @workgroup_size(64)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    if k >= arrayLength(&fin_out) / FIN_FLOATS {
        return;
    }
    let s = k * FIN_IN_WORDS;
    let a = fin_in[s];
    let b = fin_in[s + 1u];
    let o = k * FIN_FLOATS;
    put3(o, position_of(a));
    put3(o + 3u, position_of(b));
    put3(o + 6u, normal_of(a));
    put3(o + 9u, normal_of(b));
    // As the loaded instances (crates/pelt-scene/src/fur.rs, fin_instances): no fin where the
    // fur at both ends is shorter than FIN_MIN_LENGTH of the fur length.
    let keep = select(0.0, 1.0, max(fur_of(a, 6u).w, fur_of(b, 6u).w) > FIN_MIN_LENGTH);
    let ca = comb_at(a);
    let cb = comb_at(b);
    put4(o + 12u, vec4<f32>(ca.xyz, ca.w * keep));
    put4(o + 16u, vec4<f32>(cb.xyz, cb.w * keep));
    put3(o + 20u, face_normal(fin_in[s + 2u], fin_in[s + 3u], fin_in[s + 4u]));
    put3(o + 23u, face_normal(fin_in[s + 5u], fin_in[s + 6u], fin_in[s + 7u]));
    // u (2 floats), group (u32 bits), albedo (3 floats): as loaded.
    for (var w = 26u; w < FIN_FLOATS; w++) {
        fin_out[o + w] = bitcast<f32>(fin_in[s + 8u + w]);
    }
}
