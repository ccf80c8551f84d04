// upscale.wgsl: `pelt view`'s frame budget renders a moving camera's frames at a lower
// resolution; this pass scales such a frame up to the window with bilinear filtering (the
// full-screen triangle of fullscreen.wgsl). The source is sRGB-encoded and sampled as such,
// so filtering happens in linear light.

#import pelt::fullscreen::{fullscreen_position}

@vertex
fn vs_fullscreen(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(vi);
}

@group(0) @binding(0) var source: texture_2d<f32>;
@group(0) @binding(1) var source_sampler: sampler;
@group(1) @binding(0) var<uniform> target_size: vec4<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return textureSample(source, source_sampler, pos.xy * target_size.zw);
}
