//! `pelt view`: the window lives in `pelt-view`, whose `ViewArgs` are the flags.

use std::process::ExitCode;

use pelt_view::ViewArgs;

/// The source tree's shaders, for reloading in debug builds.
fn default_shaders() -> Option<std::path::PathBuf> {
    if !cfg!(debug_assertions) {
        return None;
    }
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    dir.is_dir().then_some(dir)
}

/// Runs `pelt view`.
pub fn run(mut args: ViewArgs) -> anyhow::Result<ExitCode> {
    args.shaders = args.shaders.or_else(default_shaders);
    match pelt_view::run(args) {
        Ok(()) => Ok(ExitCode::SUCCESS),
        Err(e) => {
            eprintln!("pelt: {e}");
            Ok(ExitCode::from(1))
        }
    }
}
