//! The knobs that live in the asset (fur texture size, heightfield bits, `_FUR_COMB`
//! quantization), turned by baking the asset again from its painted COLOR_0 (which a bake
//! keeps) with its own fur manifest, only that one parameter changed.

use std::path::Path;

use pelt_bake::BakeOptions;
use pelt_bake::fur::{FurAssets, bake_with_fur};
use pelt_fur::{FurConfig, FurManifest};
use pelt_io::{Document, IoError};

use super::knob::Setting;

/// Why an asset could not be baked again.
#[derive(Debug, thiserror::Error)]
pub enum RebakeError {
    /// Reading, baking or writing failed.
    #[error("re-baking {path}: {source}")]
    Io {
        /// The asset.
        path: String,
        /// Why.
        #[source]
        source: IoError,
    },
    /// The fur textures could not be made.
    #[error("re-baking {path}: fur textures: {source}")]
    Fur {
        /// The asset.
        path: String,
        /// Why.
        #[source]
        source: pelt_fur::FurError,
    },
}

/// The fur config the asset was baked with: its first material's manifest, or the defaults
/// the preview generates for an asset without one.
pub fn config_of(doc: &Document) -> FurConfig {
    let found = (0..doc.array("materials").len()).find_map(|m| {
        let (v, _) = doc.fur_manifest_json(m).ok()??;
        serde_json::from_value::<FurManifest>(v).ok()
    });
    match found {
        Some(m) => FurConfig {
            length: m.length,
            shells: m.shells,
            uv_scale: m.uv_scale,
            base_color: m.base_color,
            tip_color: m.tip_color,
            color_from_texture: m.color_from_texture,
            materials: None,
            textures: m.strands,
        },
        None => FurConfig {
            textures: pelt_scene::fur::generated_model(),
            ..FurConfig::default()
        },
    }
}

/// Bakes `src` again into `dst` with `setting`'s texture size, heightfield bits and comb
/// quantization (the rest as the asset's manifest says).
pub fn rebake(src: &Path, dst: &Path, setting: &Setting) -> Result<(), RebakeError> {
    let path = src.display().to_string();
    let io = |source| RebakeError::Io {
        path: path.clone(),
        source,
    };
    let mut doc = pelt_io::load(src).map_err(io)?;
    let mut config = config_of(&doc);
    if let Some(size) = setting.texture_size {
        config.textures.size = size;
        if config.textures.fin_height > size {
            config.textures.fin_height = 0;
        }
    }
    if let Some(bits) = setting.height_bits {
        config.textures.height_bits = bits;
    }
    let opts = BakeOptions {
        quantize: setting.quantize.unwrap_or_default(),
        ..BakeOptions::default()
    };
    let assets = FurAssets::new(config).map_err(|source| RebakeError::Fur {
        path: path.clone(),
        source,
    })?;
    bake_with_fur(&mut doc, &opts, &assets).map_err(io)?;
    pelt_io::glb::write_glb(&doc, dst).map_err(io)?;
    Ok(())
}
