//! pelt-view: `pelt view`, the preview renderer in a window. An orbit camera (left drag,
//! right or shift drag, wheel, `F`), every knob of `pelt render` on a key, drag and drop,
//! reload when the open file or the shaders change on disk, screenshots, a scripted mode for
//! tests, and a frame budget that lowers quality while the camera moves.
//!
//! - [`controls`]: keys to actions, actions to settings;
//! - [`viewer`]: the open scene, camera, budget and drawing, apart from the window system;
//! - [`watch`]: polling files for changes;
//! - [`timeline`]: an animated asset's clip, time and play state;
//! - [`app`]: the winit window and its event loop.

pub mod app;
pub mod controls;
pub mod timeline;
pub mod viewer;
pub mod watch;

use std::path::PathBuf;

use pelt_preview::knobs::Knobs;
use pelt_preview::{Backend, Mode};

pub use viewer::ViewError;

/// What `pelt view` was asked to do.
#[derive(Debug, Clone)]
pub struct ViewArgs {
    /// A scene file or an asset.
    pub input: PathBuf,
    /// wgpu back end.
    pub backend: Backend,
    /// Lighting mode.
    pub mode: Mode,
    /// Knob overrides (`size` is the window's).
    pub knobs: Knobs,
    /// Window size (None: a scene file's output size, else [`DEFAULT_SIZE`]).
    pub size: Option<(u32, u32)>,
    /// Scripted mode: draw this many frames, then exit.
    pub frames: Option<u32>,
    /// Scripted mode: write the still full-quality frame after the last one here.
    pub screenshot: Option<PathBuf>,
    /// Scripted mode: degrees to orbit before each frame after the first.
    pub orbit: f32,
    /// Target frame time while the camera moves, milliseconds.
    pub budget_ms: f64,
    /// Folder to reload the shaders from when they change.
    pub shaders: Option<PathBuf>,
    /// Show the text overlay in scripted mode too (the window always starts with it).
    pub overlay: bool,
    /// Print only errors.
    pub quiet: bool,
    /// The clip an animated asset starts with (None: its first).
    pub animation: Option<String>,
    /// Seconds into it.
    pub time: f32,
    /// Scripted mode: advance the clip one 1/30 s frame per frame drawn (the window always
    /// starts playing).
    pub play: bool,
}

/// Window size for an asset without `--size`.
pub const DEFAULT_SIZE: (u32, u32) = (960, 540);

/// The window size `args` ask for: `--size`, a scene file's output size, or
/// [`DEFAULT_SIZE`].
pub fn window_size(args: &ViewArgs) -> (u32, u32) {
    if let Some(s) = args.size {
        return s;
    }
    if pelt_preview::knobs::is_scene(&args.input)
        && let Ok(s) = pelt_preview::Scene::load(&args.input)
    {
        return (s.output.width, s.output.height);
    }
    DEFAULT_SIZE
}

/// Opens the window and runs until it closes (or the scripted frames are drawn).
pub fn run(args: ViewArgs) -> Result<(), ViewError> {
    let el = winit::event_loop::EventLoop::new().map_err(|e| ViewError::Window(e.to_string()))?;
    let mut app = app::App::new(args);
    el.run_app(&mut app)
        .map_err(|e| ViewError::Window(e.to_string()))?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}
