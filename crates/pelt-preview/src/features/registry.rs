//! The table of features. Each feature module declares one [`Feature`] ([`crate::feature`]):
//! its name, every render pipeline it may draw (as descriptors, formats left to the passes
//! that draw them), its compute pipelines, the planned passes it builds (each with when a
//! plan wants it, what it follows and its `--explain` line), its draws in the shading pass,
//! the targets it owns and the quality knobs it reads (with [`CORE_KNOBS`], the ones no one
//! feature owns). The shader-validation test and hot reload walk this table, so a shader a
//! feature declares is validated and reloaded without being listed anywhere else; a plan's
//! passes and their order come from it ([`passes`]), so a new pass needs no arm in the
//! frame's code, the plan or `--explain`.

use crate::feature::planned;
pub use crate::feature::{
    Build, Cached, DrawDesc, DrawsInto, Feature, KnobDesc, PassDesc, Reference, TargetsDesc,
};
use crate::pass::Pass;
use crate::plan::Plan;
use crate::renderer::PipelineDesc;
use crate::shaders::ShaderDesc;
use pelt_scene::knobs::spec;

/// Every feature, in the order their draws run within a phase of the shading pass and their
/// passes run where no `after` orders them.
pub const FEATURES: &[Feature] = &[
    super::skin::FEATURE,
    super::reflect::FEATURE,
    super::shadows::FEATURE,
    super::opacity::FEATURE,
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
pub const CORE_KNOBS: &[KnobDesc] = &[KnobDesc::of(&spec::MODE), KnobDesc::of(&spec::SIZE)];

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
    knobs()
        .into_iter()
        .map(|(_, k)| k)
        .find(|k| k.name() == name)
}

/// The registered pass `pass`, if a feature builds it (upscaling, mips and the overlay are
/// drawn on request, never planned).
pub fn builder(pass: Pass) -> Option<&'static PassDesc> {
    FEATURES
        .iter()
        .flat_map(|f| f.passes)
        .find(|p| p.pass == pass)
}

/// The passes a frame of `plan` runs, in order.
pub fn passes(plan: &Plan) -> Vec<Pass> {
    planned(FEATURES, plan).iter().map(|p| p.pass).collect()
}

/// `plan` in words (`--explain`): its facts, then each pass it runs with what that pass
/// says of it.
pub fn explain(plan: &Plan) -> String {
    let lines: Vec<(&str, String)> = planned(FEATURES, plan)
        .iter()
        .map(|p| (p.pass.name(), (p.explain)(plan)))
        .collect();
    plan.explain(&lines)
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
    fn every_pass_is_registered_once_and_follows_registered_passes() {
        let all: Vec<&PassDesc> = FEATURES.iter().flat_map(|f| f.passes).collect();
        assert!(all.len() >= 12, "{} passes", all.len());
        for p in &all {
            let n = all.iter().filter(|d| d.pass == p.pass).count();
            assert_eq!(n, 1, "{} is built by {n} features", p.pass);
            for a in p.after {
                assert!(
                    builder(*a).is_some(),
                    "{} follows {a}, which no feature builds",
                    p.pass
                );
            }
        }
        for p in [
            super::super::upscale::PASS,
            super::super::mips::PASS,
            super::super::overlay::PASS,
        ] {
            assert!(builder(p).is_none(), "{p} is drawn on request");
        }
        assert_eq!(
            builder(super::super::resolve::PASS).map(|d| d.into),
            Some(DrawsInto::Output)
        );
        assert!(builder(super::super::reflect::MIN_MAX).is_some_and(|d| d.cached.is_some()));
        assert!(builder(super::super::geometry::PASS).is_some_and(|d| d.cached.is_none()));
        assert!(
            FEATURES.len() <= 64,
            "a view's own targets are a 64-bit set"
        );
    }

    /// Each `after` of `passes` that `order` breaks, as (pass, the pass it should follow).
    fn broken(passes: &[PassDesc], order: &[Pass]) -> Vec<(Pass, Pass)> {
        let at = |p: Pass| order.iter().position(|&x| x == p);
        passes
            .iter()
            .flat_map(|p| p.after.iter().map(move |a| (p.pass, *a)))
            .filter(|&(p, a)| at(a) > at(p))
            .collect()
    }

    /// The order `planned` gives `passes`, all wanted.
    fn order_all(passes: &'static [PassDesc]) -> Vec<Pass> {
        let one = [Feature {
            passes,
            ..Feature::named("all")
        }];
        planned(&one, &test_plan()).iter().map(|p| p.pass).collect()
    }

    /// With every pass wanted, the order keeps every `after`: no circle among them.
    #[test]
    fn the_after_lists_order_every_pass() {
        let all: Vec<PassDesc> = FEATURES
            .iter()
            .flat_map(|f| f.passes)
            .map(|p| PassDesc {
                wanted: |_| true,
                ..*p
            })
            .collect();
        let all: &'static [PassDesc] = Box::leak(all.into_boxed_slice());
        let order = order_all(all);
        assert_eq!(order.len(), all.len());
        assert_eq!(broken(all, &order), vec![], "{order:?}");
        // Negative control: two passes each after the other cannot both be kept.
        const A: &[Pass] = &[Pass::new("a")];
        const B: &[Pass] = &[Pass::new("b")];
        let circle: &'static [PassDesc] = Box::leak(Box::new([
            PassDesc {
                pass: Pass::new("a"),
                after: B,
                ..all[0]
            },
            PassDesc {
                pass: Pass::new("b"),
                after: A,
                ..all[0]
            },
        ]));
        let order = order_all(circle);
        assert_eq!(order, [Pass::new("a"), Pass::new("b")], "registry order");
        assert_eq!(broken(circle, &order), [(Pass::new("a"), Pass::new("b"))]);
    }

    /// A plan of one cube with one light.
    fn test_plan() -> Plan {
        let s = pelt_scene::procedural::grid_scene(
            std::path::Path::new("builtin:cube"),
            1,
            1,
            1,
            64,
            48,
        );
        let meshes = vec![pelt_scene::asset::builtin("cube").expect("cube")];
        Plan::new(&s, &meshes, &[0], crate::Mode::Inferred).expect("plan")
    }

    #[test]
    fn every_knob_is_registered_once() {
        let all = knobs();
        assert!(all.len() >= 19, "{} knobs", all.len());
        for (f, k) in &all {
            let n = all.iter().filter(|(_, x)| x.name() == k.name()).count();
            assert_eq!(n, 1, "{} (read by {f}) is registered {n} times", k.name());
        }
        assert_eq!(
            knob("shells").map(KnobDesc::reference),
            Some(Reference::Strands)
        );
        assert!(knob("texture-size").is_some_and(KnobDesc::rebakes));
        assert!(knob("no-such-knob").is_none());
    }

    #[test]
    fn every_knob_spec_is_read_by_one_feature() {
        for s in spec::ALL {
            assert!(
                knob(s.name).is_some_and(|k| k.spec == *s),
                "no feature reads {}",
                s.name
            );
        }
        assert_eq!(knobs().len(), spec::ALL.len(), "a knob read twice");
    }
}
