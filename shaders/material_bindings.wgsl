// material_bindings.wgsl: an object's material (its glTF textures, samplers and factors), as
// the G-buffer, material and forward passes bind it. The group is the shader def
// MATERIAL_GROUP, which the pass's `ShaderDesc` sets from its named slot
// (`slot::MATERIAL` in the material and forward passes, `slot::GBUFFER_MATERIAL` in the
// G-buffer pass); the bindings follow `gpu_material::LAYOUT`.

#define_import_path pelt::material_bindings

#import pelt::common::{MaterialParams}

@group(#{MATERIAL_GROUP}) @binding(0) var base_texture: texture_2d<f32>;
@group(#{MATERIAL_GROUP}) @binding(1) var normal_texture: texture_2d<f32>;
@group(#{MATERIAL_GROUP}) @binding(2) var mr_texture: texture_2d<f32>;
@group(#{MATERIAL_GROUP}) @binding(3) var base_sampler: sampler;
@group(#{MATERIAL_GROUP}) @binding(4) var normal_sampler: sampler;
@group(#{MATERIAL_GROUP}) @binding(5) var mr_sampler: sampler;
@group(#{MATERIAL_GROUP}) @binding(6) var<uniform> material: MaterialParams;
