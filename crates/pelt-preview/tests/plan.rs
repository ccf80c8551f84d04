//! Which passes a plan runs and in what order, as the registry decides them from the plan's
//! facts (each feature's `wanted` and `after`), and what `--explain` says of each.

mod common;

use std::path::Path;

use glam::Vec3;
use pelt_preview::asset::{MeshData, builtin};
use pelt_preview::plan::DebugView;
use pelt_preview::procedural::grid_scene;
use pelt_preview::scene::{FurBlend, Scene};
use pelt_preview::{Mode, Plan, explain, passes};
use pelt_scene::shading::Emitter;

fn plan_of(scene: &Scene, meshes: &[MeshData], mode: Mode) -> Plan {
    Plan::new(scene, meshes, &vec![0; scene.objects.len()], mode).expect("plan")
}

fn cubes(scene: &Scene, mode: Mode) -> Plan {
    plan_of(scene, &[builtin("cube").expect("cube")], mode)
}

/// The pass names of `plan`, in order.
fn names(plan: &Plan) -> Vec<&'static str> {
    passes(plan).iter().map(|p| p.name()).collect()
}

#[test]
fn passes_follow_the_mode_and_the_scene() {
    let mut s = grid_scene(Path::new("builtin:cube"), 9, 5, 1, 160, 90);
    s.lbuffer_scale = 0.5;
    assert_eq!(
        names(&cubes(&s, Mode::Inferred)),
        ["geometry", "light", "material"]
    );
    assert_eq!(names(&cubes(&s, Mode::Forward)), ["forward"]);
    let f = explain(&cubes(&s, Mode::Forward));
    assert!(f.contains("9 objects × 5 lights"), "{f}");
    // No lights: the material pass alone.
    s.lights.clear();
    let n = cubes(&s, Mode::Inferred);
    assert_eq!(names(&n), ["material"]);
    assert!(explain(&n).contains("ambient only"), "{}", explain(&n));
}

#[test]
fn a_debug_mode_plans_one_unlit_pass() {
    let s = grid_scene(Path::new("builtin:cube"), 3, 2, 1, 64, 48);
    for view in [DebugView::Groups, DebugView::Comb] {
        let p = cubes(&s, Mode::Debug(view));
        assert_eq!((names(&p), p.lbuffer), (vec!["debug"], None));
        assert!(explain(&p).contains("unlit"), "{}", explain(&p));
    }
}

/// The fur's passes in every mode and blend, in the order the frame has always drawn them.
#[test]
fn fur_plans_its_passes_in_order_in_every_mode() {
    let sphere = [common::furry_sphere()];
    let mut s = common::scene(8, true, FurBlend::Stipple);
    s.lights[0].shadows = true;
    let cases: [(Mode, FurBlend, &[&str]); 6] = [
        (
            Mode::Inferred,
            FurBlend::Stipple,
            &[
                "shadow-maps",
                "opacity-maps",
                "geometry",
                "light",
                "obliterate",
                "material",
                "resolve",
            ],
        ),
        (
            Mode::Deferred,
            FurBlend::Wboit,
            &[
                "shadow-maps",
                "opacity-maps",
                "geometry",
                "light",
                "obliterate",
                "material",
                "fur-oit",
                "composite",
                "resolve",
            ],
        ),
        (
            Mode::Forward,
            FurBlend::Stipple,
            &["shadow-maps", "opacity-maps", "forward", "resolve"],
        ),
        (
            Mode::Forward,
            FurBlend::Wboit,
            &[
                "shadow-maps",
                "opacity-maps",
                "forward",
                "fur-oit",
                "composite",
                "resolve",
            ],
        ),
        (
            Mode::Strands,
            FurBlend::Stipple,
            &["shadow-maps", "opacity-maps", "forward"],
        ),
        (Mode::Debug(DebugView::Comb), FurBlend::Wboit, &["debug"]),
    ];
    for (mode, blend, want) in cases {
        s.fur_blend = blend;
        let p = plan_of(&s, &sphere, mode);
        assert_eq!(names(&p), want, "{mode} with {blend:?}");
        let e = explain(&p);
        for name in want {
            assert!(e.contains(&format!("\n  {name:<14}")), "{name} in\n{e}");
        }
    }
    // Without opacity layers the fur casts through its base mesh alone: no opacity pass.
    s.shadow_maps.opacity_layers = 0;
    s.fur_blend = FurBlend::Stipple;
    let p = plan_of(&s, &sphere, Mode::Forward);
    assert_eq!(names(&p), ["shadow-maps", "forward", "resolve"]);
}

#[test]
fn the_shadow_pass_runs_only_for_casting_lights_and_says_what_it_draws() {
    let mut s = grid_scene(Path::new("builtin:cube"), 1, 1, 1, 160, 90);
    let e = explain(&cubes(&s, Mode::Inferred));
    assert!(!e.contains("shadow-maps"), "{e}");
    s.lights[0].shadows = true;
    s.lights.push(pelt_preview::scene::Light {
        emitter: Emitter::Directional {
            direction: Vec3::NEG_Y,
        },
        shadows: true,
        ..s.lights[0]
    });
    let e = explain(&cubes(&s, Mode::Inferred));
    assert!(
        e.contains("shadow-maps   1 point light(s) × 6 cube faces, 1 directional light(s) × 1 orthographic map (fitted to the scene) of 512²"),
        "{e}"
    );
    assert_eq!(
        names(&cubes(&s, Mode::Inferred)),
        ["shadow-maps", "geometry", "light", "material"]
    );
}

#[test]
fn explain_says_when_and_how_the_wind_blows() {
    let mut s = grid_scene(Path::new("builtin:cube"), 1, 1, 1, 160, 90);
    assert!(!explain(&cubes(&s, Mode::Inferred)).contains("wind"));
    s.wind = Some(pelt_preview::wind::Wind {
        direction: Vec3::Z,
        strength: 0.5,
        gust_hz: 2.0,
        turbulence: 0.25,
    });
    s.time = 1.5;
    let e = explain(&cubes(&s, Mode::Inferred));
    assert!(
        e.contains(
            "wind toward [0.00, 0.00, 1.00], strength 0.50, 2 gusts/s, turbulence 0.25, at 1.5 s"
        ),
        "{e}"
    );
}
