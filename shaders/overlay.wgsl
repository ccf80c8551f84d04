// overlay.wgsl: `pelt view`'s text overlay (crates/pelt-preview/src/features/overlay.rs) over
// the finished frame: the full-screen triangle of fullscreen.wgsl, drawing only inside the
// text box: white where the CPU-rasterized 8×8 bitmap font has a pixel, a translucent dark
// box elsewhere, blended "over" the image.

#import pelt::fullscreen::{fullscreen_position}

@vertex
fn vs_fullscreen(@builtin(vertex_index) vi: u32) -> @builtin(position) vec4<f32> {
    return fullscreen_position(vi);
}

@group(0) @binding(0) var text: texture_2d<f32>;
// xy: the box's top-left corner in pixels; z: pixels per font pixel; w: unused.
@group(1) @binding(0) var<uniform> params: vec4<f32>;

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    let size = vec2<f32>(textureDimensions(text)) * params.z;
    let p = pos.xy - params.xy;
    if p.x < 0.0 || p.y < 0.0 || p.x >= size.x || p.y >= size.y {
        discard;
    }
    let texel = textureLoad(text, vec2<i32>(p / params.z), 0).r;
    return select(vec4<f32>(0.0, 0.0, 0.0, 0.6), vec4<f32>(1.0, 1.0, 1.0, 1.0), texel > 0.5);
}
