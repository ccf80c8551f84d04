// fur_gbuffer.wgsl: the geometry phase of deferred fur (Revie §2.4.2), at L-buffer
// resolution, into the same G-buffer as every other object (Kircher & Lawrance's normals and
// DSF buffer). Pass 1 (vs_base/fs_base) draws the base mesh with the grain normal of Listing
// 2.5. Pass 2 (vs_outer/fs_outer) draws the outermost shell, pushed out by the fur length ×
// the comb length and combed per Listing 2.1, into one pixel in four (the top-left of each
// 2×2 cell, Listing 2.6), with the grain normal bent toward the back at the silhouette
// (Listing 2.3). Its texels carry the fur's outer-shell ID, so the material phase can tell
// them from the base mesh.

@group(0) @binding(0) var<uniform> frame: Frame;
@group(1) @binding(0) var<uniform> object: Object;

struct FurSurface {
    @builtin(position) clip: vec4<f32>,
    @location(0) view_pos: vec3<f32>,
    @location(1) view_normal: vec3<f32>,
    @location(2) view_comb: vec3<f32>,
    @location(3) @interpolate(flat) group: u32,
}

struct GBufferOut {
    @location(0) normal: vec2<f32>,
    @location(1) dsf: vec2<u32>,
}

fn fur_surface(v: VertexIn, f: FurIn, sd: f32) -> FurSurface {
    var s: FurSurface;
    let comb = comb_object(v.normal, f.tangent, f.comb.xyz);
    let p = v.position + shell_offset(v.normal, comb, sd, object.fur_base.w, f.comb.w);
    let view = frame.view * (object.model * vec4<f32>(p, 1.0));
    s.clip = frame.proj * view;
    s.view_pos = view.xyz;
    s.view_normal = view_normal_of(v.normal, frame, object);
    s.view_comb = view_dir_of(comb, frame, object);
    s.group = v.group;
    return s;
}

@vertex
fn vs_base(v: VertexIn, f: FurIn) -> FurSurface {
    return fur_surface(v, f, 0.0);
}

@vertex
fn vs_outer(v: VertexIn, f: FurIn) -> FurSurface {
    return fur_surface(v, f, 1.0);
}

fn grain(s: FurSurface, front: bool) -> vec3<f32> {
    let n = facing_normal(s.view_normal, front);
    return grain_normal(n, normalize(s.view_comb), normalize(s.view_pos));
}

@fragment
fn fs_base(s: FurSurface, @builtin(front_facing) front: bool) -> GBufferOut {
    var out: GBufferOut;
    out.normal = encode_normal(grain(s, front));
    out.dsf = vec2<u32>(depth_code(-s.view_pos.z, frame), ((object.ids.x & 255u) << 8u) | (s.group & 255u));
    return out;
}

@fragment
fn fs_outer(s: FurSurface, @builtin(front_facing) front: bool) -> GBufferOut {
    let p = vec2<u32>(s.clip.xy);
    if ((p.x | p.y) & 1u) != 0u {
        discard;
    }
    let eye = normalize(s.view_pos);
    let n = rim_normal(grain(s, front), eye, object.fur_params.x, object.fur_params.y);
    var out: GBufferOut;
    out.normal = encode_normal(n);
    out.dsf = vec2<u32>(depth_code(-s.view_pos.z, frame), ((object.ids.z & 255u) << 8u) | (s.group & 255u));
    return out;
}
