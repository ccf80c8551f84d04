//! The WGSL sources of the preview renderer. Every file lives in the repository's top-level
//! `shaders/` folder and is compiled into the binary (and, in `pelt view --shaders DIR`,
//! reloaded from disk). A module is `common.wgsl` (shared structs and functions, no
//! bindings), then for the fur passes `fur_common.wgsl` and one of the two fur lighting
//! chunks (from the L-buffer, or forward Kajiya-Kay), for screen-space passes
//! `fullscreen.wgsl` (the one full-screen triangle), then the pass's own file. See
//! `shaders/README.md`.

/// The shared prelude.
pub const COMMON: &str = include_str!("../../../shaders/common.wgsl");

/// Every file in `shaders/`, by name.
pub const FILES: [(&str, &str); 27] = [
    ("common.wgsl", COMMON),
    (
        "fullscreen.wgsl",
        include_str!("../../../shaders/fullscreen.wgsl"),
    ),
    (
        "upscale.wgsl",
        include_str!("../../../shaders/upscale.wgsl"),
    ),
    (
        "overlay.wgsl",
        include_str!("../../../shaders/overlay.wgsl"),
    ),
    (
        "downsample.wgsl",
        include_str!("../../../shaders/downsample.wgsl"),
    ),
    (
        "tangent_frames.wgsl",
        include_str!("../../../shaders/tangent_frames.wgsl"),
    ),
    (
        "gbuffer.wgsl",
        include_str!("../../../shaders/gbuffer.wgsl"),
    ),
    ("light.wgsl", include_str!("../../../shaders/light.wgsl")),
    (
        "material.wgsl",
        include_str!("../../../shaders/material.wgsl"),
    ),
    (
        "forward.wgsl",
        include_str!("../../../shaders/forward.wgsl"),
    ),
    (
        "fur_common.wgsl",
        include_str!("../../../shaders/fur_common.wgsl"),
    ),
    (
        "fur_light_inferred.wgsl",
        include_str!("../../../shaders/fur_light_inferred.wgsl"),
    ),
    (
        "fur_light_forward.wgsl",
        include_str!("../../../shaders/fur_light_forward.wgsl"),
    ),
    (
        "fur_gbuffer.wgsl",
        include_str!("../../../shaders/fur_gbuffer.wgsl"),
    ),
    ("shells.wgsl", include_str!("../../../shaders/shells.wgsl")),
    ("fins.wgsl", include_str!("../../../shaders/fins.wgsl")),
    (
        "obliterate.wgsl",
        include_str!("../../../shaders/obliterate.wgsl"),
    ),
    (
        "composite.wgsl",
        include_str!("../../../shaders/composite.wgsl"),
    ),
    ("sky.wgsl", include_str!("../../../shaders/sky.wgsl")),
    (
        "distance_map.wgsl",
        include_str!("../../../shaders/distance_map.wgsl"),
    ),
    ("minmax.wgsl", include_str!("../../../shaders/minmax.wgsl")),
    (
        "strands.wgsl",
        include_str!("../../../shaders/strands.wgsl"),
    ),
    (
        "reflect.wgsl",
        include_str!("../../../shaders/reflect.wgsl"),
    ),
    (
        "fin_records.wgsl",
        include_str!("../../../shaders/fin_records.wgsl"),
    ),
    ("skin.wgsl", include_str!("../../../shaders/skin.wgsl")),
    (
        "skin_scatter.wgsl",
        include_str!("../../../shaders/skin_scatter.wgsl"),
    ),
    (
        "fin_rebuild.wgsl",
        include_str!("../../../shaders/fin_rebuild.wgsl"),
    ),
];

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

/// A shader module (and, for files with several, which entry points a pipeline uses).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Shader {
    /// Geometry pass: normals and DSF buffer (Kircher & Lawrance §2.1).
    GBuffer,
    /// Light pass: scissored point lights into the L-buffer (§2.2).
    Light,
    /// Material pass with DSF (§2.3, §3, §4).
    Material,
    /// Forward reference: per-object light loop.
    Forward,
    /// Fur geometry pass 1: the base mesh with grain normals (Revie §2.4.2).
    FurBase,
    /// Fur geometry pass 2: the stippled outer shell with rim normals.
    FurOuter,
    /// Stipple obliteration into the composition copy (§2.4.4).
    Obliterate,
    /// Concentric shells (instance 0: the base mesh).
    Shells(Lighting, Coverage),
    /// Silhouette fins.
    Fins(Lighting),
    /// Weighted blended OIT resolve.
    Composite,
    /// Procedural sky.
    SkyProcedural,
    /// Cube-map sky.
    SkyCube,
    /// A lower-resolution frame scaled up to the window (`pelt view`'s frame budget).
    Upscale,
    /// One mip level of a layered target from the level above.
    Downsample,
    /// `pelt view`'s text overlay.
    Overlay,
    /// Compute: comb directions from tangent frames (the GPU half of `pelt_geom::frame`).
    TangentFrames,
    /// One face of one layer of a distance map (distance_map.wgsl).
    DistanceMap,
    /// Compute: each distance-map layer's distance range (minmax.wgsl).
    MinMax,
    /// Mirrors and glass through their distance maps (reflect.wgsl).
    Reflect,
    /// Explicit strands, Kajiya-Kay per light (strands.wgsl): the converged fur reference.
    Strands,
    /// Compute: fin records decoded through the index list (the GPU half of
    /// `pelt_io::topology::fin_geometry`).
    FinRecords,
    /// Compute: linear blend skinning of positions, normals and tangents (skin.wgsl).
    Skin,
    /// Compute: skinned vertices into the vertex buffers (skin_scatter.wgsl).
    SkinScatter,
    /// Compute: a skinned mesh's fin instances from its vertices (fin_rebuild.wgsl).
    FinRebuild,
}

impl Shader {
    /// Every pipeline shader.
    pub const ALL: [Shader; 26] = [
        Shader::GBuffer,
        Shader::Light,
        Shader::Material,
        Shader::Forward,
        Shader::FurBase,
        Shader::FurOuter,
        Shader::Obliterate,
        Shader::Shells(Lighting::Inferred, Coverage::Medium),
        Shader::Shells(Lighting::Forward, Coverage::Medium),
        Shader::Fins(Lighting::Inferred),
        Shader::Fins(Lighting::Forward),
        Shader::Composite,
        Shader::SkyProcedural,
        Shader::SkyCube,
        Shader::Upscale,
        Shader::Downsample,
        Shader::Overlay,
        Shader::TangentFrames,
        Shader::DistanceMap,
        Shader::MinMax,
        Shader::Reflect,
        Shader::Strands,
        Shader::FinRecords,
        Shader::Skin,
        Shader::SkinScatter,
        Shader::FinRebuild,
    ];

    /// The pass's own file under `shaders/`.
    pub fn file(self) -> &'static str {
        match self {
            Shader::GBuffer => "gbuffer.wgsl",
            Shader::Light => "light.wgsl",
            Shader::Material => "material.wgsl",
            Shader::Forward => "forward.wgsl",
            Shader::FurBase | Shader::FurOuter => "fur_gbuffer.wgsl",
            Shader::Obliterate => "obliterate.wgsl",
            Shader::Shells(..) => "shells.wgsl",
            Shader::Fins(_) => "fins.wgsl",
            Shader::Composite => "composite.wgsl",
            Shader::SkyProcedural | Shader::SkyCube => "sky.wgsl",
            Shader::Upscale => "upscale.wgsl",
            Shader::Downsample => "downsample.wgsl",
            Shader::Overlay => "overlay.wgsl",
            Shader::TangentFrames => "tangent_frames.wgsl",
            Shader::DistanceMap => "distance_map.wgsl",
            Shader::MinMax => "minmax.wgsl",
            Shader::Reflect => "reflect.wgsl",
            Shader::Strands => "strands.wgsl",
            Shader::FinRecords => "fin_records.wgsl",
            Shader::Skin => "skin.wgsl",
            Shader::SkinScatter => "skin_scatter.wgsl",
            Shader::FinRebuild => "fin_rebuild.wgsl",
        }
    }

    /// The files the module is made of, in order.
    pub fn parts(self) -> Vec<&'static str> {
        let mut p = vec!["common.wgsl"];
        match self {
            Shader::FurBase | Shader::FurOuter | Shader::TangentFrames | Shader::FinRebuild => {
                p.push("fur_common.wgsl");
            }
            Shader::Strands => {
                p.push("fur_common.wgsl");
                p.push("fur_light_forward.wgsl");
            }
            Shader::Shells(l, _) | Shader::Fins(l) => {
                p.push("fur_common.wgsl");
                p.push(match l {
                    Lighting::Inferred => "fur_light_inferred.wgsl",
                    Lighting::Forward => "fur_light_forward.wgsl",
                });
            }
            _ => {}
        }
        if self.fullscreen() {
            p.push("fullscreen.wgsl");
        }
        p.push(self.file());
        p
    }

    /// A name for the module (files joined), for labels and errors.
    pub fn module_name(self) -> String {
        self.parts()[1..].join("+")
    }

    /// The complete module source.
    pub fn source(self) -> String {
        self.source_with(file)
    }

    /// The module source with each file's text from `text` (hot reload).
    pub fn source_with<'t>(self, text: impl Fn(&str) -> &'t str) -> String {
        self.parts()
            .into_iter()
            .map(text)
            .collect::<Vec<_>>()
            .join("\n")
    }

    /// Whether the module is a compute shader (its one entry point is `cs_main`).
    pub fn is_compute(self) -> bool {
        matches!(
            self,
            Shader::TangentFrames
                | Shader::MinMax
                | Shader::FinRecords
                | Shader::Skin
                | Shader::SkinScatter
                | Shader::FinRebuild
        )
    }

    /// Whether the pass draws fullscreen.wgsl's triangle.
    pub fn fullscreen(self) -> bool {
        matches!(
            self,
            Shader::Light
                | Shader::Obliterate
                | Shader::Composite
                | Shader::SkyProcedural
                | Shader::SkyCube
                | Shader::Upscale
                | Shader::Downsample
                | Shader::Overlay
        )
    }

    /// The vertex and fragment entry points (one pair per module; the fur shaders' blend
    /// is an `override` constant, see features/fur.rs).
    pub fn entry_points(self) -> (&'static str, &'static str) {
        if self.is_compute() {
            return ("cs_main", "cs_main");
        }
        if self.fullscreen() {
            return (
                "vs_fullscreen",
                match self {
                    Shader::SkyProcedural => "fs_procedural",
                    Shader::SkyCube => "fs_cube",
                    _ => "fs_main",
                },
            );
        }
        match self {
            Shader::FurBase => ("vs_base", "fs_base"),
            Shader::FurOuter => ("vs_outer", "fs_outer"),
            _ => ("vs_main", "fs_main"),
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
    for shader in Shader::ALL {
        validate(&shader.module_name(), &shader.source_with(lookup))?;
    }
    Ok(texts)
}
