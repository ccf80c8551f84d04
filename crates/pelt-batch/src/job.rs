//! One input baked to one output: load, bake (comb, topology), embed fur textures when the
//! config asks, record the content key (with `--incremental`), write the `.glb` atomically (temporary file in the
//! output's folder, then rename). A failure at any step removes what an earlier run left under
//! the output name, so a failed input never leaves an output that looks current.

use std::path::{Path, PathBuf};
use std::time::Instant;

use pelt_bake::fur::{FurAssets, FurReport, combed, embed};
use pelt_bake::{AssetReport, BakeOptions, bake_document};
use pelt_io::IoError;

use crate::Job;
use crate::key::{self, Record};

/// What every job of a batch shares.
pub struct Settings<'a> {
    /// The bake's options.
    pub options: BakeOptions,
    /// Fur textures to embed, if the config has a `fur` section.
    pub fur: Option<&'a FurAssets>,
    /// Everything besides the files read that shapes the output (flags, config bytes): part
    /// of the content key.
    pub salt: Vec<u8>,
    /// Skip inputs whose output records the key they have now, and record keys.
    pub incremental: bool,
}

/// A baked input.
#[derive(Debug)]
pub struct Baked {
    /// The bake's report.
    pub bake: AssetReport,
    /// The fur embedding's report.
    pub fur: Option<FurReport>,
    /// Loading time.
    pub read_ms: f64,
    /// Writing time.
    pub write_ms: f64,
    /// Size of the output.
    pub output_bytes: u64,
}

/// How a job ended.
#[derive(Debug)]
pub enum Status {
    /// Written.
    Baked(Box<Baked>),
    /// The output already records this input's key (`--incremental`).
    UpToDate,
    /// Not written; the error names the file and the place.
    Failed(JobError),
}

/// Why a job wrote no output. Every message names the file and the place.
#[derive(Debug, thiserror::Error)]
pub enum JobError {
    /// Loading, baking, embedding fur, packing or writing failed (the error names the file
    /// and the place in it).
    #[error(transparent)]
    Asset(#[from] IoError),
    /// The input's files could not be read again for the content key (`--incremental`).
    #[error("{}: hashing for the content key: {source}", input.display())]
    Key {
        /// The input.
        input: PathBuf,
        /// The read that failed.
        #[source]
        source: std::io::Error,
    },
    /// The output's folder could not be created.
    #[error("{}: create: {source}", dir.display())]
    CreateDir {
        /// The folder.
        dir: PathBuf,
        /// The OS error.
        #[source]
        source: std::io::Error,
    },
}

/// A job's result.
#[derive(Debug)]
pub struct Outcome {
    /// How it ended.
    pub status: Status,
    /// Every file read to make (or check) the output, the input first: the depfile's list.
    pub reads: Vec<PathBuf>,
}

/// Bakes `job`.
pub fn bake_file(job: &Job, s: &Settings) -> Outcome {
    if s.incremental {
        if let Some(rec) = key::read_record(&job.output) {
            if key::compute(&job.input, &rec.reads, &s.salt).is_ok_and(|k| k == rec.key) {
                let mut reads = vec![job.input.clone()];
                reads.extend(key::read_paths(&job.input, &rec.reads));
                return Outcome {
                    status: Status::UpToDate,
                    reads,
                };
            }
        }
    }
    let mut reads = vec![job.input.clone()];
    let status = match bake(job, s, &mut reads) {
        Ok(b) => Status::Baked(Box::new(b)),
        Err(e) => {
            remove_stale(&job.output);
            Status::Failed(e)
        }
    };
    Outcome { status, reads }
}

fn bake(job: &Job, s: &Settings, reads: &mut Vec<PathBuf>) -> Result<Baked, JobError> {
    let t0 = Instant::now();
    let mut doc = pelt_io::load(&job.input)?;
    reads.clone_from(&doc.files_read);
    let read_ms = ms(t0);
    let rel = key::relative_reads(&job.input, &doc.files_read);
    // The content key only with --incremental: hashing a 57 MB input costs about 40 ms of
    // CPU, a tenth of its bake. It re-reads the files from the page cache, overlapping the bake.
    let (key, bake) = rayon::join(
        || {
            s.incremental
                .then(|| key::compute(&job.input, &rel, &s.salt))
                .transpose()
        },
        || bake_document(&mut doc, &s.options),
    );
    let mut bake = bake?;
    let key = key.map_err(|source| JobError::Key {
        input: job.input.clone(),
        source,
    })?;
    let mut fur_report = None;
    if let Some(fur) = s.fur {
        let f = embed(&mut doc, fur, &combed(&bake))?;
        bake.warnings.extend(f.warnings.iter().cloned());
        fur_report = Some(f);
    }
    if key.is_some_and(|key| !key::set_record(&mut doc, &Record { key, reads: rel })) {
        bake.warnings.push(
            "extras: the root extras (or extras.pelt) is not an object; no content key was \
             recorded, so --incremental will always bake this input"
                .to_owned(),
        );
    }
    pelt_bake::pack_output(&mut doc, &s.options, &mut bake)?;
    if let Some(dir) = job.output.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|source| JobError::CreateDir {
            dir: dir.to_owned(),
            source,
        })?;
    }
    let t1 = Instant::now();
    let w = pelt_io::glb::write_glb(&doc, &job.output)?;
    Ok(Baked {
        bake,
        fur: fur_report,
        read_ms,
        write_ms: ms(t1),
        output_bytes: w.file_bytes,
    })
}

/// Removes a file an earlier run left under the output name (never a folder).
fn remove_stale(output: &Path) {
    if output.symlink_metadata().is_ok_and(|m| m.is_file()) {
        let _ = std::fs::remove_file(output);
    }
}

fn ms(t: Instant) -> f64 {
    (t.elapsed().as_secs_f64() * 1e5).round() / 100.0
}
