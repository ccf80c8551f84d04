//! Helpers shared by the pixel tests: the adapter (`PELT_BACKEND=gl|vulkan|auto`), one
//! render, FLIP against a reference, and the images a failed comparison leaves in
//! `target/render-tests/`.

#![allow(dead_code, reason = "each test binary uses a subset of the helpers")]

use std::path::PathBuf;

use glam::Vec3;
use pelt_bake::BakeOptions;
use pelt_bake::fur::{FurAssets, bake_with_fur};
use pelt_fixtures::build::{BuildOptions, ColorEncoding, document};
use pelt_fur::{FurConfig, StrandParams};
use pelt_measure::Flip;
use pelt_preview::asset::{MeshData, flatten};
use pelt_preview::fur::TextureSource;
use pelt_preview::scene::{
    Camera, FurBlend, FurSettings, Light, Material, Object, Size, Transform,
};
use pelt_preview::{Backend, Image, Mode, Preview, Scene};

pub fn preview() -> Preview {
    let backend: Backend = std::env::var("PELT_BACKEND")
        .ok()
        .map(|b| b.parse().expect("PELT_BACKEND is vulkan, gl or auto"))
        .unwrap_or_default();
    let p = Preview::new(backend)
        .expect("a wgpu adapter (install Mesa: libegl-mesa0, mesa-vulkan-drivers)");
    eprintln!("adapter: {}", p.adapter());
    let got = p.renderer.gpu.info.backend;
    match backend {
        Backend::Vulkan => assert_eq!(got, wgpu::Backend::Vulkan),
        Backend::Gl => assert_eq!(got, wgpu::Backend::Gl),
        Backend::Auto => {}
    }
    p
}

pub fn render(p: &mut Preview, scene: &Scene, mode: Mode) -> Image {
    let d = p.prepare(scene, mode).expect("prepare");
    p.render(&d).expect("render")
}

pub fn out_dir() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/render-tests");
    std::fs::create_dir_all(&dir).expect("target/render-tests");
    dir
}

/// FLIP mean error of `test` against `reference` (pelt-measure's, the one FLIP of the
/// project), and the comparison for `write_failure`.
pub fn flip_mean(reference: &Image, test: &Image) -> (f32, Flip) {
    let f = Flip::new(reference, test).expect("images of one size");
    (f.mean(), f)
}

/// Writes the three images of a failed comparison.
pub fn write_failure(name: &str, reference: &Image, test: &Image, err: &Flip) {
    let dir = out_dir();
    reference
        .save(&dir.join(format!("{name}-reference.png")))
        .expect("write");
    test.save(&dir.join(format!("{name}-actual.png")))
        .expect("write");
    err.heat_map()
        .save(&dir.join(format!("{name}-diff.png")))
        .expect("write");
}

/// Asserts FLIP mean ≤ `threshold`, writing the images when it is not. Returns the mean.
pub fn assert_flip(name: &str, reference: &Image, test: &Image, threshold: f32) -> f32 {
    let (mean, err) = flip_mean(reference, test);
    eprintln!("{name}: FLIP mean {mean:.5} (threshold {threshold})");
    if mean > threshold {
        write_failure(name, reference, test, &err);
        panic!("{name}: FLIP mean {mean:.5} > {threshold}; images in target/render-tests/");
    }
    mean
}

pub const LENGTH: f32 = 0.18;

/// The fixture sphere, baked with fur.
pub fn furry_sphere() -> MeshData {
    let mut doc = document(
        &pelt_fixtures::shapes::sphere(24, 48),
        BuildOptions {
            colors: ColorEncoding::U8x4,
            ..BuildOptions::default()
        },
    );
    let config = FurConfig {
        length: f64::from(LENGTH),
        uv_scale: 4.0,
        textures: StrandParams {
            size: 256,
            strands: 3000,
            radius: 0.005,
            ..StrandParams::default()
        },
        ..FurConfig::default()
    };
    let assets = FurAssets::new(config).expect("textures");
    bake_with_fur(&mut doc, &BakeOptions::default(), &assets).expect("bake");
    let m = flatten(&doc).expect("flatten");
    let fur = m.fur.as_ref().expect("baked fur");
    assert_eq!(fur.source, TextureSource::Baked);
    assert_eq!(fur.vertices.len(), m.vertices.len());
    assert!(!fur.fins.is_empty(), "the bake stores fin edges");
    assert!((fur.look.length - LENGTH).abs() < 1e-6);
    m
}

pub fn light(p: Vec3, color: Vec3, intensity: f32, radius: f32) -> Light {
    Light::point(p.into(), radius, intensity).with_color(color.into())
}

pub fn fur_object(settings: FurSettings) -> Object {
    Object {
        asset: PathBuf::from("sphere"),
        transform: Transform::default(),
        material: Material::Fur(settings),
        color: [1.0; 3],
    }
}

/// The furry sphere, lit by a key, a fill and a back light, on the flat background.
pub fn scene(shells: u32, fins: bool, blend: FurBlend) -> Scene {
    Scene {
        output: Size {
            width: 192,
            height: 144,
        },
        camera: Camera {
            position: [0.0, 0.6, 4.2],
            target: [0.0; 3],
            up: [0.0, 1.0, 0.0],
            fov_y_deg: 40.0,
            near: 0.5,
            far: 20.0,
        },
        ambient: [0.05; 3],
        objects: vec![fur_object(FurSettings {
            shells: Some(shells),
            fins: Some(fins),
            length: None,
            ..FurSettings::default()
        })],
        lights: vec![
            light(
                Vec3::new(2.5, 2.5, 3.0),
                Vec3::new(1.0, 0.95, 0.85),
                14.0,
                12.0,
            ),
            light(
                Vec3::new(-3.0, 0.5, 1.0),
                Vec3::new(0.5, 0.6, 1.0),
                5.0,
                10.0,
            ),
            light(Vec3::new(0.0, 1.0, -3.5), Vec3::ONE, 10.0, 10.0),
        ],
        fur_blend: blend,
        ..Scene::default()
    }
}

/// Sets every fur object's shell count.
pub fn set_shells(s: &mut Scene, shells: u32) {
    pelt_preview::knobs::Knobs {
        shells: Some(pelt_preview::knobs::ShellCount::Fixed(shells)),
        ..Default::default()
    }
    .apply(s);
}

pub mod reach;

/// The depth (0..1) of a `size` Depth32Float texture with `COPY_SRC` usage, row-major.
pub fn read_depth(
    r: &pelt_preview::Renderer,
    texture: &wgpu::Texture,
    size: (u32, u32),
) -> Vec<f32> {
    let row = (size.0 * 4).div_ceil(256) * 256;
    let buffer = r.gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("depth read"),
        size: u64::from(row * size.1),
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let mut enc = r
        .gpu
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor::default());
    enc.copy_texture_to_buffer(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::DepthOnly,
        },
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(size.1),
            },
        },
        wgpu::Extent3d {
            width: size.0,
            height: size.1,
            depth_or_array_layers: 1,
        },
    );
    r.gpu.queue.submit([enc.finish()]);
    let bytes = pelt_preview::frame::read_buffer(r, &buffer).expect("depth read back");
    bytes
        .chunks_exact(row as usize)
        .flat_map(|line| {
            line[..size.0 as usize * 4]
                .chunks_exact(4)
                .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        })
        .collect()
}
