// shells.wgsl: the concentric shells of the material phase (Revie §2.3.1, §2.4.4; Lengyel et
// al. 2001). One instanced draw per fur object: instance s is the shell at normalized depth
// s / N (Listing 2.1); instance 0 is the base mesh, drawn opaque. Each fragment is lit at the
// strand's root (base mesh) and tip (outer shell) through `fur_lighting` (the L-buffer in the
// deferred pipeline, fur_light_inferred.wgsl, or every light directly with Kajiya-Kay,
// fur_light_forward.wgsl), takes the root-to-tip albedo lerp by shell depth, and fades
// strands out with smoothstep where the shell depth reaches the heightfield sampled at
// TEXCOORD_0 × uvScale. fs_main writes straight alpha for "over" blending (inner shells
// first) or, with the WBOIT override, weighted blended OIT (McGuire & Bavoil 2013).

@group(0) @binding(0) var<uniform> frame: Frame;
@group(1) @binding(0) var<uniform> object: Object;
@group(3) @binding(0) var heightfield: texture_2d<f32>;
@group(3) @binding(1) var fin_texture: texture_2d<f32>;
@group(3) @binding(2) var repeat_sampler: sampler;
@group(3) @binding(3) var fin_sampler: sampler;
@group(3) @binding(4) var base_texture: texture_2d<f32>;
@group(3) @binding(5) var base_sampler: sampler;

struct ShellOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) view_pos: vec3<f32>,
    @location(1) strand: vec3<f32>,
    @location(2) base_clip: vec4<f32>,
    @location(3) top_clip: vec4<f32>,
    // x: base linear depth, y: top linear depth, z: shell depth, w: comb length.
    @location(4) depths: vec4<f32>,
    @location(5) uv: vec2<f32>,
    @location(6) albedo: vec3<f32>,
    @location(7) @interpolate(flat) group: u32,
    @location(8) @interpolate(flat) shell: u32,
    // The material's texture coordinates (the base colour texture's set).
    @location(9) base_uv: vec2<f32>,
}

@vertex
fn vs_main(v: VertexIn, f: FurIn, @builtin(instance_index) shell: u32) -> ShellOut {
    var o: ShellOut;
    let n = max(object.ids.w, 1u);
    let sd = f32(shell) / f32(n);
    let comb = comb_object(v.normal, f.tangent, f.comb.xyz);
    let len = object.fur_base.w;
    let to_view = frame.view * object.model;
    let p = to_view * vec4<f32>(v.position + shell_offset(v.normal, comb, sd, len, f.comb.w), 1.0);
    let pb = to_view * vec4<f32>(v.position, 1.0);
    let pt = to_view * vec4<f32>(v.position + shell_offset(v.normal, comb, 1.0, len, f.comb.w), 1.0);
    o.clip = frame.proj * p;
    o.view_pos = p.xyz;
    o.strand = view_dir_of(strand_dir(v.normal, comb, sd), frame, object);
    o.base_clip = frame.proj * pb;
    o.top_clip = frame.proj * pt;
    o.depths = vec4<f32>(-pb.z, -pt.z, sd, f.comb.w);
    o.uv = f.uv;
    o.albedo = v.albedo.rgb * object.tint.rgb;
    o.group = v.group;
    o.shell = shell;
    o.base_uv = v.uv;
    return o;
}

// Colour and coverage of a shell fragment.
fn shade(s: ShellOut) -> vec4<f32> {
    let sd = s.depths.z;
    let h = textureSample(heightfield, repeat_sampler, s.uv * object.fur_tip.w).r;
    let under = textureSample(base_texture, base_sampler, s.base_uv).rgb;
    // Strands end where the shell depth reaches their height (Revie §2.4.4); fur shorter than
    // 5 % of the length fades away rather than lying flat on the skin. The base is opaque.
    let strand = (1.0 - smoothstep(h - object.fur_params.z, h, sd)) * clamp(s.depths.w * 20.0, 0.0, 1.0);
    let a = select(strand, 1.0, s.shell == 0u);
    let l = fur_lighting(fur_query(
        s.view_pos, s.strand, s.base_clip, s.top_clip, s.depths.x, s.depths.y, s.group, frame,
    ));
    // With the fur config's colorFromTexture, the base colour texture under the strand
    // colours the whole strand (root and tip colours then shade it).
    let tint = select(vec3<f32>(1.0), under, object.params.w == 1.0);
    let albedo = s.albedo * tint * mix(object.fur_base.rgb, object.fur_tip.rgb, sd);
    return vec4<f32>(albedo * l.diffuse + object.params.y * l.specular, a);
}

@fragment
fn fs_main(s: ShellOut) -> FurOut {
    let c = shade(s);
    if c.a <= 0.0 {
        discard;
    }
    return fur_out(c, -s.view_pos.z, object.fur_params.w);
}
