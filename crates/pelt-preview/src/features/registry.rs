//! The table of features. Each feature module declares one [`Feature`]: its name, the line
//! `--explain` prints for it, every render pipeline it may draw (as descriptors, formats left
//! to the passes that draw them) and its compute pipelines. The shader-validation test and hot
//! reload walk this table, so a shader a feature declares is validated and reloaded without
//! being listed anywhere else.

use crate::renderer::{ComputeDesc, PipelineDesc};
use crate::shaders::ShaderDesc;

/// One feature of the renderer, as registered.
#[derive(Debug, Clone, Copy)]
pub struct Feature {
    /// Its name (the module's).
    pub name: &'static str,
    /// What it draws, in one line (`--explain`).
    pub explain: &'static str,
    /// Every render pipeline it may draw, each variant once.
    pub pipelines: fn() -> Vec<PipelineDesc>,
    /// Its compute pipelines.
    pub compute: &'static [ComputeDesc],
}

/// Every feature, in the order their passes run within a phase.
pub const FEATURES: &[Feature] = &[
    super::skin::FEATURE,
    super::reflect::FEATURE,
    super::geometry::FEATURE,
    super::alpha::FEATURE,
    super::fur::FEATURE,
    super::lights::FEATURE,
    super::material::FEATURE,
    super::forward::FEATURE,
    super::sky::FEATURE,
    super::wboit::FEATURE,
    super::strands::FEATURE,
    super::resolve::FEATURE,
    super::upscale::FEATURE,
    super::mips::FEATURE,
    super::overlay::FEATURE,
    super::debug::FEATURE,
];

/// Every render pipeline of every feature.
pub fn pipelines() -> Vec<PipelineDesc> {
    FEATURES.iter().flat_map(|f| (f.pipelines)()).collect()
}

/// Every distinct shader of every feature (render and compute), in registry order.
pub fn shaders() -> Vec<ShaderDesc> {
    let mut out: Vec<ShaderDesc> = Vec::new();
    let compute = FEATURES
        .iter()
        .flat_map(|f| f.compute.iter().map(|c| c.shader));
    for s in pipelines().into_iter().map(|p| p.shader).chain(compute) {
        if !out.contains(&s) {
            out.push(s);
        }
    }
    out
}
