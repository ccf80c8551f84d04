//! `pelt sweep`: every quality knob's time against its error on this machine's adapter
//! (the logic, the tables, the plots and the all-or-nothing output folder are
//! `pelt_measure::sweep`'s).

use std::process::ExitCode;

use pelt_measure::sweep::knob::Knob;
use pelt_measure::sweep::{self, Event, Row, SweepError, report};
use pelt_preview::Preview;
use pelt_preview::knobs::InputError;

use crate::SweepArgs;
use crate::progress::Progress;

/// Runs `pelt sweep`.
pub fn run(args: &SweepArgs) -> anyhow::Result<ExitCode> {
    // The folder the output folder goes into takes new files (made if missing), before the
    // references and the sweep run.
    match args.output.parent() {
        Some(p) if !p.as_os_str().is_empty() => crate::outputs::folder(p)?,
        _ => crate::outputs::folder(std::path::Path::new("."))?,
    }
    remove_staging_on_interrupt(&args.output)?;
    let knobs = args
        .knob
        .iter()
        .map(|k| Knob::parse_list(k))
        .collect::<Result<Vec<_>, _>>()?;
    let mut preview = match Preview::new(args.backend) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("pelt: {e}");
            return Ok(ExitCode::from(1));
        }
    };
    if !args.quiet {
        eprintln!("adapter: {}", preview.adapter());
    }
    let opts = sweep::Options {
        knobs,
        grid: args.grid,
        frames: args.frames,
        warmup: args.warmup,
        reference: args.reference.options(),
        out: args.output.clone(),
    };
    let base = pelt_preview::knobs::Knobs {
        size: args.size,
        ..Default::default()
    };
    let quiet = args.quiet;
    let mut bar = Progress::new(("sweep", "sweep"), 1, quiet);
    let mut strands = crate::progress::StrandSteps::default();
    let mut progress = |e: Event<'_>| match e {
        Event::Reference(t) => bar.say(&format!("sweep: computing the {} reference", t.name())),
        Event::Strands(s) => strands.show(&mut bar, s),
        Event::Row(r, i, n) => {
            bar.set_length(n as u64);
            bar.say(&row_line(r));
            bar.set(i as u64, &format!("{i} of {n} settings measured"), false);
        }
    };
    let input = (args.input.as_path(), &base, crate::render::DEFAULT_SIZE);
    let s = report::run_into(&mut preview, input, opts, &args.output, &mut progress);
    bar.finish();
    let s = match s {
        Ok(s) => s,
        Err(
            e @ (SweepError::Knob(_)
            | SweepError::TooMany(_)
            | SweepError::Input(InputError::Scene(_))),
        ) => return Err(e.into()),
        Err(e) => {
            eprintln!("pelt: {}: {e}", args.input.display());
            return Ok(ExitCode::from(1));
        }
    };
    if !quiet {
        for r in &s.references {
            if let Some(f) = r.half_vs_half_flip {
                eprintln!(
                    "strand reference: {} strands, {} samples per pixel in {} frames, half-vs-half FLIP {f:.4}, {:.0} ms per frame",
                    r.strands, r.samples, r.frames, r.ms_per_frame
                );
            }
        }
        if let Some(b) = s.best_under(0.1) {
            eprintln!(
                "best under a tenth of the strand reference's time: {}={} ({:.0} ms, FLIP {:.4})",
                b.knob, b.value, b.ms, b.error
            );
        }
        eprintln!(
            "wrote {} settings to {} (sweep.csv, sweep.json, sweep.md, sweep.png, contact.png) in {:.1} s",
            s.rows.len(),
            args.output.display(),
            s.total_ms / 1000.0
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// Ctrl-C or SIGTERM while the sweep runs: its staging folder (and the output folder, when
/// the sweep made it and it is empty) is removed before exiting with 130, so an interrupted
/// sweep leaves nothing half-written.
fn remove_staging_on_interrupt(output: &std::path::Path) -> anyhow::Result<()> {
    let staging = output.join(report::STAGING);
    let made = !output.exists();
    let output = output.to_path_buf();
    ctrlc::set_handler(move || {
        // A file being written as the folder goes can leave it behind: try again.
        for _ in 0..3 {
            if std::fs::remove_dir_all(&staging).is_ok() || !staging.exists() {
                break;
            }
        }
        if made {
            let _ = std::fs::remove_dir(&output);
        }
        eprintln!("pelt: sweep interrupted: nothing written");
        std::process::exit(130);
    })
    .map_err(|e| anyhow::anyhow!("cannot watch for Ctrl-C: {e}"))
}

/// One measured setting, as a line.
fn row_line(r: &Row) -> String {
    let lum = r
        .fur_luminance
        .map_or(String::new(), |l| format!(", fur luminance {l:.3}×"));
    format!(
        "{}={}: {:.1} ms, FLIP {:.4} against {}{lum}",
        r.knob,
        r.value,
        r.ms,
        r.error,
        r.truth.name()
    )
}
