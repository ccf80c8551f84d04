//! The fins (Lengyel et al.'s silhouette fins, as pelt draws them from the baked fin records:
//! shaders/fins.wgsl in pelt): one quad per fin edge, from the edge at the root to the edge
//! pushed out along the combed path at the tip, faded in where the edge is on the silhouette
//! (pelt's `fin_visibility`). Each quad's vertices carry their own end's position, normal and
//! object-space comb, and the other end's, so that the vertex stage (`shaders/fins.wgsl`) sees
//! the whole edge; a skinned mesh's fin vertices carry their end's joints and weights, so
//! Bevy skins the fins on the GPU with the mesh.

use bevy::asset::RenderAssetUsages;
use bevy::image::{ImageAddressMode, ImageFilterMode, ImageSampler, ImageSamplerDescriptor};
use bevy::mesh::{
    Indices, MeshVertexAttribute, MeshVertexBufferLayoutRef, PrimitiveTopology,
    VertexAttributeValues, VertexFormat,
};
use bevy::pbr::{
    ExtendedMaterial, MaterialExtension, MaterialExtensionKey, MaterialExtensionPipeline,
};
use bevy::prelude::*;
use bevy::render::render_resource::{
    AsBindGroup, Extent3d, RenderPipelineDescriptor, ShaderType, SpecializedMeshPipelineError,
    TextureDimension, TextureFormat,
};
use bevy::shader::ShaderRef;
use pelt_scene::fur::{FIN_MIN_LENGTH, Level};

use crate::extension::PeltFurData;
use crate::material::{ATTRIBUTE_FUR_COMB, set_vertex_layout};
use crate::shaders;

/// This end's object-space comb (xyz) and comb length (w; 0 on a bare edge).
pub const ATTRIBUTE_FIN_COMB: MeshVertexAttribute =
    MeshVertexAttribute::new("PeltFinComb", 0x7065_6c80, VertexFormat::Float32x4);
/// The other end's position (xyz) and the height on the fin (w: 0 root, 1 tip).
pub const ATTRIBUTE_FIN_OTHER: MeshVertexAttribute =
    MeshVertexAttribute::new("PeltFinOther", 0x7065_6c81, VertexFormat::Float32x4);
/// The other end's normal (xyz).
pub const ATTRIBUTE_FIN_OTHER_NORMAL: MeshVertexAttribute =
    MeshVertexAttribute::new("PeltFinOtherNormal", 0x7065_6c82, VertexFormat::Float32x4);
/// The other end's object-space comb and comb length.
pub const ATTRIBUTE_FIN_OTHER_COMB: MeshVertexAttribute =
    MeshVertexAttribute::new("PeltFinOtherComb", 0x7065_6c83, VertexFormat::Float32x4);
/// The edge's first face normal.
pub const ATTRIBUTE_FIN_FACE0: MeshVertexAttribute =
    MeshVertexAttribute::new("PeltFinFace0", 0x7065_6c84, VertexFormat::Float32x3);
/// Its second (the first again on a boundary).
pub const ATTRIBUTE_FIN_FACE1: MeshVertexAttribute =
    MeshVertexAttribute::new("PeltFinFace1", 0x7065_6c85, VertexFormat::Float32x3);

/// The fins of a fur primitive.
pub type FinMaterial = ExtendedMaterial<StandardMaterial, FinExtension>;

/// The fin uniform of `shaders/fins.wgsl` (keep the two in sync).
#[derive(Clone, Copy, Debug, Default, PartialEq, Reflect, ShaderType)]
pub struct FinUniform {
    /// rgb: root colour; w: fur length (mesh units).
    pub root: Vec4,
    /// rgb: tip colour; w: 1 with the analytic coverage (fins reach down to MIN_COS), 0 with
    /// the binary heightfield.
    pub tip: Vec4,
    /// rgb: the object's tint; w: root and tip colours multiply the base colour texture.
    pub tint: Vec4,
    /// The wind (as the fur's).
    pub wind: Vec4,
    /// The gusts (as the fur's).
    pub gust: Vec4,
}

/// What the fin shaders add to a `StandardMaterial`: the uniform and the fin texture.
#[derive(Asset, AsBindGroup, Reflect, Debug, Clone)]
pub struct FinExtension {
    /// The fin uniform.
    #[uniform(100)]
    pub fin: FinUniform,
    /// The fin texture with its stored levels.
    #[texture(101)]
    #[sampler(102)]
    pub texture: Handle<Image>,
}

impl MaterialExtension for FinExtension {
    fn vertex_shader() -> ShaderRef {
        ShaderRef::Handle(shaders::FINS.clone())
    }

    fn fragment_shader() -> ShaderRef {
        ShaderRef::Handle(shaders::FINS.clone())
    }

    fn enable_prepass() -> bool {
        false
    }

    fn enable_shadows() -> bool {
        false
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
            Mesh::ATTRIBUTE_UV_1.at_shader_location(3),
            ATTRIBUTE_FIN_COMB.at_shader_location(9),
            ATTRIBUTE_FIN_OTHER.at_shader_location(10),
            ATTRIBUTE_FIN_OTHER_NORMAL.at_shader_location(11),
            ATTRIBUTE_FIN_OTHER_COMB.at_shader_location(12),
            ATTRIBUTE_FIN_FACE0.at_shader_location(13),
            ATTRIBUTE_FIN_FACE1.at_shader_location(14),
        ];
        set_vertex_layout(descriptor, layout, attributes)
    }
}

/// The fin texture as an RGBA8 image with its stored levels, repeating along the edge and
/// clamped up the strand.
pub fn fin_image(levels: &[Level<[u8; 4]>]) -> Option<Image> {
    let first = levels.first()?;
    let data: Vec<u8> = levels
        .iter()
        .flat_map(|l| l.texels.iter().flatten().copied())
        .collect();
    let size = Extent3d {
        width: first.width,
        height: first.height,
        depth_or_array_layers: 1,
    };
    let mut image = Image::new(
        size,
        TextureDimension::D2,
        data,
        TextureFormat::Rgba8Unorm,
        RenderAssetUsages::RENDER_WORLD,
    );
    image.texture_descriptor.mip_level_count = levels.len() as u32;
    image.sampler = ImageSampler::Descriptor(ImageSamplerDescriptor {
        address_mode_u: ImageAddressMode::Repeat,
        address_mode_v: ImageAddressMode::ClampToEdge,
        mag_filter: ImageFilterMode::Linear,
        min_filter: ImageFilterMode::Linear,
        mipmap_filter: ImageFilterMode::Linear,
        ..default()
    });
    Some(image)
}

fn vec3s(mesh: &Mesh, a: MeshVertexAttribute) -> Option<&Vec<[f32; 3]>> {
    match mesh.attribute(a)? {
        VertexAttributeValues::Float32x3(v) => Some(v),
        _ => None,
    }
}

fn vec4s(mesh: &Mesh, a: MeshVertexAttribute) -> Option<&Vec<[f32; 4]>> {
    match mesh.attribute(a)? {
        VertexAttributeValues::Float32x4(v) => Some(v),
        _ => None,
    }
}

fn vec2s(mesh: &Mesh, a: MeshVertexAttribute) -> Option<&Vec<[f32; 2]>> {
    match mesh.attribute(a)? {
        VertexAttributeValues::Float32x2(v) => Some(v),
        _ => None,
    }
}

/// The fin mesh of `d`'s edges over `fur` (the fur mesh: positions, normals, tangents, UVs,
/// the decoded comb, and joints where skinned); None without fins or attributes.
pub fn fin_mesh(fur: &Mesh, d: &PeltFurData) -> Option<Mesh> {
    if d.fins.is_empty() {
        return None;
    }
    let (p, n, t, uv, comb) = (
        vec3s(fur, Mesh::ATTRIBUTE_POSITION)?,
        vec3s(fur, Mesh::ATTRIBUTE_NORMAL)?,
        vec4s(fur, Mesh::ATTRIBUTE_TANGENT)?,
        vec2s(fur, Mesh::ATTRIBUTE_UV_0)?,
        vec4s(fur, ATTRIBUTE_FUR_COMB)?,
    );
    let object_comb = |k: u32| {
        let (nk, tk, ck) = (n[k as usize], t[k as usize], comb[k as usize]);
        pelt_io::contract::comb_object(
            glam30::Vec3::from_array(nk),
            glam30::Vec4::from_array(tk),
            glam30::Vec3::new(ck[0], ck[1], ck[2]),
        )
    };
    let joints = (
        fur.attribute(Mesh::ATTRIBUTE_JOINT_INDEX),
        vec4s(fur, Mesh::ATTRIBUTE_JOINT_WEIGHT),
    );
    let mut out = FinArrays::default();
    for e in &d.fins {
        let [a, b] = e.ends;
        let (na, nb) = (a as usize, b as usize);
        if na >= p.len() || nb >= p.len() {
            continue;
        }
        let bare = comb[na][3].max(comb[nb][3]) <= FIN_MIN_LENGTH;
        let length = |k: usize| if bare { 0.0 } else { comb[k][3] };
        let ends = [(na, nb), (nb, na)];
        let mid_uv = [(uv[na][0] + uv[nb][0]) * 0.5, (uv[na][1] + uv[nb][1]) * 0.5];
        let first = out.position.len() as u32;
        for (end, (own, other)) in ends.into_iter().enumerate() {
            let (ko, kx) = (object_comb(own as u32), object_comb(other as u32));
            for height in [0.0f32, 1.0] {
                out.position.push(p[own]);
                out.normal.push(n[own]);
                out.uv
                    .push([e.u[0] + end as f32 * e.u[1] * d.look.uv_scale, 1.0 - height]);
                out.base_uv.push(mid_uv);
                out.comb.push([ko.x, ko.y, ko.z, length(own)]);
                out.other
                    .push([p[other][0], p[other][1], p[other][2], height]);
                out.other_normal
                    .push([n[other][0], n[other][1], n[other][2], 0.0]);
                out.other_comb.push([kx.x, kx.y, kx.z, length(other)]);
                out.face0.push(e.faces[0]);
                out.face1.push(e.faces[1]);
                out.vertex.push(own);
            }
        }
        // Vertices: end 0 root, end 0 tip, end 1 root, end 1 tip.
        out.indices
            .extend([first, first + 2, first + 3, first, first + 3, first + 1]);
    }
    Some(out.into_mesh(joints))
}

/// The fin quads' vertex arrays, and the fur mesh vertex each one copies its skin from.
#[derive(Default)]
struct FinArrays {
    position: Vec<[f32; 3]>,
    normal: Vec<[f32; 3]>,
    uv: Vec<[f32; 2]>,
    base_uv: Vec<[f32; 2]>,
    comb: Vec<[f32; 4]>,
    other: Vec<[f32; 4]>,
    other_normal: Vec<[f32; 4]>,
    other_comb: Vec<[f32; 4]>,
    face0: Vec<[f32; 3]>,
    face1: Vec<[f32; 3]>,
    vertex: Vec<usize>,
    indices: Vec<u32>,
}

impl FinArrays {
    /// The fin mesh, with each vertex's end's joints and weights where `joints` has them.
    fn into_mesh(self, joints: (Option<&VertexAttributeValues>, Option<&Vec<[f32; 4]>>)) -> Mesh {
        let mut m = Mesh::new(
            PrimitiveTopology::TriangleList,
            RenderAssetUsages::RENDER_WORLD,
        );
        if let (Some(VertexAttributeValues::Uint16x4(j)), Some(w)) = joints {
            let indices = self.vertex.iter().map(|&k| j[k]).collect();
            m.insert_attribute(
                Mesh::ATTRIBUTE_JOINT_INDEX,
                VertexAttributeValues::Uint16x4(indices),
            );
            m.insert_attribute(
                Mesh::ATTRIBUTE_JOINT_WEIGHT,
                self.vertex.iter().map(|&k| w[k]).collect::<Vec<_>>(),
            );
        }
        m.insert_attribute(Mesh::ATTRIBUTE_POSITION, self.position);
        m.insert_attribute(Mesh::ATTRIBUTE_NORMAL, self.normal);
        m.insert_attribute(Mesh::ATTRIBUTE_UV_0, self.uv);
        m.insert_attribute(Mesh::ATTRIBUTE_UV_1, self.base_uv);
        m.insert_attribute(ATTRIBUTE_FIN_COMB, self.comb);
        m.insert_attribute(ATTRIBUTE_FIN_OTHER, self.other);
        m.insert_attribute(ATTRIBUTE_FIN_OTHER_NORMAL, self.other_normal);
        m.insert_attribute(ATTRIBUTE_FIN_OTHER_COMB, self.other_comb);
        m.insert_attribute(ATTRIBUTE_FIN_FACE0, self.face0);
        m.insert_attribute(ATTRIBUTE_FIN_FACE1, self.face1);
        m.insert_indices(Indices::U32(self.indices));
        m
    }
}
