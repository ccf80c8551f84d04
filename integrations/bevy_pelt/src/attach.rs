//! Fur attached to the glTF mesh entities [`crate::extension`] tagged: the mesh gains the
//! decoded comb (and tangents where the file has none), its material becomes the fur
//! material of shell 0 (the base mesh, lit along the strands), and each shell is a child
//! entity drawing the same mesh with its own [`FurMaterial`] (Revie §2.3: the shells are the
//! mesh pushed out along the comb by the vertex stage). The shells of one primitive differ
//! only in their shell index and in a depth bias of their material that orders them inner to
//! outer in Bevy's transparent phase (which sorts by distance plus that bias; the bias is below
//! one, so it does not offset depths).

use std::sync::Arc;

use bevy::asset::RenderAssetUsages;
use bevy::camera::visibility::NoFrustumCulling;
use bevy::image::{ImageAddressMode, ImageFilterMode, ImageSampler, ImageSamplerDescriptor};
use bevy::light::NotShadowCaster;
use bevy::mesh::skinning::SkinnedMesh;
use bevy::platform::collections::HashMap;
use bevy::prelude::*;
use bevy::render::render_resource::{Extent3d, Face, TextureDimension, TextureFormat};
use pelt_fur::density::Density;
use pelt_fur::shells::ShellRule;

use crate::extension::{PeltFur, PeltFurData, PeltFurError};
use crate::fins::{FinExtension, FinMaterial, FinUniform, fin_image, fin_mesh};
use crate::material::{ATTRIBUTE_FUR_COMB, FurExtension, FurMaterial, FurUniform};
use crate::scene::PeltObject;
use crate::settings::{FurControl, FurSettings};

/// Depth bias between consecutive shells (ordering only; see the module docs).
const SHELL_ORDER_BIAS: f32 = 1e-2;

/// On a fur mesh entity once its fur is drawn: its shells and materials.
#[derive(Component, Debug)]
pub struct FurAttached {
    /// The decoded fur.
    pub data: Handle<PeltFurData>,
    /// The base mesh's material (shell 0).
    pub base: Handle<FurMaterial>,
    /// Shell `i + 1`: its entity and material.
    pub shells: Vec<(Entity, Handle<FurMaterial>)>,
    /// The shells-by-screen-size rule, where it applies (None: `max` always).
    pub rule: Option<ShellRule>,
    /// The most shells drawn (the manifest's, or the count forced).
    pub max: u32,
    /// The shells drawn this frame.
    pub drawn: u32,
    /// The mesh's bounds (mesh units): what the rule projects.
    pub bounds: (Vec3, Vec3),
    /// The fur length drawn (mesh units: the manifest's, or the scene object's).
    pub length: f32,
    /// The fins, where drawn: their entity and material.
    pub fins: Option<(Entity, Handle<FinMaterial>)>,
}

/// On each shell entity: its index (1 = innermost).
#[derive(Component, Debug, Clone, Copy)]
pub struct FurShell(pub u32);

/// The density images of one strand model (bins 0–3 and 4–7), made once per model.
#[derive(Default)]
pub(crate) struct DensityImages(HashMap<usize, (Handle<Image>, Handle<Image>)>);

/// A half-float RGBA image of bins `first..first + 4` of every level, mipmapped as stored.
fn density_image(d: &Density, first: usize) -> Image {
    let mut data = Vec::new();
    for (l, level) in d.levels.iter().enumerate() {
        let side = (d.side >> l).max(1) as usize;
        for texel in level.iter().take(side * side) {
            for k in 0..4 {
                data.extend_from_slice(&half::f16::from_f32(texel[first + k]).to_le_bytes());
            }
        }
    }
    let size = Extent3d {
        width: d.side,
        height: d.side,
        depth_or_array_layers: 1,
    };
    let mut image = Image::new(
        size,
        TextureDimension::D2,
        data,
        TextureFormat::Rgba16Float,
        RenderAssetUsages::RENDER_WORLD,
    );
    image.texture_descriptor.mip_level_count = d.levels.len() as u32;
    image.sampler = ImageSampler::Descriptor(ImageSamplerDescriptor {
        address_mode_u: ImageAddressMode::Repeat,
        address_mode_v: ImageAddressMode::Repeat,
        mag_filter: ImageFilterMode::Linear,
        min_filter: ImageFilterMode::Linear,
        mipmap_filter: ImageFilterMode::Linear,
        ..default()
    });
    image
}

/// The fur uniform of shell `shell` of `n` drawn.
pub(crate) fn uniform(
    d: &PeltFurData,
    o: &PeltObject,
    shell: u32,
    n: u32,
    control: Option<FurControl>,
) -> FurUniform {
    let l = &d.look;
    let [r, g, b] = l.base_color.to_array();
    let [tr, tg, tb] = l.tip_color.to_array();
    let opaque = matches!(control, Some(FurControl::OpaqueShells));
    let textured = l.color_from_texture && control != Some(FurControl::NoTexture);
    FurUniform {
        root: Vec4::new(r, g, b, o.length.unwrap_or(l.length)),
        tip: Vec4::new(tr, tg, tb, l.uv_scale),
        shell: Vec4::new(
            shell as f32,
            n as f32,
            d.density.kappa as f32,
            f32::from(u8::from(textured)),
        ),
        tint: o.tint.extend(f32::from(u8::from(opaque))),
        wind: Vec4::ZERO,
        gust: Vec4::ZERO,
    }
}

/// The mesh with the decoded comb, UVs and tangents, or why it cannot have them.
fn fur_mesh(mesh: &Mesh, d: &PeltFurData) -> Result<Mesh, String> {
    let mut m = mesh.clone();
    let n = m.count_vertices();
    if d.comb.len() != n {
        return Err(format!(
            "{}: {} comb values for {n} vertices as Bevy loaded them",
            d.place,
            d.comb.len()
        ));
    }
    m.insert_attribute(ATTRIBUTE_FUR_COMB, d.comb.clone());
    if m.attribute(Mesh::ATTRIBUTE_UV_0).is_none() {
        m.insert_attribute(Mesh::ATTRIBUTE_UV_0, vec![[0.0f32; 2]; n]);
    }
    if m.attribute(Mesh::ATTRIBUTE_TANGENT).is_none() {
        warn!(
            "{}: no TANGENT; MikkTSpace tangents generated (pelt regenerates them by {})",
            d.place, d.tangents
        );
        m.generate_tangents()
            .map_err(|e| format!("{}: tangents: {e}", d.place))?;
    }
    Ok(m)
}

fn bounds(mesh: &Mesh) -> (Vec3, Vec3) {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    if let Some(bevy::mesh::VertexAttributeValues::Float32x3(p)) =
        mesh.attribute(Mesh::ATTRIBUTE_POSITION)
    {
        for v in p {
            lo = lo.min(Vec3::from(*v));
            hi = hi.max(Vec3::from(*v));
        }
    }
    (lo, hi)
}

/// What attaching one primitive's fur writes to.
pub(crate) struct Sinks<'a, 'w, 's> {
    commands: &'a mut Commands<'w, 's>,
    meshes: &'a mut Assets<Mesh>,
    materials: &'a mut Assets<FurMaterial>,
    fin_materials: &'a mut Assets<FinMaterial>,
    images: &'a mut Assets<Image>,
}

/// One fur primitive to draw: its entity, fur, mesh with the comb, the glTF material, skin
/// and scene object.
struct Primitive<'a> {
    entity: Entity,
    handle: Handle<PeltFurData>,
    d: &'a PeltFurData,
    source: &'a StandardMaterial,
    skinned: Option<&'a SkinnedMesh>,
    object: PeltObject,
}

/// The scene file's object at or above `entity` (tint and overrides), or an untinted one.
fn scene_object(
    entity: Entity,
    parents: &Query<&ChildOf>,
    objects: &Query<&PeltObject>,
) -> PeltObject {
    std::iter::once(entity)
        .chain(parents.iter_ancestors(entity))
        .find_map(|e| objects.get(e).ok())
        .copied()
        .unwrap_or(PeltObject {
            tint: Vec3::ONE,
            fur: true,
            shells: None,
            length: None,
            fins: None,
        })
}

/// `source` as the base mesh draws it (opaque, both sides) or as the shells do (blended,
/// front faces).
fn pass_material(source: &StandardMaterial, shells: bool) -> StandardMaterial {
    let mut m = source.clone();
    m.alpha_mode = if shells {
        AlphaMode::Blend
    } else {
        AlphaMode::Opaque
    };
    m.cull_mode = shells.then_some(Face::Back);
    m.double_sided = !shells;
    m
}

/// Draws the fur of every tagged entity whose mesh, material and fur have loaded.
pub(crate) fn attach_fur(
    mut commands: Commands,
    found: Query<
        (
            Entity,
            &PeltFur,
            &Mesh3d,
            &MeshMaterial3d<StandardMaterial>,
            Option<&SkinnedMesh>,
        ),
        Without<FurAttached>,
    >,
    data: Res<Assets<PeltFurData>>,
    mut meshes: ResMut<Assets<Mesh>>,
    standard: Res<Assets<StandardMaterial>>,
    mut materials: ResMut<Assets<FurMaterial>>,
    mut fin_materials: ResMut<Assets<FinMaterial>>,
    mut images: ResMut<Assets<Image>>,
    mut densities: Local<DensityImages>,
    settings: Res<FurSettings>,
    parents: Query<&ChildOf>,
    objects: Query<&PeltObject>,
) {
    for (entity, fur, mesh3d, material3d, skinned) in &found {
        let object = scene_object(entity, &parents, &objects);
        if !object.fur {
            continue;
        }
        let (Some(d), Some(mesh), Some(source)) = (
            data.get(&fur.0),
            meshes.get(&mesh3d.0),
            standard.get(&material3d.0),
        ) else {
            continue;
        };
        let m = match fur_mesh(mesh, d) {
            Ok(m) => m,
            Err(e) => {
                error!("bevy_pelt: {e}");
                commands
                    .entity(entity)
                    .insert(PeltFurError(e))
                    .remove::<PeltFur>();
                continue;
            }
        };
        let key = Arc::as_ptr(&d.density) as usize;
        let density = densities
            .0
            .entry(key)
            .or_insert_with(|| {
                (
                    images.add(density_image(&d.density, 0)),
                    images.add(density_image(&d.density, 4)),
                )
            })
            .clone();
        let p = Primitive {
            entity,
            handle: fur.0.clone(),
            d,
            source,
            skinned,
            object,
        };
        let mut sinks = Sinks {
            commands: &mut commands,
            meshes: &mut meshes,
            materials: &mut materials,
            fin_materials: &mut fin_materials,
            images: &mut images,
        };
        attach(&mut sinks, &p, m, density, &settings);
    }
}

/// The base mesh's and the shells' materials and entities, and the fins where drawn.
fn attach(
    s: &mut Sinks,
    p: &Primitive,
    m: Mesh,
    (lo, hi): (Handle<Image>, Handle<Image>),
    settings: &FurSettings,
) {
    let d = p.d;
    let forced = settings.shells.or(p.object.shells);
    let max = forced.unwrap_or(d.look.shells).max(1);
    let rule = if forced.is_some() {
        None
    } else {
        d.look.shell_rule
    };
    let length = p.object.length.unwrap_or(d.look.length);
    let fins_on = settings
        .fins
        .or(p.object.fins)
        .unwrap_or(settings.binary_coverage);
    let fin = if fins_on { fin_mesh(&m, d) } else { None };
    let box_ = bounds(&m);
    let handle = s.meshes.add(m);
    let make = |shell: u32, base: &StandardMaterial| FurMaterial {
        base: base.clone(),
        extension: FurExtension {
            fur: uniform(d, &p.object, shell, max, settings.control),
            density_lo: lo.clone(),
            density_hi: hi.clone(),
        },
    };
    let base_handle = s.materials.add(make(0, &pass_material(p.source, false)));
    let mut layer = pass_material(p.source, true);
    let mut shells = Vec::new();
    for i in 1..=max {
        layer.depth_bias = i as f32 * SHELL_ORDER_BIAS;
        let h = s.materials.add(make(i, &layer));
        let mut e = s.commands.spawn((
            Mesh3d(handle.clone()),
            MeshMaterial3d(h.clone()),
            Transform::IDENTITY,
            NoFrustumCulling,
            FurShell(i),
            ChildOf(p.entity),
        ));
        if let Some(sk) = p.skinned {
            e.insert(sk.clone());
        }
        if settings.control == Some(FurControl::NoFurShadow) {
            e.insert(NotShadowCaster);
        }
        shells.push((e.id(), h));
    }
    let bias = (max + 1) as f32 * SHELL_ORDER_BIAS;
    let fins = fin.and_then(|f| spawn_fins(s, p, f, length, settings, bias));
    s.commands
        .entity(p.entity)
        .remove::<MeshMaterial3d<StandardMaterial>>()
        .insert((
            Mesh3d(handle),
            MeshMaterial3d(base_handle.clone()),
            NoFrustumCulling,
        ))
        .insert(FurAttached {
            data: p.handle.clone(),
            base: base_handle,
            shells,
            rule,
            max,
            drawn: max,
            bounds: box_,
            length,
            fins,
        });
}

/// The fins of a primitive: a child entity drawn after its shells (`bias`), blended, casting
/// no shadow.
fn spawn_fins(
    s: &mut Sinks,
    p: &Primitive,
    mesh: Mesh,
    length: f32,
    settings: &FurSettings,
    bias: f32,
) -> Option<(Entity, Handle<FinMaterial>)> {
    let texture = s.images.add(fin_image(&p.d.fin_texture)?);
    let l = &p.d.look;
    let textured = l.color_from_texture && settings.control != Some(FurControl::NoTexture);
    let fin = FinUniform {
        root: Vec3::from_array(l.base_color.to_array()).extend(length),
        tip: Vec3::from_array(l.tip_color.to_array())
            .extend(f32::from(u8::from(!settings.binary_coverage))),
        tint: p.object.tint.extend(f32::from(u8::from(textured))),
        wind: Vec4::ZERO,
        gust: Vec4::ZERO,
    };
    let mut base = p.source.clone();
    base.alpha_mode = AlphaMode::Blend;
    base.cull_mode = None;
    base.double_sided = true;
    base.depth_bias = bias;
    let h = s.fin_materials.add(FinMaterial {
        base,
        extension: FinExtension { fin, texture },
    });
    let mut e = s.commands.spawn((
        Mesh3d(s.meshes.add(mesh)),
        MeshMaterial3d(h.clone()),
        Transform::IDENTITY,
        NoFrustumCulling,
        NotShadowCaster,
        ChildOf(p.entity),
    ));
    if let Some(sk) = p.skinned {
        e.insert(sk.clone());
    }
    Some((e.id(), h))
}
