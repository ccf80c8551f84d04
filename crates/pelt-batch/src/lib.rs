//! pelt-batch: the bake as a build step that pipelines can trust.
//!
//! - [`inputs`]: which files a command line names (files, folders searched recursively,
//!   glob patterns) and where each one's output goes.
//! - [`job`]: one input baked to one output, written atomically; a failure leaves no output.
//! - [`key`]: the content key an output records (every file read, the flags, pelt's version),
//!   so `--incremental` can skip inputs whose output is already up to date.
//! - [`depfile`]: Make-syntax dependency files listing every file each output was made from.
//! - [`temp`]: sweeping the temporary files a killed run left behind.
//! - [`run`]: the batch baked on a thread pool, outcomes reported as they land.
//! - [`report`]: the report's schema (`pelt bake --report`) and the options' salt.
//! - [`messages`]: what a run says as text (each outcome, the summary, the failures).

pub mod depfile;
pub mod inputs;
pub mod job;
pub mod key;
pub mod messages;
pub mod report;
pub mod run;
pub mod temp;

pub use inputs::{Job, PlanError, plan};
pub use job::{Baked, JobError, Outcome, Settings, Status, bake_file};
