//! The bake config file (JSON): today one section, `fur`, which makes `pelt bake` generate fur
//! textures from a seeded strand model and embed them with the fur manifest (see
//! [`pelt_fur::FurConfig`] and docs/format.md). Unknown keys are errors; every error names the
//! file, and the line and column or the field.

use std::path::{Path, PathBuf};

use pelt_fur::FurConfig;
use serde::{Deserialize, Serialize};

/// A bake config.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BakeConfig {
    /// Fur textures and parameters to embed; absent = none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fur: Option<FurConfig>,
}

/// A config that could not be used.
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    /// The file could not be read.
    #[error("{}: {source}", path.display())]
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
    /// A value out of range.
    #[error("{}: fur.{field}: {why}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// The field (under `fur`).
        field: String,
        /// What is wrong.
        why: String,
    },
}

impl BakeConfig {
    /// Reads and checks a config file.
    pub fn load(path: &Path) -> Result<BakeConfig, ConfigError> {
        let text = std::fs::read_to_string(path).map_err(|source| ConfigError::Read {
            path: path.to_owned(),
            source,
        })?;
        Self::parse(path, &text)
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
                field: e.field,
                why: e.why,
            })?;
        }
        Ok(config)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
