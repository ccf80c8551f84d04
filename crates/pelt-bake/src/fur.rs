//! Embedding fur textures in a baked asset: the PNGs of a [`TextureSet`] (every mip level) as
//! images, each level a texture (REPEAT, trilinear; the fin texture clamps vertically), and
//! the fur manifest in each fur material's `extensions.PELT_fur` (`pelt_io::extension`). The textures are
//! generated once and shared by every asset of a run.

use std::collections::BTreeMap;
use std::time::Instant;

use pelt_fur::set::level_name;
use pelt_fur::{FurConfig, FurError, TextureSet};
use pelt_io::extension::{
    EXTENSION, extension_from_manifest, for_each_material_texture, remove_legacy_fur,
    sheen_fallback,
};
use pelt_io::texture::gl;
use pelt_io::{Document, IoError, PrimitiveRef};
use serde::Serialize;

/// Name of the material pelt adds for comb primitives that have none.
pub const FUR_MATERIAL_NAME: &str = "pelt fur";

/// Generated fur textures, ready to embed.
#[derive(Debug, Clone)]
pub struct FurAssets {
    /// The config they came from.
    pub config: FurConfig,
    /// The textures.
    pub set: TextureSet,
    /// Each image of `set.images()` as PNG.
    pub pngs: Vec<Vec<u8>>,
    /// Milliseconds spent generating and encoding.
    pub generate_ms: f64,
}

impl FurAssets {
    /// Generates and encodes the textures of `config`.
    pub fn new(config: FurConfig) -> Result<FurAssets, FurError> {
        let t0 = Instant::now();
        let set = pelt_fur::generate(&config.textures)?;
        let pngs = set.encode()?;
        Ok(FurAssets {
            config,
            set,
            pngs,
            generate_ms: (t0.elapsed().as_secs_f64() * 1e5).round() / 100.0,
        })
    }
}

/// What embedding did.
#[derive(Debug, Clone, Default, Serialize)]
pub struct FurReport {
    /// Materials that carry the manifest.
    pub materials: Vec<usize>,
    /// Whether a `pelt fur` material was added for comb primitives without one.
    pub material_added: bool,
    /// Images added.
    pub images: usize,
    /// PNG bytes added.
    pub texture_bytes: usize,
    /// Warnings.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// Embeds `assets` in `doc`. `combed` lists the primitives that got `_FUR_COMB`; they decide
/// the fur materials unless the config names them.
pub fn embed(
    doc: &mut Document,
    assets: &FurAssets,
    combed: &[PrimitiveRef],
) -> Result<FurReport, IoError> {
    let mut report = FurReport::default();
    strip_old_fur(doc, &mut report);
    let materials = fur_materials(doc, assets, combed, &mut report)?;
    if materials.is_empty() {
        report
            .warnings
            .push("no primitive has a comb: fur textures were not embedded".into());
        return Ok(report);
    }
    let (images, by_image) = push_textures(doc, assets, &mut report);
    let textures: BTreeMap<&str, usize> = ["heightfield", "dots", "fin"]
        .into_iter()
        .filter_map(|stem| Some((stem, by_image[images.get(&level_name(stem, 0))?])))
        .collect();
    let manifest = assets.set.manifest(
        &assets.config,
        &mut |stem, level| (None, images.get(&level_name(stem, level)).copied()),
        &mut |stem| textures.get(stem).copied(),
    );
    let manifest = serde_json::to_value(&manifest)
        .map_err(|e| IoError::invalid(&doc.path, "fur manifest", format!("cannot encode: {e}")))?;
    let value = extension_from_manifest(&manifest, &mut |image| by_image[&image]);
    for &m in &materials {
        let base = doc.array("materials")[m]["pbrMetallicRoughness"].get("baseColorTexture");
        let sheen = sheen_fallback(&value, base);
        if doc.set_fur_material(m, value.clone())
            && doc.set_material_extension(m, pelt_io::extension::SHEEN, sheen)
        {
            report.materials.push(m);
        } else {
            report.warnings.push(format!(
                "material {m}: extensions is not a JSON object: the fur manifest was not stored"
            ));
        }
    }
    Ok(report)
}

/// Choosing the fur's materials: those the config names, or else those of the combed
/// primitives (a combed primitive without a material gets the added [`FUR_MATERIAL_NAME`]
/// material), sorted, each once. An added material an earlier bake left with glTF's default
/// factors is made the neutral dielectric, with a warning.
fn fur_materials(
    doc: &mut Document,
    assets: &FurAssets,
    combed: &[PrimitiveRef],
    report: &mut FurReport,
) -> Result<Vec<usize>, IoError> {
    let mut materials: Vec<usize> = Vec::new();
    if let Some(names) = &assets.config.materials {
        for name in names {
            let found: Vec<usize> = (0..doc.array("materials").len())
                .filter(|&m| doc.material_name(m) == Some(name.as_str()))
                .collect();
            if found.is_empty() {
                return Err(doc.invalid(
                    "materials",
                    format!("the config's fur.materials names {name:?}, which is not a material of this file"),
                ));
            }
            materials.extend(found);
        }
    } else {
        let mut bare = Vec::new();
        for &r in combed {
            match doc.primitive_material(r)? {
                Some(m) => materials.push(m),
                None => bare.push(r),
            }
        }
        if !bare.is_empty() {
            let m = match find_added_material(doc) {
                Some(m) => m,
                None => doc.push_material(FUR_MATERIAL_NAME),
            };
            for r in bare {
                doc.set_primitive_material(r, m)?;
            }
            materials.push(m);
            report.material_added = true;
        }
    }
    materials.sort_unstable();
    materials.dedup();
    for &m in &materials {
        if doc.material_name(m) == Some(FUR_MATERIAL_NAME) && doc.make_neutral_if_default(m) {
            report.warnings.push(format!(
                "materials[{m}] {FUR_MATERIAL_NAME:?}: an earlier bake added it with glTF's \
                 default factors (metal, drawn black where unlit); it is now the neutral \
                 dielectric (metallic 0, roughness 0.5) a primitive without a material is drawn with"
            ));
        }
    }
    Ok(materials)
}

/// Adding the fur textures: every level's image, the tiling and fin samplers, and a texture
/// per image (level 0 the one a textureInfo names, the others its `mipLevels`, so that tools
/// which prune or dedup textures keep and remap them all). Returns the image index of each
/// level's name and the texture index of each image.
fn push_textures(
    doc: &mut Document,
    assets: &FurAssets,
    report: &mut FurReport,
) -> (BTreeMap<String, usize>, BTreeMap<usize, usize>) {
    let mut images = BTreeMap::new();
    for (img, png) in assets.set.images().zip(&assets.pngs) {
        let index = doc.push_image(png.clone(), pelt_fur::Image::MIME, &img.name);
        images.insert(img.name.clone(), index);
        report.images += 1;
        report.texture_bytes += png.len();
    }
    let tile = doc.push_sampler(gl::LINEAR, gl::LINEAR_MIPMAP_LINEAR, gl::REPEAT, gl::REPEAT);
    let fin = doc.push_sampler(
        gl::LINEAR,
        gl::LINEAR_MIPMAP_LINEAR,
        gl::REPEAT,
        gl::CLAMP_TO_EDGE,
    );
    // Every level is a texture (level 0 the one a textureInfo names, the others its
    // `mipLevels`), so that tools which prune or dedup textures keep and remap them all.
    let mut by_image = BTreeMap::new();
    for (stem, sampler) in [("heightfield", tile), ("dots", tile), ("fin", fin)] {
        let mut level = 0;
        while let Some(&image) = images.get(&level_name(stem, level)) {
            let name = match level {
                0 => format!("pelt fur {stem}"),
                l => format!("pelt fur {stem} mip {l}"),
            };
            by_image.insert(image, doc.push_texture(image, sampler, &name));
            level += 1;
        }
    }
    (images, by_image)
}

/// The material an earlier bake added to primitives without one, reused when baking its output
/// again (so a re-bake adds no second copy).
fn find_added_material(doc: &Document) -> Option<usize> {
    (0..doc.array("materials").len()).find(|&m| doc.material_name(m) == Some(FUR_MATERIAL_NAME))
}

/// Removes the fur an earlier bake embedded (each material's `PELT_fur`, or legacy
/// `extras.pelt.fur`, and the textures and images it names, where nothing else uses them), so
/// that baking a pelt output again carries one set of fur images, not two.
fn strip_old_fur(doc: &mut Document, report: &mut FurReport) {
    let mut textures = Vec::new();
    let mut images = Vec::new();
    let Some(materials) = doc.json.get_mut("materials").and_then(|m| m.as_array_mut()) else {
        return;
    };
    for m in materials.iter_mut().filter_map(|m| m.as_object_mut()) {
        let ext = m
            .get_mut("extensions")
            .and_then(|e| e.as_object_mut())
            .and_then(|e| e.shift_remove(EXTENSION));
        if let Some(mut ext) = ext {
            for_each_material_texture(&mut ext, &mut |t| textures.extend(t.as_u64()));
        }
        if m.get("extensions")
            .and_then(|e| e.as_object())
            .is_some_and(|e| e.is_empty())
        {
            m.shift_remove("extensions");
        }
        let Some(fur) = remove_legacy_fur(m) else {
            continue;
        };
        let entries = fur.get("textures").and_then(|t| t.as_object());
        for entry in entries.into_iter().flat_map(|e| e.values()) {
            textures.extend(entry.get("texture").and_then(|t| t.as_u64()));
            let levels = entry.get("levels").and_then(|l| l.as_array());
            images.extend(
                levels
                    .into_iter()
                    .flatten()
                    .filter_map(|l| l.get("image")?.as_u64()),
            );
        }
    }
    // The images of the extension's textures.
    for &t in &textures {
        images.extend(
            doc.array("textures")
                .get(t as usize)
                .and_then(|t| t.get("source")?.as_u64()),
        );
    }
    let index = |v: Vec<u64>| v.into_iter().map(|i| i as usize).collect::<Vec<_>>();
    let removed = doc.remove_textures(&index(textures), &index(images));
    if let Some(why) = removed.kept_because {
        report.warnings.push(why);
    }
}

/// Bakes `doc` (comb, tangents, groups, fins as `opts` says) and embeds `assets` in the
/// materials of the primitives that got a comb: what `pelt bake --config` does to one input.
pub fn bake_with_fur(
    doc: &mut Document,
    opts: &crate::BakeOptions,
    assets: &FurAssets,
) -> Result<(crate::AssetReport, FurReport), IoError> {
    let bake = crate::bake_document(doc, opts)?;
    let fur = embed(doc, assets, &combed(&bake))?;
    Ok((bake, fur))
}

/// The primitives a bake gave a comb: the ones [`embed`] puts fur on by default.
pub fn combed(bake: &crate::AssetReport) -> Vec<PrimitiveRef> {
    bake.primitives
        .iter()
        .filter(|p| p.status == "baked")
        .map(|p| PrimitiveRef {
            mesh: p.mesh,
            primitive: p.primitive,
        })
        .collect()
}
