//! The batch report `pelt bake --report` writes (one schema for the CLI and library users):
//! the options as stated, counts over the batch, the fur textures generated once, and each
//! input's outcome with its bake report; and the salt that the options add to every
//! output's content key ([`crate::key`]).

use std::path::PathBuf;

use pelt_bake::fur::{FurAssets, FurReport};
use pelt_bake::options::CombSource;
#[cfg(test)]
use pelt_bake::options::Quantize;
use pelt_bake::{AssetReport, BakeOptions};
use serde::Serialize;

use crate::{Job, Outcome, Status};

/// The whole report.
#[derive(Debug, Serialize)]
pub struct Report {
    /// pelt's version.
    pub pelt: &'static str,
    /// The options, as stated.
    pub options: OptionsReport,
    /// Counts over the batch.
    pub summary: Summary,
    /// The fur textures, when a config asked for them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fur: Option<FurRun>,
    /// Each input, in the order planned.
    pub inputs: Vec<InputReport>,
}

/// The fur textures of a run (generated once, embedded in every output).
#[derive(Debug, Serialize)]
pub struct FurRun {
    /// The config they came from.
    pub config: PathBuf,
    /// Time to generate them.
    pub generate_ms: f64,
    /// How many images.
    pub images: usize,
    /// Their PNG bytes together.
    pub texture_bytes: usize,
    /// The strand model's parameters.
    pub strands: pelt_fur::StrandParams,
    /// Their coverage per mip level.
    pub coverage: pelt_fur::manifest::Coverage,
}

impl FurRun {
    /// The report of `fur`, generated from `config`.
    pub fn new(fur: &FurAssets, config: PathBuf) -> FurRun {
        FurRun {
            config,
            generate_ms: fur.generate_ms,
            images: fur.pngs.len(),
            texture_bytes: fur.pngs.iter().map(Vec::len).sum(),
            strands: fur.set.params.clone(),
            coverage: fur.set.coverage.clone(),
        }
    }
}

/// Counts over the whole batch.
#[derive(Debug, Serialize, Clone, Copy, Default)]
pub struct Summary {
    /// Inputs planned.
    pub inputs: usize,
    /// Baked and written.
    pub baked: usize,
    /// Skipped: their output is up to date.
    pub up_to_date: usize,
    /// Failed (no output written).
    pub failed: usize,
    /// Worker threads.
    pub jobs: usize,
    /// The whole run's wall time.
    pub wall_ms: f64,
}

impl Summary {
    /// Counts `outcomes`, run on `jobs` threads in `wall_ms`.
    pub fn of(outcomes: &[Outcome], jobs: usize, wall_ms: f64) -> Summary {
        let mut s = Summary {
            inputs: outcomes.len(),
            jobs,
            wall_ms,
            ..Summary::default()
        };
        for o in outcomes {
            match &o.status {
                Status::Baked(_) => s.baked += 1,
                Status::UpToDate => s.up_to_date += 1,
                Status::Failed(_) => s.failed += 1,
            }
        }
        s
    }
}

impl std::fmt::Display for Summary {
    /// One line: `3 inputs: 2 baked, 0 up to date, 1 failed in 1.23 s (2 jobs)`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} inputs: {} baked, {} up to date, {} failed in {:.2} s ({} jobs)",
            self.inputs,
            self.baked,
            self.up_to_date,
            self.failed,
            self.wall_ms / 1000.0,
            self.jobs
        )
    }
}

/// The bake options as the report states them (angles in degrees).
#[derive(Debug, Serialize, Clone)]
pub struct OptionsReport {
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

/// Radians as degrees, to 1e-4° (so 60° reads 60, not 60.000004).
fn degrees(rad: f32) -> f32 {
    (rad.to_degrees() * 1e4).round() / 1e4
}

impl OptionsReport {
    /// `opts` as stated in the report.
    pub fn of(opts: &BakeOptions) -> OptionsReport {
        let generated = match opts.comb {
            CombSource::Generate(g) => Some(g),
            CombSource::Painted => None,
        };
        OptionsReport {
            tangents: opts.tangents.name(),
            tangent_generator: opts.tangent_generator.name(),
            comb_color_space: opts.color_space.name(),
            comb_axes: opts.axes.to_string(),
            quantize: opts.quantize.name(),
            topology: opts.topology_mode.name(),
            weld_epsilon: opts.topology.weld_epsilon,
            normal_tolerance_deg: degrees(opts.topology.normal_tolerance),
            comb: opts.comb.to_string(),
            comb_length: generated.map(|g| g.length),
            comb_smoothing: generated.map(|g| g.smoothing),
            crease_angle_deg: degrees(opts.crease_angle),
        }
    }

    /// Everything besides the files read that shapes an output: pelt's version (`version`),
    /// these options and the config's bytes.
    pub fn salt(&self, version: &str, config: Option<&[u8]>) -> Vec<u8> {
        let mut s = format!("pelt {version}\n").into_bytes();
        s.extend(serde_json::to_vec(self).unwrap_or_default());
        s.push(b'\n');
        if let Some(c) = config {
            s.extend((c.len() as u64).to_le_bytes());
            s.extend(c);
        }
        s
    }
}

/// One input's outcome.
#[derive(Debug, Serialize)]
pub struct InputReport {
    /// The input.
    pub input: PathBuf,
    /// Its output.
    pub output: PathBuf,
    /// `ok`, `up to date` or `failed`.
    pub status: &'static str,
    /// Every file read for this input (the input first).
    pub reads: Vec<PathBuf>,
    /// Why it failed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// The bake's report.
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub bake: Option<AssetReport>,
    /// The fur's report.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fur: Option<FurReport>,
    /// Reading time.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub read_ms: Option<f64>,
    /// Writing time.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub write_ms: Option<f64>,
    /// The output's size.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub output_bytes: Option<u64>,
}

impl InputReport {
    /// `job`'s outcome `o`.
    pub fn new(job: &Job, o: Outcome) -> InputReport {
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
            Status::Failed(e) => r.error = Some(e.to_string()),
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_read_in_whole_degrees_and_the_salt_follows_the_options() {
        let opts = BakeOptions::default();
        let r = OptionsReport::of(&opts);
        assert_eq!(r.crease_angle_deg, 60.0);
        let other = BakeOptions {
            quantize: Quantize::U8,
            ..BakeOptions::default()
        };
        let (a, b) = (r.salt("1", None), OptionsReport::of(&other).salt("1", None));
        assert_ne!(a, b);
        assert_ne!(a, r.salt("2", None));
        assert_ne!(a, r.salt("1", Some(b"{}")));
    }
}
