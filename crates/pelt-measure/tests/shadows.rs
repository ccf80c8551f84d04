//! Shadow cubes of point lights and directional lights' orthographic maps measured against
//! the CPU ray tracer's shadow rays (the same scene, lighting and occluders), so the FLIP
//! between the two is the shadow maps' own error: resolution, bias and PCF. The stages are
//! fixtures/scenes/shadows.json and sun.json at 256×144; the
//! alpha-layer case (Kircher & Lawrance Fig. 6) is a blade over three overlapping layers. A
//! failed comparison leaves `-reference.png`, `-actual.png` and `-diff.png` in
//! `target/render-tests/`. `PELT_BACKEND=gl|vulkan` picks the back end.

mod common;

use std::path::Path;

use common::{away_from, preview, save_failure};
use glam::{Vec3, Vec4Swizzles};
use pelt_measure::Flip;
use pelt_preview::knobs::{self, Knobs};
use pelt_preview::{Image, Mode, Preview, Scene};

const SIZE: (u32, u32) = (256, 144);

struct Loaded {
    scene: Scene,
    meshes: Vec<pelt_preview::asset::MeshData>,
    of: Vec<usize>,
}

/// A stage of fixtures/scenes: `shadows.json` (a point light) or `sun.json` (a directional
/// light).
fn stage(file: &str) -> Loaded {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fixtures/scenes")
        .join(file);
    let k = Knobs {
        size: Some(SIZE),
        ..Knobs::default()
    };
    let i = knobs::load(&path, &k, SIZE).expect(file);
    Loaded {
        scene: i.scene,
        meshes: i.meshes,
        of: i.mesh_of,
    }
}

fn with_shadows(l: &Loaded, on: bool) -> Scene {
    let mut s = l.scene.clone();
    s.lights.iter_mut().for_each(|x| x.shadows &= on);
    s
}

fn traced(l: &Loaded, scene: &Scene) -> Image {
    let t = pelt_trace::trace_scene(scene, &l.meshes, &l.of).expect("ray tracer");
    Image {
        width: t.width,
        height: t.height,
        rgba: t.rgba,
    }
}

fn render(p: &mut Preview, l: &Loaded, scene: &Scene, mode: Mode) -> Image {
    let sv = p
        .prepare_loaded(scene, &l.meshes, &l.of, mode)
        .expect("prepare");
    p.render(&sv).expect("render")
}

/// The pixels a shadow darkens: where the ray tracer's image with shadow rays is darker than
/// without by more than two steps in some channel.
fn shadowed(lit: &Image, dark: &Image) -> Vec<bool> {
    lit.rgba
        .chunks(4)
        .zip(dark.rgba.chunks(4))
        .map(|(a, b)| {
            a.iter()
                .zip(b)
                .take(3)
                .any(|(x, y)| *x > y.saturating_add(2))
        })
        .collect()
}

/// How many pixels `mask` keeps.
fn count(mask: &[bool]) -> usize {
    mask.iter().filter(|&&m| m).count()
}

/// The stage `l` with shadows on, rendered in `modes` against the ray tracer with shadow
/// rays: whole-image FLIP ≤ 0.02 and ≤ 0.06 over the shadowed pixels. Returns the truth and
/// the shadowed pixels.
fn matches_the_truth(
    p: &mut Preview,
    l: &Loaded,
    name: &str,
    modes: &[Mode],
) -> (Image, Vec<bool>) {
    let on = with_shadows(l, true);
    let truth = traced(l, &on);
    let mask = shadowed(&traced(l, &with_shadows(l, false)), &truth);
    let n = count(&mask);
    assert!(
        n > 1000,
        "{name}: the stage has shadows to measure ({n} pixels)"
    );
    for &mode in modes {
        let img = render(p, l, &on, mode);
        let f = Flip::new(&truth, &img).expect("same size");
        let (whole, over) = (f.mean(), f.masked_mean(&mask));
        eprintln!("{name}, {mode}: FLIP whole {whole:.4}, over {n} shadowed pixels {over:.4}");
        if whole > 0.02 || over > 0.06 || std::env::var_os("PELT_SAVE").is_some() {
            save_failure(&format!("{name}-{mode}"), &truth, &img);
        }
        assert!(whole <= 0.02, "{name}, {mode}: whole-image FLIP {whole}");
        assert!(
            over <= 0.06,
            "{name}, {mode}: FLIP over the shadowed pixels {over}"
        );
    }
    (truth, mask)
}

#[test]
fn shadow_cubes_match_the_ray_tracers_shadow_rays() {
    let l = stage("shadows.json");
    let on = with_shadows(&l, true);
    let mut p = preview();
    let (truth, mask) = matches_the_truth(&mut p, &l, "shadows", &[Mode::Forward, Mode::Deferred]);
    // The knobs reach the cubes: hard edges (1 texel) and a wider filter (4×4) draw other
    // shadows, each still close to the truth; a finer cube (1024²) too.
    let mut seen = vec![render(&mut p, &l, &on, Mode::Forward)];
    for (size, pcf) in [(512, 1), (512, 4), (1024, 2)] {
        let mut s = on.clone();
        s.shadow_maps.size = size;
        s.shadow_maps.pcf = pcf;
        let img = render(&mut p, &l, &s, Mode::Forward);
        let over = Flip::new(&truth, &img)
            .expect("same size")
            .masked_mean(&mask);
        eprintln!("forward, {size}², PCF {pcf}: FLIP over the shadow {over:.4}");
        assert!(over <= 0.08, "{size}², PCF {pcf}: {over}");
        assert!(
            seen.iter().all(|x| x.rgba != img.rgba),
            "{size}², PCF {pcf} changed nothing"
        );
        seen.push(img);
    }
    misses_without_shadows(&mut p, &l, &truth, &mask);
}

/// The negative control: the stage rendered without shadows misses the truth's shadowed
/// pixels by far.
fn misses_without_shadows(p: &mut Preview, l: &Loaded, truth: &Image, mask: &[bool]) {
    let unshadowed = render(p, l, &with_shadows(l, false), Mode::Forward);
    let miss = Flip::new(truth, &unshadowed)
        .expect("same size")
        .masked_mean(mask);
    assert!(
        miss > 0.15,
        "without shadows the shadowed pixels differ ({miss})"
    );
}

/// A directional light's orthographic map, fitted to the scene, against the ray tracer's
/// shadow rays toward it (parallel, no falloff), at full resolution (the inferred mode's
/// L-buffer adds its own upsampling error: whole-image FLIP 0.025 here, 0.012 without
/// shadows; the acne and blade tests cover it); the negative control: without shadows the
/// shadowed pixels miss by far.
#[test]
fn a_directional_lights_map_matches_the_ray_tracers_shadow_rays() {
    let l = stage("sun.json");
    let mut p = preview();
    let modes = [Mode::Forward, Mode::Deferred];
    let (truth, mask) = matches_the_truth(&mut p, &l, "sun", &modes);
    misses_without_shadows(&mut p, &l, &truth, &mask);
}

/// Kircher & Lawrance Fig. 6: a blade's shadow on three overlapping alpha layers. Each
/// layer's own part under the blade darkens with the blade's shadow, and beside it is lit as
/// without shadows, in every rasterizing mode.
#[test]
fn a_blade_shadows_each_of_three_overlapping_alpha_layers_in_every_mode() {
    let json = r#"{
        "output": {"width": 192, "height": 144},
        "camera": {"position": [0, 6, 7], "target": [0, 0.4, 0], "fovYDeg": 40, "near": 0.1, "far": 30},
        "ambient": [0.05, 0.05, 0.05],
        "objects": [
            {"asset": "builtin:cube", "transform": {"translation": [0, -0.1, 0], "scale": [8, 0.2, 8]}, "color": [0.6, 0.6, 0.6]},
            {"asset": "builtin:quad", "transform": {"translation": [-0.8, 0.4, 0], "rotation": [-0.7071068, 0, 0, 0.7071068], "scale": [1.6, 1.6, 1]}, "material": {"kind": "alpha", "opacity": 0.6}, "color": [1, 0.3, 0.3]},
            {"asset": "builtin:quad", "transform": {"translation": [0, 0.6, 0], "rotation": [-0.7071068, 0, 0, 0.7071068], "scale": [1.6, 1.6, 1]}, "material": {"kind": "alpha", "opacity": 0.6}, "color": [0.3, 1, 0.3]},
            {"asset": "builtin:quad", "transform": {"translation": [0.8, 0.8, 0], "rotation": [-0.7071068, 0, 0, 0.7071068], "scale": [1.6, 1.6, 1]}, "material": {"kind": "alpha", "opacity": 0.6}, "color": [0.3, 0.3, 1]},
            {"asset": "builtin:cube", "transform": {"translation": [0, 1.6, 0], "scale": [4, 0.05, 0.3]}, "color": [0.8, 0.8, 0.8]}
        ],
        "lights": [{"position": [0, 3.5, 0], "intensity": 6, "radius": 12, "shadows": true}]
    }"#;
    let on: Scene = serde_json::from_str(json).expect("scene");
    let mut off = on.clone();
    off.lights[0].shadows = false;
    let (meshes, of) = pelt_preview::load_meshes(&on).expect("built-in meshes");
    let l = Loaded {
        scene: on.clone(),
        meshes,
        of,
    };
    let view = pelt_preview::view::View::new(&on);
    let px = |p: Vec3| {
        let c = view.proj * view.view * p.extend(1.0);
        let ndc = c.xy() / c.w;
        let x = ((ndc.x + 1.0) * 0.5 * 192.0) as u32;
        let y = ((1.0 - ndc.y) * 0.5 * 144.0) as u32;
        (x, y)
    };
    let luma = |img: &Image, (x, y): (u32, u32)| -> u32 {
        let i = ((y * img.width + x) * 4) as usize;
        img.rgba[i..i + 3].iter().map(|&c| u32::from(c)).sum()
    };
    // On each layer, a point where it is the nearest layer to the camera: under the blade's
    // shadow (the blade runs along x at z = 0, the light straight above it) and beside it.
    let layers = [(-1.2, 0.4), (-0.4, 0.6), (1.2, 0.8)];
    let mut p = preview();
    for mode in [Mode::Inferred, Mode::Deferred, Mode::Forward] {
        let lit = render(&mut p, &l, &off, mode);
        let shadowed = render(&mut p, &l, &on, mode);
        for (i, &(x, y)) in layers.iter().enumerate() {
            let under = px(Vec3::new(x, y, 0.0));
            let beside = px(Vec3::new(x, y, -0.7));
            let (a, b) = (luma(&lit, under), luma(&shadowed, under));
            if b * 4 > a * 3 {
                save_failure(&format!("shadows-blade-{mode}"), &lit, &shadowed);
            }
            assert!(
                b * 4 <= a * 3,
                "{mode}: layer {i} under the blade: {b} vs {a} unshadowed"
            );
            let (a, b) = (luma(&lit, beside), luma(&shadowed, beside));
            assert!(
                a.abs_diff(b) <= 3,
                "{mode}: layer {i} beside the blade: {b} vs {a}"
            );
        }
    }
}

/// A cube on a floor under a light 0.6 above the floor and 6 away (about 3° to 6° over the
/// floor: grazing), scaled by `s`; the intensity keeps the floor's light the same at every
/// scale (the falloff is 1 / (1 + d²)). With `sun`, a directional light from there toward
/// the cube instead (about 5.7° over the floor), of the intensity the point light has at
/// the cube.
fn grazing_stage(s: f32, shadows: bool, sun: bool) -> Scene {
    let d2 = (36.0 + 0.36) * s * s;
    let light = if sun {
        format!(
            r#"{{"kind": "directional", "direction": [-6, -0.6, 0], "intensity": 1.5, "shadows": {shadows}}}"#
        )
    } else {
        format!(
            r#"{{"position": [{lx}, {ly}, 0], "intensity": {i}, "radius": {r}, "shadows": {shadows}}}"#,
            lx = 6.0 * s,
            ly = 0.6 * s,
            i = 1.5 * (1.0 + d2),
            r = 30.0 * s,
        )
    };
    let json = format!(
        r#"{{
        "output": {{"width": 192, "height": 108}},
        "camera": {{"position": [{cx}, {cy}, {cz}], "target": [0, 0, 0], "fovYDeg": 45, "near": {near}, "far": {far}}},
        "ambient": [0.05, 0.05, 0.05],
        "objects": [
            {{"asset": "builtin:cube", "transform": {{"translation": [0, {fy}, 0], "scale": [{fw}, {ft}, {fw}]}}, "color": [0.7, 0.7, 0.7]}},
            {{"asset": "builtin:cube", "transform": {{"translation": [0, {cyc}, 0], "scale": [{c}, {c}, {c}]}}, "color": [0.9, 0.6, 0.3]}}
        ],
        "lights": [{light}]
    }}"#,
        cx = -3.0 * s,
        cy = 4.0 * s,
        cz = 6.0 * s,
        near = 0.05 * s,
        far = 100.0 * s,
        fy = -0.1 * s,
        fw = 10.0 * s,
        ft = 0.2 * s,
        cyc = 0.5 * s,
        c = s,
    );
    serde_json::from_str(&json).expect("grazing stage")
}

/// At a grazing light and at scenes of 1 cm and of 1 km, for a point light's cube and a
/// directional light's map: no acne (a surface the ray tracer lights is lit as without
/// shadows) and no leak (the cube's shadow, contact included, matches the ray tracer's).
#[test]
fn no_acne_or_leaks_at_grazing_light_at_one_centimetre_and_at_one_kilometre() {
    let mut p = preview();
    for (s, sun) in [0.01, 1.0, 1000.0]
        .into_iter()
        .flat_map(|s| [(s, false), (s, true)])
    {
        let kind = if sun { "directional" } else { "point" };
        let on = grazing_stage(s, true, sun);
        let off = grazing_stage(s, false, sun);
        let (meshes, of) = pelt_preview::load_meshes(&on).expect("built-in meshes");
        let l = Loaded {
            scene: on.clone(),
            meshes,
            of,
        };
        let truth = traced(&l, &on);
        let mask = shadowed(&traced(&l, &off), &truth);
        // Lit in the truth and more than two pixels from its shadow (a shadow edge may fall
        // a pixel or two off: an L-buffer texel is 1.6 output pixels).
        let lit_in_truth = away_from(&mask, truth.width as usize, 2);
        assert!(
            mask.iter().filter(|&&m| m).count() > 200,
            "scale {s}, {kind}: a shadow to measure"
        );
        for mode in [Mode::Forward, Mode::Inferred] {
            let (a, b) = (
                render(&mut p, &l, &off, mode),
                render(&mut p, &l, &on, mode),
            );
            // Acne: pixels the truth lights, darkened by the shadow cube.
            let acne = a
                .rgba
                .chunks(4)
                .zip(b.rgba.chunks(4))
                .zip(&lit_in_truth)
                .filter(|((x, y), lit)| {
                    **lit
                        && x.iter()
                            .zip(y.iter())
                            .take(3)
                            .any(|(u, v)| *u > v.saturating_add(3))
                })
                .count();
            let lit = lit_in_truth.iter().filter(|&&m| m).count();
            if acne * 200 > lit {
                save_failure(&format!("shadows-acne-{s}-{kind}-{mode}"), &a, &b);
            }
            assert!(
                acne * 200 <= lit,
                "scale {s}, {kind}, {mode}: {acne} of {lit} lit pixels darkened"
            );
            // Leaks: the shadowed pixels against the ray tracer.
            let over = Flip::new(&truth, &b).expect("same size").masked_mean(&mask);
            eprintln!(
                "scale {s}, {kind}, {mode}: {acne} acne pixels of {lit}; FLIP over the shadow {over:.4}"
            );
            if over > 0.08 {
                save_failure(&format!("shadows-leak-{s}-{kind}-{mode}"), &truth, &b);
            }
            assert!(
                over <= 0.08,
                "scale {s}, {kind}, {mode}: FLIP over the shadow {over}"
            );
        }
    }
}

/// `l` with thin casters added above its floor: an upright pole 5 cm wide and a plank 4 cm
/// thick (unit cubes of the stage's own mesh, scaled), each a few texels of the map across.
fn with_thin_casters(mut l: Loaded) -> Loaded {
    let cube = l
        .scene
        .objects
        .iter()
        .position(|o| o.asset.as_os_str() == "builtin:cube")
        .expect("a cube on the stage");
    let mesh = l.of[cube];
    for (translation, scale) in [
        ([0.6, 0.8, 0.9], [0.05, 1.6, 0.05]),
        ([-0.3, 1.1, 0.6], [1.0, 0.04, 0.12]),
    ] {
        let mut o = l.scene.objects[cube].clone();
        o.transform.translation = translation;
        o.transform.rotation = [0.0, 0.0, 0.0, 1.0];
        o.transform.scale = scale;
        o.color = [0.8, 0.8, 0.8];
        l.scene.objects.push(o);
        l.of.push(mesh);
    }
    l
}

/// Thin casters beside the thick ones (sphere, cube, torus) under a point light's cube, a
/// spot light's perspective map and a directional light's orthographic map, each against the
/// ray tracer's shadow rays ([`matches_the_truth`]): the thin casters' shadows are in the
/// truth (the shadowed pixels grow by at least 15 beside the stage's own), and without
/// shadows the shadowed pixels miss by far.
#[test]
fn thin_and_thick_casters_under_point_spot_and_directional_lights_match_the_truth() {
    let mut p = preview();
    for file in ["shadows.json", "spot.json", "sun.json"] {
        let bare = stage(file);
        let before = shadowed(
            &traced(&bare, &with_shadows(&bare, false)),
            &traced(&bare, &with_shadows(&bare, true)),
        );
        let l = with_thin_casters(stage(file));
        let name = format!("thin-{}", file.trim_end_matches(".json"));
        let (truth, mask) = matches_the_truth(&mut p, &l, &name, &[Mode::Forward, Mode::Deferred]);
        let (n0, n) = (count(&before), count(&mask));
        eprintln!("{name}: {n0} shadowed pixels without the thin casters, {n} with");
        assert!(
            n >= n0 + 15,
            "{name}: the thin casters cast no shadow ({n0} → {n})"
        );
        misses_without_shadows(&mut p, &l, &truth, &mask);
    }
}
