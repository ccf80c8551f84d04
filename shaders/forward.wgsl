// forward.wgsl: the forward reference (Kircher & Lawrance §1, §6): every object loops over
// every light per pixel, O(objects × lights). Same lighting model as light.wgsl, evaluated at
// full resolution, with the specular colour taken from each light rather than rebuilt.

const MAX_FORWARD_LIGHTS: u32 = 256u;

@group(0) @binding(0) var<uniform> frame: Frame;
@group(1) @binding(0) var<uniform> object: Object;
@group(2) @binding(0) var<uniform> lights: array<Light, MAX_FORWARD_LIGHTS>;

@vertex
fn vs_main(v: VertexIn) -> Surface {
    return to_surface(v, frame, object);
}

@fragment
fn fs_main(s: Surface, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let n = facing_normal(s.view_normal, front);
    var diffuse = frame.ambient.rgb;
    var specular = vec3<f32>(0.0);
    let count = min(frame.flags.y, MAX_FORWARD_LIGHTS);
    for (var i = 0u; i < count; i++) {
        let light = lights[i];
        let r = point_light(s.view_pos, n, light, frame.ambient.w);
        diffuse += r.rgb;
        if light.color.w > 0.0 {
            specular += r.a * light.color.rgb / light.color.w;
        }
    }
    let color = s.albedo.rgb * diffuse + object.params.y * specular;
    return vec4<f32>(color, object.params.x * s.albedo.a);
}
