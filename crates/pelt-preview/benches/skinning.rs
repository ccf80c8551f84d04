//! The skinning pass (skin.wgsl) measured: wall time of one dispatch (joint matrices written,
//! encoded, submitted, waited for) against vertex count, beside the same skinning on the CPU
//! (`SkinJob::on_cpu`, what `pelt pose` and today's `pelt render --animation` run), on
//! synthetic meshes with 24 joints and four weights a vertex; then the Fox at 16 shells: a
//! static furred frame, and the pass for its vertices. `PELT_BACKEND` picks the back end.
//! Run: `cargo bench -p pelt-preview --bench skinning`.

use std::path::Path;
use std::time::Instant;

use glam::{Mat4, Quat, Vec3, Vec4};
use pelt_anim::posed::{PoseReport, SkinJob};
use pelt_anim::skinning::Influences;
use pelt_io::PrimitiveRef;
use pelt_preview::features::skin::GpuSkin;
use pelt_preview::{Backend, Mode, Preview};

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// A job of `n` vertices on a 24-joint chain, weights from a fixed xorshift sequence.
fn job(n: usize) -> SkinJob {
    let mut x = 0x9e37_79b9_u32;
    let mut rnd = move || {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        x as f32 / u32::MAX as f32
    };
    let mut joints = Vec::with_capacity(n);
    let mut weights = Vec::with_capacity(n);
    let mut positions = Vec::with_capacity(n);
    for _ in 0..n {
        let j = [0, 1, 2, 3].map(|_| (rnd() * 23.99) as u16);
        let w = [rnd(), rnd(), rnd(), rnd()];
        let s: f32 = w.iter().sum();
        joints.push(j);
        weights.push(w.map(|w| w / s));
        positions.push(Vec3::new(rnd(), rnd(), rnd()));
    }
    let mats = (0..24)
        .map(|k| {
            Mat4::from_rotation_translation(
                Quat::from_rotation_z(0.05 * k as f32),
                Vec3::new(0.0, 0.1 * k as f32, 0.0),
            )
        })
        .collect();
    SkinJob {
        primitive: PrimitiveRef {
            mesh: 0,
            primitive: 0,
        },
        normals: Some(vec![Vec3::Z; n]),
        tangents: Some(vec![Vec4::new(1.0, 0.0, 0.0, 1.0); n]),
        positions,
        influences: Influences {
            joints: vec![joints],
            weights: vec![weights],
        },
        joints: Some(mats),
        unweighted: Mat4::IDENTITY,
    }
}

/// Median wall time (ms) of one skinning dispatch: matrices written, encoded, submitted,
/// waited for.
fn gpu_ms(p: &Preview, skin: &GpuSkin, j: &SkinJob) -> f64 {
    let r = &p.renderer;
    let mats = j.joints.clone().unwrap_or_default();
    let mut times = Vec::new();
    for k in 0..15 {
        let t = Instant::now();
        skin.set_pose(r, &mats, Mat4::IDENTITY);
        let mut enc = r
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        skin.encode(r, &mut enc).expect("skin pipeline");
        r.gpu.queue.submit([enc.finish()]);
        r.gpu
            .device
            .poll(wgpu::PollType::wait_indefinitely())
            .expect("poll");
        if k >= 3 {
            times.push(t.elapsed().as_secs_f64() * 1e3);
        }
    }
    median(times)
}

#[expect(
    clippy::expect_used,
    reason = "a benchmark binary: failing loudly is the point"
)]
fn main() {
    let backend: Backend = std::env::var("PELT_BACKEND")
        .ok()
        .and_then(|b| b.parse().ok())
        .unwrap_or_default();
    let mut p = Preview::new(backend).expect("adapter");
    println!("adapter: {}", p.adapter());
    println!(
        "| vertices | GPU pass ms (median of 12) | ns / vertex | CPU on_cpu ms (median of 5) |"
    );
    println!("|---|---|---|---|");
    for n in [1_000, 10_000, 100_000, 1_000_000] {
        let j = job(n);
        let skin = GpuSkin::new(&p.renderer, &j);
        let g = gpu_ms(&p, &skin, &j);
        let cpu = median(
            (0..5)
                .map(|_| {
                    let t = Instant::now();
                    let out = j.on_cpu(&mut PoseReport::default());
                    std::hint::black_box(out);
                    t.elapsed().as_secs_f64() * 1e3
                })
                .collect(),
        );
        println!("| {n} | {g:.3} | {:.1} | {cpu:.3} |", g * 1e6 / n as f64);
    }
    // The Fox at 16 shells: the furred frame static, and skinned (the pose changed on the GPU
    // before each frame), measured the same way: one frame encoded, submitted, waited for.
    let fox = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../out/bench/fox.glb");
    if !fox.exists() {
        println!("(run `cargo run --release -- demo -o out/bench` first for the Fox rows)");
        return;
    }
    let walk = |time: f32| pelt_preview::asset::PoseAt {
        animation: "Walk".to_owned(),
        time,
    };
    let mesh = pelt_preview::asset::load_at(&fox, Some(&walk(0.35))).expect("fox");
    assert!(mesh.skin.is_some(), "the Fox skins on the GPU");
    let (lo, hi) = mesh.bounds();
    let mut scene = pelt_preview::procedural::fur_scene(&fox, lo, hi, 1280, 720, 35.0);
    for o in &mut scene.objects {
        if let pelt_preview::scene::Material::Fur(f) = &mut o.material {
            f.shells = Some(16);
        }
    }
    let quad = pelt_preview::asset::builtin("quad").expect("quad");
    let d = p
        .prepare_loaded(
            &scene,
            &[mesh.clone(), quad.clone()],
            &[0, 1],
            Mode::Inferred,
        )
        .expect("prepare");
    let frame_ms = |p: &mut Preview, pose: Option<f32>| {
        let t = Instant::now();
        if let Some(time) = pose {
            p.pose(&d, "Walk", time, &fox).expect("pose");
        }
        p.time(&d, 0, 1).expect("frame");
        t.elapsed().as_secs_f64() * 1e3
    };
    for k in 0..2 {
        frame_ms(&mut p, Some(0.05 * k as f32));
    }
    let (mut stat, mut skinned) = (Vec::new(), Vec::new());
    for k in 0..9 {
        stat.push(frame_ms(&mut p, None));
        skinned.push(frame_ms(&mut p, Some(0.07 * k as f32)));
    }
    let jobs = pelt_anim::posed::skin_jobs(&pelt_io::load(&fox).expect("fox"), Some("Walk"), 0.35)
        .expect("jobs");
    let pass_ms: f64 = jobs
        .iter()
        .map(|j| gpu_ms(&p, &GpuSkin::new(&p.renderer, j), j))
        .sum();
    // The CPU alternative: pose, flatten, upload, draw.
    let cpu_posed = median(
        (0..5)
            .map(|k| {
                let t = Instant::now();
                let m = pelt_preview::asset::posed(
                    &pelt_io::load(&fox).expect("fox"),
                    &walk(0.1 * k as f32),
                )
                .expect("posed fox");
                let d = p
                    .prepare_loaded(&scene, &[m, quad.clone()], &[0, 1], Mode::Inferred)
                    .expect("prepare");
                p.time(&d, 0, 1).expect("frame");
                t.elapsed().as_secs_f64() * 1e3
            })
            .collect(),
    );
    println!();
    println!("| Fox, 1280×720, 16 shells + fins (median of 9) | ms |");
    println!("|---|---|");
    println!("| static furred frame | {:.2} |", median(stat));
    println!(
        "| skinned furred frame (pose on the GPU, then the frame) | {:.2} |",
        median(skinned)
    );
    println!(
        "| the skinning dispatch alone (skin.wgsl), {} vertices | {pass_ms:.3} |",
        mesh.vertices.len()
    );
    println!(
        "| CPU-posed frame: load, pose, flatten, upload, draw (median of 5) | {cpu_posed:.2} |"
    );
}
