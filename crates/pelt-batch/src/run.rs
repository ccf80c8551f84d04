//! A batch baked in parallel: `threads` workers (files and the work inside large meshes share
//! one rayon pool), the temporary files a killed run left in the output folders swept first,
//! each outcome reported as it lands. One failing input never stops the others.

use std::collections::BTreeSet;
use std::path::PathBuf;

use rayon::prelude::*;

use crate::{Job, Outcome, Settings};

/// The worker threads could not be started.
#[derive(Debug, thiserror::Error)]
#[error("cannot start {threads} worker threads: {source}")]
pub struct PoolError {
    /// How many were asked for.
    pub threads: usize,
    /// Why.
    #[source]
    pub source: rayon::ThreadPoolBuildError,
}

/// Bakes every job on `threads` threads, calling `done` as each finishes; outcomes come
/// back in the jobs' order.
pub fn run(
    jobs: &[Job],
    settings: &Settings<'_>,
    threads: usize,
    done: impl Fn(&Job, &Outcome) + Sync,
) -> Result<Vec<Outcome>, PoolError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|source| PoolError { threads, source })?;
    let dirs: BTreeSet<PathBuf> = jobs
        .iter()
        .filter_map(|j| j.output.parent().map(PathBuf::from))
        .collect();
    for d in &dirs {
        crate::temp::sweep(d);
    }
    Ok(pool.install(|| {
        jobs.par_iter()
            .map(|job| {
                let o = crate::bake_file(job, settings);
                done(job, &o);
                o
            })
            .collect()
    }))
}

/// The worker count for `--jobs`: the given one, else every core.
pub fn threads(jobs: Option<usize>) -> usize {
    jobs.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, usize::from))
}
