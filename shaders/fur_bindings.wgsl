// fur_bindings.wgsl: an asset's fur textures as the shells and fins bind them at @group(3)
// (`slot::FUR` in crates/pelt-preview/src/draw.rs; the layout is `layout::FUR_TEXTURES`, bound
// by the asset cache at upload): the binary heightfield and the fin texture with their
// samplers, the base colour and its sampler, and the strand model's transmittance T(z)
// (pelt_fur::density) at z = 0..3 / 8 and 4..7 / 8, with box-filtered mips.

#define_import_path pelt::fur_bindings

@group(3) @binding(0) var heightfield: texture_2d<f32>;
@group(3) @binding(1) var fin_texture: texture_2d<f32>;
@group(3) @binding(2) var repeat_sampler: sampler;
@group(3) @binding(3) var fin_sampler: sampler;
@group(3) @binding(4) var base_texture: texture_2d<f32>;
@group(3) @binding(5) var base_sampler: sampler;
@group(3) @binding(6) var density_lo: texture_2d<f32>;
@group(3) @binding(7) var density_hi: texture_2d<f32>;
