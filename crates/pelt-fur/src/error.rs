//! Errors of the texture generator.

use std::path::PathBuf;

/// A parameter out of range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("fur texture parameter `{field}`: {why}")]
pub struct ParamError {
    /// The parameter's name (as in the config file).
    pub field: String,
    /// What is wrong with it.
    pub why: String,
}

/// Anything that can go wrong making or writing fur textures.
#[derive(Debug, thiserror::Error)]
pub enum FurError {
    /// A parameter out of range.
    #[error(transparent)]
    Param(#[from] ParamError),
    /// PNG encoding failed.
    #[error("encoding {name}: {message}")]
    Png {
        /// The image.
        name: String,
        /// The encoder's message.
        message: String,
    },
    /// Writing a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}
