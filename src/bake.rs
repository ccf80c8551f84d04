//! `pelt bake`: lay out the jobs (files, folders, globs), bake them in parallel on `--jobs`
//! threads (files and the work inside large meshes share the pool), show progress, write the
//! report and the depfile, summarize. One failing input never stops the others.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use anyhow::Context;
use pelt_bake::config::BakeConfig;
use pelt_bake::fur::{FurAssets, FurReport};
use pelt_bake::options::{
    ColorSpace, CombSource, DEFAULT_CREASE_ANGLE_DEG, Quantize, TangentGenerator, TangentMode,
    TopologyMode, TopologyOptions,
};
use pelt_bake::{AssetReport, BakeOptions};
use pelt_batch::{Job, Outcome, Settings, Status};
use rayon::prelude::*;
use serde::Serialize;

use crate::{BakeArgs, ColorSpaceArg, QuantizeArg, TangentGeneratorArg, Tangents, TopologyArg};

#[derive(Serialize)]
struct Report {
    pelt: &'static str,
    options: OptionsReport,
    summary: Summary,
    #[serde(skip_serializing_if = "Option::is_none")]
    fur: Option<FurRun>,
    inputs: Vec<InputReport>,
}

/// The fur textures of a run (generated once, embedded in every output).
#[derive(Serialize)]
struct FurRun {
    config: PathBuf,
    generate_ms: f64,
    images: usize,
    texture_bytes: usize,
    strands: pelt_fur::StrandParams,
    coverage: pelt_fur::manifest::Coverage,
}

/// Counts over the whole batch.
#[derive(Serialize, Clone, Copy, Default)]
struct Summary {
    inputs: usize,
    baked: usize,
    up_to_date: usize,
    failed: usize,
    jobs: usize,
    wall_ms: f64,
}

#[derive(Serialize, Clone)]
struct OptionsReport {
    tangents: &'static str,
    tangent_generator: &'static str,
    comb_color_space: &'static str,
    comb_axes: String,
    quantize: &'static str,
    topology: &'static str,
    weld_epsilon: f32,
    normal_tolerance_deg: f32,
    comb: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    comb_length: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    comb_smoothing: Option<u32>,
    crease_angle_deg: f32,
}

#[derive(Serialize)]
struct InputReport {
    input: PathBuf,
    output: PathBuf,
    /// `ok`, `up to date` or `failed`.
    status: &'static str,
    /// Every file read for this input (the input first).
    reads: Vec<PathBuf>,
    #[serde(skip_serializing_if = "Option::is_none")]
    error: Option<String>,
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    bake: Option<AssetReport>,
    #[serde(skip_serializing_if = "Option::is_none")]
    fur: Option<FurReport>,
    #[serde(skip_serializing_if = "Option::is_none")]
    read_ms: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    write_ms: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    output_bytes: Option<u64>,
}

fn options(args: &BakeArgs, config: Option<&BakeConfig>) -> anyhow::Result<BakeOptions> {
    let comb_config = config.and_then(|c| c.comb.clone()).unwrap_or_default();
    let comb = comb_config
        .source(args.comb)
        .map_err(|e| anyhow::anyhow!("comb.source: {e}"))?;
    let crease_deg = args.crease_angle.unwrap_or_else(|| {
        config
            .and_then(|c| c.normals.as_ref())
            .map_or(DEFAULT_CREASE_ANGLE_DEG, |n| n.crease_angle)
    });
    Ok(BakeOptions {
        tangents: match args.tangents {
            Tangents::Keep => TangentMode::Keep,
            Tangents::Regenerate => TangentMode::Regenerate,
        },
        tangent_generator: match args.tangent_generator {
            TangentGeneratorArg::Auto => TangentGenerator::Auto,
            TangentGeneratorArg::Mikktspace => TangentGenerator::Mikktspace,
            TangentGeneratorArg::Gradient => TangentGenerator::Gradient,
        },
        color_space: match args.comb_color_space {
            ColorSpaceArg::Linear => ColorSpace::Linear,
            ColorSpaceArg::Srgb => ColorSpace::Srgb,
        },
        axes: args.comb_axes,
        quantize: match args.quantize {
            QuantizeArg::Float => Quantize::Float,
            QuantizeArg::U16 => Quantize::U16,
            QuantizeArg::U8 => Quantize::U8,
        },
        topology_mode: match args.topology {
            TopologyArg::Full => TopologyMode::Full,
            TopologyArg::Groups => TopologyMode::Groups,
            TopologyArg::Off => TopologyMode::Off,
        },
        topology: TopologyOptions {
            weld_epsilon: args.weld_epsilon,
            normal_tolerance: args.normal_tolerance.to_radians(),
        },
        comb,
        crease_angle: crease_deg.to_radians(),
    })
}

/// Runs `pelt bake`.
pub fn run(args: &BakeArgs) -> anyhow::Result<ExitCode> {
    let started = Instant::now();
    let jobs = pelt_batch::plan(&args.inputs, &args.output)?;
    let config_bytes = match &args.config {
        Some(path) => {
            Some(std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?)
        }
        None => None,
    };
    let config = match (&args.config, &config_bytes) {
        (Some(path), Some(bytes)) => {
            let text = std::str::from_utf8(bytes)
                .with_context(|| format!("{} is not UTF-8 text", path.display()))?;
            Some(BakeConfig::parse(path, text)?)
        }
        _ => None,
    };
    let opts = options(args, config.as_ref())?;
    let fur = match (&args.config, config.as_ref().and_then(|c| c.fur.clone())) {
        (Some(path), Some(fur)) => Some(
            FurAssets::new(fur).with_context(|| format!("fur textures of {}", path.display()))?,
        ),
        _ => None,
    };
    let options_report = options_report(args, &opts);
    let settings = Settings {
        options: opts,
        fur: fur.as_ref(),
        salt: salt(&options_report, config_bytes.as_deref()),
        incremental: args.incremental,
    };
    let threads = args.jobs.map_or_else(
        || std::thread::available_parallelism().map_or(1, usize::from),
        usize::from,
    );
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .context("cannot start the worker threads")?;
    let dirs: std::collections::BTreeSet<PathBuf> = jobs
        .iter()
        .filter_map(|j| j.output.parent().map(PathBuf::from))
        .collect();
    for d in &dirs {
        pelt_batch::temp::sweep(d);
    }

    let progress = Progress::new(jobs.len(), args.quiet);
    let outcomes: Vec<Outcome> = pool.install(|| {
        jobs.par_iter()
            .map(|job| {
                let o = pelt_batch::bake_file(job, &settings);
                progress.done(job, &o);
                o
            })
            .collect()
    });
    progress.finish();

    let mut summary = Summary {
        inputs: jobs.len(),
        jobs: threads,
        ..Summary::default()
    };
    let mut failures = Vec::new();
    for o in &outcomes {
        match &o.status {
            Status::Baked(_) => summary.baked += 1,
            Status::UpToDate => summary.up_to_date += 1,
            Status::Failed(e) => {
                summary.failed += 1;
                failures.push(e.clone());
            }
        }
    }
    summary.wall_ms = ms(started);

    if let Some(path) = &args.depfile {
        let rules: Vec<(PathBuf, Vec<PathBuf>)> = jobs
            .iter()
            .zip(&outcomes)
            .map(|(j, o)| {
                let mut deps = o.reads.clone();
                deps.extend(args.config.iter().cloned());
                (j.output.clone(), deps)
            })
            .collect();
        pelt_io::glb::write_atomic(path, pelt_batch::depfile::render(&rules).as_bytes())?;
    }
    if let Some(path) = &args.report {
        let report = Report {
            pelt: env!("CARGO_PKG_VERSION"),
            options: options_report,
            summary,
            fur: fur
                .as_ref()
                .zip(args.config.as_ref())
                .map(|(f, path)| FurRun {
                    config: path.clone(),
                    generate_ms: f.generate_ms,
                    images: f.pngs.len(),
                    texture_bytes: f.pngs.iter().map(Vec::len).sum(),
                    strands: f.set.params.clone(),
                    coverage: f.set.coverage.clone(),
                }),
            inputs: jobs.iter().zip(outcomes).map(input_report).collect(),
        };
        crate::write_json_report(path, &report)?;
    }
    if jobs.len() > 1 && !args.quiet {
        eprintln!(
            "pelt: {} inputs: {} baked, {} up to date, {} failed in {:.2} s ({} jobs)",
            summary.inputs,
            summary.baked,
            summary.up_to_date,
            summary.failed,
            summary.wall_ms / 1000.0,
            threads
        );
    }
    if summary.failed > 0 {
        if jobs.len() > 1 {
            eprintln!(
                "pelt: {} of {} inputs failed:",
                summary.failed, summary.inputs
            );
            for f in &failures {
                eprintln!("  {f}");
            }
        } else if args.quiet {
            eprintln!("pelt: {}", failures.join("\n"));
        }
        return Ok(ExitCode::from(1));
    }
    Ok(ExitCode::SUCCESS)
}

/// Everything besides the files read that shapes an output: pelt's version, the options
/// (as the report states them) and the config's bytes.
fn salt(options: &OptionsReport, config: Option<&[u8]>) -> Vec<u8> {
    let mut s = format!("pelt {}\n", env!("CARGO_PKG_VERSION")).into_bytes();
    s.extend(serde_json::to_vec(options).unwrap_or_default());
    s.push(b'\n');
    if let Some(c) = config {
        s.extend((c.len() as u64).to_le_bytes());
        s.extend(c);
    }
    s
}

fn options_report(args: &BakeArgs, opts: &BakeOptions) -> OptionsReport {
    OptionsReport {
        tangents: match opts.tangents {
            TangentMode::Keep => "keep",
            TangentMode::Regenerate => "regenerate",
        },
        tangent_generator: match opts.tangent_generator {
            TangentGenerator::Auto => "auto",
            TangentGenerator::Mikktspace => "mikktspace",
            TangentGenerator::Gradient => "gradient",
        },
        comb_color_space: match opts.color_space {
            ColorSpace::Linear => "linear",
            ColorSpace::Srgb => "srgb",
        },
        comb_axes: opts.axes.to_string(),
        quantize: match opts.quantize {
            Quantize::Float => "float",
            Quantize::U16 => "u16",
            Quantize::U8 => "u8",
        },
        topology: match opts.topology_mode {
            TopologyMode::Full => "full",
            TopologyMode::Groups => "groups",
            TopologyMode::Off => "off",
        },
        weld_epsilon: args.weld_epsilon,
        normal_tolerance_deg: args.normal_tolerance,
        comb: opts.comb.to_string(),
        comb_length: match opts.comb {
            CombSource::Generate(g) => Some(g.length),
            CombSource::Painted => None,
        },
        comb_smoothing: match opts.comb {
            CombSource::Generate(g) => Some(g.smoothing),
            CombSource::Painted => None,
        },
        crease_angle_deg: opts.crease_angle.to_degrees(),
    }
}

fn input_report(pair: (&Job, Outcome)) -> InputReport {
    let (job, o) = pair;
    let mut r = InputReport {
        input: job.input.clone(),
        output: job.output.clone(),
        status: "failed",
        reads: o.reads,
        error: None,
        bake: None,
        fur: None,
        read_ms: None,
        write_ms: None,
        output_bytes: None,
    };
    match o.status {
        Status::Baked(b) => {
            let b = *b;
            r.status = "ok";
            r.bake = Some(b.bake);
            r.fur = b.fur;
            r.read_ms = Some(b.read_ms);
            r.write_ms = Some(b.write_ms);
            r.output_bytes = Some(b.output_bytes);
        }
        Status::UpToDate => r.status = "up to date",
        Status::Failed(e) => r.error = Some(e),
    }
    r
}

/// Per-input progress: a bar on a terminal, plain lines otherwise, nothing but errors with
/// `--quiet` (those are listed at the end).
struct Progress {
    total: usize,
    done: AtomicUsize,
    quiet: bool,
    bar: Option<indicatif::ProgressBar>,
}

impl Progress {
    fn new(total: usize, quiet: bool) -> Progress {
        use std::io::IsTerminal as _;
        let bar = (!quiet && total > 1 && std::io::stderr().is_terminal()).then(|| {
            let b = indicatif::ProgressBar::new(total as u64);
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} {wide_msg}",
            ) {
                b.set_style(style);
            }
            b
        });
        Progress {
            total,
            done: AtomicUsize::new(0),
            quiet,
            bar,
        }
    }

    fn done(&self, job: &Job, o: &Outcome) {
        let n = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        if self.quiet {
            return; // failures are listed at the end
        }
        let lines = self.lines(job, o);
        match &self.bar {
            Some(bar) => {
                // On a terminal the bar shows progress; only failures and warnings scroll.
                if !matches!(o.status, Status::UpToDate) {
                    for l in lines.iter().filter(|l| !l.starts_with("baked")) {
                        bar.println(l);
                    }
                }
                bar.set_message(job.input.display().to_string());
                bar.inc(1);
            }
            None => {
                let prefix = if self.total > 1 {
                    format!("[{n}/{}] ", self.total)
                } else {
                    String::new()
                };
                let mut text = String::new();
                for (i, l) in lines.iter().enumerate() {
                    text.push_str(if i == 0 { &prefix } else { "  " });
                    text.push_str(l);
                    text.push('\n');
                }
                eprint!("{text}");
            }
        }
    }

    fn lines(&self, job: &Job, o: &Outcome) -> Vec<String> {
        match &o.status {
            Status::Baked(b) => {
                let r = &b.bake;
                let mut v = vec![format!(
                    "baked {} -> {}: {} primitives, {} vertices, {} triangles, {} warnings",
                    job.input.display(),
                    job.output.display(),
                    r.primitives_baked,
                    r.vertices,
                    r.triangles,
                    r.warnings.len()
                )];
                v.extend(
                    r.warnings
                        .iter()
                        .map(|w| format!("warning: {}: {w}", job.input.display())),
                );
                v
            }
            Status::UpToDate => vec![format!("up to date: {}", job.output.display())],
            Status::Failed(e) if self.total == 1 => vec![format!("pelt: {e}")],
            Status::Failed(e) => vec![format!("FAILED {e}")],
        }
    }

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

fn ms(t: Instant) -> f64 {
    (t.elapsed().as_secs_f64() * 1e5).round() / 100.0
}
