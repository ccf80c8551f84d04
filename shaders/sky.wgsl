// sky.wgsl: the skybox at infinity (Frantzen's "skybox at infinity"): the full-screen
// triangle of fullscreen.wgsl at the far plane (depth 1, drawn where nothing else is), looking up the world
// direction through each pixel either in a cube map made from six images (fs_cube) or in a
// procedural sky (fs_procedural, common.wgsl's `procedural`): a zenith-to-horizon gradient,
// a darker ground, and a soft sun glow.

#import pelt::common::{procedural}
#import pelt::fullscreen::{fullscreen_position}
#import pelt::object_bindings::{frame}

@vertex
fn vs_fullscreen(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(vi);
}

@group(1) @binding(0) var sky_cube: texture_cube<f32>;
@group(1) @binding(1) var sky_sampler: sampler;

// The pixel's normalized device coordinates without the projection's jitter (a shift of
// the whole image by t puts −t in the projection's third column; zero unless a caller
// supersamples, as the strand reference does), so the sky is sampled where the geometry is.
fn ndc_of(pos: vec4<f32>) -> vec2<f32> {
    let uv = pos.xy * frame.target_size.zw;
    return vec2<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0) + frame.proj[2].xy;
}

// The world direction through a pixel (the view matrix is a rotation and a translation, so
// its inverse rotation is the transpose).
fn world_dir(ndc: vec2<f32>) -> vec3<f32> {
    let v = normalize(vec3<f32>(ndc.x * frame.proj_params.x, ndc.y * frame.proj_params.y, -1.0));
    let r = mat3x3<f32>(frame.view[0].xyz, frame.view[1].xyz, frame.view[2].xyz);
    return normalize(transpose(r) * v);
}

@fragment
fn fs_procedural(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(procedural(world_dir(ndc_of(pos))), 1.0);
}

@fragment
fn fs_cube(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(textureSample(sky_cube, sky_sampler, world_dir(ndc_of(pos))).rgb, 1.0);
}
