//! Longer fuzz runs than CI's: `pelt-fuzz [--cases N] [--seconds S] [--seed N] [--trace]`.
//! Failing inputs go to `target/fuzz-crashes/`; the exit code is 1 if there were any.

#[global_allocator]
static GLOBAL: pelt_alloc::Counting = pelt_alloc::Counting;

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1))
            .and_then(|v| v.parse::<u64>().ok())
    };
    if args.iter().any(|a| a == "--help" || a == "-h") {
        eprintln!("usage: pelt-fuzz [--cases N] [--seconds S] [--seed N] [--trace]");
        return ExitCode::SUCCESS;
    }
    let seconds = value("--seconds");
    let cases = value("--cases").unwrap_or(if seconds.is_some() { u64::MAX } else { 100_000 });
    let seed = value("--seed").unwrap_or(0x5EED_F00D);
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let seeds = match pelt_fuzz::corpus(&root) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("pelt-fuzz: cannot read the fixture corpus: {e}");
            return ExitCode::from(2);
        }
    };
    let s = pelt_fuzz::run(
        &seeds,
        seed,
        cases,
        seconds.map(|s| s as f64),
        &root.join("target/fuzz-crashes"),
        args.iter().any(|a| a == "--trace"),
    );
    println!("seed {seed}: {s}");
    for f in &s.findings {
        println!("{f}");
    }
    if s.findings.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}
