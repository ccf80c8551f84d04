//! A sweep's tables: each knob's Pareto front (the settings no other setting of the knob
//! beats on both time and error), `sweep.csv`, `sweep.json` (the rows, the references with
//! their convergence, the machine and adapter) and `sweep.md` (the Pareto table docs/sweep.md
//! quotes).

use std::fmt::Write as _;
use std::path::Path;

// The Pareto marks are made with the rows (`super::run`); their old path here keeps working.
pub use super::mark_pareto;
use super::{Row, Sweep, SweepError};

/// Quotes a CSV field when it needs it.
fn field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// `sweep.csv`.
pub fn csv(s: &Sweep) -> String {
    let mut out = String::from(
        "knob,value,ms,error,fur_luminance,reference,default,pareto,upload_bytes,image,heat\n",
    );
    for r in &s.rows {
        let _ = writeln!(
            out,
            "{},{},{:.3},{:.5},{},{},{},{},{},{},{}",
            field(&r.knob),
            field(&r.value),
            r.ms,
            r.error,
            r.fur_luminance.map_or(String::new(), |l| format!("{l:.4}")),
            r.truth.name(),
            r.default,
            r.pareto,
            r.upload_bytes,
            field(&r.image),
            field(&r.heat)
        );
    }
    out
}

fn row_json(r: &Row) -> serde_json::Value {
    serde_json::json!({
        "knob": r.knob,
        "value": r.value,
        "ms": r.ms,
        "error": r.error,
        "fur_luminance": r.fur_luminance,
        "reference": r.truth.name(),
        "default": r.default,
        "pareto": r.pareto,
        "upload_bytes": r.upload_bytes,
        "image": r.image,
        "heat": r.heat,
    })
}

/// `sweep.json`.
pub fn json(s: &Sweep) -> serde_json::Value {
    let refs: Vec<serde_json::Value> = s
        .references
        .iter()
        .map(|r| {
            serde_json::json!({
                "kind": r.truth.name(),
                "samples": r.samples,
                "half_vs_half_flip": r.half_vs_half_flip,
                "ms": r.ms,
                "ms_per_sample": r.ms_per_sample,
                "frames": r.frames,
                "grid": r.grid,
                "ms_per_frame": r.ms_per_frame,
                "strands": r.strands,
                "image": r.image,
            })
        })
        .collect();
    let strands = refs
        .iter()
        .find(|r| r["kind"] == "strands")
        .or(refs.first())
        .cloned();
    serde_json::json!({
        "adapter": s.adapter,
        "machine": {
            "os": std::env::consts::OS,
            "arch": std::env::consts::ARCH,
            "cpus": std::thread::available_parallelism().map_or(0, |n| n.get()),
        },
        "size": [s.size.0, s.size.1],
        "frames": s.frames,
        "clock": s.clock,
        "total_ms": s.total_ms,
        "reference": strands,
        "references": refs,
        "best_under_tenth_of_reference": s.best_under(0.1).map(row_json),
        "rows": s.rows.iter().map(row_json).collect::<Vec<_>>(),
    })
}

/// `sweep.md`: per knob, its settings by time with error, Pareto front and default marked;
/// then the best setting under a tenth of the strand reference's time.
pub fn markdown(s: &Sweep) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{}×{}, {} frames per setting ({} clock), adapter: {}\n",
        s.size.0, s.size.1, s.frames, s.clock, s.adapter
    );
    for r in &s.references {
        let _ = write!(out, "- reference `{}`: ", r.truth.name());
        match r.half_vs_half_flip {
            Some(f) => {
                let _ = writeln!(
                    out,
                    "{} strands, {} samples per pixel ({} frames of {}×{}), half-vs-half FLIP {f:.4}, {:.0} ms per frame ({:.1} ms per sample), {:.1} s in all",
                    r.strands,
                    r.samples,
                    r.frames,
                    r.grid,
                    r.grid,
                    r.ms_per_frame,
                    r.ms_per_sample,
                    r.ms / 1000.0
                );
            }
            None => {
                let _ = writeln!(out, "one image, {:.0} ms", r.ms);
            }
        }
    }
    out.push_str("\n| knob | value | ms | FLIP | fur luminance | against | Pareto |\n|---|---|---|---|---|---|---|\n");
    let mut rows: Vec<&Row> = s.rows.iter().collect();
    rows.sort_by(|a, b| a.knob.cmp(&b.knob).then(a.ms.total_cmp(&b.ms)));
    for r in rows {
        let value = if r.default {
            format!("**{}** (default)", r.value)
        } else {
            r.value.clone()
        };
        let _ = writeln!(
            out,
            "| {} | {value} | {:.0} | {:.4} | {} | {} | {} |",
            r.knob,
            r.ms,
            r.error,
            r.fur_luminance.map_or("–".into(), |l| format!("{l:.2}×")),
            r.truth.name(),
            if r.pareto { "●" } else { "" }
        );
    }
    if let Some(b) = s.best_under(0.1) {
        let _ = writeln!(
            out,
            "\nBest under a tenth of the strand reference's time: {}={} ({:.0} ms, FLIP {:.4}).",
            b.knob, b.value, b.ms, b.error
        );
    }
    out
}

/// Writes `sweep.csv`, `sweep.json`, `sweep.md`, `sweep.png` and `contact.png` into `dir`.
pub fn write_all(s: &Sweep, dir: &Path) -> Result<(), SweepError> {
    let put = |name: &str, bytes: &[u8]| {
        let path = dir.join(name);
        pelt_io::glb::write_atomic(&path, bytes).map_err(|e| SweepError::Write {
            path: path.display().to_string(),
            source: Box::new(e),
        })
    };
    put("sweep.csv", csv(s).as_bytes())?;
    let j = serde_json::to_string_pretty(&json(s)).unwrap_or_default();
    put("sweep.json", j.as_bytes())?;
    put("sweep.md", markdown(s).as_bytes())?;
    put("sweep.png", &super::plot::chart(s)?.png())?;
    put("contact.png", &super::plot::contact_sheet(s, dir)?.png())?;
    Ok(())
}

/// The staging folder inside a sweep's output folder.
pub const STAGING: &str = ".sweep-partial";

/// [`super::run`] with its outputs put into `output` whole: the sweep writes into a staging
/// folder inside it (`opts.out` is replaced), the report is written there too, and only when
/// everything succeeded is it moved into place; a failed sweep leaves no partial output.
pub fn run_into(
    preview: &mut pelt_preview::Preview,
    (input, base, default_size): (&Path, &pelt_preview::knobs::Knobs, (u32, u32)),
    opts: super::Options,
    output: &Path,
    progress: &mut dyn FnMut(super::Event<'_>),
) -> Result<Sweep, SweepError> {
    let staging = output.join(STAGING);
    let io = |path: &Path, e: std::io::Error| SweepError::Write {
        path: path.display().to_string(),
        source: Box::new(e),
    };
    if staging.exists() {
        std::fs::remove_dir_all(&staging).map_err(|e| io(&staging, e))?;
    }
    let opts = super::Options {
        out: staging.clone(),
        ..opts
    };
    let result = super::run(preview, input, base, default_size, &opts, progress)
        .and_then(|s| write_all(&s, &staging).map(|()| s));
    match result {
        Ok(s) => {
            publish(&staging, output).map_err(|e| io(output, e))?;
            Ok(s)
        }
        Err(e) => {
            let _ = std::fs::remove_dir_all(&staging);
            Err(e)
        }
    }
}

/// Moves every entry of `from` into `to` (replacing same-named ones), then removes `from`.
fn publish(from: &Path, to: &Path) -> std::io::Result<()> {
    for e in std::fs::read_dir(from)? {
        let e = e?;
        let dst = to.join(e.file_name());
        if dst.is_dir() {
            std::fs::remove_dir_all(&dst)?;
        }
        std::fs::rename(e.path(), dst)?;
    }
    std::fs::remove_dir(from)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sweep::knob::Truth;

    fn row(knob: &str, ms: f64, error: f32) -> Row {
        Row {
            knob: knob.into(),
            value: format!("{ms}"),
            ms,
            error,
            truth: Truth::Strands,
            default: false,
            pareto: false,
            image: String::new(),
            heat: String::new(),
            upload_bytes: 0,
            fur_luminance: None,
        }
    }

    #[test]
    fn the_front_keeps_what_nothing_beats_per_knob() {
        let mut rows = vec![
            row("shells", 10.0, 0.3),
            row("shells", 20.0, 0.2),
            row("shells", 30.0, 0.25),
            row("shells", 20.0, 0.2),
            row("fins", 50.0, 0.9),
        ];
        mark_pareto(&mut rows);
        let p: Vec<bool> = rows.iter().map(|r| r.pareto).collect();
        assert_eq!(p, [true, true, false, true, true]);
    }

    #[test]
    fn csv_quotes_fields_with_commas() {
        assert_eq!(field("a,b"), "\"a,b\"");
        assert_eq!(field("16"), "16");
    }
}
