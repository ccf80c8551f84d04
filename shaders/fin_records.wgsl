// fin_records.wgsl: the GPU half of the fin-record contract (docs/format.md, format version
// 2; pelt_io::topology::fin_geometry is the CPU half). A record is two corners, elements of the
// primitive's index list: where the edge starts in the winding of its lowest face, and in its
// second face's (0xFFFFFFFF on a boundary). Through the index list they give the edge's two
// vertices and both faces' geometric normals, computed from the positions drawn with (so
// skinned or morphed positions give the deformed normals). As a compute pass it decodes every
// record into `decoded`; the preview's tests run it against the CPU decode. The mesh's group
// uses the Storage layout, whose binding 1 is read-write: positions are only read.

const NO_CORNER: u32 = 0xffffffffu;

struct DecodedFin {
    // xy: the edge's vertices in its first face's winding; z: 1 on a boundary.
    ends: vec4<u32>,
    // xyz: the first face's unit normal (counter-clockwise).
    n0: vec4<f32>,
    // xyz: the second face's (the first's on a boundary).
    n1: vec4<f32>,
}

@group(0) @binding(0) var<storage, read> fins: array<vec2<u32>>;
@group(0) @binding(1) var<storage, read_write> decoded: array<DecodedFin>;
@group(1) @binding(0) var<storage, read> indices: array<u32>;
@group(1) @binding(1) var<storage, read_write> positions: array<f32>;

fn next_corner(c: u32) -> u32 {
    return c - c % 3u + (c + 1u) % 3u;
}

fn prev_corner(c: u32) -> u32 {
    return c - c % 3u + (c + 2u) % 3u;
}

fn corner_position(c: u32) -> vec3<f32> {
    let v = indices[c];
    return vec3<f32>(positions[3u * v], positions[3u * v + 1u], positions[3u * v + 2u]);
}

// The unit geometric normal of the face holding corner c; zero for a face with no area.
fn face_normal_at(c: u32) -> vec3<f32> {
    let a = corner_position(c);
    let n = cross(corner_position(next_corner(c)) - a, corner_position(prev_corner(c)) - a);
    let len = length(n);
    return select(vec3<f32>(0.0), n / len, len > 0.0);
}

fn decode_fin(record: vec2<u32>) -> DecodedFin {
    var d: DecodedFin;
    let c0 = record.x;
    let boundary = record.y == NO_CORNER;
    d.ends = vec4<u32>(indices[c0], indices[next_corner(c0)], select(0u, 1u, boundary), 0u);
    d.n0 = vec4<f32>(face_normal_at(c0), 0.0);
    d.n1 = select(vec4<f32>(face_normal_at(record.y), 0.0), d.n0, boundary);
    return d;
}

@compute @workgroup_size(64)
fn cs_main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i >= arrayLength(&fins) {
        return;
    }
    decoded[i] = decode_fin(fins[i]);
}
