// skin_scatter.wgsl: skinned vertices (skin.wgsl's output) copied into the vertex buffers the
// G-buffer, material and shell passes draw from: position and normal into the mesh's vertex
// records (`Vertex`, 13 floats), the tangent (the comb's frame) into the fur vertex records
// (`FurVertex`, 10 floats), at the primitive's first vertex. Albedo, group, UVs and the comb
// stay as loaded. The strides are common.wgsl's VERTEX_FLOATS and FUR_FLOATS.

#import pelt::common::{FUR_FLOATS, PosedVertex, VERTEX_FLOATS}

@group(0) @binding(0) var<storage, read> posed: array<PosedVertex>;
@group(0) @binding(1) var<storage, read_write> vertices: array<f32>;
// x: the primitive's first vertex; y: its vertex count; z: 1 when the mesh has fur vertices.
@group(1) @binding(0) var<storage, read> params: array<u32>;
@group(1) @binding(1) var<storage, read_write> fur: array<f32>;

@compute @workgroup_size(64)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = id.x;
    if k >= params[1] {
        return;
    }
    let p = posed[k];
    let v = (params[0] + k) * VERTEX_FLOATS;
    vertices[v] = p.position.x;
    vertices[v + 1u] = p.position.y;
    vertices[v + 2u] = p.position.z;
    vertices[v + 3u] = p.normal.x;
    vertices[v + 4u] = p.normal.y;
    vertices[v + 5u] = p.normal.z;
    if params[2] == 1u {
        let f = (params[0] + k) * FUR_FLOATS;
        fur[f] = p.tangent.x;
        fur[f + 1u] = p.tangent.y;
        fur[f + 2u] = p.tangent.z;
        fur[f + 3u] = p.tangent.w;
    }
}
