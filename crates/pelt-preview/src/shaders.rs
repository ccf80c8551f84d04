//! The WGSL sources of the preview renderer. Every file lives in the repository's top-level
//! `shaders/` folder and is compiled into the binary (and, in `pelt view --shaders DIR`,
//! reloaded from disk). A pass's file imports what it shares from the shared modules
//! (`#import pelt::common::{Frame, …}`: `common.wgsl`, `fur_common.wgsl`, the two fur
//! lighting chunks, `fullscreen.wgsl`, each declaring its `#define_import_path`), and
//! naga_oil composes the module (the composer Bevy uses), validated with naga. No list of
//! files is written in Rust. See `shaders/README.md`.

use naga_oil::compose::{
    ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderDefValue,
};

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

/// A shader as a feature declares it: the pass's own file under `shaders/` (which imports what
/// it shares, `#import pelt::common::{…}`, composed by naga_oil), the shader defs it is
/// composed with (names and values: `#ifdef FORWARD_LIGHT` picks the fur's lighting chunk,
/// `#{MATERIAL_GROUP}` places the material's bindings), and the entry points a
/// pipeline uses. Plain const data: modules and pipelines are keyed by it, the validation
/// test walks every one a registered feature declares.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ShaderDesc {
    /// The pass's file.
    pub file: &'static str,
    /// Shader defs and their values.
    pub defs: &'static [(&'static str, u32)],
    /// The entry points.
    pub entry: Entry,
}

impl ShaderDesc {
    /// A render shader of `file` with `vs_main` and `fs_main`.
    pub const fn render(file: &'static str) -> ShaderDesc {
        ShaderDesc {
            file,
            defs: &[],
            entry: Entry::Render("vs_main", "fs_main"),
        }
    }

    /// A full-screen pass of `file` (which declares `vs_fullscreen` from
    /// `pelt::fullscreen`), fragment entry point `fs`.
    pub const fn fullscreen(file: &'static str, fs: &'static str) -> ShaderDesc {
        ShaderDesc {
            file,
            defs: &[],
            entry: Entry::Render("vs_fullscreen", fs),
        }
    }

    /// A compute shader of `file` with `cs_main`.
    pub const fn compute(file: &'static str) -> ShaderDesc {
        ShaderDesc {
            file,
            defs: &[],
            entry: Entry::Compute("cs_main"),
        }
    }

    /// The same shader composed with `defs` set.
    pub const fn with_defs(self, defs: &'static [(&'static str, u32)]) -> ShaderDesc {
        ShaderDesc { defs, ..self }
    }

    /// The pass's own file under `shaders/`.
    pub fn file(self) -> &'static str {
        self.file
    }

    /// A name for the module (the file and its defs), for labels and errors.
    pub fn module_name(self) -> String {
        std::iter::once(self.file.to_owned())
            .chain(self.defs.iter().map(|(d, v)| format!("{d}={v}")))
            .collect::<Vec<_>>()
            .join("+")
    }

    /// The composed module, validated.
    pub fn compose(self) -> Result<naga::Module, ShaderError> {
        self.compose_with(file)
    }

    /// The composed module with each file's text from `text` (hot reload).
    pub fn compose_with<'t>(
        self,
        text: impl Fn(&str) -> &'t str,
    ) -> Result<naga::Module, ShaderError> {
        let name = self.module_name();
        let mut composer = library(&text, &name)?;
        let defs = self
            .defs
            .iter()
            .map(|(d, v)| ((*d).to_owned(), ShaderDefValue::UInt(*v)))
            .collect();
        let source = text(self.file);
        let made = composer.make_naga_module(NagaModuleDescriptor {
            source,
            file_path: self.file,
            shader_defs: defs,
            ..NagaModuleDescriptor::default()
        });
        made.map_err(|e| ShaderError::Invalid {
            module: name,
            message: e.emit_to_string(&composer),
        })
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

/// The module path a file declares (`#define_import_path`), if it is a shared module.
fn import_path(text: &str) -> Option<&str> {
    text.lines()
        .find_map(|l| l.trim().strip_prefix("#define_import_path"))
        .map(str::trim)
}

/// The module paths a file imports (`#import a::b::{…}` names module `a::b`).
fn imports(text: &str) -> Vec<&str> {
    text.lines()
        .filter_map(|l| l.trim().strip_prefix("#import"))
        .map(|l| {
            let path = l.trim().split(['{', ' ']).next().unwrap_or("");
            path.trim_end_matches(':')
        })
        .collect()
}

/// A composer holding every shared module of [`FILES`] (those that declare
/// `#define_import_path`), texts from `text`, each added after the modules it imports.
fn library<'t>(text: &impl Fn(&str) -> &'t str, module: &str) -> Result<Composer, ShaderError> {
    let mut pending: Vec<(&str, &str, &str)> = FILES
        .iter()
        .filter_map(|(name, _)| {
            let t = text(name);
            import_path(t).map(|p| (*name, p, t))
        })
        .collect();
    let mut composer = Composer::default();
    while !pending.is_empty() {
        let ready = pending
            .iter()
            .position(|(_, _, t)| imports(t).iter().all(|i| composer.contains_module(i)))
            .ok_or_else(|| ShaderError::Invalid {
                module: module.to_owned(),
                message: format!(
                    "the shared modules {:?} import one another or a module no file declares",
                    pending.iter().map(|p| p.1).collect::<Vec<_>>()
                ),
            })?;
        let (name, _, source) = pending.remove(ready);
        let added = composer.add_composable_module(ComposableModuleDescriptor {
            source,
            file_path: name,
            ..ComposableModuleDescriptor::default()
        });
        if let Err(e) = added {
            return Err(ShaderError::Invalid {
                module: name.to_owned(),
                message: e.emit_to_string(&composer),
            });
        }
    }
    Ok(composer)
}

/// `source` (a shader that imports the shared modules, e.g. a test's) composed and validated.
pub fn compose_str(name: &str, source: &str) -> Result<naga::Module, ShaderError> {
    let mut composer = library(&file, name)?;
    let made = composer.make_naga_module(NagaModuleDescriptor {
        source,
        file_path: name,
        ..NagaModuleDescriptor::default()
    });
    made.map_err(|e| ShaderError::Invalid {
        module: name.to_owned(),
        message: e.emit_to_string(&composer),
    })
}

/// The name naga_oil gives item `item` of the shared module `module` in a composed module
/// (imported items are decorated with their module's path).
pub fn decorated(module: &str, item: &str) -> String {
    Composer::decorated_name(Some(module), item)
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

/// Every file of [`FILES`] read from `dir`, each module of `shaders` built from them
/// validated. Returns the texts by file name, or the first error (nothing is replaced then).
pub fn load_dir(
    dir: &std::path::Path,
    shaders: &[ShaderDesc],
) -> Result<Vec<(&'static str, String)>, ShaderError> {
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
    for shader in shaders {
        shader.compose_with(lookup)?;
    }
    Ok(texts)
}
