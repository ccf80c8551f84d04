//! Pixel tests of the renderer on a real wgpu adapter (on a machine without a GPU: Mesa's
//! llvmpipe through GL, or lavapipe through Vulkan; `PELT_BACKEND=gl|vulkan` picks one, CI runs
//! both). Images are at most 256 × 144 and are compared with FLIP (nv-flip, as wgpu's own
//! tests do) against a reference render of the same scene; on failure the test writes
//! `NAME-actual.png`, `NAME-reference.png` and `NAME-diff.png` (FLIP error, magma) into
//! `target/render-tests/`.

use std::path::PathBuf;

use glam::{Quat, Vec3};
use pelt_preview::scene::{Camera, Light, Material, Object, Size, Transform, Unit};
use pelt_preview::{Image, Mode, Scene};

mod common;

use common::{assert_flip, flip_mean, out_dir, preview, render, write_failure};

fn object(asset: &str, at: Vec3, scale: Vec3, color: Vec3) -> Object {
    Object {
        asset: PathBuf::from(asset),
        transform: Transform {
            translation: at.into(),
            scale: scale.into(),
            ..Transform::default()
        },
        material: Material::Opaque,
        color: color.into(),
    }
}

fn light(at: Vec3, color: Vec3, intensity: f32, radius: f32) -> Light {
    Light::point(at.into(), radius, intensity).with_color(color.into())
}

fn camera(position: Vec3, target: Vec3) -> Camera {
    Camera {
        position: position.into(),
        target: target.into(),
        near: 0.5,
        far: 40.0,
        ..Camera::default()
    }
}

/// Cubes (six normal groups each) and spheres on a floor, five coloured lights.
fn opaque_scene() -> Scene {
    let mut objects = vec![object(
        "builtin:cube",
        Vec3::new(0.0, -0.6, 0.0),
        Vec3::new(8.0, 0.2, 8.0),
        Vec3::splat(0.7),
    )];
    for i in 0..9 {
        let x = (i % 3) as f32 * 1.6 - 1.6;
        let z = (i / 3) as f32 * 1.6 - 1.6;
        let shape = if i % 2 == 0 {
            "builtin:cube"
        } else {
            "builtin:sphere"
        };
        let mut o = object(
            shape,
            Vec3::new(x, 0.0, z),
            Vec3::splat(0.9),
            Vec3::new(0.9, 0.6 + 0.04 * i as f32, 0.4),
        );
        o.transform.rotation = Quat::from_rotation_y(0.3 * i as f32).to_array();
        objects.push(o);
    }
    Scene {
        output: Size {
            width: 256,
            height: 144,
        },
        camera: camera(Vec3::new(0.5, 3.0, 5.5), Vec3::new(0.0, -0.3, 0.0)),
        ambient: [0.05; 3],
        objects,
        lights: vec![
            light(
                Vec3::new(-1.5, 1.2, 1.5),
                Vec3::new(1.0, 0.5, 0.3),
                4.0,
                4.0,
            ),
            light(
                Vec3::new(1.8, 1.0, -1.0),
                Vec3::new(0.3, 0.6, 1.0),
                4.0,
                4.0,
            ),
            light(Vec3::new(0.0, 2.5, 0.0), Vec3::new(1.0, 1.0, 1.0), 3.0, 5.0),
            light(Vec3::new(2.5, 0.5, 2.5), Vec3::new(0.4, 1.0, 0.4), 3.0, 3.0),
            light(
                Vec3::new(-2.5, 0.3, -2.0),
                Vec3::new(1.0, 0.3, 0.8),
                3.0,
                3.0,
            ),
        ],
        ..Scene::default()
    }
}

#[test]
fn forward_and_deferred_agree_on_an_opaque_scene() {
    let mut p = preview();
    let s = opaque_scene();
    let forward = render(&mut p, &s, Mode::Forward);
    let deferred = render(&mut p, &s, Mode::Deferred);
    let mean = assert_flip("opaque-deferred-vs-forward", &forward, &deferred, 0.01);
    // The scene is lit (not a flat image that would agree trivially): the lights' colours show.
    let lit = forward
        .rgba
        .chunks_exact(4)
        .filter(|px| px[0].max(px[1]).max(px[2]) > 120)
        .count();
    assert!(lit > 2000, "{lit} bright pixels");
    // And the comparison can fail: without lights the images differ a lot.
    let dark = render(
        &mut p,
        &Scene {
            lights: Vec::new(),
            ..s
        },
        Mode::Deferred,
    );
    let (worse, _) = flip_mean(&forward, &dark);
    assert!(worse > 10.0 * mean.max(0.005), "unlit {worse} vs {mean}");
}

/// Many silhouettes: a field of small cubes and spheres in front of a wall, lit by lights
/// between them so that foreground and background get very different light.
fn silhouette_scene() -> Scene {
    let mut objects = vec![object(
        "builtin:cube",
        Vec3::new(0.0, 0.0, -3.0),
        Vec3::new(14.0, 9.0, 0.2),
        Vec3::splat(0.8),
    )];
    for i in 0..48 {
        let x = (i % 8) as f32 * 0.9 - 3.15;
        let y = (i / 8) as f32 * 0.75 - 1.9;
        let z = if (i / 8 + i) % 2 == 0 { 0.0 } else { -1.2 };
        let shape = if i % 3 == 0 {
            "builtin:sphere"
        } else {
            "builtin:cube"
        };
        let mut o = object(
            shape,
            Vec3::new(x, y, z),
            Vec3::splat(0.45),
            Vec3::new(0.9, 0.85, 0.8),
        );
        o.transform.rotation =
            Quat::from_euler(glam::EulerRot::XYZ, 0.4 * i as f32, 0.7 * i as f32, 0.0).to_array();
        objects.push(o);
    }
    let mut lights = Vec::new();
    for k in 0..6 {
        let x = (k % 3) as f32 * 2.6 - 2.6;
        let y = (k / 3) as f32 * 2.2 - 1.1;
        let c = [
            Vec3::new(1.0, 0.3, 0.2),
            Vec3::new(0.2, 0.5, 1.0),
            Vec3::new(0.3, 1.0, 0.3),
        ][k % 3];
        // Between the objects and the wall: the wall is lit, the objects' fronts are not.
        lights.push(light(Vec3::new(x, y, -2.2), c, 3.0, 3.5));
    }
    lights.push(light(Vec3::new(0.0, 0.0, 4.0), Vec3::splat(1.0), 6.0, 9.0));
    Scene {
        output: Size {
            width: 256,
            height: 144,
        },
        camera: camera(Vec3::new(0.0, 0.0, 6.0), Vec3::ZERO),
        ambient: [0.03; 3],
        lbuffer_scale: 0.625,
        objects,
        lights,
        ..Scene::default()
    }
}

#[test]
fn dsf_halves_the_error_of_bilinear_upsampling_at_lbuffer_scale_0_625() {
    let mut p = preview();
    let s = silhouette_scene();
    let reference = render(&mut p, &s, Mode::Deferred);
    let dsf = render(
        &mut p,
        &Scene {
            dsf: true,
            ..s.clone()
        },
        Mode::Inferred,
    );
    let bilinear = render(
        &mut p,
        &Scene {
            dsf: false,
            ..s.clone()
        },
        Mode::Inferred,
    );
    let (e_dsf, _) = flip_mean(&reference, &dsf);
    let (e_bil, err) = flip_mean(&reference, &bilinear);
    eprintln!(
        "silhouettes at 0.625: FLIP mean DSF {e_dsf:.5}, plain bilinear {e_bil:.5} (ratio {:.3})",
        e_dsf / e_bil
    );
    if e_dsf > 0.5 * e_bil {
        write_failure("silhouettes-bilinear", &reference, &bilinear, &err);
        assert_flip("silhouettes-dsf", &reference, &dsf, 0.5 * e_bil);
    }
    // Both are real errors, not noise: bilinear upsampling visibly bleeds.
    assert!(e_bil > 0.01, "bilinear error {e_bil}");
}

/// A blue cube in front of a white wall, lit only from behind the cube: the cube's visible
/// faces get ambient light alone, the wall right beside them is bright.
fn leak_scene(dsf: bool) -> Scene {
    Scene {
        output: Size {
            width: 160,
            height: 120,
        },
        camera: camera(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO),
        ambient: [0.05; 3],
        lbuffer_scale: 0.625,
        dsf,
        objects: vec![
            object(
                "builtin:cube",
                Vec3::new(0.0, 0.0, -1.5),
                Vec3::new(12.0, 10.0, 0.2),
                Vec3::new(1.0, 0.0, 0.0),
            ),
            object(
                "builtin:cube",
                Vec3::new(0.13, -0.07, 0.5),
                Vec3::splat(1.6),
                Vec3::new(0.0, 0.0, 1.0),
            ),
        ],
        lights: vec![light(
            Vec3::new(0.13, -0.07, -0.8),
            Vec3::splat(1.0),
            12.0,
            6.0,
        )],
        ..Scene::default()
    }
}

/// Pixels of the cube in a full-resolution render: blue albedo and no specular light reach
/// them, so red is 0 there (the wall is red).
fn cube_mask(i: &Image) -> Vec<bool> {
    i.rgba
        .chunks_exact(4)
        .map(|p| p[0] == 0 && p[2] > 0)
        .collect()
}

/// The largest channel difference between `a` and `b` over the masked pixels.
fn max_diff(a: &Image, b: &Image, mask: &[bool]) -> u8 {
    a.rgba
        .chunks_exact(4)
        .zip(b.rgba.chunks_exact(4))
        .zip(mask)
        .filter(|(_, m)| **m)
        .map(|((p, q), _)| (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap_or(0))
        .max()
        .unwrap_or(0)
}

#[test]
fn no_light_leaks_across_an_object_id_edge() {
    let mut p = preview();
    // Ambient 0.05 on blue albedo 1 → sRGB 63 (0.05^(1/2.4)·1.055 − 0.055 = 0.2474).
    let deferred = render(&mut p, &leak_scene(false), Mode::Deferred);
    let mask = cube_mask(&deferred);
    let n = mask.iter().filter(|m| **m).count();
    assert!(n > 1500, "the cube covers {n} pixels");
    let cube_max = deferred
        .rgba
        .chunks_exact(4)
        .zip(&mask)
        .filter(|(_, m)| **m)
        .map(|(p, _)| p[2])
        .max();
    assert_eq!(
        cube_max.map(|b| b.abs_diff(63) <= 1),
        Some(true),
        "the cube is ambient-lit only: {cube_max:?}"
    );
    // The wall beside the cube is brightly lit.
    let wall_max = deferred
        .rgba
        .chunks_exact(4)
        .map(|p| p[0])
        .max()
        .unwrap_or(0);
    assert!(wall_max > 200, "wall {wall_max}");

    let inferred = render(&mut p, &leak_scene(true), Mode::Inferred);
    let leak = max_diff(&deferred, &inferred, &mask);
    eprintln!("leak with DSF: {leak}/255 on {n} cube pixels");
    if leak > 1 {
        inferred
            .save(&out_dir().join("leak-actual.png"))
            .expect("write");
        deferred
            .save(&out_dir().join("leak-reference.png"))
            .expect("write");
        panic!(
            "light leaked onto the cube with DSF: up to {leak}/255 off the full-resolution render"
        );
    }
    // Without DSF the same edge does leak (so this test can fail).
    let bilinear = render(&mut p, &leak_scene(false), Mode::Inferred);
    let leak_b = max_diff(&deferred, &bilinear, &mask);
    eprintln!("leak with plain bilinear: {leak_b}/255");
    assert!(leak_b > 60, "plain bilinear leaks: {leak_b}");
}

/// A lit white wall and three half-transparent quads, red nearest, then green, then blue; a
/// light between green and blue lights the blue quad and the wall, not the fronts of red and
/// green.
fn alpha_scene(order: [Vec3; 3]) -> Scene {
    let mut objects = vec![object(
        "builtin:cube",
        Vec3::new(0.0, 0.0, -3.5),
        Vec3::new(12.0, 9.0, 0.2),
        Vec3::splat(1.0),
    )];
    let offsets = [
        Vec3::new(-0.5, 0.35, 0.0),
        Vec3::new(0.5, 0.35, -1.0),
        Vec3::new(0.0, -0.45, -2.0),
    ];
    for (k, c) in order.into_iter().enumerate() {
        let mut o = object("builtin:quad", offsets[k], Vec3::new(2.0, 2.0, 1.0), c);
        o.material = Material::Alpha { opacity: Unit(0.6) };
        objects.push(o);
    }
    Scene {
        output: Size {
            width: 200,
            height: 150,
        },
        camera: camera(Vec3::new(0.0, 0.0, 6.0), Vec3::ZERO),
        ambient: [0.25; 3],
        objects,
        lights: vec![light(Vec3::new(0.0, 0.0, -1.5), Vec3::splat(1.0), 3.0, 6.0)],
        ..Scene::default()
    }
}

/// Mean colour of the 5×5 block around the projection of world point `at`.
fn mean_at(i: &Image, s: &Scene, at: Vec3) -> Vec3 {
    let v = pelt_preview::view::View::new(s);
    let clip = v.proj * v.view * at.extend(1.0);
    let x = ((clip.x / clip.w * 0.5 + 0.5) * i.width as f32) as u32;
    let y = ((0.5 - clip.y / clip.w * 0.5) * i.height as f32) as u32;
    let mut sum = Vec3::ZERO;
    for dy in 0..5 {
        for dx in 0..5 {
            let p = i.pixel(x + dx - 2, y + dy - 2);
            sum += Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32);
        }
    }
    sum / 25.0
}

#[test]
fn three_stacked_alpha_layers_each_show_in_order() {
    let mut p = preview();
    let (r, g, b) = (
        Vec3::new(1.0, 0.1, 0.1),
        Vec3::new(0.1, 1.0, 0.1),
        Vec3::new(0.1, 0.1, 1.0),
    );
    let s = alpha_scene([r, g, b]);
    let d = p.prepare(&s, Mode::Inferred).expect("prepare");
    let mut patterns: Vec<u32> = d
        .plan
        .alpha
        .iter()
        .map(|&k| d.plan.objects[k].pattern)
        .collect();
    patterns.sort_unstable();
    assert_eq!(
        patterns,
        vec![1, 2, 3],
        "three layers, three stipple patterns"
    );
    let inferred = p.render(&d).expect("render");
    let forward = render(&mut p, &s, Mode::Forward);
    // Points inside: only blue, blue+green, all three, red+blue (regions of the layout).
    let probes = [
        ("blue only", Vec3::new(0.0, -1.2, -2.0)),
        ("green over blue", Vec3::new(0.9, -0.1, -1.0)),
        ("red over green over blue", Vec3::new(0.0, 0.0, 0.0)),
        ("red over blue", Vec3::new(-0.9, -0.2, 0.0)),
        ("red only", Vec3::new(-1.2, 1.1, 0.0)),
    ];
    for (name, at) in probes {
        let a = mean_at(&inferred, &s, at);
        let f = mean_at(&forward, &s, at);
        eprintln!("{name}: inferred {a:?} forward {f:?}");
        assert!(
            (a - f).abs().max_element() <= 10.0,
            "{name}: inferred {a:?} vs forward {f:?}"
        );
    }
    let (mean, _) = flip_mean(&forward, &inferred);
    eprintln!("alpha layers: FLIP mean inferred vs forward {mean:.5}");
    // Order matters and is kept: the triple overlap is reddest when red is nearest.
    let reversed = alpha_scene([b, g, r]);
    let inv = render(&mut p, &reversed, Mode::Inferred);
    let near_red = mean_at(&inferred, &s, Vec3::ZERO);
    let near_blue = mean_at(&inv, &reversed, Vec3::ZERO);
    assert!(
        near_red.x > near_blue.x + 15.0 && near_blue.z > near_red.z + 15.0,
        "{near_red:?} vs {near_blue:?}"
    );
    // Each layer shows: its own hue dominates where it is nearest.
    let red = mean_at(&inferred, &s, Vec3::new(-1.2, 1.1, 0.0));
    assert!(
        red.x > red.y + 30.0 && red.x > red.z + 30.0,
        "red layer {red:?}"
    );
    assert_flip("alpha-inferred-vs-forward", &forward, &inferred, 0.05);
}

#[test]
fn rendering_is_deterministic_and_explains_itself() {
    let mut p = preview();
    let s = opaque_scene();
    let a = render(&mut p, &s, Mode::Inferred);
    let b = render(&mut p, &s, Mode::Inferred);
    assert_eq!(a.png(), b.png(), "same scene, same bytes");
    assert_eq!((a.width, a.height), (256, 144));
    let d = p.prepare(&s, Mode::Inferred).expect("prepare");
    let e = pelt_preview::explain(&d.plan);
    assert!(
        e.contains("geometry") && e.contains("light") && e.contains("material"),
        "{e}"
    );
    // Timing runs and reports every pass, in the plan's order, each with a time a clock can
    // give (finite, not negative) and the same time in the profile; together they take time.
    // (A pass is timed in frames of its own, so it is not bounded by `frame_ms`.)
    let t = p.time(&d, 1, 3).expect("time");
    let names: Vec<&str> = t.profile.iter().map(|x| x.pass).collect();
    assert_eq!(names, ["geometry", "light", "material"], "{t:?}");
    let total: f64 = t.passes.iter().map(|(_, ms)| ms).sum();
    assert!(
        t.frame_ms.is_finite()
            && t.frame_ms > 0.0
            && t.passes.len() == t.profile.len()
            && t.passes.iter().zip(&t.profile).all(|((_, ms), x)| {
                ms.is_finite() && *ms >= 0.0 && ms.to_bits() == x.ms.to_bits()
            })
            && total > 0.0,
        "{t:?}"
    );
}
