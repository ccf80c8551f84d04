// sky.wgsl: pelt's procedural sky (shaders/common.wgsl `procedural`, shaders/sky.wgsl in pelt)
// on a sphere around the camera: the colour of the direction from the eye to the fragment.

#import bevy_pbr::{forward_io::VertexOutput, mesh_view_bindings::view}
#import pelt::common::procedural

@fragment
fn fragment(in: VertexOutput) -> @location(0) vec4<f32> {
    let d = normalize(in.world_position.xyz - view.world_position);
    return vec4<f32>(procedural(d) * view.exposure, 1.0);
}
