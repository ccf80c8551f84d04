//! `pelt bake`: the flags as `BakeOptions` (`pelt_bake::flags`), the batch run by `pelt_batch` (jobs, thread pool,
//! report schema, depfile), progress shown and the outcome summarized.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use anyhow::Context;
use pelt_bake::config::BakeConfig;
use pelt_bake::fur::FurAssets;
use pelt_batch::report::{FurRun, InputReport, OptionsReport, Report, Summary};
use pelt_batch::{Job, Outcome, Settings, Status, messages};

use crate::BakeArgs;

/// Runs `pelt bake`.
pub fn run(args: &BakeArgs) -> anyhow::Result<ExitCode> {
    let started = Instant::now();
    // The report and the depfile are checked (their folders made) before any input is baked,
    // so a bad path costs no work and leaves no output behind.
    for path in args.report.iter().chain(&args.depfile) {
        crate::outputs::file(path)?;
    }
    let jobs = pelt_batch::plan(&args.inputs, &args.output)?;
    let (config, config_bytes) = match &args.config {
        Some(path) => BakeConfig::read(path).map(|(c, b)| (Some(c), Some(b)))?,
        None => (None, None),
    };
    let opts = args.bake.options(config.as_ref())?;
    let fur = match (&args.config, config.as_ref().and_then(|c| c.fur.clone())) {
        (Some(path), Some(fur)) => Some(
            FurAssets::new(fur).with_context(|| format!("fur textures of {}", path.display()))?,
        ),
        _ => None,
    };
    let options_report = OptionsReport::of(&opts);
    let settings = Settings {
        options: opts,
        fur: fur.as_ref(),
        salt: options_report.salt(env!("CARGO_PKG_VERSION"), config_bytes.as_deref()),
        incremental: args.incremental,
    };
    let threads = pelt_batch::run::threads(args.jobs.map(usize::from));
    let progress = Progress::new(jobs.len(), args.quiet);
    let outcomes = pelt_batch::run::run(&jobs, &settings, threads, |j, o| progress.done(j, o))?;
    progress.finish();
    let summary = Summary::of(&outcomes, threads, ms(started));
    let failures = messages::failures(&outcomes);
    // A failed bake writes no depfile: a build tool reads one only after success, and an
    // input that failed leaves nothing behind.
    if let (Some(path), true) = (&args.depfile, failures.is_empty()) {
        let also: Vec<PathBuf> = args.config.iter().cloned().collect();
        let rules = pelt_batch::depfile::rules(&jobs, &outcomes, &also);
        pelt_io::glb::write_atomic(path, pelt_batch::depfile::render(&rules).as_bytes())?;
    }
    match (jobs.len() > 1, args.quiet) {
        (true, quiet) => {
            if !quiet {
                eprintln!("pelt: {summary}");
            }
            if !failures.is_empty() {
                eprintln!(
                    "pelt: {} of {} inputs failed:",
                    summary.failed, summary.inputs
                );
                failures.iter().for_each(|f| eprintln!("  {f}"));
            }
        }
        (false, true) if !failures.is_empty() => {
            let lines: Vec<String> = failures.iter().map(ToString::to_string).collect();
            eprintln!("pelt: {}", lines.join("\n"));
        }
        _ => {}
    }
    let code = if failures.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    };
    if let Some(path) = &args.report {
        let report = Report {
            pelt: env!("CARGO_PKG_VERSION"),
            options: options_report,
            summary,
            fur: fur
                .as_ref()
                .zip(args.config.clone())
                .map(|(f, c)| FurRun::new(f, c)),
            inputs: jobs
                .iter()
                .zip(outcomes)
                .map(|(j, o)| InputReport::new(j, o))
                .collect(),
        };
        crate::write_json_report(path, &report)?;
    }
    Ok(code)
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
        let lines = messages::outcome_lines(job, o, self.total > 1);
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

    fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

fn ms(t: Instant) -> f64 {
    (t.elapsed().as_secs_f64() * 1e5).round() / 100.0
}
