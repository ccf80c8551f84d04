//! The baked format's tangent-frame rule has one definition, `pelt_geom::frame`, that the
//! bake, `pelt inspect` and the preview's CPU side call; the shaders' `comb_object`
//! (fur_common.wgsl) is its GPU half. This test runs the shader as a compute pass
//! (tangent_frames.wgsl: storage buffer in, storage buffer out) over ordinary and degenerate
//! frames (zero tangent, tangent along the normal, zero normal, mirrored, a comb with no
//! direction) and asserts the GPU's directions are the CPU's.

mod common;

use glam::{DVec3, Vec3, Vec4};
use pelt_geom::frame::Frame;
use pelt_preview::renderer::ComputeDesc;

use common::preview;

/// Runs `shader`'s pipeline over `n` items (64 a workgroup) with `groups` bound in order, and reads
/// `output` back.
fn run_compute(
    r: &pelt_preview::renderer::Renderer,
    shader: &ComputeDesc,
    groups: &[&wgpu::BindGroup],
    n: usize,
    output: &wgpu::Buffer,
) -> Vec<u8> {
    let pipeline = r.compute(shader).expect("compute pipeline");
    let mut enc = r
        .gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
    {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
        pass.set_pipeline(&pipeline);
        for (k, g) in groups.iter().enumerate() {
            pass.set_bind_group(k as u32, *g, &[]);
        }
        pass.dispatch_workgroups((n as u32).div_ceil(64), 1, 1);
    }
    r.gpu.queue.submit([enc.finish()]);
    pelt_preview::frame::read_buffer(r, output).expect("read back")
}

/// A storage buffer the shader writes and the test reads back.
fn output_buffer(r: &pelt_preview::renderer::Renderer, label: &str, size: usize) -> wgpu::Buffer {
    r.gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// (normal, tangent, comb) records: every case the fallback handles, and a spread of
/// ordinary ones.
fn records() -> Vec<[Vec4; 3]> {
    let mut v = vec![
        [
            Vec4::new(0.0, 0.0, 2.0, 0.0),
            Vec4::new(1.0, 0.0, 0.3, 1.0),
            Vec4::new(0.3, -0.4, 0.5, 0.0),
        ],
        // Mirrored (w < 0).
        [
            Vec4::new(0.0, 1.0, 0.0, 0.0),
            Vec4::new(1.0, 0.0, 0.0, -1.0),
            Vec4::new(0.2, 0.9, 0.1, 0.0),
        ],
        // Zero tangent: the least-aligned axis.
        [
            Vec4::new(0.0, 1.0, 0.0, 0.0),
            Vec4::ZERO,
            Vec4::new(1.0, 0.0, 0.0, 0.0),
        ],
        // Tangent along the normal.
        [
            Vec4::new(0.0, 1.0, 0.0, 0.0),
            Vec4::new(0.0, 5.0, 0.0, 1.0),
            Vec4::new(0.0, 1.0, 0.0, 0.0),
        ],
        // Ties in the least-aligned axis (x first, then y).
        // (A comb along tangent-space x reads T itself.)
        [
            Vec4::new(0.0, 0.0, 1.0, 0.0),
            Vec4::ZERO,
            Vec4::new(1.0, 0.0, 0.0, 0.0),
        ],
        [
            Vec4::new(1.0, 0.0, 0.0, 0.0),
            Vec4::ZERO,
            Vec4::new(1.0, 0.0, 0.0, 0.0),
        ],
        // Zero normal: +Z.
        [
            Vec4::ZERO,
            Vec4::new(1.0, 0.0, 0.0, 1.0),
            Vec4::new(0.0, 1.0, 0.0, 0.0),
        ],
        // A comb with no direction: the tangent.
        [
            Vec4::new(0.0, 0.0, 1.0, 0.0),
            Vec4::new(0.0, 1.0, 0.0, 1.0),
            Vec4::ZERO,
        ],
    ];
    // Ordinary frames: a deterministic spread.
    let mut x = 0x2545_f491_u32;
    let mut rnd = || {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        x as f32 / u32::MAX as f32 * 2.0 - 1.0
    };
    for _ in 0..500 {
        let n = Vec4::new(rnd(), rnd(), rnd(), 0.0);
        let t = Vec4::new(rnd(), rnd(), rnd(), if rnd() < 0.0 { -1.0 } else { 1.0 });
        let c = Vec4::new(rnd(), rnd(), rnd().abs(), 0.0);
        if n.truncate().length() > 0.1 && t.truncate().length() > 0.1 {
            v.push([n, t, c]);
        }
    }
    v
}

fn cpu(r: &[Vec4; 3]) -> Vec3 {
    let (f, _) = Frame::new(r[0].truncate(), r[1]);
    f.comb_direction(r[2].truncate().as_dvec3()).as_vec3()
}

fn gpu(records: &[[Vec4; 3]]) -> Vec<Vec3> {
    let p = preview();
    let r = &p.renderer;
    let flat: Vec<[f32; 4]> = records
        .iter()
        .flat_map(|r| r.map(|v| v.to_array()))
        .collect();
    let input = r.gpu.buffer_init(
        "records",
        bytemuck::cast_slice(&flat),
        wgpu::BufferUsages::STORAGE,
    );
    let output = output_buffer(r, "directions", records.len() * 16);
    let group = r.storage_group(&input, &output);
    let bytes = run_compute(
        r,
        &pelt_preview::features::fur::TANGENT_FRAMES,
        &[&group],
        records.len(),
        &output,
    );
    let out: &[[f32; 4]] = bytemuck::cast_slice(&bytes);
    out.iter().map(|v| Vec3::new(v[0], v[1], v[2])).collect()
}

#[test]
fn the_shaders_comb_directions_are_pelt_geoms() {
    let rs = records();
    let got = gpu(&rs);
    let mut worst = 0.0_f32;
    for (k, (r, g)) in rs.iter().zip(&got).enumerate() {
        let want = cpu(r);
        let err = (want - *g).length();
        worst = worst.max(err);
        assert!(err < 1e-4, "record {k} {r:?}: GPU {g}, CPU {want}");
    }
    eprintln!("{} frames, largest difference {worst:.2e}", rs.len());
    // The degenerate cases land where the rule says.
    assert!((got[2] - Vec3::X).length() < 1e-6, "zero tangent: x axis");
    assert!((got[4] - Vec3::X).length() < 1e-6, "tie: x first");
    assert!((got[5] - Vec3::Y).length() < 1e-6, "tie: then y");
    assert!((got[7] - Vec3::Y).length() < 1e-6, "no comb: the tangent");
    // And the CPU rule is the bake's: to_tangent then comb_direction round-trips.
    let (f, _) = Frame::new(Vec3::new(0.2, 0.9, 0.1), Vec4::new(1.0, 0.0, 0.0, -1.0));
    let d = DVec3::new(0.6, 0.0, 0.8);
    assert!((f.comb_direction(f.to_tangent(d)) - d).length() < 1e-12);
}

/// Fin records (docs/format.md, version 2) of an open sphere (poles degenerate, a UV seam, a
/// hole cut for boundary edges), decoded by fin_records.wgsl on the GPU and by
/// `pelt_io::topology::fin_geometry` on the CPU.
#[test]
fn the_shaders_fin_decode_is_pelt_ios() {
    use pelt_geom::topology::{self, CornerNormals, TopologyOptions};
    let shape = pelt_fixtures::shapes::sphere(12, 24);
    // Cut a hole: drop 20 triangles, so some edges have one face.
    let indices: Vec<u32> = shape.indices[60..].to_vec();
    let mut t = topology::build(
        &shape.positions,
        &indices,
        CornerNormals::Vertex(&shape.normals),
        &TopologyOptions::default(),
    );
    let edges = t.take_edges();
    // Through the file's encoding and back.
    let view = pelt_io::topology::fins_view(edges);
    let records = pelt_io::topology::decode_fins(view.bytes());
    assert!(
        records.iter().any(|e| e.second_face().is_none()),
        "no boundary"
    );
    assert!(records.len() > 500);

    let p = preview();
    let r = &p.renderer;
    let storage =
        |label: &str, bytes: &[u8]| r.gpu.buffer_init(label, bytes, wgpu::BufferUsages::STORAGE);
    let fins = storage("fins", view.bytes());
    let idx = storage("indices", bytemuck::cast_slice(&indices));
    let pos: Vec<f32> = shape.positions.iter().flat_map(|p| p.to_array()).collect();
    let positions = storage("positions", bytemuck::cast_slice(&pos));
    let output = output_buffer(r, "decoded", records.len() * 48);
    let (g0, g1) = (
        r.storage_group(&fins, &output),
        r.storage_group(&idx, &positions),
    );
    let bytes = run_compute(
        r,
        &pelt_preview::features::fur::FIN_RECORDS,
        &[&g0, &g1],
        records.len(),
        &output,
    );
    let words: &[u32] = bytemuck::cast_slice(&bytes);
    let mut worst = 0.0_f32;
    for (k, (e, w)) in records.iter().zip(words.chunks_exact(12)).enumerate() {
        let cpu = pelt_io::topology::fin_geometry(e, &indices, &shape.positions);
        assert_eq!([w[0], w[1]], cpu.vertices, "record {k} {e:?}: vertices");
        assert_eq!(
            w[2] == 1,
            e.second_face().is_none(),
            "record {k}: boundary flag"
        );
        for (n, at) in cpu.face_normals.iter().zip([4, 8]) {
            let g = Vec3::new(
                f32::from_bits(w[at]),
                f32::from_bits(w[at + 1]),
                f32::from_bits(w[at + 2]),
            );
            let err = (g - *n).length();
            worst = worst.max(err);
            assert!(err < 1e-5, "record {k} {e:?}: GPU normal {g}, CPU {n}");
        }
    }
    eprintln!(
        "{} fin records: worst normal difference {worst:e}",
        records.len()
    );
}
