//! `pelt render`: a scene file or one asset (framed by a default scene) to a PNG, with the
//! plan explained, and frame timing; `pelt render-bench`: the experiments' tables
//! (`pelt_measure::bench_run`) printed.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Context as _;
use pelt_preview::animate;
use pelt_preview::asset::PoseAt;
use pelt_preview::knobs::{self, InputError};
use pelt_preview::{Mode, Plan, Preview, RenderError, Scene};

use crate::RenderArgs;
use crate::progress::Progress;

/// Exit code for an input that could not be rendered.
const FAILED: u8 = 1;

/// Output size of an asset's default scene.
pub const DEFAULT_SIZE: (u32, u32) = (640, 360);

fn fail(e: impl std::fmt::Display) -> ExitCode {
    eprintln!("pelt: {e}");
    ExitCode::from(FAILED)
}

/// Runs `pelt render`.
pub fn run(args: &RenderArgs) -> anyhow::Result<ExitCode> {
    // Checked (its folder made) before minutes of rendering, not after.
    if let Some(out) = &args.output {
        crate::outputs::file(out)?;
    }
    if let (Some(frames), Some(animation)) = (args.frames, &args.animation) {
        return contact_sheet(args, animation, frames);
    }
    let pose = args.animation.as_ref().map(|a| PoseAt {
        animation: a.clone(),
        time: args.time,
    });
    let input = match knobs::load_at(
        &args.input,
        &args.knobs.overrides,
        DEFAULT_SIZE,
        pose.as_ref(),
    ) {
        Ok(i) => i,
        // A scene file's own errors are usage errors (2); an asset that cannot load fails (1).
        Err(InputError::Scene(e)) => return Err(e.into()),
        Err(e) => return Ok(fail(e)),
    };
    let (mut scene, meshes, of) = (input.scene, input.meshes, input.mesh_of);
    for w in meshes.iter().flat_map(|m| &m.warnings) {
        eprintln!("pelt: warning: {w}");
    }
    scene.time = args.time;
    let mode = match args.knobs.mode {
        crate::RenderMode::Gpu(m) => m,
        crate::RenderMode::Raytrace => return raytrace(args, &scene, &meshes, &of),
    };
    // A plan that cannot run is named with its scene before the GPU starts.
    let plan = match Plan::new(&scene, &meshes, &of, mode) {
        Ok(p) => p,
        Err(e) => return Ok(fail(format_args!("{}: {e}", args.input.display()))),
    };
    if args.explain {
        print!("{}", pelt_preview::explain(&plan));
        if args.output.is_none() && args.bench.is_none() {
            return Ok(ExitCode::SUCCESS);
        }
    }
    let mut preview = match Preview::new(args.knobs.backend) {
        Ok(p) => p,
        Err(e) => return Ok(fail(e)),
    };
    if !args.quiet {
        eprintln!("adapter: {}", preview.adapter());
    }
    if let (Some(frames), true) = (args.bench, args.json || args.orbit.is_some()) {
        let deg = args.orbit.unwrap_or(0.0);
        return Ok(
            match pelt_preview::bench::orbit(&mut preview, &scene, &meshes, &of, mode, frames, deg)
            {
                Ok(b) if args.json => {
                    println!("{}", serde_json::to_string_pretty(&b)?);
                    ExitCode::SUCCESS
                }
                Ok(b) => {
                    println!("{b}");
                    ExitCode::SUCCESS
                }
                Err(e) => fail(e),
            },
        );
    }
    if let (Mode::Strands, Some(out), None) = (mode, &args.output, args.bench) {
        for n in &plan.notes {
            eprintln!("pelt: note: {n}");
        }
        return Ok(strands(args, &mut preview, (&scene, &meshes, &of), out));
    }
    let result = (|| -> Result<(), RenderError> {
        let d = preview.prepare_loaded(&scene, &meshes, &of, mode)?;
        for n in &d.plan.notes {
            eprintln!("pelt: note: {n}");
        }
        if let Some(out) = &args.output {
            let image = preview.render(&d)?;
            image.save(out).map_err(RenderError::Frame)?;
            if !args.quiet {
                eprintln!(
                    "wrote {} ({}×{}, {} mode)",
                    out.display(),
                    image.width,
                    image.height,
                    mode
                );
            }
        }
        if let Some(frames) = args.bench {
            let t = preview.time(&d, args.warmup, frames)?;
            println!("{t}");
            if !args.quiet {
                print!("\n{}", t.profile_table());
            }
        }
        Ok(())
    })();
    Ok(match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => fail(e),
    })
}

/// `pelt render --mode strands -o`: the converged strand reference.
fn strands(
    args: &RenderArgs,
    preview: &mut Preview,
    (scene, meshes, of): (&Scene, &[pelt_preview::asset::MeshData], &[usize]),
    out: &Path,
) -> ExitCode {
    let opts = args.reference.options();
    let mut bar = Progress::new(("strand reference", "strands"), 1, args.quiet);
    bar.say(&format!(
        "strand reference: {}×{}, up to {} samples per pixel, until two halves of them agree \
         within FLIP {}",
        scene.output.width, scene.output.height, opts.max_samples, opts.target
    ));
    let mut steps = crate::progress::StrandSteps::default();
    let r = pelt_measure::strands::reference_with(preview, (scene, meshes, of), opts, &mut |s| {
        steps.show(&mut bar, s);
    });
    bar.finish();
    let r = match r {
        Ok(r) => r,
        Err(e) => return fail(e),
    };
    let r = match r.converged(opts.target) {
        Ok(r) => r,
        Err(e) => return fail(e),
    };
    if let Err(e) = r.image.save(out) {
        return fail(e);
    }
    if !args.quiet {
        let (w, h) = (r.image.width, r.image.height);
        eprintln!("wrote {} ({w}×{h}, strands mode: {r})", out.display());
    }
    ExitCode::SUCCESS
}

/// `pelt render --mode raytrace`: the CPU ray tracer's image of the scene.
fn raytrace(
    args: &RenderArgs,
    scene: &Scene,
    meshes: &[pelt_preview::asset::MeshData],
    of: &[usize],
) -> anyhow::Result<ExitCode> {
    if args.bench.is_some() {
        anyhow::bail!("--bench times GPU frames; the ray tracer reports its own time with -o");
    }
    let Some(out) = &args.output else {
        if args.explain {
            let casting = scene.lights.iter().filter(|l| l.shadows).count();
            let n = pelt_trace::FUR_SAMPLES;
            println!(
                "mode raytrace: one ray per pixel centre ({} per pixel in a scene with fur, its fur objects traced as their strands) through a BVH, up to {} specular bounces, shadow rays toward {casting} shadow-casting light(s), on the CPU",
                n * n,
                scene.reflections.max_depth
            );
        }
        return Ok(ExitCode::SUCCESS);
    };
    let start = std::time::Instant::now();
    let rows = scene.output.height;
    let bar = std::sync::Mutex::new(Progress::new(
        ("ray tracer", "rays"),
        u64::from(rows),
        args.quiet,
    ));
    let row_done = |n: u32| {
        if let Ok(mut b) = bar.lock() {
            let msg = format!("{n} rows, {:.0} s", start.elapsed().as_secs_f64());
            b.set(u64::from(n), &msg, false);
        }
    };
    let traced = pelt_trace::trace_scene_with(scene, meshes, of, &row_done);
    if let Ok(b) = bar.lock() {
        b.finish();
    }
    let traced = match traced {
        Ok(t) => t,
        Err(e) => return Ok(fail(e)),
    };
    let image = pelt_preview::Image {
        width: traced.width,
        height: traced.height,
        rgba: traced.rgba,
    };
    if let Err(e) = image.save(out) {
        return Ok(fail(e));
    }
    if !args.quiet {
        eprintln!(
            "wrote {} ({}×{}, raytrace mode, {:.2} s on {} threads)",
            out.display(),
            image.width,
            image.height,
            start.elapsed().as_secs_f64(),
            rayon::current_num_threads()
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// Runs `pelt render-bench`: the experiments' tables (`pelt_measure::bench_run`) printed.
pub fn bench(args: &pelt_measure::bench_run::Settings) -> anyhow::Result<ExitCode> {
    let mut preview = Preview::new(args.backend).context("opening the GPU device")?;
    println!("adapter: {}", preview.adapter());
    if let Some(dir) = &args.pictures {
        crate::outputs::folder(dir)?;
    }
    let quiet = args.quiet;
    let mut status = |line: &str| {
        if !quiet {
            eprintln!("{line}");
        }
    };
    pelt_measure::bench_run::run(&mut preview, args, &mut |md| print!("{md}"), &mut status)
        .context("render-bench")?;
    Ok(ExitCode::SUCCESS)
}

/// `--frames N`: N frames evenly over the clip (from its first key, not repeating the last),
/// the camera framed on the first, as one contact sheet (`pelt_preview::animate::Clip`).
fn contact_sheet(args: &RenderArgs, animation: &str, frames: u32) -> anyhow::Result<ExitCode> {
    let Some(out) = &args.output else {
        anyhow::bail!("--frames needs -o FILE.png");
    };
    if knobs::is_scene(&args.input) {
        anyhow::bail!("--frames takes an asset (.glb, .gltf), not a scene file");
    }
    let crate::RenderMode::Gpu(mode) = args.knobs.mode else {
        anyhow::bail!("--frames renders with the GPU modes");
    };
    let loaded =
        pelt_io::load(&args.input).and_then(|d| animate::clip_range(&d, animation).map(|c| (d, c)));
    let (doc, clip) = match loaded {
        Ok(l) => l,
        Err(e) => return Ok(fail(e)),
    };
    let mut k = args.knobs.overrides;
    let (w, h) = k.size.unwrap_or(DEFAULT_SIZE);
    k.size = Some(((w / 2).max(1), (h / 2).max(1)));
    let poses = animate::spread(animation, clip, frames);
    let first = match knobs::load_at(&args.input, &k, DEFAULT_SIZE, poses.first()) {
        Ok(i) => i,
        Err(e) => return Ok(fail(e)),
    };
    let mut preview = match Preview::new(args.knobs.backend) {
        Ok(p) => p,
        Err(e) => return Ok(fail(e)),
    };
    let sheet = animate::Clip {
        scene: &first.scene,
        meshes: &first.meshes,
        mesh_of: &first.mesh_of,
        doc: &doc,
        path: &args.input,
        mode,
    };
    let tiles = match sheet.frames(&mut preview, &poses) {
        Ok(t) => t,
        Err(e) => return Ok(fail(e)),
    };
    let sheet = pelt_preview::Image::contact_sheet(&tiles, 4);
    sheet.save(out).map_err(RenderError::Frame)?;
    if !args.quiet {
        eprintln!(
            "wrote {} ({frames} frames of {animation:?} from {:.3} to {:.3} s, {}×{})",
            out.display(),
            clip.0,
            clip.1,
            sheet.width,
            sheet.height
        );
    }
    Ok(ExitCode::SUCCESS)
}
