// composite.wgsl: resolves weighted blended order-independent transparency (McGuire & Bavoil
// 2013; Frantzen's step 3) over the opaque image: the accumulated colour divided by the
// accumulated weight is the weighted average of every fur layer at the pixel, and its coverage
// is 1 − revealage (the product of every layer's 1 − alpha). Blended "over" the image.

#import pelt::fullscreen::{fullscreen_position}

@vertex
fn vs_fullscreen(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(vi);
}

@group(0) @binding(0) var accum: texture_2d<f32>;
@group(0) @binding(1) var reveal: texture_2d<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let q = vec2<i32>(pos.xy);
    let r = textureLoad(reveal, q, 0).r;
    if r >= 0.9999 {
        discard;
    }
    let a = textureLoad(accum, q, 0);
    return vec4<f32>(a.rgb / clamp(a.a, 1e-6, 3e38), 1.0 - r);
}
