//! Frame-by-frame measurement of a camera orbit (`pelt render --bench N --orbit DEG --json`):
//! each frame's wall time (plan, uniforms, encode, submit, wait for the device) and the bytes
//! it wrote to GPU buffers and textures. Frame 0 includes preparing the scene: its meshes,
//! fur textures and sky uploads and its pipelines; every later frame moves the camera by the
//! orbit step and may write only uniforms. After the orbit, the last view is profiled
//! ([`Timings`]): per pass, device time, CPU encode time, draws and state changes.

use std::time::Instant;

use serde::Serialize;

use crate::asset::MeshData;
use crate::orbit::Orbit;
use crate::{Mode, Preview, RenderError, Scene, Timings};

/// One frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FrameStat {
    /// Frame index (0: the first, with the scene's uploads).
    pub frame: usize,
    /// Wall time, milliseconds.
    pub ms: f64,
    /// Bytes written to GPU buffers and textures during the frame.
    pub upload_bytes: u64,
}

/// An orbit's frames.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OrbitBench {
    /// The adapter.
    pub adapter: String,
    /// The mode.
    pub mode: String,
    /// Output size.
    pub size: [u32; 2],
    /// Degrees turned per frame.
    pub orbit_deg: f32,
    /// Every frame.
    pub frames: Vec<FrameStat>,
    /// Median time of the frames after the first.
    pub median_ms: f64,
    /// Largest upload of a frame after the first.
    pub max_upload_after_first: u64,
    /// Where a frame's time goes at the orbit's last view: per pass, the device's time, the
    /// CPU's encode time and the draws, state changes and triangles; the frame's encode and
    /// submit time ([`Timings`]).
    pub profile: Timings,
}

/// `orbit 5°/frame: 20 frames, median 3.10 ms after the first (…)`: the report in one line.
impl std::fmt::Display for OrbitBench {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let first = self.frames.first();
        write!(
            f,
            "orbit {}°/frame: {} frames, median {:.2} ms after the first ({:.2} ms, {} bytes uploaded); at most {} bytes uploaded per later frame",
            self.orbit_deg,
            self.frames.len(),
            self.median_ms,
            first.map_or(0.0, |f| f.ms),
            first.map_or(0, |f| f.upload_bytes),
            self.max_upload_after_first
        )
    }
}

/// Renders `frames` frames of `scene`, turning the camera `deg` degrees about its target's
/// up axis before each frame after the first.
pub fn orbit(
    preview: &mut Preview,
    scene: &Scene,
    meshes: &[MeshData],
    mesh_of: &[usize],
    mode: Mode,
    frames: usize,
    deg: f32,
) -> Result<OrbitBench, RenderError> {
    preview.take_uploaded();
    let mut stats = Vec::with_capacity(frames);
    let mut orbit = Orbit::new(&scene.camera);
    let t0 = Instant::now();
    let mut sv = preview.prepare_loaded(scene, meshes, mesh_of, mode)?;
    for k in 0..frames {
        let t = if k == 0 { t0 } else { Instant::now() };
        if k > 0 {
            orbit.rotate(deg.to_radians(), 0.0);
            preview.look(&mut sv, &orbit.camera())?;
        }
        preview.draw(&sv)?;
        stats.push(FrameStat {
            frame: k,
            ms: t.elapsed().as_secs_f64() * 1e3,
            upload_bytes: preview.take_uploaded(),
        });
    }
    let profile = preview.time(&sv, 0, frames.saturating_sub(1).max(1))?;
    let mut later: Vec<f64> = stats.iter().skip(1).map(|s| s.ms).collect();
    later.sort_by(f64::total_cmp);
    Ok(OrbitBench {
        adapter: preview.adapter(),
        mode: mode.to_string(),
        size: [scene.output.width, scene.output.height],
        orbit_deg: deg,
        median_ms: later.get(later.len() / 2).copied().unwrap_or(0.0),
        max_upload_after_first: stats
            .iter()
            .skip(1)
            .map(|s| s.upload_bytes)
            .max()
            .unwrap_or(0),
        frames: stats,
        profile,
    })
}
