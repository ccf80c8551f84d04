//! What `pelt view` is asked to do ([`ViewArgs`], `pelt view`'s flags with the `cli` feature)
//! and the window size it asks for: below the window ([`crate::app`]) and the crate root,
//! which both read them.

use std::path::PathBuf;

use pelt_preview::knobs::Knobs;
use pelt_preview::{Backend, Mode};

/// What `pelt view` was asked to do. With the `cli` feature this is `pelt view`'s flags
/// (clap's `Args`), written here once.
#[derive(Debug, Clone)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
pub struct ViewArgs {
    /// A scene file (.json) or an asset (.glb, .gltf, .obj).
    pub input: PathBuf,
    /// inferred (low-resolution L-buffer, DSF), deferred (full-resolution L-buffer, no DSF),
    /// forward (per-object light loop, the reference), strands (explicit strands, the fur's
    /// reference), debug-groups (each normal group in a flat colour, neighbours distinct) or
    /// debug-comb (the decoded comb as colour, its length as brightness); M cycles them.
    #[cfg_attr(feature = "cli", arg(long, default_value = "inferred"))]
    pub mode: Mode,
    /// wgpu back end: auto, vulkan or gl.
    #[cfg_attr(feature = "cli", arg(long, default_value = "auto"))]
    pub backend: Backend,
    /// The knobs ([ ], D, - =, I and B change them in the window); `--size` is the window's
    /// (default: a scene's output size, or 960x540 for an asset).
    #[cfg_attr(feature = "cli", command(flatten))]
    pub knobs: Knobs,
    /// Target frame time (ms) while the camera moves: L-buffer scale, shells and then
    /// resolution are lowered to hold it; a still camera gets the full-quality frame.
    #[cfg_attr(feature = "cli", arg(long, value_name = "MS", default_value_t = 66.0, value_parser = pelt_preview::flags::positive_ms))]
    pub budget_ms: f64,
    /// Reload the shaders from this folder when they change (debug builds: the source
    /// tree's shaders/ by default).
    #[cfg_attr(feature = "cli", arg(long, value_name = "DIR"))]
    pub shaders: Option<PathBuf>,
    /// Scripted: draw this many frames, then exit (with --screenshot, save the last).
    #[cfg_attr(feature = "cli", arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..)))]
    pub frames: Option<u32>,
    /// Scripted: write the still, full-quality frame after the last one to this PNG.
    #[cfg_attr(feature = "cli", arg(long, value_name = "FILE", requires = "frames"))]
    pub screenshot: Option<PathBuf>,
    /// Scripted: draw the text overlay too (it is off in scripted mode, so screenshots are
    /// the plain render).
    #[cfg_attr(feature = "cli", arg(long, requires = "frames"))]
    pub overlay: bool,
    /// Scripted: orbit the camera this many degrees before each frame after the first.
    #[cfg_attr(
        feature = "cli",
        arg(
            long,
            value_name = "DEG",
            default_value_t = 0.0,
            requires = "frames",
            allow_negative_numbers = true
        )
    )]
    pub orbit: f32,
    /// Print nothing but errors.
    #[cfg_attr(feature = "cli", arg(short, long))]
    pub quiet: bool,
    /// An animated asset's clip to start with (default: its first; `pelt inspect` lists
    /// them). The window plays it: Space plays and pauses, `,` `.` step a frame, C picks
    /// the next clip.
    #[cfg_attr(feature = "cli", arg(long, value_name = "NAME"))]
    pub animation: Option<String>,
    /// Seconds into the clip (or, for a scene with wind and no animation, into the scene) to
    /// start at: a paused frame at T draws as `pelt render --time T`.
    #[cfg_attr(feature = "cli", arg(long, value_name = "SECONDS", default_value_t = 0.0, value_parser = pelt_preview::flags::finite, allow_negative_numbers = true))]
    pub time: f32,
    /// Scripted: advance the clip (or the wind) one 1/30 s frame per frame drawn (the window
    /// always plays).
    #[cfg_attr(feature = "cli", arg(long, requires = "frames"))]
    pub play: bool,
}

/// Window size for an asset without `--size`.
pub const DEFAULT_SIZE: (u32, u32) = (960, 540);

/// The window size `args` ask for: `--size`, a scene file's output size, or
/// [`DEFAULT_SIZE`].
pub fn window_size(args: &ViewArgs) -> (u32, u32) {
    if let Some(s) = args.knobs.size {
        return s;
    }
    if pelt_preview::knobs::is_scene(&args.input)
        && let Ok(s) = pelt_preview::Scene::load(&args.input)
    {
        return (s.output.width, s.output.height);
    }
    DEFAULT_SIZE
}
