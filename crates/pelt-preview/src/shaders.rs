//! The WGSL sources of the preview renderer. Every file lives in the repository's top-level
//! `shaders/` folder and is compiled into the binary (and, in `pelt view --shaders DIR`,
//! reloaded from disk). A module is `common.wgsl` (shared structs and functions, no
//! bindings), then for the fur passes `fur_common.wgsl` and one of the two fur lighting
//! chunks (from the L-buffer, or forward Kajiya-Kay), for screen-space passes
//! `fullscreen.wgsl` (the one full-screen triangle), then the pass's own file. See
//! `shaders/README.md`.

/// The shared prelude.
pub const COMMON: &str = include_str!("../../../shaders/common.wgsl");

// FILES: every `.wgsl` file in `shaders/`, by name, listed by build.rs.
include!(concat!(env!("OUT_DIR"), "/shader_files.rs"));

fn file(name: &str) -> &'static str {
    FILES
        .iter()
        .find(|(n, _)| *n == name)
        .map_or("", |(_, s)| s)
}

/// How fur is lit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Lighting {
    /// From the L-buffer at the strand's root and tip (Revie §2.4.4).
    Inferred,
    /// Every light at the strand with Kajiya-Kay (Listing 2.4): the reference.
    Forward,
}

/// Which coverage code a shell pipeline holds (the `COVERAGE` override of shells.wgsl).
/// Code a pipeline does not need is left out when it is created, not branched over: drivers
/// that run a fragment's lanes in lockstep (llvmpipe) pay for both sides of a branch. So
/// only objects that may show a pixel under 1.5 strand diameters get the strand-resolving
/// taps (`pelt_scene::footprint`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Coverage {
    /// The strand model as a medium alone: every pixel holds many strands.
    Medium,
    /// The medium, and the unfiltered heightfield taps where a pixel resolves single strands.
    Resolved,
    /// The binary heightfield alone (`--fur-coverage binary`, Revie §2.4.4 as written).
    Binary,
}

impl Coverage {
    /// The value of shells.wgsl's `COVERAGE` override.
    pub fn constant(self) -> f64 {
        match self {
            Coverage::Medium => 0.0,
            Coverage::Resolved => 1.0,
            Coverage::Binary => 2.0,
        }
    }
}

/// The entry points a pipeline uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Entry {
    /// A render pipeline's vertex and fragment entry points.
    Render(&'static str, &'static str),
    /// A compute pipeline's entry point.
    Compute(&'static str),
}

/// A shader as a feature declares it: the files its module is made of, in order (the
/// prelude first, the pass's own file last), and the entry points a pipeline uses. Plain
/// const data: pipelines are keyed by it, the validation test walks every one a registered
/// feature declares.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ShaderDesc {
    /// The files, joined in this order.
    pub parts: &'static [&'static str],
    /// The entry points.
    pub entry: Entry,
}

impl ShaderDesc {
    /// A render shader of `parts` with `vs_main` and `fs_main`.
    pub const fn render(parts: &'static [&'static str]) -> ShaderDesc {
        ShaderDesc {
            parts,
            entry: Entry::Render("vs_main", "fs_main"),
        }
    }

    /// A full-screen pass: `parts` after the shared triangle, fragment entry point `fs`.
    pub const fn fullscreen(parts: &'static [&'static str], fs: &'static str) -> ShaderDesc {
        ShaderDesc {
            parts,
            entry: Entry::Render("vs_fullscreen", fs),
        }
    }

    /// A compute shader of `parts` with `cs_main`.
    pub const fn compute(parts: &'static [&'static str]) -> ShaderDesc {
        ShaderDesc {
            parts,
            entry: Entry::Compute("cs_main"),
        }
    }

    /// The pass's own file under `shaders/` (the last part).
    pub fn file(self) -> &'static str {
        self.parts.last().copied().unwrap_or("")
    }

    /// A name for the module (files after the prelude joined), for labels and errors.
    pub fn module_name(self) -> String {
        self.parts[1.min(self.parts.len())..].join("+")
    }

    /// The complete module source.
    pub fn source(self) -> String {
        self.source_with(file)
    }

    /// The module source with each file's text from `text` (hot reload).
    pub fn source_with<'t>(self, text: impl Fn(&str) -> &'t str) -> String {
        self.parts
            .iter()
            .map(|p| text(p))
            .collect::<Vec<_>>()
            .join("\n")
    }

    /// Whether the module is a compute shader.
    pub fn is_compute(self) -> bool {
        matches!(self.entry, Entry::Compute(_))
    }

    /// The vertex and fragment entry points (a compute shader's twice).
    pub fn entry_points(self) -> (&'static str, &'static str) {
        match self.entry {
            Entry::Render(vs, fs) => (vs, fs),
            Entry::Compute(cs) => (cs, cs),
        }
    }
}

/// A shader set that failed validation.
#[derive(Debug, thiserror::Error)]
pub enum ShaderError {
    /// A file could not be read.
    #[error("{}: {source}", path.display())]
    Read {
        /// The file.
        path: std::path::PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A module does not parse or validate.
    #[error("{module}: {message}")]
    Invalid {
        /// The module (its files joined by `+`).
        module: String,
        /// naga's error, with the source lines it points at.
        message: String,
    },
}

/// Parses and validates `source` with naga, the compiler wgpu itself uses; the error is
/// naga's report with the lines it points at.
pub fn validate(module: &str, source: &str) -> Result<naga::Module, ShaderError> {
    let invalid = |message: String| ShaderError::Invalid {
        module: module.to_owned(),
        message,
    };
    let parsed = naga::front::wgsl::parse_str(source)
        .map_err(|e| invalid(e.emit_to_string_with_path(source, module)))?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::all(),
    )
    .validate(&parsed)
    .map_err(|e| invalid(e.emit_to_string_with_path(source, module)))?;
    Ok(parsed)
}

/// Every file of [`FILES`] read from `dir`, each module built from them validated. Returns
/// the texts by file name, or the first error (nothing is replaced then).
pub fn load_dir(dir: &std::path::Path) -> Result<Vec<(&'static str, String)>, ShaderError> {
    let mut texts = Vec::with_capacity(FILES.len());
    for (name, _) in FILES {
        let path = dir.join(name);
        let text =
            std::fs::read_to_string(&path).map_err(|source| ShaderError::Read { path, source })?;
        texts.push((name, text));
    }
    let lookup = |n: &str| {
        texts
            .iter()
            .find(|(t, _)| *t == n)
            .map_or("", |(_, s)| s.as_str())
    };
    for shader in crate::features::registry::shaders() {
        validate(&shader.module_name(), &shader.source_with(lookup))?;
    }
    Ok(texts)
}
