//! The fur half of an asset (Revie §2.4.1): per vertex the baked `_FUR_COMB` (tangent-space
//! comb, w = length), TANGENT and TEXCOORD_0, which the vertex shaders turn back into view
//! space with the current TBN; the baked fin edges (docs/format.md) expanded into one instance
//! record per edge for the fin quads; and the fur look and textures from the material's
//! manifest (`PELT_fur` on the material, or the legacy `extras.pelt.fur`): length, shell count, UV scale, root and tip colours, the
//! heightfield and fin texture with all their mip levels. Assets with a comb but no manifest
//! (baked without `--config`) get the default strand model's textures, generated here.

use glam::{DMat3, Mat3, Mat4, Vec2, Vec3, Vec4};
pub use pelt_fur::density::Density;
use pelt_fur::{FurConfig, FurManifest, Pixels, StrandParams};
use pelt_io::topology::StoredFins;
use pelt_io::{Document, IoError, PrimitiveRef};

use crate::vertex::{FinInstance, FurVertex};

/// One mip level of a texture, rows top to bottom.
#[derive(Debug, Clone, PartialEq)]
pub struct Level<T> {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// Texels.
    pub texels: Vec<T>,
}

/// The fur's look: what the manifest says (or the defaults).
#[derive(Debug, Clone, PartialEq)]
pub struct FurLook {
    /// Fur length in mesh units (each vertex's comb length scales it).
    pub length: f32,
    /// Default shell count, and the most the shell rule draws.
    pub shells: u32,
    /// The manifest's shells-by-screen-size rule (None: `shells` always).
    pub shell_rule: Option<pelt_fur::shells::ShellRule>,
    /// Heightfield UV scale.
    pub uv_scale: f32,
    /// Linear root colour.
    pub base_color: Vec3,
    /// Linear tip colour.
    pub tip_color: Vec3,
    /// Root and tip colours multiply the material's base colour (texture and factor) under
    /// each strand (the fur config's `colorFromTexture`).
    pub color_from_texture: bool,
}

/// Where the textures came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextureSource {
    /// The manifest and images the bake embedded.
    Baked,
    /// No manifest in the asset: the default strand model, generated at load.
    Generated,
}

/// The fur of one asset.
#[derive(Debug, Clone, PartialEq)]
pub struct FurData {
    /// Parallel to the mesh's vertices.
    pub vertices: Vec<FurVertex>,
    /// One per baked fin edge.
    pub fins: Vec<FinInstance>,
    /// Parallel to `fins`: each edge by vertex index (the GPU rebuilds skinned fins from
    /// them, `crate::skin`).
    pub fin_sources: Vec<crate::skin::FinSource>,
    /// Length, shells, colours.
    pub look: FurLook,
    /// Heightfield levels (16-bit heights; 0 = bare).
    pub heightfield: Vec<Level<u16>>,
    /// Fin texture levels (RGBA8: R height along the strand, G tint, A coverage).
    pub fin: Vec<Level<[u8; 4]>>,
    /// Where the textures came from.
    pub source: TextureSource,
    /// The strand model the textures were made from (the manifest's, or the generated
    /// defaults'): the explicit strands of the strand reference are planted from it.
    pub model: StrandParams,
    /// The same model as a medium (`pelt_fur::density`): the shells' sub-pixel coverage.
    pub density: Density,
}

/// Largest side of the density texture the preview makes.
pub const MAX_DENSITY_SIDE: u32 = 1024;

/// The medium statistics of `model` at the side its strand count calls for.
pub fn density_of(model: &StrandParams) -> Density {
    pelt_fur::density::density(
        model,
        pelt_fur::density::side_for(model.strands, MAX_DENSITY_SIDE),
    )
}

/// Heightfield and fin texture levels.
pub type Textures = (Vec<Level<u16>>, Vec<Level<[u8; 4]>>);

/// Size of the textures generated for assets without a manifest.
pub const GENERATED_SIZE: u32 = 512;

/// The look a manifest gives (what every renderer of the fur reads: pelt's preview, the Bevy
/// plugin).
pub fn look_of(m: &FurManifest) -> FurLook {
    let v = |c: [f64; 3]| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32);
    FurLook {
        length: m.length as f32,
        shells: m.shells,
        shell_rule: m.shell_rule,
        uv_scale: m.uv_scale as f32,
        base_color: v(m.base_color),
        tip_color: v(m.tip_color),
        color_from_texture: m.color_from_texture,
    }
}

/// The strand model of assets without a manifest.
pub fn generated_model() -> StrandParams {
    StrandParams {
        size: GENERATED_SIZE,
        ..StrandParams::default()
    }
}

/// Heightfield levels as the shells read them (16-bit; 8-bit and RGBA levels widened).
pub fn height_levels(images: &[pelt_fur::Image]) -> Vec<Level<u16>> {
    images
        .iter()
        .map(|i| Level {
            width: i.width,
            height: i.height,
            texels: match &i.pixels {
                Pixels::Gray16(v) => v.clone(),
                Pixels::Gray8(v) => v.iter().map(|&x| u16::from(x) * 257).collect(),
                Pixels::Rgba8(v) => v.iter().map(|x| u16::from(x[0]) * 257).collect(),
            },
        })
        .collect()
}

/// The defaults' look and textures (generated: no manifest in the asset).
pub fn generated() -> Result<(FurLook, Textures), IoError> {
    let config = FurConfig {
        textures: generated_model(),
        ..FurConfig::default()
    };
    let set = pelt_fur::generate(&config.textures).map_err(|e| IoError::Invalid {
        path: "builtin fur textures".into(),
        place: "strand model".into(),
        message: e.to_string(),
    })?;
    let heights = height_levels(&set.heightfield);
    let fin = set
        .fin
        .iter()
        .map(|i| Level {
            width: i.width,
            height: i.height,
            texels: match &i.pixels {
                Pixels::Rgba8(v) => v.clone(),
                Pixels::Gray8(v) => v.iter().map(|&x| [x, x, x, x]).collect(),
                Pixels::Gray16(v) => v.iter().map(|&x| [(x >> 8) as u8; 4]).collect(),
            },
        })
        .collect();
    let v = |c: [f64; 3]| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32);
    let look = FurLook {
        length: config.length as f32,
        shells: config.shells,
        shell_rule: Some(pelt_fur::shells::ShellRule::MEASURED),
        uv_scale: config.uv_scale as f32,
        base_color: v(config.base_color),
        tip_color: v(config.tip_color),
        color_from_texture: config.color_from_texture,
    };
    Ok((look, (heights, fin)))
}

/// The first channel of decoded PNG rows as 16-bit values (8-bit values × 257); None for bit
/// depths below 8 or palette images.
fn first_channel(color: png::ColorType, depth: png::BitDepth, buf: &[u8]) -> Option<Vec<u16>> {
    let channels = match color {
        png::ColorType::Grayscale => 1,
        png::ColorType::GrayscaleAlpha => 2,
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        png::ColorType::Indexed => return None,
    };
    match depth {
        png::BitDepth::Sixteen => Some(
            buf.chunks_exact(2 * channels)
                .map(|b| u16::from_be_bytes([b[0], b[1]]))
                .collect(),
        ),
        png::BitDepth::Eight => Some(
            buf.chunks_exact(channels)
                .map(|b| u16::from(b[0]) * 257)
                .collect(),
        ),
        _ => None,
    }
}

/// Decodes one PNG of the manifest, checking its size against what the manifest claims
/// before anything is allocated from it.
fn decode_png(
    doc: &Document,
    image: usize,
    want: (u32, u32),
    place: &str,
) -> Result<(png::ColorType, png::BitDepth, Vec<u8>), IoError> {
    let bytes = doc.image_bytes(image)?;
    let bad = |m: String| doc.invalid(format!("{place} images[{image}]"), m);
    let mut dec = png::Decoder::new(std::io::Cursor::new(bytes));
    dec.set_transformations(png::Transformations::IDENTITY);
    let mut reader = dec.read_info().map_err(|e| bad(e.to_string()))?;
    let info = reader.info();
    if (info.width, info.height) != want {
        return Err(bad(format!(
            "is {}×{}, the manifest says {}×{}",
            info.width, info.height, want.0, want.1
        )));
    }
    let (color, depth) = (info.color_type, info.bit_depth);
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| bad("image too large".into()))?;
    let mut buf = vec![0; size];
    let frame = reader
        .next_frame(&mut buf)
        .map_err(|e| bad(e.to_string()))?;
    buf.truncate(frame.buffer_size());
    Ok((color, depth, buf))
}

/// Reads the heightfield and fin levels the manifest lists.
fn baked_textures(doc: &Document, m: &FurManifest, place: &str) -> Result<Textures, IoError> {
    let image_of = |l: &pelt_fur::manifest::LevelRef, what: &str| {
        l.image
            .ok_or_else(|| doc.invalid(format!("{place}.textures.{what}"), "a level has no image"))
    };
    let mut heights = Vec::new();
    for l in &m.textures.heightfield.levels {
        let (color, depth, buf) =
            decode_png(doc, image_of(l, "heightfield")?, (l.width, l.height), place)?;
        // Gray as baked; a tool that re-encoded the image (glTF-Transform's texture
        // compression writes RGB) keeps the heights in every colour channel: the first is read.
        let texels = first_channel(color, depth, &buf).ok_or_else(|| {
            doc.invalid(
                format!("{place}.textures.heightfield"),
                format!("must be an 8- or 16-bit PNG, found {color:?} {depth:?}"),
            )
        })?;
        heights.push(Level {
            width: l.width,
            height: l.height,
            texels,
        });
    }
    let fin = fin_levels(doc, m, place)?;
    if heights.is_empty() || fin.is_empty() {
        return Err(doc.invalid(
            format!("{place}.textures"),
            "the heightfield and the fin texture need at least one level",
        ));
    }
    Ok((heights, fin))
}

/// The fin texture's levels of manifest `m` (at `place`), decoded from the document's PNGs:
/// 8-bit RGBA, at least one level.
pub fn fin_levels(
    doc: &Document,
    m: &FurManifest,
    place: &str,
) -> Result<Vec<Level<[u8; 4]>>, IoError> {
    let mut fin = Vec::new();
    for l in &m.textures.fin.levels {
        let image = l
            .image
            .ok_or_else(|| doc.invalid(format!("{place}.textures.fin"), "a level has no image"))?;
        let (color, depth, buf) = decode_png(doc, image, (l.width, l.height), place)?;
        if (color, depth) != (png::ColorType::Rgba, png::BitDepth::Eight) {
            return Err(doc.invalid(
                format!("{place}.textures.fin"),
                format!("must be 8-bit RGBA, found {color:?} {depth:?}"),
            ));
        }
        fin.push(Level {
            width: l.width,
            height: l.height,
            texels: buf
                .chunks_exact(4)
                .map(|b| [b[0], b[1], b[2], b[3]])
                .collect(),
        });
    }
    if fin.is_empty() {
        return Err(doc.invalid(
            format!("{place}.textures"),
            "the heightfield and the fin texture need at least one level",
        ));
    }
    Ok(fin)
}

/// The fur manifest of the primitive's material, if it has one.
pub fn manifest(doc: &Document, r: PrimitiveRef) -> Result<Option<(FurManifest, String)>, IoError> {
    let Some(m) = doc.primitive_material(r)? else {
        return Ok(None);
    };
    let Some((v, place)) = doc.fur_manifest_json(m)? else {
        return Ok(None);
    };
    let parsed: FurManifest =
        serde_json::from_value(v).map_err(|e| doc.invalid(&place, e.to_string()))?;
    let ok = parsed.length.is_finite()
        && parsed.length >= 0.0
        && parsed.uv_scale.is_finite()
        && parsed.uv_scale > 0.0
        && (1..=1024).contains(&parsed.shells);
    if !ok {
        return Err(doc.invalid(
            &place,
            "length must be ≥ 0, uvScale above 0 and shells 1 to 1024",
        ));
    }
    if let Some(why) = parsed.shell_rule.and_then(|r| r.invalid()) {
        return Err(doc.invalid(format!("{place}.shellRule"), why));
    }
    Ok(Some((parsed, place)))
}

/// Look and textures for an asset whose first fur manifest is `found` (None: generated).
pub fn look_and_textures(
    doc: &Document,
    found: Option<&(FurManifest, String)>,
) -> Result<(FurLook, Textures, TextureSource), IoError> {
    match found {
        Some((m, place)) => Ok((
            look_of(m),
            baked_textures(doc, m, place)?,
            TextureSource::Baked,
        )),
        None => {
            let (look, t) = generated()?;
            Ok((look, t, TextureSource::Generated))
        }
    }
}

pub use pelt_io::contract::{comb_object, read_comb};

/// One primitive's fur vertices, in the asset's space (`world` applied to the tangent). Fur
/// length is in mesh units (docs/format.md), so each vertex carries what `world` makes of a
/// mesh unit along its normal ([`length_scale`]).
pub fn fur_vertices(
    world: Mat4,
    normals: &[Vec3],
    tangents: Option<&[Vec4]>,
    uvs: Option<&[Vec2]>,
    comb: Option<&[Vec4]>,
) -> Vec<FurVertex> {
    let m3 = Mat3::from_mat4(world);
    // In f64, so that a transform without scale gives exactly 1 (images as before).
    let normal_world = m3.as_dmat3().inverse().transpose();
    let flip = if world.determinant() < 0.0 { -1.0 } else { 1.0 };
    (0..normals.len())
        .map(|k| {
            let t =
                tangents.map_or_else(|| normals[k].any_orthonormal_vector().extend(1.0), |t| t[k]);
            FurVertex {
                tangent: (m3 * t.truncate())
                    .normalize_or_zero()
                    .extend(t.w * flip)
                    .into(),
                uv: uvs.map_or([0.0; 2], |u| u[k].into()),
                comb: comb.map_or([1.0, 0.0, 0.0, 0.0], |c| c[k].into()),
                bend: [0.0, 0.0, 0.0, length_scale(normal_world, normals[k])],
            }
        })
        .collect()
}

/// What a linear map whose inverse transpose is `normal_world` makes of a mesh unit along the
/// normal `n`: the distance between the surface and the surface offset by one unit along its
/// normal, once mapped (|n| / |M⁻ᵀ n|; s for a uniform scale s, the scale across the surface
/// for a non-uniform one; exactly 1 without scale). 0 where the map collapses space (a zero
/// scale axis) or `n` is zero.
pub fn length_scale(normal_world: DMat3, n: Vec3) -> f32 {
    let n = n.as_dvec3();
    let s = n.length() / (normal_world * n).length();
    if s.is_finite() { s as f32 } else { 0.0 }
}

/// The fin texture's horizontal offset of the edge between vertices `a` and `b` (either order):
/// a hash, so that neighbouring fins do not repeat the same strands.
pub fn edge_offset(a: u32, b: u32) -> f32 {
    let z = pelt_fur::rng::mix64((u64::from(a.min(b)) << 32) | u64::from(a.max(b)));
    (z >> 40) as f32 / (1u64 << 24) as f32
}

/// Fins stand only where the fur at one end of the edge is longer than this share of the
/// fur length (the shells fade fur below 5 %; fin_rebuild.wgsl applies the same rule).
pub const FIN_MIN_LENGTH: f32 = 0.05;

/// The primitive's fin edges as instances, in the asset's space. `base` is the index of the
/// primitive's first vertex in `verts` (already in the asset's space); `mesh` is the primitive
/// as read, whose index list the fin records' corners refer to.
pub fn fin_instances(
    (doc, r): (&Document, PrimitiveRef),
    mesh: &pelt_geom::Mesh,
    verts: &[crate::vertex::Vertex],
    fur: &[FurVertex],
    (base, world): (usize, Mat4),
    material: &crate::material::Material,
    warnings: &mut Vec<String>,
) -> Result<(Vec<FinInstance>, Vec<crate::skin::FinSource>), IoError> {
    let edges = match doc.read_stored_fins(r)? {
        None => return Ok((Vec::new(), Vec::new())),
        Some(StoredFins::Valid(e)) => e,
        Some(StoredFins::Stale(why)) => {
            warnings.push(format!(
                "{}: {}: {why}; the fins were rebuilt from the triangles at load (bake the \
                 source again, or run glTF tools with integrations/gltf-transform's config, \
                 to store them)",
                doc.path.display(),
                doc.place(r)
            ));
            rebuild_fins(mesh, &fur[base..])
        }
    };
    let mut sources = Vec::with_capacity(edges.len());
    let face = |c: u32| {
        let i = |k: u32| mesh.indices[k as usize] + base as u32;
        [i(c), i(next(c)), i(prev(c))]
    };
    let n = verts.len() - base;
    let normal_world = Mat3::from_mat4(world).inverse().transpose();
    let mut out = Vec::with_capacity(edges.len());
    for e in &edges {
        // read_fins checked the corners against the index list, and read_primitive the
        // indices against the vertices.
        let g = pelt_io::topology::fin_geometry(e, &mesh.indices, &mesh.positions);
        let [a, b] = g.vertices;
        debug_assert!((a as usize) < n && (b as usize) < n);
        let (va, vb) = (&verts[base + a as usize], &verts[base + b as usize]);
        let (fa, fb) = (&fur[base + a as usize], &fur[base + b as usize]);
        let [f0, f1] = g
            .face_normals
            .map(|f| (normal_world * f).normalize_or_zero());
        // w: the comb length in the asset's units; 0 at both ends of an edge whose fur is
        // shorter than FIN_MIN_LENGTH at either end (fins.wgsl draws no fin there).
        let bare = fa.comb[3].max(fb.comb[3]) <= FIN_MIN_LENGTH;
        let comb = |v: &crate::vertex::Vertex, f: &FurVertex| {
            let c = Vec4::from(f.comb);
            let length = if bare { 0.0 } else { f.comb_length() };
            comb_object(Vec3::from(v.normal), Vec4::from(f.tangent), c.truncate()).extend(length)
        };
        let uv_len = (Vec2::from(fa.uv) - Vec2::from(fb.uv)).length();
        let mid_uv = 0.5 * (Vec2::from(va.uv) + Vec2::from(vb.uv));
        let albedo = 0.5 * (Vec4::from(va.albedo) + Vec4::from(vb.albedo));
        out.push(FinInstance {
            p0: va.position,
            p1: vb.position,
            n0: va.normal,
            n1: vb.normal,
            c0: comb(va, fa).into(),
            c1: comb(vb, fb).into(),
            f0: f0.into(),
            f1: f1.into(),
            u: [edge_offset(a, b), uv_len],
            group: va.group,
            albedo: (albedo.truncate() * base_color_at(material, mid_uv)).into(),
        });
        let f0 = face(e.corner);
        let f1 = if e.second_face().is_some() {
            face(e.second_corner)
        } else {
            f0
        };
        sources.push([
            a + base as u32,
            b + base as u32,
            f0[0],
            f0[1],
            f0[2],
            f1[0],
            f1[1],
            f1[2],
        ]);
    }
    Ok((out, sources))
}

/// The fin edges of `mesh` computed from its triangles, as a bake does (welded positions, every
/// edge with fur at an end): what a reader does with records a tool left stale. `fur` holds the
/// primitive's fur vertices (the comb's w is the length).
fn rebuild_fins(mesh: &pelt_geom::Mesh, fur: &[FurVertex]) -> Vec<pelt_geom::fins::FinEdge> {
    use pelt_geom::topology::{CornerNormals, TopologyOptions};
    let flat;
    let normals = match &mesh.normals {
        Some(n) => n.as_slice(),
        None => {
            flat = vec![Vec3::Z; mesh.positions.len()];
            &flat
        }
    };
    let mut t = pelt_geom::topology::build(
        &mesh.positions,
        &mesh.indices,
        CornerNormals::Vertex(normals),
        &TopologyOptions::default(),
    );
    let lengths: Vec<f32> = fur
        .iter()
        .take(mesh.positions.len())
        .map(|f| f.comb[3])
        .collect();
    pelt_geom::fins::build(
        t.take_edges(),
        &mesh.indices,
        pelt_geom::fins::Fur::Lengths(&lengths),
    )
}

/// What the primitive lost of pelt's contract (a tool that does not know `PELT_fur` dropped
/// it, or dropped the attributes it names), as a warning naming the file, the primitive, the
/// missing data and what to do; None when nothing is missing. `has_comb`: whether the
/// primitive has `_FUR_COMB`.
pub fn lost_contract(
    doc: &Document,
    r: PrimitiveRef,
    has_comb: bool,
) -> Result<Option<String>, IoError> {
    let stored = doc.fur_primitive(r)?.map(|(f, _)| f);
    let material = doc.primitive_material(r)?;
    let manifest = match material {
        Some(m) => doc.fur_manifest_json(m)?.is_some(),
        None => false,
    };
    // What is left of a bake whose fur data a tool dropped whole (gltfpack, Blender's
    // exporter): the sheen pelt gave the fur material, which those tools keep.
    let sheen = material.is_some_and(|m| doc.material_has_extension(m, pelt_io::extension::SHEEN));
    let fix = "bake the source again, or run glTF tools with integrations/gltf-transform's \
               config (docs/pipelines.md)";
    let lost = if has_comb && stored.is_none() && !manifest {
        "has _FUR_COMB but no PELT_fur (its fin records, normal-group summary and fur \
         manifest are gone): drawn with the default strand textures and no fins"
            .to_owned()
    } else if !has_comb && (stored.is_some_and(|f| f.contains_key("combAttribute")) || manifest) {
        "carries PELT_fur but no _FUR_COMB (a tool dropped the attribute): drawn as a bare mesh"
            .to_owned()
    } else if has_comb
        && stored.is_some_and(|f| f.contains_key("normalGroups"))
        && doc
            .attribute(r, pelt_io::contract::NORMAL_GROUP_ATTRIBUTE)?
            .is_none()
    {
        "has no _NORMAL_GROUP though PELT_fur records normal groups (a tool dropped the \
         attribute): inferred lighting blends light across its creases"
            .to_owned()
    } else if !has_comb && stored.is_none() && !manifest && sheen {
        "has a sheen material (KHR_materials_sheen) but no _FUR_COMB and no PELT_fur: if pelt \
         baked it, a tool dropped all its fur data (gltfpack and Blender's exporter do): \
         drawn as a bare mesh"
            .to_owned()
    } else {
        return Ok(None);
    };
    Ok(Some(format!(
        "{}: {}: {lost}; {fix}",
        doc.path.display(),
        doc.place(r)
    )))
}

/// The corner after `c` in its triangle.
fn next(c: u32) -> u32 {
    c - c % 3 + (c + 1) % 3
}

/// The corner before `c` in its triangle.
fn prev(c: u32) -> u32 {
    c - c % 3 + (c + 2) % 3
}

/// The linear colour of `material`'s base colour texture at `uv` (white without one).
pub fn base_color_at(material: &crate::material::Material, uv: Vec2) -> Vec3 {
    let Some(t) = &material.base_color else {
        return Vec3::ONE;
    };
    let c = |k| crate::material::srgb_to_linear(t.image.sample(uv.x, uv.y, k, t.wrap));
    Vec3::new(c(0), c(1), c(2))
}
