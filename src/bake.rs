//! `pelt bake`: load each input, bake, write a self-contained .glb, report.

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, bail};
use pelt_bake::config::BakeConfig;
use pelt_bake::fur::{FurAssets, FurReport, combed, embed};
use pelt_bake::options::{ColorSpace, Quantize, TangentMode, TopologyMode, TopologyOptions};
use pelt_bake::{AssetReport, BakeOptions, bake_document};
use serde::Serialize;

use crate::{BakeArgs, ColorSpaceArg, QuantizeArg, Tangents, TopologyArg};

#[derive(Serialize)]
struct Report {
    pelt: &'static str,
    options: OptionsReport,
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

#[derive(Serialize)]
struct OptionsReport {
    tangents: &'static str,
    comb_color_space: &'static str,
    comb_axes: String,
    quantize: &'static str,
    topology: &'static str,
    weld_epsilon: f32,
    normal_tolerance_deg: f32,
}

#[derive(Serialize)]
struct InputReport {
    input: PathBuf,
    output: PathBuf,
    status: &'static str,
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

fn options(args: &BakeArgs) -> BakeOptions {
    BakeOptions {
        tangents: match args.tangents {
            Tangents::Keep => TangentMode::Keep,
            Tangents::Regenerate => TangentMode::Regenerate,
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
    }
}

/// Output path for each input; usage errors (exit 2) when they cannot be laid out.
fn outputs(args: &BakeArgs) -> anyhow::Result<Vec<PathBuf>> {
    if args.inputs.len() == 1 && !args.output.is_dir() {
        let out = &args.output;
        if !out
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("glb"))
        {
            bail!(
                "output {} must end in .glb (pelt writes self-contained binary glTF)",
                out.display()
            );
        }
        return Ok(vec![out.clone()]);
    }
    if args.output.exists() && !args.output.is_dir() {
        bail!(
            "output {} must be a folder when baking several inputs",
            args.output.display()
        );
    }
    let mut seen = std::collections::BTreeMap::new();
    let mut outs = Vec::new();
    for input in &args.inputs {
        let stem = input
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let out = args.output.join(format!("{stem}.glb"));
        if let Some(prev) = seen.insert(out.clone(), input.clone()) {
            bail!(
                "{} and {} would both be written to {}",
                prev.display(),
                input.display(),
                out.display()
            );
        }
        outs.push(out);
    }
    Ok(outs)
}

/// Runs `pelt bake`.
pub fn run(args: &BakeArgs) -> anyhow::Result<ExitCode> {
    let opts = options(args);
    let outs = outputs(args)?;
    let fur = match &args.config {
        Some(path) => match BakeConfig::load(path)?.fur {
            Some(config) => Some(
                FurAssets::new(config)
                    .with_context(|| format!("fur textures of {}", path.display()))?,
            ),
            None => None,
        },
        None => None,
    };
    if args.inputs.len() > 1 || args.output.is_dir() {
        std::fs::create_dir_all(&args.output)
            .with_context(|| format!("cannot create {}", args.output.display()))?;
    }
    let mut failed = 0;
    let mut inputs = Vec::new();
    for (input, output) in args.inputs.iter().zip(&outs) {
        let r = bake_one(input, output, &opts, fur.as_ref());
        match &r.error {
            Some(e) => {
                failed += 1;
                eprintln!("pelt: {e}");
            }
            None if !args.quiet => {
                if let Some(b) = &r.bake {
                    eprintln!(
                        "baked {} -> {}: {} primitives, {} vertices, {} triangles, {} warnings",
                        input.display(),
                        output.display(),
                        b.primitives_baked,
                        b.vertices,
                        b.triangles,
                        b.warnings.len()
                    );
                    for w in &b.warnings {
                        eprintln!("  warning: {w}");
                    }
                }
            }
            None => {}
        }
        inputs.push(r);
    }
    if let Some(path) = &args.report {
        let report = Report {
            pelt: env!("CARGO_PKG_VERSION"),
            options: OptionsReport {
                tangents: match opts.tangents {
                    TangentMode::Keep => "keep",
                    TangentMode::Regenerate => "regenerate",
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
            },
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
            inputs,
        };
        let mut text = serde_json::to_string_pretty(&report)?;
        text.push('\n');
        if path.as_os_str() == "-" {
            print!("{text}");
        } else {
            pelt_io::glb::write_atomic(path, text.as_bytes())?;
        }
    }
    if failed > 0 {
        if args.inputs.len() > 1 {
            eprintln!("pelt: {failed} of {} inputs failed", args.inputs.len());
        }
        return Ok(ExitCode::from(1));
    }
    Ok(ExitCode::SUCCESS)
}

fn bake_one(
    input: &Path,
    output: &Path,
    opts: &BakeOptions,
    fur: Option<&FurAssets>,
) -> InputReport {
    let mut r = InputReport {
        input: input.to_owned(),
        output: output.to_owned(),
        status: "failed",
        error: None,
        bake: None,
        fur: None,
        read_ms: None,
        write_ms: None,
        output_bytes: None,
    };
    let t0 = Instant::now();
    let mut doc = match pelt_io::load(input) {
        Ok(d) => d,
        Err(e) => {
            r.error = Some(e.to_string());
            return r;
        }
    };
    r.read_ms = Some(ms(t0));
    let mut bake = match bake_document(&mut doc, opts) {
        Ok(b) => b,
        Err(e) => {
            r.error = Some(e.to_string());
            return r;
        }
    };
    if let Some(fur) = fur {
        match embed(&mut doc, fur, &combed(&bake)) {
            Ok(f) => {
                bake.warnings.extend(f.warnings.iter().cloned());
                r.fur = Some(f);
            }
            Err(e) => {
                r.error = Some(e.to_string());
                return r;
            }
        }
    }
    let t1 = Instant::now();
    match pelt_io::glb::write_glb(&doc, output) {
        Ok(w) => {
            r.output_bytes = Some(w.file_bytes);
            r.write_ms = Some(ms(t1));
            r.status = "ok";
            r.bake = Some(bake);
        }
        Err(e) => r.error = Some(e.to_string()),
    }
    r
}

fn ms(t: Instant) -> f64 {
    (t.elapsed().as_secs_f64() * 1e5).round() / 100.0
}
