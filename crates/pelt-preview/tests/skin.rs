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
