// frame.wgsl: pelt's `Frame` and `Object` (shaders/common.wgsl) filled from Bevy's view and a
// mesh's world-from-local matrix, so that pelt's own functions (shaders/fur_common.wgsl,
// imported unchanged) run in Bevy's passes. Only the fields those functions read are set.

#define_import_path bevy_pelt::frame

#import bevy_pbr::mesh_view_bindings::view
#import pelt::common::{Frame, Object}

// The inverse of a 3×3 matrix (its adjugate over its determinant).
fn inverse3(m: mat3x3<f32>) -> mat3x3<f32> {
    let a = m[0];
    let b = m[1];
    let c = m[2];
    let r0 = cross(b, c);
    let r1 = cross(c, a);
    let r2 = cross(a, b);
    let det = dot(a, r0);
    let inv = 1.0 / select(det, 1e-20, abs(det) < 1e-20);
    return transpose(mat3x3<f32>(r0, r1, r2)) * inv;
}

// The view's pelt frame: its view and projection matrices, and the wind (xyz world direction
// × strength, w time in seconds) and gusts (x per second, y turbulence).
fn pelt_frame(wind: vec4<f32>, gust: vec4<f32>) -> Frame {
    var f: Frame;
    f.view = view.view_from_world;
    f.proj = view.clip_from_view;
    f.target_size = vec4<f32>(view.viewport.zw, 1.0 / view.viewport.zw);
    f.wind = wind;
    f.gust = gust;
    return f;
}

// A mesh's pelt object: `world_from_local` (skinned or not) as its model matrix, its normal
// matrix, and `fur_length` (what the wind's noise cells are measured in).
fn pelt_object(world_from_local: mat4x4<f32>, fur_length: f32) -> Object {
    var o: Object;
    o.model = world_from_local;
    let m3 = mat3x3<f32>(world_from_local[0].xyz, world_from_local[1].xyz, world_from_local[2].xyz);
    let n3 = transpose(inverse3(m3));
    o.normal_model = mat4x4<f32>(vec4<f32>(n3[0], 0.0), vec4<f32>(n3[1], 0.0), vec4<f32>(n3[2], 0.0), vec4<f32>(0.0, 0.0, 0.0, 1.0));
    o.fur_base = vec4<f32>(0.0, 0.0, 0.0, fur_length);
    return o;
}
