//! The skinning pass (skin.wgsl) against `pelt pose`: the skinned cylinder of
//! `pelt_fixtures::skinned` (two joints, weights blending between y = 0.8 and 1.2) at several
//! times of its "Bend" clip, and the Khronos Fox mid-walk (24 joints), skinned on the GPU and
//! read back, equal the positions `pelt pose` writes within 1e-5 of the extent, normals and
//! tangents within 1e-4. Negative control: the bind matrices (no pose) differ visibly.

mod common;

use std::path::Path;

use glam::{Mat4, Vec3};
use pelt_anim::posed::{pose_document, skin_jobs};
use pelt_io::{Document, PrimitiveRef, accessor};
use pelt_preview::features::skin::{GpuSkin, PosedVertex};

use common::{out_dir, preview};

/// `doc` baked with a generated comb (smooth normals, MikkTSpace tangents, the comb the
/// skin must carry), written and read back.
fn baked(mut doc: Document, name: &str) -> Document {
    use pelt_bake::BakeOptions;
    use pelt_bake::fur::{FurAssets, bake_with_fur};
    let opts = BakeOptions {
        comb: "generate".parse().expect("comb"),
        ..BakeOptions::default()
    };
    let assets = FurAssets::new(pelt_fur::FurConfig {
        textures: pelt_fur::StrandParams {
            size: 64,
            strands: 200,
            ..pelt_fur::StrandParams::default()
        },
        ..pelt_fur::FurConfig::default()
    })
    .expect("fur textures");
    bake_with_fur(&mut doc, &opts, &assets).expect("bake");
    let path = out_dir().join(name);
    pelt_io::glb::write_glb(&doc, &path).expect("write");
    pelt_io::load(&path).expect("load")
}

fn gpu_skin(p: &pelt_preview::Preview, skin: &GpuSkin) -> Vec<PosedVertex> {
    let r = &p.renderer;
    let mut enc = r
        .gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
    skin.encode(r, &mut enc).expect("skin pipeline");
    r.gpu.queue.submit([enc.finish()]);
    skin.read_back(r).expect("read back")
}

fn attribute<const N: usize>(doc: &Document, r: PrimitiveRef, name: &str) -> Vec<[f32; N]> {
    let a = doc.attribute(r, name).expect("attr").expect(name);
    accessor::read_vec::<N>(doc, a, name).expect(name)
}

/// Largest position, normal and tangent differences (positions over the extent).
fn compare(doc: &Document, clip: &str, time: f32, p: &pelt_preview::Preview) -> [f32; 3] {
    let mut posed = doc.clone();
    pose_document(&mut posed, Some(clip), time).expect("pose");
    let mut worst = [0.0f32; 3];
    for job in skin_jobs(doc, Some(clip), time).expect("jobs") {
        let skin = GpuSkin::new(&p.renderer, &job);
        let got = gpu_skin(p, &skin);
        let r = job.primitive;
        let want_p = attribute::<3>(&posed, r, "POSITION");
        let want_n = attribute::<3>(&posed, r, "NORMAL");
        assert_eq!(got.len(), want_p.len());
        let (lo, hi) = want_p.iter().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(Vec3::from(*p)), hi.max(Vec3::from(*p))),
        );
        let extent = (hi - lo).length();
        for (k, g) in got.iter().enumerate() {
            let dp = (Vec3::from_slice(&g.position) - Vec3::from(want_p[k])).length() / extent;
            let dn = (Vec3::from_slice(&g.normal) - Vec3::from(want_n[k])).length();
            worst[0] = worst[0].max(dp);
            worst[1] = worst[1].max(dn);
        }
        // The bake wrote tangents (the comb's frame), so they are compared too.
        let want_t = attribute::<4>(&posed, r, "TANGENT");
        for (g, t) in got.iter().zip(&want_t) {
            let d = (glam::Vec4::from(g.tangent) - glam::Vec4::from(*t)).length();
            worst[2] = worst[2].max(d);
        }
        // Negative control: without the pose (every joint at its bind matrix, i.e. the
        // rest shape) the comparison fails wherever the clip moved anything.
        if time > 0.0 {
            let n = job.joints.as_ref().map_or(0, Vec::len);
            let bind: Vec<Mat4> = vec![Mat4::IDENTITY; n];
            skin.set_pose(&p.renderer, &bind, Mat4::IDENTITY);
            let rest = gpu_skin(p, &skin);
            let moved = rest
                .iter()
                .zip(&want_p)
                .map(|(g, w)| (Vec3::from_slice(&g.position) - Vec3::from(*w)).length() / extent)
                .fold(0.0f32, f32::max);
            assert!(
                moved > 1e-2,
                "{clip} at {time}: the pose moved nothing ({moved})"
            );
        }
    }
    worst
}

#[test]
fn gpu_skinning_equals_pelt_pose() {
    let p = preview();
    let cylinder = baked(pelt_fixtures::skinned::bent_cylinder(), "skin-cylinder.glb");
    let fox_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/fox/Fox.glb");
    let fox = baked(pelt_io::load(&fox_path).expect("fox"), "skin-fox.glb");
    for (doc, clip, times) in [
        (&cylinder, "Bend", &[0.0, 0.5, 1.0][..]),
        (&cylinder, "BendStep", &[1.0][..]),
        (&fox, "Walk", &[0.35][..]),
        (&fox, "Run", &[0.2][..]),
    ] {
        for &t in times {
            let [dp, dn, dt] = compare(doc, clip, t, &p);
            eprintln!(
                "{clip} at {t}: position {dp:.2e} of the extent, normal {dn:.2e}, tangent {dt:.2e}"
            );
            assert!(
                dp <= 1e-5,
                "{clip} at {t}: positions differ by {dp} of the extent"
            );
            assert!(
                dn <= 1e-4 && dt <= 1e-4,
                "{clip} at {t}: normal {dn}, tangent {dt}"
            );
        }
    }
}

/// The Fox's furred frame with its fur textures, framed on `at`'s bounds.
fn fox_scene(path: &Path, at: &pelt_preview::asset::MeshData) -> pelt_preview::Scene {
    let (lo, hi) = at.bounds();
    pelt_preview::procedural::fur_scene(path, lo, hi, 192, 128, 35.0)
}

#[test]
fn a_gpu_skinned_frame_equals_the_cpu_posed_frame() {
    use pelt_preview::asset::{PoseAt, builtin, posed, skinned};
    use pelt_preview::{Image, Mode};
    let mut p = preview();
    let fox_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/fox/Fox.glb");
    let fox = baked(pelt_io::load(&fox_path).expect("fox"), "skin-frame-fox.glb");
    let at = |time: f32| PoseAt {
        animation: "Walk".into(),
        time,
    };
    let cpu = posed(&fox, &at(0.35)).expect("CPU pose");
    // Loaded at 0.1 s (the CPU pose gives its first vertices), then skinned to 0.35 s.
    let gpu = skinned(&fox, &at(0.1)).expect("skinned");
    assert!(gpu.skin.is_some(), "the Fox skins on the GPU");
    let quad = builtin("quad").expect("quad");
    let scene = fox_scene(&fox_path, &cpu);
    let mut frame = |mesh: &pelt_preview::asset::MeshData, pose: Option<f32>| -> Image {
        let d = p
            .prepare_loaded(
                &scene,
                &[mesh.clone(), quad.clone()],
                &[0, 1],
                Mode::Inferred,
            )
            .expect("prepare");
        if let Some(t) = pose {
            let n = p.pose(&d, "Walk", t, &fox_path).expect("pose");
            assert_eq!(n, 1);
        }
        p.render(&d).expect("render")
    };
    let reference = frame(&cpu, None);
    let unposed = frame(&gpu, None);
    let got = frame(&gpu, Some(0.35));
    got.save(&out_dir().join("skin-gpu-frame.png"))
        .expect("write");
    let f = common::assert_flip("skin-gpu-frame", &reference, &got, 0.005);
    // Negative control: the same mesh not posed on the GPU (still at 0.1 s) is far off.
    let (g, _) = common::flip_mean(&reference, &unposed);
    eprintln!("GPU-skinned against CPU-posed: FLIP {f:.5}; unposed: {g:.5}");
    assert!(g > 0.005, "0.1 s and 0.35 s look alike: {g}");
    // An unknown clip is an error listing the clips.
    let d = p
        .prepare_loaded(
            &scene,
            &[gpu.clone(), quad.clone()],
            &[0, 1],
            Mode::Inferred,
        )
        .expect("prepare");
    let e = p
        .pose(&d, "Trot", 0.0, &fox_path)
        .expect_err("no Trot")
        .to_string();
    assert!(e.contains("Survey, Walk, Run"), "{e}");
    // Fins that could not follow the skin (an edge list that is not the drawn fins') are
    // refused, naming the asset, rather than left at the rest pose while the body moves.
    let mut torn = gpu.clone();
    let mut binding = (**torn.skin.as_ref().expect("binding")).clone();
    assert!(
        !binding.fins.is_empty(),
        "the Fox's fins are rebuilt on the GPU"
    );
    binding.fins.pop();
    torn.skin = Some(std::sync::Arc::new(binding));
    let e = p
        .prepare_loaded(&scene, &[torn, quad], &[0, 1], Mode::Inferred)
        .map(|_| ())
        .expect_err("fins that cannot follow the skin")
        .to_string();
    assert!(e.contains("Fox.glb") && e.contains("fins"), "{e}");
}

#[test]
fn two_objects_sharing_one_animated_asset_stand_at_their_own_times() {
    use pelt_preview::asset::{PoseAt, builtin, skinned};
    use pelt_preview::scene::{Camera, Transform};
    use pelt_preview::{Image, Mode};
    let mut p = preview();
    let fox_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/fox/Fox.glb");
    let fox = baked(pelt_io::load(&fox_path).expect("fox"), "skin-pair-fox.glb");
    let rest = PoseAt {
        animation: "Walk".into(),
        time: 0.0,
    };
    let gpu = skinned(&fox, &rest).expect("skinned");
    let (lo, hi) = gpu.bounds();
    let ext = hi - lo;
    let centre = (lo + hi) / 2.0;
    // Two foxes nose to tail along z, seen from the side: one fills each half of the image.
    let mut scene = pelt_preview::procedural::fur_scene(&fox_path, lo, hi, 256, 96, 0.0);
    let mut second = scene.objects[0].clone();
    for (o, dz) in [(&mut scene.objects[0], -0.7), (&mut second, 0.7)] {
        o.transform = Transform {
            translation: [0.0, 0.0, dz * ext.z],
            ..Transform::default()
        };
    }
    scene.objects.push(second);
    scene.camera = Camera {
        position: [centre.x + 2.6 * ext.z, centre.y + 0.2 * ext.y, centre.z],
        target: centre.to_array(),
        up: [0.0, 1.0, 0.0],
        fov_y_deg: 40.0,
        near: 0.1 * ext.z,
        far: 10.0 * ext.z,
    };
    let (a, b) = (0.1, 0.6);
    let meshes = [gpu, builtin("quad").expect("quad")];
    let mesh_of = [0, 1, 0];
    let mut frame = |times: [f32; 2], name: &str| -> Image {
        let d = p
            .prepare_loaded(&scene, &meshes, &mesh_of, Mode::Inferred)
            .expect("prepare");
        for (object, t) in [(0, times[0]), (2, times[1])] {
            let posed = p
                .pose_object(&d, object, "Walk", t, &fox_path)
                .expect("pose");
            assert!(posed, "objects[{object}] skins on the GPU");
        }
        let i = p.render(&d).expect("render");
        i.save(&out_dir().join(format!("{name}.png")))
            .expect("write");
        i
    };
    let mixed = frame([a, b], "skin-pair-mixed");
    let both_a = frame([a, a], "skin-pair-a");
    let both_b = frame([b, b], "skin-pair-b");
    // The halves of the image, each holding one fox.
    let half = |i: &Image, right: bool| -> Image {
        let w = i.width / 2;
        let x0 = if right { w } else { 0 };
        let mut rgba = Vec::with_capacity((w * i.height * 4) as usize);
        for y in 0..i.height {
            let row = ((y * i.width + x0) * 4) as usize;
            rgba.extend_from_slice(&i.rgba[row..row + (w * 4) as usize]);
        }
        Image {
            width: w,
            height: i.height,
            rgba,
        }
    };
    // Which half shows which object depends on the camera; try both and take the match.
    let (l_a, r_b) = (
        common::flip_mean(&half(&both_a, false), &half(&mixed, false)).0,
        common::flip_mean(&half(&both_b, true), &half(&mixed, true)).0,
    );
    let (l_b, r_a) = (
        common::flip_mean(&half(&both_b, false), &half(&mixed, false)).0,
        common::flip_mean(&half(&both_a, true), &half(&mixed, true)).0,
    );
    let matched = (l_a.max(r_b)).min(l_b.max(r_a));
    // Negative control: the two times look different in each half.
    let apart = common::flip_mean(&half(&both_a, false), &half(&both_b, false))
        .0
        .min(common::flip_mean(&half(&both_a, true), &half(&both_b, true)).0);
    eprintln!("each half against its own time: FLIP {matched:.5}; the two times apart: {apart:.5}");
    assert!(apart > 0.01, "0.1 s and 0.6 s of Walk look alike: {apart}");
    assert!(
        matched <= 0.001,
        "a fox is not at its own time (FLIP {matched}); images in target/render-tests/"
    );
}

/// The bounding box (x0, y0, x1, y1) of the pixels where `a` and `b` differ by more than 4/255.
fn differing_box(a: &pelt_preview::Image, b: &pelt_preview::Image) -> Option<[u32; 4]> {
    let mut bbox: Option<[u32; 4]> = None;
    for (k, (pa, pb)) in a.rgba.chunks(4).zip(b.rgba.chunks(4)).enumerate() {
        if pa.iter().zip(pb).take(3).any(|(x, y)| x.abs_diff(*y) > 4) {
            let (x, y) = (k as u32 % a.width, k as u32 / a.width);
            let r = bbox.get_or_insert([x, y, x, y]);
            *r = [r[0].min(x), r[1].min(y), r[2].max(x), r[3].max(y)];
        }
    }
    bbox
}

/// Fur springs on the walking Fox (`pelt_scene::springs`): a scene loaded at a time (`pelt
/// render --animation --time`) and one loaded elsewhere and posed there (`pelt view`, contact
/// sheets) draw the same bytes; a soft spring
/// visibly moves the fur; an infinitely stiff one draws the rest pose byte for byte on both
/// paths; a limp, barely damped one never throws the fur further than its length.
#[test]
fn fur_springs_draw_alike_on_both_paths_and_a_rigid_one_draws_the_rest_pose() {
    use pelt_anim::spring::Spring;
    use pelt_preview::asset::{PoseAt, load_scene_at, skinned};
    use pelt_preview::scene::Material;
    use pelt_preview::{Image, Mode, Scene};
    let mut p = preview();
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/fox/Fox.glb");
    let fox = baked(pelt_io::load(&src).expect("fox"), "skin-spring-fox.glb");
    let path = out_dir().join("skin-spring-fox.glb");
    let at = |time: f32| PoseAt {
        animation: "Walk".into(),
        time,
    };
    let t = 0.35;
    let framed = skinned(&fox, &at(t)).expect("skinned");
    let scene = fox_scene(&path, &framed);
    // Fur of 3 units (the demo's) on a Fox about 150 units long.
    let length = 3.0;
    let with = |spring: Option<Spring>| -> Scene {
        let mut s = scene.clone();
        if let Material::Fur(f) = &mut s.objects[0].material {
            f.spring = spring;
            f.length = Some(length);
        }
        s
    };
    // Loaded at `t` (CPU posing; preparing bends the fur there), or at 0.1 s and posed to
    // `t` on the GPU (each pose writes the bends).
    let mut draw = |s: &Scene, gpu: bool, name: &str| -> Image {
        let (meshes, of) = load_scene_at(s, Some(&at(if gpu { 0.1 } else { t }))).expect("load");
        let d = p
            .prepare_loaded(s, &meshes, &of, Mode::Inferred)
            .expect("prepare");
        if gpu {
            assert_eq!(p.pose(&d, "Walk", t, &path).expect("pose"), 1);
        }
        let i = p.render(&d).expect("render");
        i.save(&out_dir().join(format!("skin-spring-{name}.png")))
            .expect("write");
        i
    };
    // About 5 Hz, a third of critical damping.
    let soft = Spring {
        stiffness: 1000.0,
        damping: 20.0,
    };
    let rigid = Spring {
        stiffness: f32::INFINITY,
        damping: 1.0,
    };
    let still_cpu = draw(&with(None), false, "none-cpu");
    let still_gpu = draw(&with(None), true, "none-gpu");
    let soft_cpu = draw(&with(Some(soft)), false, "soft-cpu");
    let soft_gpu = draw(&with(Some(soft)), true, "soft-gpu");
    assert!(
        draw(&with(Some(rigid)), false, "rigid-cpu").rgba == still_cpu.rgba,
        "rigid, CPU"
    );
    assert!(
        draw(&with(Some(rigid)), true, "rigid-gpu").rgba == still_gpu.rgba,
        "rigid, GPU"
    );
    // Both stand where the GPU skinned them, bent by the same springs: the same bytes.
    assert!(
        soft_cpu.rgba == soft_gpu.rgba,
        "loaded at t and posed to t differ"
    );
    // Negative control: the spring moved the fur.
    let (moved, _) = common::flip_mean(&still_cpu, &soft_cpu);
    eprintln!("soft spring against no spring: FLIP {moved:.5}");
    assert!(moved > 0.005, "the spring did not move the fur: {moved}");
    // Limp (k = 10⁻³/s², d = 10⁻³/s): offsets of hundreds of fur lengths; the fur still
    // reaches no further than its length beyond where it stands without a spring.
    let limp = draw(
        &with(Some(Spring {
            stiffness: 1.0e-3,
            damping: 1.0e-3,
        })),
        false,
        "limp",
    );
    let mut bare = with(None);
    bare.objects.remove(0);
    let (meshes, of) = load_scene_at(&bare, None).expect("load");
    let d = p
        .prepare_loaded(&bare, &meshes, &of, Mode::Inferred)
        .expect("prepare");
    let empty = p.render(&d).expect("render");
    let still_box = differing_box(&empty, &still_cpu).expect("the fox is in view");
    let limp_box = differing_box(&empty, &limp).expect("the fox is in view");
    let (lo, hi) = framed.bounds();
    // The fur's length in pixels at the fox's scale on screen, doubled, and a pixel.
    let px = (still_box[3] - still_box[1]) as f32 * length / (hi - lo).y;
    let m = (2.0 * px).ceil() as u32 + 1;
    eprintln!("fox {still_box:?}, limp spring {limp_box:?}, margin {m} px");
    assert!(
        limp_box[0] + m >= still_box[0]
            && limp_box[1] + m >= still_box[1]
            && limp_box[2] <= still_box[2] + m
            && limp_box[3] <= still_box[3] + m,
        "{limp_box:?} beyond {still_box:?} ± {m}"
    );
}
