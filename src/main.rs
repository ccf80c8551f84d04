//! `pelt`: prepare vertex-painted meshes for real-time fur.
//!
//! A thin binary: argument parsing here, the work in `pelt-bake`, `pelt-io` and `pelt-geom`.
//! Exit codes: 0 ok, 1 some input failed, 2 usage error.

mod bake;
mod demo;
mod inspect;
mod outputs;
mod pose;
mod progress;
mod render;
mod sweep;
mod textures;
mod view;

#[global_allocator]
static GLOBAL: pelt_alloc::HugePageAlloc = pelt_alloc::HugePageAlloc;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use pelt_preview::flags;

const BAKE_EXAMPLES: &str = "\
Examples:
  pelt bake fixtures/creature.glb -o out/creature.glb
  pelt bake fixtures/creature.glb -o out/creature.glb --report -
  pelt bake scans/*.gltf -o out/ --report bake.json
  pelt bake assets/ -o baked/ --jobs 8 --incremental --depfile baked.d
  pelt bake 'assets/**/*.gltf' -o baked/ --quiet
  pelt bake blender_export.glb -o fur.glb --comb-color-space srgb --comb-axes x,z,-y
  pelt bake painted.obj -o painted.glb --tangents regenerate --quantize u16
  pelt bake fixtures/creature.glb -o out/creature.glb --config fixtures/fur.json";

const TEXTURES_EXAMPLES: &str = "\
Examples:
  pelt textures -o out/fur
  pelt textures --seed 7 --size 2048 --strands 40000 --radius 0.0015 -o out/fur
  pelt textures --tilt 3 --clumps 400 --clumping 0.6 --height-bits 8 -o out/fur
  pelt textures --config fixtures/fur.json -o out/fur";

const RENDER_EXAMPLES: &str = "\
Examples:
  pelt render fixtures/creature.glb -o creature.png
  pelt render fixtures/scenes/showcase.json -o showcase.png --backend gl
  pelt render fixtures/scenes/showcase.json --explain
  pelt render fixtures/scenes/showcase.json -o showcase.png --mode forward --size 320x180
  pelt render fixtures/scenes/showcase.json --bench 20
  pelt render out/demo/creature.glb --bench 30 --orbit 5 --json";

const VIEW_EXAMPLES: &str = "\
Controls: left drag orbits, right (or shift) drag pans, the wheel zooms, F frames the asset;
M mode, G debug view (normal groups, comb), [ ] L-buffer scale, D DSF, - = shells, I fins,
B stipple/WBOIT, P screenshot, R reload, T measure pass costs, O overlay, H help, Q quit.
Drop a file on the window to open it.
An animated asset plays: Space plays/pauses, , . step a frame, C picks the next clip.

Examples:
  pelt view out/demo/creature.glb
  pelt view fixtures/scenes/showcase.json --backend vulkan
  pelt view out/demo/creature.glb --budget-ms 100
  pelt view out/demo/creature.glb --frames 3 --screenshot shot.png --size 320x180
  pelt view out/demo/creature.glb --frames 24 --orbit 15 --screenshot still.png
  pelt view out/demo/fox.glb --animation Run
  pelt view out/demo/fox.glb --animation Walk --time 0.3 --play --frames 10 --screenshot walk.png";

const DEMO_EXAMPLES: &str = "\
Examples:
  pelt demo
  pelt demo -o out/demo --backend gl --size 960x540 --shells 32";

const INSPECT_EXAMPLES: &str = "\
Examples:
  pelt inspect out/creature.glb
  pelt inspect out/creature.glb --json
  pelt inspect fixtures/fox/Fox.glb        (skins, joints and animations with durations)";

const POSE_EXAMPLES: &str = "\
Examples:
  pelt pose fox.glb --animation Walk --time 0.4 -o fox-walk.glb
  pelt pose fox.glb -o fox-rest.glb        (the rest pose: skin and animations removed)
  pelt inspect fox.glb                     (lists the animations and their durations)";

#[derive(Parser)]
#[command(name = "pelt", version, about = "Prepare vertex-painted meshes for real-time fur.", long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Bake comb colors (COLOR_0) into tangent space as _FUR_COMB; write self-contained .glb.
    #[command(after_help = BAKE_EXAMPLES)]
    Bake(BakeArgs),
    /// Generate fur textures (dots, heightfield, fin texture, coverage-preserving mips) and
    /// their manifest fur.json from one seeded strand model.
    #[command(after_help = TEXTURES_EXAMPLES)]
    Textures(TexturesArgs),
    /// Render a scene file (.json) or one asset (framed and lit by a default scene) to PNG
    /// with inferred lighting, or the deferred and forward references.
    #[command(after_help = RENDER_EXAMPLES)]
    Render(RenderArgs),
    /// Open a scene file or an asset in a window: orbit, pan, zoom, every knob on a key,
    /// reload on change, screenshots; or, scripted, draw N frames and save the last.
    #[command(after_help = VIEW_EXAMPLES)]
    View(pelt_view::ViewArgs),
    /// Time the inferred-lighting paper's two experiments (101 objects × 81 lights against
    /// forward; 800×450 L-buffer with DSF against 1280×720 without) on this adapter.
    RenderBench(pelt_measure::bench_run::Settings),
    /// Bake the bundled Khronos Fox with a generated comb and render it furred and textured
    /// mid-walk (demo.png) and over its walk (fox-walk.png); bake the fixture creature and
    /// render it (creature.png), a turntable contact sheet and a mirror scene.
    #[command(after_help = DEMO_EXAMPLES)]
    Demo(DemoArgs),
    /// Show a file's meshes, attributes (with encodings), bounds and comb statistics, and its
    /// skins and animations.
    #[command(after_help = INSPECT_EXAMPLES)]
    Inspect(InspectArgs),
    /// Write a skinned or morphed asset as a static mesh in one pose of one animation
    /// (positions, normals, tangents posed on the CPU; _FUR_COMB kept in tangent space; skin
    /// and animations removed).
    #[command(after_help = POSE_EXAMPLES)]
    Pose(PoseArgs),
    /// Time every quality knob against its error: each value rendered and measured with FLIP
    /// against the converged strand reference (fur knobs), full-resolution deferred
    /// (lighting knobs) or the ray tracer (distance-map knobs); sweep.csv, sweep.json,
    /// sweep.md, sweep.png (time against error, Pareto front) and contact.png.
    #[command(after_help = SWEEP_EXAMPLES)]
    Sweep(SweepArgs),
}

const SWEEP_EXAMPLES: &str = "\
Knobs (values as for pelt render and pelt bake):
  shells fins fur-blend mode texture-size height-bits quantize    (against the strand reference)
  opacity-layers                      (fur self-shadowing, against the strands' shadow rays)
  lbuffer-scale dsf size                                          (against full-resolution deferred)
  reflections linear-steps secant-steps layers cube-size max-depth min-max
  shadow-size pcf                                                 (against the ray tracer)

Examples:
  pelt sweep out/demo/creature.glb -o sweep
  pelt sweep out/demo/creature.glb --knob shells=4,8,16,32,64 --knob fins=on,off -o sweep
  pelt sweep scene.json --knob shells=8,16 --knob lbuffer-scale=0.5,1 --grid -o sweep";

/// Arguments of `pelt sweep`.
#[derive(clap::Args)]
pub struct SweepArgs {
    /// A scene file (.json) or an asset (.glb, .gltf, .obj).
    pub input: PathBuf,
    /// Output folder: images/, heat/, assets/ (re-baked), the references, sweep.csv,
    /// sweep.json, sweep.md, sweep.png and contact.png.
    #[arg(short, long)]
    pub output: PathBuf,
    /// NAME=V1,V2,...: a knob and its values (repeatable). Without any, every knob that
    /// applies to the scene, at values around its default.
    #[arg(long, value_name = "NAME=V1,V2,...")]
    pub knob: Vec<String>,
    /// Every combination of the knobs' values instead of one knob at a time (at most 512).
    #[arg(long)]
    pub grid: bool,
    /// wgpu back end: auto, vulkan or gl.
    #[arg(long, default_value = "auto")]
    pub backend: pelt_preview::Backend,
    /// Output size WxH (overrides the scene's; the references are made at it).
    #[arg(long, value_parser = flags::size)]
    pub size: Option<(u32, u32)>,
    /// Timed frames per setting (the median is reported).
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(usize))]
    pub frames: usize,
    /// Untimed frames before them.
    #[arg(long, default_value_t = 2)]
    pub warmup: usize,
    /// How far the strand reference converges.
    #[command(flatten)]
    pub reference: ReferenceArgs,
    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Arguments of `pelt bake`.
#[derive(clap::Args)]
pub struct BakeArgs {
    /// Inputs: .gltf, .glb or .obj files, folders (searched recursively) or quoted glob
    /// patterns ('scans/**/*.gltf').
    #[arg(required = true)]
    pub inputs: Vec<PathBuf>,
    /// Output: a .glb file for one input file, else a folder (files found under a folder or
    /// a pattern keep their relative paths in it).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Worker threads, shared by the files and the work inside large meshes (default: one
    /// per core). Outputs are byte-identical for every value.
    #[arg(short, long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=1024))]
    pub jobs: Option<u16>,
    /// Skip inputs whose existing output records the same content key (the bytes of every
    /// file read, the flags, the config and pelt's version).
    #[arg(long)]
    pub incremental: bool,
    /// Write a Make-syntax depfile: one rule per output listing every file read (glTF, .bin,
    /// images, config).
    #[arg(long, value_name = "FILE")]
    pub depfile: Option<PathBuf>,
    /// Write a JSON report to FILE ("-" for standard output).
    #[arg(long, value_name = "FILE")]
    pub report: Option<PathBuf>,
    /// Tangents, the comb's encoding, topology and normals (pelt-bake's `Flags`).
    #[command(flatten)]
    pub bake: pelt_bake::flags::Flags,
    /// Bake config (JSON). Its `fur` section makes the bake generate fur textures and embed
    /// them, with the fur manifest, in each output; `comb` and `normals` set the generated
    /// comb and normals (see docs/format.md).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Print nothing but errors (listed at the end).
    #[arg(short, long)]
    pub quiet: bool,
}

/// Arguments of `pelt render`.
#[derive(clap::Args)]
pub struct RenderArgs {
    /// A scene file (.json) or an asset (.glb, .gltf, .obj).
    pub input: PathBuf,
    /// Output PNG. May be left out with --explain or --bench.
    #[arg(short, long, required_unless_present_any = ["explain", "bench"])]
    pub output: Option<PathBuf>,
    /// Mode, back end, size and the knobs.
    #[command(flatten)]
    pub knobs: KnobArgs,
    /// Pose animated assets at --time seconds of this animation (`pelt inspect` lists them),
    /// as `pelt pose` does; with --frames, each later frame is skinned on the GPU.
    #[arg(long, value_name = "NAME")]
    pub animation: Option<String>,
    /// Seconds into the scene: where the scene's wind is evaluated, and the --animation's
    /// pose (clamped to its keys).
    #[arg(long, value_name = "SECONDS", default_value_t = 0.0, value_parser = flags::finite, allow_negative_numbers = true)]
    pub time: f32,
    /// With --animation and an asset: a contact sheet of N frames evenly over the clip (4 to a
    /// row, each tile half the --size, the camera framed on the first).
    #[arg(long, value_name = "N", requires = "animation", conflicts_with = "time", value_parser = clap::value_parser!(u32).range(1..=64))]
    pub frames: Option<u32>,
    /// Print the passes this scene needs (no GPU is opened unless -o or --bench is given).
    #[arg(long)]
    pub explain: bool,
    /// Time this many frames after warm-up and print the medians (whole frame and per pass)
    /// and each pass's profile (draws, state changes, triangles, and the fragment-shader
    /// invocations and samples written the GPU counts).
    #[arg(long, value_name = "FRAMES", value_parser = clap::value_parser!(usize))]
    pub bench: Option<usize>,
    /// Untimed frames before --bench (not with --json, whose frame 0 is the cold first frame).
    #[arg(long, default_value_t = 3)]
    pub warmup: usize,
    /// With --bench: turn the camera this many degrees about its target before each frame.
    #[arg(
        long,
        value_name = "DEG",
        requires = "bench",
        allow_negative_numbers = true
    )]
    pub orbit: Option<f32>,
    /// With --bench: print one JSON object with every frame's time and the bytes it
    /// uploaded (frame 0 includes the scene's meshes, textures and pipelines).
    #[arg(long, requires = "bench")]
    pub json: bool,
    /// With --mode strands: how far the reference converges.
    #[command(flatten)]
    pub reference: ReferenceArgs,
    /// Print nothing but errors and requested output.
    #[arg(short, long)]
    pub quiet: bool,
}

/// How far the strand reference (`--mode strands`, `pelt sweep`) accumulates.
#[derive(clap::Args)]
pub struct ReferenceArgs {
    /// Accumulate jittered samples until two half-sample images differ by at most this FLIP
    /// mean (0.0001 to 0.5).
    #[arg(long, value_name = "FLIP", default_value_t = 0.005, value_parser = target_flip)]
    pub target_flip: f32,
    /// Give up (exit 1, nothing written) after this many samples per pixel.
    #[arg(long, value_name = "N", default_value_t = 4096, value_parser = clap::value_parser!(u32).range(2..=1_000_000))]
    pub max_samples: u32,
}

impl ReferenceArgs {
    /// The accumulation options.
    pub fn options(&self) -> pelt_measure::strands::Options {
        pelt_measure::strands::Options {
            target: self.target_flip,
            max_samples: self.max_samples,
            ..Default::default()
        }
    }
}

fn target_flip(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if (0.0001..=0.5).contains(&v) => Ok(v),
        _ => Err(format!("{s:?} is not a FLIP mean from 0.0001 to 0.5")),
    }
}

/// The renderer's mode, back end, size and knobs: the same flags for `pelt render` and
/// `pelt view`.
#[derive(clap::Args)]
pub struct KnobArgs {
    /// inferred (low-resolution L-buffer, DSF), deferred (full-resolution L-buffer, no DSF),
    /// forward (per-object light loop, the reference), strands (explicit strands with
    /// Kajiya-Kay, accumulated until converged: the fur's reference), raytrace (`pelt
    /// render` only: the CPU ray tracer, the ground truth of mirrors and glass), debug-groups
    /// (each normal group in a flat colour, neighbours distinct) or debug-comb (the decoded
    /// comb as colour, its length as brightness).
    #[arg(long, default_value = "inferred")]
    pub mode: RenderMode,
    /// wgpu back end: auto, vulkan or gl.
    #[arg(long, default_value = "auto")]
    pub backend: pelt_preview::Backend,
    /// The overrides: size, L-buffer, fur and reflection knobs (pelt-scene's `Knobs`).
    #[command(flatten)]
    pub overrides: pelt_preview::knobs::Knobs,
}

/// The renderer (`--mode`): one of the GPU modes, or the CPU ray tracer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RenderMode {
    /// A GPU mode.
    Gpu(pelt_preview::Mode),
    /// The CPU ray tracer.
    Raytrace,
}

impl std::str::FromStr for RenderMode {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "raytrace" => Ok(RenderMode::Raytrace),
            _ => s.parse().map(RenderMode::Gpu).map_err(|e: String| {
                e.replace("strands, debug-groups", "strands, raytrace, debug-groups")
            }),
        }
    }
}

impl std::fmt::Display for RenderMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RenderMode::Gpu(m) => m.fmt(f),
            RenderMode::Raytrace => f.write_str("raytrace"),
        }
    }
}

/// Arguments of `pelt demo`.
#[derive(clap::Args)]
pub struct DemoArgs {
    /// Output folder (created): fox.glb, demo.png, fox-walk.png, fox.json, creature.glb,
    /// creature.png, turntable.png, mirror.png, scene.json.
    #[arg(short, long, default_value = "out/demo")]
    pub output: PathBuf,
    /// wgpu back end: auto, vulkan or gl.
    #[arg(long, default_value = "auto")]
    pub backend: pelt_preview::Backend,
    /// Size of demo.png, WxH (the turntable's frames are a quarter of it).
    #[arg(long, value_parser = flags::size, default_value = "1280x720")]
    pub size: (u32, u32),
    /// Shells (default: by the fur's size on screen, at most the bake's 16).
    #[arg(long, value_parser = |s: &str| flags::count(s, pelt_fur::manifest::SHELLS))]
    pub shells: Option<u32>,
    /// How fur is composited: stipple or wboit.
    #[arg(long, default_value = "stipple")]
    pub fur_blend: pelt_preview::scene::FurBlend,
    /// Turntable frames (4 per row).
    #[arg(long, default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=64))]
    pub frames: u32,
    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Arguments of `pelt textures`. Every strand option overrides the config's
/// `fur.textures` value.
#[derive(clap::Args)]
pub struct TexturesArgs {
    /// Output folder (created): heightfield.png, dots.png, fin.png, their mips, fur.json.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Bake config whose `fur` section gives the defaults.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// The strand model's parameters (pelt-fur's `StrandFlags`).
    #[command(flatten)]
    pub strand: pelt_fur::flags::StrandFlags,
    /// Print nothing but errors.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Arguments of `pelt inspect`.
#[derive(clap::Args)]
pub struct InspectArgs {
    /// The file: .gltf, .glb or .obj.
    pub file: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `pelt pose`.
#[derive(clap::Args)]
pub struct PoseArgs {
    /// The asset: .gltf or .glb.
    pub input: PathBuf,
    /// The posed .glb to write.
    #[arg(short, long)]
    pub output: PathBuf,
    /// The animation to sample (by name; `pelt inspect` lists them). Without it, the rest
    /// pose.
    #[arg(long, value_name = "NAME")]
    pub animation: Option<String>,
    /// Time in seconds (clamped to the clip's keys).
    #[arg(long, value_name = "SECONDS", default_value_t = 0.0, value_parser = flags::finite, allow_negative_numbers = true)]
    pub time: f32,
    /// Write a JSON report to FILE ("-" for standard output).
    #[arg(long, value_name = "FILE")]
    pub report: Option<PathBuf>,
}

/// Writes a JSON report to `path` (pretty, one trailing newline), or to standard output when
/// `path` is "-".
pub fn write_json_report(
    path: &std::path::Path,
    report: &impl serde::Serialize,
) -> anyhow::Result<()> {
    let mut text = serde_json::to_string_pretty(report)?;
    text.push('\n');
    if path.as_os_str() == "-" {
        print!("{text}");
    } else {
        pelt_io::glb::write_atomic(path, text.as_bytes())?;
    }
    Ok(())
}

/// Gives Mesa a private `XDG_RUNTIME_DIR` when none is set (see
/// [`pelt_preview::gpu::private_runtime_dir`]), so a successful render prints no "error:" line.
#[expect(
    unsafe_code,
    reason = "set_var is unsafe only with other threads reading the environment; main calls this first, before any thread exists"
)]
fn quiet_mesa() {
    if let Some(dir) = pelt_preview::gpu::private_runtime_dir() {
        // SAFETY: single-threaded at this point (first statement of main).
        unsafe { std::env::set_var("XDG_RUNTIME_DIR", dir) };
    }
}

fn main() -> ExitCode {
    quiet_mesa();
    pelt_alloc::configure_from_env();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Bake(args) => bake::run(&args),
        Command::Inspect(args) => inspect::run(&args),
        Command::Pose(args) => pose::run(&args),
        Command::Textures(args) => textures::run(&args),
        Command::Render(args) => render::run(&args),
        Command::RenderBench(args) => render::bench(&args),
        Command::View(args) => view::run(args),
        Command::Demo(args) => demo::run(&args),
        Command::Sweep(args) => sweep::run(&args),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("pelt: {}", message(&e));
            ExitCode::from(2)
        }
    }
}

/// `e` and each cause its message does not already hold (errors here name their source in
/// their own message, so the chain would say it twice).
fn message(e: &anyhow::Error) -> String {
    let mut text = e.to_string();
    for cause in e.chain().skip(1) {
        let cause = cause.to_string();
        if !text.contains(&cause) {
            text = format!("{text}: {cause}");
        }
    }
    text
}
