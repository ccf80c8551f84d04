//! pelt-view: `pelt view`, the preview renderer in a window. An orbit camera (left drag,
//! right or shift drag, wheel, `F`), every knob of `pelt render` on a key, drag and drop,
//! reload when the open file or the shaders change on disk, screenshots, a scripted mode for
//! tests, and a frame budget that lowers quality while the camera moves.
//!
//! - [`controls`]: keys to actions, actions to settings;
//! - [`viewer`]: the open scene, camera, budget and drawing, apart from the window system;
//! - [`watch`]: polling files for changes;
//! - [`timeline`]: an animated asset's clip, time and play state;
//! - [`app`]: the winit window and its event loop;
//! - [`args`]: what `pelt view` is asked to do, and the window size it asks for.

pub mod app;
pub mod args;
pub mod controls;
pub mod timeline;
pub mod viewer;
pub mod watch;

pub use args::{DEFAULT_SIZE, ViewArgs, window_size};
pub use viewer::{AnimationError, ViewError, WindowError};

/// Opens the window and runs until it closes (or the scripted frames are drawn).
pub fn run(args: ViewArgs) -> Result<(), ViewError> {
    let el = winit::event_loop::EventLoop::new().map_err(WindowError::from)?;
    let mut app = app::App::new(args);
    el.run_app(&mut app).map_err(WindowError::from)?;
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}
