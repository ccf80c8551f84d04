// material.wgsl: the material pass of inferred lighting (Kircher & Lawrance §2.3, §3, §4), at
// output resolution. Each surface infers its lighting from the four L-buffer texels that
// bilinear filtering would read, keeping only those whose DSF ID matches exactly and whose
// linear depth matches within a threshold (discontinuity sensitive filtering); plain bilinear
// when none match, or when DSF is off; the ambient term alone when the frame has no L-buffer. Alpha objects read the four nearest texels of their own
// 2×2 stipple pattern. Specular colour is rebuilt from the diffuse colour (§2.2). The
// material's base colour texture multiplies the albedo; its metallic-roughness texture and
// factors scale the diffuse and specular terms (common.wgsl's metal_rough).

#import pelt::common::{DEPTH_EMPTY, DEPTH_STEPS, Surface, VertexIn, depth_from_code, dsf_id, metal_rough, specular_color, to_surface}
#import pelt::object_bindings::{frame, object}
#import pelt::material_bindings::{base_sampler, base_texture, material, mr_sampler, mr_texture}

@group(2) @binding(0) var lbuffer: texture_2d<f32>;
@group(2) @binding(1) var dsf: texture_2d<u32>;

// TEXTURED: the pipeline of materials with textures (true) or of those without (false),
// which read the neutral texel's values (white base colour, metallic-roughness 1, no normal
// map) without sampling: an untextured material pays for no texture fetch. Keep the neutral
// values in sync with crates/pelt-preview/src/gpu_material.rs.
override TEXTURED: bool = true;

@vertex
fn vs_main(v: VertexIn) -> Surface {
    return to_surface(v, frame, object);
}

// Keeps a tap inside the L-buffer without leaving its stipple lattice (step 1 or 2).
fn clamp_tap(t: vec2<i32>, size: vec2<i32>, step: i32) -> vec2<i32> {
    var r = t;
    r = select(r, r + vec2<i32>(step), r < vec2<i32>(0));
    r = select(r, r - vec2<i32>(step), r >= size);
    return clamp(r, vec2<i32>(0), size - vec2<i32>(1));
}

@fragment
fn fs_main(s: Surface, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var base_color = vec4<f32>(1.0);
    var mr = vec4<f32>(1.0);
    if TEXTURED {
        base_color = textureSample(base_texture, base_sampler, s.uv);
        mr = textureSample(mr_texture, mr_sampler, s.uv);
    }
    let albedo = s.albedo * base_color;
    let k = metal_rough(material.factors.y * mr.b, material.factors.z * mr.g);
    let depth = -s.view_pos.z;
    let pattern = object.ids.y;
    let lattice = select(2.0, 1.0, pattern == 0u);
    // How far apart (in linear depth) two L-buffer taps of this surface can be: the surface's
    // depth slope across one tap spacing, twice over, plus a few quantisation steps.
    let ratio = frame.lbuffer_size.xy * frame.target_size.zw;
    let slope = fwidth(depth) * lattice / min(ratio.x, ratio.y);
    let step = (frame.proj_params.w - frame.proj_params.z) / DEPTH_STEPS;
    let threshold = 2.0 * slope + f32(frame.flags.z) * step + 0.002 * depth;

    let size = vec2<i32>(frame.lbuffer_size.xy);
    let offset = vec2<f32>(f32(pattern & 1u), f32(pattern >> 1u));
    // The fragment in L-buffer texel space (texel centres at integers), then on its lattice.
    let q = s.clip.xy * ratio - vec2<f32>(0.5);
    let c = (q - select(vec2<f32>(0.0), offset, pattern != 0u)) / lattice;
    let base = floor(c);
    let f = c - base;
    let id = dsf_id(object, s.group);
    let step_i = i32(lattice);
    let origin = vec2<i32>(base) * step_i + select(vec2<i32>(0), vec2<i32>(offset), pattern != 0u);

    var bilinear = vec4<f32>(0.0);
    var filtered = vec4<f32>(0.0);
    var kept = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let corner = vec2<i32>(i32(k & 1u), i32(k >> 1u));
        let tap = clamp_tap(origin + corner * step_i, size, step_i);
        let w = select(1.0 - f.x, f.x, corner.x == 1) * select(1.0 - f.y, f.y, corner.y == 1);
        let l = textureLoad(lbuffer, tap, 0);
        bilinear += w * l;
        let d = textureLoad(dsf, tap, 0);
        let same = d.y == id && d.x != DEPTH_EMPTY && abs(depth_from_code(d.x, frame) - depth) <= threshold;
        // A tiny floor keeps a matching tap usable when its bilinear weight is exactly zero.
        let wk = select(0.0, max(w, 1e-4), same);
        filtered += wk * l;
        kept += wk;
    }
    var light = bilinear;
    if frame.flags.w == 0u {
        // No L-buffer (no light on screen): the ambient term alone.
        light = vec4<f32>(frame.ambient.rgb, 0.0);
    } else if frame.flags.x == 1u && kept > 0.0 {
        light = filtered / kept;
    }
    let metal = material.factors.y * mr.b;
    let spec_tint = mix(vec3<f32>(1.0), albedo.rgb, metal);
    let color = albedo.rgb * k.y * light.rgb + object.params.y * k.x * spec_tint * specular_color(light);
    return vec4<f32>(color, object.params.x * albedo.a);
}
