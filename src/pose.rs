//! `pelt pose`: load, pose on the CPU (`pelt_anim::posed`), write atomically. A failure
//! names the file and the place and writes nothing.

use std::process::ExitCode;

use crate::PoseArgs;

/// Runs `pelt pose`.
pub fn run(args: &PoseArgs) -> anyhow::Result<ExitCode> {
    crate::outputs::file(&args.output)?;
    if let Some(report) = &args.report {
        crate::outputs::file(report)?;
    }
    let result = pelt_io::Document::load(&args.input).and_then(|mut doc| {
        let report =
            pelt_anim::posed::pose_document(&mut doc, args.animation.as_deref(), args.time)?;
        pelt_io::glb::write_glb(&doc, &args.output)?;
        Ok(report)
    });
    let report = match result {
        Ok(r) => r,
        Err(e) => {
            eprintln!("pelt: {e}");
            return Ok(ExitCode::from(1));
        }
    };
    for w in &report.warnings {
        eprintln!("pelt: {}: warning: {w}", args.input.display());
    }
    if let Some(path) = &args.report {
        crate::write_json_report(path, &report)?;
    }
    eprintln!(
        "posed {} -> {}: {} at {:.3} s, {} primitives ({} vertices), {} animated nodes",
        args.input.display(),
        args.output.display(),
        report.animation.as_deref().unwrap_or("rest pose"),
        report.time,
        report.posed_primitives,
        report.posed_vertices,
        report.animated_nodes
    );
    Ok(ExitCode::SUCCESS)
}
