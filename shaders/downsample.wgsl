// downsample.wgsl: one mip level of a layered target (crates/pelt-preview/src/features/mips.rs)
// from the level above, one layer at a time: each texel the bilinear sample at its centre,
// which is the corner of four texels above, so their 2×2 average (in linear light for sRGB
// formats). The source is a 2D-array view holding only the level above, so the level being
// written is never also read; a layer index picks the face (a D2 view of one layer of an
// array cannot be sampled on every back end).

#import pelt::fullscreen::{fullscreen_position}

@vertex
fn vs_fullscreen(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(vi);
}

@group(0) @binding(0) var source: texture_2d_array<f32>;
@group(0) @binding(1) var source_sampler: sampler;
// xy: 1 / the written level's size; z: the layer.
@group(1) @binding(0) var<uniform> params: vec4<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    return textureSampleLevel(source, source_sampler, pos.xy * params.xy, i32(params.z), 0.0);
}
