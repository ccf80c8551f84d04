//! `pelt render`: a scene file or one asset (framed by a default scene) to a PNG, with the
//! plan explained, and frame timing; `pelt render-bench`: the inferred-lighting paper's two
//! experiments (Kircher & Lawrance §6) timed side by side on this machine's adapter.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Context as _;
use pelt_preview::asset::PoseAt;
use pelt_preview::knobs::{self, InputError, Knobs};
use pelt_preview::procedural::{paper_lbuffer_scale, paper_objects_and_lights};
use pelt_preview::{Mode, Plan, Preview, RenderError, Scene};

use crate::{RenderArgs, RenderBenchArgs};

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
    if let (Some(frames), Some(animation)) = (args.frames, &args.animation) {
        return contact_sheet(args, animation, frames);
    }
    let pose = args.animation.as_ref().map(|a| PoseAt {
        animation: a.clone(),
        time: args.time,
    });
    let input = match knobs::load_at(
        &args.input,
        &args.knobs.knobs(),
        DEFAULT_SIZE,
        pose.as_ref(),
    ) {
        Ok(i) => i,
        // A scene file's own errors are usage errors (2); an asset that cannot load fails (1).
        Err(InputError::Scene(e)) => return Err(e.into()),
        Err(e) => return Ok(fail(e)),
    };
    let (scene, meshes, of) = (input.scene, input.meshes, input.mesh_of);
    let mode = match args.knobs.mode {
        crate::RenderMode::Gpu(m) => m,
        crate::RenderMode::Raytrace => return raytrace(args, &scene, &meshes, &of),
    };
    if args.explain {
        match Plan::new(&scene, &meshes, &of, mode) {
            Ok(p) => print!("{}", p.explain()),
            Err(e) => return Ok(fail(e)),
        }
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
                    println!(
                        "orbit {deg}°/frame: {} frames, median {:.2} ms after the first ({:.2} ms, {} bytes uploaded); at most {} bytes uploaded per later frame",
                        b.frames.len(),
                        b.median_ms,
                        b.frames.first().map_or(0.0, |f| f.ms),
                        b.frames.first().map_or(0, |f| f.upload_bytes),
                        b.max_upload_after_first
                    );
                    ExitCode::SUCCESS
                }
                Err(e) => fail(e),
            },
        );
    }
    if let (Mode::Strands, Some(out), None) = (mode, &args.output, args.bench) {
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
            println!("{}", timings_line(&t));
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
    let r = match pelt_measure::strands::reference(preview, scene, meshes, of, opts) {
        Ok(r) => r,
        Err(e) => return fail(e),
    };
    if !r.converged {
        return fail(format!(
            "the strand reference did not converge: after {} samples the two halves differ by FLIP {:.4} (target {}); raise --max-samples or --target-flip; nothing written",
            r.samples, r.half_vs_half, opts.target
        ));
    }
    if let Err(e) = r.image.save(out) {
        return fail(e);
    }
    if !args.quiet {
        eprintln!(
            "wrote {} ({}×{}, strands mode: {} strands, {} samples per pixel in {} frames of {}×{}, half-vs-half FLIP {:.4}, {:.0} ms per frame)",
            out.display(),
            r.image.width,
            r.image.height,
            r.strands,
            r.samples,
            r.frames,
            r.grid,
            r.grid,
            r.half_vs_half,
            r.ms_per_frame
        );
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
            println!(
                "mode raytrace: one ray per pixel centre through a BVH, up to {} specular bounces, on the CPU",
                scene.reflections.max_depth
            );
        }
        return Ok(ExitCode::SUCCESS);
    };
    let start = std::time::Instant::now();
    let traced = match pelt_trace::trace_scene(scene, meshes, of) {
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

fn timings_line(t: &pelt_preview::Timings) -> String {
    let passes: Vec<String> = t
        .passes
        .iter()
        .map(|(p, ms)| format!("{} {ms:.2} ms", p.name()))
        .collect();
    format!(
        "frame {:.2} ms (median of {}); passes ({}): {}",
        t.frame_ms,
        t.frames,
        match t.clock {
            pelt_preview::PassClock::Gpu => "GPU timestamps",
            pelt_preview::PassClock::Wall => "wall time, each pass submitted alone",
        },
        passes.join(", ")
    )
}

/// Runs `pelt render-bench`.
pub fn bench(args: &RenderBenchArgs) -> anyhow::Result<ExitCode> {
    let mut preview = Preview::new(args.backend).context("opening the GPU device")?;
    println!("adapter: {}", preview.adapter());
    let asset = Path::new(&args.asset);
    let runs: Vec<(&str, Scene, Mode, &str)> = {
        let a = paper_objects_and_lights(asset);
        let b = paper_lbuffer_scale(asset);
        let b_full = Scene {
            lbuffer_scale: 1.0,
            dsf: false,
            ..b.clone()
        };
        let mut v = Vec::new();
        if matches!(
            args.experiment,
            crate::Experiment::Objects | crate::Experiment::All
        ) {
            v.push((
                "(a) 101 objects, 81 lights, 1280×720",
                a.clone(),
                Mode::Inferred,
                "inferred, L-buffer 800×450, DSF",
            ));
            v.push((
                "(a) 101 objects, 81 lights, 1280×720",
                a,
                Mode::Forward,
                "forward",
            ));
        }
        if matches!(
            args.experiment,
            crate::Experiment::Lbuffer | crate::Experiment::All
        ) {
            v.push((
                "(b) 122 lights, 1280×720",
                b,
                Mode::Inferred,
                "L-buffer 800×450 with DSF",
            ));
            v.push((
                "(b) 122 lights, 1280×720",
                b_full,
                Mode::Inferred,
                "L-buffer 1280×720 without DSF",
            ));
        }
        v
    };
    if matches!(
        args.experiment,
        crate::Experiment::Reflections | crate::Experiment::All
    ) {
        crate::reflect_bench::run(&mut preview, args)?;
        if args.experiment == crate::Experiment::Reflections {
            return Ok(ExitCode::SUCCESS);
        }
    }
    if matches!(
        args.experiment,
        crate::Experiment::Fur | crate::Experiment::All
    ) {
        v_fur(&mut preview, args)?;
        if args.experiment == crate::Experiment::Fur {
            return Ok(ExitCode::SUCCESS);
        }
    }
    println!("| experiment | configuration | frame ms (median) | passes |");
    println!("|---|---|---|---|");
    for (name, scene, mode, what) in runs {
        let d = preview.prepare(&scene, mode)?;
        let t = preview.time(&d, args.warmup, args.frames)?;
        let passes: Vec<String> = t
            .passes
            .iter()
            .map(|(p, ms)| format!("{} {ms:.1}", p.name()))
            .collect();
        println!(
            "| {name} | {what} | {:.1} | {} |",
            t.frame_ms,
            passes.join(", ")
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The fur experiment: the demo scene (baked fixture creature, 1280×720) against shell
/// count, fins on and off, stipple against WBOIT, and the forward Kajiya-Kay reference.
fn v_fur(preview: &mut Preview, args: &RenderBenchArgs) -> anyhow::Result<()> {
    use pelt_preview::scene::FurBlend;
    let dir = std::env::temp_dir().join(format!("pelt-render-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let asset = dir.join("creature.glb");
    pelt_measure::demo_creature::bake_creature(&asset)?;
    let mesh = pelt_preview::asset::load(&asset)?;
    let _ = std::fs::remove_dir_all(&dir);
    let (lo, hi) = mesh.bounds();
    let meshes = vec![mesh, pelt_preview::asset::builtin("quad").context("quad")?];
    let mut runs: Vec<(String, Scene, Mode)> = Vec::new();
    let at = |shells: u32, fins: bool, blend: FurBlend| {
        let mut s = pelt_preview::procedural::fur_scene(&asset, lo, hi, 1280, 720, 0.0);
        s.fur_blend = blend;
        Knobs {
            shells: Some(shells),
            fins: Some(fins),
            ..Knobs::default()
        }
        .apply(&mut s);
        s
    };
    for n in [4, 8, 16, 32, 64] {
        runs.push((
            format!("{n} shells, fins, stipple"),
            at(n, true, FurBlend::Stipple),
            Mode::Inferred,
        ));
    }
    runs.push((
        "16 shells, no fins, stipple".into(),
        at(16, false, FurBlend::Stipple),
        Mode::Inferred,
    ));
    runs.push((
        "16 shells, fins, WBOIT".into(),
        at(16, true, FurBlend::Wboit),
        Mode::Inferred,
    ));
    runs.push((
        "64 shells, fins, WBOIT".into(),
        at(64, true, FurBlend::Wboit),
        Mode::Inferred,
    ));
    runs.push((
        "16 shells, fins, forward Kajiya-Kay".into(),
        at(16, true, FurBlend::Stipple),
        Mode::Forward,
    ));
    println!("| fur demo, 1280×720 | frame ms (median) | passes |");
    println!("|---|---|---|");
    for (what, scene, mode) in runs {
        let d = preview.prepare_loaded(&scene, &meshes, &[0, 1], mode)?;
        let t = preview.time(&d, args.warmup, args.frames)?;
        let passes: Vec<String> = t
            .passes
            .iter()
            .map(|(p, ms)| format!("{} {ms:.1}", p.name()))
            .collect();
        println!("| {what} | {:.1} | {} |", t.frame_ms, passes.join(", "));
    }
    Ok(())
}

/// `--frames N`: N frames evenly over the clip (from its first key, not repeating the last),
/// the camera framed on the first, as one contact sheet.
fn contact_sheet(args: &RenderArgs, animation: &str, frames: u32) -> anyhow::Result<ExitCode> {
    let Some(out) = &args.output else {
        anyhow::bail!("--frames needs -o FILE.png");
    };
    if knobs::is_scene(&args.input) {
        anyhow::bail!("--frames takes an asset (.glb, .gltf), not a scene file");
    }
    let clip = match pelt_io::load(&args.input).and_then(|d| {
        let rig = pelt_anim::Rig::load(&d)?;
        rig.clip(&d, animation).map(|c| (c.start, c.end))
    }) {
        Ok(c) => c,
        Err(e) => return Ok(fail(e)),
    };
    let mode = match args.knobs.mode {
        crate::RenderMode::Gpu(m) => m,
        crate::RenderMode::Raytrace => anyhow::bail!("--frames renders with the GPU modes"),
    };
    let mut k = args.knobs.knobs();
    let (w, h) = k.size.unwrap_or(DEFAULT_SIZE);
    k.size = Some(((w / 2).max(1), (h / 2).max(1)));
    let at = |i: u32| PoseAt {
        animation: animation.to_owned(),
        time: clip.0 + (clip.1 - clip.0) * i as f32 / frames as f32,
    };
    let first = match knobs::load_at(&args.input, &k, DEFAULT_SIZE, Some(&at(0))) {
        Ok(i) => i,
        Err(e) => return Ok(fail(e)),
    };
    let mut preview = match Preview::new(args.knobs.backend) {
        Ok(p) => p,
        Err(e) => return Ok(fail(e)),
    };
    // Prepared once; each frame skins the asset on the GPU (assets the GPU cannot skin, with
    // morph targets or without NORMAL, are posed on the CPU and uploaded per frame).
    let gpu_skinned = first.meshes.iter().any(|m| m.skin.is_some());
    let mut prepared = None;
    let mut tiles = Vec::new();
    for i in 0..frames {
        if prepared.is_none() || !gpu_skinned {
            let meshes = if i == 0 {
                first.meshes.clone()
            } else {
                match knobs::load_at(&args.input, &k, DEFAULT_SIZE, Some(&at(i))) {
                    Ok(inp) => inp.meshes,
                    Err(e) => return Ok(fail(e)),
                }
            };
            match preview.prepare_loaded(&first.scene, &meshes, &first.mesh_of, mode) {
                Ok(d) => prepared = Some(d),
                Err(e) => return Ok(fail(e)),
            }
        }
        let Some(d) = &prepared else { continue };
        if gpu_skinned && i > 0 {
            let a = at(i);
            if let Err(e) = preview.pose(d, &a.animation, a.time, &args.input) {
                return Ok(fail(e));
            }
        }
        match preview.render(d) {
            Ok(t) => tiles.push(t),
            Err(e) => return Ok(fail(e)),
        }
    }
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
