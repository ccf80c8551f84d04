// fullscreen.wgsl: the one full-screen triangle every screen-space pass draws (light,
// obliteration, OIT composite, sky, upscale). Three vertices cover the target; depth is 1
// (the far plane), so the sky's "less or equal" test draws only where nothing else did and
// passes without a depth test are unaffected. Each of those passes imports it and declares
// `vs_fullscreen` as `fullscreen_position(vi)`.

#define_import_path pelt::fullscreen

fn fullscreen_position(vi: u32) -> vec4<f32> {
    let p = vec2<f32>(f32((vi << 1u) & 2u), f32(vi & 2u));
    return vec4<f32>(p * 2.0 - 1.0, 1.0, 1.0);
}
