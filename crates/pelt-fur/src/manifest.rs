//! The fur section of a bake config ([`FurConfig`]) and the manifest pelt writes with the
//! textures ([`FurManifest`]): the fur parameters a renderer needs (length, default shell
//! count, the UV scale the heightfield is sampled at, base and tip colours), where each
//! texture and mip level is, the strand parameters that made them, and their coverage,
//! measured and expected. `pelt textures` writes it as `fur.json` beside the PNGs; `pelt bake`
//! writes it into each fur material's `extras.pelt.fur` in the `.glb`. The format is in
//! docs/format.md.

use serde::{Deserialize, Serialize};

use crate::error::ParamError;
use crate::params::StrandParams;

/// Version of the manifest format.
pub const MANIFEST_VERSION: u32 = 1;

/// The `fur` section of a bake config.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields, rename_all = "camelCase")]
pub struct FurConfig {
    /// Fur length in mesh units (each vertex's `_FUR_COMB` w scales it).
    pub length: f64,
    /// Default number of shells.
    pub shells: u32,
    /// Scale applied to the mesh's UVs when sampling the heightfield and dots.
    pub uv_scale: f64,
    /// Linear RGB colour at the roots.
    pub base_color: [f64; 3],
    /// Linear RGB colour at the tips.
    pub tip_color: [f64; 3],
    /// Root and tip colours multiply the material's base colour (its texture, sampled under
    /// each strand, and factor): painted or textured assets keep their colours through the fur.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub color_from_texture: bool,
    /// Names of the materials that get fur; absent = every material of a primitive that has
    /// a comb (such primitives without a material get a new one, named `pelt fur`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub materials: Option<Vec<String>>,
    /// The strand model the textures come from.
    pub textures: StrandParams,
}

/// The shell counts a fur config, a scene and every flag accept.
pub const SHELLS: std::ops::RangeInclusive<u32> = 1..=256;

impl Default for FurConfig {
    fn default() -> Self {
        FurConfig {
            length: 0.05,
            shells: 16,
            uv_scale: 8.0,
            base_color: [0.10, 0.07, 0.05],
            tip_color: [0.60, 0.48, 0.36],
            color_from_texture: false,
            materials: None,
            textures: StrandParams::default(),
        }
    }
}

impl FurConfig {
    /// Checks every field; the error names the first bad one (texture fields as
    /// `textures.NAME`).
    pub fn validate(&self) -> Result<(), ParamError> {
        let bad = |field: &str, why: String| {
            Err(ParamError {
                field: field.to_owned(),
                why,
            })
        };
        if !(self.length.is_finite() && self.length > 0.0) {
            return bad(
                "length",
                format!("must be a positive number, got {}", self.length),
            );
        }
        if !SHELLS.contains(&self.shells) {
            return bad(
                "shells",
                format!(
                    "must be {} to {}, got {}",
                    SHELLS.start(),
                    SHELLS.end(),
                    self.shells
                ),
            );
        }
        if !(self.uv_scale.is_finite() && self.uv_scale > 0.0) {
            return bad(
                "uvScale",
                format!("must be a positive number, got {}", self.uv_scale),
            );
        }
        for (field, c) in [("baseColor", self.base_color), ("tipColor", self.tip_color)] {
            if c.iter().any(|v| !(0.0..=1.0).contains(v)) {
                return bad(field, format!("components must be in [0, 1], got {c:?}"));
            }
        }
        if let Some(m) = &self.materials {
            if m.is_empty() {
                return bad(
                    "materials",
                    "must name at least one material (or be left out)".into(),
                );
            }
        }
        self.textures.validate().map_err(|e| ParamError {
            field: format!("textures.{}", e.field),
            why: e.why,
        })
    }
}

/// Where one mip level of a texture is.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct LevelRef {
    /// File name (in `fur.json`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// glTF image index (in a `.glb`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub image: Option<usize>,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
}

/// One texture: its format and its levels (level 0 first).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct TextureEntry {
    /// glTF texture index of level 0 (in a `.glb`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub texture: Option<usize>,
    /// `gray16`, `gray8` or `rgba8`.
    pub format: String,
    /// Mip levels, level 0 first.
    pub levels: Vec<LevelRef>,
}

/// The three textures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TextureEntries {
    /// Heightfield (height of the tallest strand per texel, 0 = bare).
    pub heightfield: TextureEntry,
    /// Dot texture (coverage seen from above).
    pub dots: TextureEntry,
    /// Fin texture (side view; RGBA).
    pub fin: TextureEntry,
}

/// Coverage figures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Coverage {
    /// Mean alpha of the dot texture.
    pub dots: f64,
    /// (height, fraction of texels whose heightfield value exceeds it), for heights 0, 0.25,
    /// 0.5 and 0.75.
    pub shells: Vec<[f64; 2]>,
    /// Mean alpha of the fin texture's bottom row.
    pub fin_base: f64,
}

/// The manifest written with the textures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct FurManifest {
    /// [`MANIFEST_VERSION`].
    pub version: u32,
    /// Fur length in mesh units.
    pub length: f64,
    /// Shell count: the default, and the most [`shell_rule`](Self::shell_rule) draws.
    pub shells: u32,
    /// How many shells the fur's projected length calls for ([`crate::shells`]); absent in
    /// manifests written before it (their `shells` is always drawn).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shell_rule: Option<crate::shells::ShellRule>,
    /// UV scale for the heightfield and dots.
    pub uv_scale: f64,
    /// Root colour (linear RGB).
    pub base_color: [f64; 3],
    /// Tip colour (linear RGB).
    pub tip_color: [f64; 3],
    /// Root and tip colours multiply the material's base colour ([`FurConfig`]'s field);
    /// absent means false.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub color_from_texture: bool,
    /// The textures.
    pub textures: TextureEntries,
    /// The strand model's parameters.
    pub strands: StrandParams,
    /// Coverage measured on the textures.
    pub coverage: Coverage,
    /// Coverage the model predicts (absent with clumping, which the formulas do not cover).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub expected_coverage: Option<Coverage>,
}
