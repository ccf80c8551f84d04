//! Helpers shared by the pixel tests: the adapter (`PELT_BACKEND=gl|vulkan|auto`), one
//! render, FLIP against a reference, and the images a failed comparison leaves in
//! `target/render-tests/`.

#![allow(dead_code, reason = "each test binary uses a subset of the helpers")]

use std::path::PathBuf;

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

/// FLIP mean error of `test` against `reference`.
pub fn flip_mean(reference: &Image, test: &Image) -> (f32, nv_flip::FlipImageFloat) {
    let rgb = |i: &Image| {
        let data: Vec<u8> = i
            .rgba
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        nv_flip::FlipImageRgb8::with_data(i.width, i.height, &data)
    };
    let err = nv_flip::flip(
        rgb(reference),
        rgb(test),
        nv_flip::DEFAULT_PIXELS_PER_DEGREE,
    );
    let mean = nv_flip::FlipPool::from_image(&err).mean();
    (mean, err)
}

/// Writes the three images of a failed comparison.
pub fn write_failure(name: &str, reference: &Image, test: &Image, err: &nv_flip::FlipImageFloat) {
    let dir = out_dir();
    reference
        .save(&dir.join(format!("{name}-reference.png")))
        .expect("write");
    test.save(&dir.join(format!("{name}-actual.png")))
        .expect("write");
    let rgb = err.apply_color_lut(&nv_flip::magma_lut()).to_vec();
    let rgba: Vec<u8> = rgb
        .chunks_exact(3)
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect();
    Image {
        width: err.width(),
        height: err.height(),
        rgba,
    }
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
