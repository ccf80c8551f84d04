//! The light pass's guards (Kircher & Lawrance §2.2): counts and compiled code, not timers, so
//! a change that makes the pass do more work fails here on any machine.
//!
//! - Work: on a shadowless scene the GPU's own counters ([`pelt_preview::work`]) must be what
//!   the scissor rectangles and the depth test against each light's far side leave: the
//!   samples written equal, within a rounding band, the count this file makes on the CPU from
//!   the G-buffer's depth read back, and the fragment-shader invocations lie between those
//!   samples and the pixels of the 8×8 blocks the scissor rectangles touch (drivers shade 2×2
//!   quads or, as llvmpipe, 4×4 blocks; lavapipe measured within 4 % of its 4×4 bound here).
//!   Negative controls: the same recipes with the depth test disabled, and with the scissor
//!   opened to the whole L-buffer, each fail the check.
//! - Code: every light pipeline a view builds has what its lights do not need compiled out
//!   (the shadow lookup without a casting light; each kind's reach without the other's; the
//!   branch on the kind in every loop over lights without a directional light: forward, fur,
//!   strands, mirrors), read off the composed shader with the pipeline's override constants
//!   folded. Negative control: the constants forced back on reach that code again.

mod common;

use std::path::Path;

use glam::Vec3;
use pelt_preview::Pass;
use pelt_preview::features::forward;
use pelt_preview::features::lights;
use pelt_preview::frame::{self, Maps};
use pelt_preview::lighting;
use pelt_preview::procedural::grid_scene;
use pelt_preview::recipe::{Recipe, Step};
use pelt_preview::renderer::PipelineDesc;
use pelt_preview::scene::Light;
use pelt_preview::{Backend, Mode, Preview, Scene, SceneView};
use pelt_scene::shading::Emitter;

use common::reach::{holds, reached};

const COMMON: &str = "pelt::common";
const SHADOWS: &str = "pelt::shadows";

/// A grid of spheres under random point lights (none casting), at a test size.
fn point_scene() -> Scene {
    grid_scene(Path::new("builtin:sphere"), 16, 24, 7, 320, 180)
}

/// [`point_scene`] with a directional light between its point lights.
fn mixed_scene() -> Scene {
    let mut s = point_scene();
    let sun = Light {
        emitter: Emitter::Directional {
            direction: Vec3::new(-0.3, -1.0, -0.4).normalize(),
        },
        ..s.lights[0]
    };
    s.lights.insert(12, sun);
    s
}

/// Every pipeline the frame's recipes of `pass` use.
fn pipelines(p: &mut Preview, scene: &Scene, mode: Mode, pass: Pass) -> Vec<PipelineDesc> {
    let sv = p.prepare(scene, mode).expect("prepare");
    let out = used(&sv, Some(pass));
    assert!(!out.is_empty(), "{} draws", pass.name());
    out
}

/// Every pipeline `sv`'s frame uses (in `pass` alone, with one), each once.
fn used(sv: &SceneView, pass: Option<Pass>) -> Vec<PipelineDesc> {
    let f = sv.own_frame().expect("frame");
    let recipes = frame::recipes(&f, Maps::Always).expect("recipes");
    let mut out: Vec<PipelineDesc> = Vec::new();
    for k in recipes
        .iter()
        .filter(|r| pass.is_none_or(|p| r.pass == p))
        .flat_map(Recipe::keys)
    {
        if !out.contains(&k.desc) {
            out.push(k.desc.clone());
        }
    }
    out
}

/// Whether any pipeline of `descs` can run a directional light's code.
fn any_sun(descs: &[PipelineDesc]) -> bool {
    descs
        .iter()
        .any(|d| holds(&reached(d), COMMON, "sun_reach"))
}

#[test]
fn light_pipelines_compile_out_what_their_lights_do_not_need() {
    let mut p = common::preview();
    // Point lights, none casting: one pipeline, point reach only, no shadow lookup.
    let point = pipelines(&mut p, &point_scene(), Mode::Inferred, lights::PASS);
    assert_eq!(point.len(), 1, "one kind of light, one pipeline");
    let names = reached(&point[0]);
    eprintln!("point lights reach: {names:?}");
    assert!(holds(&names, COMMON, "point_reach"));
    assert!(
        !holds(&names, COMMON, "sun_reach"),
        "directional code compiled out"
    );
    assert!(
        !holds(&names, SHADOWS, "shadow_seen"),
        "shadow lookup compiled out"
    );
    // Negative controls: the same pipeline with its constants back at the shader's defaults.
    let shadowed = point[0].clone().with_constant(lighting::SHADOWS, None);
    assert!(holds(&reached(&shadowed), SHADOWS, "shadow_seen"));
    let either = point[0]
        .clone()
        .with_constant(lights::DIRECTIONAL, Some(1.0));
    let either = reached(&either);
    assert!(holds(&either, COMMON, "sun_reach") && !holds(&either, COMMON, "point_reach"));

    // A directional light among them: a pipeline per kind, each with its own reach only.
    let mixed = pipelines(&mut p, &mixed_scene(), Mode::Inferred, lights::PASS);
    assert_eq!(mixed.len(), 2, "a pipeline per kind");
    let kinds: Vec<(bool, bool)> = mixed
        .iter()
        .map(|d| {
            let n = reached(d);
            assert!(!holds(&n, SHADOWS, "shadow_seen"));
            (
                holds(&n, COMMON, "point_reach"),
                holds(&n, COMMON, "sun_reach"),
            )
        })
        .collect();
    assert_eq!(kinds, [(true, false), (false, true)]);

    // A casting light: the lookup is there (the check sees it where it is compiled in).
    let mut casting = point_scene();
    casting.lights[0].shadows = true;
    for d in pipelines(&mut p, &casting, Mode::Inferred, lights::PASS) {
        assert!(holds(&reached(&d), SHADOWS, "shadow_seen"));
    }

    // The forward pass loops over every light: its branch on the kind and the spot lights'
    // cones only with a sun or a spot light (point lights alone reach through bare_reach).
    let fwd = pipelines(&mut p, &point_scene(), Mode::Forward, forward::PASS);
    for d in &fwd {
        let n = reached(d);
        assert!(!holds(&n, COMMON, "sun_reach") && !holds(&n, SHADOWS, "shadow_seen"));
        assert!(holds(&n, COMMON, "bare_reach") && !holds(&n, COMMON, "point_reach"));
        let suns = reached(&d.clone().with_constant(lights::SUNS, None));
        assert!(
            holds(&suns, COMMON, "sun_reach") && holds(&suns, COMMON, "point_reach"),
            "negative control"
        );
    }
    for d in pipelines(&mut p, &mixed_scene(), Mode::Forward, forward::PASS) {
        assert!(holds(&reached(&d), COMMON, "sun_reach"));
    }
}

#[test]
fn every_pipeline_of_a_view_without_a_sun_leaves_directional_code_out() {
    // Fur lit forward and as strands, mirrors and glass with their distance maps: every loop
    // over lights leaves light_reach's branch on the kind out without a directional light,
    // and keeps it with one (the check sees the code where it is compiled in).
    let mut p = common::preview();
    let fur = [common::furry_sphere()];
    let mirrors = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/scenes/mirrors.json");
    let mirrors = Scene::load(&mirrors).expect("mirrors.json");
    let furry = common::scene(4, true, pelt_preview::scene::FurBlend::Stipple);
    for mode in [Mode::Inferred, Mode::Forward, Mode::Strands] {
        for (name, mut scene) in [("fur", furry.clone()), ("mirrors", mirrors.clone())] {
            if mode == Mode::Strands && name == "mirrors" {
                continue;
            }
            let prepare = |p: &mut Preview, s: &Scene| match name {
                "fur" => p.prepare_loaded(s, &fur, &[0], mode),
                _ => p.prepare(s, mode),
            };
            let sv = prepare(&mut p, &scene).expect("prepare");
            let descs = used(&sv, None);
            assert!(
                !any_sun(&descs),
                "{name} {mode:?}: no sun, no directional code"
            );
            let sun = Light {
                emitter: Emitter::Directional {
                    direction: Vec3::new(0.2, -1.0, -0.3).normalize(),
                },
                ..scene.lights[0]
            };
            scene.lights.push(sun);
            let sv = prepare(&mut p, &scene).expect("prepare");
            assert!(
                any_sun(&used(&sv, None)),
                "{name} {mode:?}: a sun's code is there"
            );
        }
    }
}

/// The light pass's counted work, and what the CPU expects of it.
struct LightWork {
    /// Samples written, counted by the GPU.
    samples: u64,
    /// Fragment-shader invocations, counted by the GPU (where it can).
    fragments: Option<u64>,
    /// Samples the depth test should pass: certainly, and at most (pixels within a rounding
    /// step of a light's far depth may go either way).
    expected: (u64, u64),
    /// Non-empty pixels inside the scissor rectangles (what passes with no depth test).
    unrejected: u64,
    /// 64 × the 8×8 blocks the scissor rectangles touch: more than a driver shading whole
    /// 2×2 quads or 4×4 blocks (llvmpipe) invokes.
    blocks: u64,
}

impl LightWork {
    /// Whether the counts are what the scissor and depth rejection should leave.
    fn check(&self) -> Result<(), String> {
        let (lo, hi) = self.expected;
        if self.samples < lo || self.samples > hi {
            return Err(format!(
                "{} samples written, the depth test should leave {lo}..={hi}",
                self.samples
            ));
        }
        match self.fragments {
            Some(f) if f < self.samples || f > self.blocks => Err(format!(
                "{f} fragment invocations, outside {}..={} (samples written .. blocks in the scissor rectangles)",
                self.samples, self.blocks
            )),
            _ => Ok(()),
        }
    }
}

/// The light pass of `sv` counted after `change` of its recipe, with the CPU's expectations
/// (from the G-buffer depth of the same frame) for the unchanged pass.
fn light_work(p: &Preview, sv: &SceneView, change: impl Fn(&mut [Step<'_>])) -> LightWork {
    let r = &p.renderer;
    let f = sv.own_frame().expect("frame");
    let mut recipes = frame::recipes(&f, Maps::Always).expect("recipes");
    let at = recipes
        .iter()
        .position(|x| x.pass == lights::PASS)
        .expect("a light pass");
    change(recipes[at].steps_mut());
    r.prepare(recipes.iter().flat_map(Recipe::keys))
        .expect("pipelines");
    let counted = pelt_preview::work::count(r, &recipes).expect("counted")[at].expect("renders");
    let g = sv.targets.gbuffer.as_ref().expect("a G-buffer");
    let size = f.plan.lbuffer.expect("an L-buffer");
    let depth = common::read_depth(r, &g.depth.texture, size);
    let (expected, unrejected, blocks) = expected_work(f.plan, &depth, size);
    LightWork {
        samples: counted.samples.expect("the device counts samples"),
        fragments: counted.fragments,
        expected,
        unrejected,
        blocks,
    }
}

/// What the light pass should leave of `plan`'s lights over a G-buffer of `depth` (row-major,
/// `size`): the depth-tested samples (certain, at most), the untested ones, and 64 × the 8×8
/// blocks the scissor rectangles touch. Each point light's triangle lies at light.wgsl's
/// depth of the far side of its reach; a directional light's on the far plane.
fn expected_work(
    plan: &pelt_preview::Plan,
    depth: &[f32],
    size: (u32, u32),
) -> ((u64, u64), u64, u64) {
    let v = &plan.view;
    let step = (v.far - v.near) / 65534.0;
    let (mut lo, mut hi, mut unrejected, mut blocks) = (0, 0, 0, 0);
    for l in &plan.lights {
        let far = match l.emitter.bounds() {
            Some((position, radius)) => {
                let z = v.view.transform_point3(position).z - (1.001 * radius + 4.0 * step);
                let c = v.proj * glam::Vec4::new(0.0, 0.0, z, 1.0);
                if c.w > 0.0 {
                    (c.z / c.w).clamp(0.0, 1.0)
                } else {
                    0.0
                }
            }
            None => 1.0,
        };
        let [x0, y0, x1, y1] = l.rect;
        blocks += 64 * u64::from((x1.div_ceil(8) - x0 / 8) * (y1.div_ceil(8) - y0 / 8));
        for y in y0..y1 {
            for x in x0..x1 {
                let d = depth[(y * size.0 + x) as usize];
                if d >= 1.0 {
                    continue; // empty: discarded
                }
                unrejected += 1;
                let band = 1e-6 * far.max(1e-3);
                lo += u64::from(far >= d + band);
                hi += u64::from(far >= d - band);
            }
        }
    }
    ((lo, hi), unrejected, blocks)
}

/// The device for the count guard: Vulkan (whose occlusion queries count samples), or a skip
/// where there is none, a failure when `PELT_REQUIRE_COUNTERS` is set.
fn counting_preview() -> Option<Preview> {
    match Preview::new(Backend::Vulkan) {
        Ok(p) if p.renderer.gpu.samples => Some(p),
        other => {
            let why = other.map_or_else(|e| e.to_string(), |_| "no sample counts".into());
            assert!(
                std::env::var_os("PELT_REQUIRE_COUNTERS").is_none(),
                "the light pass's count guard needs a Vulkan adapter: {why}"
            );
            eprintln!("skipped: the light pass's count guard needs a Vulkan adapter ({why})");
            None
        }
    }
}

#[test]
fn the_light_pass_shades_only_what_its_scissor_and_depth_test_leave() {
    let Some(mut p) = counting_preview() else {
        return;
    };
    for (name, scene) in [
        ("point lights", point_scene()),
        ("with a sun", mixed_scene()),
    ] {
        let sv = p.prepare(&scene, Mode::Inferred).expect("prepare");
        let w = light_work(&p, &sv, |_| {});
        eprintln!(
            "{name}: {} samples written (expected {:?}; {} without the depth test), {:?} fragment invocations (at most {})",
            w.samples, w.expected, w.unrejected, w.fragments, w.blocks
        );
        w.check().unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            w.expected.1 + w.expected.1 / 10 < w.unrejected,
            "{name}: the scene must leave the depth test something to reject"
        );

        // Negative control: no depth test, every non-empty pixel in the rectangles shades.
        let open = light_work(&p, &sv, |steps| {
            for s in steps {
                if let Step::Pipeline(k) = s {
                    k.desc.spec.depth = Some((false, wgpu::CompareFunction::Always));
                }
            }
        });
        assert_eq!(
            open.samples, open.unrejected,
            "{name}: untested, every pixel"
        );
        if name == "point lights" {
            assert!(
                open.check().is_err(),
                "the check sees a lost depth rejection"
            );
        }

        // Negative control: the scissor opened to the whole L-buffer.
        let (wd, ht) = sv.plan.lbuffer.expect("an L-buffer");
        let whole = light_work(&p, &sv, |steps| {
            for s in steps {
                if let Step::Scissor(rect) = s {
                    *rect = [0, 0, wd, ht];
                }
            }
        });
        if whole.fragments.is_some() {
            assert!(
                whole.check().is_err(),
                "{name}: the check sees a lost scissor"
            );
        }
    }
}

#[test]
fn the_light_pass_switches_pipeline_where_the_kind_of_light_changes() {
    // In the scene's order (the L-buffer's sums stay as they were): point lights, the sun,
    // point lights again.
    let mut p = common::preview();
    let sv = p.prepare(&mixed_scene(), Mode::Inferred).expect("prepare");
    let f = sv.own_frame().expect("frame");
    let recipes = frame::recipes(&f, Maps::Always).expect("recipes");
    let light = recipes
        .iter()
        .find(|r| r.pass == lights::PASS)
        .expect("light pass");
    let mut runs: Vec<Option<f64>> = Vec::new();
    for l in &f.plan.lights {
        let kind = matches!(l.emitter, Emitter::Directional { .. }).then_some(1.0);
        if runs.last() != Some(&kind) {
            runs.push(kind);
        }
    }
    assert_eq!(
        runs,
        [None, Some(1.0), None],
        "the sun lies among the point lights"
    );
    let switches: Vec<Option<f64>> = light
        .keys()
        .map(|k| k.desc.constant(lights::DIRECTIONAL))
        .collect();
    assert_eq!(switches, runs);
    assert_eq!(light.counts().pipelines, 3);
    assert_eq!(light.counts().draws as usize, f.plan.lights.len());
}
