//! pelt-preview: the preview renderer for baked assets.
//!
//! This first step holds the CPU side that the wgpu passes (issue 5: G-buffer, L-buffer, DSF
//! material pass, stippled alpha; Kircher & Lawrance) will run on:
//!
//! - [`scene`]: the scene file (objects, materials, point lights, camera, output size,
//!   L-buffer scale, DSF), with errors naming file, line and field;
//! - [`procedural`]: generated scenes for tests and benchmarks (grids of objects, seeded
//!   random lights, the paper's two experiments).

pub mod procedural;
pub mod scene;

pub use scene::{Scene, SceneError};
