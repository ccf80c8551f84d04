// lighting_inputs.wgsl: the lighting inputs every lighting pass reads at @group(4), declared
// once (crates/pelt-preview/src/lighting.rs owns the group; the features that fill each
// binding are registered there): the shadow maps and how to read them (the shadows feature),
// the fur's deep opacity layers and how to read them (the opacity feature). shadows.wgsl
// reads them; the lighting passes import its functions.

#define_import_path pelt::lighting_inputs

// A light's one map (the first layer of its slot) where it has one instead of a cube (a
// directional light's orthographic view fitted to the scene, or a perspective view).
// Keep in sync with LightMap in crates/pelt-preview/src/features/shadows.rs.
struct LightMap {
    // World to the map, projectively: q.xy / q.w its texture coordinates, q.z the distance
    // from its near plane along its axis (what shadow_map.wgsl stores), q.w the depth a
    // texel's size grows with (1 in an orthographic map).
    to_map: mat4x4<f32>,
    // x: the world size of one texel at q.w = 1 (0: the slot's light has a cube); yzw: unused.
    texel: vec4<f32>,
}

// How to read the shadow maps. Keep in sync with ShadowRead in
// crates/pelt-preview/src/features/shadows.rs.
struct ShadowRead {
    // x: the PCF side in texels (the scene's shadowMaps.pcf); yzw: unused.
    pcf: vec4<u32>,
    // Each slot's map where its light has one instead of a cube.
    maps: array<LightMap, 8>,
}

// How to read the opacity layers. Keep in sync with FurRead in
// crates/pelt-preview/src/features/opacity.rs.
struct FurRead {
    // The deep opacity layers' boundaries (world units past the nearest fur; the last one
    // where its value is reached) and w: how many layers there are (0: fur casts no coverage).
    layers: vec4<f32>,
}

// Every layer of every shadow-casting light's maps: xy the distance to the nearest opaque
// surface, zw to the nearest fur (shadow_map.wgsl, shells.wgsl's fs_nearest).
@group(4) @binding(0) var shadow_cubes: texture_2d_array<f32>;
@group(4) @binding(1) var<uniform> shadow_read: ShadowRead;
// The optical depth of each deep opacity layer (xyz), per layer of the shadow maps.
@group(4) @binding(2) var fur_opacity: texture_2d_array<f32>;
@group(4) @binding(3) var<uniform> fur_read: FurRead;
