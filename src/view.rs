//! `pelt view`: the flags into [`pelt_view::ViewArgs`]; the window lives in `pelt-view`.

use std::process::ExitCode;

use pelt_preview::knobs::Knobs;

use crate::ViewArgs;

/// The source tree's shaders, for reloading in debug builds.
fn default_shaders() -> Option<std::path::PathBuf> {
    if !cfg!(debug_assertions) {
        return None;
    }
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    dir.is_dir().then_some(dir)
}

/// Runs `pelt view`.
pub fn run(args: &ViewArgs) -> anyhow::Result<ExitCode> {
    let view = pelt_view::ViewArgs {
        input: args.input.clone(),
        backend: args.knobs.backend,
        mode: match args.knobs.mode {
            crate::RenderMode::Gpu(m) => m,
            crate::RenderMode::Raytrace => anyhow::bail!(
                "--mode raytrace is pelt render's (the CPU ray tracer writes a PNG); pelt view takes inferred, deferred, forward, strands, debug-groups or debug-comb"
            ),
        },
        // The size is the window's, not an override of the scene's.
        knobs: Knobs {
            size: None,
            ..args.knobs.knobs()
        },
        size: args.knobs.size,
        frames: args.frames,
        screenshot: args.screenshot.clone(),
        orbit: args.orbit,
        budget_ms: args.budget_ms,
        shaders: args.shaders.clone().or_else(default_shaders),
        overlay: args.overlay,
        quiet: args.quiet,
        animation: args.animation.clone(),
        time: args.time,
        play: args.play,
    };
    match pelt_view::run(view) {
        Ok(()) => Ok(ExitCode::SUCCESS),
        Err(e) => {
            eprintln!("pelt: {e}");
            Ok(ExitCode::from(1))
        }
    }
}
