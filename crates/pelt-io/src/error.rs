//! The IO error: always the file, then the place in it (mesh, primitive, attribute, accessor,
//! byte offset), then what is wrong.

use std::path::PathBuf;

/// Anything that goes wrong reading or writing an asset.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// The file could not be read or written.
    #[error("{}: {action}: {source}", path.display())]
    Fs {
        /// The file.
        path: PathBuf,
        /// What was being done ("read", "write", …).
        action: &'static str,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
    /// The file's content is wrong or unsupported at a given place.
    #[error("{}: {place}: {message}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// Where in the file (`meshes[0].primitives[1].attributes.COLOR_0 (accessor 5)`, …).
        place: String,
        /// What is wrong.
        message: String,
    },
}

impl IoError {
    /// An [`IoError::Invalid`] for `path` at `place`.
    pub fn invalid(
        path: &std::path::Path,
        place: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        IoError::Invalid {
            path: path.to_owned(),
            place: place.into(),
            message: message.into(),
        }
    }
}

impl IoError {
    /// The place and what is wrong, without the file (for a message that names it once).
    pub fn message(&self) -> String {
        match self {
            IoError::Fs { action, source, .. } => format!("{action}: {source}"),
            IoError::Invalid { place, message, .. } => format!("{place}: {message}"),
        }
    }
}

/// Result with [`IoError`].
pub type Result<T> = std::result::Result<T, IoError>;
