//! The bake config file (JSON). Sections:
//! - `fur` makes `pelt bake` generate fur textures from a seeded strand model and embed them
//!   with the fur manifest (see [`pelt_fur::FurConfig`] and docs/format.md);
//! - `comb` generates the comb of unpainted meshes (`source`, `length`, `smoothing`; the
//!   `--comb` flag overrides `source`);
//! - `normals` sets the crease angle of the smooth normals made for meshes without NORMAL
//!   (`creaseAngle`, degrees; the `--crease-angle` flag overrides it);
//! - `compress`: `"meshopt"` packs the output with `EXT_meshopt_compression`, `"none"` (the
//!   default) writes it plain (the `--compress` flag overrides it).
//!
//! Unknown keys are errors; every error names the file, and the line and column or the field.

use std::path::{Path, PathBuf};

use pelt_fur::FurConfig;
use serde::{Deserialize, Serialize};

use crate::options::{CombSource, CombSourceError, GeneratedComb, LengthTexture};

/// A bake config.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BakeConfig {
    /// Fur textures and parameters to embed; absent = none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fur: Option<FurConfig>,
    /// Where the comb comes from; absent = painted (COLOR_0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub comb: Option<CombConfig>,
    /// Normals made for meshes without NORMAL; absent = defaults.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub normals: Option<NormalsConfig>,
    /// How the output is packed; absent = plain.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub compress: Option<crate::options::Compression>,
}

/// The `comb` section.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields, rename_all = "camelCase")]
pub struct CombConfig {
    /// `painted`, `generate` or `generate:AXIS`, as the `--comb` flag.
    pub source: String,
    /// Length of a generated comb, 0 to 1 of the fur's length.
    pub length: f32,
    /// Smoothing steps of a generated comb over the welded mesh (0 to 1000).
    pub smoothing: u32,
    /// Scale `length` by a channel of a material texture (`{"texture": "baseColor",
    /// "channel": "a"}`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub length_texture: Option<LengthTextureConfig>,
}

/// `comb.lengthTexture`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "camelCase")]
pub struct LengthTextureConfig {
    /// `baseColor`, `metallicRoughness`, `normal`, `occlusion` or `emissive`.
    pub texture: String,
    /// `r`, `g`, `b` or `a`.
    pub channel: String,
}

/// Why a `comb` section names no comb.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CombSectionError {
    /// `source` is not `painted`, `generate` or `generate:AXIS`.
    #[error("{0}")]
    Source(#[from] CombSourceError),
    /// `lengthTexture.texture` names no texture slot.
    #[error("{0:?} is not baseColor, metallicRoughness, normal, occlusion or emissive")]
    LengthTexture(String),
    /// `lengthTexture.channel` names no channel.
    #[error("{0:?} is not r, g, b or a")]
    LengthChannel(String),
}

impl CombSectionError {
    /// The field at fault, from the root (`comb.source`).
    pub fn field(&self) -> &'static str {
        match self {
            CombSectionError::Source(_) => "comb.source",
            CombSectionError::LengthTexture(_) => "comb.lengthTexture.texture",
            CombSectionError::LengthChannel(_) => "comb.lengthTexture.channel",
        }
    }
}

impl LengthTextureConfig {
    fn parse(&self) -> Result<LengthTexture, CombSectionError> {
        let slot = pelt_io::picture::Slot::parse(&self.texture)
            .ok_or_else(|| CombSectionError::LengthTexture(self.texture.clone()))?;
        let channel = ["r", "g", "b", "a"]
            .iter()
            .position(|c| *c == self.channel)
            .ok_or_else(|| CombSectionError::LengthChannel(self.channel.clone()))?;
        Ok(LengthTexture {
            slot,
            channel: channel as u8,
        })
    }
}

impl Default for CombConfig {
    fn default() -> Self {
        CombConfig {
            source: "painted".to_owned(),
            length: 1.0,
            smoothing: GeneratedComb::DEFAULT_SMOOTHING,
            length_texture: None,
        }
    }
}

impl CombConfig {
    /// The comb this section asks for, with `source` replaced by `flag` when given.
    pub fn source(&self, flag: Option<CombSource>) -> Result<CombSource, CombSectionError> {
        let source = match flag {
            Some(f) => f,
            None => self.source.parse()?,
        };
        let length_texture = self
            .length_texture
            .as_ref()
            .map(LengthTextureConfig::parse)
            .transpose()?;
        Ok(match source {
            CombSource::Generate(g) => CombSource::Generate(GeneratedComb {
                length: self.length,
                smoothing: self.smoothing,
                length_texture,
                ..g
            }),
            painted => painted,
        })
    }
}

/// The `normals` section.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields, rename_all = "camelCase")]
pub struct NormalsConfig {
    /// Crease angle in degrees, 0 to 180.
    pub crease_angle: f32,
}

impl Default for NormalsConfig {
    fn default() -> Self {
        NormalsConfig {
            crease_angle: crate::options::DEFAULT_CREASE_ANGLE_DEG,
        }
    }
}

/// A config that could not be used.
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    /// The file could not be read (or is not UTF-8 text); the cause is the source.
    #[error("cannot read {}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// Not valid JSON, or a key or value of the wrong kind.
    #[error("{}:{line}:{column}: {message}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// The `comb` section names no comb (its source, or its length texture).
    #[error("{}: {}: {source}", path.display(), source.field())]
    Comb {
        /// The file.
        path: PathBuf,
        /// What is wrong, and in which field.
        #[source]
        source: CombSectionError,
    },
    /// A value out of range.
    #[error("{}: {field}: {why}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// The field, from the root (`fur.shells`).
        field: String,
        /// What is wrong.
        why: String,
    },
}

impl BakeConfig {
    /// Reads and checks a config file, and returns its bytes too (they are part of a batch's
    /// content key, so a changed config re-bakes).
    pub fn read(path: &Path) -> Result<(BakeConfig, Vec<u8>), ConfigError> {
        let read = |source| ConfigError::Read {
            path: path.to_owned(),
            source,
        };
        let bytes = std::fs::read(path).map_err(read)?;
        let text = std::str::from_utf8(&bytes).map_err(|e| {
            read(std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!("not UTF-8 text ({e})"),
            ))
        })?;
        Ok((Self::parse(path, text)?, bytes))
    }

    /// Reads and checks a config file.
    pub fn load(path: &Path) -> Result<BakeConfig, ConfigError> {
        Self::read(path).map(|(config, _)| config)
    }

    /// Parses and checks config text (`path` is used in errors).
    pub fn parse(path: &Path, text: &str) -> Result<BakeConfig, ConfigError> {
        let config: BakeConfig = serde_json::from_str(text).map_err(|e| {
            // serde_json appends " at line L column C"; the location goes in front instead.
            let message = e.to_string();
            let message = message
                .rsplit_once(" at line ")
                .map_or(message.as_str(), |(m, _)| m)
                .to_owned();
            ConfigError::Parse {
                path: path.to_owned(),
                line: e.line(),
                column: e.column(),
                message,
            }
        })?;
        if let Some(fur) = &config.fur {
            fur.validate().map_err(|e| ConfigError::Invalid {
                path: path.to_owned(),
                field: format!("fur.{}", e.field),
                why: e.why,
            })?;
        }
        let invalid = |field: &str, why: String| ConfigError::Invalid {
            path: path.to_owned(),
            field: field.to_owned(),
            why,
        };
        if let Some(comb) = &config.comb {
            // The length texture first: its error names its own field.
            let comb_error = |source| ConfigError::Comb {
                path: path.to_owned(),
                source,
            };
            if let Some(t) = &comb.length_texture {
                t.parse().map_err(comb_error)?;
            }
            comb.source(None).map_err(comb_error)?;
            if !(0.0..=1.0).contains(&comb.length) {
                return Err(invalid(
                    "comb.length",
                    format!("must be from 0 to 1, got {}", comb.length),
                ));
            }
            if comb.smoothing > 1000 {
                return Err(invalid(
                    "comb.smoothing",
                    format!("must be at most 1000, got {}", comb.smoothing),
                ));
            }
        }
        if let Some(n) = &config.normals {
            if !(0.0..=180.0).contains(&n.crease_angle) {
                return Err(invalid(
                    "normals.creaseAngle",
                    format!("must be from 0 to 180 degrees, got {}", n.crease_angle),
                ));
            }
        }
        Ok(config)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_that_cannot_be_read_names_itself_and_keeps_the_cause() {
        use std::error::Error as _;
        let dir = std::env::temp_dir().join(format!("pelt-config-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let latin1 = dir.join("latin1.json");
        std::fs::write(&latin1, b"{\"fur\": \xff}").expect("write");
        let e = BakeConfig::read(&latin1).expect_err("not UTF-8");
        assert_eq!(e.to_string(), format!("cannot read {}", latin1.display()));
        let cause = e.source().map(ToString::to_string).unwrap_or_default();
        assert!(cause.starts_with("not UTF-8 text"), "{cause}");
        let missing = BakeConfig::load(&dir.join("missing.json")).expect_err("missing");
        assert!(missing.source().is_some(), "{missing}");
        let ok = dir.join("ok.json");
        std::fs::write(&ok, b"{}").expect("write");
        let (config, bytes) = BakeConfig::read(&ok).expect("reads");
        assert_eq!((config.fur.is_none(), bytes.as_slice()), (true, &b"{}"[..]));
        std::fs::remove_dir_all(&dir).expect("clean up");
    }

    #[test]
    fn errors_name_file_place_and_field() {
        let p = Path::new("pelt.json");
        let e = BakeConfig::parse(p, "{\n  \"fur\": {\n    \"lenght\": 1\n  }\n}").unwrap_err();
        let s = e.to_string();
        assert!(s.starts_with("pelt.json:3:"), "{s}");
        assert!(s.contains("lenght"), "{s}");
        let e = BakeConfig::parse(p, r#"{"fur": {"textures": {"radius": 0.5}}}"#).unwrap_err();
        assert_eq!(
            e.to_string(),
            "pelt.json: fur.textures.radius: must be above 0 and at most 0.1 tile widths, got 0.5"
        );
        let e = BakeConfig::parse(p, r#"{"fur": {"textures": {"size": 1000}}}"#).unwrap_err();
        assert!(
            e.to_string()
                .contains("fur.textures.size: must be a power of two"),
            "{e}"
        );
        let e = BakeConfig::parse(p, r#"{"fur": {"shells": 0}}"#).unwrap_err();
        assert!(e.to_string().contains("fur.shells"), "{e}");
        let ok =
            BakeConfig::parse(p, r#"{"fur": {"length": 0.1, "textures": {"seed": 9}}}"#).unwrap();
        let fur = ok.fur.unwrap();
        assert_eq!(fur.textures.seed, 9);
        assert_eq!(fur.length, 0.1);
        assert_eq!(fur.shells, FurConfig::default().shells);
        assert_eq!(BakeConfig::parse(p, "{}").unwrap(), BakeConfig::default());
    }

    #[test]
    fn comb_and_normals_sections_parse_and_check() {
        let p = Path::new("pelt.json");
        let c = BakeConfig::parse(
            p,
            r#"{"comb": {"source": "generate:-y", "length": 0.5, "smoothing": 2},
                "normals": {"creaseAngle": 30}}"#,
        )
        .unwrap();
        let comb = c.comb.unwrap();
        let CombSource::Generate(g) = comb.source(None).unwrap() else {
            panic!("generate")
        };
        assert_eq!((g.axis, g.length, g.smoothing), ([0.0, -1.0, 0.0], 0.5, 2));
        // The flag replaces the source, not the length.
        let CombSource::Generate(g) = comb.source(Some("generate:x".parse().unwrap())).unwrap()
        else {
            panic!("flag")
        };
        assert_eq!((g.axis, g.length), ([1.0, 0.0, 0.0], 0.5));
        assert_eq!(c.normals.unwrap().crease_angle, 30.0);
        for (text, field) in [
            (r#"{"comb": {"source": "generate:q"}}"#, "comb.source"),
            (r#"{"comb": {"length": 2}}"#, "comb.length"),
            (r#"{"comb": {"smoothing": 5000}}"#, "comb.smoothing"),
            (r#"{"normals": {"creaseAngle": -1}}"#, "normals.creaseAngle"),
            (
                r#"{"comb": {"lengthTexture": {"texture": "albedo", "channel": "a"}}}"#,
                "comb.lengthTexture.texture",
            ),
            (
                r#"{"comb": {"lengthTexture": {"texture": "baseColor", "channel": "w"}}}"#,
                "comb.lengthTexture.channel",
            ),
        ] {
            let e = BakeConfig::parse(p, text).unwrap_err().to_string();
            assert!(e.starts_with(&format!("pelt.json: {field}: ")), "{e}");
        }
        let e = BakeConfig::parse(p, r#"{"comb": {"axis": "x"}}"#).unwrap_err();
        assert!(e.to_string().contains("axis"), "{e}");
    }
}
