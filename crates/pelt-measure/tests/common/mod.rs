//! Helpers shared by pelt-measure's pixel tests: the adapter (`PELT_BACKEND=gl|vulkan|auto`),
//! the folder a test leaves its images in, and the images a failed comparison leaves.

#![allow(dead_code, reason = "each test binary uses a subset of the helpers")]

use std::path::PathBuf;

use pelt_measure::Flip;
use pelt_preview::{Backend, Image, Preview};

/// A preview on the back end `PELT_BACKEND` names (default: wgpu's choice).
pub fn preview() -> Preview {
    let backend: Backend = std::env::var("PELT_BACKEND")
        .ok()
        .map(|b| b.parse().expect("PELT_BACKEND is vulkan, gl or auto"))
        .unwrap_or_default();
    let p = Preview::new(backend).expect("a wgpu adapter (Mesa's llvmpipe or lavapipe)");
    eprintln!("adapter: {}", p.adapter());
    p
}

/// `target/render-tests/`, created.
pub fn out_dir() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/render-tests");
    std::fs::create_dir_all(&dir).expect("target/render-tests");
    dir
}

/// Leaves `NAME-reference.png`, `NAME-actual.png` and the FLIP heat map `NAME-diff.png` in
/// [`out_dir`].
pub fn save_failure(name: &str, reference: &Image, test: &Image) {
    let dir = out_dir();
    let f = Flip::new(reference, test).expect("same size");
    reference
        .save(&dir.join(format!("{name}-reference.png")))
        .expect("write");
    test.save(&dir.join(format!("{name}-actual.png")))
        .expect("write");
    f.heat_map()
        .save(&dir.join(format!("{name}-diff.png")))
        .expect("write");
}

/// The pixels farther than `r` pixels (in x and y) from every pixel of `mask`.
pub fn away_from(mask: &[bool], width: usize, r: usize) -> Vec<bool> {
    let height = mask.len() / width;
    (0..mask.len())
        .map(|i| {
            let (x, y) = (i % width, i / width);
            let ys = y.saturating_sub(r)..=(y + r).min(height - 1);
            !ys.into_iter().any(|yy| {
                (x.saturating_sub(r)..=(x + r).min(width - 1)).any(|xx| mask[yy * width + xx])
            })
        })
        .collect()
}
