//! Spot lights (glTF's `KHR_lights_punctual` cone: full light within the inner half-angle,
//! none past the outer, smooth between) against the CPU ray tracer: a shadow-casting spot and a
//! fill light on fixtures/scenes/spot.json at 256×144, the spot's perspective shadow map
//! against the ray tracer's shadow rays (whole image and shadowed pixels); outside the cone
//! only the fill and the ambient light reach, in every lighting path (inferred, deferred,
//! forward, the fur's shells and the strand reference, the ray tracer). A failed comparison
//! leaves `-reference.png`, `-actual.png` and `-diff.png` in `target/render-tests/`.

mod common;

use std::path::Path;

use common::{away_from, preview, save_failure};
use glam::Vec3;
use pelt_measure::Flip;
use pelt_preview::knobs::{self, Knobs};
use pelt_preview::{Image, Mode, Preview, Scene};
use pelt_scene::light::Emitter;

const SIZE: (u32, u32) = (256, 144);

struct Loaded {
    scene: Scene,
    meshes: Vec<pelt_preview::asset::MeshData>,
    of: Vec<usize>,
}

fn load(path: &Path, size: (u32, u32)) -> Loaded {
    let k = Knobs {
        size: Some(size),
        ..Knobs::default()
    };
    let i = knobs::load(path, &k, size).expect("input");
    Loaded {
        scene: i.scene,
        meshes: i.meshes,
        of: i.mesh_of,
    }
}

fn fixture(rel: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures")
        .join(rel)
}

fn traced(l: &Loaded, scene: &Scene) -> Image {
    let t = pelt_trace::trace_scene(scene, &l.meshes, &l.of).expect("ray tracer");
    Image {
        width: t.width,
        height: t.height,
        rgba: t.rgba,
    }
}

/// A lighting path: one of the preview's modes, or the ray tracer.
#[derive(Debug, Clone, Copy)]
enum Lit {
    Preview(Mode),
    Traced,
}

fn drawn(p: &mut Preview, l: &Loaded, scene: &Scene, path: Lit) -> Image {
    match path {
        Lit::Preview(mode) => render(p, l, scene, mode),
        Lit::Traced => traced(l, scene),
    }
}

fn render(p: &mut Preview, l: &Loaded, scene: &Scene, mode: Mode) -> Image {
    let sv = p
        .prepare_loaded(scene, &l.meshes, &l.of, mode)
        .expect("prepare");
    p.render(&sv).expect("render")
}

/// `scene` with the spot light's shadows set to `on`.
fn with_shadows(scene: &Scene, on: bool) -> Scene {
    let mut s = scene.clone();
    s.lights.iter_mut().for_each(|x| x.shadows &= on);
    s
}

/// `scene` without its spot light.
fn without_spot(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    s.lights
        .retain(|l| !matches!(l.emitter, Emitter::Spot { .. }));
    s
}

/// `scene` with its spot light a point light (no cone): the negative control.
fn spot_as_point(scene: &Scene) -> Scene {
    let mut s = scene.clone();
    for l in &mut s.lights {
        if let Emitter::Spot {
            position, radius, ..
        } = l.emitter
        {
            l.emitter = Emitter::Point { position, radius };
        }
    }
    s
}

/// Pixels where `a` and `b` differ by more than `steps` in some channel.
fn differ(a: &Image, b: &Image, steps: u8) -> Vec<bool> {
    a.rgba
        .chunks(4)
        .zip(b.rgba.chunks(4))
        .map(|(x, y)| x.iter().zip(y).take(3).any(|(u, v)| u.abs_diff(*v) > steps))
        .collect()
}

fn count(mask: &[bool]) -> usize {
    mask.iter().filter(|&&m| m).count()
}

/// The shadow-casting spot light and fill light of fixtures/scenes/spot.json against the ray
/// tracer: whole-image FLIP ≤ 0.02 and ≤ 0.06 over the pixels the spot's shadow darkens, in
/// the default (inferred), deferred and forward modes; without the shadow map the shadowed
/// pixels miss by far (the negative control).
#[test]
fn a_spot_lights_perspective_shadow_map_matches_the_ray_tracer() {
    let l = load(&fixture("scenes/spot.json"), SIZE);
    assert!(
        l.scene
            .lights
            .iter()
            .any(|x| x.shadows && matches!(x.emitter, Emitter::Spot { .. })),
        "the stage's spot casts shadows"
    );
    let truth = traced(&l, &l.scene);
    let unshadowed_truth = traced(&l, &with_shadows(&l.scene, false));
    let mask = differ(&unshadowed_truth, &truth, 2);
    let n = count(&mask);
    assert!(n > 1000, "the stage has shadows to measure ({n} pixels)");
    let mut p = preview();
    for mode in [Mode::Inferred, Mode::Deferred, Mode::Forward] {
        let img = render(&mut p, &l, &l.scene, mode);
        let f = Flip::new(&truth, &img).expect("same size");
        let (whole, over) = (f.mean(), f.masked_mean(&mask));
        eprintln!("spot, {mode}: FLIP whole {whole:.4}, over {n} shadowed pixels {over:.4}");
        if whole > 0.02 || over > 0.06 || std::env::var_os("PELT_SAVE").is_some() {
            save_failure(&format!("spot-{mode}"), &truth, &img);
        }
        assert!(whole <= 0.02, "spot, {mode}: whole-image FLIP {whole}");
        assert!(over <= 0.06, "spot, {mode}: FLIP over the shadow {over}");
    }
    let unshadowed = render(&mut p, &l, &with_shadows(&l.scene, false), Mode::Forward);
    let miss = Flip::new(&truth, &unshadowed)
        .expect("same size")
        .masked_mean(&mask);
    assert!(
        miss > 0.15,
        "without the shadow map the shadow is missed ({miss})"
    );
}

/// A spot light wider than one perspective map takes (a 70° half-angle) draws a cube, as a
/// point light does, and its shadow matches the ray tracer's as closely.
#[test]
fn a_wide_spot_light_shadows_through_a_cube() {
    let mut l = load(&fixture("scenes/spot.json"), SIZE);
    for x in &mut l.scene.lights {
        if let Emitter::Spot { inner, outer, .. } = &mut x.emitter {
            (*inner, *outer) = (55.0_f32.to_radians(), 70.0_f32.to_radians());
        }
    }
    let truth = traced(&l, &l.scene);
    let mask = differ(&traced(&l, &with_shadows(&l.scene, false)), &truth, 2);
    let n = count(&mask);
    assert!(
        n > 1000,
        "the wide spot casts shadows to measure ({n} pixels)"
    );
    let mut p = preview();
    let img = render(&mut p, &l, &l.scene, Mode::Forward);
    let f = Flip::new(&truth, &img).expect("same size");
    let (whole, over) = (f.mean(), f.masked_mean(&mask));
    eprintln!("wide spot, forward: FLIP whole {whole:.4}, over {n} shadowed pixels {over:.4}");
    if whole > 0.02 || over > 0.06 {
        save_failure("spot-wide-forward", &truth, &img);
    }
    assert!(whole <= 0.02 && over <= 0.06, "wide spot: {whole}, {over}");
}

/// Where the spot light's cone does not reach (the ray tracer lights nothing there with the
/// spot alone), each lighting path draws what it draws without the spot: the fill and the
/// ambient light only; inside the cone the spot adds light. The negative control: the spot
/// drawn as a point light (no cone) lights those pixels too.
fn outside_the_cone_only_the_rest_reaches(p: &mut Preview, l: &Loaded, name: &str, paths: &[Lit]) {
    let mut alone = l.scene.clone();
    alone
        .lights
        .retain(|x| matches!(x.emitter, Emitter::Spot { .. }));
    alone.ambient = [0.0; 3];
    let dark = {
        let mut s = alone.clone();
        s.lights.clear();
        s
    };
    let lit = differ(
        &traced(l, &dark),
        &traced(l, &with_shadows(&alone, false)),
        0,
    );
    let outside = away_from(&lit, SIZE.0 as usize, 3);
    let (n_out, n_in) = (count(&outside), count(&lit));
    assert!(
        n_out > 2000 && n_in > 1000,
        "{name}: {n_out} pixels outside, {n_in} inside"
    );
    for &mode in paths {
        let with = drawn(p, l, &l.scene, mode);
        let without = drawn(p, l, &without_spot(&l.scene), mode);
        let changed = differ(&with, &without, 2);
        let leaked = changed
            .iter()
            .zip(&outside)
            .filter(|(c, o)| **c && **o)
            .count();
        let added = changed.iter().zip(&lit).filter(|(c, i)| **c && **i).count();
        eprintln!(
            "{name}, {mode:?}: {leaked} of {n_out} pixels outside the cone changed, {added} of {n_in} inside"
        );
        if leaked > 0 {
            save_failure(&format!("spot-cone-{name}-{mode:?}"), &without, &with);
        }
        assert_eq!(
            leaked, 0,
            "{name}, {mode:?}: the spot reached outside its cone"
        );
        assert!(
            added * 4 > n_in,
            "{name}, {mode:?}: the spot lit its cone ({added})"
        );
        let point = drawn(p, l, &spot_as_point(&l.scene), mode);
        let leaked = differ(&point, &without, 2)
            .iter()
            .zip(&outside)
            .filter(|(c, o)| **c && **o)
            .count();
        assert!(
            leaked > 500,
            "{name}, {mode:?}: a point light there lights outside the cone ({leaked})"
        );
    }
}

#[test]
fn outside_the_cone_only_the_fill_and_ambient_light_reach_on_the_stage() {
    let l = load(&fixture("scenes/spot.json"), SIZE);
    let mut p = preview();
    let paths = [Mode::Inferred, Mode::Deferred, Mode::Forward].map(Lit::Preview);
    outside_the_cone_only_the_rest_reaches(&mut p, &l, "stage", &paths);
    outside_the_cone_only_the_rest_reaches(&mut p, &l, "stage", &[Lit::Traced]);
}

/// The baked creature under a narrow spot from above and in front, aimed at its side, and a
/// fill light: the fur's shells (inferred and forward) and the strand reference light only
/// inside the cone.
#[test]
fn outside_the_cone_only_the_fill_and_ambient_light_reach_the_fur() {
    let mut l = load(&fixture("creature.glb"), SIZE);
    let target = Vec3::from(l.scene.camera.target);
    let eye = Vec3::from(l.scene.camera.position);
    let reach = eye.distance(target);
    let fill = l.scene.lights[1];
    let from = target + Vec3::new(0.2, 1.0, 0.6) * reach * 0.5;
    let aim = target + Vec3::new(0.25, 0.0, 0.0) * reach;
    let spot: pelt_scene::scene::Light = serde_json::from_value(serde_json::json!({
        "kind": "spot",
        "position": from.to_array(),
        "direction": (aim - from).to_array(),
        "innerDeg": 14,
        "outerDeg": 24,
        "intensity": 6.0 * reach * reach,
        "radius": reach * 3.0,
    }))
    .expect("a spot light");
    l.scene.lights = vec![spot, fill];
    let mut p = preview();
    let paths = [Mode::Inferred, Mode::Forward, Mode::Strands].map(Lit::Preview);
    outside_the_cone_only_the_rest_reaches(&mut p, &l, "fur", &paths);
}

/// `--explain` names the spot's map; a spot wider than 60° draws a cube instead.
#[test]
fn explain_names_the_spots_perspective_map() {
    let l = load(&fixture("scenes/spot.json"), SIZE);
    let plan = pelt_preview::Plan::new(&l.scene, &l.meshes, &l.of, Mode::Inferred).expect("plan");
    let e = pelt_preview::explain(&plan);
    assert!(e.contains("1 spot light(s) × 1 perspective map"), "{e}");
    assert!(
        !e.contains("point light(s) × 6"),
        "the fill casts no shadow: {e}"
    );
}
