//! The WGSL sources of the preview renderer. Every file lives in the repository's top-level
//! `shaders/` folder and is compiled into the binary; each pass's module is `common.wgsl`
//! (shared structs and functions, no bindings) followed by the pass's own file.

/// The shared prelude.
pub const COMMON: &str = include_str!("../../../shaders/common.wgsl");

/// A pass's shader file.
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
}

impl Shader {
    /// Every pass shader.
    pub const ALL: [Shader; 4] = [
        Shader::GBuffer,
        Shader::Light,
        Shader::Material,
        Shader::Forward,
    ];

    /// The file name under `shaders/`.
    pub fn file(self) -> &'static str {
        match self {
            Shader::GBuffer => "gbuffer.wgsl",
            Shader::Light => "light.wgsl",
            Shader::Material => "material.wgsl",
            Shader::Forward => "forward.wgsl",
        }
    }

    fn body(self) -> &'static str {
        match self {
            Shader::GBuffer => include_str!("../../../shaders/gbuffer.wgsl"),
            Shader::Light => include_str!("../../../shaders/light.wgsl"),
            Shader::Material => include_str!("../../../shaders/material.wgsl"),
            Shader::Forward => include_str!("../../../shaders/forward.wgsl"),
        }
    }

    /// The complete module: the prelude, then the pass's file.
    pub fn source(self) -> String {
        format!("{COMMON}\n{}", self.body())
    }
}
