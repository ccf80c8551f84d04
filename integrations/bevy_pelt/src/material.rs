//! The plugin's materials, each an `ExtendedMaterial` over Bevy's `StandardMaterial` (whose
//! base colour, texture, texture transform and factors they read):
//! - [`FurMaterial`]: the base mesh (shell 0) and each shell of a fur primitive
//!   (`shaders/fur.wgsl`, pelt's forward fur: Revie §2.3–2.4 with the strand model as a medium);
//! - [`PeltSurfaceMaterial`]: pelt's opaque forward surface (`shaders/surface.wgsl`), which the
//!   scene loader gives objects without fur so that a scene file looks as in `pelt render`;
//! - [`SkyMaterial`]: pelt's procedural sky (`shaders/sky.wgsl`).

use bevy::mesh::{
    MeshVertexAttribute, MeshVertexBufferLayoutRef, VertexAttributeDescriptor, VertexFormat,
};
use bevy::pbr::{
    ExtendedMaterial, MaterialExtension, MaterialExtensionKey, MaterialExtensionPipeline,
};
use bevy::prelude::*;
use bevy::render::render_resource::{
    AsBindGroup, RenderPipelineDescriptor, ShaderType, SpecializedMeshPipelineError,
};
use bevy::shader::ShaderRef;

use crate::shaders;

/// The decoded comb (`_FUR_COMB` of docs/extension/PELT_fur, in any of its encodings, as
/// floats: xyz the tangent-space direction, w the comb length).
pub const ATTRIBUTE_FUR_COMB: MeshVertexAttribute =
    MeshVertexAttribute::new("PeltFurComb", 0x7065_6c74, VertexFormat::Float32x4);

/// A fur primitive's base mesh or one of its shells.
pub type FurMaterial = ExtendedMaterial<StandardMaterial, FurExtension>;

/// pelt's opaque surface over a `StandardMaterial`'s colour and factors.
pub type PeltSurfaceMaterial = ExtendedMaterial<StandardMaterial, PeltSurface>;

/// The fur uniform of `shaders/fur.wgsl` (keep the two in sync).
#[derive(Clone, Copy, Debug, Default, PartialEq, Reflect, ShaderType)]
pub struct FurUniform {
    /// rgb: root colour (linear); w: fur length in mesh units.
    pub root: Vec4,
    /// rgb: tip colour; w: the density texture's UV scale.
    pub tip: Vec4,
    /// x: this shell (0: the base mesh); y: shells drawn; z: κ; w: root and tip colours
    /// multiply the base colour texture (1) or not (0).
    pub shell: Vec4,
    /// rgb: the object's tint; w: every shell opaque (1: a negative control of the tests).
    pub tint: Vec4,
    /// xyz: the wind's world direction × strength; w: the time in seconds.
    pub wind: Vec4,
    /// x: gusts per second; y: turbulence.
    pub gust: Vec4,
}

/// What the fur shaders add to a `StandardMaterial`: the uniform and the strand model's
/// density (`pelt_fur::density`, bins 0–3 and 4–7, with their box-filtered levels).
#[derive(Asset, AsBindGroup, Reflect, Debug, Clone)]
pub struct FurExtension {
    /// The fur uniform.
    #[uniform(100)]
    pub fur: FurUniform,
    /// Density bins 0–3.
    #[texture(101)]
    #[sampler(102)]
    pub density_lo: Handle<Image>,
    /// Density bins 4–7.
    #[texture(103)]
    #[sampler(104)]
    pub density_hi: Handle<Image>,
}

impl MaterialExtension for FurExtension {
    fn vertex_shader() -> ShaderRef {
        ShaderRef::Handle(shaders::FUR.clone())
    }

    fn fragment_shader() -> ShaderRef {
        ShaderRef::Handle(shaders::FUR.clone())
    }

    fn prepass_vertex_shader() -> ShaderRef {
        ShaderRef::Handle(shaders::FUR_PREPASS.clone())
    }

    fn prepass_fragment_shader() -> ShaderRef {
        ShaderRef::Handle(shaders::FUR_PREPASS.clone())
    }

    fn specialize(
        _pipeline: &MaterialExtensionPipeline,
        descriptor: &mut RenderPipelineDescriptor,
        layout: &MeshVertexBufferLayoutRef,
        _key: MaterialExtensionKey<Self>,
    ) -> Result<(), SpecializedMeshPipelineError> {
        let attributes = [
            Mesh::ATTRIBUTE_POSITION.at_shader_location(0),
            Mesh::ATTRIBUTE_NORMAL.at_shader_location(1),
            Mesh::ATTRIBUTE_UV_0.at_shader_location(2),
            Mesh::ATTRIBUTE_TANGENT.at_shader_location(4),
            ATTRIBUTE_FUR_COMB.at_shader_location(9),
        ];
        set_vertex_layout(descriptor, layout, attributes)
    }
}

/// The vertex buffer of a pipeline whose shader reads `attributes`, and the skin's joints
/// and weights at locations 6 and 7 where the mesh has them (Bevy's `SKINNED` def then
/// declares them in the shader).
pub(crate) fn set_vertex_layout(
    descriptor: &mut RenderPipelineDescriptor,
    layout: &MeshVertexBufferLayoutRef,
    attributes: impl IntoIterator<Item = VertexAttributeDescriptor>,
) -> Result<(), SpecializedMeshPipelineError> {
    let mut all: Vec<_> = attributes.into_iter().collect();
    if layout.0.contains(Mesh::ATTRIBUTE_JOINT_INDEX)
        && layout.0.contains(Mesh::ATTRIBUTE_JOINT_WEIGHT)
    {
        all.push(Mesh::ATTRIBUTE_JOINT_INDEX.at_shader_location(6));
        all.push(Mesh::ATTRIBUTE_JOINT_WEIGHT.at_shader_location(7));
    }
    descriptor.vertex.buffers = vec![layout.0.get_layout(&all)?];
    Ok(())
}

/// pelt's opaque surface: no data of its own.
#[derive(Asset, AsBindGroup, Reflect, Debug, Clone, Default)]
pub struct PeltSurface {}

impl MaterialExtension for PeltSurface {
    fn fragment_shader() -> ShaderRef {
        ShaderRef::Handle(shaders::SURFACE.clone())
    }

    fn specialize(
        _pipeline: &MaterialExtensionPipeline,
        descriptor: &mut RenderPipelineDescriptor,
        _layout: &MeshVertexBufferLayoutRef,
        _key: MaterialExtensionKey<Self>,
    ) -> Result<(), SpecializedMeshPipelineError> {
        // The fragment stage reads its mesh's flags (shadow receiver).
        let def = "VERTEX_OUTPUT_INSTANCE_INDEX";
        descriptor.vertex.shader_defs.push(def.into());
        if let Some(f) = descriptor.fragment.as_mut() {
            f.shader_defs.push(def.into());
        }
        Ok(())
    }
}

/// pelt's procedural sky, drawn on a sphere around the camera.
#[derive(Asset, AsBindGroup, TypePath, Debug, Clone, Default)]
pub struct SkyMaterial {}

impl Material for SkyMaterial {
    fn fragment_shader() -> ShaderRef {
        ShaderRef::Handle(shaders::SKY.clone())
    }

    fn specialize(
        _pipeline: &bevy::pbr::MaterialPipeline,
        descriptor: &mut RenderPipelineDescriptor,
        _layout: &MeshVertexBufferLayoutRef,
        _key: bevy::pbr::MaterialPipelineKey<Self>,
    ) -> Result<(), SpecializedMeshPipelineError> {
        // Seen from inside.
        descriptor.primitive.cull_mode = None;
        Ok(())
    }
}
