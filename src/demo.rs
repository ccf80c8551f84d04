//! `pelt demo`: runs `pelt_measure::demo` and says what it wrote.

use std::process::ExitCode;

use pelt_measure::demo::{self, DemoOptions};
use pelt_preview::Preview;

use crate::DemoArgs;

/// Runs `pelt demo`.
pub fn run(args: &DemoArgs) -> anyhow::Result<ExitCode> {
    let mut preview = Preview::new(args.backend)?;
    if !args.quiet {
        eprintln!("adapter: {}", preview.adapter());
    }
    let t0 = std::time::Instant::now();
    let options = DemoOptions {
        output: args.output.clone(),
        size: args.size,
        frames: args.frames,
        shells: args.shells,
        fur_blend: args.fur_blend,
    };
    let out = demo::run(&mut preview, &options)?;
    if !args.quiet {
        let files: Vec<String> = out
            .files
            .iter()
            .map(|(f, what)| format!("{} ({what})", f.display()))
            .collect();
        let s = t0.elapsed().as_secs_f64();
        eprintln!("wrote {} in {s:.1} s", files.join(", "));
    }
    Ok(ExitCode::SUCCESS)
}
