//! The table of features. Each feature module declares one [`Feature`]: its name, the line
//! `--explain` prints for it, every render pipeline it may draw (as descriptors, formats left
//! to the passes that draw them), its compute pipelines and the planned passes it builds. The
//! shader-validation test and hot reload walk this table, so a shader a feature declares is
//! validated and reloaded without being listed anywhere else; the frame looks each planned
//! pass up here ([`builder`]), so a new pass needs no arm in the frame's code.

use crate::features::{Frame, MissingInput};
use crate::plan::Pass;
use crate::recipe::Recipe;
use crate::renderer::{ComputeDesc, PipelineDesc};
use crate::shaders::ShaderDesc;

/// Builds a planned pass's recipes from the frame.
#[derive(Debug, Clone, Copy)]
pub enum Build {
    /// One render or compute pass.
    One(for<'a> fn(&Frame<'a>) -> Result<Recipe<'a>, MissingInput>),
    /// Several (the distance maps: one per face and layer).
    Many(for<'a> fn(&Frame<'a>) -> Result<Vec<Recipe<'a>>, MissingInput>),
}

impl Build {
    /// The recipes, appended to `out`.
    pub fn run<'a>(self, f: &Frame<'a>, out: &mut Vec<Recipe<'a>>) -> Result<(), MissingInput> {
        match self {
            Build::One(b) => out.push(b(f)?),
            Build::Many(b) => out.extend(b(f)?),
        }
        Ok(())
    }
}

/// Where a pass draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DrawsInto {
    /// The scene colour where the plan blends fur into one ([`super::resolve`]), else the
    /// output: every pass before the resolve.
    Scene,
    /// The output itself (the resolve).
    Output,
}

/// A planned pass a feature builds.
#[derive(Debug, Clone, Copy)]
pub struct PassDesc {
    /// The pass, as the plan lists it.
    pub pass: Pass,
    /// Where it draws.
    pub into: DrawsInto,
    /// Whether it draws the scene's distance maps, skipped while they are fresh.
    pub maps: bool,
    /// Its recipes.
    pub build: Build,
}

impl PassDesc {
    /// A pass drawing into the scene colour.
    pub const fn new(pass: Pass, build: Build) -> PassDesc {
        PassDesc {
            pass,
            into: DrawsInto::Scene,
            maps: false,
            build,
        }
    }
}

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
    /// The planned passes it builds.
    pub passes: &'static [PassDesc],
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

/// The feature pass that builds `pass`, if one does (upscaling, mips and the overlay are
/// drawn on request, never planned).
pub fn builder(pass: Pass) -> Option<&'static PassDesc> {
    FEATURES
        .iter()
        .flat_map(|f| f.passes)
        .find(|p| p.pass == pass)
}

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_plannable_pass_has_exactly_one_builder() {
        let planned = [
            Pass::DistanceMaps,
            Pass::MinMax,
            Pass::Geometry,
            Pass::Light,
            Pass::Obliterate,
            Pass::Material,
            Pass::Forward,
            Pass::FurAccum,
            Pass::Composite,
            Pass::Resolve,
            Pass::Debug,
        ];
        for p in planned {
            let n = FEATURES
                .iter()
                .flat_map(|f| f.passes)
                .filter(|d| d.pass == p)
                .count();
            assert_eq!(n, 1, "{} is built by {n} features", p.name());
        }
        for p in [Pass::Upscale, Pass::Mips, Pass::Overlay] {
            assert!(builder(p).is_none(), "{} is drawn on request", p.name());
        }
        assert_eq!(
            builder(Pass::Resolve).map(|d| d.into),
            Some(DrawsInto::Output)
        );
        assert!(builder(Pass::MinMax).is_some_and(|d| d.maps));
    }
}
