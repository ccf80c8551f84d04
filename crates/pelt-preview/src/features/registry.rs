//! The table of features. Each feature module declares one [`Feature`] ([`crate::feature`]):
//! its name, the line `--explain` prints for it, every render pipeline it may draw (as
//! descriptors, formats left to the passes that draw them), its compute pipelines, the
//! planned passes it builds, its draws in the shading pass, the targets it owns and the
//! quality knobs it reads (with [`CORE_KNOBS`], the ones no one feature owns). The
//! shader-validation test and hot reload walk this table, so a shader a feature declares is
//! validated and reloaded without being listed anywhere else; the frame looks each planned
//! pass up here ([`builder`]), so a new pass needs no arm in the frame's code.

pub use crate::feature::{
    Build, Cached, DrawDesc, DrawsInto, Feature, KnobDesc, PassDesc, Reference, TargetsDesc,
};
use crate::plan::Pass;
use crate::renderer::PipelineDesc;
use crate::shaders::ShaderDesc;

/// Every feature, in the order their draws run within a phase of the shading pass.
pub const FEATURES: &[Feature] = &[
    super::skin::FEATURE,
    super::shadows::FEATURE,
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

/// The knobs the renderer as a whole reads (no one feature owns them).
pub const CORE_KNOBS: &[KnobDesc] = &[
    KnobDesc::new(
        "mode",
        "inferred, deferred or forward",
        "inferred",
        Reference::Strands,
    ),
    KnobDesc::new(
        "size",
        "WxH, each 8 to 4096",
        "the scene's",
        Reference::Deferred,
    ),
];

/// Every registered knob with the feature that reads it (`core` for [`CORE_KNOBS`]).
pub fn knobs() -> Vec<(&'static str, &'static KnobDesc)> {
    let core = CORE_KNOBS.iter().map(|k| ("core", k));
    let features = FEATURES
        .iter()
        .flat_map(|f| f.knobs.iter().map(move |k| (f.name, k)));
    core.chain(features).collect()
}

/// The registered knob called `name`.
pub fn knob(name: &str) -> Option<&'static KnobDesc> {
    knobs().into_iter().map(|(_, k)| k).find(|k| k.name == name)
}

/// The feature pass that builds `pass`, if one does (upscaling, mips and the overlay are
/// drawn on request, never planned).
pub fn builder(pass: Pass) -> Option<&'static PassDesc> {
    FEATURES
        .iter()
        .flat_map(|f| f.passes)
        .find(|p| p.pass == pass)
}

/// The own targets of every feature that has some, in registry order (a view's
/// [`crate::targets::TargetSpec`] names them by position).
pub fn targets() -> Vec<TargetsDesc> {
    FEATURES.iter().filter_map(|f| f.targets).collect()
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
            Pass::Shadows,
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
        assert!(builder(Pass::MinMax).is_some_and(|d| d.cached.is_some()));
        assert!(builder(Pass::Geometry).is_some_and(|d| d.cached.is_none()));
        assert!(
            FEATURES.len() <= 64,
            "a view's own targets are a 64-bit set"
        );
    }

    #[test]
    fn every_knob_is_registered_once() {
        let all = knobs();
        assert!(all.len() >= 19, "{} knobs", all.len());
        for (f, k) in &all {
            let n = all.iter().filter(|(_, x)| x.name == k.name).count();
            assert_eq!(n, 1, "{} (read by {f}) is registered {n} times", k.name);
        }
        assert_eq!(
            knob("shells").map(|k| k.reference),
            Some(Reference::Strands)
        );
        assert!(knob("texture-size").is_some_and(|k| k.rebakes));
        assert!(knob("no-such-knob").is_none());
    }
}
