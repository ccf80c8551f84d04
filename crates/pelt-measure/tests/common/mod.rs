//! Helpers shared by pelt-measure's pixel tests: the adapter (`PELT_BACKEND=gl|vulkan|auto`)
//! and the folder a test leaves its images in.

use std::path::PathBuf;

use pelt_preview::{Backend, Preview};

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
