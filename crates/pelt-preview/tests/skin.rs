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
