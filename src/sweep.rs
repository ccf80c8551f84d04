//! `pelt sweep`: every quality knob's time against its error on this machine's adapter
//! (the logic, the tables, the plots and the all-or-nothing output folder are
//! `pelt_measure::sweep`'s).

use std::process::ExitCode;

use pelt_measure::sweep::knob::Knob;
use pelt_measure::sweep::{self, Row, SweepError, report};
use pelt_preview::Preview;
use pelt_preview::knobs::InputError;

use crate::SweepArgs;

/// Runs `pelt sweep`.
pub fn run(args: &SweepArgs) -> anyhow::Result<ExitCode> {
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
    let mut progress = |r: &Row| {
        if !quiet {
            let lum = r
                .fur_luminance
                .map_or(String::new(), |l| format!(", fur luminance {l:.3}×"));
            eprintln!(
                "{}={}: {:.1} ms, FLIP {:.4} against {}{lum}",
                r.knob,
                r.value,
                r.ms,
                r.error,
                r.truth.name()
            );
        }
    };
    let input = (args.input.as_path(), &base, crate::render::DEFAULT_SIZE);
    let s = match report::run_into(&mut preview, input, opts, &args.output, &mut progress) {
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
