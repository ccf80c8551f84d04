//! `pelt textures`: generate a fur texture set and its manifest into a folder.

use std::process::ExitCode;
use std::time::Instant;

use pelt_bake::config::BakeConfig;
use pelt_fur::FurConfig;

use crate::TexturesArgs;

/// The fur config: the file's `fur` section (or defaults) with the flags applied.
fn config(args: &TexturesArgs) -> anyhow::Result<FurConfig> {
    let mut fur = match &args.config {
        Some(path) => BakeConfig::load(path)?.fur.unwrap_or_default(),
        None => FurConfig::default(),
    };
    args.strand.apply(&mut fur.textures);
    fur.validate()
        .map_err(|e| anyhow::anyhow!("fur.{}: {}", e.field, e.why))?;
    Ok(fur)
}

/// Runs `pelt textures`.
pub fn run(args: &TexturesArgs) -> anyhow::Result<ExitCode> {
    let fur = config(args)?;
    let t0 = Instant::now();
    let set = pelt_fur::generate(&fur.textures)?;
    let generated = t0.elapsed();
    let bytes = match set.write_dir(&args.output, &fur) {
        Ok(b) => b,
        Err(e) => {
            eprintln!("pelt: {e}");
            return Ok(ExitCode::from(1));
        }
    };
    if !args.quiet {
        let p = &fur.textures;
        eprintln!(
            "wrote {} images and fur.json to {} ({:.1} MB) in {:.0} ms ({:.0} ms generating)",
            set.images().count(),
            args.output.display(),
            bytes as f64 / 1e6,
            t0.elapsed().as_secs_f64() * 1e3,
            generated.as_secs_f64() * 1e3,
        );
        eprintln!(
            "  {} strands, seed {}, {}² (fin {}×{}), heightfield {}-bit",
            p.strands,
            p.seed,
            p.size,
            p.size,
            p.fin_rows(),
            u8::from(p.height_bits)
        );
        let expected = set.expected_coverage();
        eprint!("  coverage: dots {:.4}", set.coverage.dots);
        if let Some(e) = &expected {
            eprint!(" (model {:.4})", e.dots);
        }
        eprintln!();
        for (i, [h, c]) in set.coverage.shells.iter().enumerate() {
            eprint!("  shell at height {h:.2}: {c:.4}");
            if let Some(e) = &expected {
                eprint!(" (model {:.4})", e.shells[i][1]);
            }
            eprintln!();
        }
    }
    Ok(ExitCode::SUCCESS)
}
